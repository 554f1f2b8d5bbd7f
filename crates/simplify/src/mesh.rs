//! Simplifying a [`Mesh`]: its faces and every per-corner stream through
//! [`crate::simplify_with_attributes`], each stream weighted by its meaning
//! ([`crate::AttributeOptions`]), and the result put back into a mesh.

use glam::DVec3;
use wildlod_mesh::{Attribute, Mesh, MorphChannel, Semantic, Skinning, ABSENT};

use crate::assemble::uv_health::uv_damage;
use crate::error::Error;
use crate::input::{
    AttributeInput, AttributeStream, FittedStream, MorphStream, SkinStream, StreamKind,
};
use crate::options::{InputData, NormalMode, Options};
use crate::report::Report;
use crate::simplify::simplify_with_attributes_and_progress;

/// Simplifies a mesh with its attributes fitted, not copied (Hoppe 1999;
/// Knodt 2024 §3): every UV set, normal, tangent, color and morph delta is
/// evaluated at the simplified positions from the linear functionals of the
/// faces merged into it, seams are kept (see [`crate::SeamPolicy`]), and
/// skin weights end as one influence set per position. Faces keep their
/// part. Values no corner uses any more are dropped.
pub fn simplify_mesh(mesh: &Mesh, options: &Options) -> Result<(Mesh, Report), Error> {
    simplify_mesh_with_progress(mesh, options, &|_| {})
}

/// The stream settings a semantic gets: weight, seams, kind.
fn stream_settings(semantic: &Semantic, options: &Options) -> (f64, bool, StreamKind) {
    let a = &options.attributes;
    match semantic {
        Semantic::TexCoord(_) => (a.tex_coord_weight, true, StreamKind::TexCoord),
        Semantic::Normal => (a.normal_weight, true, StreamKind::Direction),
        // Tangents follow the UV layout's seams and are not steered by:
        // they follow from the UVs and normals.
        Semantic::Tangent => (0.0, true, StreamKind::Direction),
        Semantic::Color(_) => (a.color_weight, true, StreamKind::Color),
        // Deltas follow the same fit as positions; a morph target is no
        // reason to keep or move a vertex.
        Semantic::Morph { .. } => (0.0, false, StreamKind::Generic),
        Semantic::Custom(_) => (0.0, false, StreamKind::Carried),
    }
}

