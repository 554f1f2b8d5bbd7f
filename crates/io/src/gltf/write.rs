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

use super::bin::{Bin, Section};
use super::encode::{encode_mesh, EncodeOptions};
use super::images::ImageWriter;
use super::load::{self, QUANTIZATION};
use super::passthrough::Passthrough;
use super::{animation_json, glb, rewrite, scene_json, uri};
use crate::{Document, ErrorKind, Format, OutputFiles};

/// Writes `doc` to `path` as `.gltf` (with a `.bin` beside it) or `.glb`.
pub(crate) fn write(
    doc: &Document,
    path: &Path,
    format: Format,
    files: &mut OutputFiles,
) -> Result<(), ErrorKind> {
    write_with_lods(doc, None, path, format, files)
}

/// [`write()`], with lower levels of detail added as `MSFT_lod` nodes when
/// `lods` is given (see [`super::lod`]).
pub(crate) fn write_with_lods(
    doc: &Document,
    lods: Option<&crate::LodLevels>,
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
    let (mut json, mut used_quantization, mesh_map) = match pass {
        Some(p) => rewrite::from_passthrough(&doc.scene, p, &mut bin, &mut images, &mut warnings)?,
        // A glTF source's animations index its own JSON, which a changed
        // graph no longer matches: they are dropped (with the warning of
        // `graph_unchanged`). Any other scene's tracks are written.
        None => from_scene(
            &doc.scene,
            doc.gltf.is_none(),
            &mut bin,
            &mut images,
            &mut warnings,
        )?,
    };
    if let Some(lods) = lods {
        let opts = EncodeOptions {
            quantization: pass.is_some_and(|p| p.quantization),
        };
        used_quantization |=
            super::lod::add_levels(&mut json, lods, &mesh_map, &mut bin, &opts, &mut warnings)?;
    }
    let coarsest = lods.map_or(0, |l| l.levels.len());
    if coarsest > 0 {
        let levels =
            super::image_levels::image_view_levels(&json, &bin.accessors, |v| bin.level_of(v));
        bin.defer_images(&levels, coarsest);
    }
    bin.lay_out_for_streaming(coarsest);
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

fn array<'a>(json: &'a Value, key: &str) -> &'a [Value] {
    json.get(key)
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or(&[])
}

/// The JSON of a document built from the scene alone; its animations
/// written from their tracks when `with_animations`.
fn from_scene(
    scene: &Scene,
    with_animations: bool,
    bin: &mut Bin,
    images: &mut ImageWriter,
    warnings: &mut Vec<String>,
) -> Result<(Value, bool, Vec<Option<usize>>), ErrorKind> {
    let opts = EncodeOptions {
        quantization: false,
    };
    let mut mesh_map = vec![None; scene.meshes.len()];
    let mut meshes = Vec::new();
    bin.section = Section::Level(0);
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
    // Animations, skins: data every level shares (see `Section`).
    bin.section = Section::Shared;
    let (animations, animated) = if with_animations {
        (
            animation_json::animations(scene, bin, warnings),
            animation_json::animated_nodes(scene),
        )
    } else {
        (Vec::new(), Vec::new())
    };
    let (nodes, roots) = scene_json::nodes(scene, &mesh_map, &animated, warnings);
    let skins = scene_json::skins(scene, bin);
    bin.section = Section::Textures;
    let (textures, imgs, samplers) = scene_json::textures(scene, bin, images)?;
    bin.section = Section::Shared;
    let mut out = Map::new();
    out.insert(
        "asset".into(),
        json!({"version": "2.0", "generator": GENERATOR}),
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
    out.insert("samplers".into(), Value::Array(samplers));
    out.insert("animations".into(), Value::Array(animations));
    Ok((Value::Object(out), false, mesh_map))
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
    set_generator(&mut out);
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

/// `asset.generator` of every file written: the tool that wrote the file
/// (glTF 2.0 §5.2), whatever made its input.
pub(crate) const GENERATOR: &str = concat!("wildlod ", env!("CARGO_PKG_VERSION"));

/// Names wildlod as the generator, keeping the asset's other properties
/// (version, copyright, extras); an asset that is not an object is
/// replaced (the reader already refused a missing `version`).
fn set_generator(out: &mut Map<String, Value>) {
    match out.get_mut("asset").and_then(Value::as_object_mut) {
        Some(asset) => {
            asset.insert("generator".into(), json!(GENERATOR));
        }
        None => {
            out.insert(
                "asset".into(),
                json!({"version": "2.0", "generator": GENERATOR}),
            );
        }
    }
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
