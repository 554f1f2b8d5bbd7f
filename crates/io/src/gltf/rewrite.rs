//! Writing a document read from glTF: its original JSON with the meshes
//! rebuilt from the scene.
//!
//! Pipeline: decide which source accessors to keep → copy their buffer
//! views and themselves into the new buffer → encode the meshes → remap
//! every reference to a moved accessor or mesh (nodes, skins, animations,
//! kept primitives) → materials, textures and images.

use serde_json::{json, Map, Value};
use wildlod_mesh::Scene;

use super::accessor::element_size;
use super::bin::{Bin, Section};
use super::encode::{encode_mesh, EncodeOptions};
use super::images::ImageWriter;
use super::passthrough::{MeshSource, Passthrough};
use super::scene_json;
use crate::ErrorKind;

/// Old index → new index (`None`: not written).
pub(crate) type IndexMap = Vec<Option<usize>>;

fn array<'a>(json: &'a Value, key: &str) -> &'a [Value] {
    json.get(key)
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or(&[])
}

fn index(v: Option<&Value>) -> Option<usize> {
    v.and_then(Value::as_u64)
        .and_then(|i| usize::try_from(i).ok())
}

/// Rewrites an index value through `map`; values not in the map stay.
fn remap(v: &mut Value, map: &[Option<usize>]) {
    if let Some(n) = index(Some(v)).and_then(|i| map.get(i).copied().flatten()) {
        *v = json!(n);
    }
}

/// The JSON of a document read from glTF, with meshes rebuilt; returns it,
/// whether quantized encodings were used, and the written index of every
/// scene mesh (`None`: not written).
pub(crate) fn from_passthrough(
    scene: &Scene,
    p: &Passthrough,
    bin: &mut Bin,
    images: &mut ImageWriter,
    warnings: &mut Vec<String>,
) -> Result<(Value, bool, IndexMap), ErrorKind> {
    let src = &p.json;
    let mut out = src.as_object().cloned().unwrap_or_default();
    let keep = kept_accessors(src, &p.meshes);
    bin.section = Section::Shared;
    let view_map = copy_views(p, &keep, bin)?;
    let acc_map = copy_accessors(src, &keep, &view_map, bin);
    bin.section = Section::Level(0);
    let material_map = (scene.materials != p.read.materials).then(|| material_map(scene, p));
    let meshes = rebuild_meshes(scene, p, &acc_map, material_map.as_deref(), bin, warnings)?;
    out.insert("meshes".into(), Value::Array(meshes.json));
    remap_references(&mut out, src, &meshes.map, &acc_map);
    bin.section = Section::Textures;
    materials_and_images(&mut out, scene, p, bin, images, warnings)?;
    bin.section = Section::Shared;
    Ok((Value::Object(out), meshes.used_quantization, meshes.map))
}

/// Accessor indices a primitive refers to (attributes, indices, morph targets).
fn primitive_accessors(prim: &Value) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::new();
    if let Some(a) = prim.get("attributes").and_then(Value::as_object) {
        out.extend(a.values().filter_map(|v| index(Some(v))));
    }
    out.extend(index(prim.get("indices")));
    for t in array(prim, "targets") {
        if let Some(t) = t.as_object() {
            out.extend(t.values().filter_map(|v| index(Some(v))));
        }
    }
    out
}

/// Rewrites every accessor index in a primitive through `map`.
fn remap_primitive(prim: &mut Value, map: &[Option<usize>]) {
    if let Some(a) = prim.get_mut("attributes").and_then(Value::as_object_mut) {
        a.values_mut().for_each(|v| remap(v, map));
    }
    if let Some(i) = prim.get_mut("indices") {
        remap(i, map);
    }
    for t in prim
        .get_mut("targets")
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
    {
        if let Some(t) = t.as_object_mut() {
            t.values_mut().for_each(|v| remap(v, map));
        }
    }
}

