//! Closest points between points, segments and triangles.
//!
//! Everything here is exact up to floating-point rounding and total on its
//! input: degenerate triangles (zero area, collinear or coincident corners)
//! and zero-length segments are handled as the point sets they are, and no
//! input makes a function panic or loop. A NaN query point gives a NaN
//! distance.

use glam::DVec3;

/// Below this `sin²` of the angle at the first corner a triangle is treated
/// as the union of its edges. The normal `ab × ac` carries an absolute error
/// of a few ulps of `|ab|·|ac|`, so its direction is good to about
/// `1e-16 / sin A` rad, while the edge fallback is off by at most the
/// triangle's width, `sin A` times its size. The two errors meet at
/// `sin A ≈ 1e-8`: results on slivers are within about 1e-8 of the
/// triangle's size (far below the precision of `f32` input), and exact up
/// to rounding elsewhere.
const SIN2_DEGENERATE: f64 = 1e-16;

/// The point of segment `[a, b]` closest to `p`, and its parameter `t`
/// (`point = a + t (b − a)`, `t ∈ [0, 1]`). A zero-length segment gives `a`.
#[inline]
pub fn closest_point_on_segment(p: DVec3, a: DVec3, b: DVec3) -> (DVec3, f64) {
    let ab = b - a;
    let len2 = ab.length_squared();
    // NaN lengths go to the endpoint too.
    if len2.is_nan() || len2 <= 0.0 {
        return (a, 0.0);
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    (a + ab * t, t)
}

/// Where the closest point lies on a triangle and how it was found.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Candidate {
    point: DVec3,
    bary: [f64; 3],
    dist2: f64,
}

/// Closest point to `p` on edge `k` of triangle `[a, b, c]` (edge 0 = ab,
/// 1 = bc, 2 = ca), with barycentrics.
#[inline]
fn on_edge(p: DVec3, v: [DVec3; 3], k: usize) -> Candidate {
    let (i, j) = (k, (k + 1) % 3);
    let (point, t) = closest_point_on_segment(p, v[i], v[j]);
    let mut bary = [0.0; 3];
    bary[i] = 1.0 - t;
    bary[j] += t;
    Candidate {
        point,
        bary,
        dist2: (p - point).length_squared(),
    }
}

/// The closest of the candidates on the edges for which `use_edge` is
/// true; ties keep the lower edge, so the answer does not depend on rounding
/// noise in a caller's loop order.
#[inline]
fn best_edge(p: DVec3, v: [DVec3; 3], use_edge: [bool; 3]) -> Candidate {
    let mut best: Option<Candidate> = None;
    for (k, &u) in use_edge.iter().enumerate() {
        if !u {
            continue;
        }
        let c = on_edge(p, v, k);
        match best {
            Some(b) if c.dist2.is_nan() || c.dist2 >= b.dist2 => {}
            _ => best = Some(c),
        }
    }
    best.unwrap_or(Candidate {
        point: v[0],
        bary: [1.0, 0.0, 0.0],
        dist2: (p - v[0]).length_squared(),
    })
}

/// The point of triangle `[a, b, c]` closest to `p`, with its barycentric
/// coordinates `[u, v, w]` (`point = u a + v b + w c`, all in `[0, 1]`,
/// summing to 1). On slivers (a width below about 1e-6 of the length) the
/// barycentrics are less accurate than the point: they are determined only
/// to about `1e-16 · length / width`.
///
/// The triangle is the intersection of three half-planes in its plane. When
/// the projection of `p` lies in all three, it is the answer. Otherwise the
/// closest point lies on an edge whose half-plane `p` violates (at a vertex
/// the normal cone is spanned by the two outward edge normals, so at least
/// one of them is violated), and that edge's closest point is taken. A
/// degenerate triangle (zero area, collinear or coincident corners) is the
/// union of its edges and is treated as such.
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, [f64; 3]) {
    let r = closest_on_triangle(p, a, b, c);
    (r.point, r.bary)
}

/// Squared distance from `p` to triangle `[a, b, c]`; see
/// [`closest_point_on_triangle`].
#[inline]
pub fn point_triangle_distance2(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    closest_on_triangle(p, a, b, c).dist2
}

