//! One atlas per output material across every mesh of a bake (W §4.3:
//! "our mapping approach is compatible with any injective texture
//! mapping", so the charts of several meshes packed together are one more
//! injective layout).
//!
//! A group is every output face, of any mesh, with the same group key (the
//! input material, or with `merge_materials` its alpha mode and
//! sidedness). Its charts are made per mesh (charts grow over shared
//! vertices, and meshes share none) and packed into one square atlas by
//! `atlas/`, which only sees a longer chart list.
//!
//! Texel density across meshes: each mesh is in its own local units, so
//! its positions are scaled by its world scale before the layout (the
//! packer gives every chart the same texels per unit of length) and each
//! triangle's input density (`density.rs`, texels per local unit area) is
//! divided by the square of that scale: densities are per unit of world
//! area, comparable across meshes. A textured chart then gets texels in
//! proportion to the input texels it shows, whatever its mesh's scale;
//! surface without a density of its own (no UVs, no texture: the typical
//! density) gets texels per unit of *world* area, so a mesh drawn twice as
//! large gets four times the atlas area. Each mesh's level scale (√ of the
//! triangles it kept, floored by its textures' detail) multiplies its
//! charts' density squared, so a mesh reduced further gets fewer texels,
//! as its own atlas would have. The atlas side is chosen as for one mesh
//! (the input's density times the level scale, at least
//! [`MIN_LEVEL_SIDE`], a power of two, growing until the charts fit), with
//! the members' texel counts summed.

use std::time::Instant;

use crate::atlas::{atlas_stats, build_atlas_weighted, Atlas, AtlasOptions, AtlasStats};
use crate::density::triangle_densities;
use crate::interface::{BakeError, BakeOptions};
use crate::mapping::SuccessiveMap;
use crate::prepare::{GroupKey, Prepared};

/// The smallest atlas side a level's density is scaled down to (unless the
/// input's own density gives less): below it charts of a few texels blur
/// whatever they hold.
const MIN_LEVEL_SIDE: f64 = 256.0;

/// Relative spread under which every member's density counts as equal (no
/// per-chart densities: the layout of a single uniform mesh is unchanged).
const SAME_DENSITY: f64 = 1e-9;

/// The faces of every mesh that go into one atlas.
pub(crate) struct SharedGroup {
    /// The group key.
    pub key: GroupKey,
    /// The input material of the group's first face (the output
    /// material's factors and name come from it).
    pub first_material: Option<u32>,
    /// Meshes with faces in the group, in mesh order, with their local
    /// group (part) index.
    pub meshes: Vec<(usize, u32)>,
    /// Per entry of `meshes`: its range of `members`.
    pub ranges: Vec<std::ops::Range<usize>>,
    /// Triangles laid out (far outliers' left out), as (mesh, triangle),
    /// contiguous per mesh in `meshes` order (see `ranges`): index = atlas
    /// owner.
    pub members: Vec<(u32, u32)>,
    /// Whether any member mesh is textured (else only a normal map is
    /// baked, and a layout that does not fit is dropped).
    pub textured: bool,
}

/// A group's atlas and what laying it out cost.
pub(crate) struct SharedAtlas {
    /// UVs (in texels) of every member triangle's corners, in `members`
    /// order.
    pub atlas: Atlas,
    /// Layout statistics.
    pub stats: AtlasStats,
    /// Seconds spent on the layout.
    pub layout_seconds: f64,
}

/// The groups of every mesh not in `kept`, in first-use order (mesh by
/// mesh, each mesh's groups in its part order): for one mesh exactly its
/// own groups.
pub(crate) fn shared_groups(prepared: &[Prepared], kept: &[bool]) -> Vec<SharedGroup> {
    let mut groups: Vec<SharedGroup> = Vec::new();
    for (m, p) in prepared.iter().enumerate() {
        if kept[m] {
            continue;
        }
        for (lg, &key) in p.group_keys.iter().enumerate() {
            let g = match groups.iter().position(|g| g.key == key) {
                Some(g) => g,
                None => {
                    groups.push(SharedGroup {
                        key,
                        first_material: p.group_first_material[lg],
                        meshes: Vec::new(),
                        ranges: Vec::new(),
                        members: Vec::new(),
                        textured: false,
                    });
                    groups.len() - 1
                }
            };
            let group = &mut groups[g];
            group.meshes.push((m, lg as u32));
            group.textured |= p.textured;
            let start = group.members.len();
            group.members.extend(
                (0..p.triangles.len() as u32)
                    .filter(|&t| p.tri_group[t as usize] == lg as u32)
                    .filter(|&t| !p.triangles[t as usize].iter().any(|&v| p.far[v as usize]))
                    .map(|t| (m as u32, t)),
            );
            let end = group.members.len();
            group.ranges.push(start..end);
        }
    }
    groups
}

