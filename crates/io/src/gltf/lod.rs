//! Levels of detail in one glTF file, as the `MSFT_lod` vendor extension
//! describes them for nodes: every node showing a mesh (the highest level)
//! lists in `extensions.MSFT_lod.ids` one extra node per lower level, each
//! with the same transform (and skin) and that level's mesh; the extra nodes
//! are in no scene, so a viewer without the extension shows the highest
//! level only. `extras.MSFT_screencoverage` on the base node holds one
//! threshold per level plus the one below which nothing is drawn.
//!
//! A viewer swaps a node carrying `MSFT_lod` for a lower level *with its
//! whole subtree*. So a node that shows a mesh and also has children (the
//! truck's body, parent of its wheels) does not carry the extension: its
//! mesh moves onto a new leaf child (identity transform, named
//! `NAME_lod0`), which carries it, and the children stay at every level.

use std::collections::HashMap;

use serde_json::{json, Map, Value};

use super::bin::{Bin, Section};
use super::encode::{encode_mesh, EncodeOptions};
use crate::{ErrorKind, LodLevels};

/// The extension's name.
pub(crate) const MSFT_LOD: &str = "MSFT_lod";

fn index(v: Option<&Value>) -> Option<usize> {
    v.and_then(Value::as_u64)
        .and_then(|i| usize::try_from(i).ok())
}

/// Morph targets of the primitives of a mesh's JSON (their largest count).
fn target_count(mesh: &Value) -> usize {
    mesh.get("primitives")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .map(|p| {
            p.get("targets")
                .and_then(Value::as_array)
                .map_or(0, Vec::len)
        })
        .max()
        .unwrap_or(0)
}

/// Checks that `lods` fits a scene of `meshes` meshes.
fn check_shape(lods: &LodLevels, meshes: usize) -> Result<(), ErrorKind> {
    for (l, level) in lods.levels.iter().enumerate() {
        if level.len() != meshes {
            return Err(ErrorKind::Unsupported(format!(
                "level of detail {} has {} meshes, but the document has {meshes}",
                l + 1,
                level.len()
            )));
        }
    }
    if !lods.screen_coverage.is_empty() {
        if lods.screen_coverage.len() != meshes {
            return Err(ErrorKind::Unsupported(format!(
                "screen coverage is given for {} meshes, but the document has {meshes}",
                lods.screen_coverage.len()
            )));
        }
        let want = lods.levels.len() + 1;
        if let Some((m, c)) = lods
            .screen_coverage
            .iter()
            .enumerate()
            .find(|(_, c)| c.len() != want || c.iter().any(|x| !x.is_finite()))
        {
            return Err(ErrorKind::Unsupported(format!(
                "mesh {m} has {} finite screen coverage values, but {want} levels need {want}",
                c.iter().filter(|x| x.is_finite()).count()
            )));
        }
    }
    Ok(())
}

