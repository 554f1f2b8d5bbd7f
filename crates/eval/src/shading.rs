//! Normal Chamfer distances: the texture Chamfer scheme (closest sample
//! pairs, [`crate::appearance`]) applied to normals. For every sample of
//! one surface, the angle between its normal and that of the spatially
//! closest sample of the other surface, in degrees. It measures what
//! lighting shows of a level of detail beyond its distance to the input:
//! smoothed edges, faceting, normals that no longer follow the surface.
//!
//! Two normals per sample: the interpolated vertex normal
//! ([`crate::EvalMesh::normal_at`], the *normal* Chamfer), and the shading
//! normal a glTF renderer lights with, the normal map applied in the
//! MikkTSpace frame ([`crate::EvalMesh::shading_normal_at`], the
//! *shading-normal* Chamfer). Without normal maps on either side the two
//! are equal; a level of detail that carries the input's small-scale shape
//! in a baked normal map scores better on the second.

use glam::DVec3;

/// Angle in degrees between two unit vectors, orientation ignored (0° to
/// 90°): the closest sample of a thin shell (a cup's wall, a cushion) is as
/// likely on its other side, whose normal points the other way, and would
/// otherwise read as a 180° error.
pub(crate) fn unoriented_angle(a: DVec3, b: DVec3) -> f64 {
    a.dot(b).abs().min(1.0).acos().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_ignore_orientation() {
        let tilted = DVec3::new(0.5, 0.0, 0.75f64.sqrt());
        assert!((unoriented_angle(DVec3::Z, tilted) - 30.0).abs() < 1e-9);
        assert!((unoriented_angle(-DVec3::Z, tilted) - 30.0).abs() < 1e-9);
        assert_eq!(unoriented_angle(DVec3::X, DVec3::X), 0.0);
        assert!((unoriented_angle(DVec3::X, DVec3::Y) - 90.0).abs() < 1e-9);
    }
}
