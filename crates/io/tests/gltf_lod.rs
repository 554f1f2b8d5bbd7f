//! Levels of detail in one glTF file (`MSFT_lod` on nodes): the JSON
//! layout viewers rely on, and that the file still reads as its highest
//! level.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use serde_json::Value;
use wildlod_io::{Document, LodLevels, WriteOptions};
use wildlod_mesh::{shapes, Node, Scene, IDENTITY};

/// Two nodes instancing one torus, levels made of coarser tori.
fn scene() -> (Scene, Vec<Vec<wildlod_mesh::Mesh>>) {
    let mut scene = Scene::from_mesh(shapes::torus(24, 12, 1.0, 0.3));
    scene.meshes[0].name = "ring".into();
    let mut moved = IDENTITY;
    moved[12] = 3.0;
    scene.nodes = vec![
        Node {
            name: "a".into(),
            mesh: Some(0),
            ..Node::default()
        },
        Node {
            name: "b".into(),
            matrix: moved,
            mesh: Some(0),
            ..Node::default()
        },
    ];
    scene.roots = vec![0, 1];
    let levels = vec![
        vec![shapes::torus(12, 6, 1.0, 0.3)],
        vec![shapes::torus(6, 3, 1.0, 0.3)],
    ];
    (scene, levels)
}

fn json_of(path: &std::path::Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn every_mesh_node_lists_its_lower_levels_outside_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, levels) = scene();
    let coverage = vec![vec![0.5, 0.2, 0.0]];
    let path = dir.path().join("lods.gltf");
    wildlod_io::write_lods(
        &Document::from_scene(scene),
        &LodLevels {
            levels: &levels,
            screen_coverage: &coverage,
        },
        &path,
        &WriteOptions::default(),
    )
    .unwrap();
    let j = json_of(&path);
    assert!(j["extensionsUsed"]
        .as_array()
        .unwrap()
        .contains(&Value::from("MSFT_lod")));
    let nodes = j["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 6, "2 base nodes + 2 levels each");
    let in_scene: Vec<u64> = j["scenes"][0]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let mut faces = Vec::new();
    for base in [0usize, 1] {
        let ids: Vec<usize> = nodes[base]["extensions"]["MSFT_lod"]["ids"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as usize)
            .collect();
        assert_eq!(ids.len(), 2);
        assert_eq!(
            nodes[base]["extras"]["MSFT_screencoverage"],
            serde_json::json!([0.5, 0.2, 0.0])
        );
        for &id in &ids {
            assert!(
                !in_scene.contains(&(id as u64)),
                "level node {id} is in the scene"
            );
            assert_eq!(nodes[id]["matrix"], nodes[base]["matrix"]);
        }
        // Meshes are shared between the instances, one per level.
        let meshes: Vec<u64> = std::iter::once(base)
            .chain(ids)
            .map(|n| nodes[n]["mesh"].as_u64().unwrap())
            .collect();
        faces.push(meshes);
    }
    assert_eq!(faces[0], faces[1]);
    assert_eq!(j["meshes"].as_array().unwrap().len(), 3);
    assert_eq!(j["meshes"][1]["name"], "ring_lod1");
    // Read back, the scene shows the highest level only; the levels are
    // meshes of their own.
    let doc = wildlod_io::read(&path).unwrap();
    assert_eq!(doc.scene.meshes.len(), 3);
    assert_eq!(doc.scene.roots.len(), 2);
    for &r in &doc.scene.roots {
        assert_eq!(doc.scene.nodes[r as usize].mesh, Some(0));
    }
    assert_eq!(doc.scene.meshes[0].triangle_count(), 24 * 12 * 2);
}

#[test]
fn levels_are_refused_for_formats_without_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, levels) = scene();
    let e = wildlod_io::write_lods(
        &Document::from_scene(scene),
        &LodLevels {
            levels: &levels,
            screen_coverage: &[],
        },
        dir.path().join("x.obj"),
        &WriteOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("glTF"), "{e}");
    assert!(!dir.path().join("x.obj").exists());
}

#[test]
fn a_level_with_the_wrong_mesh_count_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = scene();
    let levels = vec![vec![]];
    let e = wildlod_io::write_lods(
        &Document::from_scene(scene),
        &LodLevels {
            levels: &levels,
            screen_coverage: &[],
        },
        dir.path().join("x.glb"),
        &WriteOptions::default(),
    )
    .unwrap_err();
    assert!(
        format!("{e}").contains("level of detail 1 has 0 meshes"),
        "{e}"
    );
}
