//! A bounding volume hierarchy over axis-aligned boxes: flat node array,
//! binned-SAH build, nearest-primitive, pairs-within-a-margin and
//! any-hit ray queries.
//!
//! The tree knows only boxes; what a primitive is (a triangle, a point, a
//! whole component) and its exact distance belong to the caller, who passes
//! them as closures. The simplifier uses it for the virtual-edge search of
//! W §4.1.1, the evaluator for point-to-surface distances.

mod build;
mod nearest;
mod pairs;
mod ray;
#[cfg(test)]
mod tests;

use crate::aabb::Aabb;

/// A node: a leaf holds `count > 0` primitives starting at `start` in the
/// leaf-order arrays; an inner node (`count == 0`) has its children at
/// `start` and `start + 1`, so one index serves both.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    bounds: Aabb,
    start: u32,
    count: u32,
}

impl Node {
    #[inline]
    fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// Range of leaf-order slots of a leaf.
    #[inline]
    fn slots(&self) -> std::ops::Range<usize> {
        self.start as usize..(self.start + self.count) as usize
    }
}

/// A bounding volume hierarchy over primitive boxes.
///
/// Built once from one [`Aabb`] per primitive (primitive `i` is `boxes[i]`);
/// queries report primitive indices. The same boxes always give the same
/// tree, and every query visits nodes in an order fixed by the tree, so
/// callbacks are called in a deterministic order.
///
/// Empty boxes (see [`Aabb::empty`]) are allowed: such primitives are never
/// reported, whatever the margin.
///
/// ```
/// use glam::DVec3;
/// use wildlod_geometry::{Aabb, Bvh};
///
/// let points = [DVec3::ZERO, DVec3::X, DVec3::new(5.0, 0.0, 0.0)];
/// let bvh = Bvh::build(&points.map(Aabb::from_point));
/// // Nearest point to (4, 0, 0) under the caller's exact distance.
/// let q = DVec3::new(4.0, 0.0, 0.0);
/// let near = bvh.nearest(q, f64::INFINITY, |i| points[i as usize].distance_squared(q));
/// assert_eq!(near, Some((2, 1.0)));
/// // Pairs of points at most 1.5 apart.
/// let mut pairs = Vec::new();
/// bvh.self_pairs_within(1.5, |i, j| pairs.push((i, j)));
/// assert_eq!(pairs, [(0, 1)]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Primitive index of every leaf slot.
    prims: Vec<u32>,
    /// Box of every leaf slot (`boxes[k]` bounds primitive `prims[k]`),
    /// stored in leaf order so that leaf scans read memory sequentially.
    boxes: Vec<Aabb>,
}

impl Bvh {
    /// Number of primitives.
    #[inline]
    pub fn len(&self) -> usize {
        self.prims.len()
    }

    /// True when the tree has no primitive.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// Bounds of all primitives ([`Aabb::EMPTY`] when there is none).
    #[inline]
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    /// Number of nodes (inner and leaves).
    #[inline]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The primitive index of every leaf slot, in leaf order: the order in
    /// which leaves store their primitives. Storing per-primitive data in
    /// this order makes leaf scans read memory sequentially.
    #[inline]
    pub fn slot_order(&self) -> &[u32] {
        &self.prims
    }

    /// Length of the longest root-to-leaf path, counting nodes (0 when
    /// empty); for tests and diagnostics.
    pub fn depth(&self) -> usize {
        if self.nodes.is_empty() {
            return 0;
        }
        let mut deepest = 0;
        let mut stack = vec![(0u32, 1usize)];
        while let Some((n, d)) = stack.pop() {
            deepest = deepest.max(d);
            let node = &self.nodes[n as usize];
            if !node.is_leaf() {
                stack.push((node.start, d + 1));
                stack.push((node.start + 1, d + 1));
            }
        }
        deepest
    }
}
