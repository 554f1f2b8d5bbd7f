//! glTF JSON built from the [`Scene`] itself: for documents that did not
//! come from glTF, and for materials and textures that changed since
//! reading.

use serde_json::{json, Map, Value};
use wildlod_mesh::{AlphaMode, ImageSource, Material, Sampler, Scene, TextureRef, Wrap, IDENTITY};

use super::accessor::Component;
use super::bin::Bin;
use super::images::ImageWriter;
use super::trs::decompose;
use crate::ErrorKind;

/// Nodes; `mesh_map` gives the written index of every scene mesh (`None`
/// when it was dropped for having no triangles). Meshes no node reaches
/// get a root node of their own so they are displayed. Nodes marked in
/// `animated` are written as translation, rotation and scale (glTF forbids
/// `matrix` on an animation's target), with a warning where their matrix
/// has no such form.
pub(crate) fn nodes(
    scene: &Scene,
    mesh_map: &[Option<usize>],
    animated: &[bool],
    warnings: &mut Vec<String>,
) -> (Vec<Value>, Vec<u32>) {
    let mut out: Vec<Value> = scene
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let mut o = Map::new();
            if !n.name.is_empty() {
                o.insert("name".into(), json!(n.name));
            }
            if animated.get(i).copied().unwrap_or(false) {
                let trs = decompose(&n.matrix);
                if !trs.exact {
                    warnings.push(format!(
                        "node {i} is animated but its matrix is not a translation, rotation and \
                         scale (it has shear); written as the nearest such transform"
                    ));
                }
                if trs.translation != [0.0; 3] {
                    o.insert("translation".into(), json!(trs.translation));
                }
                if trs.rotation != [0.0, 0.0, 0.0, 1.0] {
                    o.insert("rotation".into(), json!(trs.rotation));
                }
                if trs.scale != [1.0; 3] {
                    o.insert("scale".into(), json!(trs.scale));
                }
            } else if n.matrix != IDENTITY {
                o.insert("matrix".into(), json!(n.matrix));
            }
            if let Some(m) = n
                .mesh
                .and_then(|m| mesh_map.get(m as usize).copied().flatten())
            {
                o.insert("mesh".into(), json!(m));
                if let Some(s) = n.skin {
                    o.insert("skin".into(), json!(s));
                }
            }
            if !n.children.is_empty() {
                o.insert("children".into(), json!(n.children));
            }
            Value::Object(o)
        })
        .collect();
    let mut roots = scene.roots.clone();
    let reached = reached_meshes(scene);
    for (m, written) in mesh_map.iter().enumerate() {
        if let (Some(w), false) = (written, reached.get(m).copied().unwrap_or(false)) {
            roots.push(out.len() as u32);
            let name = scene.meshes.get(m).map(|x| x.name.as_str()).unwrap_or("");
            let mut o = Map::new();
            if !name.is_empty() {
                o.insert("name".into(), json!(name));
            }
            o.insert("mesh".into(), json!(w));
            out.push(Value::Object(o));
        }
    }
    (out, roots)
}

/// Which meshes some node reachable from the roots instances.
fn reached_meshes(scene: &Scene) -> Vec<bool> {
    let mut reached = vec![false; scene.meshes.len()];
    let mut seen = vec![false; scene.nodes.len()];
    let mut stack = scene.roots.clone();
    while let Some(n) = stack.pop() {
        let Some(s) = seen.get_mut(n as usize) else {
            continue;
        };
        if *s {
            continue;
        }
        *s = true;
        let node = &scene.nodes[n as usize];
        if let Some(r) = node.mesh.and_then(|m| reached.get_mut(m as usize)) {
            *r = true;
        }
        stack.extend_from_slice(&node.children);
    }
    reached
}

/// Skins, with inverse bind matrices written to `bin`.
pub(crate) fn skins(scene: &Scene, bin: &mut Bin) -> Vec<Value> {
    scene
        .skins
        .iter()
        .map(|s| {
            let mut o = Map::new();
            if !s.name.is_empty() {
                o.insert("name".into(), json!(s.name));
            }
            o.insert("joints".into(), json!(s.joints));
            if let Some(k) = s.skeleton {
                o.insert("skeleton".into(), json!(k));
            }
            if !s.inverse_bind_matrices.is_empty() {
                let bytes: Vec<u8> = s
                    .inverse_bind_matrices
                    .iter()
                    .flatten()
                    .flat_map(|x| x.to_le_bytes())
                    .collect();
                let v = bin.view(&bytes, None, None);
                let a = bin.accessor(
                    v,
                    Component::F32,
                    false,
                    s.inverse_bind_matrices.len(),
                    "MAT4",
                    None,
                );
                o.insert("inverseBindMatrices".into(), json!(a));
            }
            Value::Object(o)
        })
        .collect()
}

