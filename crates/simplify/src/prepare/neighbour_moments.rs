//! The positions of a vertex's listed neighbours, summed to second order,
//! so that a sum over them of a function quadratic in each (the crease
//! area term's swept areas, W Eq. 15) is read in constant time.
//!
//! A vertex of a fan written from a rim vertex has most of its hundred
//! thousand sides as creases (rounded corners fold the slivers), and the
//! crease area term summed the swept area against every one of them at
//! every evaluation of one of its edges: two thirds of the run. The
//! moments are kept with the crease lists (see `Complex::keep_crease_lists`),
//! a neighbour added or removed as its side becomes or stops being a
//! crease, or moved when it is the kept vertex of a collapse.

use glam::DVec3;

/// Count, sum and sum of outer products of a set of points, and the
/// largest squared length any of them had (never lowered: a bound on how
/// far they are from the origin, so that a term can tell an outlier among
/// them without reading them).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NeighbourMoments {
    /// How many points.
    pub count: f64,
    /// Their sum.
    pub sum: DVec3,
    /// The sum of their outer products k kᵀ: xx, xy, xz, yy, yz, zz.
    pub outer: [f64; 6],
    /// At least the largest squared length of any point added.
    pub max_norm_sq: f64,
}

impl NeighbourMoments {
    /// The moments of `points`.
    pub fn of(points: impl IntoIterator<Item = DVec3>) -> Self {
        let mut m = NeighbourMoments::default();
        for k in points {
            m.add(k);
        }
        m
    }

    /// Adds point `k`.
    pub fn add(&mut self, k: DVec3) {
        let n = k.length_squared();
        // NaN counts as infinitely far.
        self.max_norm_sq = if n.is_nan() {
            f64::INFINITY
        } else {
            self.max_norm_sq.max(n)
        };
        self.shift(k, 1.0);
    }

    /// Removes point `k`, added before.
    pub fn remove(&mut self, k: DVec3) {
        self.shift(k, -1.0);
    }

    fn shift(&mut self, k: DVec3, s: f64) {
        self.count += s;
        self.sum += s * k;
        let o = [
            k.x * k.x,
            k.x * k.y,
            k.x * k.z,
            k.y * k.y,
            k.y * k.z,
            k.z * k.z,
        ];
        for (a, b) in self.outer.iter_mut().zip(o) {
            *a += s * b;
        }
    }

    /// `M₂ p` for the outer-product sum M₂.
    pub fn outer_times(&self, p: DVec3) -> DVec3 {
        let [xx, xy, xz, yy, yz, zz] = self.outer;
        DVec3::new(
            xx * p.x + xy * p.y + xz * p.z,
            xy * p.x + yy * p.y + yz * p.z,
            xz * p.x + yz * p.y + zz * p.z,
        )
    }

    /// The trace of M₂: the sum of the points' squared lengths.
    pub fn outer_trace(&self) -> f64 {
        self.outer[0] + self.outer[3] + self.outer[5]
    }
}
