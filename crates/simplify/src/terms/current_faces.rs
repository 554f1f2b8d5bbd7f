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

use glam::DVec3;

use crate::prepare::complex::Complex;
use crate::prepare::geometry::newell;

/// The most faces an endpoint's present faces are read from at one
/// evaluation: ten ordinary vertices' worth (six faces each), rounded up to
/// a power of two. A vertex with more (the center of a fan of thousands of
/// slivers, a pole) is ranked by its memory quadric alone when it moves:
/// reading all its faces at every try made a fan of 85,000 triangles
/// around one vertex quadratic (`tests/degenerate_fans.rs`).
const MAX_FACES_READ: usize = 64;

/// What collapsing edge `i`–`j` to `x` costs the present surface: over
/// the faces around `i` and `j` that survive it (those without both
/// corners), the squared distance by which the moved corner (`i` or `j`)
/// leaves the face's current plane, weighted by `weight` times the
/// corner's share of the face's current area (area / corners, as the
/// memory quadrics share an input face, W Eq. 9). It is the quadric error
/// of the present surface, as if the endpoints' quadrics were built from
/// it now (memoryless, Lindstrom and Turk), evaluated at `x`. Faces
/// without area (and points and edges, which have no plane) add nothing,
/// and so do the faces of an endpoint with more than [`MAX_FACES_READ`].
pub(crate) fn current_face_cost(c: &Complex, i: u32, j: u32, x: DVec3, weight: f64) -> f64 {
    let p = |v: u32| c.pos[v as usize];
    let mut sum = 0.0;
    // The faces around `i` without `j`, then around `j` without `i`; an
    // endpoint that stays where it is lifts none of its faces (on flat
    // and straight ground most collapses keep one, see `evaluate`).
    for (corner, other) in [(i, j), (j, i)] {
        let moved = x - p(corner);
        if moved == DVec3::ZERO || c.vert_faces[corner as usize].len() > MAX_FACES_READ {
            continue;
        }
        for &f in &c.vert_faces[corner as usize] {
            let face = c.face(f);
            if face.len() < 3 || face.contains(&other) {
                continue;
            }
            // Twice the face's area along its normal (the cross product of
            // a triangle, Newell's sum for a polygon).
            let twice = match *face {
                [a, b, d] => (p(b) - p(a)).cross(p(d) - p(a)),
                _ => newell(face.iter().map(|&v| p(v))).0,
            };
            let len = twice.length();
            if !(len.is_finite() && len > 0.0) {
                continue;
            }
            // share · (n · δ)² with n = twice / len and share = len / (2k).
            let lift = twice.dot(moved);
            sum += lift * lift / (2.0 * face.len() as f64 * len);
        }
    }
    weight * sum
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let q = |x: DVec3| current_face_cost(&c, 0, 1, x, 2.0);
        // At the origin nothing moves.
        assert!(q(DVec3::ZERO).abs() < 1e-15);
        // At (0.3, 0, 0) both surviving faces keep their planes: in the
        // flat one, and on the tilted one's plane (its normal has no x).
        assert!(q(DVec3::new(0.3, 0.0, 0.0)).abs() < 1e-15);
        // At (0, 0, 0.5): 0.5 off the flat plane, 0.5/√2 off the tilted
        // one, each weighed by a third of its area:
        // 2 · (0.5/3 · 0.25 + (√2/2)/3 · 0.125) = (0.25 + 0.125·√2) / 3.
        let want = (0.25 + 0.125 * 2f64.sqrt()) / 3.0;
        let got = q(DVec3::new(0.0, 0.0, 0.5));
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    }

    #[test]
    fn a_quads_corner_carries_a_quarter_of_its_area() {
        // The unit square z = 0 (a quad) and a triangle 0–4–1 hanging off
        // its edge. Collapsing 0 with 4 removes the triangle; the quad
        // survives around 0, whose share is 1/4: lifting 0 by 0.2 costs
        // 3 · 0.25 · 0.04 = 0.03 at weight 3.
        let pos = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::Y,
            DVec3::new(0.5, -1.0, 0.5),
        ];
        let c = Complex::new(pos, &[0, 4, 7], &[0, 1, 2, 3, 0, 4, 1]).0;
        let got = current_face_cost(&c, 0, 4, DVec3::new(0.0, 0.0, 0.2), 3.0);
        assert!((got - 0.03).abs() < 1e-12, "{got}");
    }

    #[test]
    fn the_faces_that_vanish_with_the_edge_add_nothing() {
        // One triangle: collapsing any of its edges leaves no face.
        let c = Complex::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], &[0, 3], &[0, 1, 2]).0;
        assert_eq!(
            current_face_cost(&c, 0, 1, DVec3::new(0.0, 0.0, 3.0), 1.0),
            0.0
        );
    }
}