/// [`simplify_mesh`] with a progress callback (see
/// [`crate::simplify_polygons_with_progress`]).
pub fn simplify_mesh_with_progress(
    mesh: &Mesh,
    options: &Options,
    progress: &dyn Fn(f64),
) -> Result<(Mesh, Report), Error> {
    mesh.validate()
        .map_err(|e| Error::InvalidMesh(e.to_string()))?;
    let joints = vertex_joints(mesh);
    let see_through = see_through_faces(mesh, options);
    let morphs = if options.attributes.morph_poses && options.data.morph_targets.is_empty() {
        morph_targets(mesh)
    } else {
        Vec::new()
    };
    let with_joints;
    let options = if (joints.is_empty() || !options.data.vertex_joints.is_empty())
        && see_through.is_empty()
        && morphs.is_empty()
    {
        options
    } else {
        with_joints = Options {
            data: InputData {
                vertex_joints: if options.data.vertex_joints.is_empty() {
                    joints
                } else {
                    options.data.vertex_joints.clone()
                },
                morph_targets: if morphs.is_empty() {
                    options.data.morph_targets.clone()
                } else {
                    morphs
                },
                see_through_faces: if see_through.is_empty() {
                    options.data.see_through_faces.clone()
                } else {
                    see_through
                },
                ..options.data.clone()
            },
            ..options.clone()
        };
        &with_joints
    };
    // UV sets steer only where a texture samples them: a set read on some
    // faces and not others goes in as two streams, the read corners (which
    // steer) and the others (fitted only), joined again below.
    let steer = steering_faces(mesh, options);
    let split: Vec<Option<[Vec<u32>; 2]>> = mesh
        .attributes
        .iter()
        .zip(&steer)
        .map(|(a, faces)| {
            let faces = faces.as_ref().filter(|f| f.contains(&true))?;
            let mut parts = [a.indices.clone(), a.indices.clone()];
            for (f, &read) in faces.iter().enumerate() {
                let corners = mesh.faces.offsets[f] as usize..mesh.faces.offsets[f + 1] as usize;
                parts[usize::from(read)][corners].fill(ABSENT);
            }
            Some(parts)
        })
        .collect();
    let mut streams: Vec<AttributeStream<'_>> = Vec::new();
    // Per mesh attribute, its streams: one, or (read, unread); morph
    // deltas go to their own sparse fit (`morphs`, `morph_of`).
    let mut stream_of: Vec<(usize, Option<usize>)> = Vec::new();
    let mut morphs: Vec<MorphStream<'_>> = Vec::new();
    let mut morph_of: Vec<Option<usize>> = Vec::new();
    for ((a, faces), parts) in mesh.attributes.iter().zip(&steer).zip(&split) {
        if matches!(a.semantic, Semantic::Morph { .. }) && a.components == 3 {
            morph_of.push(Some(morphs.len()));
            stream_of.push((usize::MAX, None));
            morphs.push(MorphStream {
                values: &a.values,
                indices: &a.indices,
            });
            continue;
        }
        morph_of.push(None);
        let (weight, seams, kind) = stream_settings(&a.semantic, options);
        let first = streams.len();
        match parts {
            Some([read, unread]) => {
                stream_of.push((first, Some(first + 1)));
                streams.push(stream(a, read, weight, seams, kind));
                streams.push(stream(a, unread, 0.0, seams, kind));
            }
            None => {
                // Read nowhere: fitted only.
                let weight = if faces.is_some() { 0.0 } else { weight };
                stream_of.push((first, None));
                streams.push(stream(a, &a.indices, weight, seams, kind));
            }
        }
    }
    let skin = mesh.skinning.as_ref().map(|s| SkinStream {
        influences: s.influences as usize,
        joints: &s.joints,
        weights: &s.weights,
        indices: &s.indices,
        weight: options.attributes.skin_weight,
    });
    let groups = material_groups(mesh);
    let input = AttributeInput {
        streams,
        skin,
        morphs,
        face_groups: &groups,
    };
    let s = simplify_with_attributes_and_progress(
        &mesh.positions,
        &mesh.faces,
        &input,
        options,
        progress,
    )?;
    let mut out = Mesh {
        name: mesh.name.clone(),
        positions: s.positions,
        faces: s.faces,
        face_parts: s
            .face_origin
            .iter()
            .map(|&f| mesh.face_parts[f as usize])
            .collect(),
        parts: mesh.parts.clone(),
        // Each stream's values and indices are the fitted ones, set below:
        // copying the input's first would double the peak on a mesh of
        // many streams (52 blend shapes: 150 MB).
        attributes: mesh
            .attributes
            .iter()
            .map(|a| Attribute {
                semantic: a.semantic.clone(),
                components: a.components,
                values: Vec::new(),
                indices: Vec::new(),
                format: a.format,
            })
            .collect(),
        skinning: None,
    };
    let mut fitted_streams: Vec<Option<FittedStream>> =
        s.attributes.into_iter().map(Some).collect();
    let mut fitted_morphs: Vec<Option<Vec<[f32; 3]>>> = s.morphs.into_iter().map(Some).collect();
    for ((a, &(first, second)), morph) in out.attributes.iter_mut().zip(&stream_of).zip(&morph_of) {
        if let Some(k) = *morph {
            // One delta per output position, shared by its corners.
            let deltas = fitted_morphs[k].take().unwrap_or_default();
            a.values = deltas.into_iter().flatten().collect();
            a.indices = out.faces.indices.clone();
            continue;
        }
        let mut fitted = fitted_streams[first].take().unwrap_or_default();
        if let Some(other) = second.and_then(|k| fitted_streams[k].take()) {
            join_streams(&mut fitted, other);
        }
        a.values = fitted.values;
        a.indices = fitted.indices;
        if a.semantic == Semantic::Tangent && a.components == 4 {
            // The handedness is a sign, not a quantity to average.
            for w in a.values.chunks_exact_mut(4) {
                w[3] = if w[3] < 0.0 { -1.0 } else { 1.0 };
            }
        }
    }
    let mut report = s.report;
    // How well the kept UVs still show the textures (see `uv_health.rs`).
    for (k, read) in steer.iter().enumerate() {
        if read.as_ref().is_some_and(|r| !r.contains(&true)) {
            continue;
        }
        let damage = uv_damage(mesh, &out, &s.face_origin, k, read.as_deref());
        report.uv_damage = match (report.uv_damage, damage) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
    }
    if options.quads_active(mesh.faces.arity_counts().1) && !options.record.history {
        // Leftover triangle pairs that make a good quad are joined: the
        // same triangles drawn, more of the quad-dominant topology kept
        // (normals and tangents below see the final faces). Readers and
        // renderers pick their own diagonal, so a joined quad is at most
        // as warped as the input's own quads would be at the output's
        // resolution (`warp_at_resolution`) or flat to what no screen
        // shows: Blender drew a coarse cage's joined quads warped by the
        // run's error visibly otherwise. Pairs folded past a
        // crease stay two faces. Not where the history is kept: re-baking
        // walks it from each output face's own input face.
        let limits = crate::quad_pairs::JoinLimits {
            max_warp: options.attributes.invisible_distance * mesh.diagonal(),
            max_relative_warp: warp_at_resolution(
                median_quad_warp(mesh),
                mesh.triangle_count(),
                out.triangle_count(),
            ),
            max_fold_degrees: options.metric.crease_angle,
        };
        report.joined_quads = crate::quad_pairs::join_triangle_pairs(&mut out, limits);
    }
    for a in &mut out.attributes {
        if a.semantic == Semantic::Normal && a.components == 3 {
            if options.attributes.normals == NormalMode::Recompute {
                recompute_normals(&out.positions, &out.faces, a);
            }
            report.stray_normals += fix_stray_normals(&out.positions, &out.faces, a);
        }
    }
    if let Some(k) = out
        .attributes
        .iter()
        .position(|a| a.semantic == Semantic::Tangent)
    {
        // Tangents follow from normals and UVs: a renderer (or a normal map
        // baked for this mesh) rebuilds them with MikkTSpace, so they are
        // regenerated that way rather than fitted. UV set 0 is the one
        // normal maps use unless a material says otherwise; where MikkTSpace
        // cannot run (no normals), the fitted tangents stay.
        if let Ok(t) = wildlod_mesh::tangents::generate_tangents(&out, 0) {
            let a = &mut out.attributes[k];
            a.values = t.values;
            a.indices = t.indices;
        }
    }
    if let (Some(src), Some(fitted)) = (&mesh.skinning, s.skin) {
        out.skinning = Some(Skinning {
            influences: src.influences,
            joints: fitted.joints,
            weights: fitted.weights,
            // One influence set per output vertex, shared by its corners.
            indices: out.faces.indices.clone(),
            weight_format: src.weight_format,
            joint_format: src.joint_format,
        });
    }
    out.compact();
    Ok((out, report))
}

