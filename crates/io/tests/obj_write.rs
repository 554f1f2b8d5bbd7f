//! OBJ + MTL writing: flattening, streams, parts, materials, images, and
//! what OBJ cannot hold.

use std::path::Path;

use wildlod_io::{read, write, Document, ErrorKind, WriteOptions};
use wildlod_mesh::shapes::{cube, quad_grid};
use wildlod_mesh::{
    Animation, Attribute, ComponentFormat, ImageSource, Material, Mesh, Node, Part, Scene,
    Semantic, Texture, TextureRef, ABSENT, IDENTITY,
};

fn write_ok(doc: &Document, path: &Path) -> Vec<String> {
    write(doc, path, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A 2×1 quad grid in two parts, the second with a textured material.
fn two_part_grid() -> Scene {
    let mut m = quad_grid(2, 1);
    m.name = "grid".into();
    m.parts = vec![
        Part {
            name: "left".into(),
            material: None,
        },
        Part {
            name: "right".into(),
            material: Some(0),
        },
    ];
    m.face_parts = vec![0, 1];
    let mut s = Scene::from_mesh(m);
    s.materials.push(Material {
        name: "paint".into(),
        base_color: [0.5, 0.25, 0.125, 1.0],
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        metallic: 0.0,
        ..Material::default()
    });
    s.textures.push(Texture {
        name: "png".into(),
        source: ImageSource::Embedded {
            bytes: b"\x89PNG fake".to_vec(),
            mime_type: "image/png".into(),
        },
        sampler: Default::default(),
    });
    s
}

#[test]
fn quads_parts_and_uvs_survive_a_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let doc = Document::from_scene(two_part_grid());
    let out = dir.path().join("grid.obj");
    assert!(write_ok(&doc, &out).is_empty());
    let back = read(&out).unwrap();
    let (a, b) = (&doc.scene.meshes[0], &back.scene.meshes[0]);
    assert_eq!(a.faces, b.faces);
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.parts, b.parts);
    assert_eq!(a.face_parts, b.face_parts);
    let (ua, ub) = (&a.attributes[0], &b.attributes[0]);
    for c in 0..a.faces.corner_count() {
        assert_eq!(ua.corner_value(c), ub.corner_value(c));
    }
    assert_eq!(back.scene.materials[0].base_color, [0.5, 0.25, 0.125, 1.0]);
}

#[test]
fn embedded_image_is_written_beside_the_obj_and_named_relative() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grid.obj");
    write_ok(&Document::from_scene(two_part_grid()), &out);
    assert_eq!(file_names(dir.path()), ["grid.mtl", "grid.obj", "png.png"]);
    // Named after its texture ("png"), as the .gltf writer names images
    // held in memory.
    assert_eq!(
        std::fs::read(dir.path().join("png.png")).unwrap(),
        b"\x89PNG fake"
    );
    let mtl = std::fs::read_to_string(dir.path().join("grid.mtl")).unwrap();
    assert!(mtl.contains("map_Kd png.png\n"), "{mtl}");
    let obj = std::fs::read_to_string(&out).unwrap();
    assert!(obj.contains("mtllib grid.mtl\n"));
}

#[test]
fn part_without_material_after_one_with_keeps_no_material() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = two_part_grid();
    s.meshes[0].face_parts = vec![1, 0];
    let out = dir.path().join("g.obj");
    write_ok(&Document::from_scene(s.clone()), &out);
    let back = read(&out).unwrap();
    let parts: Vec<_> = back.scene.meshes[0]
        .parts
        .iter()
        .map(|p| (p.name.as_str(), p.material))
        .collect();
    assert_eq!(parts, [("right", Some(0)), ("left", None)]);
}

#[test]
fn instances_are_flattened_with_their_world_matrices() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = Scene::from_mesh(cube());
    s.nodes[0].mesh = None;
    s.nodes[0].children = vec![1, 2];
    for x in [10.0, 20.0] {
        let mut m = IDENTITY;
        m[12] = x;
        s.nodes.push(Node {
            matrix: m,
            mesh: Some(0),
            ..Node::default()
        });
    }
    let out = dir.path().join("two.obj");
    write_ok(&Document::from_scene(s), &out);
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("\no ").count(), 2, "{text}");
    let back = read(&out).unwrap();
    let m = &back.scene.meshes[0];
    assert_eq!(m.positions.len(), 16);
    assert_eq!(m.faces.len(), 12);
    assert_eq!(m.positions[1], [11.0, 0.0, 0.0]);
    assert_eq!(m.positions[9], [21.0, 0.0, 0.0]);
    // The second copy's faces use its own vertices.
    assert_eq!(m.faces.face(6), &[8, 10, 11, 9]);
}

#[test]
fn floats_are_written_shortest_and_read_back_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let p = vec![
        [0.1, 1.0e-7, -3.402_823_5e38],
        [f32::MIN_POSITIVE, 1.0 / 3.0, -0.0],
        [123_456.79, 5e-45, 2.5],
    ];
    let s = Scene::from_mesh(Mesh::from_triangles(p.clone(), &[0, 1, 2]));
    let out = dir.path().join("f.obj");
    write_ok(&Document::from_scene(s), &out);
    let back = read(&out).unwrap();
    let bits = |v: &Vec<[f32; 3]>| v.iter().map(|q| q.map(f32::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&back.scene.meshes[0].positions), bits(&p));
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("v 0.1 0.0000001 "));
}