/// Appends the lower levels' meshes and nodes to a written document's JSON
/// (`mesh_map`: written index of every scene mesh) and returns whether an
/// encoding needed `KHR_mesh_quantization`. A level whose mesh has no face
/// left reuses the level above it, so every node has the same number of
/// levels. `extensionsUsed` is filled later from the extensions present.
pub(crate) fn add_levels(
    json: &mut Value,
    lods: &LodLevels,
    mesh_map: &[Option<usize>],
    bin: &mut Bin,
    opts: &EncodeOptions,
    warnings: &mut Vec<String>,
) -> Result<bool, ErrorKind> {
    check_shape(lods, mesh_map.len())?;
    let Some(out) = json.as_object_mut() else {
        return Ok(false);
    };
    let mut meshes: Vec<Value> = out
        .get("meshes")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    let mut used_quantization = false;
    // written[l][m]: the JSON mesh showing scene mesh m at level l + 1.
    let mut written: Vec<Vec<Option<usize>>> = Vec::with_capacity(lods.levels.len());
    let mut above: Vec<Option<usize>> = mesh_map.to_vec();
    for (l, level) in lods.levels.iter().enumerate() {
        let mut this = above.clone();
        bin.section = Section::Level(l + 1);
        for (mi, mesh) in level.iter().enumerate() {
            let Some(base) = mesh_map[mi] else {
                // No node shows the highest level: nothing to attach to.
                continue;
            };
            mesh.validate().map_err(ErrorKind::Invalid)?;
            let enc = encode_mesh(mesh, mi, bin, opts, warnings)?;
            used_quantization |= enc.used_quantization;
            if enc.primitives.is_empty() {
                warnings.push(format!(
                    "mesh {mi} has no faces at level of detail {}; the level above stands in for it",
                    l + 1
                ));
                continue;
            }
            let base_json = meshes.get(base).cloned().unwrap_or_else(|| json!({}));
            let mut m = Map::new();
            let name = base_json.get("name").and_then(Value::as_str).unwrap_or("");
            let name = if name.is_empty() {
                format!("mesh{mi}_lod{}", l + 1)
            } else {
                format!("{name}_lod{}", l + 1)
            };
            m.insert("name".into(), json!(name));
            m.insert(
                "primitives".into(),
                Value::Array(enc.primitives.into_iter().map(|(_, p)| p).collect()),
            );
            // Default morph weights carry over while the targets do.
            if let Some(w) = base_json.get("weights") {
                if w.as_array().map(Vec::len) == Some(target_count(&Value::Object(m.clone()))) {
                    m.insert("weights".into(), w.clone());
                }
            }
            this[mi] = Some(meshes.len());
            meshes.push(Value::Object(m));
        }
        written.push(this.clone());
        above = this;
    }
    let scene_of: HashMap<usize, usize> = mesh_map
        .iter()
        .enumerate()
        .filter_map(|(mi, w)| w.map(|w| (w, mi)))
        .collect();
    let mut nodes: Vec<Value> = out
        .get("nodes")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    let base_nodes = nodes.len();
    // (node, the leaf its mesh moved to).
    let mut moved = Vec::new();
    for i in 0..base_nodes {
        let Some(&mi) = index(nodes[i].get("mesh")).and_then(|w| scene_of.get(&w)) else {
            continue;
        };
        if !written.iter().any(|this| this[mi].is_some()) {
            continue;
        }
        let base_name = match nodes[i].get("name").and_then(Value::as_str) {
            Some(n) if !n.is_empty() => n.to_string(),
            _ => format!("node{i}"),
        };
        // The node whose mesh the levels replace.
        let holder = if has_children(&nodes[i]) {
            let leaf = move_mesh_to_leaf(&mut nodes, i, &base_name);
            moved.push((i, leaf));
            leaf
        } else {
            i
        };
        let mut ids = Vec::with_capacity(written.len());
        for (l, this) in written.iter().enumerate() {
            let Some(w) = this[mi] else {
                continue;
            };
            let base = &nodes[holder];
            let mut node = Map::new();
            let name = format!("{base_name}_lod{}", l + 1);
            node.insert("name".into(), json!(name));
            for k in ["matrix", "translation", "rotation", "scale", "skin"] {
                if let Some(v) = base.get(k) {
                    node.insert(k.into(), v.clone());
                }
            }
            let targets = meshes.get(w).map_or(0, target_count);
            if let Some(v) = base.get("weights") {
                if v.as_array().map(Vec::len) == Some(targets) {
                    node.insert("weights".into(), v.clone());
                }
            }
            // Instances drawn by GPU instancing stay instanced at every level.
            if let Some(inst) = base
                .get("extensions")
                .and_then(|e| e.get("EXT_mesh_gpu_instancing"))
            {
                node.insert(
                    "extensions".into(),
                    json!({ "EXT_mesh_gpu_instancing": inst.clone() }),
                );
            }
            node.insert("mesh".into(), json!(w));
            ids.push(nodes.len());
            nodes.push(Value::Object(node));
        }
        if ids.is_empty() {
            continue;
        }
        let Some(base) = nodes[holder].as_object_mut() else {
            continue;
        };
        let ext = base
            .entry("extensions")
            .or_insert_with(|| json!({}))
            .as_object_mut();
        if let Some(ext) = ext {
            ext.insert(MSFT_LOD.into(), json!({ "ids": ids }));
        }
        if let Some(coverage) = lods.screen_coverage.get(mi) {
            match base.entry("extras").or_insert_with(|| json!({})) {
                Value::Object(extras) => {
                    extras.insert("MSFT_screencoverage".into(), json!(coverage));
                }
                _ => warnings.push(format!(
                    "node {i} has extras that are not an object: no MSFT_screencoverage hint is written"
                )),
            }
        }
    }
    retarget_weight_animations(out, &moved);
    out.insert("meshes".into(), Value::Array(meshes));
    out.insert("nodes".into(), Value::Array(nodes));
    Ok(used_quantization)
}

