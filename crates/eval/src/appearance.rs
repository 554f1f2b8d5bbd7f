//! The paired metrics of what a surface looks like, from one set of
//! samples per side: texture Chamfer ([`crate::texture`]), normal and
//! shading-normal Chamfer ([`crate::shading`]), each with its sampling
//! floor ([`crate::paired`]). One nearest-sample search per direction
//! serves all three.

use glam::DVec3;

use crate::eval_mesh::EvalMesh;
use crate::paired::{sample_sets, Paired};
use crate::sampling::{AreaSampler, Stream};
use crate::shading::unoriented_angle;
use crate::texture::color_distance;

/// What a sample carries.
struct Look {
    /// Displayed color (black where the surface has no base color
    /// texture: then it is not measured).
    color: [f32; 3],
    /// Vertex normal.
    normal: DVec3,
    /// Shading normal (normal map applied).
    shading: DVec3,
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
            }
        },
    );
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
    }
}
