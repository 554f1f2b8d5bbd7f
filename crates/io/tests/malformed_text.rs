//! Malformed OBJ, PLY and STL files built in code: each is an error that
//! names the file and the line or element, never a panic, never an
//! allocation sized by a count the file cannot hold.

use wildlod_io::{read, Error, ErrorKind};

/// Reads `bytes` saved as `name`; the read must fail.
fn fails(name: &str, bytes: &[u8]) -> Error {
    let dir = tempfile::tempdir().expect("temp dir");
    let p = dir.path().join(name);
    std::fs::write(&p, bytes).expect("write test file");
    match read(&p) {
        Ok(_) => panic!("{name} was read, but is malformed"),
        Err(e) => {
            assert!(
                e.to_string().contains(name),
                "error does not name the file: {e}"
            );
            e
        }
    }
}

/// Asserts a syntax error at `line` whose message contains `what`.
fn at_line(e: Error, line: usize, what: &str) {
    match &e.kind {
        ErrorKind::Syntax { line: l, message } if *l == line && message.contains(what) => {}
        _ => panic!("expected line {line} '{what}', got: {e}"),
    }
}

/// Asserts an error at element `element` whose message contains `what`.
fn at_element(e: Error, element: &str, what: &str) {
    match &e.kind {
        ErrorKind::Malformed {
            element: el,
            message,
        } if el == element && message.contains(what) => {}
        _ => panic!("expected '{element}' '{what}', got: {e}"),
    }
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn empty_files_are_refused_in_every_format() {
    for name in ["e.obj", "e.ply", "e.stl", "e.off"] {
        assert!(matches!(fails(name, b"").kind, ErrorKind::EmptyFile));
    }
}

#[test]
fn obj_binary_garbage_names_its_line() {
    let mut bytes = b"v 0 0 0\n".to_vec();
    bytes.extend_from_slice(&[0x89, 0x00, 0xff, 0x13, b'\n', 0x01, 0x02]);
    at_line(fails("g.obj", &bytes), 2, "not an OBJ statement");
}

#[test]
fn obj_of_only_two_vertex_faces_has_no_faces() {
    // Two-vertex faces are skipped (scene exports carry them; see
    // tests/off.rs), so a file of nothing else has no faces.
    at_element(
        fails("f.obj", format!("{TRI}f 1 2\n").as_bytes()),
        "OBJ",
        "the file has no faces",
    );
}

#[test]
fn obj_index_zero_names_its_line() {
    at_line(
        fails("z.obj", format!("{TRI}f 0 1 2\n").as_bytes()),
        4,
        "index 0",
    );
}

#[test]
fn obj_index_out_of_range_names_its_line() {
    at_line(
        fails(
            "r.obj",
            format!("{TRI}f 1 2 3\n\nf 1 2 9\nf 1 2 3\n").as_bytes(),
        ),
        6,
        "vertex index 9 is out of range",
    );
    at_line(
        fails("t.obj", format!("{TRI}vt 0 0\nf 1/1 2/1 3/2\n").as_bytes()),
        5,
        "texture coordinate index 2",
    );
    at_line(
        fails("n.obj", format!("{TRI}f 1//1 2//1 3//1\n").as_bytes()),
        4,
        "normal index 1",
    );
    at_line(
        fails(
            "h.obj",
            format!("{TRI}f 1 2 99999999999999999999999\n").as_bytes(),
        ),
        4,
        "not an integer",
    );
}

#[test]
fn obj_negative_index_before_the_first_vertex_names_its_line() {
    at_line(
        fails("neg.obj", format!("{TRI}f -1 -2 -4\n").as_bytes()),
        4,
        "relative vertex index -4",
    );
}

#[test]
fn obj_non_finite_and_non_numeric_coordinates_name_their_line() {
    at_line(
        fails("nan.obj", b"v 0 0 0\nv nan 0 0\n"),
        2,
        "'nan' is not a finite number",
    );
    at_line(
        fails("inf.obj", b"v 0 0 0\nv 0 0 0\nv 0 -inf 0\n"),
        3,
        "finite",
    );
    at_line(fails("big.obj", b"v 0 0 1e40\n"), 1, "finite");
    at_line(
        fails("txt.obj", b"v 0 0 0\nv 0 1.0x 0\n"),
        2,
        "'1.0x' is not a number",
    );
    at_line(
        fails("vt.obj", format!("{TRI}vt 0 NaN\n").as_bytes()),
        4,
        "texture coordinate",
    );
    at_line(
        fails("vn.obj", format!("{TRI}vn 0 0\n").as_bytes()),
        4,
        "3 values, found 2",
    );
    at_line(fails("two.obj", b"v 0 0\n"), 1, "3 coordinates");
}

#[test]
fn obj_without_faces_is_an_error() {
    at_element(fails("nf.obj", TRI.as_bytes()), "OBJ", "no faces");
    at_element(
        fails("ws.obj", b"\n  \n# only a comment\n"),
        "OBJ",
        "no faces",
    );
}

#[test]
fn stl_truncated_binary_names_the_cut_triangle() {
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&3u32.to_le_bytes());
    bytes.extend_from_slice(&[0u8; 50 * 3 - 10]);
    at_element(fails("cut.stl", &bytes), "STL triangle 2", "truncated");
}

