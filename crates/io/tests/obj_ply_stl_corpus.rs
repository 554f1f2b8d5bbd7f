//! Every OBJ and STL of the shared corpus: read, validate, face counts by
//! arity as the corpus README states them, and round trips through the same
//! format (and OBJ → PLY → PLY) with bit-equal data per corner.

use std::path::{Path, PathBuf};

use wildlod_io::{read, write, Document, WriteOptions};
use wildlod_mesh::{ImageSource, Mesh, Semantic};
use wildlod_testkit::{corpus, mesh_files, readme_face_counts as readme_counts, short};

fn obj_and_stl(root: &Path) -> Vec<PathBuf> {
    mesh_files(root, "")
        .into_iter()
        .filter(|p| matches!(ext(p).as_str(), "obj" | "stl"))
        .collect()
}

fn ext(p: &Path) -> String {
    p.extension()
        .expect("mesh files have extensions")
        .to_string_lossy()
        .to_ascii_lowercase()
}

#[test]
fn every_corpus_obj_and_stl_reads_with_the_readme_face_counts() {
    let Some(root) = corpus("every_corpus_obj_and_stl_reads_with_the_readme_face_counts") else {
        return;
    };
    let table = readme_counts(&root);
    let files = obj_and_stl(&root);
    assert!(
        files.len() >= 25,
        "found only {} OBJ/STL files",
        files.len()
    );
    for f in files {
        let name = short(&root, &f);
        let doc = read(&f).unwrap_or_else(|e| panic!("{e}"));
        doc.scene.validate().unwrap();
        assert_eq!(doc.scene.meshes.len(), 1, "{name}");
        let counts = doc.scene.meshes[0].faces.arity_counts();
        let expected = table
            .get(&PathBuf::from(&name))
            .unwrap_or_else(|| panic!("{name} is not in the README table"));
        assert_eq!(counts, *expected, "{name}: faces by arity");
    }
}

/// Asserts that two meshes hold the same data: positions bit for bit,
/// faces, parts, and every stream's value at every corner.
fn assert_same_mesh(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.positions.len(), b.positions.len(), "{what}: vertex count");
    let bits = |p: &[f32; 3]| p.map(f32::to_bits);
    assert!(
        a.positions
            .iter()
            .map(bits)
            .eq(b.positions.iter().map(bits)),
        "{what}: positions differ"
    );
    assert_eq!(a.faces, b.faces, "{what}: faces");
    assert_eq!(a.face_parts, b.face_parts, "{what}: face parts");
    assert_eq!(a.parts, b.parts, "{what}: parts");
    assert_same_corner_values(a, b, what);
}

/// Every stream of `a` exists in `b` with bit-equal values per corner.
fn assert_same_corner_values(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.attributes.len(), b.attributes.len(), "{what}: streams");
    for sa in &a.attributes {
        let sb = b
            .attribute(&sa.semantic)
            .unwrap_or_else(|| panic!("{what}: {:?} lost", sa.semantic));
        for c in 0..a.faces.corner_count() {
            let va = sa
                .corner_value(c)
                .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            let vb = sb
                .corner_value(c)
                .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            assert_eq!(va, vb, "{what}: {:?} at corner {c}", sa.semantic);
        }
    }
}

