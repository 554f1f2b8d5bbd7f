//! Levels of detail in one glTF file, as the `MSFT_lod` vendor extension
//! describes them for nodes: every node showing a mesh (the highest level)
//! lists in `extensions.MSFT_lod.ids` one extra node per lower level, each
//! with the same transform (and skin) and that level's mesh; the extra nodes
//! are in no scene, so a viewer without the extension shows the highest
//! level only. `extras.MSFT_screencoverage` on the base node holds one
//! threshold per level plus the one below which nothing is drawn.

use std::collections::HashMap;

use serde_json::{json, Map, Value};

use super::bin::Bin;
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
    for i in 0..base_nodes {
        let Some(&mi) = index(nodes[i].get("mesh")).and_then(|w| scene_of.get(&w)) else {
            continue;
        };
        let mut ids = Vec::with_capacity(written.len());
        for (l, this) in written.iter().enumerate() {
            let Some(w) = this[mi] else {
                continue;
            };
            let base = &nodes[i];
            let mut node = Map::new();
            let name = base.get("name").and_then(Value::as_str).unwrap_or("");
            let name = if name.is_empty() {
                format!("node{i}_lod{}", l + 1)
            } else {
                format!("{name}_lod{}", l + 1)
            };
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
        let Some(base) = nodes[i].as_object_mut() else {
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
    out.insert("meshes".into(), Value::Array(meshes));
    out.insert("nodes".into(), Value::Array(nodes));
    Ok(used_quantization)
}
