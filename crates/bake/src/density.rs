//! How many input texels each part of the LOD's surface stands for, so that
//! the atlas gives its texels where the input has its detail.
//!
//! An asset's UV layout spends texels unevenly on purpose: a logo, a face or
//! printed text gets a large share of the image on a small part of the
//! surface. An atlas that gives each chart texels in proportion to its area
//! alone brings such an island back at a fraction of its resolution. So
//! every output triangle is sampled on a grid, each sample mapped back to
//! the input face it came from through the history, and the triangle gets
//! the mean density (input texels per unit of 3D area, from the input's UVs
//! and the size of the material's base colour image) of the faces its
//! samples land on. `atlas/` scales each chart by it.

use rayon::prelude::*;
use wildlod_mesh::Semantic;

use crate::bake::BakeInput;
use crate::mapping::SuccessiveMap;

/// Samples over a group's whole surface, at least: a chart's mean density
/// needs a few samples per input UV island it covers, not one per output
/// triangle.
const SAMPLE_BUDGET: f64 = 1024.0;

/// Most samples on one output triangle (an 8 × 8 grid).
const MAX_GRID: usize = 8;

/// Input densities within this ratio of each other count as uniform: the
/// charts' scales would differ by at most its square root (6%), not worth
/// a mapped sample per output triangle (a scan's or a terrain's
/// 100,000).
const UNIFORM_RATIO: f64 = 1.12;

/// Whether every textured input face has about the same density
/// ([`UNIFORM_RATIO`]).
fn uniform(face_density: &[Option<f64>]) -> bool {
    let (lo, hi) = face_density
        .iter()
        .flatten()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &d| {
            (lo.min(d), hi.max(d))
        });
    hi <= lo * UNIFORM_RATIO
}

/// Input texels per unit of 3D area of every input face (`None`: no
/// texture, or a degenerate face): the sum over its fan triangles of the UV
/// area times the base colour image's size (any texture's when the
/// material has no base colour texture), over their 3D area.
pub(crate) fn input_face_densities(input: &BakeInput) -> Vec<Option<f64>> {
    let mesh = input.mesh;
    (0..mesh.faces.len())
        .map(|f| {
            let m = mesh
                .parts
                .get(mesh.face_parts[f] as usize)
                .and_then(|p| p.material)
                .and_then(|m| input.materials.get(m as usize))?;
            let r = m.base_color_texture.or_else(|| m.texture_refs().next())?;
            let img = input.images.get(r.texture as usize)?.as_ref()?;
            let uv = mesh.attribute(&Semantic::TexCoord(r.tex_coord))?;
            let start = mesh.faces.offsets[f] as usize;
            let face = mesh.faces.face(f);
            let (mut texels, mut area) = (0.0f64, 0.0f64);
            for k in 1..face.len().saturating_sub(1) {
                let c = [start, start + k, start + k + 1];
                let p = c.map(|c| {
                    glam::DVec3::from(mesh.positions[mesh.faces.indices[c] as usize].map(f64::from))
                });
                let q: Option<Vec<[f64; 2]>> = c
                    .iter()
                    .map(|&c| {
                        let v = uv.corner_value(c)?;
                        Some([f64::from(v[0]), f64::from(*v.get(1)?)])
                    })
                    .collect();
                let q = q?;
                area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
                texels += 0.5
                    * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                        - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]))
                        .abs()
                    * f64::from(img.width)
                    * f64::from(img.height);
            }
            let d = texels / area;
            (area > 0.0 && d.is_finite() && d > 0.0).then_some(d)
        })
        .collect()
}

/// The input's texel density over each output triangle (`NaN` where no
/// sample lands on a textured face): `triangles` over `positions`, each on
/// the output face whose input face id is `origins[t]`, sampled on a grid
/// of equal sub-triangles (more on larger triangles) and mapped back with
/// `map`; `face_density` from [`input_face_densities`]. Empty (every chart
/// at the same density) when the input's density is uniform.
pub(crate) fn triangle_densities(
    map: &SuccessiveMap,
    face_density: &[Option<f64>],
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    origins: &[u32],
) -> Vec<f64> {
    let area = |t: &[u32; 3]| {
        let p = t.map(|v| glam::DVec3::from(positions[v as usize].map(f64::from)));
        0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
    };
    if uniform(face_density) {
        return Vec::new();
    }
    let areas: Vec<f64> = triangles.iter().map(area).collect();
    let total: f64 = areas.iter().filter(|a| a.is_finite()).sum();
    let budget = SAMPLE_BUDGET.max(triangles.len() as f64);
    triangles
        .par_iter()
        .zip(origins.par_iter())
        .zip(areas.par_iter())
        .map(|((t, &origin), &a)| {
            let share = if total > 0.0 && a.is_finite() {
                a / total
            } else {
                0.0
            };
            // k × k sub-triangles: about the triangle's share of the budget.
            let k = ((budget * share).sqrt().ceil() as usize).clamp(1, MAX_GRID);
            let p = t.map(|v| positions[v as usize]);
            let (mut sum, mut n) = (0.0, 0usize);
            let mut at = |s: f32, r: f32| {
                let w = [1.0 - s - r, s, r];
                let q = [0, 1, 2].map(|a| w[0] * p[0][a] + w[1] * p[1][a] + w[2] * p[2][a]);
                let hit = map.map(origin, q);
                if let Some(Some(d)) = face_density.get(hit.face as usize) {
                    sum += d;
                    n += 1;
                }
            };
            let kf = k as f32;
            for i in 0..k {
                for j in 0..k - i {
                    // Centroids of the upward sub-triangle and, where there
                    // is one, the downward one beside it.
                    at((i as f32 + 1.0 / 3.0) / kf, (j as f32 + 1.0 / 3.0) / kf);
                    if i + j + 1 < k {
                        at((i as f32 + 2.0 / 3.0) / kf, (j as f32 + 2.0 / 3.0) / kf);
                    }
                }
            }
            if n > 0 {
                sum / n as f64
            } else {
                f64::NAN
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densities_within_the_ratio_are_uniform_and_untextured_faces_do_not_count() {
        assert!(uniform(&[Some(100.0), None, Some(110.0)]));
        assert!(!uniform(&[Some(100.0), None, Some(130.0)]));
        // Nothing textured: nothing to weigh.
        assert!(uniform(&[None, None]));
        assert!(uniform(&[]));
    }
}
