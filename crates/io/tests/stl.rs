//! STL reading (ASCII and binary, told apart by size first) and binary
//! writing.

use std::path::Path;

use wildlod_io::{read, write, Document, WriteOptions};
use wildlod_mesh::shapes::cube;
use wildlod_mesh::{Node, Scene, IDENTITY};

fn read_bytes(dir: &Path, name: &str, bytes: &[u8]) -> Document {
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write test file");
    read(&p).unwrap_or_else(|e| panic!("{e}"))
}

/// A binary STL of the given triangles with an arbitrary header.
fn binary(header: &[u8], tris: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut out = vec![b' '; 80];
    out[..header.len()].copy_from_slice(header);
    out.extend_from_slice(&(tris.len() as u32).to_le_bytes());
    for t in tris {
        out.extend_from_slice(&[0u8; 12]);
        for v in t {
            for c in v {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[test]
fn binary_file_whose_header_starts_with_solid_reads_as_binary() {
    let dir = tempfile::tempdir().unwrap();
    let doc = read_bytes(
        dir.path(),
        "s.stl",
        &binary(b"solid exported by a CAD tool", &[TRI, TRI]),
    );
    let m = &doc.scene.meshes[0];
    assert_eq!(m.faces.len(), 2);
    // A soup: every triangle has its own three positions.
    assert_eq!(m.positions.len(), 6);
    assert_eq!(m.faces.face(1), &[3, 4, 5]);
    assert_eq!(m.positions[4], [1.0, 0.0, 0.0]);
}

#[test]
fn binary_file_with_padding_after_the_triangles_still_reads() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = binary(b"solid padded", &[TRI]);
    bytes.extend_from_slice(&[0; 7]);
    let doc = read_bytes(dir.path(), "p.stl", &bytes);
    assert_eq!(doc.scene.meshes[0].faces.len(), 1);
}

#[test]
fn ascii_solids_become_parts_named_after_them() {
    let dir = tempfile::tempdir().unwrap();
    let facet = "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
    let text = format!(
        "solid first part\n{facet}{facet}endsolid first part\nsolid second\n{facet}endsolid second\n"
    );
    let doc = read_bytes(dir.path(), "a.stl", text.as_bytes());
    let m = &doc.scene.meshes[0];
    let names: Vec<_> = m.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["first part", "second"]);
    assert_eq!(m.face_parts, [0, 0, 1]);
    assert_eq!(m.positions.len(), 9);
}

#[test]
fn ascii_solid_without_endsolid_ends_at_the_next_solid() {
    let dir = tempfile::tempdir().unwrap();
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let text = format!("solid a\n{facet}solid b\n{facet}{facet}");
    let doc = read_bytes(dir.path(), "n.stl", text.as_bytes());
    let m = &doc.scene.meshes[0];
    assert_eq!(m.parts.len(), 2);
    assert_eq!(m.face_parts, [0, 1, 1]);
}

#[test]
fn ascii_keywords_are_case_insensitive_and_nan_normals_are_ignored() {
    let dir = tempfile::tempdir().unwrap();
    let text = "SOLID x\r\n\tFACET NORMAL nan nan nan\r\n\t\tOUTER LOOP\r\n\t\t\tVERTEX 0 0 0\r\n\t\t\tVERTEX 1E0 0 0\r\n\
                \t\t\tVERTEX 0 1 0\r\n\t\tENDLOOP\r\n\tENDFACET\r\nENDSOLID x\r\n";
    let doc = read_bytes(dir.path(), "u.stl", text.as_bytes());
    assert_eq!(doc.scene.meshes[0].positions[1], [1.0, 0.0, 0.0]);
}

#[test]
fn ascii_loop_with_four_vertices_is_kept_as_a_quad() {
    let dir = tempfile::tempdir().unwrap();
    let text = "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
    let doc = read_bytes(dir.path(), "q.stl", text.as_bytes());
    assert_eq!(doc.scene.meshes[0].faces.arity_counts(), (0, 1, 0));
}

#[test]
fn writing_triangulates_and_computes_unit_facet_normals() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cube.stl");
    let warnings = write(
        &Document::from_scene(Scene::from_mesh(cube())),
        &p,
        &WriteOptions::default(),
    )
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let bytes = std::fs::read(&p).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * 12);
    assert!(!bytes.starts_with(b"solid"));
    assert!(String::from_utf8_lossy(&bytes[..80]).contains("wildlod"));
    assert_eq!(u32::from_le_bytes(bytes[80..84].try_into().unwrap()), 12);
    let f = |o: usize| f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
    // The first quad of the cube (z = 0) faces -z.
    assert_eq!([f(84), f(88), f(92)], [0.0, 0.0, -1.0]);
    let back = read(&p).unwrap();
    assert_eq!(back.scene.meshes[0].faces.arity_counts(), (12, 0, 0));
}

#[test]
fn instances_are_flattened_with_their_world_matrices() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = Scene::from_mesh(cube());
    let mut m = IDENTITY;
    m[13] = -4.0;
    s.nodes.push(Node {
        matrix: m,
        mesh: Some(0),
        ..Node::default()
    });
    s.roots.push(1);
    let p = dir.path().join("two.stl");
    write(&Document::from_scene(s), &p, &WriteOptions::default()).unwrap();
    let back = read(&p).unwrap();
    let m = &back.scene.meshes[0];
    assert_eq!(m.faces.len(), 24);
    assert!(m.positions[36..].iter().all(|p| p[1] <= -3.0));
}

#[test]
fn writing_over_the_source_is_refused_unless_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("part.stl");
    let bytes = binary(b"original", &[TRI]);
    std::fs::write(&src, &bytes).unwrap();
    let doc = read(&src).unwrap();
    let err = write(&doc, &src, &WriteOptions::default()).unwrap_err();
    assert!(
        matches!(err.kind, wildlod_io::ErrorKind::WouldOverwriteInput(_)),
        "{err}"
    );
    assert_eq!(std::fs::read(&src).unwrap(), bytes);
    let allow = WriteOptions {
        allow_overwrite_input: true,
    };
    write(&doc, &src, &allow).unwrap();
    assert!(std::fs::read(&src)
        .unwrap()
        .starts_with(b"binary STL written by wildlod"));
}