/// The GPU-instancing extension's per-instance accessors of a node.
fn instancing_attributes(node: &mut Value) -> Option<&mut Map<String, Value>> {
    node.get_mut("extensions")?
        .get_mut("EXT_mesh_gpu_instancing")?
        .get_mut("attributes")?
        .as_object_mut()
}

/// Which source accessors are copied. Those only triangle primitives use
/// are rebuilt from the scene; every other one (animations, skins, kept
/// primitives, instancing, even unreferenced ones) is copied, since
/// something we do not interpret may still use it.
fn kept_accessors(src: &Value, meshes: &[MeshSource]) -> Vec<bool> {
    let n = array(src, "accessors").len();
    let mut mesh_use = vec![false; n];
    let mut other_use = vec![false; n];
    for (mi, m) in array(src, "meshes").iter().enumerate() {
        let kept = meshes
            .get(mi)
            .map(|s| s.kept_primitives.as_slice())
            .unwrap_or(&[]);
        for (pi, prim) in array(m, "primitives").iter().enumerate() {
            let flags = if kept.contains(&pi) {
                &mut other_use
            } else {
                &mut mesh_use
            };
            for a in primitive_accessors(prim) {
                if let Some(f) = flags.get_mut(a) {
                    *f = true;
                }
            }
        }
    }
    let mut mark = |v: Option<&Value>| {
        if let Some(f) = index(v).and_then(|a| other_use.get_mut(a)) {
            *f = true;
        }
    };
    for s in array(src, "skins") {
        mark(s.get("inverseBindMatrices"));
    }
    for a in array(src, "animations") {
        for s in array(a, "samplers") {
            mark(s.get("input"));
            mark(s.get("output"));
        }
    }
    for n in array(src, "nodes") {
        let mut n = n.clone();
        if let Some(attrs) = instancing_attributes(&mut n) {
            attrs.values().for_each(|v| mark(Some(v)));
        }
    }
    (0..n).map(|a| other_use[a] || !mesh_use[a]).collect()
}

/// The bytes of source buffer view `v`.
fn source_view(p: &Passthrough, v: usize) -> Option<Vec<u8>> {
    let view = array(&p.json, "bufferViews").get(v)?;
    let b = index(view.get("buffer"))?;
    let start = index(view.get("byteOffset")).unwrap_or(0);
    let len = index(view.get("byteLength"))?;
    p.buffers.get(b)?.get(start, len).map(<[u8]>::to_vec)
}

/// Bytes per component of a JSON `componentType`.
fn component_size(v: Option<&Value>) -> usize {
    match index(v) {
        Some(5120 | 5121) => 1,
        Some(5122 | 5123) => 2,
        _ => 4,
    }
}

/// Per buffer view of `src`: (byteOffset within the view, component size)
/// of every use by a kept accessor (its own data and its sparse parts), or
/// `None` for a view no kept accessor uses.
fn view_uses(src: &Value, keep: &[bool]) -> Vec<Option<Vec<(usize, usize)>>> {
    let mut uses: Vec<Option<Vec<(usize, usize)>>> = vec![None; array(src, "bufferViews").len()];
    let mut need = |v: Option<&Value>, offset: Option<&Value>, size: usize| {
        if let Some(u) = index(v).and_then(|v| uses.get_mut(v)) {
            u.get_or_insert_with(Vec::new)
                .push((index(offset).unwrap_or(0), size));
        }
    };
    for (acc, _) in array(src, "accessors").iter().zip(keep).filter(|(_, &k)| k) {
        let size = component_size(acc.get("componentType"));
        need(acc.get("bufferView"), acc.get("byteOffset"), size);
        if let Some(s) = acc.get("sparse") {
            let (i, v) = (&s["indices"], &s["values"]);
            let isize = component_size(i.get("componentType"));
            need(i.get("bufferView"), i.get("byteOffset"), isize);
            need(v.get("bufferView"), v.get("byteOffset"), size);
        }
    }
    uses
}