#[inline]
fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Candidate {
    let v = [a, b, c];
    let (ab, ac) = (b - a, c - a);
    let n = ab.cross(ac);
    if !is_reliable_normal(n, ab, ac) {
        return best_edge(p, v, [true; 3]);
    }
    // Signed areas (times |n|²·2) of the sub-triangles opposite each corner:
    // the unnormalized barycentrics of p's projection onto the plane.
    let ea = n.dot((c - b).cross(p - b));
    let eb = n.dot((a - c).cross(p - c));
    let ec = n.dot(ab.cross(p - a));
    if ea >= 0.0 && eb >= 0.0 && ec >= 0.0 {
        // The point is the projection onto the plane, not the barycentric
        // combination: on a sliver the barycentrics are ill-conditioned
        // (an error of ε·size/width along the sliver) while the projection
        // is only tilted by the normal's error.
        let s = ea + eb + ec;
        let (bv, bw) = (eb / s, ec / s);
        let point = p - n * (n.dot(p - a) / n.length_squared());
        return Candidate {
            point,
            bary: [1.0 - bv - bw, bv, bw],
            dist2: (p - point).length_squared(),
        };
    }
    // Edge k is opposite corner k + 2: ab ↔ c, bc ↔ a, ca ↔ b.
    best_edge(p, v, [ec < 0.0, ea < 0.0, eb < 0.0])
}

/// The closest points `(on [p0, p1], on [q0, q1])` of two segments.
///
/// The squared distance `|p(s) − q(t)|²` is a convex quadratic on the unit
/// square: its minimum is the interior critical point when the segments are
/// not parallel and it falls inside, else it lies on the square's border,
/// i.e. one of the four endpoint-to-segment problems. Parallel, overlapping
/// and zero-length segments therefore need no special formula.
pub fn segment_segment_closest(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (DVec3, DVec3) {
    let (x, y, _) = segment_segment_closest_dist2(p0, p1, q0, q1);
    (x, y)
}

/// [`segment_segment_closest`] with the squared distance.
pub(crate) fn segment_segment_closest_dist2(
    p0: DVec3,
    p1: DVec3,
    q0: DVec3,
    q1: DVec3,
) -> (DVec3, DVec3, f64) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, b) = (d1.length_squared(), d2.length_squared(), d1.dot(d2));
    let denom = a * e - b * b;
    // Relative test: denom = a e sin²θ. Nearly parallel segments fall
    // through to the border cases, which are exact for them.
    if denom > 1e-14 * a * e {
        let (c, f) = (d1.dot(r), d2.dot(r));
        let s = (b * f - c * e) / denom;
        let t = (a * f - b * c) / denom;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            let (x, y) = (p0 + d1 * s, q0 + d2 * t);
            return (x, y, (x - y).length_squared());
        }
    }
    let mut best: Option<(DVec3, DVec3, f64)> = None;
    let mut consider = |x: DVec3, y: DVec3| {
        let d = (x - y).length_squared();
        match best {
            Some((_, _, bd)) if d.is_nan() || d >= bd => {}
            _ => best = Some((x, y, d)),
        }
    };
    consider(p0, closest_point_on_segment(p0, q0, q1).0);
    consider(p1, closest_point_on_segment(p1, q0, q1).0);
    consider(closest_point_on_segment(q0, p0, p1).0, q0);
    consider(closest_point_on_segment(q1, p0, p1).0, q1);
    best.unwrap_or((p0, q0, (p0 - q0).length_squared()))
}

/// True when `a, b, c` span a triangle whose normal can be trusted (see
/// [`SIN2_DEGENERATE`]); degenerate triangles are handled through their
/// edges instead.
#[inline]
pub(crate) fn has_reliable_normal(a: DVec3, b: DVec3, c: DVec3) -> bool {
    let (ab, ac) = (b - a, c - a);
    is_reliable_normal(ab.cross(ac), ab, ac)
}

