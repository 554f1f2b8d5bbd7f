//! glTF document → [`Scene`]: one [`Mesh`] per glTF mesh (primitives
//! concatenated, one part each), nodes, skins, animation summaries,
//! materials and textures.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use gltf_json::validation::Checked;
use gltf_json::Root;
use serde_json::Value;
use wildlod_mesh::{
    AlphaMode, Animation, Attribute, ComponentFormat, ImageSource, Interpolation, Material, Mesh,
    MorphChannel, Node, Part, Sampler, Scene, Semantic, Skin, Skinning, Texture, TextureRef, Track,
    TrackPath, Wrap, ABSENT,
};

use super::accessor::Data;
use super::attribute_keys::{morph_key, semantic_key};
use super::load::{self, Loaded};
use super::passthrough::{MeshSource, Passthrough, SourceBuffer};
use super::rewrite;
use super::texture_transform;
use super::trs::trs_matrix;
use super::uri::{self, UriKind};
use crate::ErrorKind;

/// Reads a `.gltf` or `.glb` file whose bytes are `data`.
pub(crate) fn read(
    path: &Path,
    data: &[u8],
    warnings: &mut Vec<String>,
) -> Result<(Scene, Passthrough), ErrorKind> {
    let mut loaded = load::load(path, data, warnings)?;
    let dir = load::absolute(path.parent().unwrap_or(Path::new("")));
    let dir = if dir.as_os_str().is_empty() {
        load::absolute(Path::new("."))
    } else {
        dir
    };
    let bytes: u64 = loaded.buffers.iter().map(|b| b.len() as u64).sum();
    // Values and corners a file may expand to. Primitives that share an
    // accessor decode its bytes once per distinct attribute set, which
    // legitimately expands a little; a file expanding far beyond its
    // binary data is hostile. (JSON size does not count: it holds no
    // vertex data.)
    let budget = bytes.saturating_mul(4).saturating_add(1 << 24);
    let d = Data {
        root: &loaded.root,
        buffers: &loaded.buffers,
        max_unbacked: budget,
    };
    // Everything the writer may copy verbatim must lie inside its buffer,
    // not only what this reader decodes.
    for v in 0..loaded.root.buffer_views.len() {
        d.view(v)?;
    }
    for a in 0..loaded.root.accessors.len() {
        d.check(a)?;
    }
    let mut scene = Scene::default();
    let mut sources = Vec::new();
    let mut budget_left = Budget { units: budget };
    let prims_json = |mi: usize| -> &[Value] {
        loaded
            .json
            .get("meshes")
            .and_then(|m| m.get(mi))
            .and_then(|m| m.get("primitives"))
            .and_then(Value::as_array)
            .map(Vec::as_slice)
            .unwrap_or(&[])
    };
    for (mi, m) in loaded.root.meshes.iter().enumerate() {
        let (mesh, source) = read_mesh(
            &d,
            mi,
            m.name.clone().unwrap_or_default(),
            prims_json(mi),
            &mut budget_left,
            warnings,
        )?;
        scene.meshes.push(mesh);
        sources.push(source);
    }
    scene.nodes = read_nodes(&loaded.root);
    scene.roots = read_roots(&loaded.root);
    scene.skins = read_skins(&d)?;
    scene.animations = read_animations(&d)?;
    scene.materials = loaded.root.materials.iter().map(read_material).collect();
    let mut external = loaded.external.clone();
    scene.textures = read_textures(&d, &dir, &mut external, warnings)?;
    let quantization = declares(&loaded.json, load::QUANTIZATION);
    // UV maps of the materials go into the UVs (and out of the document).
    texture_transform::apply_texture_transforms(&mut scene, &mut loaded.json);
    let read_scene = Scene {
        meshes: Vec::new(),
        ..scene.clone()
    };
    let Loaded { json, buffers, .. } = loaded;
    // Only what a write copies byte for byte stays; the meshes are decoded.
    let copied = rewrite::copied_views(&json, &sources);
    let views = json
        .get("bufferViews")
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or(&[]);
    let buffers = buffers
        .iter()
        .enumerate()
        .map(|(b, bytes)| {
            let spans = views
                .iter()
                .zip(&copied)
                .filter(|(_, &c)| c)
                .filter_map(|(v, _)| {
                    let index = |k: &str| v.get(k).and_then(Value::as_u64).map(|x| x as usize);
                    (index("buffer")? == b).then(|| {
                        (
                            index("byteOffset").unwrap_or(0),
                            index("byteLength").unwrap_or(0),
                        )
                    })
                });
            SourceBuffer::keep(bytes, spans)
        })
        .collect();
    let pass = Passthrough {
        json,
        buffers,
        source_dir: dir,
        external,
        meshes: sources,
        read: read_scene,
        quantization,
    };
    Ok((scene, pass))
}

/// Whether `extensionsUsed` lists `name`.
fn declares(json: &Value, name: &str) -> bool {
    json.get("extensionsUsed")
        .and_then(Value::as_array)
        .is_some_and(|a| a.iter().any(|v| v.as_str() == Some(name)))
}