#[test]
fn texture_v_is_written_with_the_bottom_left_origin_and_reads_back_bit_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = Mesh::from_triangles(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2]);
    let values = vec![0.0, 0.0, 0.5, 0.1, 0.25, 0.123_456_79];
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: values.clone(),
        indices: vec![0, 1, 2],
        format: ComponentFormat::F32,
    });
    let out = dir.path().join("v.obj");
    write_ok(&Document::from_scene(Scene::from_mesh(m)), &out);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("vt 0 1\nvt 0.5 0.9\n"), "{text}");
    let back = read(&out).unwrap();
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&back.scene.meshes[0].attributes[0].values),
        bits(&values)
    );
}

#[test]
fn face_with_partly_absent_uvs_drops_uvs_for_that_face() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = quad_grid(2, 1);
    m.attributes[0].indices[5] = ABSENT;
    let out = dir.path().join("a.obj");
    write_ok(&Document::from_scene(Scene::from_mesh(m)), &out);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("f 1/1 2/2 5/5 4/4\n"), "{text}");
    assert!(text.contains("f 2 3 6 5\n"), "{text}");
}

#[test]
fn position_colors_are_kept_and_per_corner_colors_are_dropped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = cube();
    let n = m.faces.corner_count();
    m.attributes.push(Attribute {
        semantic: Semantic::Color(0),
        components: 4,
        values: (0..8)
            .flat_map(|v| [v as f32 / 8.0, 0.5, 1.0, 0.25])
            .collect(),
        indices: m.faces.indices.clone(),
        format: ComponentFormat::F32,
    });
    let out = dir.path().join("c.obj");
    let doc = Document::from_scene(Scene::from_mesh(m.clone()));
    assert!(write_ok(&doc, &out).is_empty());
    let back = read(&out).unwrap();
    let c = back.scene.meshes[0].attribute(&Semantic::Color(0)).unwrap();
    assert_eq!(c.components, 4);
    assert_eq!(c.corner_value(1), Some(&[2.0 / 8.0, 0.5, 1.0, 0.25][..]));

    // Corner colors that differ at one position have no OBJ form.
    m.attributes[0].indices = (0..n as u32).map(|c| c % 8).collect();
    let warnings = write_ok(&Document::from_scene(Scene::from_mesh(m)), &out);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("per-corner vertex colors")),
        "{warnings:?}"
    );
    assert!(read(&out).unwrap().scene.meshes[0]
        .attribute(&Semantic::Color(0))
        .is_none());
}

#[test]
fn content_obj_cannot_hold_is_dropped_with_one_warning_each() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = quad_grid(1, 1);
    let corners = m.faces.indices.clone();
    for semantic in [
        Semantic::TexCoord(1),
        Semantic::Tangent,
        Semantic::TexCoord(2),
    ] {
        m.attributes.push(Attribute {
            semantic,
            components: 4,
            values: vec![0.0; 16],
            indices: corners.clone(),
            format: ComponentFormat::F32,
        });
    }
    let mut s = Scene::from_mesh(m);
    s.animations.push(Animation::default());
    let warnings = write_ok(&Document::from_scene(s), &dir.path().join("w.obj"));
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    for what in ["animations", "tangents", "UV sets beyond the first"] {
        assert!(
            warnings.iter().any(|w| w.contains(what)),
            "{what}: {warnings:?}"
        );
    }
}

#[test]
fn material_names_are_made_unique_and_never_empty() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = quad_grid(3, 1);
    m.parts = (0..3)
        .map(|i| Part {
            name: String::new(),
            material: Some(i),
        })
        .collect();
    m.face_parts = vec![0, 1, 2];
    let mut s = Scene::from_mesh(m);
    for name in ["same", "same", ""] {
        s.materials.push(Material {
            name: name.into(),
            ..Material::default()
        });
    }
    let out = dir.path().join("n.obj");
    write_ok(&Document::from_scene(s), &out);
    let back = read(&out).unwrap();
    let names: Vec<_> = back
        .scene
        .materials
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    assert_eq!(names, ["same", "same_1", "material_2"]);
    // glTF's metallic default of 1 is written, since OBJ's default is 0.
    assert!(back.scene.materials.iter().all(|m| m.metallic == 1.0));
}

#[test]
fn writing_over_the_source_is_refused_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("in.obj");
    std::fs::write(
        &src,
        "mtllib in.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    )
    .unwrap();
    let doc = read(&src).unwrap();
    let err = write(&doc, &src, &WriteOptions::default()).unwrap_err();
    assert!(
        matches!(err.kind, ErrorKind::WouldOverwriteInput(_)),
        "{err}"
    );
    assert_eq!(file_names(dir.path()), ["in.obj"]);
}