/// The buffer views a write may copy from the source, byte for byte: those
/// of copied accessors ([`kept_accessors`]) and of images. Everything else
/// in the source buffers (the triangle primitives' data, usually nearly
/// all of it) is rebuilt from the scene, so the reader need not keep it.
pub(super) fn copied_views(src: &Value, meshes: &[MeshSource]) -> Vec<bool> {
    let mut out: Vec<bool> = view_uses(src, &kept_accessors(src, meshes))
        .iter()
        .map(Option::is_some)
        .collect();
    for img in array(src, "images") {
        if let Some(f) = index(img.get("bufferView")).and_then(|v| out.get_mut(v)) {
            *f = true;
        }
    }
    out
}

/// Copies the buffer views kept accessors use (their own and their sparse
/// parts'), byte for byte. Each view starts where every accessor into it
/// lands on a multiple of its component size: the source's offset modulo 4
/// when that works (it does for any valid file), else the first that does,
/// so a misaligned source does not make a misaligned output.
fn copy_views(p: &Passthrough, keep: &[bool], bin: &mut Bin) -> Result<IndexMap, ErrorKind> {
    let views = array(&p.json, "bufferViews");
    let uses = view_uses(&p.json, keep);
    let mut map = vec![None; views.len()];
    for (v, view) in views.iter().enumerate() {
        let Some(uses) = &uses[v] else {
            continue;
        };
        let bytes = source_view(p, v).ok_or_else(|| {
            ErrorKind::malformed(format!("bufferView {v}"), "lies outside its buffer")
        })?;
        let mut template = view.as_object().cloned().unwrap_or_default();
        let old = index(template.get("byteOffset")).unwrap_or(0) % 4;
        let aligned = |r: usize| uses.iter().all(|&(o, size)| (r + o) % size == 0);
        let residue = [old, 0, 1, 2, 3]
            .into_iter()
            .find(|&r| aligned(r))
            .unwrap_or(old);
        for k in ["buffer", "byteOffset", "byteLength"] {
            template.remove(k);
        }
        map[v] = Some(bin.view_from(&bytes, residue as u64, template));
    }
    Ok(map)
}

/// Copies the kept accessors, pointing them at the copied views.
fn copy_accessors(
    src: &Value,
    keep: &[bool],
    view_map: &[Option<usize>],
    bin: &mut Bin,
) -> IndexMap {
    let accessors = array(src, "accessors");
    let mut map = vec![None; accessors.len()];
    for (a, acc) in accessors.iter().enumerate() {
        if !keep[a] {
            continue;
        }
        let mut acc = acc.clone();
        // JSON null means absent, as serde reads it.
        let has = |acc: &Value, k: &str| acc.get(k).is_some_and(|v| !v.is_null());
        if let Some(v) = acc.get_mut("bufferView").filter(|v| !v.is_null()) {
            remap(v, view_map);
        } else if !has(&acc, "sparse") {
            // All zeros by the specification, but common readers (the gltf
            // crate among them) insist on a buffer view: give it one.
            let size = element_size(
                index(acc.get("componentType")).unwrap_or(0) as u64,
                acc.get("type").and_then(Value::as_str).unwrap_or(""),
            );
            let count = index(acc.get("count")).unwrap_or(0);
            if let (Some(size), Some(o)) = (size, acc.as_object_mut()) {
                let v = bin.view(&vec![0; size.saturating_mul(count)], None, None);
                o.insert("bufferView".into(), json!(v));
            }
        }
        if let Some(s) = acc.get_mut("sparse") {
            for part in ["indices", "values"] {
                if let Some(v) = s.get_mut(part).and_then(|x| x.get_mut("bufferView")) {
                    remap(v, view_map);
                }
            }
        }
        bin.accessors.push(acc);
        map[a] = Some(bin.accessors.len() - 1);
    }
    map
}

/// The extension names used by any of `materials`, sorted, each once.
fn extension_names(materials: &[Value]) -> Vec<String> {
    let mut names: Vec<String> = materials
        .iter()
        .filter_map(|m| m.get("extensions").and_then(Value::as_object))
        .flat_map(|e| e.keys().cloned())
        .collect();
    names.sort();
    names.dedup();
    names
}

