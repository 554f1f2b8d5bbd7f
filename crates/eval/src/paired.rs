//! Values on two surfaces compared between spatially closest samples: the
//! scheme of the texture Chamfer distance (W §5, Table 2, after Yuan et al.
//! 2018), for any value a surface point carries (a color, a normal).
//!
//! Each surface is sampled with its own random numbers ([`Side`]), and the
//! reference a second time ([`Side::Floor`]): the reference against that
//! second set is the metric's sampling floor, what two samplings of one
//! surface differ by. A candidate within the floor of the reference is
//! indistinguishable from it at this sample count.

use glam::DVec3;
use rayon::prelude::*;
use wildlod_geometry::{Aabb, Bvh};

use crate::eval_mesh::EvalMesh;
use crate::sampling::{chunk_count, chunk_len, AreaSampler, Side, Stream, CHUNK};

/// Sample points of one surface with a value each, and a tree over them.
pub(crate) struct SampleSet<T> {
    points: Vec<DVec3>,
    values: Vec<T>,
    tree: Bvh,
}

/// The value a surface carries at barycentrics of a triangle.
pub(crate) type ValueAt<'f, T> = &'f (dyn Fn(&EvalMesh, usize, [f64; 3]) -> T + Sync);

impl<T: Send + Sync> SampleSet<T> {
    /// `n` samples of `mesh` (which `sampler` can sample) from `stream` of
    /// `side`, each with its value.
    pub(crate) fn draw(
        (mesh, sampler): (&EvalMesh, &AreaSampler),
        n: usize,
        seed: u64,
        stream: (Stream, Side),
        value: ValueAt<'_, T>,
    ) -> Self {
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
        let (points, values): (Vec<DVec3>, Vec<T>) = chunks.into_iter().flatten().unzip();
        let boxes: Vec<Aabb> = points.iter().map(|&p| Aabb::from_point(p)).collect();
        SampleSet {
            tree: Bvh::build(&boxes),
            points,
            values,
        }
    }

    /// The value of every sample, in drawing order.
    pub(crate) fn values(&self) -> &[T] {
        &self.values
    }

    /// Means over these samples of the `N` differences `diff` gives
    /// between a sample's value and that of the nearest sample of `to`
    /// (nearest by position; the lowest index on ties): one nearest-sample
    /// search serves every metric.
    pub(crate) fn means_to<const N: usize>(
        &self,
        to: &SampleSet<T>,
        diff: &(dyn Fn(&T, &T) -> [f64; N] + Sync),
    ) -> [f64; N] {
        let sums: Vec<[f64; N]> = self
            .points
            .par_chunks(CHUNK)
            .zip(self.values.par_chunks(CHUNK))
            .map(|(pts, vals)| {
                let mut sum = [0.0; N];
                for (&p, v) in pts.iter().zip(vals) {
                    let nearest = to.tree.nearest(p, f64::INFINITY, |j| {
                        to.points[j as usize].distance_squared(p)
                    });
                    if let Some((j, _)) = nearest {
                        for (s, d) in sum.iter_mut().zip(diff(v, &to.values[j as usize])) {
                            *s += d;
                        }
                    }
                }
                sum
            })
            .collect();
        // Summed in chunk order: the same total whatever the thread count.
        let n = self.points.len() as f64;
        std::array::from_fn(|k| sums.iter().map(|s| s[k]).sum::<f64>() / n)
    }
}

/// One paired metric between a reference and a candidate, with its floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Paired {
    /// Mean over the reference's samples.
    pub(crate) ref_to_cand: f64,
    /// Mean over the candidate's samples.
    pub(crate) cand_to_ref: f64,
    /// The same metric, both directions averaged, between the reference's
    /// samples and a second, independent sampling of the reference.
    pub(crate) floor: f64,
}

impl Paired {
    /// Both directions averaged: the metric.
    pub(crate) fn mean(&self) -> f64 {
        0.5 * (self.ref_to_cand + self.cand_to_ref)
    }

    /// Measures the `N` differences `diff` gives between the three sample
    /// sets of a comparison: the reference's, the candidate's, and the
    /// reference's second sampling.
    pub(crate) fn measure<T: Send + Sync, const N: usize>(
        [reference, candidate, floor]: [&SampleSet<T>; 3],
        diff: &(dyn Fn(&T, &T) -> [f64; N] + Sync),
    ) -> [Paired; N] {
        let r2c = reference.means_to(candidate, diff);
        let c2r = candidate.means_to(reference, diff);
        let r2f = reference.means_to(floor, diff);
        let f2r = floor.means_to(reference, diff);
        std::array::from_fn(|k| Paired {
            ref_to_cand: r2c[k],
            cand_to_ref: c2r[k],
            floor: 0.5 * (r2f[k] + f2r[k]),
        })
    }
}

/// The three sample sets of a paired comparison of `value`: the reference
/// ([`Side::Reference`]), the candidate ([`Side::Candidate`]) and the
/// reference again ([`Side::Floor`]). The caller checks that both surfaces
/// can be sampled.
pub(crate) fn sample_sets<T: Send + Sync>(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
    stream: Stream,
    value: ValueAt<'_, T>,
) -> [SampleSet<T>; 3] {
    let ((r, f), c) = rayon::join(
        || {
            rayon::join(
                || SampleSet::draw(reference, n, seed, (stream, Side::Reference), value),
                || SampleSet::draw(reference, n, seed, (stream, Side::Floor), value),
            )
        },
        || SampleSet::draw(candidate, n, seed, (stream, Side::Candidate), value),
    );
    [r, c, f]
}
