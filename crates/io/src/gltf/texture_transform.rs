//! `KHR_texture_transform` applied to the UVs when a file is read.
//!
//! The extension puts an affine map (offset, rotation, scale) between a
//! primitive's UVs and the texture: gltfpack stores every UV set quantized
//! and undoes the quantization this way, and tiled materials use it to
//! repeat a texture. The mesh model has no such map, so without this step
//! every reader of UVs (the keep-or-re-bake decision, the texel density,
//! the bake's texture lookups, an OBJ written from the scene) would read
//! the texture at the wrong place. Instead the map is applied to the UV
//! values the material's faces use, and removed from the document:
//!
//! - per material and UV set, the first of its five core texture slots
//!   (base color, metallic-roughness, normal, occlusion, emissive) that
//!   reads the set gives the map the set is rewritten with, for the faces
//!   of that material only (values shared with faces of other materials
//!   are copied first);
//! - a slot reading the same set through another map, or a set another
//!   texture of the material reads too (an extension's texture this step
//!   does not rewrite), gets a new UV set holding its own map's values;
//! - the written document keeps every texture reference consistent: the
//!   slot's `texCoord` points at the set that now holds its UVs, and the
//!   extension is dropped from it (and from `extensionsUsed` and
//!   `extensionsRequired` once no texture uses it).
//!
//! The map follows the extension's reference implementations (CesiumGltf,
//! three.js): scale first, then rotation, `u' = cos·sₓu + sin·s_yv + oₓ`,
//! `v' = −sin·sₓu + cos·s_yv + o_y`.

use std::collections::HashMap;

use serde_json::Value;
use wildlod_mesh::{Attribute, ComponentFormat, Material, Scene, Semantic, TextureRef, ABSENT};

/// The extension's name.
pub(crate) const TEXTURE_TRANSFORM: &str = "KHR_texture_transform";

/// The field of [`Material`] a texture slot fills.
type Field = fn(&mut Material) -> &mut Option<TextureRef>;

/// The core texture slots of a material: the JSON path of the texture
/// info and the field of [`Material`] it fills.
const SLOTS: [(&[&str], Field); 5] = [
    (&["pbrMetallicRoughness", "baseColorTexture"], |m| {
        &mut m.base_color_texture
    }),
    (&["pbrMetallicRoughness", "metallicRoughnessTexture"], |m| {
        &mut m.metallic_roughness_texture
    }),
    (&["normalTexture"], |m| &mut m.normal_texture),
    (&["occlusionTexture"], |m| &mut m.occlusion_texture),
    (&["emissiveTexture"], |m| &mut m.emissive_texture),
];

/// `[a, b, c, d, e, f]`: `u' = a·u + b·v + c`, `v' = d·u + e·v + f`.
type Affine = [f64; 6];

const IDENTITY: Affine = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// The map of a `KHR_texture_transform` object, and its `texCoord`
/// override.
fn affine(ext: &Value) -> (Affine, Option<u32>) {
    let pair = |key: &str, default: [f64; 2]| {
        ext.get(key)
            .and_then(Value::as_array)
            .and_then(|a| Some([a.first()?.as_f64()?, a.get(1)?.as_f64()?]))
            .filter(|p| p.iter().all(|x| x.is_finite()))
            .unwrap_or(default)
    };
    let [ox, oy] = pair("offset", [0.0, 0.0]);
    let [sx, sy] = pair("scale", [1.0, 1.0]);
    let r = ext
        .get("rotation")
        .and_then(Value::as_f64)
        .filter(|r| r.is_finite())
        .unwrap_or(0.0);
    let (s, c) = r.sin_cos();
    let set = ext
        .get("texCoord")
        .and_then(Value::as_u64)
        .and_then(|t| u32::try_from(t).ok());
    ([c * sx, s * sy, ox, -s * sx, c * sy, oy], set)
}

fn apply(a: &Affine, uv: [f32; 2]) -> [f32; 2] {
    let (u, v) = (f64::from(uv[0]), f64::from(uv[1]));
    [
        (a[0] * u + a[1] * v + a[2]) as f32,
        (a[3] * u + a[4] * v + a[5]) as f32,
    ]
}

/// The `texCoord` of every texture info in `v` (any object with an
/// `index`), except those at the `skip` paths of the material.
fn other_sets(v: &Value, path: &mut Vec<String>, skip: &[Vec<String>], out: &mut Vec<u32>) {
    match v {
        Value::Object(o) => {
            if o.get("index").is_some_and(Value::is_u64) && !skip.contains(path) {
                let set = o.get("texCoord").and_then(Value::as_u64).unwrap_or(0);
                out.push(u32::try_from(set).unwrap_or(u32::MAX));
            }
            for (k, x) in o {
                path.push(k.clone());
                other_sets(x, path, skip, out);
                path.pop();
            }
        }
        Value::Array(a) => a.iter().for_each(|x| other_sets(x, path, skip, out)),
        _ => {}
    }
}