/// What is left of the expansion allowance, in 4-byte units of the mesh
/// model: vertex values, per-corner indices of every stream, skin slots.
struct Budget {
    units: u64,
}

impl Budget {
    fn take(&mut self, element: &str, units: u64) -> Result<(), ErrorKind> {
        if units > self.units {
            return Err(ErrorKind::ImplausibleCount {
                element: format!("{element} (mesh data expanded from shared accessors)"),
                count: units,
                max: self.units,
            });
        }
        self.units -= units;
        Ok(())
    }
}

/// A stream being assembled: per-vertex values, per-corner indices.
struct StreamBuild {
    components: usize,
    values: Vec<f32>,
    indices: Vec<u32>,
    format: ComponentFormat,
}

impl StreamBuild {
    /// Pads the value pool with defaults up to `vertices` values.
    fn pad_to(&mut self, vertices: usize, fill: &[f32]) {
        while self.values.len() < vertices * self.components {
            let k = self.values.len() % self.components;
            self.values.push(fill.get(k).copied().unwrap_or(0.0));
        }
    }

    /// Widens every value to `n` components (COLOR_0 as VEC3 in one
    /// primitive and VEC4 in another).
    fn widen(&mut self, n: usize, fill: &[f32]) {
        if n <= self.components {
            return;
        }
        let old = std::mem::take(&mut self.values);
        for chunk in old.chunks(self.components) {
            self.values.extend_from_slice(chunk);
            for k in self.components..n {
                self.values.push(fill.get(k).copied().unwrap_or(0.0));
            }
        }
        self.components = n;
    }
}

/// Value of components a primitive does not supply: opaque alpha for
/// colors, zero elsewhere.
fn fill_for(s: &Semantic) -> &'static [f32] {
    match s {
        Semantic::Color(_) => &[1.0, 1.0, 1.0, 1.0],
        _ => &[0.0, 0.0, 0.0, 0.0],
    }
}

/// A primitive attribute, classified.
enum Slot {
    Position,
    Stream(Semantic),
    Joints(u32),
    Weights(u32),
}

fn classify(name: &str) -> Slot {
    let num = |p: &str| name.strip_prefix(p).and_then(|n| n.parse::<u32>().ok());
    match name {
        "POSITION" => Slot::Position,
        "NORMAL" => Slot::Stream(Semantic::Normal),
        "TANGENT" => Slot::Stream(Semantic::Tangent),
        _ => {
            if let Some(n) = num("TEXCOORD_") {
                Slot::Stream(Semantic::TexCoord(n))
            } else if let Some(n) = num("COLOR_") {
                Slot::Stream(Semantic::Color(n))
            } else if let Some(n) = num("JOINTS_") {
                Slot::Joints(n)
            } else if let Some(n) = num("WEIGHTS_") {
                Slot::Weights(n)
            } else {
                Slot::Stream(Semantic::Custom(name.to_string()))
            }
        }
    }
}

/// Components glTF requires for a semantic (`None`: any of 1 to 4).
fn required_components(s: &Semantic) -> Option<&'static [usize]> {
    match s {
        Semantic::TexCoord(_) => Some(&[2]),
        Semantic::Normal => Some(&[3]),
        Semantic::Tangent => Some(&[4]),
        Semantic::Color(_) => Some(&[3, 4]),
        Semantic::Morph { .. } => Some(&[3]),
        Semantic::Custom(_) => None,
    }
}

fn accessor_index(v: &Value) -> Option<usize> {
    v.as_u64().and_then(|i| usize::try_from(i).ok())
}

/// Primitive modes (glTF 2.0 §3.7.2.1).
const TRIANGLES: u64 = 4;
const TRIANGLE_STRIP: u64 = 5;
const TRIANGLE_FAN: u64 = 6;

