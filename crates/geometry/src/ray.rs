//! Ray–triangle intersection (Möller & Trumbore 1997).

use glam::DVec3;

/// The parameter `t ≥ 0` at which the ray `origin + t·dir` crosses the
/// triangle `(a, b, c)` (either side), or `None` when it misses, runs
/// parallel to its plane, or the triangle is degenerate. Edges and corners
/// count as hits up to rounding.
pub fn ray_triangle(origin: DVec3, dir: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    // Relative to the sizes involved, so the test is scale-free.
    let scale = e1.length() * e2.length() * dir.length();
    // NaN (a non-finite corner) fails the comparison too.
    if det.abs().partial_cmp(&(1e-12 * scale)) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if !(-1e-12..=1.0 + 1e-12).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < -1e-12 || u + v > 1.0 + 1e-12 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t >= 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_misses_outside_and_parallel() {
        let (a, b, c) = (
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        );
        let down = DVec3::new(0.0, 0.0, -1.0);
        // Straight down onto (0.5, 0.5, 0) from height 3: t = 3.
        assert_eq!(
            ray_triangle(DVec3::new(0.5, 0.5, 3.0), down, a, b, c),
            Some(3.0)
        );
        // From below, going down: behind the origin.
        assert_eq!(
            ray_triangle(DVec3::new(0.5, 0.5, -1.0), down, a, b, c),
            None
        );
        // Outside the hypotenuse.
        assert_eq!(ray_triangle(DVec3::new(1.5, 1.5, 3.0), down, a, b, c), None);
        // Parallel to the plane.
        assert_eq!(
            ray_triangle(DVec3::new(0.5, 0.5, 1.0), DVec3::X, a, b, c),
            None
        );
        // A slanted ray, twice as long a direction: t halves.
        let t = ray_triangle(
            DVec3::new(0.5, 0.5, 2.0),
            DVec3::new(0.0, 0.0, -2.0),
            a,
            b,
            c,
        );
        assert_eq!(t, Some(1.0));
        // Degenerate triangle.
        assert_eq!(ray_triangle(DVec3::new(0.5, 0.0, 1.0), down, a, b, b), None);
    }
}
