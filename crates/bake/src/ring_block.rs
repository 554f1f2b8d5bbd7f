//! Distances from a point to every triangle of a recorded edge one-ring,
//! four triangles at a time (W §4.3.1: each step of a walk through the
//! history picks the ring triangle closest to the point).
//!
//! A walk takes about ten steps per texel and a ring holds about nine
//! triangles, so the whole mapping is these distances. Measuring all of a
//! ring's triangles branch-free, in structure-of-arrays blocks of four
//! that the compiler turns into vector instructions, costs less than
//! skipping most of them by bounds one at a time, and the argmin is then
//! exact with no rounding argument about what a bound may skip.
//!
//! The squared distance comes from an in-plane dual basis: two dot
//! products give the barycentrics of the point's shadow on the triangle's
//! plane; when the shadow is inside, the distance is the plane distance,
//! else the least distance to the edges whose lines have the shadow on
//! their outer side (the closest point of a convex polygon to an outside
//! point lies on such an edge). A degenerate triangle gets a NaN basis,
//! which makes every edge count as outer: its distance is that to the
//! segments it collapses to.

use glam::{DVec3, Vec3};

/// Lanes of a block.
pub(crate) const LANES: usize = 4;

/// Four triangles as structure of arrays (each field: x, y, z lanes).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(16))]
pub(crate) struct RingBlock {
    /// First corner.
    a: [[f32; LANES]; 3],
    /// Edges `ab`, `ac`, `bc`.
    e1: [[f32; LANES]; 3],
    e2: [[f32; LANES]; 3],
    e3: [[f32; LANES]; 3],
    /// Dual basis of `ab`, `ac` in the plane: the shadow of `p` is
    /// `a + s·ab + t·ac` with `s = du · (p − a)`, `t = dv · (p − a)`.
    du: [[f32; LANES]; 3],
    dv: [[f32; LANES]; 3],
    /// Unit normal.
    n: [[f32; LANES]; 3],
    /// `1 / |e|²` for `ab`, `ac`, `bc` (zero for a zero-length edge).
    inv: [[f32; LANES]; 3],
}

impl RingBlock {
    /// Blocks for `triangles`, in order, the last one padded (padding
    /// lanes measure garbage and are never read).
    pub fn pack(triangles: &[[Vec3; 3]], out: &mut Vec<RingBlock>) {
        for chunk in triangles.chunks(LANES) {
            let mut b = RingBlock::default();
            for (l, t) in chunk.iter().enumerate() {
                b.set(l, t);
            }
            out.push(b);
        }
    }

    fn set(&mut self, l: usize, corners: &[Vec3; 3]) {
        let [a, b, c] = corners.map(|q| q.as_dvec3());
        let (e1, e2, e3) = (b - a, c - a, c - b);
        let (l1, l2, l12) = (e1.length_squared(), e2.length_squared(), e1.dot(e2));
        let det = l1 * l2 - l12 * l12;
        // Below `f32`'s precision relative to the edges the basis carries
        // no digit: measure such a sliver by its edges alone.
        let (du, dv) = if det > 1e-10 * l1 * l2 {
            ((e1 * l2 - e2 * l12) / det, (e2 * l1 - e1 * l12) / det)
        } else {
            (DVec3::NAN, DVec3::NAN)
        };
        let n = e1.cross(e2).normalize_or_zero();
        let inv = |x: f64| if x > 0.0 { (1.0 / x) as f32 } else { 0.0 };
        let put = |f: &mut [[f32; LANES]; 3], v: Vec3| {
            f[0][l] = v.x;
            f[1][l] = v.y;
            f[2][l] = v.z;
        };
        put(&mut self.a, corners[0]);
        put(&mut self.e1, corners[1] - corners[0]);
        put(&mut self.e2, corners[2] - corners[0]);
        put(&mut self.e3, corners[2] - corners[1]);
        put(&mut self.du, du.as_vec3());
        put(&mut self.dv, dv.as_vec3());
        put(&mut self.n, n.as_vec3());
        put(
            &mut self.inv,
            Vec3::new(inv(l1), inv(l2), inv(e3.length_squared())),
        );
    }

    /// Triangle `l` of `self` copied into lane `to` of `out`, field by
    /// field: `out` measures it bit for bit as `self` does.
    pub fn copy_lane(&self, l: usize, out: &mut RingBlock, to: usize) {
        for (dst, src) in [
            (&mut out.a, &self.a),
            (&mut out.e1, &self.e1),
            (&mut out.e2, &self.e2),
            (&mut out.e3, &self.e3),
            (&mut out.du, &self.du),
            (&mut out.dv, &self.dv),
            (&mut out.n, &self.n),
            (&mut out.inv, &self.inv),
        ] {
            for c in 0..3 {
                dst[c][to] = src[c][l];
            }
        }
    }

    /// Squared distances from `p` to the block's four triangles.
    #[inline]
    pub fn distances(&self, p: Vec3) -> [f32; LANES] {
        let mut d = [0.0; LANES];
        for (l, d) in d.iter_mut().enumerate() {
            *d = self.lane(l, p);
        }
        d
    }