fn round_trip(doc: &Document, dir: &Path, file: &str) -> (Document, Vec<String>) {
    let out = dir.join(file);
    let warnings = write(doc, &out, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let back = read(&out).unwrap_or_else(|e| panic!("{e}"));
    (back, warnings)
}

#[test]
fn every_corpus_obj_round_trips_through_obj_bit_exactly() {
    let Some(root) = corpus("every_corpus_obj_round_trips_through_obj_bit_exactly") else {
        return;
    };
    for f in obj_and_stl(&root).into_iter().filter(|p| ext(p) == "obj") {
        let name = short(&root, &f);
        let doc = read(&f).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let (back, warnings) = round_trip(&doc, dir.path(), "out.obj");
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert_same_mesh(&doc.scene.meshes[0], &back.scene.meshes[0], &name);
        assert_eq!(
            doc.scene.materials, back.scene.materials,
            "{name}: materials"
        );
        // Textures are copied beside the output (so that it can be moved):
        // the same images, names and samplers, read from the copies.
        assert_eq!(doc.scene.textures.len(), back.scene.textures.len());
        for (a, b) in doc.scene.textures.iter().zip(&back.scene.textures) {
            assert_eq!(
                (&a.name, a.sampler),
                (&b.name, b.sampler),
                "{name}: textures"
            );
            match (&a.source, &b.source) {
                (ImageSource::Path(pa), ImageSource::Path(pb)) => {
                    assert!(pb.starts_with(dir.path()), "{name}: {}", pb.display());
                    assert_eq!(std::fs::read(pa).ok(), std::fs::read(pb).ok(), "{name}");
                }
                other => panic!("{name}: {other:?}"),
            }
        }
        // The arities the README states survive too.
        assert_eq!(
            doc.scene.meshes[0].faces.arity_counts(),
            back.scene.meshes[0].faces.arity_counts()
        );
    }
}

#[test]
fn every_corpus_stl_round_trips_through_binary_stl() {
    let Some(root) = corpus("every_corpus_stl_round_trips_through_binary_stl") else {
        return;
    };
    for f in obj_and_stl(&root).into_iter().filter(|p| ext(p) == "stl") {
        let name = short(&root, &f);
        let doc = read(&f).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let (back, warnings) = round_trip(&doc, dir.path(), "out.stl");
        let (a, b) = (&doc.scene.meshes[0], &back.scene.meshes[0]);
        assert_eq!(a.positions, b.positions, "{name}: positions");
        assert_eq!(a.faces, b.faces, "{name}: faces");
        // Binary STL has one unnamed solid; several solids are merged and
        // the writer says so.
        assert_eq!(b.parts.len(), 1, "{name}");
        assert_eq!(b.parts[0].name, "", "{name}");
        assert_eq!(
            a.parts.len() > 1,
            warnings.iter().any(|w| w.contains("one solid")),
            "{name}: {warnings:?}"
        );
        assert!(b.materials_free(), "{name}");
        // Written binary, the file size says so exactly.
        let len = std::fs::metadata(dir.path().join("out.stl")).unwrap().len();
        assert_eq!(len, 84 + 50 * a.faces.len() as u64, "{name}");
    }
}

trait MaterialsFree {
    fn materials_free(&self) -> bool;
}

impl MaterialsFree for Mesh {
    fn materials_free(&self) -> bool {
        self.parts.iter().all(|p| p.material.is_none()) && self.attributes.is_empty()
    }
}

#[test]
fn every_corpus_obj_converts_to_ply_with_the_same_corners() {
    let Some(root) = corpus("every_corpus_obj_converts_to_ply_with_the_same_corners") else {
        return;
    };
    for f in obj_and_stl(&root).into_iter().filter(|p| ext(p) == "obj") {
        let name = short(&root, &f);
        let doc = read(&f).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let (ply, _) = round_trip(&doc, dir.path(), "out.ply");
        let (a, b) = (&doc.scene.meshes[0], &ply.scene.meshes[0]);
        assert_eq!(a.faces.offsets, b.faces.offsets, "{name}: arities");
        for c in 0..a.faces.corner_count() {
            let pa = a.positions[a.faces.indices[c] as usize].map(f32::to_bits);
            let pb = b.positions[b.faces.indices[c] as usize].map(f32::to_bits);
            assert_eq!(pa, pb, "{name}: position at corner {c}");
        }
        for sa in &a.attributes {
            let sb = b.attribute(&sa.semantic).unwrap();
            for c in 0..a.faces.corner_count() {
                let Some(va) = sa.corner_value(c) else {
                    continue;
                };
                let vb = sb.corner_value(c).unwrap();
                if sa.semantic == Semantic::TexCoord(0) {
                    // PLY's 32-bit t = 1 − v cannot hold every bit of a v
                    // below 0.5 or outside [0, 1] (OBJ text can): equal to
                    // half a float step of 1 − v.
                    assert_eq!(va[0], vb[0], "{name}: u at {c}");
                    let tol = f32::EPSILON * (1.0 - va[1]).abs() / 2.0;
                    assert!((va[1] - vb[1]).abs() <= tol, "{name}: v at {c}");
                } else {
                    assert_eq!(va, vb, "{name}: {:?} at {c}", sa.semantic);
                }
            }
        }
        if a.attributes.is_empty() {
            assert_eq!(a.positions, b.positions, "{name}: positions as stored");
        }
        // PLY → PLY changes nothing at all.
        let (again, warnings) = round_trip(&ply, dir.path(), "again.ply");
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert_same_mesh(b, &again.scene.meshes[0], &name);
    }
}

#[test]
fn spider_windows_texture_paths_resolve_to_existing_images() {
    let Some(root) = corpus("spider_windows_texture_paths_resolve_to_existing_images") else {
        return;
    };
    let doc = read(root.join("wild/spider/spider.obj")).unwrap();
    // The MTL defines 5 materials; faces use 4 (Brusttex is never used).
    let names: Vec<&str> = doc
        .scene
        .materials
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    assert_eq!(names, ["HLeibTex", "Skin", "BeinTex", "Augentex"]);
    assert_eq!(doc.scene.textures.len(), 4);
    for t in &doc.scene.textures {
        let ImageSource::Path(p) = &t.source else {
            panic!("{t:?}")
        };
        assert!(p.is_absolute() && p.is_file(), "{}", p.display());
        assert!(!p.to_string_lossy().contains('\\'));
    }
    let skin = doc
        .scene
        .materials
        .iter()
        .find(|m| m.name == "Skin")
        .unwrap();
    let tex = &doc.scene.textures[skin.base_color_texture.unwrap().texture as usize];
    assert_eq!(
        tex.source,
        ImageSource::Path(root.join("wild/spider/wal67ar_small.jpg"))
    );
    assert!(
        doc.warnings.iter().all(|w| !w.contains("not on disk")),
        "{:?}",
        doc.warnings
    );
}

#[test]
fn missing_material_library_is_a_warning_not_an_error() {
    let Some(root) = corpus("missing_material_library_is_a_warning_not_an_error") else {
        return;
    };
    for f in [
        "quad/quadknot.obj",
        "wild/nonmanifold_edge.obj",
        "wild/nonmanifold_vertex.obj",
    ] {
        let doc = read(root.join(f)).unwrap();
        assert!(
            doc.warnings
                .iter()
                .any(|w| w.contains("material library") && w.contains("cannot be read")),
            "{f}: {:?}",
            doc.warnings
        );
    }
}

#[test]
fn textured_obj_written_elsewhere_copies_its_texture_beside_the_mtl() {
    let Some(root) = corpus("textured_obj_written_elsewhere_copies_its_texture_beside_the_mtl")
    else {
        return;
    };
    let doc = read(root.join("textured/bob/bob_tri.obj")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    write(&doc, dir.path().join("bob.obj"), &WriteOptions::default()).unwrap();
    let mtl = std::fs::read_to_string(dir.path().join("bob.mtl")).unwrap();
    assert!(mtl.contains("map_Kd bob_diffuse.png\n"), "{mtl}");
    assert_eq!(
        std::fs::read(dir.path().join("bob_diffuse.png")).unwrap(),
        std::fs::read(root.join("textured/bob/bob_diffuse.png")).unwrap()
    );
}