fn read_mesh(
    d: &Data<'_>,
    mi: usize,
    name: String,
    prims: &[Value],
    budget: &mut Budget,
    warnings: &mut Vec<String>,
) -> Result<(Mesh, MeshSource), ErrorKind> {
    let mut mesh = Mesh {
        name,
        ..Mesh::default()
    };
    let mut source = MeshSource::default();
    let mut streams: BTreeMap<Semantic, StreamBuild> = BTreeMap::new();
    // Skinning sets: slot n of a vertex is set n / 4.
    let sets = prims
        .iter()
        .filter_map(|p| p.get("attributes").and_then(Value::as_object))
        .flat_map(|a| a.keys())
        .filter_map(|k| match classify(k) {
            Slot::Joints(n) | Slot::Weights(n) => Some(n),
            _ => None,
        })
        .max()
        .map(|n| n as usize + 1)
        .unwrap_or(0);
    if sets > 64 {
        return Err(ErrorKind::malformed(
            format!("mesh {mi}"),
            format!("{sets} JOINTS/WEIGHTS sets; at most 64 are supported"),
        ));
    }
    let influences = 4 * sets;
    let mut skin_joints: Vec<u16> = Vec::new();
    let mut skin_weights: Vec<f32> = Vec::new();
    let mut skin_indices: Vec<u32> = Vec::new();
    let mut joint_format: Option<ComponentFormat> = None;
    let mut weight_format: Option<ComponentFormat> = None;
    // Primitives with the same attributes share their vertices.
    let mut shared: HashMap<String, (u32, usize, bool)> = HashMap::new();

    for (pi, prim) in prims.iter().enumerate() {
        let here = || format!("mesh {mi} primitive {pi}");
        let mode = prim
            .get("mode")
            .and_then(Value::as_u64)
            .unwrap_or(TRIANGLES);
        if !matches!(mode, TRIANGLES | TRIANGLE_STRIP | TRIANGLE_FAN) {
            let what = match mode {
                0 => "points",
                1 => "lines",
                2 => "a line loop",
                3 => "a line strip",
                _ => "an unknown mode",
            };
            warnings.push(format!(
                "{}: {what} cannot be simplified; the primitive is written back unchanged",
                here()
            ));
            source.kept_primitives.push(pi);
            continue;
        }
        let empty = serde_json::Map::new();
        let attrs = prim
            .get("attributes")
            .and_then(Value::as_object)
            .unwrap_or(&empty);
        let pos_acc = attrs
            .get("POSITION")
            .and_then(accessor_index)
            .ok_or_else(|| ErrorKind::malformed(here(), "has no POSITION attribute"))?;
        let key = format!(
            "{}|{}",
            Value::Object(attrs.clone()),
            prim.get("targets").unwrap_or(&Value::Null)
        );
        let (base, count, skinned) = match shared.get(&key) {
            Some(&s) => s,
            None => {
                let base = mesh.positions.len();
                read_vertices(
                    d,
                    &here(),
                    pos_acc,
                    attrs,
                    prim.get("targets"),
                    &mut mesh.positions,
                    &mut streams,
                    budget,
                    warnings,
                )?;
                let count = mesh.positions.len() - base;
                let skinned = read_skin_vertices(
                    d,
                    &here(),
                    attrs,
                    count,
                    influences,
                    base,
                    (&mut skin_joints, &mut skin_weights),
                    (&mut joint_format, &mut weight_format),
                    budget,
                )?;
                // Corner indices are u32: the last vertex must fit too.
                let base = u32::try_from(base + count)
                    .map(|_| base as u32)
                    .map_err(|_| {
                        ErrorKind::malformed(here(), "more than 4 billion vertices in one mesh")
                    })?;
                shared.insert(key, (base, count, skinned));
                (base, count, skinned)
            }
        };
        let tris = read_triangles(d, &here(), prim, mode, count, warnings)?;
        // Every stream, the skinning and the faces keep an index per corner.
        let per_corner = 1 + streams.len() as u64 + u64::from(influences > 0);
        budget.take(&here(), (tris.len() as u64).saturating_mul(per_corner))?;
        let part = mesh.parts.len() as u32;
        let first_corner = mesh.faces.indices.len();
        // Streams new in this primitive get ABSENT on every earlier corner.
        let backfill: usize = streams
            .values()
            .map(|s| first_corner.saturating_sub(s.indices.len()))
            .sum();
        budget.take(&here(), backfill as u64)?;
        // Reserved up front: grown by doubling, these arrays would hold up
        // to twice their size for the rest of the run.
        mesh.faces.indices.reserve(tris.len());
        mesh.faces.offsets.reserve(tris.len() / 3);
        mesh.face_parts.reserve(tris.len() / 3);
        for t in tris.chunks_exact(3) {
            mesh.faces.push(&[base + t[0], base + t[1], base + t[2]]);
            mesh.face_parts.push(part);
        }
        // Every stream is indexed like the positions, or ABSENT where this
        // primitive lacks it.
        let corners = &mesh.faces.indices[first_corner..];
        let present: Vec<String> = attrs.keys().cloned().collect();
        for (sem, s) in streams.iter_mut() {
            let has = match sem {
                Semantic::Morph { target, channel } => prim
                    .get("targets")
                    .and_then(|t| t.get(*target as usize))
                    .and_then(|t| t.get(morph_key(*channel)))
                    .is_some(),
                Semantic::Custom(n) => present.iter().any(|k| k == n),
                other => present.iter().any(|k| *k == semantic_key(other)),
            };
            s.indices.resize(first_corner, ABSENT);
            if has {
                s.indices.extend_from_slice(corners);
            } else {
                s.indices.resize(first_corner + corners.len(), ABSENT);
            }
        }
        if influences > 0 {
            skin_indices.resize(first_corner, ABSENT);
            if skinned {
                skin_indices.extend_from_slice(corners);
            } else {
                skin_indices.resize(first_corner + corners.len(), ABSENT);
            }
        }
        mesh.parts.push(Part {
            // glTF primitives have no name; wildlod writes a part's name
            // (an OBJ group) to `extras.name`.
            name: prim
                .pointer("/extras/name")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string(),
            material: prim
                .get("material")
                .and_then(Value::as_u64)
                .and_then(|m| u32::try_from(m).ok()),
        });
        source.part_primitives.push(pi);
    }
    let vertices = mesh.positions.len();
    let corners = mesh.faces.indices.len();
    let padding: usize = streams
        .values()
        .map(|s| {
            (vertices * s.components).saturating_sub(s.values.len())
                + corners.saturating_sub(s.indices.len())
        })
        .sum();
    budget.take(&format!("mesh {mi}"), padding as u64)?;
    for (sem, mut s) in streams {
        s.pad_to(vertices, fill_for(&sem));
        s.indices.resize(corners, ABSENT);
        mesh.attributes.push(Attribute {
            components: s.components as u8,
            values: s.values,
            indices: s.indices,
            format: s.format,
            semantic: sem,
        });
    }
    if influences > 0 {
        skin_joints.resize(vertices * influences, 0);
        skin_weights.resize(vertices * influences, 0.0);
        skin_indices.resize(corners, ABSENT);
        mesh.skinning = Some(Skinning {
            influences: influences as u8,
            joints: skin_joints,
            weights: skin_weights,
            indices: skin_indices,
            weight_format: weight_format.unwrap_or_default(),
            joint_format: joint_format.unwrap_or(ComponentFormat::U16),
        });
    }
    Ok((mesh, source))
}

