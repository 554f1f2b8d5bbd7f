//! A triangle of a recorded edge one-ring with the bounds the coherent
//! walk reasons with (W §4.3.1, App. C.2): which ring triangles can be no
//! point's choice over a whole ball of points. The distances a walk
//! compares come from `ring_block.rs`; the closest *point* is needed only
//! once per walk, at its end, and comes from Ericson's region test here.

use glam::Vec3;
use wildlod_geometry::closest_point_on_triangle;

/// A ring triangle with its bounds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RingTriangle {
    pub corners: [Vec3; 3],
    pub center: Vec3,
    /// Bounding-sphere radius around `center`, a hair larger than measured
    /// so that rounding never makes it skip the true closest triangle.
    pub radius: f32,
    /// The input face the triangle belongs to.
    pub face: u32,
    /// Largest absolute corner coordinate: the scale of the rounding in
    /// distances to it.
    pub mag: f32,
}

impl RingTriangle {
    /// The triangle `corners` of input face `face`.
    pub fn new(corners: [Vec3; 3], face: u32) -> Self {
        let center = (corners[0] + corners[1] + corners[2]) / 3.0;
        let radius = corners
            .iter()
            .map(|&q| q.distance(center))
            .fold(0.0f32, f32::max);
        RingTriangle {
            corners,
            center,
            radius: radius * (1.0 + 1e-5) + 1e-12,
            face,
            mag: corners
                .iter()
                .map(|q| q.abs().max_element())
                .fold(0.0f32, f32::max),
        }
    }

    /// The point of the triangle closest to `p`.
    #[inline]
    pub fn closest(&self, p: Vec3) -> Vec3 {
        closest_on_triangle(p, &self.corners)
    }
}

/// The point of triangle `t` closest to `p` (Ericson, *Real-Time Collision
/// Detection*, §5.1.5, by Voronoi regions), in `f32`. A degenerate triangle
/// can divide by zero there; it then goes to the exact `f64` routine of
/// `wildlod-geometry`.
#[inline]
pub(crate) fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + ab * v;
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + ac * w;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + (c - b) * w;
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    let q = a + ab * v + ac * w;
    if q.is_finite() {
        q
    } else {
        let (q, _) =
            closest_point_on_triangle(p.as_dvec3(), a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
        q.as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_closest_point_agrees_with_the_exact_one() {
        let t = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.1, 0.0),
            Vec3::new(0.3, 1.5, 0.2),
        ];
        // A grid of query points around the triangle hits every region.
        for i in -4..=8 {
            for j in -4..=8 {
                for k in -2..=2 {
                    let p = Vec3::new(i as f32 * 0.3, j as f32 * 0.3, k as f32 * 0.4);
                    let fast = closest_on_triangle(p, &t);
                    let (exact, _) = closest_point_on_triangle(
                        p.as_dvec3(),
                        t[0].as_dvec3(),
                        t[1].as_dvec3(),
                        t[2].as_dvec3(),
                    );
                    assert!((fast.as_dvec3() - exact).length() < 1e-5, "{p:?}");
                }
            }
        }
        // Degenerate (collinear) triangles still give a point on them.
        let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let q = closest_on_triangle(Vec3::new(1.5, 1.0, 0.0), &flat);
        assert!((q - Vec3::new(1.5, 0.0, 0.0)).length() < 1e-6, "{q:?}");
    }
}
