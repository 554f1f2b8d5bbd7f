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
//! and the size of the material's base colour image, where that texture
//! has detail: [`input_face_densities`]) of the faces its samples land on.
//! `atlas/` scales each chart by it.

use rayon::prelude::*;
use wildlod_mesh::Semantic;

use crate::input::BakeInput;
use crate::mapping::SuccessiveMap;
use crate::texture_detail::{ImageAnalyses, VISIBLE_BLUR};

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

/// Input texels per unit of 3D area of every input face, where its texture
/// has detail (`None`: no texture, or a degenerate face). The density is
/// the sum over its fan triangles of the UV area times the base colour
/// image's size (any texture's when the material has no base colour
/// texture), over their 3D area. UV density is not always detail: a
/// conformal map magnifies parts of a texture of flat colour (bob: 0.3–3.5×
/// over flat yellow and dots), and following it there moves texels away
/// from the rest for nothing. So a face's density is blended (in log
/// space) from the typical one (the area-weighted geometric mean) to its
/// own by its detail: the mean colour distance of the texels under its UVs
/// to their 2 × 2 block's mean, over [`FULL_DETAIL`] (capped at 1). A logo,
/// text or a face keeps its density; a flat or smooth region gets the
/// typical one.
pub(crate) fn input_face_densities(
    input: &BakeInput,
    analyses: &ImageAnalyses,
) -> Vec<Option<f64>> {
    let raw = raw_face_densities(input, analyses);
    // Typical density: area-weighted geometric mean.
    let (mut ls, mut wsum) = (0.0, 0.0);
    for &(d, _, a) in raw.iter().flatten() {
        ls += a * d.ln();
        wsum += a;
    }
    if wsum <= 0.0 {
        return raw.iter().map(|r| r.map(|r| r.0)).collect();
    }
    let typical = ls / wsum;
    raw.iter()
        .map(|r| {
            r.map(|(d, c, _)| {
                let c = c.clamp(0.0, 1.0);
                ((1.0 - c) * typical + c * d.ln()).exp()
            })
        })
        .collect()
}

/// Per 2 × 2 block of `img` (blocks clipped at the border): the mean colour
/// distance (RGB in 0..1) of its texels to the block's mean.
fn block_detail(img: &wildlod_mesh::Rgba8Image) -> (usize, usize, Vec<f32>) {
    let (w, h) = (img.width as usize, img.height as usize);
    let (bw, bh) = (w.div_ceil(2), h.div_ceil(2));
    let mut out = vec![0.0f32; bw * bh];
    for by in 0..bh {
        for bx in 0..bw {
            let mut px = Vec::with_capacity(4);
            for y in 2 * by..(2 * by + 2).min(h) {
                for x in 2 * bx..(2 * bx + 2).min(w) {
                    let p = img.pixels[y * w + x];
                    px.push([p[0], p[1], p[2]].map(|c| f32::from(c) / 255.0));
                }
            }
            let n = px.len() as f32;
            let mean = [0, 1, 2].map(|k| px.iter().map(|p| p[k]).sum::<f32>() / n);
            out[by * bw + bx] = px
                .iter()
                .map(|p| (0..3).map(|k| (p[k] - mean[k]).powi(2)).sum::<f32>().sqrt())
                .sum::<f32>()
                / n;
        }
    }
    (bw, bh, out)
}

/// Mean colour distance of texels to their 2 × 2 block's mean that counts
/// as full detail: the just-noticeable step of `texture_detail.rs`
/// ([`VISIBLE_BLUR`]), the change a 2 × 2 box average may make before it
/// shows. A face whose texels a halved density would visibly change keeps
/// its own density; below, it leans to the typical one. (Measured: five
/// times the step gave the same texture Chamfer on bob, the file whose
/// conformal UVs this is for, within 0.0002.)
const FULL_DETAIL: f64 = VISIBLE_BLUR;