#[test]
fn extracted_image_may_not_replace_a_texture_the_scene_reads() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = two_part_grid();
    let existing = dir.path().join("png.png");
    std::fs::write(&existing, b"input texture").unwrap();
    // Texture 1 is read from png.png; texture 0 (embedded, named "png")
    // would be extracted under that very name.
    s.textures.push(Texture {
        name: "disk".into(),
        source: ImageSource::Path(existing.clone()),
        sampler: Default::default(),
    });
    s.materials[0].normal_texture = Some(TextureRef {
        texture: 1,
        tex_coord: 0,
    });
    let err = write(
        &Document::from_scene(s),
        dir.path().join("out.obj"),
        &WriteOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(err.kind, ErrorKind::WouldOverwriteInput(_)),
        "{err}"
    );
    assert_eq!(std::fs::read(&existing).unwrap(), b"input texture");
    assert_eq!(file_names(dir.path()), ["png.png"]);
}

#[test]
fn failed_write_into_a_missing_directory_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("missing/grid.obj");
    assert!(write(
        &Document::from_scene(two_part_grid()),
        &out,
        &WriteOptions::default()
    )
    .is_err());
    assert!(file_names(dir.path()).is_empty());
}

#[test]
fn texture_inside_the_output_directory_is_named_relative() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    let mut s = two_part_grid();
    s.textures[0].source = ImageSource::Path(dir.path().join("tex/a b.png"));
    write_ok(&Document::from_scene(s), &dir.path().join("r.obj"));
    let mtl = std::fs::read_to_string(dir.path().join("r.mtl")).unwrap();
    assert!(mtl.contains("map_Kd tex/a b.png\n"), "{mtl}");
    let back = read(dir.path().join("r.obj")).unwrap();
    assert_eq!(
        back.scene.textures[0].source,
        ImageSource::Path(dir.path().join("tex/a b.png"))
    );
}

#[test]
fn material_library_of_the_source_is_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("a.obj");
    std::fs::write(
        &src,
        "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("b.mtl"), "newmtl m\nKd 1 0 0\n").unwrap();
    let doc = read(&src).unwrap();
    let err = write(&doc, dir.path().join("b.obj"), &WriteOptions::default()).unwrap_err();
    assert!(
        matches!(err.kind, ErrorKind::WouldOverwriteInput(_)),
        "{err}"
    );
    assert_eq!(file_names(dir.path()), ["a.obj", "b.mtl"]);
    // Writing elsewhere is fine.
    write_ok(&doc, &dir.path().join("c.obj"));
}

#[test]
fn map_options_stay_with_their_image_and_go_with_a_new_one() {
    // `-s` and `-o` (texture scale and offset) and `-clamp` mean something
    // to renderers that honour them; the scene has no field for them. A
    // kept-UV output keeps them before the same image; a material whose
    // image changed (a re-bake) gets none.
    let dir = tempfile::tempdir().expect("temp dir");
    let src = dir.path().join("src");
    std::fs::create_dir(&src).expect("mkdir");
    std::fs::write(src.join("t.png"), b"\x89PNG\r\n\x1a\n not decoded").expect("image");
    std::fs::write(
        src.join("m.mtl"),
        "newmtl tiled\nKd 1 1 1\nmap_Kd -s 2 2 1 -clamp on t.png\nmap_Bump -bm 0.5 t.png\n",
    )
    .expect("mtl");
    std::fs::write(
        src.join("a.obj"),
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl tiled\nf 1/1 2/2 3/3\n",
    )
    .expect("obj");
    let doc = read(src.join("a.obj")).expect("reads");
    let out = dir.path().join("kept");
    std::fs::create_dir(&out).expect("mkdir");
    write_ok(&doc, &out.join("b.obj"));
    let mtl = std::fs::read_to_string(out.join("b.mtl")).expect("mtl");
    assert!(mtl.contains("map_Kd -s 2 2 1 -clamp on t.png"), "{mtl}");
    assert!(mtl.contains("map_Bump -bm 0.5 t.png"), "{mtl}");
    // The base colour replaced by another image: its options do not apply.
    let mut baked = doc.clone();
    baked.scene.textures.push(wildlod_mesh::Texture {
        name: "baked".into(),
        source: ImageSource::Embedded {
            bytes: b"\x89PNG\r\n\x1a\n baked".to_vec(),
            mime_type: "image/png".into(),
        },
        sampler: Default::default(),
    });
    let new = baked.scene.textures.len() as u32 - 1;
    if let Some(r) = baked.scene.materials[0].base_color_texture.as_mut() {
        r.texture = new;
    }
    let out = dir.path().join("baked");
    std::fs::create_dir(&out).expect("mkdir");
    write_ok(&baked, &out.join("b.obj"));
    let mtl = std::fs::read_to_string(out.join("b.mtl")).expect("mtl");
    let line = mtl
        .lines()
        .find(|l| l.starts_with("map_Kd"))
        .expect("map_Kd");
    assert!(!line.contains("-s") && !line.contains("-clamp"), "{mtl}");
    assert!(mtl.contains("map_Bump -bm 0.5 t.png"), "{mtl}");
}