/// The median [`crate::quad_pairs::relative_warp`] of the input's
/// quads (0 without any): how warped the artist's own quads are.
fn median_quad_warp(mesh: &Mesh) -> f64 {
    let mut warps: Vec<f64> = mesh
        .faces
        .iter()
        .filter(|f| f.len() == 4)
        .filter_map(|f| {
            let p = |k: usize| mesh.positions.get(f[k] as usize).copied();
            Some(crate::quad_pairs::relative_warp(&[
                p(0)?,
                p(1)?,
                p(2)?,
                p(3)?,
            ]))
        })
        .filter(|w| w.is_finite())
        .collect();
    if warps.is_empty() {
        return 0.0;
    }
    let mid = warps.len() / 2;
    *warps.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// How warped the input's quads, `median` of them ([`median_quad_warp`]),
/// would be at the resolution of an output of `output_triangles` made
/// from `input_triangles`: a quad's warp over its diagonal grows with its
/// size on a surface of a given curvature (the warp is about the
/// curvature times the diagonal squared), and an output's faces are
/// √(input ÷ output) times the input's across.
fn warp_at_resolution(median: f64, input_triangles: usize, output_triangles: usize) -> f64 {
    median * (input_triangles as f64 / output_triangles.max(1) as f64).sqrt()
}

/// A per-corner stream of `a`'s values.
fn stream<'a>(
    a: &'a Attribute,
    indices: &'a [u32],
    weight: f64,
    seams: bool,
    kind: StreamKind,
) -> AttributeStream<'a> {
    AttributeStream {
        components: a.components as usize,
        values: &a.values,
        indices,
        weight,
        seams,
        kind,
    }
}

