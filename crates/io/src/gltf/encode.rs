//! [`Mesh`] → glTF primitives: one per non-empty part, polygons cut into
//! triangles (`shapes::triangulate`), vertices made of the distinct corner combinations, and
//! every stream encoded back in its source format where glTF allows it.

use std::borrow::Cow;

use serde_json::{json, Map, Value};
use wildlod_mesh::{shapes, Attribute, ComponentFormat, Mesh, MorphChannel, Semantic, ABSENT};

use super::accessor::{
    component_of, push_raw, raw, representable, type_name, vertex_stride, Component,
};
use super::attribute_keys::morph_key;
use super::bin::{Bin, ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER};
use crate::ErrorKind;

/// Encoding choices for one write.
pub(crate) struct EncodeOptions {
    /// Whether KHR_mesh_quantization encodings may be used (the source
    /// declared the extension).
    pub quantization: bool,
}

/// Primitives of one mesh, each with the part it came from.
pub(crate) struct Encoded {
    pub primitives: Vec<(usize, Value)>,
    /// Whether an attribute used an encoding only KHR_mesh_quantization allows.
    pub used_quantization: bool,
}

/// What encoding the parts of one mesh had to do.
#[derive(Default)]
struct Stats {
    used_quantization: bool,
    /// Zero-length normals and tangents replaced by a default direction.
    defaulted_vectors: usize,
}

/// glTF requires unit normals and tangent directions (and a ±1 tangent
/// sign). Simplified meshes interpolate them, so vectors clearly off unit
/// length are renormalized; vectors already unit within float noise are
/// left bit for bit. Zero vectors cannot be normalized and become
/// `fallback`. Returns how many did.
fn make_unit(values: &mut [f32], comps: usize, fallback: &[f32; 4]) -> usize {
    // Well inside the Khronos validator's tolerance, well above f32 noise.
    const TOLERANCE: f64 = 1e-4;
    let mut defaulted = 0;
    for v in values.chunks_exact_mut(comps) {
        let len = (v[..3].iter().map(|&x| x as f64 * x as f64).sum::<f64>()).sqrt();
        if len < 1e-12 {
            v[..3].copy_from_slice(&fallback[..3]);
            defaulted += 1;
        } else if (len - 1.0).abs() > TOLERANCE {
            for x in &mut v[..3] {
                *x = (*x as f64 / len) as f32;
            }
        }
        if comps == 4 && v[3].abs() != 1.0 {
            v[3] = if v[3] < 0.0 { -1.0 } else { 1.0 };
        }
    }
    defaulted
}

/// The glTF attribute name of a stream (morph channels excluded).
fn attribute_name(s: &Semantic) -> String {
    match s {
        Semantic::TexCoord(n) => format!("TEXCOORD_{n}"),
        Semantic::Normal => "NORMAL".into(),
        Semantic::Tangent => "TANGENT".into(),
        Semantic::Color(n) => format!("COLOR_{n}"),
        // glTF requires application-specific names to start with '_'.
        Semantic::Custom(n) if n.starts_with('_') => n.clone(),
        Semantic::Custom(n) => format!("_{n}"),
        Semantic::Morph { channel, .. } => morph_key(*channel).into(),
    }
}

/// Components glTF stores for a stream of `have` components.
fn written_components(s: &Semantic, have: usize) -> usize {
    match s {
        Semantic::TexCoord(_) => 2,
        Semantic::Normal | Semantic::Morph { .. } => 3,
        Semantic::Tangent => 4,
        Semantic::Color(_) => {
            if have >= 4 {
                4
            } else {
                3
            }
        }
        Semantic::Custom(_) => have.clamp(1, 4),
    }
}

/// The value written where a corner has no value, or a component is missing.
fn default_value(s: &Semantic) -> [f32; 4] {
    match s {
        Semantic::Normal => [0.0, 0.0, 1.0, 0.0],
        Semantic::Tangent => [1.0, 0.0, 0.0, 1.0],
        Semantic::Color(_) => [1.0; 4],
        _ => [0.0; 4],
    }
}

/// Which encodings glTF allows for a stream: `(core, with quantization)`.
fn allowed(s: &Semantic, f: ComponentFormat) -> (bool, bool) {
    use ComponentFormat as F;
    let core = |list: &[F]| list.contains(&f);
    match s {
        Semantic::TexCoord(_) => (
            core(&[F::F32, F::U8Norm, F::U16Norm]),
            core(&[F::I8, F::I8Norm, F::U8, F::I16, F::I16Norm, F::U16]),
        ),
        Semantic::Color(_) => (core(&[F::F32, F::U8Norm, F::U16Norm]), false),
        Semantic::Normal | Semantic::Tangent => (f == F::F32, core(&[F::I8Norm, F::I16Norm])),
        Semantic::Morph {
            channel: MorphChannel::Position,
            ..
        } => (f == F::F32, core(&[F::I8, F::I8Norm, F::I16, F::I16Norm])),
        Semantic::Morph { .. } => (f == F::F32, core(&[F::I8Norm, F::I16Norm])),
        // Application-specific attributes may use any type but unsigned int.
        Semantic::Custom(_) => (f != F::U32, false),
    }
}

