//! Writing `.gltf` and `.glb`.
//!
//! A document read from glTF is written from its original JSON: meshes,
//! accessors, buffer views and buffers are rebuilt from the scene, every
//! other object is kept, and each reference to an accessor or buffer view
//! is remapped. Any other document is built from the [`Scene`] alone.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde_json::{json, Map, Value};
use wildlod_mesh::{ImageSource, Scene};

use super::bin::Bin;
use super::encode::{encode_mesh, EncodeOptions};
use super::images::ImageWriter;
use super::load::{self, QUANTIZATION};
use super::passthrough::Passthrough;
use super::{glb, scene_json, uri};
use crate::{Document, ErrorKind, Format, OutputFiles};

/// Writes `doc` to `path` as `.gltf` (with a `.bin` beside it) or `.glb`.
pub(crate) fn write(
    doc: &Document,
    path: &Path,
    format: Format,
    files: &mut OutputFiles,
) -> Result<(), ErrorKind> {
    let mut warnings = Vec::new();
    if let Some(p) = &doc.gltf {
        for f in &p.external {
            files.protect(f);
        }
    }
    for t in &doc.scene.textures {
        if let ImageSource::Path(p) = &t.source {
            files.protect(p);
        }
    }
    let pass = doc
        .gltf
        .as_ref()
        .filter(|p| graph_unchanged(&doc.scene, p, &mut warnings));
    let source_dir = match &doc.gltf {
        Some(p) => Some(p.source_dir.clone()),
        None => doc.source.as_deref().and_then(Path::parent).map(|d| {
            load::absolute(if d.as_os_str().is_empty() {
                Path::new(".")
            } else {
                d
            })
        }),
    };
    let mut images = ImageWriter::new(path, format, source_dir.as_deref());
    let mut bin = Bin::default();
    let (json, used_quantization) = match pass {
        Some(p) => from_passthrough(&doc.scene, p, &mut bin, &mut images, &mut warnings)?,
        None => from_scene(&doc.scene, &mut bin, &mut images, &mut warnings)?,
    };
    let source_lists = pass.map(|p| &p.json);
    let json = finish(json, &bin, path, format, source_lists, used_quantization);
    // Refuse to write what readers would reject: the same validation the
    // reader applies, on our own output.
    load::typed(&json, "written glTF", &mut warnings)?;
    warnings.append(&mut images.warnings);
    let main = match format {
        Format::Glb => {
            let text = serde_json::to_vec(&json).map_err(|e| {
                ErrorKind::Unsupported(format!("cannot serialize the glTF JSON: {e}"))
            })?;
            glb::build(&text, &bin.data)?
        }
        _ => serde_json::to_vec_pretty(&json)
            .map_err(|e| ErrorKind::Unsupported(format!("cannot serialize the glTF JSON: {e}")))?,
    };
    files.add(path, main)?;
    if format != Format::Glb && !bin.data.is_empty() {
        files.add(&bin_path(path), std::mem::take(&mut bin.data))?;
    }
    for (p, bytes) in std::mem::take(&mut images.sidecars) {
        files.add(&p, bytes)?;
    }
    for w in warnings {
        files.warn(w);
    }
    Ok(())
}

/// `<stem>.bin` beside a `.gltf`.
fn bin_path(path: &Path) -> PathBuf {
    path.with_extension("bin")
}

/// Whether the scene graph is still the one read, so that the source JSON
/// (nodes, skins, animations that index them) can be trusted.
fn graph_unchanged(scene: &Scene, p: &Passthrough, warnings: &mut Vec<String>) -> bool {
    let same = scene.meshes.len() == p.meshes.len()
        && scene.nodes == p.read.nodes
        && scene.roots == p.read.roots
        && scene.skins == p.read.skins
        && scene.animations == p.read.animations;
    if !same {
        warnings.push(
            "the scene graph (meshes, nodes, skins or animations) changed since the glTF was \
             read: the file is written from the scene alone, without the source's animations, \
             cameras and extensions"
                .into(),
        );
    }
    same
}