/// Per mesh attribute, which faces it steers on, where that is not every
/// face: `Some` for a UV set when [`crate::InputData::material_uv_sets`] is known
/// and some face's material does not sample it (see there); `None`
/// otherwise (the stream steers everywhere by its weight).
fn steering_faces(mesh: &Mesh, options: &Options) -> Vec<Option<Vec<bool>>> {
    let Some(sets) = &options.data.material_uv_sets else {
        return vec![None; mesh.attributes.len()];
    };
    let part_sets: Vec<u32> = mesh
        .parts
        .iter()
        .map(|p| {
            p.material
                .and_then(|m| sets.get(m as usize).copied())
                .unwrap_or(0)
        })
        .collect();
    mesh.attributes
        .iter()
        .map(|a| {
            let Semantic::TexCoord(k) = a.semantic else {
                return None;
            };
            let bit = if k < 32 { 1u32 << k } else { 0 };
            let faces: Vec<bool> = mesh
                .face_parts
                .iter()
                .map(|&p| part_sets.get(p as usize).is_some_and(|s| s & bit != 0))
                .collect();
            (!faces.iter().all(|&r| r)).then_some(faces)
        })
        .collect()
}

/// Joins the fitted halves of a stream given as two (see
/// [`steering_faces`]): every corner takes the value of the half that has
/// one.
fn join_streams(first: &mut FittedStream, second: FittedStream) {
    let m = first.components.max(1);
    let offset = (first.values.len() / m) as u32;
    for (x, &y) in first.indices.iter_mut().zip(&second.indices) {
        if *x == ABSENT && y != ABSENT {
            *x = y + offset;
        }
    }
    first.values.extend_from_slice(&second.values);
}

/// The faces of [`crate::InputData::see_through_materials`], when the caller named
/// some and gave no per-face flags; empty otherwise.
fn see_through_faces(mesh: &Mesh, options: &Options) -> Vec<bool> {
    if options.data.see_through_materials.is_empty() || !options.data.see_through_faces.is_empty() {
        return Vec::new();
    }
    let part_sees: Vec<bool> = mesh
        .parts
        .iter()
        .map(|p| {
            p.material
                .is_some_and(|m| options.data.see_through_materials.contains(&m))
        })
        .collect();
    if !part_sees.contains(&true) {
        return Vec::new();
    }
    mesh.face_parts
        .iter()
        .map(|&p| part_sees.get(p as usize).copied().unwrap_or(false))
        .collect()
}

/// A material id per face when the mesh has faces of at least two
/// materials (their borders are kept like seams); empty otherwise.
fn material_groups(mesh: &Mesh) -> Vec<u32> {
    let material = |f: usize| {
        mesh.parts
            .get(mesh.face_parts[f] as usize)
            .and_then(|p| p.material)
            .unwrap_or(u32::MAX)
    };
    let n = mesh.faces.len();
    if n == 0 || (1..n).all(|f| material(f) == material(0)) {
        return Vec::new();
    }
    (0..n).map(material).collect()
}