/// Appends a primitive's positions and attribute values (not skinning).
#[allow(clippy::too_many_arguments)]
fn read_vertices(
    d: &Data<'_>,
    here: &str,
    pos_acc: usize,
    attrs: &serde_json::Map<String, Value>,
    targets: Option<&Value>,
    positions: &mut Vec<[f32; 3]>,
    streams: &mut BTreeMap<Semantic, StreamBuild>,
    budget: &mut Budget,
    warnings: &mut Vec<String>,
) -> Result<(), ErrorKind> {
    let pos = d.floats(pos_acc)?;
    if pos.components != 3 {
        return Err(ErrorKind::malformed(
            here,
            format!(
                "POSITION (accessor {pos_acc}) has {} components; glTF requires VEC3",
                pos.components
            ),
        ));
    }
    let count = pos.count();
    budget.take(here, pos.values.len() as u64)?;
    let base = positions.len();
    positions.reserve(count);
    for (e, p) in pos.values.chunks_exact(3).enumerate() {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(ErrorKind::malformed(
                here,
                format!("POSITION (accessor {pos_acc}) element {e} is not finite: {p:?}"),
            ));
        }
        positions.push([p[0], p[1], p[2]]);
    }
    let mut inputs: Vec<(Semantic, String, usize)> = Vec::new();
    for (k, v) in attrs {
        if let Slot::Stream(sem) = classify(k) {
            if let Some(a) = accessor_index(v) {
                inputs.push((sem, k.clone(), a));
            }
        }
    }
    if let Some(targets) = targets.and_then(Value::as_array) {
        for (t, target) in targets.iter().enumerate() {
            let Some(obj) = target.as_object() else {
                continue;
            };
            for (k, v) in obj {
                let channel = match k.as_str() {
                    "POSITION" => MorphChannel::Position,
                    "NORMAL" => MorphChannel::Normal,
                    "TANGENT" => MorphChannel::Tangent,
                    _ => {
                        warnings.push(format!(
                            "{here}: morph target {t} attribute {k} is not supported and is dropped"
                        ));
                        continue;
                    }
                };
                if let Some(a) = accessor_index(v) {
                    let sem = Semantic::Morph {
                        target: t as u32,
                        channel,
                    };
                    inputs.push((sem, format!("morph target {t} {k}"), a));
                }
            }
        }
    }
    for (sem, label, a) in inputs {
        let dec = d.floats(a)?;
        if dec.count() != count {
            return Err(ErrorKind::malformed(
                here,
                format!(
                    "accessor {a} ({label}) has {} elements, but POSITION (accessor {pos_acc}) has {count}",
                    dec.count()
                ),
            ));
        }
        match required_components(&sem) {
            Some(ok) if !ok.contains(&dec.components) => {
                return Err(ErrorKind::malformed(
                    here,
                    format!(
                        "accessor {a} ({label}) has {} components per element; glTF requires {}",
                        dec.components,
                        ok.iter()
                            .map(|n| n.to_string())
                            .collect::<Vec<_>>()
                            .join(" or ")
                    ),
                ));
            }
            None if dec.components > 4 => {
                warnings.push(format!(
                    "{here}: attribute {label} is a matrix, which the mesh model cannot hold; dropped"
                ));
                continue;
            }
            _ => {}
        }
        if let Some(e) = dec
            .values
            .chunks(dec.components)
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(ErrorKind::malformed(
                here,
                format!("accessor {a} ({label}) element {e} is not finite"),
            ));
        }
        let fill = fill_for(&sem);
        // This primitive's values, and the padding a new or widened stream
        // needs for the vertices before it.
        let (have, width) = streams
            .get(&sem)
            .map(|s| (s.values.len(), s.components.max(dec.components)))
            .unwrap_or((0, dec.components));
        let grown = ((base + count) * width).saturating_sub(have);
        budget.take(here, grown as u64)?;
        let s = streams.entry(sem).or_insert_with(|| StreamBuild {
            components: dec.components,
            values: Vec::new(),
            indices: Vec::new(),
            format: dec.format,
        });
        if s.format != dec.format {
            // Mixed encodings across primitives: only floats hold both.
            s.format = ComponentFormat::F32;
        }
        s.widen(dec.components, fill);
        s.pad_to(base, fill);
        let n = s.components;
        for v in dec.values.chunks(dec.components) {
            s.values.extend_from_slice(v);
            s.values
                .extend_from_slice(fill.get(v.len()..n).unwrap_or(&[]));
        }
    }
    Ok(())
}