/// Lays out `group` in one atlas (see the module doc). `Ok(None)`: an
/// untextured group (a normal map only) whose charts do not fit usefully:
/// not worth an atlas of mostly gutter, its meshes keep their materials.
///
/// # Errors
/// [`BakeError::AtlasFull`] when the charts do not fit the largest atlas.
pub(crate) fn lay_out(
    group: &SharedGroup,
    prepared: &[Prepared],
    maps: &[Option<SuccessiveMap>],
    face_densities: &[Vec<Option<f64>>],
    options: &BakeOptions,
) -> Result<Option<SharedAtlas>, BakeError> {
    // Every member mesh's output positions in world units, one after the
    // other; triangles renumbered into them.
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(group.members.len());
    let mut offsets = vec![0u32; prepared.len()];
    for &(m, _) in &group.meshes {
        let p = &prepared[m];
        offsets[m] = positions.len() as u32;
        let ws = p.world_scale as f32;
        positions.extend(p.s.positions.iter().map(|q| q.map(|c| c * ws)));
    }
    for &(m, t) in &group.members {
        let off = offsets[m as usize];
        tris.push(prepared[m as usize].triangles[t as usize].map(|v| v + off));
    }
    let densities = member_densities(group, prepared, maps, face_densities);
    // A chosen size stays within the input images' own texels: a file
    // whose UVs repeat one image (leaf cards, tiled walls, trim sheets)
    // would otherwise get every repeat its own texels, an atlas many
    // times the input's.
    let unique = options
        .texture_size
        .is_none()
        .then(|| unique_side(group, prepared))
        .flatten();
    let limit = options
        .max_texture_size
        .min(unique.unwrap_or(u32::MAX))
        .max(64);
    let mut size = options
        .texture_size
        .unwrap_or_else(|| density_size(group, prepared, options).min(limit));
    let t_layout = Instant::now();
    // A size chosen here grows (up to `max_texture_size`) until every
    // chart has a place worth its padding; an asked-for size (or the
    // largest) is used as long as every chart has a place.
    let atlas = loop {
        let atlas = build_atlas_weighted(
            &positions,
            &tris,
            &[],
            &densities,
            &AtlasOptions {
                size,
                padding: options.padding,
                max_chart_angle: options.max_chart_angle,
                // A size that may still grow needs a useful packing or
                // none.
                useful_only: options.texture_size.is_none() && size < limit,
            },
        );
        if !group.textured && !atlas.fits {
            return Ok(None);
        }
        let fixed = options.texture_size.is_some() || size >= options.max_texture_size;
        // Past the input's own texels an atlas grows only until every
        // chart has a place, however small.
        if atlas.fits || ((fixed || size >= limit) && atlas.placed) {
            break atlas;
        }
        if fixed {
            return Err(BakeError::AtlasFull {
                charts: atlas.chart_count,
                size,
            });
        }
        size = (2 * size).min(options.max_texture_size.max(size));
    };
    let layout_seconds = t_layout.elapsed().as_secs_f64();
    let stats = atlas_stats(&positions, &tris, &atlas);
    Ok(Some(SharedAtlas {
        atlas,
        stats,
        layout_seconds,
    }))
}

