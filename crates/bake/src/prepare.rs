//! One mesh's share of a bake, before any atlas (W §4.3): simplified with
//! the collapse history recorded (collapses cross UV seams freely), the
//! output triangulated, its faces grouped by output material, and every
//! per-corner stream the atlas does not replace carried from the input.
//! Also what the shared layout needs to know of the mesh: its level's
//! density scale and its input's texel totals.

use std::time::Instant;

use wildlod_mesh::tangents::generate_tangents;
use wildlod_mesh::{Attribute, ComponentFormat, Faces, Mesh, Part, Semantic, ABSENT};
use wildlod_simplify::{
    simplify_with_attributes, AttributeInput, FittedSkin, History, MorphStream, Options, Report,
    Simplified, SkinStream,
};

use crate::channels::corner_normals;
use crate::input::BakeInput;
use crate::interface::{BakeError, BakeOptions};
use crate::texture_detail::ImageAnalyses;

/// Faces meeting at a larger angle keep separate normals at their shared
/// vertices: the usual "auto smooth" angle of modelling tools.
const CREASE_DEGREES: f32 = 60.0;

/// What groups output faces into atlases: the input material, or with
/// [`BakeOptions::merge_materials`] its (alpha mode, double-sidedness).
pub(crate) type GroupKey = (u32, u32, u32);

/// One mesh simplified and made ready for the shared layout.
pub(crate) struct Prepared<'a> {
    /// What it was baked from.
    pub input: BakeInput<'a>,
    /// The simplifier's output (its history taken out into `history`).
    pub s: Simplified,
    /// The collapse history, for the successive mapping.
    pub history: History,
    /// Output triangles (fans of the output faces).
    pub triangles: Vec<[u32; 3]>,
    /// Input face id of every output triangle (what the map starts from).
    pub tri_origin: Vec<u32>,
    /// Local group of every triangle (index into `group_keys`).
    pub tri_group: Vec<u32>,
    /// Keys of the mesh's groups, in first-use order (one part each).
    pub group_keys: Vec<GroupKey>,
    /// Input material of each group's first face.
    pub group_first_material: Vec<Option<u32>>,
    /// The output mesh: one part per group, no material or UVs yet.
    pub out: Mesh,
    /// Whether any of its materials has a texture or it has vertex colors.
    pub textured: bool,
    /// Output vertices the simplifier left in place as far outliers: their
    /// faces get no atlas space (one would set the charts' common scale).
    pub far: Vec<bool>,
    /// Linear scale of the level's texel density against the input's.
    pub level_scale: f64,
    /// Input texels and 3D area over the input's textured faces.
    pub input_texels: (f64, f64),
    /// The textures (indices into `input.images`) those texels come from,
    /// ascending, each once: what the input's images hold, however often
    /// its UVs repeat them.
    pub input_textures: Vec<u32>,
    /// Length scale from the mesh's units to the scene's.
    pub world_scale: f64,
    /// Seconds spent here.
    pub seconds: f64,
}