fn has_children(node: &Value) -> bool {
    node.get("children")
        .and_then(Value::as_array)
        .is_some_and(|c| !c.is_empty())
}

/// What moves from a node onto the leaf that takes over its mesh: the
/// mesh and everything that describes how it is drawn.
const MESH_KEYS: [&str; 3] = ["mesh", "skin", "weights"];

/// Moves node `i`'s mesh (with its skin, morph weights and GPU instancing)
/// onto a new child with the identity transform, named `NAME_lod0`, and
/// returns the child's index. The node keeps its transform, children,
/// name, other extensions and extras, so animations and joints that refer
/// to it are unaffected.
fn move_mesh_to_leaf(nodes: &mut Vec<Value>, i: usize, name: &str) -> usize {
    let leaf_index = nodes.len();
    let mut leaf = Map::new();
    leaf.insert("name".into(), json!(format!("{name}_lod0")));
    if let Some(node) = nodes[i].as_object_mut() {
        for k in MESH_KEYS {
            if let Some(v) = node.remove(k) {
                leaf.insert(k.into(), v);
            }
        }
        if let Some(ext) = node.get_mut("extensions").and_then(Value::as_object_mut) {
            if let Some(inst) = ext.remove("EXT_mesh_gpu_instancing") {
                leaf.insert(
                    "extensions".into(),
                    json!({ "EXT_mesh_gpu_instancing": inst }),
                );
            }
            if ext.is_empty() {
                node.remove("extensions");
            }
        }
        match node.get_mut("children").and_then(Value::as_array_mut) {
            Some(children) => children.push(json!(leaf_index)),
            None => {
                node.insert("children".into(), json!([leaf_index]));
            }
        }
    }
    nodes.push(Value::Object(leaf));
    leaf_index
}

/// Points animation channels that drive the morph weights of a node whose
/// mesh moved at the leaf that now holds the mesh (glTF animates weights
/// on the node that instantiates the mesh).
fn retarget_weight_animations(out: &mut Map<String, Value>, moved: &[(usize, usize)]) {
    if moved.is_empty() {
        return;
    }
    let leaf_of: HashMap<usize, usize> = moved.iter().copied().collect();
    let animations = out.get_mut("animations").and_then(Value::as_array_mut);
    for a in animations.into_iter().flatten() {
        let channels = a.get_mut("channels").and_then(Value::as_array_mut);
        for target in channels
            .into_iter()
            .flatten()
            .filter_map(|c| c.get_mut("target"))
        {
            if target.get("path").and_then(Value::as_str) != Some("weights") {
                continue;
            }
            if let Some(&leaf) = index(target.get("node")).and_then(|n| leaf_of.get(&n)) {
                target["node"] = json!(leaf);
            }
        }
    }
}