fn texture_info(t: &TextureRef) -> Value {
    let mut o = Map::new();
    o.insert("index".into(), json!(t.texture));
    if t.tex_coord != 0 {
        o.insert("texCoord".into(), json!(t.tex_coord));
    }
    Value::Object(o)
}

/// Materials, default values omitted.
pub(crate) fn materials(materials: &[Material]) -> Vec<Value> {
    let d = Material::default();
    materials
        .iter()
        .map(|m| {
            let mut o = Map::new();
            if !m.name.is_empty() {
                o.insert("name".into(), json!(m.name));
            }
            let mut pbr = Map::new();
            if m.base_color != d.base_color {
                pbr.insert("baseColorFactor".into(), json!(m.base_color));
            }
            if let Some(t) = &m.base_color_texture {
                pbr.insert("baseColorTexture".into(), texture_info(t));
            }
            if m.metallic != d.metallic {
                pbr.insert("metallicFactor".into(), json!(m.metallic));
            }
            if m.roughness != d.roughness {
                pbr.insert("roughnessFactor".into(), json!(m.roughness));
            }
            if let Some(t) = &m.metallic_roughness_texture {
                pbr.insert("metallicRoughnessTexture".into(), texture_info(t));
            }
            o.insert("pbrMetallicRoughness".into(), Value::Object(pbr));
            for (key, t) in [
                ("normalTexture", &m.normal_texture),
                ("occlusionTexture", &m.occlusion_texture),
                ("emissiveTexture", &m.emissive_texture),
            ] {
                if let Some(t) = t {
                    o.insert(key.into(), texture_info(t));
                }
            }
            if m.emissive != d.emissive {
                o.insert("emissiveFactor".into(), json!(m.emissive));
            }
            match m.alpha_mode {
                AlphaMode::Opaque => {}
                AlphaMode::Blend => {
                    o.insert("alphaMode".into(), json!("BLEND"));
                }
                AlphaMode::Mask => {
                    o.insert("alphaMode".into(), json!("MASK"));
                    if m.alpha_cutoff != 0.5 {
                        o.insert("alphaCutoff".into(), json!(m.alpha_cutoff));
                    }
                }
            }
            if m.double_sided {
                o.insert("doubleSided".into(), json!(true));
            }
            Value::Object(o)
        })
        .collect()
}

/// Textures, their images (one per distinct source) and their samplers
/// (one per distinct non-default sampler; the default, repeat, needs none).
pub(crate) type TexturesJson = (Vec<Value>, Vec<Value>, Vec<Value>);

/// Textures, images and samplers of the scene; see [`TexturesJson`].
pub(crate) fn textures(
    scene: &Scene,
    bin: &mut Bin,
    images: &mut ImageWriter,
) -> Result<TexturesJson, ErrorKind> {
    let mut sources: Vec<&ImageSource> = Vec::new();
    let mut image_json = Vec::new();
    let mut textures = Vec::new();
    let mut samplers: Vec<Sampler> = Vec::new();
    for (ti, t) in scene.textures.iter().enumerate() {
        let ii = match sources.iter().position(|s| *s == &t.source) {
            Some(i) => i,
            None => {
                let mut placed = match &t.source {
                    ImageSource::Embedded { bytes, mime_type } if !t.name.is_empty() => {
                        images.named(bin, &t.name, bytes, mime_type)
                    }
                    ImageSource::Embedded { bytes, mime_type } => {
                        images.embedded(bin, bytes, mime_type)
                    }
                    ImageSource::Path(p) => {
                        images.file(bin, &format!("texture {ti}"), p, None, None)?
                    }
                };
                // The image is named after the texture (an OBJ's texture is
                // named after its file): without it viewers list images
                // as numbers.
                if !t.name.is_empty() {
                    placed.insert("name".into(), json!(t.name));
                }
                sources.push(&t.source);
                image_json.push(Value::Object(placed));
                sources.len() - 1
            }
        };
        let mut o = Map::new();
        if !t.name.is_empty() {
            o.insert("name".into(), json!(t.name));
        }
        o.insert("source".into(), json!(ii));
        if t.sampler != Sampler::default() {
            let si = match samplers.iter().position(|s| *s == t.sampler) {
                Some(i) => i,
                None => {
                    samplers.push(t.sampler);
                    samplers.len() - 1
                }
            };
            o.insert("sampler".into(), json!(si));
        }
        textures.push(Value::Object(o));
    }
    // glTF's enums: 33071 clamp to edge, 33648 mirrored repeat, 10497 repeat.
    let code = |w: Wrap| match w {
        Wrap::ClampToEdge => 33071,
        Wrap::MirroredRepeat => 33648,
        Wrap::Repeat => 10497,
    };
    let sampler_json = samplers
        .iter()
        .map(|s| json!({"wrapS": code(s.wrap_u), "wrapT": code(s.wrap_v)}))
        .collect();
    Ok((textures, image_json, sampler_json))
}