/// Encodes every non-empty part of `mesh` as a primitive.
pub(crate) fn encode_mesh(
    mesh: &Mesh,
    mi: usize,
    bin: &mut Bin,
    opts: &EncodeOptions,
    warnings: &mut Vec<String>,
) -> Result<Encoded, ErrorKind> {
    let mesh: Cow<Mesh> = if mesh.faces.iter().all(|f| f.len() == 3) {
        Cow::Borrowed(mesh)
    } else {
        Cow::Owned(shapes::triangulate(mesh))
    };
    let mut by_part: Vec<Vec<usize>> = vec![Vec::new(); mesh.parts.len()];
    for (f, &p) in mesh.face_parts.iter().enumerate() {
        if let Some(list) = by_part.get_mut(p as usize) {
            list.push(f);
        }
    }
    let mut names = std::collections::BTreeSet::new();
    let mut streams: Vec<&Attribute> = Vec::new();
    for a in &mesh.attributes {
        if matches!(a.semantic, Semantic::Morph { .. }) || names.insert(attribute_name(&a.semantic))
        {
            streams.push(a);
        } else {
            warnings.push(format!(
                "mesh {mi}: a second attribute named {} is not written",
                attribute_name(&a.semantic)
            ));
        }
    }
    let mut primitives = Vec::new();
    let mut stats = Stats::default();
    let mut scratch = vec![u32::MAX; mesh.positions.len()];
    for (part, faces) in by_part.iter().enumerate() {
        if faces.is_empty() {
            continue;
        }
        let prim = encode_part(
            &mesh,
            mi,
            part,
            faces,
            &streams,
            bin,
            opts,
            &mut scratch,
            &mut stats,
        )?;
        primitives.push((part, prim));
    }
    if stats.defaulted_vectors > 0 {
        warnings.push(format!(
            "mesh {mi}: {} zero-length normals or tangents written as a default direction",
            stats.defaulted_vectors
        ));
    }
    Ok(Encoded {
        primitives,
        used_quantization: stats.used_quantization,
    })
}

/// The corner that stands for each vertex of a primitive, and every
/// corner's vertex.
struct Vertices {
    representative: Vec<usize>,
    corner_vertex: Vec<u32>,
}

/// Distinct (position, stream values, skin entry) combinations over the
/// corners, numbered in ascending key order (position first), so a mesh
/// read from glTF keeps its vertex order.
fn unique_vertices(
    mesh: &Mesh,
    corners: &[usize],
    streams: &[&Attribute],
    skin: bool,
    scratch: &mut [u32],
) -> Vertices {
    let pos = &mesh.faces.indices;
    let skin_idx = mesh.skinning.as_ref().filter(|_| skin).map(|s| &s.indices);
    let like_positions = corners.iter().all(|&c| {
        streams.iter().all(|a| a.indices[c] == pos[c]) && skin_idx.map_or(true, |s| s[c] == pos[c])
    });
    if like_positions {
        // Fast path: the key is the position alone.
        let mut used: Vec<u32> = corners.iter().map(|&c| pos[c]).collect();
        used.sort_unstable();
        used.dedup();
        let mut representative = vec![0usize; used.len()];
        for (k, &p) in used.iter().enumerate() {
            scratch[p as usize] = k as u32;
        }
        let corner_vertex: Vec<u32> = corners.iter().map(|&c| scratch[pos[c] as usize]).collect();
        for (i, &c) in corners.iter().enumerate() {
            representative[corner_vertex[i] as usize] = c;
        }
        for &p in &used {
            scratch[p as usize] = u32::MAX;
        }
        return Vertices {
            representative,
            corner_vertex,
        };
    }
    let width = 1 + streams.len() + usize::from(skin_idx.is_some());
    let mut keys: Vec<u32> = Vec::with_capacity(corners.len() * width);
    for &c in corners {
        keys.push(pos[c]);
        keys.extend(streams.iter().map(|a| a.indices[c]));
        if let Some(s) = skin_idx {
            keys.push(s[c]);
        }
    }
    let key = |i: usize| &keys[i * width..(i + 1) * width];
    let mut order: Vec<usize> = (0..corners.len()).collect();
    order.sort_by(|&a, &b| key(a).cmp(key(b)).then(a.cmp(&b)));
    let mut corner_vertex = vec![0u32; corners.len()];
    let mut representative = Vec::new();
    let mut prev: Option<usize> = None;
    for &i in &order {
        if prev.map_or(true, |p| key(p) != key(i)) {
            representative.push(corners[i]);
        }
        corner_vertex[i] = (representative.len() - 1) as u32;
        prev = Some(i);
    }
    Vertices {
        representative,
        corner_vertex,
    }
}

