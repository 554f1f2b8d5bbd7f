//! Texture Chamfer distance (W §5, Table 2, after Yuan et al. 2018): for
//! samples on one surface, the L2 difference between their color and the
//! color of the spatially closest sample of the other surface.

use glam::DVec3;
use rayon::prelude::*;
use wildlod_geometry::{Aabb, Bvh};

use crate::eval_mesh::EvalMesh;
use crate::sampling::{chunk_count, chunk_len, AreaSampler, Stream, CHUNK};

/// Colored sample points of one surface.
struct ColoredSamples {
    points: Vec<DVec3>,
    colors: Vec<[f32; 3]>,
}

fn colored_samples(
    mesh: &EvalMesh,
    sampler: &AreaSampler,
    n: usize,
    seed: u64,
    stream: Stream,
) -> ColoredSamples {
    let chunks: Vec<_> = (0..chunk_count(n))
        .into_par_iter()
        .map(|c| {
            sampler
                .chunk(mesh, seed, stream, c, chunk_len(n, c))
                .into_iter()
                .map(|s| (s.point, mesh.color_at(s.triangle as usize, s.bary)))
                .collect::<Vec<_>>()
        })
        .collect();
    let (points, colors) = chunks.into_iter().flatten().unzip();
    ColoredSamples { points, colors }
}

/// Mean over `from`'s samples of the RGB L2 difference to the nearest
/// sample of `to` (nearest by position; the lowest index on ties).
fn directed(from: &ColoredSamples, to: &ColoredSamples, to_bvh: &Bvh) -> f64 {
    let sums: Vec<f64> = from
        .points
        .par_chunks(CHUNK)
        .zip(from.colors.par_chunks(CHUNK))
        .map(|(pts, cols)| {
            let mut sum = 0.0;
            for (&p, col) in pts.iter().zip(cols) {
                let nearest = to_bvh.nearest(p, f64::INFINITY, |j| {
                    to.points[j as usize].distance_squared(p)
                });
                if let Some((j, _)) = nearest {
                    let other = &to.colors[j as usize];
                    let d2: f32 = (0..3).map(|k| (col[k] - other[k]).powi(2)).sum();
                    sum += f64::from(d2).sqrt();
                }
            }
            sum
        })
        .collect();
    // Summed in chunk order: the same total whatever the thread count.
    sums.iter().sum::<f64>() / from.points.len() as f64
}

/// Both directions of the texture Chamfer distance, `(reference → candidate,
/// candidate → reference)`, or `None` when either mesh has no base color
/// texture or no area to sample, or `n` is 0.
pub(crate) fn texture_chamfer(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
) -> Option<(f64, f64)> {
    let usable = |(m, s): (&EvalMesh, &AreaSampler)| m.has_texture() && s.can_sample();
    if n == 0 || !usable(reference) || !usable(candidate) {
        return None;
    }
    let (r, c) = rayon::join(
        || colored_samples(reference.0, reference.1, n, seed, Stream::Texture),
        || colored_samples(candidate.0, candidate.1, n, seed, Stream::Texture),
    );
    let tree = |s: &ColoredSamples| {
        let boxes: Vec<Aabb> = s.points.iter().map(|&p| Aabb::from_point(p)).collect();
        Bvh::build(&boxes)
    };
    let (rt, ct) = rayon::join(|| tree(&r), || tree(&c));
    Some((directed(&r, &c, &ct), directed(&c, &r, &rt)))
}
