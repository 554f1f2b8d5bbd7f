//! Survey coordinates (UTM, site grids) in PLY, OFF and STL: read relative
//! to a point a node holds, written back in f64 where the format can hold
//! it, and a warning where it cannot (`crate::far` in the library). The
//! OBJ cases are in `obj_read.rs`.

use std::path::Path;

use wildlod_io::{read, write, Document, WriteOptions};

/// A 2 × 1 quad at survey coordinates, to the millimetre: in f32, y steps
/// by a quarter of a unit there.
const QUAD: [[f64; 3]; 4] = [
    [512345.678, 4123456.789, 133.456],
    [512347.679, 4123456.789, 133.456],
    [512347.679, 4123457.791, 133.457],
    [512345.678, 4123457.791, 133.457],
];

fn read_ok(path: &Path) -> Document {
    read(path).unwrap_or_else(|e| panic!("{e}"))
}

fn write_ok(doc: &Document, path: &Path) -> Vec<String> {
    write(doc, path, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The document's first mesh placed by the first node, in f64.
fn placed(doc: &Document) -> Vec<[f64; 3]> {
    let s = &doc.scene;
    let t: [f64; 3] = std::array::from_fn(|k| f64::from(s.nodes[0].matrix[12 + k]));
    s.meshes[0]
        .positions
        .iter()
        .map(|p| std::array::from_fn(|k| t[k] + f64::from(p[k])))
        .collect()
}

fn assert_quad(got: &[[f64; 3]], tolerance: f64) {
    assert_eq!(got.len(), 4);
    for (g, w) in got.iter().zip(QUAD) {
        for k in 0..3 {
            assert!((g[k] - w[k]).abs() < tolerance, "{} for {}", g[k], w[k]);
        }
    }
}

fn binary_ply(coordinate: &str) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\n\
         property {coordinate} x\nproperty {coordinate} y\nproperty {coordinate} z\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    for p in QUAD {
        for c in p {
            if coordinate == "double" {
                out.extend_from_slice(&c.to_le_bytes());
            } else {
                out.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
    }
    out.push(4);
    for i in 0..4i32 {
        out.extend_from_slice(&i.to_le_bytes());
    }
    out
}

#[test]
fn ply_doubles_keep_their_millimetres() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("site.ply");
    std::fs::write(&path, binary_ply("double")).expect("write");
    let doc = read_ok(&path);
    assert_quad(&placed(&doc), 1e-6);
    // Relative to the box's centre, positions stay small.
    assert!(doc.scene.meshes[0]
        .positions
        .iter()
        .flatten()
        .all(|c| c.abs() < 2.0));
    // Written back as doubles, at the same coordinates.
    let out = dir.path().join("back.ply");
    write_ok(&doc, &out);
    let head = std::fs::read(&out).expect("read back");
    let text = String::from_utf8_lossy(&head[..200]);
    assert!(text.contains("property double x"), "{text}");
    let again = read_ok(&out);
    assert_quad(&placed(&again), 1e-6);
}

#[test]
fn ply_floats_far_away_are_read_as_the_file_rounded_them() {
    // A binary `float` file already lost the millimetres: what it holds is
    // read exactly, relative to a point, and nothing is invented.
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("site32.ply");
    std::fs::write(&path, binary_ply("float")).expect("write");
    let doc = read_ok(&path);
    for (g, w) in placed(&doc).iter().zip(QUAD) {
        for k in 0..3 {
            assert_eq!(g[k], f64::from(w[k] as f32));
        }
    }
}

#[test]
fn ascii_ply_floats_keep_the_digits_the_text_has() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("site.ply");
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
    );
    for p in QUAD {
        text += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    text += "4 0 1 2 3\n";
    std::fs::write(&path, text).expect("write");
    assert_quad(&placed(&read_ok(&path)), 1e-6);
}

#[test]
fn ply_near_the_origin_is_read_and_written_as_before() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("near.ply");
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                end_header\n0.1 0 0\n1 0 0\n0 1 0.3\n3 0 1 2\n";
    std::fs::write(&path, text).expect("write");
    let doc = read_ok(&path);
    assert_eq!(doc.scene.nodes[0].matrix, wildlod_mesh::IDENTITY);
    assert_eq!(doc.scene.meshes[0].positions[0], [0.1, 0.0, 0.0]);
    let out = dir.path().join("back.ply");
    write_ok(&doc, &out);
    let head = std::fs::read(&out).expect("read back");
    assert!(String::from_utf8_lossy(&head[..150]).contains("property float x"));
}

#[test]
fn off_survey_coordinates_come_back_as_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("site.off");
    let mut text = String::from("OFF\n4 1 0\n");
    for p in QUAD {
        text += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    text += "4 0 1 2 3\n";
    std::fs::write(&path, &text).expect("write");
    let doc = read_ok(&path);
    assert_quad(&placed(&doc), 1e-6);
    let out = dir.path().join("back.off");
    write_ok(&doc, &out);
    let back = std::fs::read_to_string(&out).expect("read back");
    let lines: Vec<&str> = back.lines().collect();
    let want: Vec<String> = QUAD
        .iter()
        .map(|p| format!("{} {} {}", p[0], p[1], p[2]))
        .collect();
    assert_eq!(&lines[2..6], want.as_slice());
}

#[test]
fn stl_says_it_rounds_survey_coordinates() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("site.ply");
    std::fs::write(&path, binary_ply("double")).expect("write");
    let doc = read_ok(&path);
    let warnings = write_ok(&doc, &dir.path().join("site.stl"));
    assert!(
        warnings.iter().any(|w| w.contains("32-bit floats round")),
        "{warnings:?}"
    );
    // Near the origin, no such warning.
    let near = dir.path().join("near.off");
    std::fs::write(&near, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").expect("write");
    let warnings = write_ok(&read_ok(&near), &dir.path().join("near.stl"));
    assert!(
        warnings.iter().all(|w| !w.contains("32-bit")),
        "{warnings:?}"
    );
}
