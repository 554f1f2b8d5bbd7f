//! Test helpers shared by the symmetry tests: a seeded generator, options
//! without a cap, and the brute-force matched count of one plane.

use glam::DVec3;

use super::plane::{pair_error, Plane};
use super::SymmetryOptions;

/// A tiny xorshift64* generator for seeded property tests (no `rand`).
pub(super) struct Rng(pub(super) u64);

impl Rng {
    /// Next 64 random bits.
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    pub(super) fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub(super) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform in 0..n.
    pub(super) fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    /// A random unit vector.
    pub(super) fn direction(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// Options with a given `δ` and no cap.
pub(super) fn opts(delta: f64) -> SymmetryOptions {
    SymmetryOptions {
        delta,
        max_work: u64::MAX,
        ..SymmetryOptions::default()
    }
}

/// Reference matched count of one plane: O(|V|²) candidate pairs, then
/// a maximum matching by Kuhn's algorithm.
pub(super) fn brute_matched(positions: &[DVec3], plane: Plane, delta: f64) -> u64 {
    let sigma: Vec<f64> = positions
        .iter()
        .map(|&p| plane.signed_distance(p))
        .collect();
    let on_plane = positions
        .iter()
        .zip(&sigma)
        .filter(|(p, s)| p.is_finite() && s.abs() < delta)
        .count() as u64;
    let side = |sign: f64| -> Vec<usize> {
        (0..positions.len())
            .filter(|&i| positions[i].is_finite() && sign * sigma[i] >= delta)
            .collect()
    };
    let (pos, neg) = (side(1.0), side(-1.0));
    let adj: Vec<Vec<usize>> = pos
        .iter()
        .map(|&a| {
            (0..neg.len())
                .filter(|&j| {
                    let b = neg[j];
                    pair_error(
                        (a as u32, positions[a], sigma[a]),
                        (b as u32, positions[b], sigma[b]),
                        plane.n,
                    ) < delta
                })
                .collect()
        })
        .collect();
    on_plane + 2 * kuhn_matching(&adj, neg.len())
}

/// Maximum matching by Kuhn's algorithm: for each left vertex, look
/// for an augmenting path by recursive search (Berge: none left means
/// maximum). The textbook method, independent of
/// [`max_matching`](super::matching::max_matching).
pub(super) fn kuhn_matching(adj: &[Vec<usize>], right: usize) -> u64 {
    fn augment(u: usize, adj: &[Vec<usize>], seen: &mut [bool], owner: &mut [usize]) -> bool {
        for &v in &adj[u] {
            if !seen[v] {
                seen[v] = true;
                if owner[v] == usize::MAX || augment(owner[v], adj, seen, owner) {
                    owner[v] = u;
                    return true;
                }
            }
        }
        false
    }
    let mut owner = vec![usize::MAX; right];
    (0..adj.len())
        .filter(|&u| augment(u, adj, &mut vec![false; right], &mut owner))
        .count() as u64
}
