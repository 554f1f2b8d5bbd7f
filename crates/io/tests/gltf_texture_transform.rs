//! `KHR_texture_transform` is applied to the UVs when a file is read (as
//! gltfpack's quantized files need), and nothing reads it twice.

mod gltf_support;

use gltf_support::{read_bytes, write_gltf_and_read_back, Builder};
use serde_json::{json, Value};
use wildlod_mesh::{Mesh, Semantic};

const UV: [[f32; 2]; 4] = [[0.1, 0.2], [0.9, 0.2], [0.9, 0.8], [0.1, 0.8]];

/// A quad in two primitives sharing positions and UVs: triangle (0, 1, 2)
/// with material 0, triangle (0, 2, 3) with material 1.
fn quad(materials: Value) -> Builder {
    let mut b = Builder::new();
    let pos = b.floats(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
        "VEC3",
    );
    let uv = b.floats(&UV.concat(), "VEC2");
    let first = b.indices(&[0, 1, 2]);
    let second = b.indices(&[0, 2, 3]);
    b.mesh(json!([
        {"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "indices": first, "material": 0},
        {"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "indices": second, "material": 1}
    ]));
    let png = b.view(b"\x89PNG\r\n\x1a\n not decoded here", None);
    b.json["images"] = json!([{"bufferView": png, "mimeType": "image/png"}]);
    b.json["textures"] = json!([{"source": 0}]);
    b.json["materials"] = materials;
    b.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
    b
}

/// The UV of set `set` at every corner (by face, then corner).
fn corner_uvs(m: &Mesh, set: u32) -> Vec<Option<[f32; 2]>> {
    let Some(a) = m.attribute(&Semantic::TexCoord(set)) else {
        return vec![None; m.faces.indices.len()];
    };
    a.indices
        .iter()
        .map(|&i| (i != wildlod_mesh::ABSENT).then(|| [a.value(i)[0], a.value(i)[1]]))
        .collect()
}

fn close(a: Option<[f32; 2]>, b: [f32; 2]) -> bool {
    a.is_some_and(|a| (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6)
}

#[test]
fn the_map_moves_the_uvs_of_its_material_only_and_leaves_the_document() {
    // Offset (0.5, 0.25), scale (2, 3), a quarter turn: u' = 3v + 0.5,
    // v' = −2u + 0.25 (scale, then rotation, as CesiumGltf and three.js
    // apply it).
    let transform = json!({"offset": [0.5, 0.25], "scale": [2.0, 3.0],
                           "rotation": std::f64::consts::FRAC_PI_2});
    let b = quad(json!([
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": transform}}}},
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}
    ]));
    let doc = read_bytes("t.glb", &b.glb()).expect("reads");
    let m = &doc.scene.meshes[0];
    let uvs = corner_uvs(m, 0);
    let moved = |[u, v]: [f32; 2]| [3.0 * v + 0.5, -2.0 * u + 0.25];
    // First triangle: corners 0, 1, 2 moved; second: 0, 2, 3 as they were.
    for (k, &vtx) in [0usize, 1, 2].iter().enumerate() {
        assert!(close(uvs[k], moved(UV[vtx])), "corner {k}: {:?}", uvs[k]);
    }
    for (k, &vtx) in [0usize, 2, 3].iter().enumerate() {
        assert!(
            close(uvs[3 + k], UV[vtx]),
            "corner {}: {:?}",
            3 + k,
            uvs[3 + k]
        );
    }
    assert_eq!(
        doc.scene.materials[0]
            .base_color_texture
            .map(|r| r.tex_coord),
        Some(0)
    );
    // Written back, the map is gone from the material and the extension
    // list, and read again the UVs are the same (applied once, not twice).
    let (text, again) = write_gltf_and_read_back(&doc);
    assert!(!text.contains("KHR_texture_transform"), "{text}");
    assert_eq!(corner_uvs(&again.scene.meshes[0], 0), uvs);
}

#[test]
fn a_slot_reading_the_set_through_another_map_gets_its_own_set() {
    // Base color through a scale of 2, the normal map of the same material
    // through none: the normal map gets a new set with the original UVs,
    // set 0 holds the scaled ones.
    let b = quad(json!([
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": {"scale": [2.0, 2.0]}}}},
         "normalTexture": {"index": 0}},
        {}
    ]));
    let doc = read_bytes("t.glb", &b.glb()).expect("reads");
    let m = &doc.scene.meshes[0];
    let mat = &doc.scene.materials[0];
    assert_eq!(mat.base_color_texture.map(|r| r.tex_coord), Some(0));
    let normal_set = mat.normal_texture.map(|r| r.tex_coord).expect("normal");
    assert_eq!(normal_set, 1);
    let scaled = corner_uvs(m, 0);
    let plain = corner_uvs(m, 1);
    for (k, &vtx) in [0usize, 1, 2].iter().enumerate() {
        let [u, v] = UV[vtx];
        assert!(close(scaled[k], [2.0 * u, 2.0 * v]), "{:?}", scaled[k]);
        assert!(close(plain[k], UV[vtx]), "{:?}", plain[k]);
    }
    // Faces of the other material have no value in the new set.
    assert!(plain[3..].iter().all(Option::is_none));
    // The written material points its normal map at the new set.
    let (text, again) = write_gltf_and_read_back(&doc);
    let json: Value = serde_json::from_str(&text).expect("json");
    assert_eq!(json["materials"][0]["normalTexture"]["texCoord"], json!(1));
    assert_eq!(corner_uvs(&again.scene.meshes[0], 1)[..3], plain[..3]);
}

#[test]
fn a_texcoord_override_reads_the_named_set() {
    // The transform names set 1 (with no map of its own): the reference
    // reads set 1, written as its texCoord.
    let mut b = quad(json!([
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": {"texCoord": 1}}}}},
        {}
    ]));
    let uv1 = b.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], "VEC2");
    for p in 0..2 {
        b.json["meshes"][0]["primitives"][p]["attributes"]["TEXCOORD_1"] = json!(uv1);
    }
    let doc = read_bytes("t.glb", &b.glb()).expect("reads");
    assert_eq!(
        doc.scene.materials[0]
            .base_color_texture
            .map(|r| r.tex_coord),
        Some(1)
    );
    assert!(close(corner_uvs(&doc.scene.meshes[0], 1)[1], [1.0, 0.0]));
}
