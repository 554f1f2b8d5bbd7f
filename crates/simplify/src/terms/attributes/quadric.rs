//! Hoppe's attribute quadric (Hoppe 1999, "New quadric metric for
//! simplifying meshes with appearance attributes"), for one wedge of one
//! stream of `m` components, stored flat so wedges live in one `Vec<f64>`.
//!
//! A face with area share `a` whose attribute `k` follows `s_k(p) = g_k·p +
//! d_k` contributes, for a vertex at `v` carrying values `s`,
//!
//! `a · Σ_k (g_k·v + d_k − s_k)²`
//! `= vᵀAv + 2bᵀv + c − 2 Σ_k s_k (B_k·v + e_k) + α Σ_k s_k²`
//!
//! with `A = a Σ g_k g_kᵀ`, `b = a Σ d_k g_k`, `c = a Σ d_k²`, `B_k = a g_k`,
//! `e_k = a d_k`, `α = a`; all of them add up over faces and over merged
//! wedges (memory, like the plane quadrics). For a given `v` the best values
//! are `s_k = (B_k·v + e_k) / α` (the least-squares fit of the faces' linear
//! functions at `v`), and putting them back leaves a quadric in `v` alone:
//!
//! `A' = A − Σ B_k B_kᵀ / α`, `b' = b − Σ e_k B_k / α`, `c' = c − Σ e_k² / α`
//!
//! which is what a collapse adds to its position quadric, so that the
//! optimal position accounts for the attributes (Hoppe's joint solve).

use glam::DVec3;

use crate::terms::quadric::Quadric;

/// Layout of one wedge's quadric: `[α, A (6), b (3), c, B (3m), e (m)]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    /// Components of the stream.
    pub m: usize,
}

const ALPHA: usize = 0;
const A: usize = 1;
const B_LIN: usize = 7;
const C: usize = 10;
const GRAD: usize = 11;

impl Layout {
    /// Floats per wedge.
    pub fn stride(self) -> usize {
        GRAD + 4 * self.m
    }

    /// Adds a face's contribution: area share `a`, gradients `g[k]` and
    /// offsets `d[k]` of its `m` components.
    pub fn add_face(self, q: &mut [f64], a: f64, g: &[DVec3], d: &[f64]) {
        q[ALPHA] += a;
        for k in 0..self.m {
            let (gk, dk) = (g[k], d[k]);
            let ag = gk * a;
            q[A] += ag.x * gk.x;
            q[A + 1] += ag.x * gk.y;
            q[A + 2] += ag.x * gk.z;
            q[A + 3] += ag.y * gk.y;
            q[A + 4] += ag.y * gk.z;
            q[A + 5] += ag.z * gk.z;
            q[B_LIN] += ag.x * dk;
            q[B_LIN + 1] += ag.y * dk;
            q[B_LIN + 2] += ag.z * dk;
            q[C] += a * dk * dk;
            let s = GRAD + 3 * k;
            q[s] += ag.x;
            q[s + 1] += ag.y;
            q[s + 2] += ag.z;
            q[GRAD + 3 * self.m + k] += a * dk;
        }
    }

    /// The total area share `α`.
    #[cfg(test)]
    pub fn alpha(self, q: &[f64]) -> f64 {
        q[ALPHA]
    }

    /// The position quadric left after choosing the best values for every
    /// `v` (see the module docs), times `scale`. Zero without area.
    pub fn reduce(self, q: &[f64], scale: f64) -> Quadric {
        let alpha = q[ALPHA];
        if (alpha.is_nan() || alpha <= 0.0) || scale == 0.0 {
            return Quadric::ZERO;
        }
        let mut a = [q[A], q[A + 1], q[A + 2], q[A + 3], q[A + 4], q[A + 5]];
        let mut b = DVec3::new(q[B_LIN], q[B_LIN + 1], q[B_LIN + 2]);
        let mut c = q[C];
        let inv = 1.0 / alpha;
        for k in 0..self.m {
            let s = GRAD + 3 * k;
            let g = DVec3::new(q[s], q[s + 1], q[s + 2]);
            let e = q[GRAD + 3 * self.m + k];
            let gi = g * inv;
            a[0] -= gi.x * g.x;
            a[1] -= gi.x * g.y;
            a[2] -= gi.x * g.z;
            a[3] -= gi.y * g.y;
            a[4] -= gi.y * g.z;
            a[5] -= gi.z * g.z;
            b -= gi * e;
            c -= e * e * inv;
        }
        Quadric {
            a: a.map(|x| x * scale),
            b: b * scale,
            c: c * scale,
            weight: 0.0,
        }
    }

    /// The best values at `v`: `s_k = (B_k·v + e_k) / α`, into `out` (`m`
    /// values). `None` without area.
    pub fn values(self, q: &[f64], v: DVec3, out: &mut [f64]) -> Option<()> {
        let alpha = q[ALPHA];
        if alpha.is_nan() || alpha <= 0.0 {
            return None;
        }
        for (k, o) in out.iter_mut().enumerate().take(self.m) {
            let s = GRAD + 3 * k;
            let g = DVec3::new(q[s], q[s + 1], q[s + 2]);
            *o = (g.dot(v) + q[GRAD + 3 * self.m + k]) / alpha;
        }
        Some(())
    }

