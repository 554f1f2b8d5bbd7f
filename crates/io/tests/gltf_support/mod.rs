//! Helpers shared by the glTF integration tests: checking written files
//! for validity and layout, and comparing scenes corner by corner.

#![allow(dead_code)]

use std::path::Path;

use serde_json::Value;
use wildlod_mesh::{ImageSource, Mesh, Scene, ABSENT};

/// The JSON and binary chunk of a written `.gltf` (with its `.bin`) or `.glb`.
pub fn written_parts(path: &Path) -> (Value, Vec<u8>) {
    let bytes = std::fs::read(path).expect("written file is readable");
    if bytes.starts_with(b"glTF") {
        let u32_at =
            |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().expect("four bytes")) as usize;
        assert_eq!(u32_at(4), 2, "GLB version");
        assert_eq!(u32_at(8), bytes.len(), "GLB length");
        let json_len = u32_at(12);
        assert_eq!(json_len % 4, 0, "JSON chunk padded");
        assert_eq!(&bytes[16..20], b"JSON");
        let json: Value =
            serde_json::from_slice(&bytes[20..20 + json_len]).expect("written JSON parses");
        let mut bin = Vec::new();
        if 20 + json_len < bytes.len() {
            let at = 20 + json_len;
            let bin_len = u32_at(at);
            assert_eq!(bin_len % 4, 0, "BIN chunk padded");
            assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
            assert_eq!(at + 8 + bin_len, bytes.len(), "nothing after the BIN chunk");
            bin = bytes[at + 8..].to_vec();
        }
        (json, bin)
    } else {
        let json: Value = serde_json::from_slice(&bytes).expect("written JSON parses");
        let bin = match json.pointer("/buffers/0/uri").and_then(Value::as_str) {
            Some(u) => std::fs::read(path.parent().expect("a file has a directory").join(u))
                .expect("written file is readable"),
            None => Vec::new(),
        };
        (json, bin)
    }
}

fn component_size(c: u64) -> usize {
    match c {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        _ => 4,
    }
}

fn type_shape(t: &str) -> (usize, usize) {
    match t {
        "SCALAR" => (1, 1),
        "VEC2" => (1, 2),
        "VEC3" => (1, 3),
        "VEC4" => (1, 4),
        "MAT2" => (2, 2),
        "MAT3" => (3, 3),
        _ => (4, 4),
    }
}

