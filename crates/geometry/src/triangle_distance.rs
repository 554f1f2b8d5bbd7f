//! Exact Euclidean distance between two triangles, as W §4.1.1 needs for
//! virtual edges (the distance between *triangles* of different components,
//! not between their vertices).

use glam::DVec3;

use crate::closest::{
    closest_point_on_triangle, has_reliable_normal, segment_segment_closest_dist2,
};

/// The closest pair of points of two triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPair {
    /// Squared distance between the triangles (0 when they intersect).
    pub distance2: f64,
    /// The point on the first triangle.
    pub on_first: DVec3,
    /// The point on the second triangle (equal to `on_first` when they
    /// intersect).
    pub on_second: DVec3,
}

impl ClosestPair {
    /// Distance between the triangles.
    #[inline]
    pub fn distance(&self) -> f64 {
        self.distance2.sqrt()
    }
}

/// Where segment `[p, q]` passes through the interior or border of triangle
/// `t`, when it crosses the triangle's plane there; `None` when it does not,
/// or when it lies in the plane (coplanar contact is found through the
/// edges and vertices instead), or when `t` is degenerate.
#[inline]
fn segment_crosses_triangle(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> Option<DVec3> {
    let [a, b, c] = *t;
    let n = (b - a).cross(c - a);
    let (sp, sq) = (n.dot(p - a), n.dot(q - a));
    if (sp > 0.0 && sq > 0.0) || (sp < 0.0 && sq < 0.0) || (sp == 0.0 && sq == 0.0) {
        return None;
    }
    if !(sp - sq).is_finite() || !has_reliable_normal(a, b, c) {
        return None;
    }
    let x = p + (q - p) * (sp / (sp - sq));
    let inside = n.dot((b - a).cross(x - a)) >= 0.0
        && n.dot((c - b).cross(x - b)) >= 0.0
        && n.dot((a - c).cross(x - c)) >= 0.0;
    inside.then_some(x)
}

/// True when the closed triangles share a point (up to rounding on contact
/// exactly at an edge, where [`triangle_triangle_distance`] returns a
/// distance of the order of the rounding error instead of 0).
pub fn triangles_intersect(t1: &[DVec3; 3], t2: &[DVec3; 3]) -> bool {
    triangle_triangle_closest(t1, t2).distance2 == 0.0
}

/// Euclidean distance between two closed triangles, 0 when they intersect.
/// Degenerate triangles (segments, points) are measured as such.
///
/// See [`triangle_triangle_closest`] for the method.
pub fn triangle_triangle_distance(t1: &[DVec3; 3], t2: &[DVec3; 3]) -> f64 {
    triangle_triangle_closest(t1, t2).distance()
}

/// The closest points of two closed triangles.
///
/// Two triangles that intersect do so along a segment (or a polygon when
/// coplanar) whose ends lie on the edges of one of them, so they intersect
/// iff an edge of one meets the other triangle: an edge crossing the other's
/// plane inside it gives distance 0 at once, and coplanar contact shows up
/// as a zero vertex–triangle or edge–edge distance. Otherwise the minimum of
/// the squared distance over the two triangles is attained at a vertex of
/// one of them or between two edges (were both points interior to both
/// faces, the faces would be parallel and a vertex would do as well), so it
/// is the smallest of six vertex–triangle and nine edge–edge distances.
/// Ties go to the first candidate in that order, so results are
/// deterministic.
pub fn triangle_triangle_closest(t1: &[DVec3; 3], t2: &[DVec3; 3]) -> ClosestPair {
    for k in 0..3 {
        let (p, q) = (t1[k], t1[(k + 1) % 3]);
        if let Some(x) = segment_crosses_triangle(p, q, t2) {
            return ClosestPair {
                distance2: 0.0,
                on_first: x,
                on_second: x,
            };
        }
        let (p, q) = (t2[k], t2[(k + 1) % 3]);
        if let Some(x) = segment_crosses_triangle(p, q, t1) {
            return ClosestPair {
                distance2: 0.0,
                on_first: x,
                on_second: x,
            };
        }
    }
    let mut best = ClosestPair {
        distance2: f64::INFINITY,
        on_first: t1[0],
        on_second: t2[0],
    };
    let mut consider = |x: DVec3, y: DVec3, d2: f64| {
        if d2 < best.distance2 {
            best = ClosestPair {
                distance2: d2,
                on_first: x,
                on_second: y,
            };
        }
    };
    for &p in t1 {
        let (q, _) = closest_point_on_triangle(p, t2[0], t2[1], t2[2]);
        consider(p, q, (p - q).length_squared());
    }
    for &q in t2 {
        let (p, _) = closest_point_on_triangle(q, t1[0], t1[1], t1[2]);
        consider(p, q, (p - q).length_squared());
    }
    for i in 0..3 {
        for j in 0..3 {
            let (x, y, d2) =
                segment_segment_closest_dist2(t1[i], t1[(i + 1) % 3], t2[j], t2[(j + 1) % 3]);
            consider(x, y, d2);
        }
    }
    if best.distance2 == f64::INFINITY {
        // Only NaN input gets here; report it as such rather than as "far".
        best.distance2 = f64::NAN;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::closest::point_triangle_distance2;
    use crate::testing::Rng;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    const T: [DVec3; 3] = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];

    #[test]
    fn separated_triangles_are_their_vertex_to_face_gap_apart() {
        // A triangle hovering 2 above T, pointing down at (0.2, 0.2).
        let u = [v(0.2, 0.2, 2.0), v(0.2, 0.2, 5.0), v(1.0, 1.0, 5.0)];
        let r = triangle_triangle_closest(&T, &u);
        assert!((r.distance() - 2.0).abs() < 1e-15);
        assert!((r.on_first - v(0.2, 0.2, 0.0)).length() < 1e-15);
        assert_eq!(r.on_second, u[0]);
        assert!(!triangles_intersect(&T, &u));
    }

    #[test]
    fn triangles_touching_at_a_vertex_are_zero_apart() {
        let u = [v(1.0, 0.0, 0.0), v(2.0, 0.0, 1.0), v(2.0, 1.0, -1.0)];
        assert_eq!(triangle_triangle_distance(&T, &u), 0.0);
        assert!(triangles_intersect(&T, &u));
    }

    #[test]
    fn crossing_triangles_are_zero_apart_at_a_shared_point() {
        // A vertical triangle piercing T's interior along x = 0.25.
        let u = [v(0.25, -1.0, -1.0), v(0.25, 0.3, 1.0), v(0.25, 0.3, -1.0)];
        let r = triangle_triangle_closest(&T, &u);
        assert_eq!(r.distance2, 0.0);
        assert!(point_triangle_distance2(r.on_first, T[0], T[1], T[2]) < 1e-24);
        assert!(point_triangle_distance2(r.on_first, u[0], u[1], u[2]) < 1e-24);
        // Chain-link crossing: neither triangle's vertices are near the other.
        let w = [v(0.2, 0.2, -1.0), v(0.2, 0.2, 1.0), v(-3.0, 0.2, 0.0)];
        assert_eq!(triangle_triangle_distance(&T, &w), 0.0);
    }

    #[test]
    fn coplanar_overlapping_triangles_are_zero_apart() {
        let u = [v(0.2, 0.2, 0.0), v(2.0, 0.2, 0.0), v(0.2, 2.0, 0.0)];
        assert!(triangle_triangle_distance(&T, &u) < 1e-15);
        // One strictly inside the other: no edges cross.
        let small = [v(0.1, 0.1, 0.0), v(0.3, 0.1, 0.0), v(0.1, 0.3, 0.0)];
        assert_eq!(triangle_triangle_distance(&T, &small), 0.0);
        assert_eq!(triangle_triangle_distance(&small, &T), 0.0);
    }

    #[test]
    fn parallel_triangles_offset_by_d_are_d_apart() {
        for d in [1e-6, 0.01, 0.5, 3.0] {
            let u = T.map(|p| p + v(0.1, 0.1, d));
            assert!((triangle_triangle_distance(&T, &u) - d).abs() < 1e-15);
            assert!((triangle_triangle_distance(&u, &T) - d).abs() < 1e-15);
        }
    }

    #[test]
    fn coplanar_disjoint_triangles_are_their_edge_gap_apart() {
        // Mirror of T across the line x + y = 1.5.
        let u = [v(1.5, 1.5, 0.0), v(0.5, 1.5, 0.0), v(1.5, 0.5, 0.0)];
        // Edge bc of T lies on x + y = 1; u's edge on x + y = 2 → gap 1/√2.
        let d = triangle_triangle_distance(&T, &u);
        assert!((d - 0.5f64.sqrt()).abs() < 1e-15, "{d}");
    }

    #[test]
    fn degenerate_triangles_are_measured_as_segments_and_points() {
        let seg = [v(0.2, 0.2, -1.0), v(0.2, 0.2, 1.0), v(0.2, 0.2, 0.5)];
        assert_eq!(triangle_triangle_distance(&T, &seg), 0.0);
        let pt = [v(0.2, 0.2, 5.0); 3];
        assert!((triangle_triangle_distance(&T, &pt) - 5.0).abs() < 1e-15);
        assert!((triangle_triangle_distance(&pt, &pt)).abs() < 1e-15);
        assert!(triangle_triangle_distance(&[DVec3::NAN; 3], &T).is_nan());
    }

    fn random_triangle(rng: &mut Rng, center: DVec3) -> [DVec3; 3] {
        let mut t = [center; 3];
        for p in &mut t {
            *p += v(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
        }
        t
    }

    /// For convex sets the pair (x, y) is closest iff each is the projection
    /// of the other: `(x − y)·(x' − x) ≥ 0` over the corners x' of the first
    /// set and likewise for the second.
    fn certified(r: &ClosestPair, t1: &[DVec3; 3], t2: &[DVec3; 3]) -> bool {
        certified_within(r, t1, t2, 1e-10, 1e-12)
    }

    /// [`certified`] with the points `on` away from their triangles at most
    /// and the variational inequalities violated by `dot` at most.
    fn certified_within(
        r: &ClosestPair,
        t1: &[DVec3; 3],
        t2: &[DVec3; 3],
        on: f64,
        dot: f64,
    ) -> bool {
        let (x, y) = (r.on_first, r.on_second);
        let on1 = point_triangle_distance2(x, t1[0], t1[1], t1[2]) <= on * on;
        let on2 = point_triangle_distance2(y, t2[0], t2[1], t2[2]) <= on * on;
        let d = x - y;
        on1 && on2
            && t1.iter().all(|&p| d.dot(p - x) >= -dot)
            && t2.iter().all(|&q| (-d).dot(q - y) >= -dot)
    }

    #[test]
    fn random_triangle_pairs_give_certified_closest_pairs() {
        let mut rng = Rng::new(5);
        let mut hits = 0;
        for i in 0..20_000 {
            let mut t1 = random_triangle(&mut rng, DVec3::ZERO);
            let off = v(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            );
            let mut t2 = random_triangle(&mut rng, off);
            match i % 8 {
                0 => t2[2] = t2[1],                  // a segment
                1 => t2 = t1.map(|p| p + off * 0.1), // translated copy
                2 => t2[1] = t1[1],                  // shared vertex
                3 => {
                    // A coplanar pair.
                    for p in t1.iter_mut().chain(t2.iter_mut()) {
                        p.z = 0.0;
                    }
                }
                _ => {}
            }
            let r = triangle_triangle_closest(&t1, &t2);
            assert!(certified(&r, &t1, &t2), "case {i}: {r:?}");
            if r.distance2 == 0.0 {
                hits += 1;
            }
            let s = triangle_triangle_closest(&t2, &t1);
            assert!((s.distance2 - r.distance2).abs() < 1e-12, "case {i}");
        }
        assert!(hits > 1000, "the random set must exercise intersections");
    }

    #[test]
    fn sliver_pairs_give_certified_closest_pairs() {
        let mut rng = Rng::new(15);
        for i in 0..10_000 {
            let mut t = [random_triangle(&mut rng, DVec3::ZERO), [DVec3::ZERO; 3]];
            let center = v(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            t[1] = random_triangle(&mut rng, center);
            // Squash one or both into slivers of width 1e-4 to 1e-13.
            let eps = 10f64.powi(-4 - (i % 10) as i32);
            for tri in t.iter_mut().take(1 + i % 2) {
                let (a, b) = (tri[0], tri[1]);
                tri[2] =
                    a + (b - a) * rng.range(-0.5, 1.5) + (b - a).any_orthonormal_vector() * eps;
            }
            let r = triangle_triangle_closest(&t[0], &t[1]);
            // A sliver's plane is ill-conditioned: answers are good to about
            // 1e-8 of its size (see `SIN2_DEGENERATE`), and the checker's
            // own point-to-sliver distances are no better.
            assert!(
                certified_within(&r, &t[0], &t[1], 1e-7, 1e-7),
                "case {i}: {r:?}"
            );
        }
    }

    #[test]
    fn random_pairs_are_no_farther_than_dense_samples() {
        let mut rng = Rng::new(9);
        let n = 24;
        let grid = |t: &[DVec3; 3]| {
            let mut pts = Vec::new();
            for i in 0..=n {
                for j in 0..=n - i {
                    let (s, u) = (i as f64 / n as f64, j as f64 / n as f64);
                    pts.push(t[0] + (t[1] - t[0]) * s + (t[2] - t[0]) * u);
                }
            }
            pts
        };
        for _ in 0..200 {
            let t1 = random_triangle(&mut rng, DVec3::ZERO);
            let center = v(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), 0.0);
            let t2 = random_triangle(&mut rng, center);
            let d = triangle_triangle_distance(&t1, &t2);
            let brute = grid(&t1)
                .iter()
                .map(|&p| point_triangle_distance2(p, t2[0], t2[1], t2[2]).sqrt())
                .fold(f64::INFINITY, f64::min);
            assert!(d <= brute + 1e-12, "{d} > {brute}");
        }
    }
}