/// Appends a primitive's skin entries (one per vertex) when it has
/// JOINTS_n/WEIGHTS_n; returns whether it does.
#[allow(clippy::too_many_arguments)]
fn read_skin_vertices(
    d: &Data<'_>,
    here: &str,
    attrs: &serde_json::Map<String, Value>,
    count: usize,
    influences: usize,
    base: usize,
    (joints, weights): (&mut Vec<u16>, &mut Vec<f32>),
    (joint_format, weight_format): (&mut Option<ComponentFormat>, &mut Option<ComponentFormat>),
    budget: &mut Budget,
) -> Result<bool, ErrorKind> {
    let mut sets: BTreeMap<u32, (Option<usize>, Option<usize>)> = BTreeMap::new();
    for (k, v) in attrs {
        match classify(k) {
            Slot::Joints(n) => sets.entry(n).or_default().0 = accessor_index(v),
            Slot::Weights(n) => sets.entry(n).or_default().1 = accessor_index(v),
            _ => {}
        }
    }
    if sets.is_empty() {
        return Ok(false);
    }
    // Joints and weights of this primitive's vertices and of the unskinned
    // ones before it.
    let slots = (base + count).saturating_mul(influences) as u64;
    budget.take(
        here,
        slots
            .saturating_mul(2)
            .saturating_sub(joints.len() as u64 * 2),
    )?;
    joints.resize(base * influences, 0);
    weights.resize(base * influences, 0.0);
    let start = joints.len();
    joints.resize(start + count * influences, 0);
    weights.resize(start + count * influences, 0.0);
    for (n, (ja, wa)) in sets {
        let (Some(ja), Some(wa)) = (ja, wa) else {
            return Err(ErrorKind::malformed(
                here,
                format!("JOINTS_{n} and WEIGHTS_{n} must come together; one is missing"),
            ));
        };
        let j = d.uints(ja)?;
        let w = d.floats(wa)?;
        for (a, label, dec_count, comps) in [
            (ja, "JOINTS", j.count(), j.components),
            (wa, "WEIGHTS", w.count(), w.components),
        ] {
            if dec_count != count || comps != 4 {
                return Err(ErrorKind::malformed(
                    here,
                    format!(
                        "accessor {a} ({label}_{n}) has {dec_count} elements of {comps} \
                         components; {count} VEC4 elements expected"
                    ),
                ));
            }
        }
        merge_format(joint_format, j.format, ComponentFormat::U16);
        merge_format(weight_format, w.format, ComponentFormat::F32);
        let slot = n as usize * 4;
        for v in 0..count {
            for k in 0..4 {
                let jv = j.values[v * 4 + k];
                let joint = u16::try_from(jv).map_err(|_| {
                    ErrorKind::malformed(
                        here,
                        format!("accessor {ja} (JOINTS_{n}) element {v} has joint {jv}"),
                    )
                })?;
                let at = start + v * influences + slot + k;
                joints[at] = joint;
                weights[at] = w.values[v * 4 + k];
            }
        }
    }
    Ok(true)
}

fn merge_format(slot: &mut Option<ComponentFormat>, f: ComponentFormat, mixed: ComponentFormat) {
    *slot = match *slot {
        None => Some(f),
        Some(old) if old == f => Some(f),
        Some(_) => Some(mixed),
    };
}

