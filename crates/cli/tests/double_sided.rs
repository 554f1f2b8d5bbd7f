//! Visible twins (issue 31, decision 5): a sheet exported double-sided
//! (every face written twice, once each way) simplified to glTF is written
//! once with a double-sided material, its budget of the triangles the
//! input drew; to OBJ both sides stay faces.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::collections::HashMap;

use support::{s, wildlod};
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{Mesh, Scene, Semantic};
use wildlod_testkit::scenes;

/// Face pairs of `mesh` that are one cycle of positions both ways round.
fn twin_pairs(mesh: &Mesh) -> usize {
    let key = |f: usize| -> Vec<[u32; 3]> {
        let c: Vec<[u32; 3]> = mesh
            .faces
            .face(f)
            .iter()
            .map(|&v| mesh.positions[v as usize].map(f32::to_bits))
            .collect();
        let start = (0..c.len()).min_by_key(|&k| c[k]).unwrap();
        c[start..].iter().chain(&c[..start]).copied().collect()
    };
    let mut seen: HashMap<Vec<[u32; 3]>, usize> = HashMap::new();
    let mut pairs = 0;
    for f in 0..mesh.faces.len() {
        let mut back: Vec<[u32; 3]> = key(f);
        back[1..].reverse();
        if let Some(n) = seen.get_mut(&back).filter(|n| **n > 0) {
            *n -= 1;
            pairs += 1;
        } else {
            *seen.entry(key(f)).or_default() += 1;
        }
    }
    pairs
}

/// The flag of [`scenes::double_sided_sheet`] without its texture and UVs
/// (an untextured sheet: its back looks like the front's back).
fn plain_sheet() -> Scene {
    let mut scene = scenes::double_sided_sheet();
    for m in &mut scene.meshes {
        m.attributes
            .retain(|a| !matches!(a.semantic, Semantic::TexCoord(_)));
    }
    for mat in &mut scene.materials {
        mat.base_color_texture = None;
    }
    scene.textures.clear();
    scene
}

#[test]
fn a_double_sided_sheet_to_gltf_is_one_face_per_twin_pair_with_a_double_sided_material() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sheet.glb");
    wildlod_io::write(
        &Document::from_scene(plain_sheet()),
        &input,
        &WriteOptions::default(),
    )
    .unwrap();
    let drawn = 9600;
    assert_eq!(
        twin_pairs(&wildlod_io::read(&input).unwrap().scene.meshes[0]),
        4800
    );

    let out = dir.path().join("lod.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["double_sided_twins"], 4800, "{j}");
    assert_eq!(j["input_triangles"], drawn, "{j}");
    let lod = wildlod_io::read(&out).unwrap().scene;
    let mesh = &lod.meshes[0];
    // One face per pair: no twins left, every face of a double-sided
    // material, and the budget of what the input drew.
    assert_eq!(twin_pairs(mesh), 0);
    for &p in &mesh.face_parts {
        let m = mesh.parts[p as usize].material.unwrap();
        assert!(lod.materials[m as usize].double_sided);
    }
    let triangles = mesh.triangle_count();
    assert!(triangles.abs_diff(drawn / 10) <= 1, "{triangles}");
    assert_eq!(j["output_triangles"], triangles, "{j}");

    // OBJ has no double-sided flag: both sides stay faces.
    let obj = dir.path().join("lod.obj");
    let o = wildlod(&["simplify", s(&input), "-o", s(&obj), "--ratio", "0.1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mesh = wildlod_io::read(&obj).unwrap().scene.meshes.remove(0);
    assert!(
        twin_pairs(&mesh) * 2 >= mesh.faces.len() - 2,
        "{}",
        mesh.faces.len()
    );
}

/// A back with UVs of its own (the flag's back mirrored to read the right
/// way round) would show otherwise as a double-sided face: its faces stay.
#[test]
fn twins_whose_back_shows_its_own_uvs_keep_both_faces() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("flag.glb");
    wildlod_io::write(
        &Document::from_scene(scenes::double_sided_sheet()),
        &input,
        &WriteOptions::default(),
    )
    .unwrap();
    let out = dir.path().join("lod.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["double_sided_twins"], 0, "{j}");
    let mesh = wildlod_io::read(&out).unwrap().scene.meshes.remove(0);
    assert!(
        twin_pairs(&mesh) * 2 >= mesh.faces.len() - 2,
        "{}",
        mesh.faces.len()
    );
}
