//! PLY reading (ASCII, binary little and big endian) and writing (binary
//! little endian), on files generated here: the corpus has no PLY.

use std::path::{Path, PathBuf};

use wildlod_io::{read, write, Document, WriteOptions};
use wildlod_mesh::shapes::{cube, quad_grid, torus};
use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Part, Scene, Semantic};

/// A PLY body encoding.
#[derive(Clone, Copy, PartialEq)]
enum Enc {
    Ascii,
    Le,
    Be,
}

impl Enc {
    fn name(self) -> &'static str {
        match self {
            Enc::Ascii => "ascii",
            Enc::Le => "binary_little_endian",
            Enc::Be => "binary_big_endian",
        }
    }
}

/// One element to encode: name, properties (type, name; list types as
/// "list uchar int"), and rows of values (a list is its length then items).
struct El<'a> {
    name: &'a str,
    props: &'a [(&'a str, &'a str)],
    rows: Vec<Vec<f64>>,
}

fn put(out: &mut Vec<u8>, ty: &str, v: f64, enc: Enc) {
    if enc == Enc::Ascii {
        let s = if ty == "float" || ty == "float32" {
            format!("{} ", v as f32)
        } else {
            format!("{v} ")
        };
        out.extend_from_slice(s.as_bytes());
        return;
    }
    let mut b: Vec<u8> = match ty {
        "char" | "int8" => (v as i8).to_le_bytes().to_vec(),
        "uchar" | "uint8" => (v as u8).to_le_bytes().to_vec(),
        "short" | "int16" => (v as i16).to_le_bytes().to_vec(),
        "ushort" | "uint16" => (v as u16).to_le_bytes().to_vec(),
        "int" | "int32" => (v as i32).to_le_bytes().to_vec(),
        "uint" | "uint32" => (v as u32).to_le_bytes().to_vec(),
        "float" | "float32" => (v as f32).to_le_bytes().to_vec(),
        "double" | "float64" => v.to_le_bytes().to_vec(),
        other => panic!("type {other}"),
    };
    if enc == Enc::Be {
        b.reverse();
    }
    out.extend_from_slice(&b);
}

fn encode(enc: Enc, elements: &[El]) -> Vec<u8> {
    let mut out = format!("ply\nformat {} 1.0\ncomment made by a test\n", enc.name());
    for e in elements {
        out += &format!("element {} {}\n", e.name, e.rows.len());
        for (ty, name) in e.props {
            out += &format!("property {ty} {name}\n");
        }
    }
    out += "end_header\n";
    let mut out = out.into_bytes();
    for e in elements {
        for row in &e.rows {
            let mut vals = row.iter();
            for (ty, _) in e.props {
                let words: Vec<&str> = ty.split_whitespace().collect();
                if let ["list", count, item] = words[..] {
                    let n = *vals.next().expect("list length");
                    put(&mut out, count, n, enc);
                    for _ in 0..n as usize {
                        put(&mut out, item, *vals.next().expect("list item"), enc);
                    }
                } else {
                    put(&mut out, ty, *vals.next().expect("value"), enc);
                }
            }
            if enc == Enc::Ascii {
                out.push(b'\n');
            }
        }
    }
    out
}

fn read_bytes(dir: &Path, name: &str, bytes: &[u8]) -> Document {
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write test file");
    read(&p).unwrap_or_else(|e| panic!("{e}"))
}