/// Simplifies `input.mesh` with `simplify` (history recorded) and builds
/// its [`Prepared`] share of a bake.
pub(crate) fn prepare<'a>(
    input: BakeInput<'a>,
    simplify: &Options,
    options: &BakeOptions,
    world_scale: f64,
    analyses: &ImageAnalyses,
) -> Result<Prepared<'a>, BakeError> {
    let t0 = Instant::now();
    let mesh = input.mesh;
    let mut opts = simplify.clone();
    opts.record.history = true;
    if opts.data.vertex_joints.is_empty() {
        opts.data.vertex_joints = wildlod_simplify::vertex_joints(mesh);
    }
    // Blend shapes are poses here too (`simplify_mesh` does the same).
    if opts.attributes.morph_poses && opts.data.morph_targets.is_empty() {
        opts.data.morph_targets = wildlod_simplify::morph_targets(mesh);
    }
    // Positions and faces steer the collapses, UVs do not (W: collapses
    // cross seams freely); skin influences and morph deltas are fitted
    // through every collapse (Knodt 2024 §3) so that the LOD deforms like
    // the input.
    let morph_attributes: Vec<usize> = mesh
        .attributes
        .iter()
        .enumerate()
        .filter(|(_, a)| matches!(a.semantic, Semantic::Morph { .. }) && a.components == 3)
        .map(|(i, _)| i)
        .collect();
    let attributes = AttributeInput {
        morphs: morph_attributes
            .iter()
            .map(|&i| MorphStream {
                values: &mesh.attributes[i].values,
                indices: &mesh.attributes[i].indices,
            })
            .collect(),
        skin: mesh.skinning.as_ref().map(|sk| SkinStream {
            influences: sk.influences as usize,
            joints: &sk.joints,
            weights: &sk.weights,
            indices: &sk.indices,
            weight: opts.attributes.skin_weight,
        }),
        ..AttributeInput::default()
    };
    let mut s = simplify_with_attributes(&mesh.positions, &mesh.faces, &attributes, &opts)?;
    let history = s.history.take().unwrap_or_default();
    // Triangles of the output, each remembering its output face and the
    // output corners it uses.
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut tri_face: Vec<u32> = Vec::new();
    let mut tri_corners: Vec<[u32; 3]> = Vec::new();
    for f in 0..s.faces.len() {
        let face = s.faces.face(f);
        let start = s.faces.offsets[f];
        for k in 1..face.len().saturating_sub(1) {
            triangles.push([face[0], face[k], face[k + 1]]);
            tri_face.push(f as u32);
            tri_corners.push([start, start + k as u32, start + k as u32 + 1]);
        }
    }
    let material_of_face = |f: u32| -> Option<u32> {
        let input_face = s.face_origin[f as usize] as usize;
        mesh.parts
            .get(mesh.face_parts[input_face] as usize)
            .and_then(|p| p.material)
            .filter(|&m| (m as usize) < input.materials.len())
    };
    let textured = mesh
        .parts
        .iter()
        .filter_map(|p| p.material)
        .filter_map(|m| input.materials.get(m as usize))
        .any(|m| m.texture_refs().next().is_some())
        || mesh.attribute(&Semantic::Color(0)).is_some();

    // Output groups: one per output material.
    let key = |m: Option<u32>| -> GroupKey {
        let mat = m.and_then(|m| input.materials.get(m as usize));
        if options.merge_materials {
            let alpha = mat.map_or(0, |m| m.alpha_mode as u32);
            let sides = mat.map_or(0, |m| m.double_sided as u32);
            (alpha, sides, 0)
        } else {
            (0, 0, m.map_or(u32::MAX, |m| m))
        }
    };
    let mut keys: Vec<GroupKey> = Vec::new();
    let mut group_first_material: Vec<Option<u32>> = Vec::new();
    let mut tri_group = Vec::with_capacity(triangles.len());
    for &f in &tri_face {
        let m = material_of_face(f);
        let k = key(m);
        let g = match keys.iter().position(|x| *x == k) {
            Some(g) => g,
            None => {
                keys.push(k);
                group_first_material.push(m);
                keys.len() - 1
            }
        };
        tri_group.push(g as u32);
    }

    let mut out = carried_mesh(mesh, &s, &triangles, &tri_corners, &morph_attributes);
    if let (Some(fitted), Some(input_skin)) = (&s.skin, &mesh.skinning) {
        out.skinning = Some(fitted_skinning(fitted, input_skin, &triangles));
    }
    if mesh.attribute(&Semantic::Normal).is_some() {
        // Carried corner normals belong to whichever input vertex each
        // corner was, so one output vertex gets several: faceted shading.
        // Fresh normals, smooth up to a crease angle, shade the new
        // geometry (and the normal map is baked relative to them).
        out.attributes.retain(|a| a.semantic != Semantic::Normal);
        out.attributes
            .push(smooth_normals(&s.positions, &triangles, CREASE_DEGREES));
    }
    out.face_parts = tri_group.clone();
    out.parts = group_first_material
        .iter()
        .map(|&m| Part {
            name: m
                .and_then(|m| input.materials.get(m as usize))
                .map(|m| m.name.clone())
                .unwrap_or_default(),
            material: None,
        })
        .collect();
    let mut far = vec![false; s.positions.len()];
    for &o in &s.report.outliers {
        if let Some(&v) = s.vertex_map.get(o as usize) {
            if let Some(f) = far.get_mut(v as usize) {
                *f = true;
            }
        }
    }
    let scale = level_scale(&input, &s.report, options, analyses);
    let tri_origin = tri_face
        .iter()
        .map(|&f| s.face_origin[f as usize])
        .collect();
    let (input_texels, input_textures) = input_texels(&input);
    Ok(Prepared {
        input,
        history,
        triangles,
        tri_origin,
        tri_group,
        group_keys: keys,
        group_first_material,
        out,
        textured,
        far,
        level_scale: scale,
        input_texels,
        input_textures,
        world_scale: if world_scale.is_finite() && world_scale > 0.0 {
            world_scale
        } else {
            1.0
        },
        s,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// Per-corner normals of `triangles`: at each corner, the area-weighted
/// normals of the triangles around its vertex that turn by at most
/// `crease` degrees from its own triangle; equal values shared.
fn smooth_normals(positions: &[[f32; 3]], triangles: &[[u32; 3]], crease: f32) -> Attribute {
    let cos = crease.to_radians().cos();
    let face_n: Vec<glam::Vec3> = triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| glam::Vec3::from(positions[v as usize]));
            (p[1] - p[0]).cross(p[2] - p[0])
        })
        .collect();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); positions.len()];
    for (f, t) in triangles.iter().enumerate() {
        for &v in t {
            around[v as usize].push(f as u32);
        }
    }
    let mut values: Vec<f32> = Vec::new();
    let mut indices = Vec::with_capacity(3 * triangles.len());
    let mut seen = std::collections::HashMap::new();
    for (f, t) in triangles.iter().enumerate() {
        let own = face_n[f].normalize_or_zero();
        for &v in t {
            let mut n = glam::Vec3::ZERO;
            for &g in &around[v as usize] {
                let other = face_n[g as usize];
                if own == glam::Vec3::ZERO || other.normalize_or_zero().dot(own) >= cos {
                    n += other;
                }
            }
            let n = n.try_normalize().unwrap_or(if own == glam::Vec3::ZERO {
                glam::Vec3::Z
            } else {
                own
            });
            let key = n.to_array().map(f32::to_bits);
            let next = seen.len() as u32;
            let i = *seen.entry(key).or_insert_with(|| {
                values.extend_from_slice(&n.to_array());
                next
            });
            indices.push(i);
        }
    }
    Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values,
        indices,
        format: ComponentFormat::F32,
    }
}

