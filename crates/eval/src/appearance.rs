//! The paired metrics of what a surface looks like, from one set of
//! samples per side: texture Chamfer, normal and shading-normal Chamfer,
//! each with its sampling floor ([`crate::paired`]). One nearest-sample
//! search per direction serves all three.
//!
//! Texture Chamfer distance (W §5, Table 2, after Yuan et al. 2018): for
//! samples on one surface, the L2 difference between their color and the
//! color of the spatially closest sample of the other surface
//! ([`color_distance`]).
//!
//! Normal Chamfer distances: the texture Chamfer scheme (closest sample
//! pairs) applied to normals. For every sample of one surface, the angle
//! between its normal and that of the spatially closest sample of the
//! other surface, in degrees ([`unoriented_angle`]). It measures what
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

use crate::eval_mesh::EvalMesh;
use crate::paired::{sample_sets, Paired};
use crate::sampling::{AreaSampler, Stream};

/// What a sample carries.
struct Look {
    /// Displayed color (black where the surface has no base color
    /// texture: then it is not measured).
    color: [f32; 3],
    /// Vertex normal.
    normal: DVec3,
    /// Shading normal (normal map applied).
    shading: DVec3,
    /// Whether an alpha test draws it (`None`: not alpha-tested).
    drawn: Option<bool>,
}

/// The paired metrics of a comparison.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Appearance {
    /// Texture Chamfer distance: `None` unless both sides have a base
    /// color texture.
    pub(crate) texture: Option<Paired>,
    /// Normal Chamfer distance in degrees.
    pub(crate) normal: Option<Paired>,
    /// Shading-normal Chamfer distance in degrees.
    pub(crate) shading: Option<Paired>,
    /// The fraction of the alpha-tested surface an alpha test draws, on
    /// the reference and on the candidate: `None` on a side with no
    /// alpha-tested material (both `None` unless one side has one).
    pub(crate) coverage: [Option<f64>; 2],
}

/// All three metrics with `n` samples per set, or all `None` when either
/// surface has no area to sample or `n` is 0.
pub(crate) fn appearance(
    reference: (&EvalMesh, &AreaSampler),
    candidate: (&EvalMesh, &AreaSampler),
    n: usize,
    seed: u64,
) -> Appearance {
    if n == 0 || !reference.1.can_sample() || !candidate.1.can_sample() {
        return Appearance::default();
    }
    let textured = reference.0.has_texture() && candidate.0.has_texture();
    let mapped = reference.0.has_normal_map() || candidate.0.has_normal_map();
    let tested = reference.0.alpha_tested() || candidate.0.alpha_tested();
    let sets = sample_sets(
        reference,
        candidate,
        n,
        seed,
        Stream::Paired,
        &|m, t, bary| {
            let normal = m.normal_at(t, bary);
            Look {
                color: if textured {
                    m.color_at(t, bary)
                } else {
                    [0.0; 3]
                },
                normal,
                shading: if mapped {
                    m.shading_normal_at(t, bary)
                } else {
                    normal
                },
                drawn: if tested {
                    m.passes_alpha_test(t, bary)
                } else {
                    None
                },
            }
        },
    );
    let coverage = [&sets[0], &sets[1]].map(|set| {
        let (drawn, tested) = set
            .values()
            .iter()
            .filter_map(|l| l.drawn)
            .fold((0usize, 0usize), |(d, n), x| (d + usize::from(x), n + 1));
        (tested > 0).then(|| drawn as f64 / tested as f64)
    });
    let [texture, normal, shading] =
        Paired::measure([&sets[0], &sets[1], &sets[2]], &|a: &Look, b: &Look| {
            let normal = unoriented_angle(a.normal, b.normal);
            [
                color_distance(&a.color, &b.color),
                normal,
                if mapped {
                    unoriented_angle(a.shading, b.shading)
                } else {
                    normal
                },
            ]
        });
    Appearance {
        texture: textured.then_some(texture),
        normal: Some(normal),
        shading: Some(shading),
        coverage,
    }
}

/// L2 distance between two RGB colors (components in [0, 1]).
pub(crate) fn color_distance(a: &[f32; 3], b: &[f32; 3]) -> f64 {
    let d2: f32 = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum();
    f64::from(d2).sqrt()
}

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
    fn color_distance_is_euclidean_over_rgb() {
        assert!((color_distance(&[0.2, 0.4, 0.6], &[0.5, 0.4, 0.2]) - 0.5).abs() < 1e-7);
        assert_eq!(color_distance(&[0.3; 3], &[0.3; 3]), 0.0);
    }

    #[test]
    fn angles_ignore_orientation() {
        let tilted = DVec3::new(0.5, 0.0, 0.75f64.sqrt());
        assert!((unoriented_angle(DVec3::Z, tilted) - 30.0).abs() < 1e-9);
        assert!((unoriented_angle(-DVec3::Z, tilted) - 30.0).abs() < 1e-9);
        assert_eq!(unoriented_angle(DVec3::X, DVec3::X), 0.0);
        assert!((unoriented_angle(DVec3::X, DVec3::Y) - 90.0).abs() < 1e-9);
    }
}
