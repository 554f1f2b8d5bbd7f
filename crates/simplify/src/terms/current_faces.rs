//! The current faces' planes: how far a collapse moves the surface as it
//! is now, beside how far the memory quadrics say it moves from the input.
//!
//! The vertex quadrics keep every input plane a vertex ever carried (W
//! Eq. 13, memory), which is what holds sharp features where they were (W
//! Fig. 16). But they weigh each plane by the input area it came with, and
//! that is the area of the faces the vertex was part of, not of the faces
//! it shapes now. A vertex that no collapse has touched yet still carries
//! only its own input faces' share while its faces have grown to many
//! times that: on a plate cut by a grid of holes, the rim vertices kept at
//! mid-height between top and bottom held those planes weakly, and the
//! collapses next to them pinched the walls into streaks. The memoryless
//! measure (Lindstrom and Turk's view: what the present surface loses)
//! sees those grown faces at their present size.
//!
//! The term only ranks: the vertex is still placed by the memory quadrics,
//! so features stay where the input had them, and the cost is the memory
//! cost plus this one at that position. Where the collapse keeps every
//! surviving face in its plane (flat regions, straight creases) it adds
//! nothing: free collapses stay free.

use crate::prepare::complex::Complex;
use crate::prepare::geometry::face_plane;
use crate::terms::quadric::Quadric;

/// The planes of the faces around `i` and `j` that survive collapsing edge
/// `i`–`j` (those without both corners), each through its corner `i` or
/// `j` and weighted by `weight` times its corner's share of its current
/// area (area / corners, as the memory quadrics share an input face, W
/// Eq. 9): the quadric error of the present surface, as if the endpoints'
/// quadrics were built from it now (memoryless, Lindstrom and Turk).
/// Evaluated at the new position it is the area-weighted squared distance
/// by which the collapse lifts those faces' moved corners off their
/// present planes.
/// Faces without area (and points and edges, which have no plane) add
/// nothing. Its own `weight` is 0: it ranks, it carries no area.
pub(crate) fn current_face_quadric(c: &Complex, i: u32, j: u32, weight: f64) -> Quadric {
    let mut sum = Quadric::ZERO;
    for f in c.star_faces_iter(i, j) {
        let face = c.face(f);
        let (has_i, has_j) = (face.contains(&i), face.contains(&j));
        if face.len() < 3 || (has_i && has_j) {
            continue;
        }
        let Some((n, area, _)) = face_plane(c, f) else {
            continue;
        };
        let corner = if has_i { i } else { j };
        let share = area / face.len() as f64;
        sum += Quadric::plane(n, c.pos[corner as usize], weight * share);
    }
    sum.weight = 0.0;
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A fan of four triangles around vertex 0 at the origin: two in the
    /// plane z = 0 (areas 1/2 each), two tilted up along +y (planes
    /// through the origin with normal (0, −1, 1)/√2, areas √2/2 each).
    fn fan() -> Complex {
        let pos = vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 1.0),
        ];
        let idx = [0, 2, 1, 0, 3, 2, 0, 1, 4, 0, 4, 3];
        Complex::new(pos, &[0, 3, 6, 9, 12], &idx).0
    }

    #[test]
    fn it_is_the_moved_corners_area_weighted_squared_distance_to_the_present_planes() {
        let c = fan();
        // Collapsing 0 into 1: faces 0–2–1 and 0–1–4 vanish; 0–3–2 (flat,
        // area 1/2) and 0–4–3 (tilted, area √2/2) survive around 0, and
        // nothing survives around 1 but faces it already shares with 0.
        let q = current_face_quadric(&c, 0, 1, 2.0);
        assert_eq!(q.weight, 0.0);
        // At the origin nothing moves.
        assert!(q.eval(DVec3::ZERO).abs() < 1e-15);
        // At (0.3, 0, 0) both surviving faces keep their planes: in the
        // flat one, and on the tilted one's plane (its normal has no x).
        assert!(q.eval(DVec3::new(0.3, 0.0, 0.0)).abs() < 1e-15);
        // At (0, 0, 0.5): 0.5 off the flat plane, 0.5/√2 off the tilted
        // one, each weighed by a third of its area:
        // 2 · (0.5/3 · 0.25 + (√2/2)/3 · 0.125) = (0.25 + 0.125·√2) / 3.
        let want = (0.25 + 0.125 * 2f64.sqrt()) / 3.0;
        let got = q.eval(DVec3::new(0.0, 0.0, 0.5));
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    }

    #[test]
    fn the_faces_that_vanish_with_the_edge_add_nothing() {
        // One triangle: collapsing any of its edges leaves no face.
        let c = Complex::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], &[0, 3], &[0, 1, 2]).0;
        let q = current_face_quadric(&c, 0, 1, 1.0);
        assert_eq!(q.eval(DVec3::new(0.0, 0.0, 3.0)), 0.0);
    }
}
