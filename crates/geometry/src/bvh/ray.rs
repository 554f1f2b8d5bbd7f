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
///
/// Run for every node a ray passes near, so written to compile without
/// branches per axis: one early test for an empty box, one at the end
/// (bounds only narrow, so a ray that misses one slab misses at the end).
#[inline]
fn entry(b: &Aabb, origin: DVec3, inv: DVec3, max_t: f64) -> Option<f64> {
    if b.is_empty() {
        return None;
    }
    let lo = (b.min - origin) * inv;
    let hi = (b.max - origin) * inv;
    let (mut t0, mut t1) = (0.0f64, max_t);
    for (l, h) in [(lo.x, hi.x), (lo.y, hi.y), (lo.z, hi.z)] {
        // A parallel ray inside the slab gives (−∞, +∞); outside, both
        // infinities on one side. One in the plane of a face gives 0·∞ =
        // NaN there and an infinity at the other face, and may count as
        // missing the box: it can only graze what the box holds (an edge
        // or a vertex of a triangle), never cross it. NaN fails every
        // comparison, so it never narrows the range (plain comparisons,
        // not `f64::max`, whose NaN rule costs instructions).
        let (near, far) = if l <= h { (l, h) } else { (h, l) };
        if near > t0 {
            t0 = near;
        }
        if far < t1 {
            t1 = far;
        }
    }
    (t0 <= t1).then_some(t0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_test_enters_where_a_ray_meets_the_box() {
        let b = Aabb {
            min: DVec3::ZERO,
            max: DVec3::ONE,
        };
        let at = |o: DVec3, d: DVec3, max_t: f64| entry(&b, o, d.recip(), max_t);
        // Through the box along x from x = −1: enters at t = 1.
        assert_eq!(at(DVec3::new(-1.0, 0.5, 0.5), DVec3::X, 5.0), Some(1.0));
        // Too short to reach it.
        assert_eq!(at(DVec3::new(-1.0, 0.5, 0.5), DVec3::X, 0.5), None);
        // Parallel to the x slabs, outside them: never enters.
        assert_eq!(at(DVec3::new(-1.0, 0.5, 0.5), DVec3::Y, 5.0), None);
        // Parallel to the x and y slabs, between them: enters at z = 0.
        assert_eq!(at(DVec3::new(0.25, 0.5, -1.0), DVec3::Z, 5.0), Some(1.0));
        // Starting inside, whatever the direction.
        assert_eq!(at(DVec3::splat(0.5), -DVec3::ONE, 0.1), Some(0.0));
        // An empty box is never entered.
        let empty = Aabb::EMPTY;
        assert_eq!(entry(&empty, DVec3::ZERO, DVec3::ONE, 1.0), None);
    }
}