fn write_read(doc: &Document, dir: &Path, name: &str) -> (Document, Vec<String>, PathBuf) {
    let p = dir.join(name);
    let w = write(doc, &p, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    (read(&p).unwrap_or_else(|e| panic!("{e}")), w, p)
}

/// Two quads sharing an edge, with per-vertex normals, uchar colors, UVs:
/// ```text
/// 3---4---5
/// |   |   |
/// 0---1---2
/// ```
fn two_quads(color: &'static str) -> Vec<El<'static>> {
    let props: &'static [(&str, &str)] = match color {
        "uchar" => &[
            ("float", "x"),
            ("float", "y"),
            ("float", "z"),
            ("float", "nx"),
            ("float", "ny"),
            ("float", "nz"),
            ("uchar", "red"),
            ("uchar", "green"),
            ("uchar", "blue"),
            ("float", "s"),
            ("float", "t"),
        ],
        _ => &[
            ("double", "x"),
            ("double", "y"),
            ("double", "z"),
            ("float", "nx"),
            ("float", "ny"),
            ("float", "nz"),
            ("float", "red"),
            ("float", "green"),
            ("float", "blue"),
            ("float", "alpha"),
            ("float", "u"),
            ("float", "v"),
        ],
    };
    let vertices = (0..6)
        .map(|i| {
            let (x, y) = ((i % 3) as f64, (i / 3) as f64);
            let mut r = vec![x, y, 0.0, 0.0, 0.0, 1.0];
            if color == "uchar" {
                r.extend([(40 * i) as f64, 255.0, 0.0]);
            } else {
                r.extend([i as f64 / 6.0, 0.1, 0.2, 0.3]);
            }
            r.extend([x / 2.0, y]);
            r
        })
        .collect();
    vec![
        El {
            name: "vertex",
            props,
            rows: vertices,
        },
        El {
            name: "face",
            props: &[("list uchar int", "vertex_indices")],
            rows: vec![vec![4.0, 0.0, 1.0, 4.0, 3.0], vec![4.0, 1.0, 2.0, 5.0, 4.0]],
        },
    ]
}

#[test]
fn ascii_quads_keep_arity_and_vertex_properties_become_corner_streams() {
    let dir = tempfile::tempdir().unwrap();
    let doc = read_bytes(
        dir.path(),
        "q.ply",
        &encode(Enc::Ascii, &two_quads("uchar")),
    );
    let m = &doc.scene.meshes[0];
    assert_eq!(m.faces.arity_counts(), (0, 2, 0));
    assert_eq!(m.faces.face(1), &[1, 2, 5, 4]);
    assert_eq!(m.positions[5], [2.0, 1.0, 0.0]);
    let c = m.attribute(&Semantic::Color(0)).unwrap();
    assert_eq!((c.components, c.format), (3, ComponentFormat::U8Norm));
    // Corner 5 is vertex 2: red 80/255.
    assert_eq!(c.corner_value(5), Some(&[80.0 / 255.0, 1.0, 0.0][..]));
    let uv = m.attribute(&Semantic::TexCoord(0)).unwrap();
    assert_eq!(uv.indices, m.faces.indices);
    // PLY's t = 1 (top of the image) is the model's v = 0.
    assert_eq!(uv.value(5), &[1.0, 0.0]);
    assert_eq!(uv.value(0), &[0.0, 1.0]);
    assert_eq!(
        m.attribute(&Semantic::Normal).unwrap().value(0),
        &[0.0, 0.0, 1.0]
    );
}

#[test]
fn the_three_encodings_read_the_same_mesh() {
    let dir = tempfile::tempdir().unwrap();
    for color in ["uchar", "float"] {
        let docs: Vec<Document> = [Enc::Ascii, Enc::Le, Enc::Be]
            .iter()
            .map(|&e| read_bytes(dir.path(), "e.ply", &encode(e, &two_quads(color))))
            .collect();
        assert_eq!(docs[0].scene.meshes[0], docs[1].scene.meshes[0], "{color}");
        assert_eq!(docs[1].scene.meshes[0], docs[2].scene.meshes[0], "{color}");
    }
}

#[test]
fn unknown_elements_are_skipped_including_binary_lists() {
    let dir = tempfile::tempdir().unwrap();
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        let mut els = two_quads("uchar");
        els.insert(
            0,
            El {
                name: "material",
                props: &[("float", "shine"), ("list int double", "spectrum")],
                rows: vec![vec![1.0, 3.0, 0.1, 0.2, 0.3], vec![2.0, 0.0]],
            },
        );
        els.insert(
            2,
            El {
                name: "edge",
                props: &[
                    ("int", "vertex1"),
                    ("int", "vertex2"),
                    ("list ushort uchar", "tags"),
                ],
                rows: vec![vec![0.0, 1.0, 2.0, 7.0, 8.0]],
            },
        );
        els.push(El {
            name: "range_grid",
            props: &[("list uchar int", "vertex_indices")],
            rows: vec![vec![1.0, 0.0]],
        });
        let doc = read_bytes(dir.path(), "u.ply", &encode(enc, &els));
        assert_eq!(doc.scene.meshes[0].faces.len(), 2);
        assert_eq!(doc.scene.meshes[0].positions.len(), 6);
    }
}

#[test]
fn ascii_and_binary_inputs_round_trip_through_binary_output() {
    let dir = tempfile::tempdir().unwrap();
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        for color in ["uchar", "float"] {
            let doc = read_bytes(dir.path(), "in.ply", &encode(enc, &two_quads(color)));
            let (back, warnings, path) = write_read(&doc, dir.path(), "out.ply");
            assert!(warnings.is_empty(), "{warnings:?}");
            // Every stream is per vertex already: the mesh comes back as is,
            // uchar colors as uchar.
            assert_eq!(doc.scene.meshes[0], back.scene.meshes[0]);
            let head = std::fs::read(&path).unwrap();
            let end = head.windows(10).position(|w| w == b"end_header").unwrap();
            let head = String::from_utf8_lossy(&head[..end]);
            assert!(head.starts_with(
                "ply\nformat binary_little_endian 1.0\ncomment generated by wildlod\n"
            ));
            assert!(head.contains(&format!("property {color} red")), "{head}");
        }
    }
}