/// What one material's faces need: the map its UV set `k` is rewritten
/// with in place, and the new sets `(new, source, map)` to add.
#[derive(Default)]
struct MaterialPlan {
    in_place: Vec<(u32, Affine)>,
    added: Vec<(u32, u32, Affine)>,
}

/// Applies every core slot's `KHR_texture_transform` to the UVs of
/// `scene` (read from `json`), updates the materials' UV sets, and strips
/// the applied transforms from `json`. Returns how many texture
/// references had one.
pub(crate) fn apply_texture_transforms(scene: &mut Scene, json: &mut Value) -> usize {
    let Some(materials) = json.get_mut("materials").and_then(Value::as_array_mut) else {
        return 0;
    };
    // The first UV set no mesh and no material uses: new sets go there.
    let mut next_set = scene
        .meshes
        .iter()
        .flat_map(|m| &m.attributes)
        .filter_map(|a| match a.semantic {
            Semantic::TexCoord(n) => Some(n.saturating_add(1)),
            _ => None,
        })
        .chain(scene.materials.iter_mut().flat_map(|m| {
            SLOTS
                .iter()
                .filter_map(|(_, f)| f(m).as_ref().map(|r| r.tex_coord.saturating_add(1)))
                .collect::<Vec<_>>()
        }))
        .max()
        .unwrap_or(0);
    let mut plans: Vec<MaterialPlan> = Vec::new();
    let mut applied = 0;
    for (mi, mj) in materials.iter_mut().enumerate() {
        let mut plan = MaterialPlan::default();
        let Some(material) = scene.materials.get_mut(mi) else {
            plans.push(plan);
            continue;
        };
        let skip: Vec<Vec<String>> = SLOTS
            .iter()
            .map(|(p, _)| p.iter().map(|s| s.to_string()).collect())
            .collect();
        let mut foreign = Vec::new();
        other_sets(mj, &mut Vec::new(), &skip, &mut foreign);
        // Sets already rewritten in place (with their map), and the new
        // sets made for (source, map).
        let mut kept: Vec<(u32, Affine)> = Vec::new();
        for (path, field) in SLOTS {
            let mut info = Some(&mut *mj);
            for key in path {
                info = info.and_then(|v| v.get_mut(*key));
            }
            let Some(info) = info.and_then(Value::as_object_mut) else {
                continue;
            };
            let Some(r) = field(material).as_mut() else {
                continue;
            };
            let ext = info
                .get_mut("extensions")
                .and_then(Value::as_object_mut)
                .and_then(|e| e.remove(TEXTURE_TRANSFORM));
            if ext.is_some()
                && info
                    .get("extensions")
                    .and_then(Value::as_object)
                    .is_some_and(|e| e.is_empty())
            {
                info.remove("extensions");
            }
            applied += usize::from(ext.is_some());
            let (map, set) = ext.as_ref().map_or((IDENTITY, None), affine);
            let source = set.unwrap_or(r.tex_coord);
            let target = match kept.iter().find(|k| k.0 == source) {
                // The set holds this map's values already.
                Some(&(_, m)) if m == map => source,
                // First reader: the set takes its map, unless a texture
                // this step leaves alone reads the set too.
                None if map == IDENTITY || !foreign.contains(&source) => {
                    kept.push((source, map));
                    if map != IDENTITY {
                        plan.in_place.push((source, map));
                    }
                    source
                }
                _ => match plan.added.iter().find(|a| a.1 == source && a.2 == map) {
                    Some(a) => a.0,
                    // A hostile `texCoord` of 2³² − 1 leaves no set to
                    // add: the texture reads its own set untransformed.
                    None if next_set == u32::MAX => source,
                    None => {
                        plan.added.push((next_set, source, map));
                        next_set += 1;
                        next_set - 1
                    }
                },
            };
            if target == r.tex_coord && ext.is_none() {
                continue;
            }
            r.tex_coord = target;
            if target == 0 {
                info.remove("texCoord");
            } else {
                info.insert("texCoord".into(), target.into());
            }
        }
        plans.push(plan);
    }
    if applied == 0 {
        return 0;
    }
    for mesh in &mut scene.meshes {
        rewrite_mesh(mesh, &plans);
    }
    let still_used = materials.iter().any(|m| mentions(m, TEXTURE_TRANSFORM));
    if !still_used {
        for key in ["extensionsUsed", "extensionsRequired"] {
            if let Some(list) = json.get_mut(key).and_then(Value::as_array_mut) {
                list.retain(|e| e.as_str() != Some(TEXTURE_TRANSFORM));
            }
        }
    }
    applied
}

/// Whether any object key in `v` is `name`.
fn mentions(v: &Value, name: &str) -> bool {
    match v {
        Value::Object(o) => o.iter().any(|(k, x)| k == name || mentions(x, name)),
        Value::Array(a) => a.iter().any(|x| mentions(x, name)),
        _ => false,
    }
}

