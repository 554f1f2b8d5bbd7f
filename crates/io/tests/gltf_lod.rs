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

/// A body node showing a mesh with a wheel node (its own mesh) below it,
/// levels made of coarser tori.
fn body_with_wheel() -> (Scene, Vec<Vec<wildlod_mesh::Mesh>>) {
    let mut scene = Scene::from_mesh(shapes::torus(24, 12, 1.0, 0.3));
    scene.meshes.push(shapes::torus(16, 8, 0.3, 0.1));
    let mut moved = IDENTITY;
    moved[12] = 2.0;
    scene.nodes = vec![
        Node {
            name: "body".into(),
            mesh: Some(0),
            children: vec![1],
            ..Node::default()
        },
        Node {
            name: "wheel".into(),
            matrix: moved,
            mesh: Some(1),
            ..Node::default()
        },
    ];
    scene.roots = vec![0];
    let levels = vec![
        vec![
            shapes::torus(12, 6, 1.0, 0.3),
            shapes::torus(8, 4, 0.3, 0.1),
        ],
        vec![shapes::torus(6, 3, 1.0, 0.3), shapes::torus(4, 3, 0.3, 0.1)],
    ];
    (scene, levels)
}

fn indices(v: &Value) -> Vec<usize> {
    v.as_array()
        .map(|a| {
            a.iter()
                .filter_map(|x| x.as_u64())
                .map(|x| x as usize)
                .collect()
        })
        .unwrap_or_default()
}

/// The level-0 meshes a viewer shows at level `k`: nodes with `MSFT_lod`
/// swapped for their `k`-th level with their whole subtree.
fn shown_at_level(j: &Value, k: usize) -> Vec<usize> {
    fn walk(j: &Value, n: usize, k: usize, out: &mut Vec<usize>) {
        let node = &j["nodes"][n];
        let ids = indices(&node["extensions"]["MSFT_lod"]["ids"]);
        let shown = if k == 0 {
            n
        } else {
            *ids.get(k - 1).unwrap_or(&n)
        };
        if let Some(m) = node["mesh"].as_u64() {
            assert!(
                j["nodes"][shown]["mesh"].is_u64(),
                "level {k} of node {n} shows nothing"
            );
            out.push(m as usize);
        }
        for c in indices(&j["nodes"][shown]["children"]) {
            walk(j, c, k, out);
        }
    }
    let mut out = Vec::new();
    for r in indices(&j["scenes"][0]["nodes"]) {
        walk(j, r, k, &mut out);
    }
    out.sort_unstable();
    out
}

#[test]
fn a_mesh_node_with_children_hands_its_mesh_to_a_leaf_so_every_level_keeps_them() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, levels) = body_with_wheel();
    let path = dir.path().join("car.gltf");
    let coverage = vec![vec![0.4, 0.1, 0.0], vec![0.3, 0.05, 0.0]];
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
    let nodes = j["nodes"].as_array().unwrap();
    // The body keeps its name, transform and children, and gains a leaf
    // holding its mesh, its levels and its hints.
    let body = &nodes[0];
    assert_eq!(body["name"], "body");
    assert!(body.get("mesh").is_none() && body["extensions"]["MSFT_lod"].is_null());
    let children = indices(&body["children"]);
    assert_eq!(children.len(), 2);
    let leaf = &nodes[children[1]];
    assert_eq!(leaf["name"], "body_lod0");
    assert_eq!(leaf["mesh"], 0);
    assert!(leaf.get("matrix").is_none() && leaf.get("children").is_none());
    assert_eq!(
        leaf["extras"]["MSFT_screencoverage"],
        serde_json::json!([0.4, 0.1, 0.0])
    );
    for id in indices(&leaf["extensions"]["MSFT_lod"]["ids"]) {
        assert!(nodes[id]["name"].as_str().unwrap().starts_with("body_lod"));
        assert!(nodes[id].get("matrix").is_none());
    }
    // Every node with MSFT_lod is a leaf, and every level shows both meshes.
    for n in nodes {
        if n["extensions"]["MSFT_lod"].is_object() {
            assert!(indices(&n["children"]).is_empty(), "{n}");
        }
    }
    for k in 0..=2 {
        assert_eq!(shown_at_level(&j, k), vec![0, 1], "level {k}");
    }
    // Read back, the scene still shows the full model where it was.
    let doc = wildlod_io::read(&path).unwrap();
    assert_eq!(doc.scene.meshes[0].triangle_count(), 24 * 12 * 2);
}

#[test]
fn levels_are_laid_out_coarsest_first_and_the_generator_is_wildlod() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, levels) = body_with_wheel();
    let path = dir.path().join("car.glb");
    wildlod_io::write_lods(
        &Document::from_scene(scene),
        &LodLevels {
            levels: &levels,
            screen_coverage: &[],
        },
        &path,
        &WriteOptions::default(),
    )
    .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let j: Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    assert_eq!(
        j["asset"]["generator"],
        format!("wildlod {}", env!("CARGO_PKG_VERSION")).as_str()
    );
    // Level of every mesh: 0 on the nodes in the scene, k on their k-th
    // MSFT_lod node.
    let mut level_of = std::collections::HashMap::new();
    for n in j["nodes"].as_array().unwrap() {
        if let Some(m) = n["mesh"].as_u64() {
            level_of.entry(m).or_insert(0usize);
        }
        for (k, id) in indices(&n["extensions"]["MSFT_lod"]["ids"])
            .into_iter()
            .enumerate()
        {
            level_of.insert(j["nodes"][id]["mesh"].as_u64().unwrap(), k + 1);
        }
    }
    // (byte offset, level) of every view, in buffer order.
    let mut views = Vec::new();
    for (m, level) in &level_of {
        for p in j["meshes"][*m as usize]["primitives"].as_array().unwrap() {
            let mut acc: Vec<u64> = p["attributes"]
                .as_object()
                .unwrap()
                .values()
                .filter_map(Value::as_u64)
                .collect();
            acc.push(p["indices"].as_u64().unwrap());
            for a in acc {
                let v = j["accessors"][a as usize]["bufferView"].as_u64().unwrap() as usize;
                views.push((
                    j["bufferViews"][v]["byteOffset"].as_u64().unwrap_or(0),
                    *level,
                ));
            }
        }
    }
    assert_eq!(views.len(), j["bufferViews"].as_array().unwrap().len());
    views.sort_unstable();
    let order: Vec<usize> = views.iter().map(|v| v.1).collect();
    assert!(order.windows(2).all(|w| w[0] >= w[1]), "{order:?}");
    assert_eq!((order[0], order[order.len() - 1]), (2, 0));
}