#[test]
fn stl_declaring_four_billion_triangles_is_implausible() {
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&4_000_000_000u32.to_le_bytes());
    bytes.extend_from_slice(&[0u8; 200]);
    match fails("huge.stl", &bytes).kind {
        ErrorKind::ImplausibleCount { count, max, .. } => {
            assert_eq!((count, max), (4_000_000_000, 4));
        }
        other => panic!("{other}"),
    }
}

#[test]
fn stl_short_binary_and_non_finite_binary_vertex_are_named() {
    at_element(
        fails("short.stl", &[1, 2, 3, 0, 9]),
        "STL header",
        "too short",
    );
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&1u32.to_le_bytes());
    bytes.extend_from_slice(&[0u8; 50]);
    bytes[84 + 12 + 12 + 4..84 + 12 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    at_element(
        fails("nan.stl", &bytes),
        "STL triangle 0",
        "vertex 1 has a non-finite",
    );
}

#[test]
fn stl_ascii_errors_name_their_line() {
    let head = "solid s\nfacet normal 0 0 1\nouter loop\n";
    at_line(
        fails(
            "l.stl",
            format!("{head}vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendfacet\n").as_bytes(),
        ),
        7,
        "expected 'vertex' or 'endloop'",
    );
    at_line(
        fails(
            "n.stl",
            format!("{head}vertex 0 0 0\nvertex 1 zero 0\n").as_bytes(),
        ),
        5,
        "'zero' is not a number",
    );
    at_line(
        fails(
            "i.stl",
            format!("{head}vertex 0 0 0\nvertex 1 0 0\nvertex 0 inf 0\n").as_bytes(),
        ),
        6,
        "finite",
    );
    at_line(
        fails(
            "two.stl",
            format!("{head}vertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n").as_bytes(),
        ),
        2,
        "3 vertices, found 2",
    );
    at_line(
        fails("eof.stl", format!("{head}vertex 0 0 0\n").as_bytes()),
        4,
        "ends inside a facet",
    );
    at_line(
        fails("kw.stl", b"solid s\nfacet normal 0 0 1\nloop\n"),
        3,
        "expected 'outer'",
    );
    at_element(
        fails("empty.stl", b"solid nothing\nendsolid nothing\n"),
        "STL",
        "no facets",
    );
}

