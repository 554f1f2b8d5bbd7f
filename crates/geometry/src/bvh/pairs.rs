//! Pair queries by simultaneous traversal of two trees (or of one tree with
//! itself): every primitive pair whose boxes lie within a margin.

use std::ops::ControlFlow;

use rayon::prelude::*;

use super::Bvh;

/// How many independent node pairs the parallel queries cut the traversal
/// into. Fixed, not derived from the thread count, so that the output order
/// is the same on every machine; a few hundred tasks keep a handful of
/// threads busy despite uneven subtrees.
const PARALLEL_TASKS: usize = 512;

/// A pair of nodes still to visit: from two trees, or from one tree with
/// itself (`same`), in which case `a == b` means "pairs inside node a".
#[derive(Clone, Copy, Debug)]
struct Visit {
    a: u32,
    b: u32,
}

/// The two trees of a traversal (the same tree twice for self pairs).
struct Walk<'t> {
    left: &'t Bvh,
    right: &'t Bvh,
    same: bool,
    m2: f64,
}

impl Walk<'_> {
    /// Node pairs to visit instead of `v`, pruned by box distance, or `None`
    /// when `v` is a pair of leaves.
    fn children(&self, v: Visit, out: &mut Vec<Visit>) -> bool {
        let na = &self.left.nodes[v.a as usize];
        let nb = &self.right.nodes[v.b as usize];
        if self.same && v.a == v.b {
            if na.is_leaf() {
                return false;
            }
            let (l, r) = (na.start, na.start + 1);
            // Pairs within each child, then across the children.
            out.push(Visit { a: l, b: l });
            out.push(Visit { a: r, b: r });
            self.push_if_near(Visit { a: l, b: r }, out);
            return true;
        }
        let descend_a = match (na.is_leaf(), nb.is_leaf()) {
            (true, true) => return false,
            (false, true) => true,
            (true, false) => false,
            // Split the bigger box: it is the one whose children are most
            // likely to separate from the other.
            (false, false) => na.bounds.half_area() >= nb.bounds.half_area(),
        };
        if descend_a {
            self.push_if_near(
                Visit {
                    a: na.start,
                    b: v.b,
                },
                out,
            );
            self.push_if_near(
                Visit {
                    a: na.start + 1,
                    b: v.b,
                },
                out,
            );
        } else {
            self.push_if_near(
                Visit {
                    a: v.a,
                    b: nb.start,
                },
                out,
            );
            self.push_if_near(
                Visit {
                    a: v.a,
                    b: nb.start + 1,
                },
                out,
            );
        }
        true
    }

    #[inline]
    fn push_if_near(&self, v: Visit, out: &mut Vec<Visit>) {
        let ba = &self.left.nodes[v.a as usize].bounds;
        let bb = &self.right.nodes[v.b as usize].bounds;
        if ba.distance2(bb) <= self.m2 {
            out.push(v);
        }
    }

    /// Reports the primitive pairs of a pair of leaves, until `f` breaks.
    fn leaves(&self, v: Visit, f: &mut impl FnMut(u32, u32) -> ControlFlow<()>) -> ControlFlow<()> {
        let na = &self.left.nodes[v.a as usize];
        let nb = &self.right.nodes[v.b as usize];
        if self.same && v.a == v.b {
            let slots = na.slots();
            for i in slots.clone() {
                for j in i + 1..slots.end {
                    if near(self.left.boxes[i].distance2(&self.left.boxes[j]), self.m2) {
                        let (p, q) = (self.left.prims[i], self.left.prims[j]);
                        f(p.min(q), p.max(q))?;
                    }
                }
            }
            return ControlFlow::Continue(());
        }
        for i in na.slots() {
            let bi = &self.left.boxes[i];
            for j in nb.slots() {
                if near(bi.distance2(&self.right.boxes[j]), self.m2) {
                    let (p, q) = (self.left.prims[i], self.right.prims[j]);
                    if self.same {
                        f(p.min(q), p.max(q))?;
                    } else {
                        f(p, q)?;
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// Depth-first traversal from `start`, until `f` breaks.
    fn run(
        &self,
        start: Visit,
        f: &mut impl FnMut(u32, u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let mut stack = vec![start];
        let mut next = Vec::with_capacity(3);
        while let Some(v) = stack.pop() {
            next.clear();
            if self.children(v, &mut next) {
                // Reversed so that the first child is visited first.
                stack.extend(next.iter().rev());
            } else {
                self.leaves(v, f)?;
            }
        }
        ControlFlow::Continue(())
    }

    /// The root visit, if the roots are near enough to matter at all.
    fn root(&self) -> Option<Visit> {
        if self.left.nodes.is_empty() || self.right.nodes.is_empty() || self.m2.is_nan() {
            return None;
        }
        let v = Visit { a: 0, b: 0 };
        let mut out = Vec::with_capacity(1);
        if self.same {
            out.push(v);
        } else {
            self.push_if_near(v, &mut out);
        }
        out.pop()
    }

    /// Cuts the traversal into about [`PARALLEL_TASKS`] independent node
    /// pairs, breadth first, in an order that depends only on the trees.
    fn tasks(&self) -> Vec<Visit> {
        let mut tasks: Vec<Visit> = self.root().into_iter().collect();
        let mut next = Vec::new();
        let mut scratch = Vec::with_capacity(3);
        while !tasks.is_empty() && tasks.len() < PARALLEL_TASKS {
            next.clear();
            let mut grew = false;
            for &v in &tasks {
                scratch.clear();
                if self.children(v, &mut scratch) {
                    grew = true;
                    next.extend_from_slice(&scratch);
                } else {
                    next.push(v);
                }
            }
            std::mem::swap(&mut tasks, &mut next);
            if !grew {
                break;
            }
        }
        tasks
    }

    fn par_collect<T, F>(&self, f: F) -> Vec<T>
    where
        T: Send,
        F: Fn(u32, u32) -> Option<T> + Sync,
    {
        let chunks: Vec<Vec<T>> = self
            .tasks()
            .into_par_iter()
            .map(|v| {
                let mut out = Vec::new();
                let _ = self.run(v, &mut |i, j| {
                    out.extend(f(i, j));
                    ControlFlow::Continue(())
                });
                out
            })
            .collect();
        chunks.into_iter().flatten().collect()
    }
}

/// Whether two primitive boxes at squared distance `d2` are within the
/// squared margin; an infinite distance means an empty box, never near.
#[inline]
pub(super) fn near(d2: f64, m2: f64) -> bool {
    d2 <= m2 && d2 < f64::INFINITY
}

/// Squared margin, or NaN for a margin that admits nothing.
fn margin2(margin: f64) -> f64 {
    if margin >= 0.0 {
        margin * margin
    } else {
        f64::NAN
    }
}

impl Bvh {
    /// Calls `f(i, j)` for every primitive `i` of `self` and `j` of `other`
    /// whose boxes are within `margin` of each other (box distance ≤
    /// `margin`; 0 includes touching boxes). Dual-tree traversal, in a
    /// deterministic order. A negative or NaN margin reports nothing.
    pub fn pairs_within<F>(&self, other: &Bvh, margin: f64, mut f: F)
    where
        F: FnMut(u32, u32),
    {
        let _ = self.pairs_within_until(other, margin, |i, j| {
            f(i, j);
            ControlFlow::Continue(())
        });
    }

    /// [`Bvh::pairs_within`] that stops as soon as `f` breaks, for callers
    /// with a work budget; returns whether it stopped early.
    pub fn pairs_within_until<F>(&self, other: &Bvh, margin: f64, mut f: F) -> ControlFlow<()>
    where
        F: FnMut(u32, u32) -> ControlFlow<()>,
    {
        let w = Walk {
            left: self,
            right: other,
            same: false,
            m2: margin2(margin),
        };
        match w.root() {
            Some(root) => w.run(root, &mut f),
            None => ControlFlow::Continue(()),
        }
    }

    /// Calls `f(i, j)` with `i < j` once for every unordered pair of
    /// distinct primitives whose boxes are within `margin` of each other.
    /// A negative or NaN margin reports nothing.
    pub fn self_pairs_within<F>(&self, margin: f64, mut f: F)
    where
        F: FnMut(u32, u32),
    {
        let _ = self.self_pairs_within_until(margin, |i, j| {
            f(i, j);
            ControlFlow::Continue(())
        });
    }

    /// [`Bvh::self_pairs_within`] that stops as soon as `f` breaks, for
    /// callers with a work budget; returns whether it stopped early.
    pub fn self_pairs_within_until<F>(&self, margin: f64, mut f: F) -> ControlFlow<()>
    where
        F: FnMut(u32, u32) -> ControlFlow<()>,
    {
        let w = Walk {
            left: self,
            right: self,
            same: true,
            m2: margin2(margin),
        };
        match w.root() {
            Some(root) => w.run(root, &mut f),
            None => ControlFlow::Continue(()),
        }
    }

    /// [`Bvh::pairs_within`] on the rayon pool: `f` runs on every pair and
    /// its `Some` results are returned, in an order that depends only on the
    /// trees (not on the thread count).
    pub fn par_pairs_within<T, F>(&self, other: &Bvh, margin: f64, f: F) -> Vec<T>
    where
        T: Send,
        F: Fn(u32, u32) -> Option<T> + Sync,
    {
        Walk {
            left: self,
            right: other,
            same: false,
            m2: margin2(margin),
        }
        .par_collect(f)
    }

    /// [`Bvh::self_pairs_within`] on the rayon pool: `f(i, j)` (with
    /// `i < j`) runs on every pair and its `Some` results are returned, in
    /// an order that depends only on the tree (not on the thread count).
    pub fn par_self_pairs_within<T, F>(&self, margin: f64, f: F) -> Vec<T>
    where
        T: Send,
        F: Fn(u32, u32) -> Option<T> + Sync,
    {
        Walk {
            left: self,
            right: self,
            same: true,
            m2: margin2(margin),
        }
        .par_collect(f)
    }
}