/// The triangles of a primitive as vertex indices local to it.
fn read_triangles(
    d: &Data<'_>,
    here: &str,
    prim: &Value,
    mode: u64,
    count: usize,
    warnings: &mut Vec<String>,
) -> Result<Vec<u32>, ErrorKind> {
    let indices: Vec<u32> = match prim.get("indices").and_then(accessor_index) {
        Some(a) => {
            let dec = d.uints(a)?;
            if dec.components != 1 {
                return Err(ErrorKind::malformed(
                    here,
                    format!("indices (accessor {a}) must be SCALAR"),
                ));
            }
            if let Some((k, &bad)) = dec
                .values
                .iter()
                .enumerate()
                .find(|(_, &i)| i as usize >= count)
            {
                return Err(ErrorKind::malformed(
                    here,
                    format!(
                        "index {k} of accessor {a} is {bad}, but the primitive has {count} vertices"
                    ),
                ));
            }
            dec.values
        }
        None => {
            let n = u32::try_from(count).map_err(|_| {
                ErrorKind::malformed(here, "more than 4 billion vertices in one primitive")
            })?;
            (0..n).collect()
        }
    };
    let n = indices.len();
    let tris = match mode {
        TRIANGLES => {
            if n % 3 != 0 {
                warnings.push(format!(
                    "{here}: {n} indices is not a multiple of 3; the last {} are ignored",
                    n % 3
                ));
            }
            let mut t = indices;
            t.truncate(n - n % 3);
            t
        }
        _ => {
            // glTF 2.0 §3.7.2.1 orders strip and fan triangles so that
            // they keep the winding of the first one. Triangles with a
            // repeated index are strip restarts, not geometry: dropped.
            let mut t = Vec::with_capacity(3 * n.saturating_sub(2));
            for i in 0..n.saturating_sub(2) {
                let tri = if mode == TRIANGLE_STRIP {
                    [indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]]
                } else {
                    [indices[i + 1], indices[i + 2], indices[0]]
                };
                if tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] {
                    t.extend_from_slice(&tri);
                }
            }
            t
        }
    };
    Ok(tris)
}

fn read_nodes(root: &Root) -> Vec<Node> {
    root.nodes
        .iter()
        .map(|n| Node {
            name: n.name.clone().unwrap_or_default(),
            matrix: match n.matrix {
                Some(m) => m,
                None => trs_matrix(
                    n.translation.unwrap_or([0.0; 3]),
                    n.rotation.map(|r| r.0).unwrap_or([0.0, 0.0, 0.0, 1.0]),
                    n.scale.unwrap_or([1.0; 3]),
                ),
            },
            mesh: n.mesh.map(|m| m.value() as u32),
            skin: n.skin.map(|s| s.value() as u32),
            children: n
                .children
                .iter()
                .flatten()
                .map(|c| c.value() as u32)
                .collect(),
        })
        .collect()
}

/// The displayed scene's roots: the default scene, else scene 0, else
/// every node without a parent.
fn read_roots(root: &Root) -> Vec<u32> {
    let scene = root
        .scene
        .and_then(|s| root.scenes.get(s.value()))
        .or_else(|| root.scenes.first());
    if let Some(s) = scene {
        return s.nodes.iter().map(|n| n.value() as u32).collect();
    }
    let mut has_parent = vec![false; root.nodes.len()];
    for n in &root.nodes {
        for c in n.children.iter().flatten() {
            if let Some(h) = has_parent.get_mut(c.value()) {
                *h = true;
            }
        }
    }
    (0..root.nodes.len() as u32)
        .filter(|&i| !has_parent[i as usize])
        .collect()
}

fn read_skins(d: &Data<'_>) -> Result<Vec<Skin>, ErrorKind> {
    let mut out = Vec::with_capacity(d.root.skins.len());
    for (si, s) in d.root.skins.iter().enumerate() {
        let joints: Vec<u32> = s.joints.iter().map(|j| j.value() as u32).collect();
        let mut ibm = Vec::new();
        if let Some(a) = s.inverse_bind_matrices {
            let dec = d.floats(a.value())?;
            if dec.components != 16 || dec.count() != joints.len() {
                return Err(ErrorKind::malformed(
                    format!("skin {si}"),
                    format!(
                        "inverseBindMatrices (accessor {}) holds {} elements of {} components; \
                         {} MAT4 expected, one per joint",
                        a.value(),
                        dec.count(),
                        dec.components,
                        joints.len()
                    ),
                ));
            }
            for m in dec.values.chunks_exact(16) {
                let mut a = [0.0f32; 16];
                a.copy_from_slice(m);
                ibm.push(a);
            }
        }
        out.push(Skin {
            name: s.name.clone().unwrap_or_default(),
            joints,
            inverse_bind_matrices: ibm,
            skeleton: s.skeleton.map(|k| k.value() as u32),
        });
    }
    Ok(out)
}

fn read_animations(d: &Data<'_>) -> Result<Vec<Animation>, ErrorKind> {
    // Samplers often share one input accessor: decode each once.
    let mut max_time: HashMap<usize, f32> = HashMap::new();
    let mut out = Vec::with_capacity(d.root.animations.len());
    for a in &d.root.animations {
        let mut duration = 0.0f32;
        for s in &a.samplers {
            let i = s.input.value();
            let t = match max_time.get(&i) {
                Some(&t) => t,
                None => {
                    let dec = d.floats(i)?;
                    let t = dec
                        .values
                        .iter()
                        .copied()
                        .filter(|v| v.is_finite())
                        .fold(0.0f32, f32::max);
                    max_time.insert(i, t);
                    t
                }
            };
            duration = duration.max(t);
        }
        let mut tracks = Vec::with_capacity(a.channels.len());
        for ch in &a.channels {
            let node = ch.target.node.value();
            let Some(sampler) = a.samplers.get(ch.sampler.value()) else {
                continue;
            };
            if node >= d.root.nodes.len() {
                continue;
            }
            use gltf_json::animation::{Interpolation as I, Property};
            let path = match ch.target.path {
                Checked::Valid(Property::Translation) => TrackPath::Translation,
                Checked::Valid(Property::Rotation) => TrackPath::Rotation,
                Checked::Valid(Property::Scale) => TrackPath::Scale,
                Checked::Valid(Property::MorphTargetWeights) => TrackPath::Weights,
                Checked::Invalid => continue,
            };
            let interpolation = match sampler.interpolation {
                Checked::Valid(I::Step) => Interpolation::Step,
                Checked::Valid(I::CubicSpline) => Interpolation::CubicSpline,
                _ => Interpolation::Linear,
            };
            tracks.push(Track {
                node: node as u32,
                path,
                interpolation,
                times: d.floats(sampler.input.value())?.values,
                values: d.floats(sampler.output.value())?.values,
            });
        }
        out.push(Animation {
            name: a.name.clone().unwrap_or_default(),
            channels: a.channels.len(),
            duration,
            tracks,
        });
    }
    Ok(out)
}

