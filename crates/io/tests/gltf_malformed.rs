//! Malformed glTF and GLB input: each is an error that names the problem,
//! never a panic or a huge allocation.

mod gltf_support;

use gltf_support::{read_bytes, triangle, Builder};
use serde_json::json;
use wildlod_io::ErrorKind;

/// Reads `bytes` as `name`, expects an error, and returns its message.
fn error_of(name: &str, bytes: &[u8]) -> String {
    match read_bytes(name, bytes) {
        Ok(_) => panic!("{name}: read succeeded"),
        Err(e) => e.to_string(),
    }
}

fn assert_mentions(msg: &str, words: &[&str]) {
    for w in words {
        assert!(msg.contains(w), "{msg:?} should mention {w:?}");
    }
}

#[test]
fn the_builder_triangle_reads_as_glb_and_as_embedded_gltf() {
    let b = triangle();
    for (name, bytes) in [("t.glb", b.glb()), ("t.gltf", b.gltf_embedded())] {
        let doc = read_bytes(name, &bytes).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(doc.scene.meshes[0].triangle_count(), 1, "{name}");
    }
}

#[test]
fn empty_files_are_an_error() {
    for name in ["e.glb", "e.gltf"] {
        assert_mentions(&error_of(name, b""), &["empty"]);
    }
}

#[test]
fn binary_garbage_is_an_error_naming_header_or_json() {
    let garbage: Vec<u8> = (0..200u32).map(|i| (i * 37 % 251) as u8).collect();
    assert_mentions(&error_of("g.glb", &garbage), &["GLB header", "magic"]);
    assert_mentions(&error_of("g.gltf", &garbage), &["not valid JSON"]);
}

#[test]
fn truncated_glb_is_an_error_naming_the_cut_part() {
    let glb = triangle().glb();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().expect("4 bytes")) as usize;
    // In the header.
    assert_mentions(&error_of("t.glb", &glb[..7]), &["GLB header", "12-byte"]);
    // In the JSON chunk.
    assert_mentions(
        &error_of("t.glb", &glb[..20 + json_len / 2]),
        &["JSON chunk", "truncated"],
    );
    // In the BIN chunk's header, and in its data.
    assert_mentions(
        &error_of("t.glb", &glb[..20 + json_len + 4]),
        &["BIN chunk", "truncated"],
    );
    assert_mentions(
        &error_of("t.glb", &glb[..glb.len() - 2]),
        &["BIN chunk", "truncated"],
    );
}

#[test]
fn every_truncation_and_byte_flip_of_a_glb_is_an_error_or_a_valid_scene() {
    let b = triangle();
    let glb = b.glb();
    let dir = tempfile::tempdir().expect("temp dir");
    let p = dir.path().join("f.glb");
    let read = |bytes: &[u8]| {
        std::fs::write(&p, bytes).expect("write");
        if let Ok(doc) = wildlod_io::read(&p) {
            // What reads must be valid.
            doc.scene.validate().expect("valid scene");
        }
    };
    for n in 0..glb.len() {
        read(&glb[..n]);
    }
    for i in 0..glb.len() {
        for v in [0x00, 0xFF, b'9', b'-', b'"'] {
            let mut m = glb.clone();
            m[i] = v;
            read(&m);
        }
    }
}