/// `n = ab × ac` is trustworthy; false for NaN.
#[inline]
fn is_reliable_normal(n: DVec3, ab: DVec3, ac: DVec3) -> bool {
    n.length_squared() > SIN2_DEGENERATE * ab.length_squared() * ac.length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;

    const A: DVec3 = DVec3::new(0.0, 0.0, 0.0);
    const B: DVec3 = DVec3::new(1.0, 0.0, 0.0);
    const C: DVec3 = DVec3::new(0.0, 1.0, 0.0);

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    fn assert_close(got: (DVec3, [f64; 3]), point: DVec3, bary: [f64; 3]) {
        assert!(
            (got.0 - point).length() < 1e-12,
            "point {:?} != {:?}",
            got.0,
            point
        );
        for (g, w) in got.1.iter().zip(bary) {
            assert!((g - w).abs() < 1e-12, "bary {:?}", got.1);
        }
    }

    #[test]
    fn point_above_face_projects_into_the_face() {
        let r = closest_point_on_triangle(v(0.25, 0.25, 5.0), A, B, C);
        assert_close(r, v(0.25, 0.25, 0.0), [0.5, 0.25, 0.25]);
        assert!((point_triangle_distance2(v(0.25, 0.25, 5.0), A, B, C) - 25.0).abs() < 1e-12);
    }

    #[test]
    fn points_in_vertex_regions_snap_to_the_vertex() {
        assert_close(
            closest_point_on_triangle(v(-1.0, -1.0, 1.0), A, B, C),
            A,
            [1.0, 0.0, 0.0],
        );
        assert_close(
            closest_point_on_triangle(v(2.0, -1.0, 0.0), A, B, C),
            B,
            [0.0, 1.0, 0.0],
        );
        assert_close(
            closest_point_on_triangle(v(-1.0, 2.0, -3.0), A, B, C),
            C,
            [0.0, 0.0, 1.0],
        );
    }

    #[test]
    fn points_in_edge_regions_project_onto_the_edge() {
        // Edge ab.
        assert_close(
            closest_point_on_triangle(v(0.5, -1.0, 2.0), A, B, C),
            v(0.5, 0.0, 0.0),
            [0.5, 0.5, 0.0],
        );
        // Edge ca.
        assert_close(
            closest_point_on_triangle(v(-1.0, 0.25, 0.0), A, B, C),
            v(0.0, 0.25, 0.0),
            [0.75, 0.0, 0.25],
        );
        // Edge bc: (1, 1) projects to its midpoint.
        assert_close(
            closest_point_on_triangle(v(1.0, 1.0, 3.0), A, B, C),
            v(0.5, 0.5, 0.0),
            [0.0, 0.5, 0.5],
        );
    }

    #[test]
    fn collinear_triangle_is_treated_as_its_longest_segment() {
        let (a, b, c) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0));
        let (q, bary) = closest_point_on_triangle(v(1.5, 1.0, 0.0), a, b, c);
        assert!((q - v(1.5, 0.0, 0.0)).length() < 1e-15);
        let back = a * bary[0] + b * bary[1] + c * bary[2];
        assert!((back - q).length() < 1e-15);
        assert!(bary.iter().all(|&x| (0.0..=1.0).contains(&x)));
    }

    #[test]
    fn coincident_corners_give_that_point() {
        let p = v(1.0, 2.0, 3.0);
        let (q, bary) = closest_point_on_triangle(v(0.0, 0.0, 0.0), p, p, p);
        assert_eq!(q, p);
        assert!((bary.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // Two coincident corners: the triangle is the segment [a, c].
        let (q, _) = closest_point_on_triangle(v(0.5, 1.0, 7.0), A, A, B);
        assert!((q - v(0.5, 0.0, 0.0)).length() < 1e-15);
    }

    #[test]
    fn nan_input_gives_nan_distance_without_panicking() {
        assert!(point_triangle_distance2(DVec3::NAN, A, B, C).is_nan());
        let d = point_triangle_distance2(v(1.0, 1.0, 1.0), B, C, DVec3::NAN);
        assert!(d.is_nan() || d >= 0.0);
    }

    /// Variational certificate: `q` is the closest point of a convex set `S`
    /// to `p` iff `(p − q)·(x − q) ≤ 0` for every `x ∈ S`; for the convex
    /// hull of the corners, checking the corners suffices.
    fn is_projection(p: DVec3, q: DVec3, corners: &[DVec3], tol: f64) -> bool {
        corners.iter().all(|&x| (p - q).dot(x - q) <= tol)
    }

    fn random_point(rng: &mut Rng, scale: f64) -> DVec3 {
        v(
            rng.range(-scale, scale),
            rng.range(-scale, scale),
            rng.range(-scale, scale),
        )
    }

    #[test]
    fn random_triangles_give_certified_projections() {
        let mut rng = Rng::new(7);
        for i in 0..20_000 {
            let (a, b, c) = (
                random_point(&mut rng, 1.0),
                random_point(&mut rng, 1.0),
                random_point(&mut rng, 1.0),
            );
            // Every tenth triangle is made degenerate in a different way.
            let (a, b, c) = match i % 10 {
                0 => (a, a, c),
                1 => (a, b, a + (b - a) * 0.3),
                2 => (a, a, a),
                _ => (a, b, c),
            };
            let p = random_point(&mut rng, 3.0);
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            assert!(bary.iter().all(|&x| (-1e-12..=1.0 + 1e-12).contains(&x)));
            let back = a * bary[0] + b * bary[1] + c * bary[2];
            assert!((back - q).length() < 1e-9, "case {i}");
            assert!(is_projection(p, q, &[a, b, c], 1e-9), "case {i}");
        }
    }

    #[test]
    fn slivers_and_far_offsets_still_give_certified_projections() {
        let mut rng = Rng::new(13);
        for i in 0..20_000 {
            let (a, b) = (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
            // c within `eps` of the line ab (eps from 1e-3 down to 1e-14,
            // across the degenerate threshold), then everything moved far
            // from the origin.
            let eps = 10f64.powi(-3 - i % 12);
            let off = (b - a).any_orthonormal_vector() * eps;
            let c = a + (b - a) * rng.range(-0.5, 1.5) + off;
            let shift = DVec3::splat(if i % 2 == 0 { 0.0 } else { 1e4 });
            let (a, b, c) = (a + shift, b + shift, c + shift);
            let p = random_point(&mut rng, 2.0) + shift;
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            assert!(
                bary.iter().all(|&x| (-1e-9..=1.0 + 1e-9).contains(&x)),
                "case {i}"
            );
            // Barycentrics of slivers are ill-conditioned (see the
            // function's documentation); the point itself is certified.
            let back = a * bary[0] + b * bary[1] + c * bary[2];
            assert!((back - q).length() < 1e-6, "case {i}");
            // Rounding at 1e4 is ~1e-12 per coordinate; the certificate
            // is a product of two lengths of order 1.
            assert!(is_projection(p, q, &[a, b, c], 1e-7), "case {i}");
        }
    }

    #[test]
    fn random_points_are_no_farther_than_a_dense_barycentric_grid() {
        let mut rng = Rng::new(11);
        for _ in 0..300 {
            let (a, b, c) = (
                random_point(&mut rng, 1.0),
                random_point(&mut rng, 1.0),
                random_point(&mut rng, 1.0),
            );
            let p = random_point(&mut rng, 2.0);
            let d = point_triangle_distance2(p, a, b, c).sqrt();
            let n = 60;
            let mut brute = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=n - i {
                    let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                    brute = brute.min((a + (b - a) * s + (c - a) * t - p).length());
                }
            }
            assert!(d <= brute + 1e-12);
            // The grid spacing bounds how much closer the true point can be.
            assert!(brute - d <= 2.0 * (b - a).length().max((c - a).length()) / n as f64);
        }
    }

    #[test]
    fn crossing_segments_meet_at_their_crossing() {
        let (x, y) = segment_segment_closest(
            v(-1.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.5, -1.0, 2.0),
            v(0.5, 1.0, 2.0),
        );
        assert!((x - v(0.5, 0.0, 0.0)).length() < 1e-15);
        assert!((y - v(0.5, 0.0, 2.0)).length() < 1e-15);
    }

    #[test]
    fn segments_clamped_at_endpoints_meet_endpoint_to_segment() {
        // q's line crosses p's line beyond p1: the answer is p1 to q.
        let (x, y) = segment_segment_closest(
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(3.0, -1.0, 1.0),
            v(3.0, 1.0, 1.0),
        );
        assert_eq!(x, v(1.0, 0.0, 0.0));
        assert!((y - v(3.0, 0.0, 1.0)).length() < 1e-15);
    }

    #[test]
    fn parallel_overlapping_segments_are_their_offset_apart() {
        let (x, y) = segment_segment_closest(
            v(0.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
            v(1.0, 0.5, 0.0),
            v(3.0, 0.5, 0.0),
        );
        assert!(((x - y).length() - 0.5).abs() < 1e-15);
        assert!((1.0..=2.0).contains(&x.x));
        // Parallel and disjoint along the line: end to end.
        let (x, y) = segment_segment_closest(
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(3.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
        );
        assert_eq!((x, y), (v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0)));
    }

    #[test]
    fn zero_length_segments_behave_as_points() {
        let p = v(0.5, 1.0, 0.0);
        let (x, y) = segment_segment_closest(p, p, v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
        assert_eq!(x, p);
        assert!((y - v(0.5, 0.0, 0.0)).length() < 1e-15);
        let (x, y) = segment_segment_closest(p, p, p, p);
        assert_eq!((x, y), (p, p));
    }

    #[test]
    fn random_segment_pairs_give_certified_closest_points() {
        let mut rng = Rng::new(3);
        for i in 0..20_000 {
            let (p0, p1, q0) = (
                random_point(&mut rng, 1.0),
                random_point(&mut rng, 1.0),
                random_point(&mut rng, 1.0),
            );
            let q1 = match i % 5 {
                0 => q0 + (p1 - p0) * rng.range(-2.0, 2.0), // parallel
                1 => q0,                                    // a point
                _ => random_point(&mut rng, 1.0),
            };
            let (x, y) = segment_segment_closest(p0, p1, q0, q1);
            // x is the projection of y onto [p0, p1] and vice versa.
            assert!(is_projection(y, x, &[p0, p1], 1e-12), "case {i}");
            assert!(is_projection(x, y, &[q0, q1], 1e-12), "case {i}");
        }
    }
}
