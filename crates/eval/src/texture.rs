//! Texture Chamfer distance (W §5, Table 2, after Yuan et al. 2018): for
//! samples on one surface, the L2 difference between their color and the
//! color of the spatially closest sample of the other surface.

use crate::eval_mesh::EvalMesh;
use crate::paired::{sample_sets, Paired};
use crate::sampling::{AreaSampler, Stream};

/// The texture Chamfer distance in both directions with its sampling
/// floor, or `None` when either mesh has no base color texture or no area
/// to sample, or `n` is 0.
pub(crate) fn texture_chamfer(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
) -> Option<Paired> {
    let usable = |(m, s): (&EvalMesh, &AreaSampler)| m.has_texture() && s.can_sample();
    if n == 0 || !usable(reference) || !usable(candidate) {
        return None;
    }
    let sets = sample_sets(
        reference,
        candidate,
        n,
        seed,
        Stream::Texture,
        &|m, t, bary| m.color_at(t, bary),
    );
    Some(Paired::measure(
        [&sets[0], &sets[1], &sets[2]],
        &|a: &[f32; 3], b: &[f32; 3]| {
            let d2: f32 = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum();
            f64::from(d2).sqrt()
        },
    ))
}
