//! OBJ + MTL reading: what each statement becomes in the mesh model.

use std::path::Path;

use wildlod_io::{read, Document};
use wildlod_mesh::{AlphaMode, ImageSource, Semantic, ABSENT};

/// Writes `files` (name, content) into a fresh directory and reads the
/// first one.
fn read_files(files: &[(&str, &str)]) -> (Document, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("temp dir");
    for (name, text) in files {
        let p = dir.path().join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).expect("create dir");
        }
        std::fs::write(p, text).expect("write test file");
    }
    let doc = read(dir.path().join(files[0].0)).unwrap_or_else(|e| panic!("{e}"));
    (doc, dir)
}

fn read_obj(text: &str) -> Document {
    read_files(&[("m.obj", text)]).0
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n";

#[test]
fn quads_and_ngons_keep_their_arity() {
    let doc = read_obj(&format!("{SQUARE}f 1 2 3 4\nf 1 2 3\nf 1 5 2 3 4\n"));
    let m = &doc.scene.meshes[0];
    assert_eq!(m.faces.arity_counts(), (1, 1, 1));
    assert_eq!(m.faces.face(0), &[0, 1, 2, 3]);
    assert_eq!(m.faces.face(2), &[0, 4, 1, 2, 3]);
}

#[test]
fn corner_indices_mirror_vt_and_vn_and_missing_ones_are_absent() {
    let doc = read_obj(&format!(
        "{SQUARE}vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvn 0 0 -1\n\
         f 1/1/2 2/2/2 3/3/1\nf 1//1 3//1 4//2\nf 1/3 2/2 3/1\nf 1 2 3\n"
    ));
    let m = &doc.scene.meshes[0];
    let uv = m.attribute(&Semantic::TexCoord(0)).unwrap();
    let n = m.attribute(&Semantic::Normal).unwrap();
    assert_eq!(uv.values.len(), 6);
    assert_eq!(
        uv.indices,
        [0, 1, 2, ABSENT, ABSENT, ABSENT, 2, 1, 0, ABSENT, ABSENT, ABSENT]
    );
    assert_eq!(
        n.indices,
        [1, 1, 0, 0, 0, 1, ABSENT, ABSENT, ABSENT, ABSENT, ABSENT, ABSENT]
    );
    m.validate().unwrap();
}

#[test]
fn negative_indices_count_back_from_the_last_definition() {
    let doc =
        read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf -3/-1 -2/-1 -1/-1\nv 5 5 5\nf -4 -3 -1\n");
    let m = &doc.scene.meshes[0];
    assert_eq!(m.faces.face(0), &[0, 1, 2]);
    assert_eq!(m.faces.face(1), &[0, 1, 3]);
    assert_eq!(m.attributes[0].indices[..3], [0, 0, 0]);
}

#[test]
fn vertex_colors_become_a_color_stream_indexed_like_positions() {
    let doc = read_obj("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0\nv 1 1 0 0 0 1\nf 1 2 3\nf 2 4 3\n");
    let m = &doc.scene.meshes[0];
    let c = m.attribute(&Semantic::Color(0)).unwrap();
    assert_eq!(c.components, 3);
    // Vertex 3 has no color: its corners have none either.
    assert_eq!(c.indices, [0, 1, ABSENT, 1, 3, ABSENT]);
    assert_eq!(c.corner_value(4), Some(&[0.0, 0.0, 1.0][..]));
}

#[test]
fn texture_v_is_flipped_to_the_models_top_left_origin() {
    // OBJ's v = 0 is the bottom row of the image; the model's (glTF's) is
    // the top row.
    let doc = read_obj(&format!(
        "{SQUARE}vt 0.25 0\nvt 0.5 0.75\nvt 1\nf 1/1 2/2 3/3\n"
    ));
    let uv = &doc.scene.meshes[0].attributes[0];
    assert_eq!(uv.values, [0.25, 1.0, 0.5, 0.25, 1.0, 1.0]);
}

#[test]
fn vertex_w_and_texture_w_are_dropped() {
    let doc = read_obj("v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 0.5\nvt 0.25 0.5 0.75\nf 1/1 2/1 3/1\n");
    let m = &doc.scene.meshes[0];
    assert_eq!(m.positions[2], [0.0, 1.0, 0.0]);
    assert!(m.attribute(&Semantic::Color(0)).is_none());
    assert_eq!(m.attributes[0].components, 2);
    assert_eq!(m.attributes[0].values, [0.25, 0.5]);
}

#[test]
fn continuation_crlf_tabs_comments_and_blank_lines_are_accepted() {
    let doc = read_obj(
        "# header\r\n\r\nv\t0 0 0\r\nv 1 0 0 # trailing comment\r\n  v 0 1 0\r\n\
         v 1 1 0\r\nf 1 2 \\\r\n 4 3\r\n\t\r\n",
    );
    let m = &doc.scene.meshes[0];
    assert_eq!(m.faces.face(0), &[0, 1, 3, 2]);
    assert_eq!(m.positions.len(), 4);
}

#[test]
fn statements_without_polygon_data_give_one_warning() {
    let doc = read_obj(&format!(
        "{SQUARE}s 1\nf 1 2 3\ns off\nl 1 2\np 1\ncurv 0 1 1 2\nvp 0.5\nf 1 3 4\n"
    ));
    let w: Vec<_> = doc
        .warnings
        .iter()
        .filter(|w| w.contains("ignored"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", doc.warnings);
    assert!(
        w[0].contains("'l' ×1") && w[0].contains("'curv' ×1"),
        "{}",
        w[0]
    );
    // Smoothing groups are ordinary OBJ, read without a warning.
    assert!(!w[0].contains("'s'"), "{}", w[0]);
    assert_eq!(doc.scene.meshes[0].faces.len(), 2);
}

#[test]
fn groups_objects_and_materials_make_parts() {
    let doc = read_obj(&format!(
        "{SQUARE}o body\nf 1 2 3\ng left\nusemtl red\nf 1 2 3\ng right\nf 1 3 4\n\
         g left\nf 2 3 4\nusemtl blue\nf 1 2 4\no other\nf 1 2 3\n"
    ));
    let m = &doc.scene.meshes[0];
    let parts: Vec<_> = m
        .parts
        .iter()
        .map(|p| (p.name.as_str(), p.material))
        .collect();
    assert_eq!(
        parts,
        [
            ("body", None),
            ("left", Some(0)),
            ("right", Some(0)),
            ("left", Some(1)),
            // `o` ends the group; the material stays in effect.
            ("other", Some(1)),
        ]
    );
    assert_eq!(m.face_parts, [0, 1, 2, 1, 3, 4]);
}

#[test]
fn unknown_material_gets_a_default_material_and_a_warning() {
    let doc = read_obj(&format!("{SQUARE}usemtl nowhere\nf 1 2 3\n"));
    let mat = &doc.scene.materials[0];
    assert_eq!(mat.name, "nowhere");
    assert_eq!(mat.base_color, [1.0; 4]);
    assert_eq!(mat.metallic, 0.0);
    assert!(
        doc.warnings.iter().any(|w| w.contains("nowhere")),
        "{:?}",
        doc.warnings
    );
}

#[test]
fn mtl_fields_map_onto_the_material() {
    let (doc, dir) = read_files(&[
        (
            "m.obj",
            &format!("mtllib lib.mtl\n{SQUARE}usemtl shiny\nf 1 2 3\n"),
        ),
        (
            "lib.mtl",
            "newmtl shiny\nKd 0.5 0.25 1\nd 0.5\nKe 1 0 0\nPr 0.3\nPm 0.7\n\
             map_Kd -bm 1 -s 1 1 1 tex\\base.png\nmap_Bump -bm 0.5 n.png\n\
             map_Ke glow.png\nmap_Pr orm.png\nmap_Pm orm.png\n",
        ),
        ("tex/base.png", ""),
        ("n.png", ""),
        ("glow.png", ""),
        ("orm.png", ""),
    ]);
    let m = &doc.scene.materials[0];
    assert_eq!(m.base_color, [0.5, 0.25, 1.0, 0.5]);
    assert_eq!(m.alpha_mode, AlphaMode::Blend);
    assert_eq!(m.emissive, [1.0, 0.0, 0.0]);
    assert_eq!((m.roughness, m.metallic), (0.3, 0.7));
    let path = |r: Option<wildlod_mesh::TextureRef>| match &doc.scene.textures
        [r.unwrap().texture as usize]
        .source
    {
        ImageSource::Path(p) => p.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(path(m.base_color_texture), dir.path().join("tex/base.png"));
    assert_eq!(path(m.normal_texture), dir.path().join("n.png"));
    assert_eq!(path(m.emissive_texture), dir.path().join("glow.png"));
    assert_eq!(
        path(m.metallic_roughness_texture),
        dir.path().join("orm.png")
    );
    // map_Pr and map_Pm name one image: one texture.
    assert_eq!(doc.scene.textures.len(), 4);
    assert!(doc.warnings.is_empty(), "{:?}", doc.warnings);
}

#[test]
fn tr_is_one_minus_d_and_d_wins_over_tr() {
    let (doc, _dir) = read_files(&[
        (
            "m.obj",
            &format!("mtllib a.mtl\n{SQUARE}usemtl tr\nf 1 2 3\nusemtl both\nf 1 2 3\n"),
        ),
        ("a.mtl", "newmtl tr\nTr 0.25\nnewmtl both\nTr 0.9\nd 1\n"),
    ]);
    assert_eq!(doc.scene.materials[0].base_color[3], 0.75);
    assert_eq!(doc.scene.materials[1].base_color[3], 1.0);
    assert_eq!(doc.scene.materials[1].alpha_mode, AlphaMode::Opaque);
}

#[test]
fn same_image_in_two_materials_is_one_texture() {
    let (doc, _dir) = read_files(&[
        (
            "m.obj",
            &format!("mtllib a.mtl\n{SQUARE}usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n"),
        ),
        (
            "a.mtl",
            "newmtl a\nmap_Kd t.png\nnewmtl b\nmap_Kd ./t.png\n",
        ),
        ("t.png", ""),
    ]);
    assert_eq!(doc.scene.textures.len(), 1);
    assert_eq!(
        doc.scene.materials[0].base_color_texture,
        doc.scene.materials[1].base_color_texture
    );
}

#[test]
fn missing_texture_is_a_warning_and_the_reference_is_kept() {
    let (doc, dir) = read_files(&[
        (
            "m.obj",
            &format!("mtllib a.mtl\n{SQUARE}usemtl a\nf 1 2 3\n"),
        ),
        ("a.mtl", "newmtl a\nmap_Kd gone.png\n"),
    ]);
    assert!(doc
        .warnings
        .iter()
        .any(|w| w.contains("gone.png") && w.contains("not on disk")));
    assert_eq!(
        doc.scene.textures[0].source,
        ImageSource::Path(dir.path().join("gone.png"))
    );
}

#[test]
fn texture_whose_case_differs_on_disk_is_found() {
    let (doc, dir) = read_files(&[
        (
            "m.obj",
            &format!("mtllib a.mtl\n{SQUARE}usemtl a\nf 1 2 3\n"),
        ),
        ("a.mtl", "newmtl a\nmap_Kd TEX.PNG\n"),
        ("tex.png", ""),
    ]);
    assert_eq!(
        doc.scene.textures[0].source,
        ImageSource::Path(dir.path().join("tex.png"))
    );
    assert!(doc.warnings.is_empty(), "{:?}", doc.warnings);
}

#[test]
fn several_libraries_and_names_with_spaces_or_quotes_are_found() {
    let (doc, _dir) = read_files(&[
        (
            "m.obj",
            &format!(
                "mtllib one.mtl two.mtl\nmtllib my lib.mtl\nmtllib \"sub dir/q.mtl\"\n{SQUARE}\
                 usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\nusemtl c\nf 1 2 3\nusemtl d\nf 1 2 3\n"
            ),
        ),
        ("one.mtl", "newmtl a\nKd 1 0 0\n"),
        ("two.mtl", "newmtl b\nKd 0 1 0\n"),
        ("my lib.mtl", "newmtl c\nKd 0 0 1\n"),
        ("sub dir/q.mtl", "newmtl d\nKd 0.5 0.5 0.5\n"),
    ]);
    let colors: Vec<[f32; 4]> = doc.scene.materials.iter().map(|m| m.base_color).collect();
    assert_eq!(
        colors,
        [
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0, 1.0],
            [0.5, 0.5, 0.5, 1.0]
        ]
    );
    assert!(doc.warnings.is_empty(), "{:?}", doc.warnings);
}

#[test]
fn bad_mtl_statement_is_a_warning_naming_the_library_line() {
    let (doc, _dir) = read_files(&[
        (
            "m.obj",
            &format!("mtllib a.mtl\n{SQUARE}usemtl a\nf 1 2 3\n"),
        ),
        ("a.mtl", "newmtl a\nKd 1 x 0\nKe 0 1 0\n"),
    ]);
    assert!(
        doc.warnings
            .iter()
            .any(|w| w.contains("a.mtl line 2") && w.contains("'x'")),
        "{:?}",
        doc.warnings
    );
    assert_eq!(doc.scene.materials[0].emissive, [0.0, 1.0, 0.0]);
}

#[test]
fn scene_is_one_mesh_named_after_the_file_on_one_root_node() {
    let (doc, _dir) = read_files(&[("tray part.obj", &format!("{SQUARE}f 1 2 3\n"))]);
    let s = &doc.scene;
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.meshes[0].name, "tray part");
    assert_eq!(s.roots, [0]);
    assert_eq!(s.nodes[0].mesh, Some(0));
    assert!(Path::new(doc.source.as_ref().unwrap()).ends_with("tray part.obj"));
}

/// A 2 × 1 quad at survey coordinates: x near 5·10⁵, y near 4·10⁶,
/// written to the millimetre.
const SURVEY_QUAD: &str = "v 512345.678 4123456.789 133.456\nv 512347.679 4123456.789 133.456\n\
                           v 512347.679 4123457.791 133.457\nv 512345.678 4123457.791 133.457\n\
                           f 1 2 3 4\n";

#[test]
fn survey_coordinates_are_read_relative_to_a_point_a_node_holds() {
    // Read into f32 directly, y would step by a quarter of a unit: the
    // quad's millimetres would be gone and its two rows a quarter apart
    // or merged. Relative to the box's centre they are kept, and the node
    // puts the centre back.
    let doc = read_obj(SURVEY_QUAD);
    let s = &doc.scene;
    let t: [f64; 3] = std::array::from_fn(|k| f64::from(s.nodes[0].matrix[12 + k]));
    let want = [
        [512345.678, 4123456.789, 133.456],
        [512347.679, 4123456.789, 133.456],
        [512347.679, 4123457.791, 133.457],
        [512345.678, 4123457.791, 133.457],
    ];
    for (p, w) in s.meshes[0].positions.iter().zip(want) {
        for k in 0..3 {
            let got = t[k] + f64::from(p[k]);
            assert!((got - w[k]).abs() < 1e-6, "{got} for {}", w[k]);
        }
    }
    // The point is the box's centre (to f32), so positions stay small.
    assert!(s.meshes[0]
        .positions
        .iter()
        .flatten()
        .all(|c| c.abs() < 2.0));
    // Ordinary coordinates are read as they are, under an identity node.
    let near = read_obj(&format!("{SQUARE}f 1 2 3 4\n"));
    assert_eq!(near.scene.nodes[0].matrix, wildlod_mesh::IDENTITY);
    assert_eq!(near.scene.meshes[0].positions[2], [1.0, 1.0, 0.0]);
}

#[test]
fn survey_coordinates_come_back_as_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("survey.obj");
    std::fs::write(&input, SURVEY_QUAD).expect("write");
    let doc = read(&input).unwrap_or_else(|e| panic!("{e}"));
    let output = dir.path().join("back.obj");
    wildlod_io::write(&doc, &output, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(&output).expect("read back");
    let written: Vec<&str> = text.lines().filter(|l| l.starts_with("v ")).collect();
    let want: Vec<&str> = SURVEY_QUAD
        .lines()
        .filter(|l| l.starts_with("v "))
        .collect();
    let want: Vec<String> = want.iter().map(|l| l.trim().to_string()).collect();
    assert_eq!(written, want);
}