#[test]
fn bad_json_is_an_error_with_its_position() {
    let msg = error_of("b.gltf", br#"{"asset": {"version": "2.0"}, "nodes": [ }"#);
    assert_mentions(&msg, &["not valid JSON", "line 1"]);
}

#[test]
fn json_that_is_not_gltf_is_an_error() {
    assert_mentions(
        &error_of("n.gltf", br#"{"hello": "world"}"#),
        &["asset.version"],
    );
    assert_mentions(&error_of("n.gltf", b"[1, 2, 3]"), &["not a JSON object"]);
    assert_mentions(
        &error_of("v1.gltf", br#"{"asset": {"version": "1.0"}}"#),
        &["version 1.0"],
    );
    // Right shape at the top, wrong inside.
    assert_mentions(
        &error_of(
            "w.gltf",
            br#"{"asset": {"version": "2.0"}, "nodes": [{"mesh": "zero"}]}"#,
        ),
        &["not a valid glTF 2.0 document"],
    );
}

#[test]
fn index_out_of_range_names_mesh_primitive_and_accessor() {
    let mut b = Builder::new();
    let pos = b.floats(&[0.0; 9], "VEC3");
    let idx = b.indices(&[0, 1, 7]);
    b.mesh(json!([{"attributes": {"POSITION": pos}, "indices": idx}]));
    let msg = error_of("i.glb", &b.glb());
    assert_mentions(
        &msg,
        &["mesh 0 primitive 0", "accessor 1", "is 7", "3 vertices"],
    );
}

#[test]
fn non_finite_positions_name_the_accessor_and_element() {
    for bad in [f32::NAN, f32::INFINITY] {
        let mut b = Builder::new();
        let pos = b.floats(&[0.0, 0.0, 0.0, bad, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
        b.json["accessors"][pos]["min"] = json!([0.0, 0.0, 0.0]);
        b.json["accessors"][pos]["max"] = json!([1.0, 1.0, 0.0]);
        b.mesh(json!([{"attributes": {"POSITION": pos}}]));
        let msg = error_of("nan.glb", &b.glb());
        assert_mentions(
            &msg,
            &[
                "mesh 0 primitive 0",
                "POSITION (accessor 0) element 1",
                "not finite",
            ],
        );
    }
}

#[test]
fn accessor_counts_in_the_billions_fail_before_allocating() {
    let mut b = triangle();
    b.json["accessors"][0]["count"] = json!(3_000_000_000u64);
    let e = read_bytes("big.glb", &b.glb()).expect_err("implausible");
    assert!(
        matches!(
            &e.kind,
            ErrorKind::ImplausibleCount {
                count: 3_000_000_000,
                ..
            }
        ),
        "{e}"
    );
    assert_mentions(&e.to_string(), &["accessor 0"]);
    // Without a buffer view nothing backs the count at all.
    let mut b = triangle();
    b.json["accessors"][0]
        .as_object_mut()
        .expect("object")
        .remove("bufferView");
    b.json["accessors"][0]["count"] = json!(4_000_000_000u64);
    let e = read_bytes("big.glb", &b.glb()).expect_err("implausible");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

#[test]
fn glb_chunk_declaring_gigabytes_is_an_error_not_an_allocation() {
    let mut glb = triangle().glb();
    glb[12..16].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    assert_mentions(&error_of("huge.glb", &glb), &["JSON chunk", "4294967280"]);
}

#[test]
fn buffer_view_beyond_its_buffer_is_an_error_naming_it() {
    let mut b = triangle();
    b.json["bufferViews"][1]["byteOffset"] = json!(1000);
    let msg = error_of("v.glb", &b.glb());
    assert_mentions(&msg, &["bufferView 1", "beyond the end of buffer 0"]);
    // Even when no accessor uses it.
    let mut b = triangle();
    b.view(&[0; 4], None);
    b.json["bufferViews"][2]["byteLength"] = json!(400);
    assert_mentions(&error_of("v.glb", &b.glb()), &["bufferView 2"]);
}

#[test]
fn attribute_count_mismatch_names_both_accessors() {
    let mut b = Builder::new();
    let pos = b.floats(&[0.0; 9], "VEC3");
    let nrm = b.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC3");
    b.mesh(json!([{"attributes": {"POSITION": pos, "NORMAL": nrm}}]));
    let msg = error_of("c.glb", &b.glb());
    assert_mentions(
        &msg,
        &["accessor 1 (NORMAL) has 2 elements", "accessor 0) has 3"],
    );
}

#[test]
fn data_uri_that_is_not_base64_is_an_error() {
    let b = triangle();
    let mut j: serde_json::Value = serde_json::from_slice(&b.gltf_embedded()).expect("json");
    j["buffers"][0]["uri"] = json!("data:application/octet-stream,rawbytes");
    let msg = error_of("d.gltf", &serde_json::to_vec(&j).expect("json"));
    assert_mentions(&msg, &["buffer 0", "not base64"]);
    j["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@@");
    let msg = error_of("d.gltf", &serde_json::to_vec(&j).expect("json"));
    assert_mentions(&msg, &["buffer 0", "base64"]);
}

#[test]
fn missing_external_bin_names_the_buffer_and_file() {
    let msg = error_of("m.gltf", &triangle().gltf_external("missing.bin"));
    assert_mentions(&msg, &["buffer 0", "missing.bin"]);
}

#[test]
fn short_external_bin_is_an_error() {
    let b = triangle();
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("d.bin"), &b.bin[..10]).expect("write");
    std::fs::write(dir.path().join("s.gltf"), b.gltf_external("d.bin")).expect("write");
    let e = wildlod_io::read(dir.path().join("s.gltf")).expect_err("short");
    assert_mentions(&e.to_string(), &["buffer 0", "byteLength"]);
}

#[test]
fn draco_compressed_files_are_unsupported_with_a_clear_message() {
    // (Meshopt compression is decoded: `gltf_meshopt.rs`.)
    let ext = "KHR_draco_mesh_compression";
    let mut b = triangle();
    b.json["extensionsUsed"] = json!([ext]);
    b.json["extensionsRequired"] = json!([ext]);
    let e = read_bytes("c.glb", &b.glb()).expect_err("compressed");
    assert!(matches!(e.kind, ErrorKind::Unsupported(_)), "{e}");
    assert_mentions(&e.to_string(), &[ext, "decompress"]);
}

#[test]
fn position_referring_to_a_missing_accessor_is_an_error_not_a_panic() {
    let mut b = triangle();
    b.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99);
    assert_mentions(
        &error_of("p.glb", &b.glb()),
        &["mesh 0 primitive 0", "accessor 99"],
    );
}

#[test]
fn sparse_index_out_of_range_is_an_error() {
    let mut b = triangle();
    let si = b.view(&9u16.to_le_bytes(), None);
    let sv = b.view(&[0u8; 12], None);
    b.json["accessors"][0]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": si, "componentType": 5123},
        "values": {"bufferView": sv}
    });
    assert_mentions(&error_of("s.glb", &b.glb()), &["accessor 0 sparse", "is 9"]);
}

#[test]
fn cyclic_node_graph_is_an_error_not_a_hang() {
    let mut b = triangle();
    b.json["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
    let e = read_bytes("cycle.glb", &b.glb()).expect_err("cycle");
    assert!(matches!(e.kind, ErrorKind::Invalid(_)), "{e}");
}

#[test]
fn validation_errors_name_the_json_path() {
    let mut b = triangle();
    b.json["nodes"][0]["mesh"] = json!(5);
    assert_mentions(
        &error_of("x.glb", &b.glb()),
        &["nodes[0].mesh", "index out of range"],
    );
}

#[test]
fn hostile_shared_accessors_hit_the_expansion_budget() {
    // One accessor referenced by a hundred thousand primitives, each with
    // a different attribute set so that they cannot share vertices: 12
    // billion floats if decoded.
    let mut b = triangle();
    let big = b.floats(&vec![0.5; 3 * 20_000], "VEC3");
    let prims: Vec<serde_json::Value> = (0..100_000)
        .map(|i| json!({"attributes": {"POSITION": big, format!("_X{i}"): big}, "indices": 1}))
        .collect();
    b.json["meshes"][0]["primitives"] = serde_json::Value::Array(prims);
    let e = read_bytes("budget.glb", &b.glb()).expect_err("over budget");
    assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }), "{e}");
}