/// A binary little-endian PLY header for `vertices` and `faces` counts.
fn ply_header(format: &str, vertices: u64, faces: u64) -> Vec<u8> {
    format!(
        "ply\nformat {format} 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\n\
         property float z\nelement face {faces}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes()
}

fn le_triangle_body(indices: [i32; 3]) -> Vec<u8> {
    let mut b = Vec::new();
    for v in [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in v {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    b.push(3);
    for i in indices {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b
}

#[test]
fn ply_header_declaring_billions_of_vertices_is_implausible() {
    let mut bytes = ply_header("binary_little_endian", 4_000_000_000, 1);
    bytes.extend_from_slice(&le_triangle_body([0, 1, 2]));
    match fails("huge.ply", &bytes).kind {
        ErrorKind::ImplausibleCount { element, count, .. } => {
            assert_eq!(element, "PLY element 'vertex'");
            assert_eq!(count, 4_000_000_000);
        }
        other => panic!("{other}"),
    }
    // ASCII too: every value needs at least a character and a separator.
    let mut bytes = ply_header("ascii", 3, 18_000_000_000_000_000_000);
    bytes.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    assert!(matches!(
        fails("huge2.ply", &bytes).kind,
        ErrorKind::ImplausibleCount { .. }
    ));
}

#[test]
fn ply_truncated_body_names_the_element_and_index() {
    let mut bytes = ply_header("binary_little_endian", 3, 1);
    let body = le_triangle_body([0, 1, 2]);
    bytes.extend_from_slice(&body[..body.len() - 3]);
    at_element(
        fails("cut.ply", &bytes),
        "PLY element 'face' 0",
        "truncated",
    );

    let mut bytes = ply_header("ascii", 3, 2);
    bytes.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1\n");
    at_element(
        fails("cut2.ply", &bytes),
        "PLY element 'face' 1",
        "truncated",
    );
}

#[test]
fn ply_list_length_beyond_the_file_is_truncation_not_allocation() {
    let mut bytes = String::from(
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n",
    )
    .into_bytes();
    bytes.extend_from_slice(&[0u8; 36]);
    bytes.extend_from_slice(&u32::MAX.to_be_bytes());
    bytes.extend_from_slice(&[0u8; 12]);
    at_element(
        fails("list.ply", &bytes),
        "PLY element 'face' 0",
        "truncated",
    );
}

#[test]
fn ply_unknown_format_names_the_header_line() {
    let bytes = b"ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n";
    at_line(
        fails("fmt.ply", bytes),
        2,
        "unknown format 'binary_middle_endian'",
    );
    let bytes = b"ply\nformat ascii 2.0\nend_header\n";
    at_line(fails("ver.ply", bytes), 2, "version");
    at_element(
        fails("magic.ply", b"PLY\nformat ascii 1.0\n"),
        "PLY header",
        "'ply'",
    );
    at_element(
        fails("open.ply", b"ply\nformat ascii 1.0\nelement vertex 1\n"),
        "PLY header",
        "end_header",
    );
    at_line(
        fails(
            "type.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty vec3 x\nend_header\n",
        ),
        4,
        "unknown type 'vec3'",
    );
}

#[test]
fn ply_face_index_out_of_range_names_the_face() {
    let mut bytes = ply_header("binary_little_endian", 3, 1);
    bytes.extend_from_slice(&le_triangle_body([0, 1, 3]));
    at_element(
        fails("idx.ply", &bytes),
        "PLY element 'face' 0",
        "vertex index 3 is out of range",
    );
    let mut bytes = ply_header("binary_little_endian", 3, 1);
    bytes.extend_from_slice(&le_triangle_body([0, -1, 2]));
    at_element(
        fails("neg.ply", &bytes),
        "PLY element 'face' 0",
        "vertex index -1",
    );
}

#[test]
fn ply_value_errors_name_the_element_and_index() {
    let mut bytes = ply_header("ascii", 3, 1);
    bytes.extend_from_slice(b"0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n");
    at_element(
        fails("txt.ply", &bytes),
        "PLY element 'vertex' 1",
        "'x' is not a number",
    );
    let mut bytes = ply_header("ascii", 3, 1);
    bytes.extend_from_slice(b"0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n");
    at_element(fails("nan.ply", &bytes), "PLY element 'vertex' 2", "finite");
    let mut bytes = ply_header("ascii", 3, 1);
    bytes.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n2 0 1\n");
    // Its only face has two vertices: skipped, and nothing is left.
    at_element(fails("two.ply", &bytes), "PLY", "the file has no faces");
    let mut bytes = ply_header("ascii", 3, 1);
    bytes.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n");
    at_element(
        fails("count.ply", &bytes),
        "PLY element 'face' 0",
        "does not fit",
    );
    let mut bytes = ply_header("ascii", 3, 0);
    bytes.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n");
    at_element(fails("nofaces.ply", &bytes), "PLY", "no faces");
}

/// xorshift64*: reproducible mutations without a dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn mutate(rng: &mut Rng, src: &[u8]) -> Vec<u8> {
    let mut b = src.to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(b.len());
        match rng.below(6) {
            0 => b.truncate(at),
            1 => {
                let last = b.len().saturating_sub(1);
                b[at.min(last)] = rng.next() as u8;
            }
            2 => {
                let alphabet = b"0123456789-+.e /\n\r\\#nafv";
                b.insert(at, alphabet[rng.below(alphabet.len())]);
            }
            3 => {
                let n = rng.below(8);
                b.splice(at..(at + n).min(b.len()), []);
            }
            4 => {
                // Plausible tokens in odd places.
                let words: [&[u8]; 8] = [
                    b"-1",
                    b"0",
                    b"4294967295",
                    b"nan",
                    b"f ",
                    b"\nf 1 2",
                    b"list",
                    b"endloop",
                ];
                let w = words[rng.below(words.len())];
                b.splice(at..at, w.iter().copied());
            }
            _ => {
                let x = rng.next().to_le_bytes();
                let n = (1 + rng.below(4)).min(b.len().saturating_sub(at));
                b[at..at + n].copy_from_slice(&x[..n]);
            }
        }
        if b.is_empty() {
            break;
        }
    }
    b
}

#[test]
fn mutated_files_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let obj = b"mtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n\
                g a\nusemtl m\nf 1/1/1 2/2/1 3/1/1 4/2/1\nf -1 -2 -3\n"
        .to_vec();
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl m\nKd 1 0 0\nmap_Kd -s 1 1 1 t.png\n",
    )
    .unwrap();
    let mut ascii_ply = ply_header("ascii", 3, 1);
    ascii_ply.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    let mut le_ply = ply_header("binary_little_endian", 3, 1);
    le_ply.extend_from_slice(&le_triangle_body([0, 1, 2]));
    let ascii_stl = b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n".to_vec();
    let mut bin_stl = b"solid but binary".to_vec();
    bin_stl.resize(80, b' ');
    bin_stl.extend_from_slice(&2u32.to_le_bytes());
    for k in 0..100u8 {
        bin_stl.push(k % 7);
    }
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut errors = 0;
    for (name, src) in [
        ("x.obj", &obj),
        ("x.ply", &ascii_ply),
        ("y.ply", &le_ply),
        ("x.stl", &ascii_stl),
        ("y.stl", &bin_stl),
    ] {
        for _ in 0..400 {
            let bytes = mutate(&mut rng, src);
            let p = dir.path().join(name);
            std::fs::write(&p, &bytes).unwrap();
            // Either outcome is fine; a successful read has passed validate().
            if read(&p).is_err() {
                errors += 1;
            }
        }
    }
    assert!(
        errors > 100,
        "the mutations should break many files, broke {errors}"
    );
}