/// Accessor indices a primitive refers to (attributes, indices, morph targets).
fn primitive_accessors(prim: &Value) -> Vec<usize> {
    let mut out = Vec::new();
    let index = |v: &Value| v.as_u64().map(|i| i as usize);
    if let Some(a) = prim.get("attributes").and_then(Value::as_object) {
        out.extend(a.values().filter_map(index));
    }
    if let Some(i) = prim.get("indices").and_then(index) {
        out.push(i);
    }
    for t in prim
        .get("targets")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        if let Some(t) = t.as_object() {
            out.extend(t.values().filter_map(index));
        }
    }
    out
}

/// Rewrites every accessor index in a primitive through `map`.
fn remap_primitive(prim: &mut Value, map: &[Option<usize>]) {
    let fix = |v: &mut Value| {
        if let Some(n) = v
            .as_u64()
            .and_then(|i| map.get(i as usize).copied().flatten())
        {
            *v = json!(n);
        }
    };
    if let Some(a) = prim.get_mut("attributes").and_then(Value::as_object_mut) {
        a.values_mut().for_each(fix);
    }
    if let Some(i) = prim.get_mut("indices") {
        fix(i);
    }
    for t in prim
        .get_mut("targets")
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
    {
        if let Some(t) = t.as_object_mut() {
            t.values_mut().for_each(fix);
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

/// The GPU-instancing extension's per-instance accessors of a node.
fn instancing_attributes(node: &mut Value) -> Option<&mut Map<String, Value>> {
    node.get_mut("extensions")?
        .get_mut("EXT_mesh_gpu_instancing")?
        .get_mut("attributes")?
        .as_object_mut()
}

fn array<'a>(json: &'a Value, key: &str) -> &'a [Value] {
    json.get(key)
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or(&[])
}

/// The JSON of a document read from glTF, with meshes rebuilt; returns it
/// and whether quantized encodings were used.
fn from_passthrough(
    scene: &Scene,
    p: &Passthrough,
    bin: &mut Bin,
    images: &mut ImageWriter,
    warnings: &mut Vec<String>,
) -> Result<(Value, bool), ErrorKind> {
    let src = &p.json;
    let mut out = src.as_object().cloned().unwrap_or_default();
    let accessors = array(src, "accessors");
    let views = array(src, "bufferViews");
    let index = |v: Option<&Value>| v.and_then(Value::as_u64).map(|i| i as usize);

    // Accessors only triangle primitives use are rebuilt; every other one
    // (animations, skins, kept primitives, extensions, unreferenced) is
    // copied, since something we do not interpret may still use it.
    let mut mesh_use = vec![false; accessors.len()];
    let mut other_use = vec![false; accessors.len()];
    for (mi, m) in array(src, "meshes").iter().enumerate() {
        let kept = p
            .meshes
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
            for v in attrs.values() {
                mark(Some(v));
            }
        }
    }
    let keep: Vec<bool> = (0..accessors.len())
        .map(|a| other_use[a] || !mesh_use[a])
        .collect();

    // Buffer views of kept accessors, copied byte for byte.
    let view_bytes = |v: usize| -> Option<Vec<u8>> {
        let view = views.get(v)?;
        let b = index(view.get("buffer"))?;
        let start = index(view.get("byteOffset")).unwrap_or(0);
        let len = index(view.get("byteLength"))?;
        p.buffers
            .get(b)?
            .get(start..start.checked_add(len)?)
            .map(<[u8]>::to_vec)
    };
    let mut view_needed = vec![false; views.len()];
    for (a, acc) in accessors.iter().enumerate() {
        if !keep[a] {
            continue;
        }
        let sparse = acc.get("sparse");
        for v in [
            acc.get("bufferView"),
            sparse
                .and_then(|s| s.get("indices"))
                .and_then(|s| s.get("bufferView")),
            sparse
                .and_then(|s| s.get("values"))
                .and_then(|s| s.get("bufferView")),
        ] {
            if let Some(f) = index(v).and_then(|v| view_needed.get_mut(v)) {
                *f = true;
            }
        }
    }
    let mut view_map: Vec<Option<usize>> = vec![None; views.len()];
    for (v, needed) in view_needed.iter().enumerate() {
        if !needed {
            continue;
        }
        let bytes = view_bytes(v).ok_or_else(|| {
            ErrorKind::malformed(format!("bufferView {v}"), "lies outside its buffer")
        })?;
        let mut template = views[v].as_object().cloned().unwrap_or_default();
        let old_offset = index(template.get("byteOffset")).unwrap_or(0) as u64;
        for k in ["buffer", "byteOffset", "byteLength"] {
            template.remove(k);
        }
        view_map[v] = Some(bin.view_from(&bytes, old_offset, template));
    }
    let fix_view = |v: &mut Value| {
        if let Some(n) = v
            .as_u64()
            .and_then(|i| view_map.get(i as usize).copied().flatten())
        {
            *v = json!(n);
        }
    };
    let mut acc_map: Vec<Option<usize>> = vec![None; accessors.len()];
    for (a, acc) in accessors.iter().enumerate() {
        if !keep[a] {
            continue;
        }
        let mut acc = acc.clone();
        if let Some(v) = acc.get_mut("bufferView") {
            fix_view(v);
        }
        if let Some(s) = acc.get_mut("sparse") {
            for part in ["indices", "values"] {
                if let Some(v) = s.get_mut(part).and_then(|x| x.get_mut("bufferView")) {
                    fix_view(v);
                }
            }
        }
        bin.accessors.push(acc);
        acc_map[a] = Some(bin.accessors.len() - 1);
    }
    let fix_acc = |v: &mut Value| {
        if let Some(n) = v
            .as_u64()
            .and_then(|i| acc_map.get(i as usize).copied().flatten())
        {
            *v = json!(n);
        }
    };

    // Meshes.
    let opts = EncodeOptions {
        quantization: p.quantization,
    };
    let mut used_quantization = false;
    let src_meshes = array(src, "meshes");
    let mut mesh_map: Vec<Option<usize>> = vec![None; scene.meshes.len()];
    let mut meshes_out = Vec::new();
    for (mi, mesh) in scene.meshes.iter().enumerate() {
        let enc = encode_mesh(mesh, mi, bin, &opts, warnings)?;
        used_quantization |= enc.used_quantization;
        let src_mesh = src_meshes.get(mi).cloned().unwrap_or_else(|| json!({}));
        let src_prims = array(&src_mesh, "primitives");
        let source = p.meshes.get(mi).cloned().unwrap_or_default();
        // Parts still match the source primitives one to one unless an
        // edit added or removed parts.
        let aligned = source.part_primitives.len() == mesh.parts.len();
        let mut prims = Vec::new();
        for (part, prim) in enc.primitives {
            let mut prim = prim.as_object().cloned().unwrap_or_default();
            let from = aligned
                .then(|| source.part_primitives.get(part))
                .flatten()
                .and_then(|&sp| src_prims.get(sp))
                .and_then(Value::as_object);
            if let Some(from) = from {
                for (k, v) in from {
                    if !matches!(
                        k.as_str(),
                        "attributes" | "indices" | "material" | "mode" | "targets"
                    ) {
                        prim.insert(k.clone(), v.clone());
                    }
                }
                strip_draco(&mut prim);
            }
            prims.push(Value::Object(prim));
        }
        for &kp in &source.kept_primitives {
            if let Some(prim) = src_prims.get(kp) {
                let mut prim = prim.clone();
                remap_primitive(&mut prim, &acc_map);
                if let Some(o) = prim.as_object_mut() {
                    strip_draco(o);
                }
                prims.push(prim);
            }
        }
        if prims.is_empty() {
            warnings.push(format!(
                "mesh {mi} has no faces left; it is not written and nodes no longer refer to it"
            ));
            continue;
        }
        let targets = prims
            .iter()
            .map(|p| array(p, "targets").len())
            .max()
            .unwrap_or(0);
        let mut m = src_mesh.as_object().cloned().unwrap_or_default();
        m.insert("primitives".into(), Value::Array(prims));
        if mesh.name.is_empty() {
            m.remove("name");
        } else {
            m.insert("name".into(), json!(mesh.name));
        }
        if targets == 0 {
            m.remove("weights");
        }
        mesh_map[mi] = Some(meshes_out.len());
        meshes_out.push(Value::Object(m));
    }
    out.insert("meshes".into(), Value::Array(meshes_out));

    // Nodes: mesh indices shift when meshes were dropped; instancing
    // accessors move.
    let mut nodes = array(src, "nodes").to_vec();
    for n in &mut nodes {
        if let Some(attrs) = instancing_attributes(n) {
            attrs.values_mut().for_each(fix_acc);
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
    if !nodes.is_empty() {
        out.insert("nodes".into(), Value::Array(nodes));
    }
    let mut skins = array(src, "skins").to_vec();
    for s in &mut skins {
        if let Some(v) = s.get_mut("inverseBindMatrices") {
            fix_acc(v);
        }
    }
    if !skins.is_empty() {
        out.insert("skins".into(), Value::Array(skins));
    }
    let mut animations = array(src, "animations").to_vec();
    for a in &mut animations {
        for s in a
            .get_mut("samplers")
            .and_then(Value::as_array_mut)
            .into_iter()
            .flatten()
        {
            for k in ["input", "output"] {
                if let Some(v) = s.get_mut(k) {
                    fix_acc(v);
                }
            }
        }
    }
    if !animations.is_empty() {
        out.insert("animations".into(), Value::Array(animations));
    }

    // Materials and textures: the source's own objects while unchanged,
    // rebuilt from the scene once a later step replaced them.
    if scene.materials != p.read.materials {
        out.insert(
            "materials".into(),
            Value::Array(scene_json::materials(&scene.materials)),
        );
    }
    if scene.textures == p.read.textures {
        let mut imgs = Vec::new();
        for (i, img) in array(src, "images").iter().enumerate() {
            imgs.push(images.passthrough(bin, i, img, &view_bytes)?);
        }
        if !imgs.is_empty() {
            out.insert("images".into(), Value::Array(imgs));
        }
    } else {
        let (textures, imgs) = scene_json::textures(scene, bin, images)?;
        out.insert("textures".into(), Value::Array(textures));
        out.insert("images".into(), Value::Array(imgs));
        out.remove("samplers");
    }
    Ok((Value::Object(out), used_quantization))
}

/// The JSON of a document built from the scene alone.
fn from_scene(
    scene: &Scene,
    bin: &mut Bin,
    images: &mut ImageWriter,
    warnings: &mut Vec<String>,
) -> Result<(Value, bool), ErrorKind> {
    let opts = EncodeOptions {
        quantization: false,
    };
    let mut mesh_map = vec![None; scene.meshes.len()];
    let mut meshes = Vec::new();
    for (mi, mesh) in scene.meshes.iter().enumerate() {
        let enc = encode_mesh(mesh, mi, bin, &opts, warnings)?;
        if enc.primitives.is_empty() {
            warnings.push(format!("mesh {mi} has no faces; it is not written"));
            continue;
        }
        let mut m = Map::new();
        if !mesh.name.is_empty() {
            m.insert("name".into(), json!(mesh.name));
        }
        m.insert(
            "primitives".into(),
            Value::Array(enc.primitives.into_iter().map(|(_, p)| p).collect()),
        );
        mesh_map[mi] = Some(meshes.len());
        meshes.push(Value::Object(m));
    }
    let (nodes, roots) = scene_json::nodes(scene, &mesh_map);
    let skins = scene_json::skins(scene, bin);
    let (textures, imgs) = scene_json::textures(scene, bin, images)?;
    if !scene.animations.is_empty() {
        warnings.push(format!(
            "{} animations are not written: the scene holds only their summaries",
            scene.animations.len()
        ));
    }
    let mut out = Map::new();
    out.insert(
        "asset".into(),
        json!({"version": "2.0", "generator": concat!("wildlod ", env!("CARGO_PKG_VERSION"))}),
    );
    if !roots.is_empty() {
        out.insert("scene".into(), json!(0));
        out.insert("scenes".into(), json!([{ "nodes": roots }]));
    }
    out.insert("nodes".into(), Value::Array(nodes));
    out.insert("meshes".into(), Value::Array(meshes));
    out.insert("skins".into(), Value::Array(skins));
    out.insert(
        "materials".into(),
        Value::Array(scene_json::materials(&scene.materials)),
    );
    out.insert("textures".into(), Value::Array(textures));
    out.insert("images".into(), Value::Array(imgs));
    Ok((Value::Object(out), false))
}

/// Adds the binary data's views, accessors and buffer, drops empty
/// top-level arrays (glTF forbids them), and lists exactly the extensions
/// the output uses.
fn finish(
    json: Value,
    bin: &Bin,
    path: &Path,
    format: Format,
    source: Option<&Value>,
    used_quantization: bool,
) -> Value {
    let mut out = match json {
        Value::Object(o) => o,
        _ => Map::new(),
    };
    out.insert("accessors".into(), Value::Array(bin.accessors.clone()));
    out.insert("bufferViews".into(), Value::Array(bin.views.clone()));
    if bin.data.is_empty() {
        out.remove("buffers");
    } else {
        let mut b = Map::new();
        b.insert("byteLength".into(), json!(bin.data.len()));
        if format != Format::Glb {
            let name = bin_path(path);
            let name = name.file_name().map(PathBuf::from).unwrap_or_default();
            b.insert("uri".into(), json!(uri::percent_encode_path(&name)));
        }
        out.insert("buffers".into(), json!([b]));
    }
    for key in [
        "accessors",
        "animations",
        "bufferViews",
        "buffers",
        "cameras",
        "images",
        "materials",
        "meshes",
        "nodes",
        "samplers",
        "scenes",
        "skins",
        "textures",
    ] {
        if out
            .get(key)
            .and_then(Value::as_array)
            .is_some_and(Vec::is_empty)
        {
            out.remove(key);
        }
    }
    if !out.contains_key("scenes") {
        out.remove("scene");
    }
    let mut present = BTreeSet::new();
    for (k, v) in &out {
        if k != "extensionsUsed" && k != "extensionsRequired" {
            extension_names(k, v, &mut present);
        }
    }
    let list = |key: &str| -> Vec<String> {
        source
            .map(|s| array(s, key))
            .unwrap_or(&[])
            .iter()
            .filter_map(|v| v.as_str().map(str::to_string))
            .collect()
    };
    let keep = |e: &String| present.contains(e) || (e == QUANTIZATION && used_quantization);
    let mut used: Vec<String> = list("extensionsUsed").into_iter().filter(keep).collect();
    let mut required: Vec<String> = list("extensionsRequired")
        .into_iter()
        .filter(keep)
        .collect();
    // Extensions the output uses but the source did not declare.
    for e in &present {
        if !used.contains(e) {
            used.push(e.clone());
        }
    }
    if used_quantization {
        for l in [&mut used, &mut required] {
            if !l.iter().any(|e| e == QUANTIZATION) {
                l.push(QUANTIZATION.into());
            }
        }
    }
    out.remove("extensionsUsed");
    out.remove("extensionsRequired");
    if !used.is_empty() {
        out.insert("extensionsUsed".into(), json!(used));
    }
    if !required.is_empty() {
        out.insert("extensionsRequired".into(), json!(required));
    }
    Value::Object(out)
}

/// Names of the extensions present anywhere in `v` (keys of `extensions`
/// objects). `extras` are application data and are not searched.
fn extension_names(key: &str, v: &Value, out: &mut BTreeSet<String>) {
    if key == "extras" {
        return;
    }
    match v {
        Value::Object(o) => {
            if key == "extensions" {
                out.extend(o.keys().cloned());
            }
            for (k, x) in o {
                extension_names(k, x, out);
            }
        }
        Value::Array(a) => {
            for x in a {
                extension_names("", x, out);
            }
        }
        _ => {}
    }
}