/// The simplified triangles with every per-corner stream except UVs,
/// tangents and colors carried from the input corner each output corner
/// is (normals, custom streams, skin influences), and the morph deltas of
/// `morph_attributes` (mesh attribute indices, in the order of
/// `s.morphs`) as fitted, one per output vertex.
fn carried_mesh(
    mesh: &Mesh,
    s: &wildlod_simplify::Simplified,
    triangles: &[[u32; 3]],
    tri_corners: &[[u32; 3]],
    morph_attributes: &[usize],
) -> Mesh {
    let mut faces = Faces::with_capacity(triangles.len(), 3 * triangles.len());
    for t in triangles {
        faces.push(t);
    }
    let input_corner = |out_corner: u32| s.corner_origin[out_corner as usize] as usize;
    let corners: Vec<usize> = tri_corners
        .iter()
        .flatten()
        .map(|&c| input_corner(c))
        .collect();
    let attributes = mesh
        .attributes
        .iter()
        .enumerate()
        .filter(|(_, a)| {
            !matches!(
                a.semantic,
                Semantic::TexCoord(_) | Semantic::Tangent | Semantic::Color(_)
            )
        })
        .map(|(i, a)| {
            let fitted = morph_attributes
                .iter()
                .position(|&m| m == i)
                .and_then(|k| s.morphs.get(k));
            match fitted {
                Some(deltas) => Attribute {
                    values: deltas.iter().flatten().copied().collect(),
                    indices: faces.indices.clone(),
                    ..a.clone()
                },
                None => Attribute {
                    indices: corners.iter().map(|&c| a.indices[c]).collect(),
                    ..a.clone()
                },
            }
        })
        .collect();
    let skinning = mesh.skinning.as_ref().map(|sk| wildlod_mesh::Skinning {
        indices: corners.iter().map(|&c| sk.indices[c]).collect(),
        ..sk.clone()
    });
    let mut out = Mesh {
        name: mesh.name.clone(),
        positions: s.positions.clone(),
        faces,
        face_parts: vec![0; triangles.len()],
        parts: vec![Part::default()],
        attributes,
        skinning,
    };
    out.compact();
    out
}