fn read_material(m: &gltf_json::Material) -> Material {
    let pbr = &m.pbr_metallic_roughness;
    let info = |i: &Option<gltf_json::texture::Info>| {
        i.as_ref().map(|i| TextureRef {
            texture: i.index.value() as u32,
            tex_coord: i.tex_coord,
        })
    };
    Material {
        name: m.name.clone().unwrap_or_default(),
        base_color: pbr.base_color_factor.0,
        base_color_texture: info(&pbr.base_color_texture),
        metallic: pbr.metallic_factor.0,
        roughness: pbr.roughness_factor.0,
        metallic_roughness_texture: info(&pbr.metallic_roughness_texture),
        normal_texture: m.normal_texture.as_ref().map(|t| TextureRef {
            texture: t.index.value() as u32,
            tex_coord: t.tex_coord,
        }),
        occlusion_texture: m.occlusion_texture.as_ref().map(|t| TextureRef {
            texture: t.index.value() as u32,
            tex_coord: t.tex_coord,
        }),
        emissive: m.emissive_factor.0,
        emissive_texture: info(&m.emissive_texture),
        alpha_mode: match m.alpha_mode {
            Checked::Valid(gltf_json::material::AlphaMode::Mask) => AlphaMode::Mask,
            Checked::Valid(gltf_json::material::AlphaMode::Blend) => AlphaMode::Blend,
            _ => AlphaMode::Opaque,
        },
        alpha_cutoff: m.alpha_cutoff.map(|c| c.0).unwrap_or(0.5),
        double_sided: m.double_sided,
    }
}