/// Normals from the simplified faces: every corner takes the area-weighted
/// sum of the face normals of the corners that share its value (its wedge),
/// so corners that kept one normal wedge are smooth and hard edges stay
/// hard.
fn recompute_normals(
    positions: &[[f32; 3]],
    faces: &wildlod_mesh::Faces,
    normals: &mut wildlod_mesh::Attribute,
) {
    let count = normals.value_count();
    let mut sum = vec![DVec3::ZERO; count];
    let p = |v: u32| DVec3::from(positions[v as usize].map(f64::from));
    let mut corner = 0usize;
    for face in faces.iter() {
        let mut n = DVec3::ZERO;
        for k in 0..face.len() {
            n += p(face[k]).cross(p(face[(k + 1) % face.len()]));
        }
        for _ in face {
            let i = normals.indices[corner];
            if i != ABSENT {
                sum[i as usize] += n;
            }
            corner += 1;
        }
    }
    for (i, s) in sum.iter().enumerate() {
        let len = s.length();
        if len > 0.0 && len.is_finite() {
            let n = *s / len;
            normals.values[3 * i..3 * i + 3].copy_from_slice(&[n.x as f32, n.y as f32, n.z as f32]);
        }
    }
}

/// A normal farther than this from every face it shades points away from
/// the surface it lights: it shades a face as if seen edge-on or from
/// behind (a black shard). 75°, not 90°: at grazing angles a lit face is
/// already dark, and a smooth coarse level's normals stay far within this
/// of some face they shade (a sphere at 1% of its triangles: about 30°).
const STRAY_NORMAL_DEGREES: f64 = 75.0;

/// Replaces every normal value that points more than
/// [`STRAY_NORMAL_DEGREES`] away from every face it shades (its corners'
/// faces) by the area-weighted normal of those faces, or, where even that
/// leaves it stray (faces turning every way), by its largest face's normal.
/// Each value is one wedge, so the input's hard edges stay hard. Returns
/// how many values were replaced.
///
/// A fitted normal is a least-squares blend of the normals merged into its
/// wedge: a facade's normal merged with those of the recesses that were
/// flattened into it can point along the wall. Such a normal is a defect,
/// whatever the fit says.
fn fix_stray_normals(
    positions: &[[f32; 3]],
    faces: &wildlod_mesh::Faces,
    normals: &mut wildlod_mesh::Attribute,
) -> usize {
    let count = normals.value_count();
    let cos = STRAY_NORMAL_DEGREES.to_radians().cos();
    let p = |v: u32| DVec3::from(positions[v as usize].map(f64::from));
    let face_normals: Vec<DVec3> = faces
        .iter()
        .map(|face| {
            let mut n = DVec3::ZERO;
            for k in 0..face.len() {
                n += p(face[k]).cross(p(face[(k + 1) % face.len()]));
            }
            n
        })
        .collect();
    let value = |values: &[f32], i: usize| {
        DVec3::new(
            values[3 * i] as f64,
            values[3 * i + 1] as f64,
            values[3 * i + 2] as f64,
        )
    };
    // Per value: whether some face it shades is within the bound.
    let mut agrees = vec![false; count];
    let mut used = vec![false; count];
    let mut corner = 0usize;
    for (f, face) in faces.iter().enumerate() {
        let n = face_normals[f];
        for _ in face {
            let i = normals.indices[corner];
            corner += 1;
            if i == ABSENT {
                continue;
            }
            let i = i as usize;
            used[i] = true;
            let len = n.length();
            if len > 0.0 && value(&normals.values, i).dot(n) >= cos * len {
                agrees[i] = true;
            }
        }
    }
    let stray: Vec<usize> = (0..count).filter(|&i| used[i] && !agrees[i]).collect();
    if stray.is_empty() {
        return 0;
    }
    let mut sum = vec![DVec3::ZERO; count];
    let mut largest = vec![DVec3::ZERO; count];
    let mut corner = 0usize;
    for (f, face) in faces.iter().enumerate() {
        let n = face_normals[f];
        for _ in face {
            let i = normals.indices[corner];
            corner += 1;
            if i == ABSENT || agrees[i as usize] {
                continue;
            }
            let i = i as usize;
            sum[i] += n;
            if n.length_squared() > largest[i].length_squared() {
                largest[i] = n;
            }
        }
    }
    let mut fixed = 0;
    for i in stray {
        let (s, l) = (sum[i], largest[i]);
        let smooth = s.normalize_or_zero();
        // The blend agrees with its largest face unless the faces turn
        // every way; then that face's own normal does.
        let n = if smooth.dot(l) >= cos * l.length() {
            smooth
        } else {
            l.normalize_or_zero()
        };
        if n == DVec3::ZERO {
            continue;
        }
        normals.values[3 * i..3 * i + 3].copy_from_slice(&[n.x as f32, n.y as f32, n.z as f32]);
        fixed += 1;
    }
    fixed
}

