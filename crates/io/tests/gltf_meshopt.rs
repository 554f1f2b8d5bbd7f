//! `EXT_meshopt_compression` files (what `gltfpack -c` writes) read as the
//! uncompressed file they encode.

mod gltf_support;

use gltf_support::{read_bytes, write_gltf_and_read_back, Builder};
use serde_json::json;
use wildlod_mesh::Semantic;

/// A 3×3 grid of vertices, 8 triangles, with normals tilted per vertex.
fn grid() -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u16>) {
    let mut p = Vec::new();
    let mut n = Vec::new();
    for y in 0..3 {
        for x in 0..3 {
            p.push([x as f32 * 0.5, y as f32 * 0.25, (x * y) as f32 * 0.125]);
            let v = [0.1 * x as f32, -0.2 * y as f32, 1.0];
            let len = v.iter().map(|c| c * c).sum::<f32>().sqrt();
            n.push(v.map(|c| c / len));
        }
    }
    let mut idx = Vec::new();
    for y in 0..2u16 {
        for x in 0..2u16 {
            let a = y * 3 + x;
            idx.extend([a, a + 1, a + 4, a, a + 4, a + 3]);
        }
    }
    (p, n, idx)
}

/// The grid with its three streams compressed into buffer 0 and laid out
/// in fallback buffer 1 (absent from the file, as gltfpack writes it):
/// positions as plain floats, normals as 8-bit octahedral, indices as
/// triangles. `fallback_length` overrides buffer 1's declared length.
fn compressed(fallback_length: Option<u64>) -> Builder {
    let (p, n, idx) = grid();
    let mut b = Builder::new();
    let pos = meshopt::encode_vertex_buffer(&p).expect("encodes");
    let oct: Vec<[i8; 4]> = meshopt::encode_filter_oct::<i8>(
        &n.iter()
            .map(|v| [v[0], v[1], v[2], 0.0])
            .collect::<Vec<_>>(),
        8,
    );
    let nrm = meshopt::encode_vertex_buffer(&oct).expect("encodes");
    let tri =
        meshopt::encode_index_buffer(&idx.iter().map(|&i| u32::from(i)).collect::<Vec<_>>(), 9)
            .expect("encodes");
    // Where each stream lies once decoded, in buffer 1.
    let (pos_at, nrm_at, idx_at) = (0usize, 9 * 12, 9 * 12 + 9 * 4);
    let total = idx_at + idx.len() * 2;
    let mut views = Vec::new();
    for (data, at, len, stride, count, mode, filter, target) in [
        (&pos, pos_at, 9 * 12, 12, 9, "ATTRIBUTES", "NONE", 34962),
        (&nrm, nrm_at, 9 * 4, 4, 9, "ATTRIBUTES", "OCTAHEDRAL", 34962),
        (
            &tri,
            idx_at,
            idx.len() * 2,
            2,
            idx.len(),
            "TRIANGLES",
            "NONE",
            34963,
        ),
    ] {
        while b.bin.len() % 4 != 0 {
            b.bin.push(0);
        }
        let offset = b.bin.len();
        b.bin.extend_from_slice(data);
        let mut v = json!({"buffer": 1, "byteOffset": at, "byteLength": len, "target": target,
            "extensions": {"EXT_meshopt_compression": {"buffer": 0, "byteOffset": offset,
                "byteLength": data.len(), "byteStride": stride, "count": count,
                "mode": mode, "filter": filter}}});
        if mode == "ATTRIBUTES" {
            v["byteStride"] = stride.into();
        }
        views.push(v);
    }
    b.json["bufferViews"] = json!(views);
    let lo = [0.0, 0.0, 0.0];
    let hi = [1.0, 0.5, 0.5];
    b.json["accessors"] = json!([
        {"bufferView": 0, "componentType": 5126, "count": 9, "type": "VEC3", "min": lo, "max": hi},
        {"bufferView": 1, "componentType": 5120, "normalized": true, "count": 9, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": idx.len(), "type": "SCALAR"}
    ]);
    b.mesh(json!([{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]));
    b.extra_buffers.push(
        json!({"byteLength": fallback_length.unwrap_or(total as u64),
        "extensions": {"EXT_meshopt_compression": {"fallback": true}}}),
    );
    b.json["extensionsUsed"] = json!(["EXT_meshopt_compression", "KHR_mesh_quantization"]);
    b.json["extensionsRequired"] = json!(["EXT_meshopt_compression", "KHR_mesh_quantization"]);
    b
}

#[test]
fn compressed_views_read_as_the_data_they_encode() {
    let doc = read_bytes("c.glb", &compressed(None).glb()).unwrap_or_else(|e| panic!("{e}"));
    let (p, n, idx) = grid();
    let m = &doc.scene.meshes[0];
    assert_eq!(m.positions, p);
    // The index codec may rotate a triangle's corners (winding kept).
    let canonical = |t: &[u32]| {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
    };
    let want: Vec<u32> = idx.iter().map(|&i| u32::from(i)).collect();
    assert_eq!(
        m.faces.indices.chunks(3).map(canonical).collect::<Vec<_>>(),
        want.chunks(3).map(canonical).collect::<Vec<_>>()
    );
    // Normals through 8-bit octahedral encoding: within a few degrees.
    let normals = m.attribute(&Semantic::Normal).expect("normals");
    for (c, &i) in normals.indices.iter().enumerate() {
        let v = normals.value(i);
        let want = n[m.faces.indices[c] as usize];
        let dot: f32 = (0..3).map(|k| v[k] * want[k]).sum();
        assert!(dot > 0.995, "corner {c}: {v:?} against {want:?}");
    }
    // Written back uncompressed, with the extension gone.
    let (text, again) = write_gltf_and_read_back(&doc);
    assert!(!text.contains("meshopt_compression"), "{text}");
    assert_eq!(again.scene.meshes[0].positions, p);
}

#[test]
fn a_fallback_buffer_larger_than_the_data_could_decode_to_is_refused() {
    let e = read_bytes("c.glb", &compressed(Some(1 << 40)).glb()).expect_err("hostile");
    let text = e.to_string();
    assert!(
        text.contains("buffer 1") && text.contains("refusing"),
        "{text}"
    );
}

#[test]
fn a_corrupt_stream_is_an_error_naming_the_view() {
    let mut b = compressed(None);
    // The index stream's header byte says nothing meshopt knows.
    let at = b.json["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["byteOffset"]
        .as_u64()
        .expect("offset") as usize;
    b.bin[at] = 0x00;
    let e = read_bytes("c.glb", &b.glb()).expect_err("corrupt");
    assert!(e.to_string().contains("bufferView 2"), "{e}");
}

#[test]
fn a_stride_past_the_extensions_limit_is_an_error_naming_the_view() {
    let mut b = compressed(None);
    // The view is long enough for it: the decoder's stride limit refuses.
    b.json["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = json!(260);
    b.json["bufferViews"][0]["byteLength"] = json!(9 * 260);
    let e = read_bytes("c.glb", &b.glb()).expect_err("stride");
    let text = e.to_string();
    assert!(
        text.contains("bufferView 0") && text.contains("byteStride 260"),
        "{text}"
    );
}
