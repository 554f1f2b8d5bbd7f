//! Values on two surfaces compared between spatially closest samples: the
//! scheme of the texture Chamfer distance (W §5, Table 2, after Yuan et al.
//! 2018), for any value a surface point carries (a color, a normal).

use glam::DVec3;
use rayon::prelude::*;
use wildlod_geometry::{Aabb, Bvh};

use crate::eval_mesh::EvalMesh;
use crate::sampling::{chunk_count, chunk_len, AreaSampler, Stream, CHUNK};

/// Sample points of one surface with a value each.
struct Samples<T> {
    points: Vec<DVec3>,
    values: Vec<T>,
}

fn samples<T: Send>(
    mesh: &EvalMesh,
    sampler: &AreaSampler,
    n: usize,
    seed: u64,
    stream: Stream,
    value: &(dyn Fn(&EvalMesh, usize, [f64; 3]) -> T + Sync),
) -> Samples<T> {
    let chunks: Vec<_> = (0..chunk_count(n))
        .into_par_iter()
        .map(|c| {
            sampler
                .chunk(mesh, seed, stream, c, chunk_len(n, c))
                .into_iter()
                .map(|s| (s.point, value(mesh, s.triangle as usize, s.bary)))
                .collect::<Vec<_>>()
        })
        .collect();
    let (points, values) = chunks.into_iter().flatten().unzip();
    Samples { points, values }
}

/// Mean over `from`'s samples of `diff` to the nearest sample of `to`
/// (nearest by position; the lowest index on ties).
fn directed<T: Sync>(
    from: &Samples<T>,
    to: &Samples<T>,
    to_bvh: &Bvh,
    diff: &(dyn Fn(&T, &T) -> f64 + Sync),
) -> f64 {
    let sums: Vec<f64> = from
        .points
        .par_chunks(CHUNK)
        .zip(from.values.par_chunks(CHUNK))
        .map(|(pts, vals)| {
            let mut sum = 0.0;
            for (&p, v) in pts.iter().zip(vals) {
                let nearest = to_bvh.nearest(p, f64::INFINITY, |j| {
                    to.points[j as usize].distance_squared(p)
                });
                if let Some((j, _)) = nearest {
                    sum += diff(v, &to.values[j as usize]);
                }
            }
            sum
        })
        .collect();
    // Summed in chunk order: the same total whatever the thread count.
    sums.iter().sum::<f64>() / from.points.len() as f64
}

/// Both directions `(reference → candidate, candidate → reference)` of the
/// mean `diff` between every sample's value and that of the spatially
/// closest sample of the other surface. `n` samples per surface, drawn from
/// `stream` with `seed`; the caller checks that both surfaces can be
/// sampled.
pub(crate) fn paired_chamfer<T: Send + Sync>(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
    stream: Stream,
    value: &(dyn Fn(&EvalMesh, usize, [f64; 3]) -> T + Sync),
    diff: &(dyn Fn(&T, &T) -> f64 + Sync),
) -> (f64, f64) {
    let (r, c) = rayon::join(
        || samples(reference.0, reference.1, n, seed, stream, value),
        || samples(candidate.0, candidate.1, n, seed, stream, value),
    );
    let tree = |s: &Samples<T>| {
        let boxes: Vec<Aabb> = s.points.iter().map(|&p| Aabb::from_point(p)).collect();
        Bvh::build(&boxes)
    };
    let (rt, ct) = rayon::join(|| tree(&r), || tree(&c));
    (directed(&r, &c, &ct, diff), directed(&c, &r, &rt, diff))
}