    /// The attribute error of carrying values `s` at `v` (the unreduced
    /// quadric); for tests and diagnostics.
    #[cfg(test)]
    pub fn error(self, q: &[f64], v: DVec3, s: &[f64]) -> f64 {
        let quad = Quadric {
            a: [q[A], q[A + 1], q[A + 2], q[A + 3], q[A + 4], q[A + 5]],
            b: DVec3::new(q[B_LIN], q[B_LIN + 1], q[B_LIN + 2]),
            c: q[C],
            weight: 0.0,
        };
        let mut e = quad.eval(v);
        for (k, &sk) in s.iter().enumerate().take(self.m) {
            let g = DVec3::new(q[GRAD + 3 * k], q[GRAD + 3 * k + 1], q[GRAD + 3 * k + 2]);
            e += -2.0 * sk * (g.dot(v) + q[GRAD + 3 * self.m + k]) + q[ALPHA] * sk * sk;
        }
        e
    }
}

/// `dst += src`, element-wise (merging wedges).
#[inline]
pub(crate) fn accumulate(dst: &mut [f64], src: &[f64]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d += s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_linear_field_has_no_error_and_gives_its_value_anywhere() {
        // One component, s(p) = 2x − y + 3, from two faces of areas 0.5 and
        // 0.25 (same field): the reduced quadric is zero and the fitted value
        // at any v is the field's.
        let l = Layout { m: 1 };
        let mut q = vec![0.0; l.stride()];
        let g = [DVec3::new(2.0, -1.0, 0.0)];
        l.add_face(&mut q, 0.5, &g, &[3.0]);
        l.add_face(&mut q, 0.25, &g, &[3.0]);
        let v = DVec3::new(0.3, -2.0, 7.0);
        let mut s = [0.0];
        l.values(&q, v, &mut s).unwrap();
        assert!((s[0] - (0.6 + 2.0 + 3.0)).abs() < 1e-12, "{}", s[0]);
        let r = l.reduce(&q, 1.0);
        assert!(r.eval(v).abs() < 1e-12);
        // The unreduced error at the fitted value is zero too, and carrying
        // a value off by 0.5 costs α · 0.25 = 0.1875.
        assert!(l.error(&q, v, &s).abs() < 1e-12);
        assert!((l.error(&q, v, &[s[0] + 0.5]) - 0.1875).abs() < 1e-12);
    }

    #[test]
    fn two_fields_disagree_by_a_hand_computed_amount() {
        // Face 1 (area 1): s = x. Face 2 (area 1): s = −x. At v = (2, 0, 0)
        // the best value is the mean, 0, and each face misses by 2: the
        // reduced error is 1·4 + 1·4 = 8; at the origin it is 0.
        let l = Layout { m: 1 };
        let mut q = vec![0.0; l.stride()];
        l.add_face(&mut q, 1.0, &[DVec3::X], &[0.0]);
        l.add_face(&mut q, 1.0, &[-DVec3::X], &[0.0]);
        let r = l.reduce(&q, 1.0);
        assert!((r.eval(DVec3::new(2.0, 0.0, 0.0)) - 8.0).abs() < 1e-12);
        assert!(r.eval(DVec3::ZERO).abs() < 1e-12);
        // Scaled by the stream's weight.
        assert!((l.reduce(&q, 0.25).eval(DVec3::new(2.0, 0.0, 0.0)) - 2.0).abs() < 1e-12);
        let mut s = [9.0];
        l.values(&q, DVec3::new(2.0, 0.0, 0.0), &mut s).unwrap();
        assert!(s[0].abs() < 1e-12);
    }

    #[test]
    fn merged_wedges_sum_and_components_are_independent() {
        // Two components: (x, y) on one face, (x + 1, 2y) on another.
        let l = Layout { m: 2 };
        let mut a = vec![0.0; l.stride()];
        let mut b = vec![0.0; l.stride()];
        l.add_face(&mut a, 2.0, &[DVec3::X, DVec3::Y], &[0.0, 0.0]);
        l.add_face(&mut b, 1.0, &[DVec3::X, 2.0 * DVec3::Y], &[1.0, 0.0]);
        accumulate(&mut a, &b);
        assert_eq!(l.alpha(&a), 3.0);
        // At v = (0, 1, 0): component 0 = (2·0 + 1·1)/3 = 1/3; component 1 =
        // (2·1 + 1·2)/3 = 4/3.
        let mut s = [0.0; 2];
        l.values(&a, DVec3::Y, &mut s).unwrap();
        assert!((s[0] - 1.0 / 3.0).abs() < 1e-12 && (s[1] - 4.0 / 3.0).abs() < 1e-12);
        // Reduced error there: component 0: 2·(1/3)² + 1·(2/3)² = 2/3;
        // component 1: 2·(1/3)² + 1·(2/3)² = 2/3. Total 4/3.
        let r = l.reduce(&a, 1.0);
        assert!(
            (r.eval(DVec3::Y) - 4.0 / 3.0).abs() < 1e-12,
            "{}",
            r.eval(DVec3::Y)
        );
        // The unreduced error at the best values equals the reduced one.
        assert!((l.error(&a, DVec3::Y, &s) - r.eval(DVec3::Y)).abs() < 1e-12);
    }

    #[test]
    fn no_area_reduces_to_zero_and_has_no_value() {
        let l = Layout { m: 3 };
        let q = vec![0.0; l.stride()];
        assert_eq!(l.reduce(&q, 1.0), Quadric::ZERO);
        assert!(l.values(&q, DVec3::ZERO, &mut [0.0; 3]).is_none());
    }
}