#[allow(clippy::too_many_arguments)]
fn encode_part(
    mesh: &Mesh,
    mi: usize,
    part: usize,
    faces: &[usize],
    streams: &[&Attribute],
    bin: &mut Bin,
    opts: &EncodeOptions,
    scratch: &mut [u32],
    stats: &mut Stats,
) -> Result<Value, ErrorKind> {
    let corners: Vec<usize> = faces
        .iter()
        .flat_map(|&f| mesh.faces.corner_range(f))
        .collect();
    // A stream is written when some corner of the part has it; morph
    // targets always, since every primitive of a mesh needs the same targets.
    let present: Vec<&Attribute> = streams
        .iter()
        .copied()
        .filter(|a| {
            matches!(a.semantic, Semantic::Morph { .. })
                || corners.iter().any(|&c| a.indices[c] != ABSENT)
        })
        .collect();
    let skin = mesh
        .skinning
        .as_ref()
        .filter(|s| corners.iter().any(|&c| s.indices[c] != ABSENT));
    let verts = unique_vertices(mesh, &corners, &present, skin.is_some(), scratch);
    let n = verts.representative.len();
    let too_many = || {
        ErrorKind::Unsupported(format!(
            "mesh {mi} part {part}: {n} vertices is more than a glTF primitive can index"
        ))
    };
    if n >= u32::MAX as usize {
        return Err(too_many());
    }

    let mut attributes = Map::new();
    // POSITION: always f32 (the model keeps no source encoding for it).
    let positions: Vec<f32> = verts
        .representative
        .iter()
        .flat_map(|&c| mesh.positions[mesh.faces.indices[c] as usize])
        .collect();
    let a = write_stream(bin, &positions, 3, ComponentFormat::F32, true);
    attributes.insert("POSITION".into(), json!(a));

    let mut targets: Vec<Map<String, Value>> = Vec::new();
    for attr in &present {
        let comps = written_components(&attr.semantic, attr.components as usize);
        let fill = default_value(&attr.semantic);
        let have = attr.components as usize;
        let mut values = Vec::with_capacity(n * comps);
        for &c in &verts.representative {
            let v = match attr.indices[c] {
                ABSENT => None,
                i => attr.values.get(i as usize * have..(i as usize + 1) * have),
            };
            for k in 0..comps {
                let x = match v {
                    Some(v) if k < v.len() => v[k],
                    // Morph deltas default to no displacement.
                    _ if matches!(attr.semantic, Semantic::Morph { .. }) => 0.0,
                    _ => fill[k],
                };
                values.push(x);
            }
        }
        let (core, ext) = allowed(&attr.semantic, attr.format);
        let fits = (core || (ext && opts.quantization))
            && values.iter().all(|&v| representable(v, attr.format));
        let format = if fits {
            attr.format
        } else {
            ComponentFormat::F32
        };
        if fits && !core {
            stats.used_quantization = true;
        }
        if format == ComponentFormat::F32
            && matches!(attr.semantic, Semantic::Normal | Semantic::Tangent)
        {
            stats.defaulted_vectors += make_unit(&mut values, comps, &fill);
        }
        let bounds = matches!(
            attr.semantic,
            Semantic::Morph {
                channel: MorphChannel::Position,
                ..
            }
        );
        let a = write_stream(bin, &values, comps, format, bounds);
        match &attr.semantic {
            Semantic::Morph { target, channel } => {
                let t = *target as usize;
                if targets.len() <= t {
                    targets.resize(t + 1, Map::new());
                }
                targets[t].insert(morph_key(*channel).into(), json!(a));
            }
            s => {
                attributes.insert(attribute_name(s), json!(a));
            }
        }
    }
    if let Some(s) = skin {
        write_skin(bin, s, &verts.representative, &mut attributes)?;
    }

    let max_index = n.saturating_sub(1);
    // glTF forbids the largest value of the index type (primitive restart).
    let (component, size) = if max_index < u16::MAX as usize {
        (Component::U16, 2)
    } else {
        (Component::U32, 4)
    };
    let mut bytes = Vec::with_capacity(verts.corner_vertex.len() * size);
    for &v in &verts.corner_vertex {
        push_raw(&mut bytes, v as f64, component);
    }
    let view = bin.view(&bytes, None, Some(ELEMENT_ARRAY_BUFFER));
    let indices = bin.accessor(
        view,
        component,
        false,
        verts.corner_vertex.len(),
        "SCALAR",
        None,
    );

    let mut prim = Map::new();
    prim.insert("attributes".into(), Value::Object(attributes));
    prim.insert("indices".into(), json!(indices));
    if let Some(p) = mesh.parts.get(part) {
        if let Some(m) = p.material {
            prim.insert("material".into(), json!(m));
        }
        // Keeps OBJ group names through glTF; the reader looks here.
        if !p.name.is_empty() {
            prim.insert("extras".into(), json!({ "name": p.name }));
        }
    }
    if !targets.is_empty() {
        prim.insert(
            "targets".into(),
            Value::Array(targets.into_iter().map(Value::Object).collect()),
        );
    }
    Ok(Value::Object(prim))
}