/// Per face: its own density, its detail over [`FULL_DETAIL`] (1 where no
/// block could be read) and its 3D area.
fn raw_face_densities(input: &BakeInput, analyses: &ImageAnalyses) -> Vec<Option<(f64, f64, f64)>> {
    let mesh = input.mesh;
    // Images the shared analyses do not hold (another image list).
    let mut details: std::collections::HashMap<u32, (usize, usize, Vec<f32>)> =
        std::collections::HashMap::new();
    (0..mesh.faces.len())
        .map(|f| {
            let m = mesh
                .parts
                .get(mesh.face_parts[f] as usize)
                .and_then(|p| p.material)
                .and_then(|m| input.materials.get(m as usize))?;
            let r = m.base_color_texture.or_else(|| m.texture_refs().next())?;
            let img = input.images.get(r.texture as usize)?.as_ref()?;
            let (bw, bh, detail) = match analyses.get(input.images, r.texture as usize) {
                Some(a) => a.detail(block_detail),
                None => &*details
                    .entry(r.texture)
                    .or_insert_with(|| block_detail(img)),
            };
            let (mut dsum, mut dn) = (0.0f64, 0usize);
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
                // Blocks whose centers the UV triangle covers (wrapped as
                // a repeating sampler reads them), else the one under its
                // centroid.
                let b = [0, 1, 2].map(|k| [q[k][0] * *bw as f64, q[k][1] * *bh as f64]);
                let lo = [0, 1].map(|a| b.iter().map(|v| v[a]).fold(f64::INFINITY, f64::min));
                let hi = [0, 1].map(|a| b.iter().map(|v| v[a]).fold(f64::NEG_INFINITY, f64::max));
                let cross = |o: [f64; 2], a: [f64; 2], c: [f64; 2]| {
                    (a[0] - o[0]) * (c[1] - o[1]) - (a[1] - o[1]) * (c[0] - o[0])
                };
                let s = cross(b[0], b[1], b[2]).signum();
                let at = |x: i64, y: i64| {
                    detail[y.rem_euclid(*bh as i64) as usize * *bw
                        + x.rem_euclid(*bw as i64) as usize]
                };
                let before = dn;
                if lo[0].is_finite()
                    && hi[0].is_finite()
                    && lo[1].is_finite()
                    && hi[1].is_finite()
                    && (hi[0] - lo[0]) * (hi[1] - lo[1]) < 4.0e7
                {
                    for y in (lo[1] - 0.5).ceil() as i64..=(hi[1] - 0.5).floor() as i64 {
                        for x in (lo[0] - 0.5).ceil() as i64..=(hi[0] - 0.5).floor() as i64 {
                            let c = [x as f64 + 0.5, y as f64 + 0.5];
                            if s * cross(b[0], b[1], c) >= 0.0
                                && s * cross(b[1], b[2], c) >= 0.0
                                && s * cross(b[2], b[0], c) >= 0.0
                            {
                                dsum += f64::from(at(x, y));
                                dn += 1;
                            }
                        }
                    }
                    if dn == before {
                        let m = [0, 1].map(|a| (b[0][a] + b[1][a] + b[2][a]) / 3.0);
                        dsum += f64::from(at(m[0].floor() as i64, m[1].floor() as i64));
                        dn += 1;
                    }
                }
                area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
                texels += 0.5
                    * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                        - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]))
                        .abs()
                    * f64::from(img.width)
                    * f64::from(img.height);
            }
            let d = texels / area;
            let c = if dn > 0 {
                dsum / dn as f64 / FULL_DETAIL
            } else {
                1.0
            };
            (area > 0.0 && d.is_finite() && d > 0.0).then_some((d, c, area))
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

    use wildlod_mesh::{
        Attribute, ComponentFormat, Faces, ImageSource, Material, Mesh, Rgba8Image, Sampler,
        Texture, TextureRef,
    };

    #[test]
    fn dense_detailed_faces_keep_their_density_and_dense_flat_ones_get_the_typical() {
        // A 64² image: rings 12 texels apart on its left half, one flat
        // colour on its right.
        let mut img = Rgba8Image::filled(64, 64, [90, 140, 200, 255]);
        for y in 0..64u32 {
            for x in 0..32u32 {
                let r = ((x as f32 - 16.0).powi(2) + (y as f32 - 32.0).powi(2)).sqrt();
                let v = 128.0 + 100.0 * (std::f32::consts::TAU * r / 12.0).sin();
                img.pixels[(y * 64 + x) as usize] = [v as u8, (255.0 - v) as u8, 128, 255];
            }
        }
        // Three right triangles with legs 1 (area ½) side by side; the
        // first two map onto 32 × 32 texels (rings, flat), the third onto
        // 8 × 8 flat texels.
        let mut positions = Vec::new();
        let mut f = Faces::new();
        let mut uvs = Vec::new();
        let uv_tris = [
            [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]],
            [[0.5, 0.0], [1.0, 0.0], [0.5, 0.5]],
            [[0.5, 0.5], [0.625, 0.5], [0.5, 0.625]],
        ];
        for (k, t) in uv_tris.iter().enumerate() {
            let x = 2.0 * k as f32;
            let base = positions.len() as u32;
            positions.extend([[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x, 1.0, 0.0]]);
            f.push(&[base, base + 1, base + 2]);
            for q in t {
                uvs.extend_from_slice(q);
            }
        }
        let mut mesh = Mesh::from_polygons(positions, f);
        mesh.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: uvs,
            indices: (0..9).collect(),
            format: ComponentFormat::F32,
        });
        mesh.parts[0].material = Some(0);
        let materials = [Material {
            base_color_texture: Some(TextureRef {
                texture: 0,
                tex_coord: 0,
            }),
            ..Material::default()
        }];
        let textures = [Texture {
            name: "t".into(),
            source: ImageSource::Path("t.png".into()),
            sampler: Sampler::default(),
        }];
        let images = [Some(img)];
        let input = BakeInput {
            mesh: &mesh,
            materials: &materials,
            textures: &textures,
            images: &images,
        };
        let analyses = ImageAnalyses::new(&images);
        let raw = raw_face_densities(&input, &analyses);
        let own: Vec<f64> = raw.iter().map(|r| r.expect("textured").0).collect();
        // 512 texels on ½ unit², twice; 32 on ½.
        assert!((own[0] - 1024.0).abs() < 1e-6 && (own[1] - 1024.0).abs() < 1e-6);
        assert!((own[2] - 64.0).abs() < 1e-6, "{own:?}");
        let detail: Vec<f64> = raw.iter().map(|r| r.expect("textured").1).collect();
        assert!(
            detail[0] >= 1.0 && detail[1] == 0.0 && detail[2] == 0.0,
            "{detail:?}"
        );
        let eff: Vec<f64> = input_face_densities(&input, &analyses)
            .into_iter()
            .flatten()
            .collect();
        // Typical: the geometric mean of 1024, 1024 and 64 (equal areas).
        let typical = (1024f64 * 1024.0 * 64.0).cbrt();
        assert!((eff[0] - 1024.0).abs() < 1e-6, "{eff:?}");
        assert!(
            (eff[1] - typical).abs() < 1e-6 && (eff[2] - typical).abs() < 1e-6,
            "{eff:?}"
        );
    }

    #[test]
    fn densities_within_the_ratio_are_uniform_and_untextured_faces_do_not_count() {
        assert!(uniform(&[Some(100.0), None, Some(110.0)]));
        assert!(!uniform(&[Some(100.0), None, Some(130.0)]));
        // Nothing textured: nothing to weigh.
        assert!(uniform(&[None, None]));
        assert!(uniform(&[]));
    }
}