/// Checks a written file: the `gltf` crate's validation passes, there is
/// one buffer whose byteLength matches the data, and every view and
/// accessor is aligned and inside its parent (vertex attributes on 4-byte
/// boundaries with 4-byte strides).
pub fn check_written(path: &Path) -> Value {
    let bytes = std::fs::read(path).expect("written file is readable");
    if let Err(e) = gltf::Gltf::from_slice(&bytes) {
        panic!("{}: gltf crate validation failed: {e:?}", path.display());
    }
    let (json, bin) = written_parts(path);
    let buffers = json["buffers"].as_array().cloned().unwrap_or_default();
    if bin.is_empty() {
        assert!(buffers.is_empty());
        return json;
    }
    assert_eq!(buffers.len(), 1, "one buffer");
    let byte_length = buffers[0]["byteLength"]
        .as_u64()
        .expect("field required by glTF") as usize;
    if bytes.starts_with(b"glTF") {
        assert!(
            byte_length <= bin.len() && bin.len() - byte_length < 4,
            "BIN chunk is byteLength padded"
        );
    } else {
        assert_eq!(byte_length, bin.len(), ".bin size equals byteLength");
    }
    let views = json["bufferViews"].as_array().cloned().unwrap_or_default();
    for (i, v) in views.iter().enumerate() {
        let off = v["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = v["byteLength"].as_u64().expect("field required by glTF") as usize;
        assert!(off + len <= byte_length, "bufferView {i} inside the buffer");
        if let Some(s) = v["byteStride"].as_u64() {
            assert!(
                (4..=252).contains(&s) && s % 4 == 0,
                "bufferView {i} stride {s}"
            );
        }
    }
    let mut vertex_accessors = std::collections::BTreeSet::new();
    for m in json["meshes"].as_array().into_iter().flatten() {
        for p in m["primitives"].as_array().expect("field required by glTF") {
            for a in p["attributes"]
                .as_object()
                .expect("field required by glTF")
                .values()
            {
                vertex_accessors.insert(a.as_u64().expect("field required by glTF") as usize);
            }
            for t in p["targets"].as_array().into_iter().flatten() {
                for a in t.as_object().expect("field required by glTF").values() {
                    vertex_accessors.insert(a.as_u64().expect("field required by glTF") as usize);
                }
            }
        }
    }
    for (i, a) in json["accessors"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        let Some(v) = a["bufferView"].as_u64() else {
            continue;
        };
        let view = &views[v as usize];
        let size = component_size(a["componentType"].as_u64().expect("field required by glTF"));
        let (cols, rows) = type_shape(a["type"].as_str().expect("field required by glTF"));
        let col = if cols > 1 {
            (rows * size).div_ceil(4) * 4
        } else {
            rows * size
        };
        let elem = col * (cols - 1) + rows * size;
        let stride = view["byteStride"]
            .as_u64()
            .map(|s| s as usize)
            .unwrap_or(elem);
        let voff = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let aoff = a["byteOffset"].as_u64().unwrap_or(0) as usize;
        let count = a["count"].as_u64().expect("field required by glTF") as usize;
        assert_eq!(
            (voff + aoff) % size,
            0,
            "accessor {i} aligned to its component"
        );
        if count > 0 {
            let end = aoff + (count - 1) * stride + elem;
            assert!(
                end <= view["byteLength"].as_u64().expect("field required by glTF") as usize,
                "accessor {i} inside bufferView {v}"
            );
        }
        if vertex_accessors.contains(&i) {
            assert_eq!(
                (voff + aoff) % 4,
                0,
                "vertex accessor {i} on a 4-byte boundary"
            );
            assert_eq!(stride % 4, 0, "vertex accessor {i} stride multiple of 4");
        }
    }
    json
}

/// Asserts that two meshes hold the same faces, positions, attributes and
/// skinning corner by corner (bit-equal values).
pub fn assert_same_mesh(name: &str, a: &Mesh, b: &Mesh) {
    assert_eq!(a.faces.offsets, b.faces.offsets, "{name}: face arities");
    assert_eq!(a.face_parts.len(), b.face_parts.len(), "{name}: face parts");
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for c in 0..a.faces.indices.len() {
        let pa = a.positions[a.faces.indices[c] as usize];
        let pb = b.positions[b.faces.indices[c] as usize];
        assert_eq!(bits(&pa), bits(&pb), "{name}: position of corner {c}");
    }
    let sems = |m: &Mesh| {
        m.attributes
            .iter()
            .map(|x| x.semantic.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(sems(a), sems(b), "{name}: attribute streams");
    for (sa, sb) in a.attributes.iter().zip(&b.attributes) {
        assert_eq!(
            sa.components, sb.components,
            "{name}: {:?} components",
            sa.semantic
        );
        assert_eq!(sa.format, sb.format, "{name}: {:?} format", sa.semantic);
        for c in 0..a.faces.indices.len() {
            assert_eq!(
                sa.corner_value(c).map(bits),
                sb.corner_value(c).map(bits),
                "{name}: {:?} at corner {c}",
                sa.semantic
            );
        }
    }
    match (&a.skinning, &b.skinning) {
        (None, None) => {}
        (Some(sa), Some(sb)) => {
            assert_eq!(sa.influences, sb.influences, "{name}: influences");
            assert_eq!(sa.weight_format, sb.weight_format, "{name}: weight format");
            assert_eq!(sa.joint_format, sb.joint_format, "{name}: joint format");
            for c in 0..a.faces.indices.len() {
                let ea = (sa.indices[c] != ABSENT).then(|| sa.entry(sa.indices[c]));
                let eb = (sb.indices[c] != ABSENT).then(|| sb.entry(sb.indices[c]));
                let ea = ea.map(|(j, w)| (j.to_vec(), bits(w)));
                let eb = eb.map(|(j, w)| (j.to_vec(), bits(w)));
                assert_eq!(ea, eb, "{name}: skin entry at corner {c}");
            }
        }
        _ => panic!("{name}: skinning present on one side only"),
    }
}

/// Positions that some face uses.
pub fn used_vertices(m: &Mesh) -> usize {
    let mut used = vec![false; m.positions.len()];
    for &v in &m.faces.indices {
        used[v as usize] = true;
    }
    used.iter().filter(|&&u| u).count()
}

/// The bytes of an image source.
pub fn image_bytes(s: &ImageSource) -> Vec<u8> {
    match s {
        ImageSource::Embedded { bytes, .. } => bytes.clone(),
        ImageSource::Path(p) => std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())),
    }
}

/// Asserts that two scenes match: meshes corner by corner, nodes, roots,
/// skins, animations, materials, and image bytes.
pub fn assert_same_scene(name: &str, a: &Scene, b: &Scene) {
    assert_eq!(a.meshes.len(), b.meshes.len(), "{name}: mesh count");
    for (i, (ma, mb)) in a.meshes.iter().zip(&b.meshes).enumerate() {
        assert_same_mesh(&format!("{name} mesh {i}"), ma, mb);
        assert_eq!(
            used_vertices(ma),
            used_vertices(mb),
            "{name} mesh {i}: vertices"
        );
        let mats = |m: &Mesh| m.parts.iter().map(|p| p.material).collect::<Vec<_>>();
        assert_eq!(mats(ma), mats(mb), "{name} mesh {i}: part materials");
    }
    assert_eq!(a.nodes, b.nodes, "{name}: nodes");
    assert_eq!(a.roots, b.roots, "{name}: roots");
    assert_eq!(a.skins, b.skins, "{name}: skins");
    assert_eq!(a.animations, b.animations, "{name}: animations");
    assert_eq!(a.materials, b.materials, "{name}: materials");
    assert_eq!(a.textures.len(), b.textures.len(), "{name}: textures");
    for (i, (ta, tb)) in a.textures.iter().zip(&b.textures).enumerate() {
        assert_eq!(ta.name, tb.name, "{name}: texture {i} name");
        assert!(
            image_bytes(&ta.source) == image_bytes(&tb.source),
            "{name}: texture {i} image bytes"
        );
    }
}
