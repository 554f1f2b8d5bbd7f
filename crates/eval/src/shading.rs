//! Normal Chamfer distances: the texture Chamfer scheme (closest sample
//! pairs) applied to normals. For every sample of one surface, the angle
//! between its normal and that of the spatially closest sample of the other
//! surface, in degrees. It measures what lighting shows of a level of
//! detail beyond its distance to the input: smoothed edges, faceting,
//! normals that no longer follow the surface.
//!
//! Two normals per sample: the interpolated vertex normal
//! ([`EvalMesh::normal_at`], the *normal* Chamfer), and the shading normal
//! a glTF renderer lights with, the normal map applied in the MikkTSpace
//! frame ([`EvalMesh::shading_normal_at`], the *shading-normal* Chamfer).
//! Without normal maps on either side the two are equal; a level of detail
//! that carries the input's small-scale shape in a baked normal map scores
//! better on the second.
//!
//! The angle ignores orientation (0° to 90°): the closest sample of a thin
//! shell (a cup's wall, a cushion) is as likely on its other side, whose
//! normal points the other way, and would read as a 180° error.

use glam::DVec3;

use crate::eval_mesh::EvalMesh;
use crate::paired::{sample_sets, Paired};
use crate::sampling::{AreaSampler, Stream};

/// Angle in degrees between two unit vectors, orientation ignored.
fn unoriented_angle(a: &DVec3, b: &DVec3) -> f64 {
    a.dot(*b).abs().min(1.0).acos().to_degrees()
}

/// The normal and the shading-normal Chamfer distances in degrees, both
/// directions with their floors, or `None` when either mesh has no area to
/// sample or `n` is 0. Both come from the same samples.
pub(crate) fn normal_chamfers(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
) -> Option<(Paired, Paired)> {
    if n == 0 || !reference.1.can_sample() || !candidate.1.can_sample() {
        return None;
    }
    let sets = sample_sets(
        reference,
        candidate,
        n,
        seed,
        Stream::Normal,
        &|m, t, bary| (m.normal_at(t, bary), m.shading_normal_at(t, bary)),
    );
    let sets = [&sets[0], &sets[1], &sets[2]];
    let normal = Paired::measure(sets, &|a: &(DVec3, DVec3), b: &(DVec3, DVec3)| {
        unoriented_angle(&a.0, &b.0)
    });
    let shading = if reference.0.has_normal_map() || candidate.0.has_normal_map() {
        Paired::measure(sets, &|a: &(DVec3, DVec3), b: &(DVec3, DVec3)| {
            unoriented_angle(&a.1, &b.1)
        })
    } else {
        // Equal by definition: every shading normal is the vertex normal.
        normal
    };
    Some((normal, shading))
}
