//! How a run keeps its per-vertex quadrics: in single precision, each
//! expanded about its vertex's position, so that a million-vertex run
//! holds 64 bytes per vertex of them instead of 128 (issue 15's memory
//! bar).
//!
//! Single precision is enough once the expansion point is near where the
//! quadric is evaluated. Stored as `xᵀAx + 2bᵀx + c`, a quadric evaluated
//! near its vertex is a difference of large numbers (`c` alone is about
//! `|x|²` times the weight), which single precision would round to noise
//! at the scale of a fine mesh's edges. About an origin `o` near the vertex
//! the same quadric is `uᵀAu + 2gᵀu + e` with `u = x − o`, `g = Ao + b` (half
//! its gradient at `o`) and `e = E(o)`: every stored number is small where
//! it matters, and rounding each costs a relative 6e-8 of what it is. The
//! arithmetic (sums, placement, costs) stays in double precision on the
//! expanded [`Quadric`]; only what lives between collapses is compact.
//!
//! The origin is not stored: it is the vertex's position rounded to single
//! precision, and only a collapse moves a vertex (and stores the merged
//! quadric about the new one) until the final refit, which reads the
//! quadrics about the positions it started from. Whoever expands a quadric
//! passes that position; debug builds check it. Rounded, not exact: the
//! numbers are then those measured when the origin was kept in the struct
//! (outputs byte-identical); about the exact position, where a vertex's
//! own error is pure cancellation of either sign, a hair-thin spur
//! (`tests/geometry.rs`) lost 70% of its height at 20% under the area
//! floor instead of nothing.

use crate::terms::quadric::{sym_mul, Quadric};
use glam::DVec3;

/// A vertex quadric as a run stores it: [`Quadric`] in single precision,
/// expanded about its vertex's position (see the module documentation).
/// 44 bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct StoredQuadric {
    /// Upper triangle of A: xx, xy, xz, yy, yz, zz.
    a: [f32; 6],
    /// `A·origin + b`.
    g: [f32; 3],
    /// `E(origin)`.
    e: f32,
    weight: f32,
    /// The origin, to check that the quadric is expanded about it.
    #[cfg(debug_assertions)]
    origin: DVec3,
}

/// `x` rounded to single precision, non-finite components to 0 (an
/// origin only has to be somewhere; the quadric is exact about any).
fn round(x: DVec3) -> [f32; 3] {
    x.to_array()
        .map(|v| if v.is_finite() { v as f32 } else { 0.0 })
}

fn widen(x: [f32; 3]) -> DVec3 {
    DVec3::new(x[0] as f64, x[1] as f64, x[2] as f64)
}

impl StoredQuadric {
    /// `q`, expanded about `origin` (rounded to single precision): the
    /// vertex's position, where the run evaluates it.
    pub fn new(q: &Quadric, origin: DVec3) -> StoredQuadric {
        let o = widen(round(origin));
        let g = sym_mul(&q.a, o) + q.b;
        StoredQuadric {
            a: q.a.map(|v| v as f32),
            g: round(g),
            e: q.eval(o) as f32,
            weight: q.weight as f32,
            #[cfg(debug_assertions)]
            origin,
        }
    }

    /// The stored quadric in double precision, in the usual form, given
    /// the `origin` it was stored about (its vertex's position then).
    #[inline]
    pub fn quadric(&self, origin: DVec3) -> Quadric {
        #[cfg(debug_assertions)]
        debug_assert!(
            self.origin == origin || self.weight == 0.0 && self.e == 0.0,
            "quadric stored about {} read about {origin}",
            self.origin
        );
        let o = widen(round(origin));
        let a = self.a.map(f64::from);
        let g = widen(self.g);
        let ao = sym_mul(&a, o);
        Quadric {
            a,
            b: g - ao,
            c: o.dot(ao) - 2.0 * g.dot(o) + self.e as f64,
            weight: self.weight as f64,
        }
    }

    /// The accumulated weight (area).
    #[inline]
    pub fn weight(&self) -> f64 {
        self.weight as f64
    }
}

/// An isotropic quadric `s |x − m|² + r`: a sum of point quadrics
/// ([`Quadric::point`]) such as the regularization part a run keeps per
/// vertex, as its total weight `s`, the weighted mean `m` of its points
/// and their weighted spread `r` about it, in single precision (20 bytes;
/// the general form would take 40 in double precision). The mean is the
/// natural origin here: the spread is what is left after it is taken out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Isotropic {
    s: f32,
    m: [f32; 3],
    r: f32,
}

impl Isotropic {
    /// The isotropic part of `q`: exact (up to the rounding of what is
    /// stored) when `q` is a sum of point quadrics (off-diagonal zero,
    /// equal diagonal, no weight).
    pub fn of(q: &Quadric) -> Isotropic {
        debug_assert!(q.a[1] == 0.0 && q.a[2] == 0.0 && q.a[4] == 0.0);
        debug_assert!(q.a[0] == q.a[3] && q.a[0] == q.a[5] && q.weight == 0.0);
        let s = q.a[0];
        if s > 0.0 {
            let m = round(-q.b / s);
            Isotropic {
                s: s as f32,
                m,
                r: q.eval(widen(m)) as f32,
            }
        } else {
            Isotropic {
                s: s as f32,
                m: [0.0; 3],
                r: q.c as f32,
            }
        }
    }