/// Rewrites and adds the UV sets of one mesh's faces as their materials'
/// plans say.
fn rewrite_mesh(mesh: &mut wildlod_mesh::Mesh, plans: &[MaterialPlan]) {
    let face_plan = |f: usize| -> Option<&MaterialPlan> {
        let part = mesh.parts.get(*mesh.face_parts.get(f)? as usize)?;
        plans.get(part.material? as usize)
    };
    // Corner ranges per face, with the face's plan.
    let faces: Vec<(std::ops::Range<usize>, Option<&MaterialPlan>)> = (0..mesh.faces.len())
        .map(|f| {
            let start = mesh.faces.offsets[f] as usize;
            let end = mesh.faces.offsets[f + 1] as usize;
            (start..end, face_plan(f))
        })
        .collect();
    let sets: Vec<u32> = mesh
        .attributes
        .iter()
        .filter_map(|a| match a.semantic {
            Semantic::TexCoord(n) => Some(n),
            _ => None,
        })
        .collect();
    let mut new_attributes = Vec::new();
    for set in sets {
        let Some(at) = mesh
            .attributes
            .iter()
            .position(|a| a.semantic == Semantic::TexCoord(set))
        else {
            continue;
        };
        let source = &mesh.attributes[at];
        if source.components < 2 {
            continue;
        }
        // Added sets read the source before it is rewritten in place.
        let mut added: Vec<(u32, Affine)> = Vec::new();
        for (_, plan) in &faces {
            for a in plan.iter().flat_map(|p| &p.added) {
                if a.1 == set && !added.iter().any(|x| x.0 == a.0) {
                    added.push((a.0, a.2));
                }
            }
        }
        for (new, map) in added {
            let corners: Vec<usize> = faces
                .iter()
                .filter(|(_, p)| p.is_some_and(|p| p.added.iter().any(|a| a.0 == new)))
                .flat_map(|(r, _)| r.clone())
                .collect();
            let a = mapped(
                source,
                corners.into_iter(),
                |_| Some(map),
                Semantic::TexCoord(new),
            );
            if !a.values.is_empty() {
                new_attributes.push(a);
            }
        }
        let touched = faces
            .iter()
            .any(|(_, p)| p.is_some_and(|p| p.in_place.iter().any(|x| x.0 == set)));
        if touched {
            let map_of = |c: usize| -> Option<Affine> {
                let f = faces.partition_point(|(r, _)| r.end <= c);
                let plan = faces.get(f)?.1?;
                plan.in_place.iter().find(|x| x.0 == set).map(|x| x.1)
            };
            let all = 0..source.indices.len();
            let rewritten = mapped(source, all, map_of, Semantic::TexCoord(set));
            mesh.attributes[at] = rewritten;
        }
    }
    mesh.attributes.extend(new_attributes);
}

/// A two-component (at least) UV stream holding `source`'s values at
/// `corners`, each through `map(corner)` (`None`: unchanged), and nothing
/// elsewhere; equal (value, map) pairs share one value.
fn mapped(
    source: &Attribute,
    corners: impl Iterator<Item = usize>,
    map: impl Fn(usize) -> Option<Affine>,
    semantic: Semantic,
) -> Attribute {
    let m = source.components as usize;
    let mut out = Attribute {
        semantic,
        components: source.components,
        values: Vec::new(),
        indices: vec![ABSENT; source.indices.len()],
        format: ComponentFormat::F32,
    };
    let mut seen: HashMap<(u32, Option<[u64; 6]>), u32> = HashMap::new();
    for c in corners {
        let i = source.indices[c];
        if i == ABSENT {
            continue;
        }
        let a = map(c);
        let key = (i, a.map(|a| a.map(f64::to_bits)));
        let next = (out.values.len() / m) as u32;
        let slot = *seen.entry(key).or_insert_with(|| {
            let v = &source.values[i as usize * m..i as usize * m + m];
            let mut value = v.to_vec();
            if let Some(a) = a {
                let [u, w] = apply(&a, [v[0], v[1]]);
                value[0] = u;
                value[1] = w;
            }
            out.values.extend_from_slice(&value);
            next
        });
        out.indices[c] = slot;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_scale_and_rotation_compose_as_the_reference_viewers_do() {
        // Scale (2, 3), then a quarter turn, then the offset (0.5, 0.25):
        // (0.1, 0.2) → scaled (0.2, 0.6) → turned (0.6, −0.2) → (1.1, 0.05).
        let (a, set) = affine(&serde_json::json!({
            "offset": [0.5, 0.25], "scale": [2.0, 3.0],
            "rotation": std::f64::consts::FRAC_PI_2, "texCoord": 2
        }));
        let [u, v] = apply(&a, [0.1, 0.2]);
        assert!((u - 1.1).abs() < 1e-6 && (v - 0.05).abs() < 1e-6, "{u} {v}");
        assert_eq!(set, Some(2));
        // Absent or malformed members take their defaults.
        let (a, set) = affine(&serde_json::json!({"scale": "big", "offset": [1.0]}));
        assert_eq!((a, set), (IDENTITY, None));
    }
}
