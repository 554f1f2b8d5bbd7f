//! OFF (and COFF, NOFF, STOFF) reading and writing, hostile OFF headers,
//! and faces with fewer than three distinct vertices in OBJ and PLY.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use std::path::{Path, PathBuf};

use wildlod_io::{Document, ErrorKind, WriteOptions};
use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Scene, Semantic};

fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A triangle, a quad and a pentagon over 8 vertices, with a color per
/// vertex (RGBA).
fn colored_polygons() -> Mesh {
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.25],
        [2.0, 0.0, 0.5],
        [3.0, 0.5, 0.5],
        [2.5, 1.5, 0.75],
        [1.5, 1.25, 1e-7],
    ];
    let mut faces = Faces::new();
    faces.push(&[0, 1, 3]);
    faces.push(&[1, 2, 7, 3]);
    faces.push(&[1, 4, 5, 6, 7]);
    let mut m = Mesh::from_polygons(positions, faces);
    let values: Vec<f32> = (0..8)
        .flat_map(|v| [v as f32 / 8.0, 0.5, 1.0 - v as f32 / 8.0, 0.75])
        .collect();
    m.attributes.push(Attribute {
        semantic: Semantic::Color(0),
        components: 4,
        values,
        indices: m.faces.indices.clone(),
        format: ComponentFormat::F32,
    });
    m
}

#[test]
fn off_round_trips_positions_polygons_and_colors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("polygons.off");
    let m = colored_polygons();
    wildlod_io::write(
        &Document::from_scene(Scene::from_mesh(m.clone())),
        &path,
        &WriteOptions::default(),
    )
    .unwrap();
    assert!(std::fs::read_to_string(&path)
        .unwrap()
        .starts_with("COFF\n"));
    let back = wildlod_io::read(&path).unwrap().scene;
    let b = &back.meshes[0];
    assert_eq!(b.positions, m.positions, "positions bit for bit");
    assert_eq!(b.faces, m.faces, "faces and their arities");
    let (c0, c1) = (
        m.attribute(&Semantic::Color(0)).unwrap(),
        b.attribute(&Semantic::Color(0)).unwrap(),
    );
    assert_eq!(c1.components, 4);
    for corner in 0..m.faces.corner_count() {
        assert_eq!(c0.corner_value(corner), c1.corner_value(corner), "{corner}");
    }
}

#[test]
fn off_variants_read_with_comments_normals_colors_and_face_colors() {
    let dir = tempfile::tempdir().unwrap();
    // NOFF with comments, counts on the header line, integer colors on
    // faces (0-255), a colormap index on one face.
    let p = write_file(
        dir.path(),
        "a.off",
        "# made by hand\nNOFF 4 3 0\n\
         0 0 0  0 0 1\n1 0 0  0 0 1 # a comment\n\n1 1 0 0 0 1\n0 1 0 0 0 1\n\
         3 0 1 2 255 0 0\n3 0 2 3 0 255 0\n3 0 1 3 7\n",
    );
    let doc = wildlod_io::read(&p).unwrap();
    let m = &doc.scene.meshes[0];
    assert_eq!(m.faces.len(), 3);
    assert_eq!(m.positions[2], [1.0, 1.0, 0.0]);
    let n = m.attribute(&Semantic::Normal).unwrap();
    assert_eq!(n.corner_value(0), Some(&[0.0, 0.0, 1.0][..]));
    let c = m.attribute(&Semantic::Color(0)).unwrap();
    assert_eq!(c.corner_value(0), Some(&[1.0, 0.0, 0.0][..]));
    assert_eq!(c.corner_value(3), Some(&[0.0, 1.0, 0.0][..]));
    assert_eq!(c.corner_value(6), None, "a colormap index is no color");
    // Face colors write back as face colors.
    let out = dir.path().join("b.off");
    wildlod_io::write(&doc, &out, &WriteOptions::default()).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("NOFF\n"), "{text}");
    assert!(text.contains("\n3 0 1 2 1 0 0\n"), "{text}");
    // COFF with float RGB colors, and a file without the keyword.
    let p = write_file(
        dir.path(),
        "c.off",
        "COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 0.5\n3 0 1 2\n",
    );
    let m = &wildlod_io::read(&p).unwrap().scene.meshes[0];
    let c = m.attribute(&Semantic::Color(0)).unwrap();
    assert_eq!(c.corner_value(2), Some(&[0.0, 0.0, 0.5][..]));
    let p = write_file(dir.path(), "d.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    assert_eq!(wildlod_io::read(&p).unwrap().scene.meshes[0].faces.len(), 1);
}