/// The simplifier's fitted influences (one set per output vertex) as the
/// triangulated mesh's per-corner skinning; a vertex no skinned corner
/// reached (all weights 0) has none.
fn fitted_skinning(
    fitted: &FittedSkin,
    input: &wildlod_mesh::Skinning,
    triangles: &[[u32; 3]],
) -> wildlod_mesh::Skinning {
    let k = fitted.influences.max(1);
    let indices = triangles
        .iter()
        .flatten()
        .map(|&v| {
            let w = fitted.weights.get(v as usize * k..(v as usize + 1) * k);
            match w {
                Some(w) if w.iter().any(|&x| x > 0.0) => v,
                _ => ABSENT,
            }
        })
        .collect();
    wildlod_mesh::Skinning {
        influences: fitted.influences as u8,
        joints: fitted.joints.clone(),
        weights: fitted.weights.clone(),
        indices,
        weight_format: input.weight_format,
        joint_format: input.joint_format,
    }
}

/// Sets `TEXCOORD_0` from per-corner UVs, sharing equal values.
pub(crate) fn set_uvs(out: &mut Mesh, corner_uv: &[[f32; 2]]) {
    let mut values = Vec::new();
    let mut indices = Vec::with_capacity(corner_uv.len());
    let mut seen = std::collections::HashMap::new();
    for uv in corner_uv {
        let key = [uv[0].to_bits(), uv[1].to_bits()];
        let next = seen.len() as u32;
        let i = *seen.entry(key).or_insert_with(|| {
            values.extend_from_slice(uv);
            next
        });
        indices.push(i);
    }
    out.attributes
        .retain(|a| a.semantic != Semantic::TexCoord(0));
    out.attributes.insert(
        0,
        Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values,
            indices,
            format: ComponentFormat::F32,
        },
    );
}

/// Gives the mesh a normal stream when it has none (flat normals, what a
/// renderer would use), so tangents can be generated.
pub(crate) fn ensure_normals(out: &mut Mesh, normals: &[glam::Vec3]) {
    if out.attribute(&Semantic::Normal).is_some() {
        return;
    }
    out.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values: normals.iter().flat_map(|n| n.to_array()).collect(),
        indices: (0..normals.len() as u32).collect(),
        format: ComponentFormat::F32,
    });
}

/// Per-corner tangents of the input for UV set `set`: its stream when it
/// has one, else MikkTSpace.
pub(crate) fn input_tangents(mesh: &Mesh, set: u32) -> Option<Vec<[f32; 4]>> {
    let from = |a: &Attribute| -> Vec<[f32; 4]> {
        (0..mesh.faces.corner_count())
            .map(|c| match a.corner_value(c) {
                Some(v) if v.len() >= 4 => [v[0], v[1], v[2], v[3]],
                Some(v) if v.len() == 3 => [v[0], v[1], v[2], 1.0],
                _ => [1.0, 0.0, 0.0, 1.0],
            })
            .collect()
    };
    if let Some(t) = mesh.attribute(&Semantic::Tangent) {
        return Some(from(t));
    }
    let generated = if mesh.attribute(&Semantic::Normal).is_some() {
        generate_tangents(mesh, set).ok()?
    } else {
        let mut m = mesh.clone();
        let n = corner_normals(mesh);
        ensure_normals(&mut m, &n);
        generate_tangents(&m, set).ok()?
    };
    Some(from(&generated))
}

