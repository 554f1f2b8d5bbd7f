//! Morph target deltas (blend shapes) fitted through every collapse, the
//! way Hoppe 1999 fits any attribute (`s(p) = g·p + d` per face, summed
//! area-weighted per vertex, evaluated at the final position), but stored
//! sparsely per vertex, as joint weights are (`skin.rs`).
//!
//! A face rig carries dozens of targets (ARKit's 52), each a three-component
//! delta per vertex, and each moves a small region: a mouth, a brow. Fitted
//! as ordinary streams, every target had its own wedges and a dense quadric
//! for every wedge of the mesh, and a 160k-triangle sphere with 52 small
//! targets took 14× the time and 28× the memory of the sphere without them.
//! Here a vertex holds one term per delta set that is nonzero on one of its
//! faces; the rest of the mesh pays for the shared area sum alone. Deltas
//! do not steer collapses (their shapes do, as poses: `terms/posed.rs`), so
//! only the functional sums are kept, not the quadric's squared terms.
//! Copies of one position share one sum: a morphed vertex cannot crack
//! along a UV seam.

use glam::DVec3;
use smallvec::SmallVec;

/// One delta set's functional sums at a vertex: per component `c`, the
/// area-weighted sums of the faces' gradients `G[c] = Σ a g` and offsets
/// `D[c] = Σ a d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MorphTerm {
    /// Which delta set (index into the caller's morph streams).
    pub set: u32,
    pub grad: [DVec3; 3],
    pub offset: [f64; 3],
}

/// The morph sums of one vertex.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MorphSums {
    /// Area of every face added (the denominator of every fitted value).
    pub alpha: f64,
    /// Terms of the delta sets nonzero on some face added, by set.
    pub terms: SmallVec<[MorphTerm; 1]>,
    /// An input corner at this vertex, whose deltas a vertex that never
    /// moved and never merged keeps bit for bit; `u32::MAX`: none yet.
    pub first_corner: u32,
    /// Whether a collapse merged another vertex into this one.
    pub merged: bool,
}

impl Default for MorphSums {
    fn default() -> Self {
        MorphSums {
            alpha: 0.0,
            terms: SmallVec::new(),
            first_corner: u32::MAX,
            merged: false,
        }
    }
}

impl MorphSums {
    /// Adds a face's functional of delta set `set` with area share `a`.
    pub fn add(&mut self, set: u32, a: f64, grad: [DVec3; 3], offset: [f64; 3]) {
        let term = match self.terms.iter_mut().find(|t| t.set == set) {
            Some(t) => t,
            None => {
                let at = self.terms.partition_point(|t| t.set < set);
                self.terms.insert(
                    at,
                    MorphTerm {
                        set,
                        grad: [DVec3::ZERO; 3],
                        offset: [0.0; 3],
                    },
                );
                &mut self.terms[at]
            }
        };
        for c in 0..3 {
            term.grad[c] += grad[c] * a;
            term.offset[c] += offset[c] * a;
        }
    }

    /// Absorbs `other` (the sums of a vertex merged into this one).
    pub fn merge(&mut self, other: &MorphSums) {
        self.alpha += other.alpha;
        for t in &other.terms {
            let (grad, offset) = (t.grad, t.offset);
            // Already area-weighted: add with share 1.
            self.add(t.set, 1.0, grad, offset);
        }
        self.merged = true;
    }

    /// The fitted deltas of set `set` at `p`: `(G·p + D) / α` per
    /// component; zero where no face of the set reached the vertex.
    pub fn value(&self, set: u32, p: DVec3) -> [f64; 3] {
        match self.terms.iter().find(|t| t.set == set) {
            Some(t) if self.alpha > 0.0 => {
                std::array::from_fn(|c| (t.grad[c].dot(p) + t.offset[c]) / self.alpha)
            }
            _ => [0.0; 3],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_delta_field_is_fitted_exactly_after_merging() {
        // Two faces carrying the field δ(p) = (x, 2y, 0) + (0, 0, 1): each
        // adds the same functional, with areas 1 and 3.
        let grad = [DVec3::X, DVec3::Y * 2.0, DVec3::ZERO];
        let offset = [0.0, 0.0, 1.0];
        let mut a = MorphSums::default();
        a.alpha += 1.0;
        a.add(4, 1.0, grad, offset);
        let mut b = MorphSums::default();
        b.alpha += 3.0;
        b.add(4, 3.0, grad, offset);
        a.merge(&b);
        assert!(a.merged);
        let p = DVec3::new(0.5, -2.0, 7.0);
        let v = a.value(4, p);
        assert!((v[0] - 0.5).abs() < 1e-15 && (v[1] + 4.0).abs() < 1e-15);
        assert!((v[2] - 1.0).abs() < 1e-15);
        // A set no face carried is zero.
        assert_eq!(a.value(0, p), [0.0; 3]);
    }

    #[test]
    fn faces_without_a_set_dilute_it_by_their_area() {
        // A vertex with two faces of equal area, the set nonzero on one
        // (constant 1 in x): fitted, it carries half.
        let mut s = MorphSums::default();
        s.alpha += 2.0;
        s.add(1, 1.0, [DVec3::ZERO; 3], [1.0, 0.0, 0.0]);
        assert_eq!(s.value(1, DVec3::ZERO), [0.5, 0.0, 0.0]);
    }

    #[test]
    fn terms_stay_sorted_by_set_and_merge_by_set() {
        let mut s = MorphSums::default();
        for set in [7, 2, 5] {
            s.add(set, 1.0, [DVec3::ZERO; 3], [set as f64; 3]);
        }
        let mut o = MorphSums::default();
        o.add(5, 1.0, [DVec3::ZERO; 3], [1.0; 3]);
        o.add(3, 1.0, [DVec3::ZERO; 3], [1.0; 3]);
        s.merge(&o);
        let sets: Vec<u32> = s.terms.iter().map(|t| t.set).collect();
        assert_eq!(sets, [2, 3, 5, 7]);
        assert_eq!(s.terms[2].offset, [6.0; 3]);
    }
}