/// Every corner of `a` has the same position and stream values in `b`.
fn assert_same_corners(a: &Mesh, b: &Mesh) {
    assert_eq!(a.faces.offsets, b.faces.offsets);
    for c in 0..a.faces.corner_count() {
        assert_eq!(
            a.positions[a.faces.indices[c] as usize], b.positions[b.faces.indices[c] as usize],
            "corner {c}"
        );
        for s in &a.attributes {
            let t = b.attribute(&s.semantic).expect("stream kept");
            assert_eq!(
                s.corner_value(c),
                t.corner_value(c),
                "{:?} corner {c}",
                s.semantic
            );
        }
    }
}

#[test]
fn corner_streams_split_vertices_by_distinct_combination() {
    let dir = tempfile::tempdir().unwrap();
    // A torus has a UV seam where u wraps: give it per-corner UVs that
    // differ across the seam, and one normal per corner of each face.
    let mut m = torus(6, 4, 2.0, 0.5);
    let mut uv_values = Vec::new();
    let mut uv_indices = Vec::new();
    for f in 0..m.faces.len() {
        for (k, c) in m.faces.corner_range(f).enumerate() {
            let v = m.faces.indices[c];
            // Corners 1 and 2 of the last column sit on the seam: u = 1.
            let seam = f / 4 == 5 && (k == 1 || k == 2);
            let u = if seam { 1.0 } else { (v / 4) as f32 / 6.0 };
            uv_values.extend([u, (v % 4) as f32 / 4.0]);
            uv_indices.push((uv_values.len() / 2 - 1) as u32);
        }
    }
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv_values,
        indices: uv_indices,
        format: ComponentFormat::F32,
    });
    let doc = Document::from_scene(Scene::from_mesh(m.clone()));
    let (back, warnings, _) = write_read(&doc, dir.path(), "t.ply");
    assert!(warnings.is_empty(), "{warnings:?}");
    let b = &back.scene.meshes[0];
    assert_same_corners(&m, b);
    // 24 positions, and the 4 on the seam appear a second time with u = 1.
    assert_eq!(b.positions.len(), 28);
}

#[test]
fn mesh_without_attributes_keeps_its_positions_as_stored() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = cube();
    // An unused vertex, and a duplicate of vertex 0 used by no face.
    m.positions.push([5.0, 5.0, 5.0]);
    m.positions.push([0.0, 0.0, 0.0]);
    let doc = Document::from_scene(Scene::from_mesh(m.clone()));
    let (back, _, _) = write_read(&doc, dir.path(), "c.ply");
    assert_eq!(back.scene.meshes[0].positions, m.positions);
    assert_eq!(back.scene.meshes[0].faces, m.faces);
}

#[test]
fn face_texcoord_lists_become_per_corner_uvs() {
    let dir = tempfile::tempdir().unwrap();
    let els = [
        El {
            name: "vertex",
            props: &[("float", "x"), ("float", "y"), ("float", "z")],
            rows: vec![
                vec![0.0, 0.0, 0.0],
                vec![1.0, 0.0, 0.0],
                vec![0.0, 1.0, 0.0],
            ],
        },
        El {
            name: "face",
            props: &[
                ("list uchar int", "vertex_indices"),
                ("list uchar float", "texcoord"),
            ],
            rows: vec![vec![3.0, 0.0, 1.0, 2.0, 6.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0]],
        },
    ];
    let doc = read_bytes(dir.path(), "w.ply", &encode(Enc::Le, &els));
    let uv = doc.scene.meshes[0]
        .attribute(&Semantic::TexCoord(0))
        .unwrap();
    assert_eq!(uv.indices, [0, 1, 2]);
    assert_eq!(uv.value(1), &[1.0, 1.0]);
    assert_eq!(uv.value(2), &[0.0, 0.0]);
}

#[test]
fn any_integer_types_work_for_counts_and_indices() {
    let dir = tempfile::tempdir().unwrap();
    for (list, name) in [
        ("list char uchar", "vertex_index"),
        ("list ushort short", "vertex_indices"),
        ("list uint uint", "vertex_indices"),
        ("list uint8 int32", "vertex_indices"),
    ] {
        let props = [(list, name)];
        let els = [
            El {
                name: "vertex",
                props: &[("int", "x"), ("short", "y"), ("uchar", "z")],
                rows: vec![
                    vec![0.0, 0.0, 0.0],
                    vec![1.0, 0.0, 0.0],
                    vec![0.0, 1.0, 0.0],
                    vec![-3.0, 4.0, 5.0],
                ],
            },
            El {
                name: "face",
                props: &props,
                rows: vec![vec![4.0, 0.0, 1.0, 2.0, 3.0]],
            },
        ];
        for enc in [Enc::Ascii, Enc::Be] {
            let doc = read_bytes(dir.path(), "i.ply", &encode(enc, &els));
            assert_eq!(doc.scene.meshes[0].faces.face(0), &[0, 1, 2, 3], "{list}");
            assert_eq!(doc.scene.meshes[0].positions[3], [-3.0, 4.0, 5.0]);
        }
    }
}