    /// As a full quadric (double precision).
    #[inline]
    pub fn quadric(&self) -> Quadric {
        let (s, m) = (self.s as f64, widen(self.m));
        Quadric {
            a: [s, 0.0, 0.0, s, 0.0, s],
            b: -m * s,
            c: s * m.length_squared() + self.r as f64,
            weight: 0.0,
        }
    }
}

impl std::ops::Add for Isotropic {
    type Output = Isotropic;
    /// The sum, about the new weighted mean (the parallel-axis theorem:
    /// each part's spread grows by its weight times its mean's squared
    /// distance to the new one).
    fn add(self, o: Isotropic) -> Isotropic {
        let (s1, s2) = (self.s as f64, o.s as f64);
        let (m1, m2) = (widen(self.m), widen(o.m));
        let s = s1 + s2;
        let spread = self.r as f64 + o.r as f64;
        if s > 0.0 {
            let m = round((m1 * s1 + m2 * s2) / s);
            let mw = widen(m);
            Isotropic {
                s: s as f32,
                m,
                r: (spread + s1 * m1.distance_squared(mw) + s2 * m2.distance_squared(mw)) as f32,
            }
        } else {
            Isotropic {
                s: s as f32,
                m: [0.0; 3],
                r: spread as f32,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs())
    }

    #[test]
    fn a_stored_quadric_is_exact_at_its_origin_and_close_everywhere() {
        // The plane z = 0.25 with weight 2, plus a boundary term, stored
        // about (0.125, 0.25, 0.375), whose coordinates single precision
        // holds exactly: E(origin) = 2 · (0.375 − 0.25)² = 0.03125.
        let plane = Quadric::plane(DVec3::Z, DVec3::new(0.0, 0.0, 0.25), 2.0);
        let o = DVec3::new(0.125, 0.25, 0.375);
        let s = StoredQuadric::new(&plane, o);
        assert_eq!(s.e, 0.03125);
        assert_eq!(s.weight(), 2.0);
        // g = A o + b = 2 n (n·o − 0.25) = (0, 0, 0.25).
        assert_eq!(s.g, [0.0, 0.0, 0.25]);
        let back = s.quadric(o);
        assert_eq!(back.eval(o), 0.03125);
        let q = plane + Quadric::boundary_area(DVec3::new(0.1, 0.0, 0.2), DVec3::ONE);
        let back = StoredQuadric::new(&q, o).quadric(o);
        for x in [
            o,
            DVec3::ZERO,
            DVec3::new(0.3, -0.2, 0.9),
            DVec3::splat(2.0),
        ] {
            assert!(close(back.eval(x), q.eval(x), 1e-6), "{x}");
        }
    }

    #[test]
    fn small_differences_near_the_origin_survive_single_precision() {
        // A vertex far from the coordinate origin, on the plane x = 0.7:
        // moving it by 1e-5 along the normal costs 1e-10. Stored as
        // (A, b, c) in single precision, c = 0.49 alone would be rounded by
        // 3e-8, 300 times that cost; expanded about the vertex the cost
        // comes back to a relative 1e-6, about the vertex rounded to single
        // precision as about the vertex itself.
        let p = DVec3::new(0.7, 0.6, -0.4) + DVec3::splat(1e-12);
        let q = Quadric::plane(DVec3::X, p, 1.0);
        let back = StoredQuadric::new(&q, p).quadric(p);
        let moved = p + DVec3::new(1e-5, 3e-6, 0.0);
        assert!(back.eval(p).abs() < 1e-15);
        assert!(close(back.eval(moved), 1e-10, 1e-6), "{}", back.eval(moved));
    }

    #[test]
    fn isotropic_is_weight_mean_and_spread() {
        // Points (0,0,0) and (2,0,0), weight 1 each: s = 2, m = (1,0,0),
        // spread 1 + 1 = 2; E((1,1,0)) = |(1,1,0)|² + |(−1,1,0)|² = 4.
        let a = Quadric::point(DVec3::ZERO, 1.0);
        let b = Quadric::point(DVec3::new(2.0, 0.0, 0.0), 1.0);
        let both = Isotropic::of(&(a + b));
        assert_eq!((both.s, both.m, both.r), (2.0, [1.0, 0.0, 0.0], 2.0));
        let x = DVec3::new(1.0, 1.0, 0.0);
        assert_eq!(both.quadric().eval(x), 4.0);
        // Summed as isotropic quadrics: the same (parallel axes).
        let summed = Isotropic::of(&a) + Isotropic::of(&b);
        assert_eq!(summed, both);
        // With a third point of weight 2 at (1,3,0): s = 4, m = (1,1.5,0),
        // spread 2 + 2·1.5² + 2·1.5² = 11.
        let c = Isotropic::of(&Quadric::point(DVec3::new(1.0, 3.0, 0.0), 2.0));
        let all = summed + c;
        assert_eq!((all.s, all.m, all.r), (4.0, [1.0, 1.5, 0.0], 11.0));
        // The zero quadric stays zero.
        let zero = Isotropic::of(&Quadric::ZERO);
        assert_eq!(zero + zero, Isotropic::default());
        assert_eq!(zero.quadric(), Quadric::ZERO);
    }
}