    /// Squared distance from `p` to triangle `l` of the block: the same
    /// operations, in the same order, as [`RingBlock::distances`], so the
    /// two agree bit for bit.
    #[inline(always)]
    pub fn lane(&self, l: usize, p: Vec3) -> f32 {
        let ap = [p.x - self.a[0][l], p.y - self.a[1][l], p.z - self.a[2][l]];
        let dot =
            |f: &[[f32; LANES]; 3], v: [f32; 3]| f[0][l] * v[0] + f[1][l] * v[1] + f[2][l] * v[2];
        let s = dot(&self.du, ap);
        let t = dot(&self.dv, ap);
        let h = dot(&self.n, ap);
        // Distance from `w` to the segment from its origin along `e`.
        let segment = |e: &[[f32; LANES]; 3], w: [f32; 3], inv: f32| {
            let x = dot(e, w) * inv;
            let x = if x > 0.0 { x } else { 0.0 };
            let x = if x < 1.0 { x } else { 1.0 };
            let q = [w[0] - e[0][l] * x, w[1] - e[1][l] * x, w[2] - e[2][l] * x];
            q[0] * q[0] + q[1] * q[1] + q[2] * q[2]
        };
        let bp = [
            ap[0] - self.e1[0][l],
            ap[1] - self.e1[1][l],
            ap[2] - self.e1[2][l],
        ];
        let d_ab = segment(&self.e1, ap, self.inv[0][l]);
        let d_ac = segment(&self.e2, ap, self.inv[1][l]);
        let d_bc = segment(&self.e3, bp, self.inv[2][l]);
        let u = s + t;
        // An edge counts unless the shadow is on its inner side; a NaN
        // basis (a degenerate triangle) fails every test: all edges count.
        let d_ab = if t >= 0.0 { f32::INFINITY } else { d_ab };
        let d_ac = if s >= 0.0 { f32::INFINITY } else { d_ac };
        let d_bc = if u <= 1.0 { f32::INFINITY } else { d_bc };
        let out = if d_ab < d_ac { d_ab } else { d_ac };
        let out = if out < d_bc { out } else { d_bc };
        let inside = s >= 0.0 && t >= 0.0 && u <= 1.0;
        if inside {
            h * h
        } else {
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_geometry::closest_point_on_triangle;

    fn exact_distance(p: Vec3, t: &[Vec3; 3]) -> f64 {
        let (q, _) = closest_point_on_triangle(
            p.as_dvec3(),
            t[0].as_dvec3(),
            t[1].as_dvec3(),
            t[2].as_dvec3(),
        );
        (q - p.as_dvec3()).length()
    }

    fn block(tris: &[[Vec3; 3]]) -> RingBlock {
        let mut out = Vec::new();
        RingBlock::pack(tris, &mut out);
        assert_eq!(out.len(), 1);
        out[0]
    }

    #[test]
    fn distances_to_a_right_triangle_are_the_hand_computed_ones() {
        // The right triangle (0,0,0), (2,0,0), (0,2,0).
        let b = block(&[[Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0]]);
        // Above the interior: the height.
        assert_eq!(b.lane(0, Vec3::new(0.5, 0.5, 3.0)), 9.0);
        // Beyond edge ab (y < 0): to (1, 0, 0), 1 + 4.
        assert_eq!(b.lane(0, Vec3::new(1.0, -1.0, 2.0)), 5.0);
        // Beyond the hypotenuse: (2, 2, 0) is √2 from its midpoint.
        assert!((b.lane(0, Vec3::new(2.0, 2.0, 0.0)) - 2.0).abs() < 1e-6);
        // In corner a's region, beyond two edges: to the origin.
        assert_eq!(b.lane(0, Vec3::new(-1.0, -2.0, 2.0)), 9.0);
        // Beyond corner c, past both ac and bc: to (0, 2, 0).
        assert!((b.lane(0, Vec3::new(-1.0, 3.0, 0.0)) - 2.0).abs() < 1e-6);
    }

    #[test]
    fn distances_agree_with_the_exact_routine_in_every_region() {
        let tris = [
            // A tilted triangle.
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.1, 0.0),
                Vec3::new(0.3, 1.5, 0.2),
            ],
            // A sliver.
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(3.0, 0.0, 0.0),
                Vec3::new(1.5, 1e-3, 0.0),
            ],
            // Collinear: the segment from 0 to 2x.
            [Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
            // All three corners at one point.
            [Vec3::ONE; 3],
        ];
        let b = block(&tris);
        for i in -4..=10 {
            for j in -4..=8 {
                for k in -2..=2 {
                    let p = Vec3::new(i as f32 * 0.3, j as f32 * 0.3, k as f32 * 0.4);
                    let all = b.distances(p);
                    for (l, t) in tris.iter().enumerate() {
                        // The vector form and the lane agree bit for bit.
                        assert_eq!(all[l].to_bits(), b.lane(l, p).to_bits());
                        let fast = f64::from(all[l]).sqrt();
                        let exact = exact_distance(p, t);
                        assert!((fast - exact).abs() < 1e-5, "{t:?} {p:?}: {fast} {exact}");
                    }
                }
            }
        }
    }
}