/// Removes from material `m`'s extensions every texture reference (an
/// object with an `index`) that no longer names the texture it named in
/// the source, noting `extension.key` in `dropped`.
fn drop_stale_extension_textures(
    m: &mut Value,
    scene: &Scene,
    p: &Passthrough,
    dropped: &mut Vec<String>,
) {
    let Some(exts) = m.get_mut("extensions").and_then(Value::as_object_mut) else {
        return;
    };
    for (name, ext) in exts.iter_mut() {
        let Some(ext) = ext.as_object_mut() else {
            continue;
        };
        let stale: Vec<String> = ext
            .iter()
            .filter_map(|(key, v)| {
                let i = index(v.get("index"))?;
                let same = matches!(
                    (scene.textures.get(i), p.read.textures.get(i)),
                    (Some(a), Some(b)) if a == b
                );
                (!same).then(|| key.clone())
            })
            .collect();
        for key in stale {
            ext.remove(&key);
            dropped.push(format!("{name}.{key}"));
        }
    }
}

/// Removes Draco data from an object's extensions: the compressed buffer
/// views it points to are not written, the uncompressed data is.
fn strip_draco(obj: &mut Map<String, Value>) {
    if let Some(ext) = obj.get_mut("extensions").and_then(Value::as_object_mut) {
        ext.remove("KHR_draco_mesh_compression");
        if ext.is_empty() {
            obj.remove("extensions");
        }
    }
}

/// The written meshes.
struct Meshes {
    json: Vec<Value>,
    /// Scene mesh → written mesh (`None`: no primitive left).
    map: IndexMap,
    used_quantization: bool,
}

/// Encodes every scene mesh into the source mesh's JSON (name, weights,
/// extras, extensions kept), giving each primitive the extras and
/// extensions of the source primitive its part came from, and appending
/// the primitives the model could not hold.
fn rebuild_meshes(
    scene: &Scene,
    p: &Passthrough,
    acc_map: &[Option<usize>],
    material_map: Option<&[Option<usize>]>,
    bin: &mut Bin,
    warnings: &mut Vec<String>,
) -> Result<Meshes, ErrorKind> {
    let mut lost_variants = false;
    let opts = EncodeOptions {
        quantization: p.quantization,
    };
    let src_meshes = array(&p.json, "meshes");
    let mut out = Meshes {
        json: Vec::new(),
        map: vec![None; scene.meshes.len()],
        used_quantization: false,
    };
    for (mi, mesh) in scene.meshes.iter().enumerate() {
        let enc = encode_mesh(mesh, mi, bin, &opts, warnings)?;
        out.used_quantization |= enc.used_quantization;
        let src_mesh = src_meshes.get(mi).cloned().unwrap_or_else(|| json!({}));
        let src_prims = array(&src_mesh, "primitives");
        let source = p.meshes.get(mi).cloned().unwrap_or_default();
        // Parts match the source primitives one to one unless an edit added
        // or removed parts.
        let aligned = source.part_primitives.len() == mesh.parts.len();
        let mut prims = Vec::new();
        for (part, prim) in enc.primitives {
            let mut prim = prim.as_object().cloned().unwrap_or_default();
            let from = aligned
                .then(|| source.part_primitives.get(part))
                .flatten()
                .and_then(|&sp| src_prims.get(sp))
                .and_then(Value::as_object);
            for (k, v) in from.into_iter().flatten() {
                if !matches!(
                    k.as_str(),
                    "attributes" | "indices" | "material" | "mode" | "targets"
                ) {
                    prim.insert(k.clone(), v.clone());
                }
            }
            strip_draco(&mut prim);
            if let Some(map) = material_map {
                lost_variants |= remap_variants(&mut prim, map);
            }
            prims.push(Value::Object(prim));
        }
        for prim in source
            .kept_primitives
            .iter()
            .filter_map(|&k| src_prims.get(k))
        {
            let mut prim = prim.clone();
            remap_primitive(&mut prim, acc_map);
            if let Some(o) = prim.as_object_mut() {
                strip_draco(o);
                if let Some(map) = material_map {
                    // A kept primitive's material, in the rebuilt list.
                    match index(o.get("material")).map(|m| map.get(m).copied().flatten()) {
                        Some(Some(n)) => {
                            o.insert("material".into(), json!(n));
                        }
                        Some(None) => {
                            o.remove("material");
                        }
                        None => {}
                    }
                    lost_variants |= remap_variants(o, map);
                }
            }
            prims.push(prim);
        }
        if prims.is_empty() {
            warnings.push(format!(
                "mesh {mi} has no faces left; it is not written and nodes no longer refer to it"
            ));
            continue;
        }
        let targets = prims.iter().map(|p| array(p, "targets").len()).max();
        let mut m = src_mesh.as_object().cloned().unwrap_or_default();
        m.insert("primitives".into(), Value::Array(prims));
        if mesh.name.is_empty() {
            m.remove("name");
        } else {
            m.insert("name".into(), json!(mesh.name));
        }
        // Default morph weights describe targets that no longer exist.
        if targets == Some(0) {
            m.remove("weights");
        }
        out.map[mi] = Some(out.json.len());
        out.json.push(Value::Object(m));
    }
    if lost_variants {
        warnings.push(
            "materials were rebuilt (re-baked or merged): material variants \
             (KHR_materials_variants) whose material has no rebuilt counterpart of its name \
             are dropped"
                .into(),
        );
    }
    Ok(out)
}

