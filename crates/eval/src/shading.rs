//! Normal Chamfer distance: the texture Chamfer scheme (closest sample
//! pairs) applied to shading normals. For every sample of one surface, the
//! angle between its shading normal and that of the spatially closest
//! sample of the other surface, in degrees. It measures what lighting shows
//! of a level of detail beyond its distance to the input: smoothed edges,
//! faceting, normals that no longer follow the surface.
//!
//! The angle ignores orientation (0° to 90°): the closest sample of a thin
//! shell (a cup's wall, a cushion) is as likely on its other side, whose
//! normal points the other way, and would read as a 180° error.

use crate::eval_mesh::EvalMesh;
use crate::paired::paired_chamfer;
use crate::sampling::{AreaSampler, Stream};

/// Both directions of the normal Chamfer distance in degrees, `(reference →
/// candidate, candidate → reference)`, or `None` when either mesh has no
/// area to sample or `n` is 0.
pub(crate) fn normal_chamfer(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
) -> Option<(f64, f64)> {
    if n == 0 || !reference.1.can_sample() || !candidate.1.can_sample() {
        return None;
    }
    Some(paired_chamfer(
        reference,
        candidate,
        n,
        seed,
        Stream::Normal,
        &|m, t, bary| m.normal_at(t, bary),
        &|a: &glam::DVec3, b: &glam::DVec3| a.dot(*b).abs().min(1.0).acos().to_degrees(),
    ))
}