#[test]
fn off_faces_with_fewer_than_three_distinct_vertices_are_skipped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(
        dir.path(),
        "e.off",
        "OFF\n4 4 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n2 0 1\n3 2 2 3\n4 0 1 2 3\n",
    );
    let doc = wildlod_io::read(&p).unwrap();
    assert_eq!(doc.scene.meshes[0].faces.len(), 2);
    assert_eq!(
        doc.warnings,
        vec!["skipped 2 faces with fewer than 3 distinct vertices".to_string()]
    );
}

/// Reading `text` as OFF fails (no panic) with the file named and a
/// message containing `needle`.
fn refused(text: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(dir.path(), "hostile.off", text);
    let e = wildlod_io::read(&p).expect_err(text);
    let msg = e.to_string();
    assert!(msg.contains("hostile.off"), "{msg}");
    assert!(msg.contains(needle), "{text:?}: {msg}");
}

#[test]
fn hostile_off_headers_give_errors_not_panics() {
    // Counts far beyond what the file can hold: refused before allocating.
    refused("OFF\n4000000000 1 0\n0 0 0\n", "OFF vertex count declares");
    refused("OFF\n3 99999999999 0\n0 0 0\n", "OFF face count declares");
    refused("OFF\n-3 1 0\n", "not a non-negative integer");
    refused(
        "OFF\n18446744073709551616 1 0\n",
        "not a non-negative integer",
    );
    // Truncated: missing vertices, missing faces, no counts.
    refused("OFF\n3 1 0\n0 0 0\n1 0 0\n", "ends after 2 of 3 vertices");
    refused(
        "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "ends after 1 of 2 faces",
    );
    refused("OFF\n", "no vertex and face counts");
    refused("OFF\n3\n", "counts");
    // Bad faces and values.
    refused("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "out of range");
    refused(
        "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2\n",
        "announces 5 corners",
    );
    refused(
        "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
        "not a finite number",
    );
    refused(
        "OFF\n3 1 0\n0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "vertex 0 has 2 values",
    );
    // Variants we do not read, and things that are not OFF.
    refused("4OFF\n1 0 0\n0 0 0 0\n", "4D");
    refused("OFF BINARY\n", "binary OFF");
    refused("PLY\n3 1 0\n", "not an OFF header");
    refused("# only a comment\n", "no header");
    refused("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 0 0\n", "no faces");
}

#[test]
fn obj_and_ply_skip_faces_with_fewer_than_three_distinct_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write_file(
        dir.path(),
        "w.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\nf 2 2 3\nl 1 2\np 1\n",
    );
    let doc = wildlod_io::read(&obj).unwrap();
    assert_eq!(doc.scene.meshes[0].faces.len(), 1);
    assert!(
        doc.warnings
            .iter()
            .any(|w| w == "skipped 2 faces with fewer than 3 distinct vertices"),
        "{:?}",
        doc.warnings
    );
    let ply = write_file(
        dir.path(),
        "w.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n1 2\n",
    );
    let doc = wildlod_io::read(&ply).unwrap();
    assert_eq!(doc.scene.meshes[0].faces.len(), 1);
    assert_eq!(
        doc.warnings,
        vec!["skipped 2 faces with fewer than 3 distinct vertices".to_string()]
    );
    // A file of nothing but such faces has no faces.
    let obj = write_file(dir.path(), "x.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
    let e = wildlod_io::read(&obj).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::Malformed { .. }), "{e}");
}