/// Source material index → rebuilt material index, matched by name where
/// exactly one source and at least one rebuilt material carry it (the
/// first of those); `None` for a source material with no counterpart.
fn material_map(scene: &Scene, p: &Passthrough) -> IndexMap {
    p.read
        .materials
        .iter()
        .map(|m| {
            let unique = p.read.materials.iter().filter(|s| s.name == m.name).count() == 1;
            unique
                .then(|| scene.materials.iter().position(|s| s.name == m.name))
                .flatten()
        })
        .collect()
}

/// Points a primitive's `KHR_materials_variants` mappings at the rebuilt
/// materials through `map`, dropping mappings (and the extension, once
/// empty) whose material has none; true when something was dropped.
fn remap_variants(prim: &mut Map<String, Value>, map: &[Option<usize>]) -> bool {
    let Some(ext) = prim.get_mut("extensions").and_then(Value::as_object_mut) else {
        return false;
    };
    let Some(mappings) = ext
        .get_mut("KHR_materials_variants")
        .and_then(|v| v.get_mut("mappings"))
        .and_then(Value::as_array_mut)
    else {
        return false;
    };
    let before = mappings.len();
    mappings.retain_mut(|m| {
        match index(m.get("material")).and_then(|i| map.get(i).copied().flatten()) {
            Some(n) => {
                m["material"] = json!(n);
                true
            }
            None => false,
        }
    });
    let dropped = mappings.len() < before;
    if mappings.is_empty() {
        ext.remove("KHR_materials_variants");
        if ext.is_empty() {
            prim.remove("extensions");
        }
    }
    dropped
}

/// Points nodes, skins and animations at the moved meshes and accessors.
/// A node whose mesh was not written loses its mesh, skin and weights.
fn remap_references(
    out: &mut Map<String, Value>,
    src: &Value,
    mesh_map: &[Option<usize>],
    acc_map: &[Option<usize>],
) {
    let mut nodes = array(src, "nodes").to_vec();
    for n in &mut nodes {
        if let Some(attrs) = instancing_attributes(n) {
            attrs.values_mut().for_each(|v| remap(v, acc_map));
        }
        let Some(o) = n.as_object_mut() else {
            continue;
        };
        if let Some(m) = index(o.get("mesh")) {
            match mesh_map.get(m).copied().flatten() {
                Some(w) => {
                    o.insert("mesh".into(), json!(w));
                }
                None => {
                    for k in ["mesh", "skin", "weights"] {
                        o.remove(k);
                    }
                }
            }
        }
    }
    let mut skins = array(src, "skins").to_vec();
    for s in &mut skins {
        if let Some(v) = s.get_mut("inverseBindMatrices") {
            remap(v, acc_map);
        }
    }
    let mut animations = array(src, "animations").to_vec();
    for a in &mut animations {
        let samplers = a.get_mut("samplers").and_then(Value::as_array_mut);
        for s in samplers.into_iter().flatten() {
            for k in ["input", "output"] {
                if let Some(v) = s.get_mut(k) {
                    remap(v, acc_map);
                }
            }
        }
    }
    for (key, list) in [
        ("nodes", nodes),
        ("skins", skins),
        ("animations", animations),
    ] {
        if !list.is_empty() {
            out.insert(key.into(), Value::Array(list));
        }
    }
}