/// A small document touching most of the reader: attributes, sparse data,
/// morph targets, skins, animations, an embedded image and materials.
fn rich() -> Builder {
    let mut b = triangle();
    let nrm = b.floats(&[0.0, 0.0, 1.0].repeat(3), "VEC3");
    let uv = b.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2");
    let joints = b.view(&[0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0], None);
    let joints = b.accessor(Some(joints), 5121, 3, "VEC4", json!({}));
    let weights = b.floats(&[1.0, 0.0, 0.0, 0.0].repeat(3), "VEC4");
    let si = b.view(&2u16.to_le_bytes(), None);
    let sv = b.view(
        &[0.0f32, 0.0, 1.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
        None,
    );
    let morph = b.accessor(
        None,
        5126,
        3,
        "VEC3",
        json!({"min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, 1.0], "sparse": {
            "count": 1,
            "indices": {"bufferView": si, "componentType": 5123},
            "values": {"bufferView": sv}
        }}),
    );
    let ibm = b.floats(&wildlod_mesh::IDENTITY.repeat(2), "MAT4");
    let times = b.floats(&[0.0, 1.0], "SCALAR");
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let rot = b.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, h, h], "VEC4");
    let png = b.view(b"\x89PNG\r\n\x1a\n not really", None);
    let prim = &mut b.json["meshes"][0]["primitives"][0];
    prim["attributes"]["NORMAL"] = json!(nrm);
    prim["attributes"]["TEXCOORD_0"] = json!(uv);
    prim["attributes"]["JOINTS_0"] = json!(joints);
    prim["attributes"]["WEIGHTS_0"] = json!(weights);
    prim["targets"] = json!([{ "POSITION": morph }]);
    prim["material"] = json!(0);
    prim["mode"] = json!(4);
    b.json["meshes"][0]["weights"] = json!([0.0]);
    b.json["nodes"] = json!([
        {"mesh": 0, "skin": 0, "children": [1], "translation": [1.0, 2.0, 3.0]},
        {"children": [2], "rotation": [0.0, 0.0, 0.0, 1.0], "scale": [1.0, 1.0, 1.0]},
        {"matrix": wildlod_mesh::IDENTITY}
    ]);
    b.json["skins"] = json!([{"joints": [1, 2], "inverseBindMatrices": ibm, "skeleton": 1}]);
    b.json["animations"] = json!([{
        "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}],
        "samplers": [{"input": times, "output": rot}]
    }]);
    b.json["images"] = json!([{"bufferView": png, "mimeType": "image/png"}]);
    b.json["samplers"] = json!([{"wrapS": 33071}]);
    b.json["textures"] = json!([{"source": 0, "sampler": 0}]);
    b.json["materials"] = json!([{
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 0}},
        "normalTexture": {"index": 0}, "alphaMode": "MASK", "alphaCutoff": 0.3
    }]);
    b
}

