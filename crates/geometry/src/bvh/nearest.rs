//! Point queries: the nearest primitive under the caller's exact distance,
//! and the primitives whose boxes lie near a query box.

use glam::DVec3;

use super::Bvh;
use crate::aabb::Aabb;

impl Bvh {
    /// The primitive nearest to `p` whose squared distance is at most
    /// `max_dist2`, as `(primitive, squared distance)`.
    ///
    /// `dist2(prim)` is the caller's exact squared distance from `p` to the
    /// primitive; it must never be less than the squared distance from `p`
    /// to the primitive's box, which is what makes pruning safe. It is
    /// called only for primitives whose box is close enough to matter.
    /// NaN distances are ignored, and primitives with empty boxes are never
    /// reported.
    ///
    /// Depth-first branch and bound, nearer child first. Among primitives
    /// at the same distance the lowest index wins, so the answer does not
    /// depend on the tree's shape. Pass `f64::INFINITY` for no limit.
    pub fn nearest<F>(&self, p: DVec3, max_dist2: f64, mut dist2: F) -> Option<(u32, f64)>
    where
        F: FnMut(u32) -> f64,
    {
        self.nearest_by_slot(p, max_dist2, |k| dist2(self.prims[k]))
    }

    /// [`Bvh::nearest`] with the distance closure given the leaf slot of
    /// the primitive instead of its index, for callers that store their
    /// primitives in leaf order (see [`Bvh::slot_order`]) to read them
    /// sequentially.
    pub(crate) fn nearest_by_slot<F>(
        &self,
        p: DVec3,
        max_dist2: f64,
        mut dist2: F,
    ) -> Option<(u32, f64)>
    where
        F: FnMut(usize) -> f64,
    {
        let root = self.nodes.first()?;
        let mut bound = max_dist2;
        let mut best: Option<(u32, f64)> = None;
        let d = root.bounds.distance2_to_point(p);
        if d.is_nan() || d > bound || d == f64::INFINITY {
            return None;
        }
        let mut stack: Vec<(u32, f64)> = Vec::with_capacity(64);
        stack.push((0, d));
        while let Some((n, d)) = stack.pop() {
            // `bound` may have shrunk since this node was pushed. Equal
            // distances are still visited: they may hold a lower index.
            if d > bound {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.is_leaf() {
                for k in node.slots() {
                    // An infinite box distance means an empty box (or a
                    // point at infinity): never a candidate.
                    let bd = self.boxes[k].distance2_to_point(p);
                    if bd.is_nan() || bd > bound || bd == f64::INFINITY {
                        continue;
                    }
                    let prim = self.prims[k];
                    let dp = dist2(k);
                    let better = match best {
                        None => dp <= bound,
                        Some((bp, bd)) => dp < bd || (dp == bd && prim < bp),
                    };
                    if better {
                        best = Some((prim, dp));
                        bound = dp;
                    }
                }
                continue;
            }
            let (l, r) = (node.start, node.start + 1);
            let dl = self.nodes[l as usize].bounds.distance2_to_point(p);
            let dr = self.nodes[r as usize].bounds.distance2_to_point(p);
            // Push the farther child first so the nearer one is popped
            // first and tightens the bound early.
            let (near, far) = if dr < dl {
                ((r, dr), (l, dl))
            } else {
                ((l, dl), (r, dr))
            };
            if far.1 <= bound {
                stack.push(far);
            }
            if near.1 <= bound {
                stack.push(near);
            }
        }
        best
    }

    /// Calls `f(prim)` for every primitive whose box is within `margin` of
    /// `query` (box distance ≤ `margin`; 0 includes touching boxes), in
    /// tree order. A negative or NaN margin reports nothing.
    pub fn query_within<F>(&self, query: &Aabb, margin: f64, mut f: F)
    where
        F: FnMut(u32),
    {
        if margin.is_nan() || margin < 0.0 || self.nodes.is_empty() {
            return;
        }
        let m2 = margin * margin;
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if node.bounds.distance2(query) > m2 {
                continue;
            }
            if node.is_leaf() {
                for k in node.slots() {
                    if super::pairs::near(self.boxes[k].distance2(query), m2) {
                        f(self.prims[k]);
                    }
                }
            } else {
                stack.push(node.start + 1);
                stack.push(node.start);
            }
        }
    }
}