/// Materials and textures: the source's own objects while unchanged,
/// rebuilt from the scene once a later step (re-baking) replaced them.
/// Source images are placed for the output format either way they stay.
fn materials_and_images(
    out: &mut Map<String, Value>,
    scene: &Scene,
    p: &Passthrough,
    bin: &mut Bin,
    images: &mut ImageWriter,
    warnings: &mut Vec<String>,
) -> Result<(), ErrorKind> {
    let source = array(&p.json, "materials");
    let mut lost: Vec<String> = Vec::new();
    if scene.materials != p.read.materials {
        // Rebuilt (re-baked or merged): a material keeps the extensions
        // (clearcoat, sheen, transmission…) of the one source material of
        // its name, if there is exactly one.
        let mut rebuilt = scene_json::materials(&scene.materials);
        for (m, json) in scene.materials.iter().zip(rebuilt.iter_mut()) {
            let mut named = p
                .read
                .materials
                .iter()
                .enumerate()
                .filter(|(_, s)| s.name == m.name);
            let ext = match (named.next(), named.next()) {
                (Some((i, _)), None) => source.get(i).and_then(|s| s.get("extensions")),
                _ => None,
            };
            if let (Some(ext), Some(o)) = (ext, json.as_object_mut()) {
                o.insert("extensions".into(), ext.clone());
            }
        }
        let carried = extension_names(&rebuilt);
        lost = extension_names(source)
            .into_iter()
            .filter(|n| !carried.contains(n))
            .collect();
        out.insert("materials".into(), Value::Array(rebuilt));
    }
    if !lost.is_empty() {
        warnings.push(format!(
            "materials were rebuilt (re-baked or merged) without a source material of their \
             name: their extensions ({}) are not carried over",
            lost.join(", ")
        ));
    }
    if scene.textures != p.read.textures {
        // Textures were replaced (a re-bake): a texture an extension names
        // is an index into the source's textures, laid out on the source's
        // UVs.
        let mut dropped = Vec::new();
        if let Some(Value::Array(materials)) = out.get_mut("materials") {
            for m in materials.iter_mut() {
                drop_stale_extension_textures(m, scene, p, &mut dropped);
            }
        }
        if !dropped.is_empty() {
            dropped.sort();
            dropped.dedup();
            warnings.push(format!(
                "textures were re-baked: material extension textures ({}) are dropped, \
                 only base colour, metallic-roughness, normal, occlusion and emissive are \
                 re-baked; the extensions' factors stay",
                dropped.join(", ")
            ));
        }
    }
    if scene.textures == p.read.textures {
        let view = |v: usize| source_view(p, v);
        let mut placed = Vec::new();
        for (i, img) in array(&p.json, "images").iter().enumerate() {
            placed.push(images.passthrough(bin, i, img, &view)?);
        }
        if !placed.is_empty() {
            out.insert("images".into(), Value::Array(placed));
        }
    } else {
        let (textures, placed, samplers) = scene_json::textures(scene, bin, images)?;
        out.insert("textures".into(), Value::Array(textures));
        out.insert("images".into(), Value::Array(placed));
        // The source's samplers belonged to the replaced textures; the
        // scene's own wrap modes replace them.
        out.insert("samplers".into(), Value::Array(samplers));
    }
    Ok(())
}