/// The linear scale of a level's texel density against the input's (see
/// [`BakeOptions::density_follows_level`]): √(triangles kept), but no
/// smaller than the most detailed base colour image the mesh uses allows
/// ([`crate::texture_detail::ImageAnalysis::content_scale`]); 1 with the option off. Per mesh: the shared
/// atlas weighs each mesh's charts by its own (`shared_layout.rs`).
fn level_scale(
    input: &BakeInput,
    report: &Report,
    options: &BakeOptions,
    analyses: &ImageAnalyses,
) -> f64 {
    let level = report.output_triangles as f64 / report.input_triangles.max(1) as f64;
    // An asked-for size needs no scale (and no pass over the images).
    if options.texture_size.is_some()
        || !(options.density_follows_level && level.is_finite() && level > 0.0)
    {
        return 1.0;
    }
    let min_scale = level.min(1.0).sqrt();
    // Per base colour image: the UV triangles of the faces showing it.
    let mesh = input.mesh;
    let mut uvs: Vec<(u32, Vec<[[f32; 2]; 3]>)> = Vec::new();
    for f in 0..mesh.faces.len() {
        let Some(r) = mesh
            .parts
            .get(mesh.face_parts[f] as usize)
            .and_then(|p| p.material)
            .and_then(|m| input.materials.get(m as usize))
            .and_then(|m| m.base_color_texture)
        else {
            continue;
        };
        let Some(uv) = mesh.attribute(&Semantic::TexCoord(r.tex_coord)) else {
            continue;
        };
        let start = mesh.faces.offsets[f] as usize;
        let n = mesh.faces.face(f).len();
        let at = |c: usize| uv.corner_value(c).map(|v| [v[0], v[1]]);
        let k = match uvs.iter().position(|(t, _)| *t == r.texture) {
            Some(k) => k,
            None => {
                uvs.push((r.texture, Vec::new()));
                uvs.len() - 1
            }
        };
        for j in 1..n.saturating_sub(1) {
            if let (Some(a), Some(b), Some(c)) = (at(start), at(start + j), at(start + j + 1)) {
                uvs[k].1.push([a, b, c]);
            }
        }
    }
    uvs.iter()
        .filter_map(|(t, tris)| analyses.content_scale(input.images, *t as usize, tris, min_scale))
        .fold(min_scale, f64::max)
}

/// The input's texels and 3D area over its textured faces (each face's
/// base colour image, else its first texture): the input's texel density
/// is their ratio. Also the textures they come from (ascending, distinct).
fn input_texels(input: &BakeInput) -> ((f64, f64), Vec<u32>) {
    let mesh = input.mesh;
    let (mut texels, mut area) = (0.0f64, 0.0f64);
    let mut used = Vec::new();
    for f in 0..mesh.faces.len() {
        let part = mesh.face_parts[f] as usize;
        let Some(m) = mesh
            .parts
            .get(part)
            .and_then(|p| p.material)
            .and_then(|m| input.materials.get(m as usize))
        else {
            continue;
        };
        let Some(r) = m.base_color_texture.or_else(|| m.texture_refs().next()) else {
            continue;
        };
        let Some(img) = input
            .images
            .get(r.texture as usize)
            .and_then(Option::as_ref)
        else {
            continue;
        };
        let Some(uv) = mesh.attribute(&Semantic::TexCoord(r.tex_coord)) else {
            continue;
        };
        if used.last() != Some(&r.texture) {
            used.push(r.texture);
        }
        let start = mesh.faces.offsets[f] as usize;
        let face = mesh.faces.face(f);
        for k in 1..face.len().saturating_sub(1) {
            let c = [start, start + k, start + k + 1];
            let p = c.map(|c| {
                glam::DVec3::from(mesh.positions[mesh.faces.indices[c] as usize].map(f64::from))
            });
            let q: Option<Vec<&[f32]>> = c.iter().map(|&c| uv.corner_value(c)).collect();
            let Some(q) = q else { continue };
            let a3 = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            let a2 = 0.5
                * ((q[1][0] - q[0][0]) as f64 * (q[2][1] - q[0][1]) as f64
                    - (q[1][1] - q[0][1]) as f64 * (q[2][0] - q[0][0]) as f64)
                    .abs();
            area += a3;
            texels += a2 * img.width as f64 * img.height as f64;
        }
    }
    used.sort_unstable();
    used.dedup();
    ((texels, area), used)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normals_average_within_the_crease_and_split_beyond_it() {
        // Two triangles hinged along x at 30° (smoothed) and at 90° (split).
        for (angle, split) in [(30f32, false), (90f32, true)] {
            let (c, s) = (angle.to_radians().cos(), angle.to_radians().sin());
            let p = vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.5, -c, s],
            ];
            let t = [[0u32, 1, 2], [1, 0, 3]];
            let a = smooth_normals(&p, &t, 60.0);
            let n0 = a.corner_value(0).expect("normal");
            let n3 = a.corner_value(4).expect("normal");
            if split {
                assert!((n0[2] - 1.0).abs() < 1e-6, "{n0:?}");
                assert!(n3[2] < 0.1, "{n3:?}");
            } else {
                // Vertex 0 is shared: both corners get the same average.
                assert_eq!(n0, n3);
                assert!(n0[2] < 1.0 && n0[2] > 0.9, "{n0:?}");
            }
        }
    }
}