/// JSON pointers of every scalar in `v`.
fn scalar_pointers(v: &serde_json::Value, at: String, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                scalar_pointers(x, format!("{at}/{k}"), out);
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                scalar_pointers(x, format!("{at}/{i}"), out);
            }
        }
        _ => out.push(at),
    }
}

#[test]
fn every_scalar_of_a_rich_document_replaced_by_hostile_values_never_panics() {
    let b = rich();
    let doc = read_bytes("rich.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(doc.scene.skins[0].joints.len(), 2);
    assert_eq!(doc.scene.animations[0].duration, 1.0);
    let mut pointers = Vec::new();
    scalar_pointers(&b.json, String::new(), &mut pointers);
    let hostile = [
        json!(-1),
        json!(0),
        json!(3),
        json!(4_294_967_295u64),
        json!(1e300),
        json!("x"),
        json!(null),
    ];
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("m.glb");
    let mut read_ok = 0;
    for p in &pointers {
        for h in &hostile {
            let mut m = Builder {
                json: b.json.clone(),
                bin: b.bin.clone(),
                extra_buffers: Vec::new(),
            };
            *m.json.pointer_mut(p).expect("pointer exists") = h.clone();
            std::fs::write(&path, m.glb()).expect("write");
            // Shown when an assertion below fails.
            eprintln!("{p} = {h}");
            if let Ok(doc) = wildlod_io::read(&path) {
                doc.scene.validate().expect("what reads is valid");
                // What reads also writes.
                let out = dir.path().join("w.glb");
                if wildlod_io::write(&doc, &out, &Default::default()).is_ok() {
                    gltf_support::check_written(&out);
                }
                read_ok += 1;
            }
        }
    }
    // Many replacements are harmless (names, factors): the test must
    // have exercised the success path too.
    assert!(read_ok > 10, "{read_ok}");
}