#[test]
fn polygon_with_more_than_255_corners_gets_a_wide_count() {
    let dir = tempfile::tempdir().unwrap();
    let n = 300;
    let positions: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let mut faces = Faces::new();
    faces.push(&(0..n as u32).collect::<Vec<_>>());
    let doc = Document::from_scene(Scene::from_mesh(Mesh::from_polygons(positions, faces)));
    let (back, _, path) = write_read(&doc, dir.path(), "big.ply");
    assert_eq!(back.scene.meshes[0].faces.arity(0), n);
    let bytes = std::fs::read(path).unwrap();
    assert!(
        String::from_utf8_lossy(&bytes[..300]).contains("property list uint int vertex_indices")
    );
}

#[test]
fn instances_are_flattened_and_parts_dropped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = quad_grid(2, 1);
    g.parts.push(Part {
        name: "b".into(),
        material: None,
    });
    g.face_parts = vec![0, 1];
    let mut s = Scene::from_mesh(g);
    let mut m = wildlod_mesh::IDENTITY;
    m[14] = 3.0;
    s.nodes.push(wildlod_mesh::Node {
        matrix: m,
        mesh: Some(0),
        ..Default::default()
    });
    s.roots.push(1);
    let (back, warnings, _) = write_read(&Document::from_scene(s), dir.path(), "f.ply");
    let b = &back.scene.meshes[0];
    assert_eq!(b.faces.len(), 4);
    assert_eq!(b.positions.len(), 12);
    assert_eq!(b.positions[6], [0.0, 0.0, 3.0]);
    assert!(
        warnings.iter().any(|w| w.contains("parts or materials")),
        "{warnings:?}"
    );
}

#[test]
fn texture_v_is_flipped_on_read_and_round_trips_bit_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let ts = [0.3, 0.123_456_79, -2.5, 1.7, 0.999_999_9, 1e-6];
    let els = [
        El {
            name: "vertex",
            props: &[
                ("float", "x"),
                ("float", "y"),
                ("float", "z"),
                ("float", "s"),
                ("float", "t"),
            ],
            rows: ts
                .iter()
                .enumerate()
                .map(|(i, &t)| vec![i as f64, (i % 2) as f64, 0.0, 0.5, t as f32 as f64])
                .collect(),
        },
        El {
            name: "face",
            props: &[("list uchar int", "vertex_indices")],
            rows: vec![vec![3.0, 0.0, 1.0, 2.0], vec![3.0, 3.0, 4.0, 5.0]],
        },
    ];
    let doc = read_bytes(dir.path(), "t.ply", &encode(Enc::Le, &els));
    let uv = doc.scene.meshes[0]
        .attribute(&Semantic::TexCoord(0))
        .unwrap()
        .clone();
    assert_eq!(uv.value(0)[1], (1.0 - 0.3f32 as f64) as f32);
    let (back, _, _) = write_read(&doc, dir.path(), "back.ply");
    let again = back.scene.meshes[0]
        .attribute(&Semantic::TexCoord(0))
        .unwrap();
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&again.values), bits(&uv.values));
}

#[test]
fn writing_over_the_source_is_refused_and_a_failed_write_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = encode(Enc::Ascii, &two_quads("uchar"));
    let doc = read_bytes(dir.path(), "src.ply", &bytes);
    let err = write(&doc, dir.path().join("./src.ply"), &WriteOptions::default()).unwrap_err();
    assert!(
        matches!(err.kind, wildlod_io::ErrorKind::WouldOverwriteInput(_)),
        "{err}"
    );
    assert_eq!(std::fs::read(dir.path().join("src.ply")).unwrap(), bytes);
    assert!(write(
        &doc,
        dir.path().join("no/such/dir.ply"),
        &WriteOptions::default()
    )
    .is_err());
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["src.ply"]);
}

#[test]
fn ascii_integers_written_as_integral_floats_are_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n\
                property list uchar int vertex_indices\nend_header\n\
                0 0 0 255.000000 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255.0\n3.0 0 1 2\n";
    let doc = read_bytes(dir.path(), "f.ply", text.as_bytes());
    let c = doc.scene.meshes[0].attribute(&Semantic::Color(0)).unwrap();
    assert_eq!(c.value(0), &[1.0, 0.0, 0.0]);
    let text = text.replace("255.000000", "254.5");
    let p = dir.path().join("g.ply");
    std::fs::write(&p, text).unwrap();
    assert!(read(&p)
        .unwrap_err()
        .to_string()
        .contains("PLY element 'vertex' 0"));
}