/// Morph targets taken as poses at most ([`morph_targets`]): each pose
/// weighs `1 / (poses + 1)` of a vertex's planes, so past a few dozen a
/// target adds little (a 52-target face rig is within), and each costs a
/// pass over the mesh: the cap keeps a file of thousands of sparse targets
/// from costing thousands of passes.
pub const MAX_MORPH_POSES: usize = 64;

/// The position morph targets of `mesh` as [`crate::InputData::morph_targets`]:
/// per target (in target order), every position's delta, taken from the
/// first corner on it (glTF stores one per vertex, and copies of a
/// position share it). Targets that move nothing are left out; of more
/// than [`MAX_MORPH_POSES`], those that move the surface most (the sum of
/// their deltas' lengths over the positions) are kept.
pub fn morph_targets(mesh: &Mesh) -> Vec<Vec<[f32; 3]>> {
    let mut targets: Vec<(u32, &Attribute)> = mesh
        .attributes
        .iter()
        .filter_map(|a| match a.semantic {
            Semantic::Morph {
                target,
                channel: MorphChannel::Position,
            } if a.components >= 3 => Some((target, a)),
            _ => None,
        })
        .collect();
    targets.sort_by_key(|t| t.0);
    let n = mesh.positions.len();
    // Every position's delta: that of its first corner.
    let deltas_of = |a: &Attribute| -> Vec<[f32; 3]> {
        let mut deltas = vec![[0.0f32; 3]; n];
        let mut seen = vec![false; n];
        for (c, &v) in mesh.faces.indices.iter().enumerate() {
            let Some(slot) = seen.get_mut(v as usize).filter(|s| !**s) else {
                continue;
            };
            *slot = true;
            if let Some(d) = a.corner_value(c) {
                deltas[v as usize] = [d[0], d[1], d[2]];
            }
        }
        deltas
    };
    // The sum of a target's delta lengths over the positions.
    let size = |a: &Attribute| -> f64 {
        let mut seen = vec![false; n];
        let mut sum = 0.0;
        for (c, &v) in mesh.faces.indices.iter().enumerate() {
            let Some(slot) = seen.get_mut(v as usize).filter(|s| !**s) else {
                continue;
            };
            *slot = true;
            if let Some(d) = a.corner_value(c) {
                let l = d.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>().sqrt();
                if l.is_finite() {
                    sum += l;
                }
            }
        }
        sum
    };
    let mut sized: Vec<(f64, u32)> = targets
        .iter()
        .map(|&(t, a)| (size(a), t))
        .filter(|&(s, _)| s > 0.0)
        .collect();
    // Largest first, ties to the lower target; then back in target order.
    sized.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
    sized.truncate(MAX_MORPH_POSES);
    let mut kept: Vec<u32> = sized.into_iter().map(|(_, t)| t).collect();
    kept.sort_unstable();
    targets
        .into_iter()
        .filter(|(t, _)| kept.binary_search(t).is_ok())
        .map(|(_, a)| deltas_of(a))
        .collect()
}

