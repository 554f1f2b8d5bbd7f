//! Ray queries: whether a ray segment hits any primitive, for visibility
//! tests (is a face enclosed by the rest of the mesh?).

use glam::DVec3;

use super::Bvh;
use crate::aabb::Aabb;

impl Bvh {
    /// Whether the segment `origin + t·dir`, `t` in `[0, max_t]`, hits a
    /// primitive: `hit(prim)` is the caller's exact test, called only for
    /// primitives whose box the segment crosses, in tree order, until one
    /// returns true. `dir` need not be normalized; `max_t` is in its units.
    pub fn any_hit<F>(&self, origin: DVec3, dir: DVec3, max_t: f64, mut hit: F) -> bool
    where
        F: FnMut(u32) -> bool,
    {
        if self.nodes.is_empty() || max_t.is_nan() || max_t < 0.0 {
            return false;
        }
        let inv = dir.recip();
        // Nearer child first: inside a closed surface the first hit is
        // near, and finding it ends the query. A fixed stack: rays are
        // cast by the million, one allocation each would dominate.
        let mut stack = [0u32; 96];
        let mut top = 0usize;
        if entry(&self.nodes[0].bounds, origin, inv, max_t).is_none() {
            return false;
        }
        stack[top] = 0;
        top += 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if node.is_leaf() {
                for k in node.slots() {
                    if entry(&self.boxes[k], origin, inv, max_t).is_some() && hit(self.prims[k]) {
                        return true;
                    }
                }
                continue;
            }
            if top + 2 > stack.len() {
                // Deeper than any tree built from finite boxes; answer
                // by brute force over every primitive instead.
                return (0..self.prims.len()).any(|k| {
                    entry(&self.boxes[k], origin, inv, max_t).is_some() && hit(self.prims[k])
                });
            }
            let (l, r) = (node.start, node.start + 1);
            let tl = entry(&self.nodes[l as usize].bounds, origin, inv, max_t);
            let tr = entry(&self.nodes[r as usize].bounds, origin, inv, max_t);
            let mut push = |n: u32| {
                stack[top] = n;
                top += 1;
            };
            match (tl, tr) {
                (Some(a), Some(b)) if a <= b => {
                    push(r);
                    push(l);
                }
                (Some(_), Some(_)) => {
                    push(l);
                    push(r);
                }
                (Some(_), None) => push(l),
                (None, Some(_)) => push(r),
                (None, None) => {}
            }
        }
        false
    }
}

/// The slab test: where `origin + t·dir`, `t` in `[0, max_t]`, enters the
/// box (`None`: it does not meet it), with `inv` = 1 / `dir` per axis (an
/// infinite component for an axis the ray runs parallel to, which the
/// comparisons handle).
fn entry(b: &Aabb, origin: DVec3, inv: DVec3, max_t: f64) -> Option<f64> {
    if b.is_empty() {
        return None;
    }
    let (mut t0, mut t1) = (0.0f64, max_t);
    for a in 0..3 {
        let (lo, hi) = (
            (b.min[a] - origin[a]) * inv[a],
            (b.max[a] - origin[a]) * inv[a],
        );
        // A parallel ray inside the slab gives (−∞, +∞); outside, both
        // infinities on one side; 0·∞ (origin on the slab's face) is NaN,
        // which counts as inside.
        let (near, far) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        if !near.is_nan() {
            t0 = t0.max(near);
        }
        if !far.is_nan() {
            t1 = t1.min(far);
        }
        if t0 > t1 {
            return None;
        }
    }
    Some(t0)
}