fn read_textures(
    d: &Data<'_>,
    dir: &Path,
    external: &mut Vec<std::path::PathBuf>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Texture>, ErrorKind> {
    let mut images: Vec<Option<ImageSource>> = vec![None; d.root.images.len()];
    let mut out = Vec::with_capacity(d.root.textures.len());
    for t in &d.root.textures {
        let ii = t.source.value();
        let image = d
            .root
            .images
            .get(ii)
            .ok_or_else(|| ErrorKind::malformed(format!("image {ii}"), "does not exist"))?;
        let source = match images.get(ii).cloned().flatten() {
            Some(s) => s,
            None => {
                let s = read_image(d, ii, image, dir, external, warnings)?;
                if let Some(slot) = images.get_mut(ii) {
                    *slot = Some(s.clone());
                }
                s
            }
        };
        out.push(Texture {
            name: t
                .name
                .clone()
                .or_else(|| image.name.clone())
                .unwrap_or_default(),
            source,
            sampler: t
                .sampler
                .and_then(|i| d.root.samplers.get(i.value()))
                .map(|s| Sampler {
                    wrap_u: wrap(&s.wrap_s),
                    wrap_v: wrap(&s.wrap_t),
                })
                .unwrap_or_default(),
        });
    }
    Ok(out)
}

/// A glTF wrapping mode; invalid values read as glTF's default, repeat.
fn wrap(w: &Checked<gltf_json::texture::WrappingMode>) -> Wrap {
    use gltf_json::texture::WrappingMode as W;
    match w {
        Checked::Valid(W::ClampToEdge) => Wrap::ClampToEdge,
        Checked::Valid(W::MirroredRepeat) => Wrap::MirroredRepeat,
        _ => Wrap::Repeat,
    }
}

fn read_image(
    d: &Data<'_>,
    ii: usize,
    image: &gltf_json::Image,
    dir: &Path,
    external: &mut Vec<std::path::PathBuf>,
    warnings: &mut Vec<String>,
) -> Result<ImageSource, ErrorKind> {
    let name = || format!("image {ii}");
    let declared = image.mime_type.as_ref().map(|m| m.0.clone());
    let mime = |bytes: &[u8], hint: Option<&str>| {
        hint.filter(|h| !h.is_empty())
            .map(str::to_string)
            .or(declared.clone())
            .or_else(|| uri::sniff_image_mime(bytes).map(str::to_string))
            .unwrap_or_else(|| "application/octet-stream".to_string())
    };
    if let Some(u) = &image.uri {
        return Ok(match uri::classify(u) {
            UriKind::Data {
                base64: Some(p),
                mime: m,
            } => {
                let bytes = uri::decode_base64(p).map_err(|e| ErrorKind::malformed(name(), e))?;
                let mime_type = mime(&bytes, Some(m));
                ImageSource::Embedded { bytes, mime_type }
            }
            UriKind::Data { base64: None, .. } => {
                return Err(ErrorKind::malformed(
                    name(),
                    "its data URI is not base64-encoded",
                ))
            }
            UriKind::Remote => {
                warnings.push(format!(
                    "{}: remote URI {u:?} is not fetched; it is kept as is",
                    name()
                ));
                ImageSource::Path(u.into())
            }
            UriKind::Relative(rel) => {
                let p = uri::resolve(dir, &rel);
                // Missing: a warning (the output keeps the URI). There but
                // not a regular file (a FIFO would block the writer that
                // embeds it): refused now.
                match crate::regular::not_regular(&p) {
                    Ok(()) => {}
                    Err(ErrorKind::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => {
                        warnings.push(format!("{}: file {} not found", name(), p.display()));
                    }
                    Err(e) => return Err(ErrorKind::malformed(name(), e.to_string())),
                }
                external.push(p.clone());
                ImageSource::Path(p)
            }
        });
    }
    if let Some(v) = image.buffer_view {
        let bytes = d.view(v.value())?.to_vec();
        let mime_type = mime(&bytes, None);
        return Ok(ImageSource::Embedded { bytes, mime_type });
    }
    Err(ErrorKind::malformed(
        name(),
        "has neither uri nor bufferView",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bytes of the source buffers a document keeps for writing back, and
    /// the buffers' full length.
    fn kept(rel: &str) -> Option<(usize, usize, Value)> {
        let c = wildlod_testkit::corpus("documents_keep_only_the_bytes_a_write_copies")?;
        let doc = crate::read(c.join(rel)).unwrap_or_else(|e| panic!("{e}"));
        let pass = doc.gltf.unwrap_or_else(|| panic!("{rel}: no passthrough"));
        let total = pass.json["buffers"]
            .as_array()
            .map(|b| {
                b.iter()
                    .filter_map(|b| b["byteLength"].as_u64())
                    .sum::<u64>()
            })
            .unwrap_or(0) as usize;
        let kept = pass.buffers.iter().map(SourceBuffer::kept_bytes).sum();
        Some((kept, total, pass.json))
    }

    /// Total length of the views of images, animation curves and inverse
    /// bind matrices: what a write copies from a file whose primitives are
    /// all triangles.
    fn copied_by_meaning(json: &Value) -> usize {
        let list = |v: &Value| v.as_array().cloned().unwrap_or_default();
        let view_of = |acc: &Value| {
            acc.as_u64()
                .and_then(|a| json["accessors"][a as usize]["bufferView"].as_u64())
        };
        let mut views: Vec<u64> = list(&json["images"])
            .iter()
            .filter_map(|i| i["bufferView"].as_u64())
            .collect();
        for a in list(&json["animations"]) {
            for s in list(&a["samplers"]) {
                views.extend(view_of(&s["input"]));
                views.extend(view_of(&s["output"]));
            }
        }
        for s in list(&json["skins"]) {
            views.extend(view_of(&s["inverseBindMatrices"]));
        }
        views.sort_unstable();
        views.dedup();
        views
            .iter()
            .filter_map(|&v| json["bufferViews"][v as usize]["byteLength"].as_u64())
            .sum::<u64>() as usize
    }

    #[test]
    fn documents_keep_only_the_bytes_a_write_copies() {
        // A mesh and nothing else: the decoded mesh is all a write needs.
        let Some((dragon, total, _)) = kept("large/dragon_vrip.glb") else {
            return;
        };
        assert!(total > 10_000_000);
        assert_eq!(dragon, 0);
        // The truck's embedded image and its wheels' animation curves, and
        // CesiumMan's image, skin and walk are copied as they are; their
        // meshes are not.
        for rel in ["textured/CesiumMilkTruck.glb", "skinned/CesiumMan.glb"] {
            let (kept, total, json) = kept(rel).unwrap_or_default();
            let copied = copied_by_meaning(&json);
            assert!(copied > 0 && copied < total, "{rel}: {copied} of {total}");
            assert_eq!(kept, copied, "{rel}");
        }
    }

    #[test]
    fn attribute_names_classify_into_semantics() {
        assert!(matches!(classify("POSITION"), Slot::Position));
        assert!(matches!(
            classify("TEXCOORD_1"),
            Slot::Stream(Semantic::TexCoord(1))
        ));
        assert!(matches!(classify("JOINTS_0"), Slot::Joints(0)));
        assert!(matches!(classify("WEIGHTS_2"), Slot::Weights(2)));
        assert!(matches!(classify("_ID"), Slot::Stream(Semantic::Custom(n)) if n == "_ID"));
    }
}