/// Joint influences per vertex from the mesh's skinning (each vertex takes
/// the entry of its first corner); empty when the mesh is not skinned. The
/// input of Knodt's joint-difference term (Knodt 2024 Eq. 3,
/// [`crate::InputData::vertex_joints`]).
pub fn vertex_joints(mesh: &Mesh) -> Vec<Vec<(u32, f32)>> {
    let Some(s) = &mesh.skinning else {
        return Vec::new();
    };
    let mut out: Vec<Vec<(u32, f32)>> = vec![Vec::new(); mesh.positions.len()];
    let mut seen = vec![false; mesh.positions.len()];
    for (corner, &v) in mesh.faces.indices.iter().enumerate() {
        let (v, entry) = (v as usize, s.indices[corner]);
        if seen[v] || entry == ABSENT {
            continue;
        }
        seen[v] = true;
        let (joints, weights) = s.entry(entry);
        out[v] = joints
            .iter()
            .zip(weights)
            .filter(|(_, &w)| w > 0.0)
            .map(|(&j, &w)| (j as u32, w))
            .collect();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::Faces;

    /// A unit square in z = 0 as two triangles, and a normal stream with
    /// one value per corner of the first triangle and one shared value on
    /// the second: `normals[0..3]` for triangle 0, `normals[3]` for
    /// triangle 1.
    fn square(normals: [[f32; 3]; 4]) -> (Vec<[f32; 3]>, Faces, Attribute) {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let faces = Faces::from_triangles(&[0, 1, 2, 0, 2, 3]);
        let a = Attribute {
            semantic: Semantic::Normal,
            components: 3,
            values: normals.iter().flatten().copied().collect(),
            indices: vec![0, 1, 2, 3, 3, 3],
            format: Default::default(),
        };
        (positions, faces, a)
    }

    #[test]
    fn normals_pointing_away_from_every_face_they_shade_are_replaced() {
        let tilt = |deg: f32| {
            let r = deg.to_radians();
            [r.sin(), 0.0, r.cos()]
        };
        // 60° and 74° off the face stay (a coarse smooth surface's normals
        // lean that far); 76° and 180° are replaced by the face's normal.
        let (p, f, mut a) = square([tilt(60.0), tilt(74.0), tilt(76.0), [0.0, 0.0, -1.0]]);
        assert_eq!(fix_stray_normals(&p, &f, &mut a), 2);
        assert_eq!(&a.values[0..3], &tilt(60.0));
        assert_eq!(&a.values[3..6], &tilt(74.0));
        assert_eq!(&a.values[6..9], &[0.0, 0.0, 1.0]);
        assert_eq!(&a.values[9..12], &[0.0, 0.0, 1.0]);
    }

    #[test]
    fn the_input_warp_at_a_coarser_resolution_grows_with_the_quads_size() {
        // On z = x·y the quad (±a, ±a) has its diagonals 2a² apart (one at
        // z = a², one at −a²) over a diagonal of 2√2·a: relative warp
        // a/√2, twice as much for a quad twice as wide. Such a quad covers
        // four of the smaller ones: a quarter of the triangles.
        let quad = |a: f32| {
            [
                [-a, -a, a * a],
                [a, -a, -a * a],
                [a, a, a * a],
                [-a, a, -a * a],
            ]
        };
        let (small, large) = (
            crate::quad_pairs::relative_warp(&quad(0.05)),
            crate::quad_pairs::relative_warp(&quad(0.1)),
        );
        assert!((small - 0.05 / 2f64.sqrt()).abs() < 1e-6, "{small}");
        assert!((large / small - 2.0).abs() < 1e-4, "{small} {large}");
        assert_eq!(warp_at_resolution(small, 400, 100), 2.0 * small);
        assert_eq!(warp_at_resolution(small, 100, 100), small);
        // No output triangles: as if one.
        assert_eq!(warp_at_resolution(0.01, 100, 0), 0.1);
    }

    #[test]
    fn a_normal_within_the_bound_of_one_of_its_faces_stays() {
        // A hinge: the value shared by both faces of a 90° fold points along
        // the first face's plane (90° from it) but within 0° of the second.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        // Triangle (0,1,2) faces +z; triangle (0,3,1) faces +y.
        let faces = Faces::from_triangles(&[0, 1, 2, 0, 3, 1]);
        let mut a = Attribute {
            semantic: Semantic::Normal,
            components: 3,
            values: vec![0.0, 1.0, 0.0],
            indices: vec![0; 6],
            format: Default::default(),
        };
        assert_eq!(fix_stray_normals(&positions, &faces, &mut a), 0);
        assert_eq!(a.values, vec![0.0, 1.0, 0.0]);
    }
}