/// Per member triangle: the texel density its chart should get, in texels
/// per unit of world area (input density / world scale², times the mesh's
/// level scale²); empty when every member mesh is uniform at one density
/// (every chart at the common scale).
fn member_densities(
    group: &SharedGroup,
    prepared: &[Prepared],
    maps: &[Option<SuccessiveMap>],
    face_densities: &[Vec<Option<f64>>],
) -> Vec<f64> {
    let mut per_mesh: Vec<(Vec<f64>, f64, f64)> = Vec::with_capacity(group.meshes.len());
    for (&(m, _), range) in group.meshes.iter().zip(&group.ranges) {
        let p = &prepared[m];
        let members = &group.members[range.clone()];
        let tris: Vec<[u32; 3]> = members
            .iter()
            .map(|&(_, t)| p.triangles[t as usize])
            .collect();
        let origins: Vec<u32> = members
            .iter()
            .map(|&(_, t)| p.tri_origin[t as usize])
            .collect();
        let own = match &maps[m] {
            Some(map) => {
                triangle_densities(map, &face_densities[m], &p.s.positions, &tris, &origins)
            }
            None => Vec::new(),
        };
        // A uniform mesh's one density (NaN: none of its faces textured).
        let known: Vec<f64> = face_densities[m].iter().flatten().copied().collect();
        let uniform = if known.is_empty() {
            f64::NAN
        } else {
            known.iter().sum::<f64>() / known.len() as f64
        };
        let ls = p.level_scale.min(1.0);
        let factor = ls * ls / (p.world_scale * p.world_scale);
        per_mesh.push((own, uniform, factor));
    }
    if let [(own, _, _)] = per_mesh.as_slice() {
        // One mesh: its own densities as they are (a common factor would
        // change nothing but rounding).
        return own.clone();
    }
    if per_mesh.iter().all(|(own, _, _)| own.is_empty()) {
        let values: Vec<f64> = per_mesh
            .iter()
            .map(|(_, u, f)| u * f)
            .filter(|v| v.is_finite() && *v > 0.0)
            .collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(0.0, f64::max);
        if values.is_empty() || hi <= lo * (1.0 + SAME_DENSITY) {
            return Vec::new();
        }
    }
    let mut out = Vec::with_capacity(group.members.len());
    for ((own, uniform, factor), range) in per_mesh.iter().zip(&group.ranges) {
        for i in 0..range.len() {
            let d = if own.is_empty() { *uniform } else { own[i] };
            out.push(d * factor);
        }
    }
    out
}

/// The side of the smallest square power-of-two atlas that holds every
/// texel of the input images its member meshes' textured faces read (each
/// image once, however often the UVs repeat it; the meshes, as for
/// [`density_size`], so that a group baking only a normal map shares its
/// mesh's bound); `None` when they read none.
fn unique_side(group: &SharedGroup, prepared: &[Prepared]) -> Option<u32> {
    let mut seen: Vec<u32> = Vec::new();
    let mut texels = 0.0f64;
    for &(m, _) in &group.meshes {
        let p = &prepared[m];
        for &t in &p.input_textures {
            if seen.contains(&t) {
                continue;
            }
            seen.push(t);
            if let Some(Some(img)) = p.input.images.get(t as usize) {
                texels += img.width as f64 * img.height as f64;
            }
        }
    }
    (texels >= 1.0).then(|| {
        let side = texels.sqrt().ceil().min(f64::from(1u32 << 30)) as u32;
        side.next_power_of_two()
    })
}

/// Atlas side for the input's texel density: per member mesh, its input's
/// texels per unit area (over its textured faces) times its area in the
/// group, over an expected atlas use of 60%; summed, and scaled by the
/// members' level scales ([`MIN_LEVEL_SIDE`] at least, never above the
/// input's density); rounded to a power of two in `[64,
/// max_texture_size]`. Areas are in each mesh's own units: the ratio of
/// its output area to its input area does not depend on them.
fn density_size(group: &SharedGroup, prepared: &[Prepared], options: &BakeOptions) -> u32 {
    let (mut full2, mut scaled2) = (0.0f64, 0.0f64);
    for (&(m, _), range) in group.meshes.iter().zip(&group.ranges) {
        let p = &prepared[m];
        let (texels, area) = p.input_texels;
        let mut out_area = 0.0;
        for &(_, t) in &group.members[range.clone()] {
            let q = p.triangles[t as usize]
                .map(|v| glam::DVec3::from(p.s.positions[v as usize].map(f64::from)));
            out_area += 0.5 * (q[1] - q[0]).cross(q[2] - q[0]).length();
        }
        if !(area > 0.0 && texels > 0.0 && out_area > 0.0) {
            continue;
        }
        let f2 = texels / area * out_area / 0.6;
        let s = p.level_scale.min(1.0);
        full2 += f2;
        scaled2 += f2 * s * s;
    }
    let cap = options.max_texture_size.max(64);
    if full2 <= 0.0 || full2.is_nan() {
        return 1024.min(cap);
    }
    let side = scaled2.sqrt().max(full2.sqrt().min(MIN_LEVEL_SIDE));
    let pow = side.max(1.0).log2().round().clamp(6.0, 31.0);
    (2f64.powf(pow) as u32).clamp(64, cap)
}