/// Writes one vertex stream in its own view (stride padded to 4 bytes);
/// returns the accessor index.
fn write_stream(
    bin: &mut Bin,
    values: &[f32],
    comps: usize,
    format: ComponentFormat,
    bounds: bool,
) -> usize {
    let (component, normalized) = component_of(format);
    let stride = vertex_stride(component, comps);
    let count = values.len() / comps;
    let mut bytes = Vec::with_capacity(count * stride);
    let mut lo = vec![f64::INFINITY; comps];
    let mut hi = vec![f64::NEG_INFINITY; comps];
    for v in values.chunks_exact(comps) {
        for (k, &x) in v.iter().enumerate() {
            let r = raw(x, format);
            lo[k] = lo[k].min(r);
            hi[k] = hi[k].max(r);
            push_raw(&mut bytes, r, component);
        }
        bytes.resize(bytes.len().div_ceil(4) * 4, 0);
    }
    let explicit = (stride != comps * component.size()).then_some(stride);
    let view = bin.view(&bytes, explicit, Some(ARRAY_BUFFER));
    let bounds = (bounds && count > 0).then_some((lo, hi));
    bin.accessor(view, component, normalized, count, type_name(comps), bounds)
}

/// Writes JOINTS_n / WEIGHTS_n sets of four influences.
fn write_skin(
    bin: &mut Bin,
    s: &wildlod_mesh::Skinning,
    representative: &[usize],
    attributes: &mut Map<String, Value>,
) -> Result<(), ErrorKind> {
    let k = s.influences as usize;
    let sets = k.div_ceil(4);
    let n = representative.len();
    let mut joints = vec![0u16; n * sets * 4];
    let mut weights = vec![0f32; n * sets * 4];
    for (v, &c) in representative.iter().enumerate() {
        let e = s.indices[c];
        if e == ABSENT {
            continue;
        }
        let r = e as usize * k..(e as usize + 1) * k;
        if let (Some(j), Some(w)) = (s.joints.get(r.clone()), s.weights.get(r)) {
            joints[v * sets * 4..v * sets * 4 + k].copy_from_slice(j);
            weights[v * sets * 4..v * sets * 4 + k].copy_from_slice(w);
        }
    }
    let joint_format = if s.joint_format == ComponentFormat::U8 && joints.iter().all(|&j| j <= 255)
    {
        ComponentFormat::U8
    } else {
        ComponentFormat::U16
    };
    let weight_format = match s.weight_format {
        f @ (ComponentFormat::U8Norm | ComponentFormat::U16Norm)
            if weights.iter().all(|&w| representable(w, f)) =>
        {
            f
        }
        _ => ComponentFormat::F32,
    };
    let raw_weights = quantize_weights(&weights, sets * 4, weight_format);
    // A weight that rounds to zero in the file's encoding leaves its slot
    // unused: the validator expects joint 0 there
    // (ACCESSOR_JOINTS_USED_ZERO_WEIGHT). Slots whose weight was zero
    // already are written as read, so that unchanged files round-trip.
    for ((j, &raw), &w) in joints.iter_mut().zip(&raw_weights).zip(&weights) {
        if raw == 0.0 && w != 0.0 {
            *j = 0;
        }
    }
    for set in 0..sets {
        let pick = |i: usize, v: usize| v * sets * 4 + set * 4 + i;
        let jv: Vec<f32> = (0..n)
            .flat_map(|v| (0..4).map(move |i| (v, i)))
            .map(|(v, i)| joints[pick(i, v)] as f32)
            .collect();
        let a = write_stream(bin, &jv, 4, joint_format, false);
        attributes.insert(format!("JOINTS_{set}"), json!(a));
        let (component, normalized) = component_of(weight_format);
        let stride = vertex_stride(component, 4);
        let mut bytes = Vec::with_capacity(n * stride);
        for v in 0..n {
            for i in 0..4 {
                push_raw(&mut bytes, raw_weights[pick(i, v)], component);
            }
        }
        let view = bin.view(&bytes, None, Some(ARRAY_BUFFER));
        let a = bin.accessor(view, component, normalized, n, "VEC4", None);
        attributes.insert(format!("WEIGHTS_{set}"), json!(a));
    }
    Ok(())
}

