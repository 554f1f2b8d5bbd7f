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
    match gltf::Gltf::from_slice(&bytes) {
        Ok(_) => {}
        // The gltf crate is built without KHR_mesh_quantization support and
        // reports a file that requires it as unsupported; that is not an
        // error of the file.
        Err(gltf::Error::Validation(errs))
            if errs.iter().all(|(p, e)| {
                *e == gltf::json::validation::Error::Unsupported
                    && p.as_str().contains("KHR_mesh_quantization")
            }) => {}
        Err(e) => panic!("{}: gltf crate validation failed: {e:?}", path.display()),
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
        if used_vertices(ma) == ma.positions.len() {
            // Nothing unused to drop: the vertices come back in their order.
            let bits = |m: &Mesh| -> Vec<[u32; 3]> {
                m.positions.iter().map(|p| p.map(f32::to_bits)).collect()
            };
            assert!(bits(ma) == bits(mb), "{name} mesh {i}: vertex order");
        }
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

/// A glTF document assembled in code: JSON plus one binary buffer.
pub struct Builder {
    pub json: Value,
    pub bin: Vec<u8>,
    /// Buffers after buffer 0 (the binary chunk), as JSON.
    pub extra_buffers: Vec<Value>,
}

impl Builder {
    /// An asset with nothing in it.
    pub fn new() -> Self {
        Builder {
            json: serde_json::json!({"asset": {"version": "2.0"}}),
            bin: Vec::new(),
            extra_buffers: Vec::new(),
        }
    }

    fn push(&mut self, key: &str, v: Value) -> usize {
        let arr = self.json[key].as_array_mut();
        match arr {
            Some(a) => {
                a.push(v);
                a.len() - 1
            }
            None => {
                self.json[key] = Value::Array(vec![v]);
                0
            }
        }
    }

    /// Appends `bytes` as a 4-byte aligned buffer view.
    pub fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let mut v = serde_json::json!({
            "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()
        });
        if let Some(s) = stride {
            v["byteStride"] = s.into();
        }
        self.bin.extend_from_slice(bytes);
        self.push("bufferViews", v)
    }

    /// Appends an accessor; `extra` is merged into its JSON.
    pub fn accessor(
        &mut self,
        view: Option<usize>,
        component: u32,
        count: usize,
        ty: &str,
        extra: Value,
    ) -> usize {
        let mut a = serde_json::json!({"componentType": component, "count": count, "type": ty});
        if let Some(v) = view {
            a["bufferView"] = v.into();
        }
        if let Value::Object(e) = extra {
            for (k, v) in e {
                a[k.as_str()] = v;
            }
        }
        self.push("accessors", a)
    }

    /// A float accessor over `values` (min/max included for VEC3).
    pub fn floats(&mut self, values: &[f32], ty: &str) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let n = type_shape(ty).0 * type_shape(ty).1;
        let view = self.view(&bytes, None);
        let mut extra = serde_json::json!({});
        if ty == "VEC3" {
            let lo: Vec<f32> = (0..3)
                .map(|k| {
                    values
                        .iter()
                        .skip(k)
                        .step_by(3)
                        .copied()
                        .fold(f32::INFINITY, f32::min)
                })
                .collect();
            let hi: Vec<f32> = (0..3)
                .map(|k| {
                    values
                        .iter()
                        .skip(k)
                        .step_by(3)
                        .copied()
                        .fold(f32::NEG_INFINITY, f32::max)
                })
                .collect();
            extra = serde_json::json!({"min": lo, "max": hi});
        }
        self.accessor(Some(view), 5126, values.len() / n, ty, extra)
    }

    /// An unsigned short index accessor.
    pub fn indices(&mut self, idx: &[u16]) -> usize {
        let bytes: Vec<u8> = idx.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None);
        self.accessor(Some(view), 5123, idx.len(), "SCALAR", serde_json::json!({}))
    }

    /// Adds a mesh of the given primitives, a node instancing it, and the
    /// default scene if there is none yet; returns the mesh index.
    pub fn mesh(&mut self, primitives: Value) -> usize {
        let m = self.push("meshes", serde_json::json!({ "primitives": primitives }));
        let n = self.push("nodes", serde_json::json!({ "mesh": m }));
        if self.json.get("scenes").is_none() {
            self.json["scenes"] = serde_json::json!([{"nodes": []}]);
            self.json["scene"] = 0.into();
        }
        if let Some(roots) = self.json["scenes"][0]["nodes"].as_array_mut() {
            roots.push(n.into());
        }
        m
    }

    fn with_buffer(&self, uri: Option<String>) -> Value {
        let mut j = self.json.clone();
        if !self.bin.is_empty() {
            let mut b = serde_json::json!({"byteLength": self.bin.len()});
            if let Some(u) = uri {
                b["uri"] = u.into();
            }
            j["buffers"] = serde_json::json!([b]);
        }
        if let Some(list) = j["buffers"].as_array_mut() {
            list.extend(self.extra_buffers.iter().cloned());
        }
        j
    }

    /// The document as GLB bytes.
    pub fn glb(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.with_buffer(None)).expect("serializable");
        while json.len() % 4 != 0 {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        if !bin.is_empty() {
            out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
            out.extend_from_slice(b"BIN\0");
            out.extend_from_slice(&bin);
        }
        out
    }

    /// The document as `.gltf` JSON with the buffer in a base64 data URI.
    pub fn gltf_embedded(&self) -> Vec<u8> {
        use base64::Engine;
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        serde_json::to_vec_pretty(&self.with_buffer(Some(uri))).expect("serializable")
    }

    /// The document as `.gltf` JSON whose buffer is the file `uri`.
    pub fn gltf_external(&self, uri: &str) -> Vec<u8> {
        serde_json::to_vec_pretty(&self.with_buffer(Some(uri.to_string()))).expect("serializable")
    }
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

/// One triangle: POSITION (accessor 0) and u16 indices (accessor 1) in
/// mesh 0, node 0.
pub fn triangle() -> Builder {
    let mut b = Builder::new();
    let pos = b.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let idx = b.indices(&[0, 1, 2]);
    b.mesh(serde_json::json!([{"attributes": {"POSITION": pos}, "indices": idx}]));
    b
}

/// Writes `bytes` as `name` in a fresh directory and reads it.
pub fn read_bytes(name: &str, bytes: &[u8]) -> Result<wildlod_io::Document, wildlod_io::Error> {
    let dir = tempfile::tempdir().expect("temp dir");
    let p = dir.path().join(name);
    std::fs::write(&p, bytes).expect("write test file");
    wildlod_io::read(&p)
}

/// `doc` written as `.gltf` in a fresh directory: the written JSON text
/// and the document read back from it.
pub fn write_gltf_and_read_back(doc: &wildlod_io::Document) -> (String, wildlod_io::Document) {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out.gltf");
    wildlod_io::write(doc, &out, &wildlod_io::WriteOptions::default()).expect("writes");
    let text = std::fs::read_to_string(&out).expect("written");
    let again = wildlod_io::read(&out).expect("reads back");
    (text, again)
}