/// Raw weight values; for normalized integer encodings the rounding error
/// of an entry is moved onto its largest weight, so that weights that
/// summed to one still do exactly (renderers and validators expect it).
fn quantize_weights(weights: &[f32], per_entry: usize, format: ComponentFormat) -> Vec<f64> {
    let mut out: Vec<f64> = weights.iter().map(|&w| raw(w, format)).collect();
    let full = match format {
        ComponentFormat::U8Norm => 255.0,
        ComponentFormat::U16Norm => 65535.0,
        _ => return out,
    };
    for (entry, w) in out.chunks_mut(per_entry).zip(weights.chunks(per_entry)) {
        let sum: f64 = w.iter().map(|&x| x as f64).sum();
        if (sum - 1.0).abs() > 1e-2 {
            continue;
        }
        let diff = full - entry.iter().sum::<f64>();
        if diff == 0.0 {
            continue;
        }
        let big = (0..entry.len()).fold(0, |b, i| if entry[i] > entry[b] { i } else { b });
        entry[big] = (entry[big] + diff).clamp(0.0, full);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::Faces;

    #[test]
    fn off_unit_normals_are_renormalized_and_unit_ones_left_bit_for_bit() {
        let third = 1.0f32 / 3.0f32.sqrt();
        let mut v = vec![third, third, third, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0];
        let before = v[..3].to_vec();
        let defaulted = make_unit(&mut v, 3, &[0.0, 0.0, 1.0, 0.0]);
        assert_eq!(defaulted, 1);
        assert_eq!(&v[..3], &before[..]);
        assert_eq!(&v[3..], &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
        let mut t = vec![0.6, 0.0, 0.0, -0.3];
        make_unit(&mut t, 4, &[1.0, 0.0, 0.0, 1.0]);
        assert_eq!(t, vec![1.0, 0.0, 0.0, -1.0]);
    }

    #[test]
    fn quantized_weights_keep_summing_to_one() {
        // Thirds do not round to a sum of 255 on their own (85 · 3 = 255,
        // but 0.3/0.3/0.4 gives 77 + 77 + 102 = 256).
        let w = [0.3f32, 0.3, 0.4, 0.0];
        let q = quantize_weights(&w, 4, ComponentFormat::U8Norm);
        assert_eq!(q.iter().sum::<f64>(), 255.0);
        assert_eq!(q[2], 101.0);
    }

    #[test]
    fn corners_sharing_position_but_not_uv_become_two_vertices_in_position_order() {
        // Two triangles over positions 0..4; position 1 has UV 0 in one
        // triangle and UV 3 in the other.
        let mut m = Mesh::from_polygons(
            vec![[0.0; 3]; 4],
            Faces::from_triangles(&[2, 1, 0, 1, 3, 2]),
        );
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: vec![0.0; 8],
            indices: vec![2, 0, 0, 3, 1, 2],
            format: ComponentFormat::F32,
        });
        let corners: Vec<usize> = (0..6).collect();
        let streams = [&m.attributes[0]];
        let mut scratch = vec![u32::MAX; 4];
        let v = unique_vertices(&m, &corners, &streams, false, &mut scratch);
        // Keys (pos, uv): (0,0) (1,0) (1,3) (2,2) (3,1)
        assert_eq!(v.representative.len(), 5);
        assert_eq!(v.corner_vertex, vec![3, 1, 0, 2, 4, 3]);
    }

    #[test]
    fn streams_indexed_like_positions_keep_position_order_and_drop_unused() {
        let m = Mesh::from_triangles(vec![[0.0; 3]; 5], &[4, 2, 3]);
        let mut scratch = vec![u32::MAX; 5];
        let v = unique_vertices(&m, &[0, 1, 2], &[], false, &mut scratch);
        assert_eq!(v.representative, vec![1, 2, 0]);
        assert_eq!(v.corner_vertex, vec![2, 0, 1]);
        assert!(scratch.iter().all(|&s| s == u32::MAX));
    }
}
