//! Top-down build with binned SAH splits (Wald 2007, "On fast Construction
//! of SAH-based Bounding Volume Hierarchies"): the top of the tree is split
//! on one thread, then the subtrees below it are built in parallel and
//! stitched in a fixed order, so the tree does not depend on the thread
//! count.

use rayon::prelude::*;

use super::{Bvh, Node};
use crate::aabb::Aabb;

/// Leaves hold at most this many primitives. Small leaves suit our
/// queries, whose per-primitive test (a closest point on a triangle, a
/// triangle–triangle distance) costs far more than a box test.
const MAX_LEAF: usize = 4;

/// SAH bins per split. 16 is within a percent or two of a full sweep in
/// Wald's measurements, at a fraction of the cost.
const BINS: usize = 16;

/// Ranges smaller than this are built as one sequential subtree. Large
/// enough that a task outweighs rayon's overhead, small enough that a
/// million primitives make dozens of tasks for the threads to share.
const PARALLEL_GRAIN: usize = 16 * 1024;

/// A primitive while building: its box travels with it through the
/// partitions, so every pass reads memory sequentially instead of gathering
/// by primitive index.
#[derive(Clone, Copy)]
struct Item {
    bounds: Aabb,
    prim: u32,
}

impl Item {
    /// Centroid, recomputed rather than stored: cheaper than the memory
    /// traffic of carrying it.
    #[inline]
    fn centroid(&self) -> glam::DVec3 {
        self.bounds.center()
    }
}

/// A range of items waiting to become node `node`.
#[derive(Clone, Copy)]
struct Task {
    node: u32,
    start: usize,
    end: usize,
    bounds: Aabb,
    centroids: Aabb,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    centroids: Aabb,
    count: usize,
}

const EMPTY_BIN: Bin = Bin {
    bounds: Aabb::EMPTY,
    centroids: Aabb::EMPTY,
    count: 0,
};

const PLACEHOLDER: Node = Node {
    bounds: Aabb::EMPTY,
    start: 0,
    count: 0,
};

impl Bvh {
    /// Builds the tree over `boxes` (one per primitive), using the rayon
    /// pool for large inputs. The tree is the same whatever the thread
    /// count.
    ///
    /// Splits are chosen by the surface area heuristic over 16
    /// centroid bins along the longest axis of the centroids' box. When all
    /// centroids coincide (many identical boxes) or are NaN (empty boxes),
    /// the range is halved by index instead, so depth stays logarithmic and
    /// the build cannot loop.
    pub fn build(boxes: &[Aabb]) -> Bvh {
        let n = boxes.len();
        if n == 0 {
            return Bvh::default();
        }
        let mut items: Vec<Item> = boxes
            .iter()
            .enumerate()
            .map(|(i, b)| Item {
                bounds: *b,
                prim: i as u32,
            })
            .collect();
        let root = Task {
            node: 0,
            start: 0,
            end: n,
            bounds: items.iter().fold(Aabb::EMPTY, |b, it| b.union(&it.bounds)),
            centroids: Aabb::from_points(items.iter().map(Item::centroid)),
        };
        let mut nodes = Vec::with_capacity(2 * n.div_ceil(MAX_LEAF));
        nodes.push(PLACEHOLDER);
        let mut deferred = Vec::new();
        grow(&mut nodes, &mut items, root, PARALLEL_GRAIN, &mut deferred);

        // Deferred ranges are disjoint; carve the items into one slice each.
        deferred.sort_by_key(|t| t.start);
        let mut slices = Vec::with_capacity(deferred.len());
        let mut rest: &mut [Item] = &mut items;
        let mut offset = 0;
        for t in &deferred {
            let (_, tail) = std::mem::take(&mut rest).split_at_mut(t.start - offset);
            let (mine, tail) = tail.split_at_mut(t.end - t.start);
            slices.push(mine);
            rest = tail;
            offset = t.end;
        }
        let subtrees: Vec<Vec<Node>> = deferred
            .par_iter()
            .zip(slices.into_par_iter())
            .map(|(t, slice)| {
                let local_root = Task {
                    node: 0,
                    start: 0,
                    end: t.end - t.start,
                    ..*t
                };
                let mut local = vec![PLACEHOLDER];
                grow(&mut local, slice, local_root, 0, &mut Vec::new());
                local
            })
            .collect();
        for (t, local) in deferred.iter().zip(subtrees) {
            // Local node 0 takes the deferred node's place; the others are
            // appended, so local index c ≥ 1 lands at base + c − 1.
            let base = nodes.len() as u32;
            let place = |mut nd: Node| {
                if nd.is_leaf() {
                    nd.start += t.start as u32;
                } else {
                    nd.start = base + nd.start - 1;
                }
                nd
            };
            nodes[t.node as usize] = place(local[0]);
            nodes.extend(local[1..].iter().map(|&nd| place(nd)));
        }
        Bvh {
            nodes,
            prims: items.iter().map(|it| it.prim).collect(),
            boxes: items.iter().map(|it| it.bounds).collect(),
        }
    }
}

/// Builds the subtree of `root` into `nodes` (where `root.node` already
/// exists), depth first. Ranges of fewer than `defer_below` items that still
/// need splitting are not built but pushed to `deferred`.
fn grow(
    nodes: &mut Vec<Node>,
    items: &mut [Item],
    root: Task,
    defer_below: usize,
    deferred: &mut Vec<Task>,
) {
    let mut stack = vec![root];
    while let Some(t) = stack.pop() {
        let count = t.end - t.start;
        if count <= MAX_LEAF {
            nodes[t.node as usize] = Node {
                bounds: t.bounds,
                start: t.start as u32,
                count: count as u32,
            };
            continue;
        }
        if count < defer_below {
            deferred.push(t);
            continue;
        }
        let (left, right) = split(items, &t);
        let first = nodes.len() as u32;
        nodes[t.node as usize] = Node {
            bounds: t.bounds,
            start: first,
            count: 0,
        };
        nodes.push(PLACEHOLDER);
        nodes.push(PLACEHOLDER);
        // Right pushed first: the left subtree is built first, which keeps
        // the memory layout depth-first.
        stack.push(Task {
            node: first + 1,
            ..right
        });
        stack.push(Task {
            node: first,
            ..left
        });
    }
}

/// Splits the task's range in two non-empty halves, reordering
/// `items[start..end]`; returns both halves (their `node` is unset).
fn split(items: &mut [Item], t: &Task) -> (Task, Task) {
    let slots = &mut items[t.start..t.end];
    let axis = t.centroids.longest_axis();
    let lo = t.centroids.min[axis];
    let extent = t.centroids.max[axis] - lo;
    if extent > 0.0 && extent.is_finite() {
        let scale = BINS as f64 / extent;
        // NaN centroids (empty boxes) cast to bin 0: `as` saturates.
        let bin_of = |c: f64| (((c - lo) * scale) as usize).min(BINS - 1);
        let fill = |chunk: &[Item]| {
            let mut bins = [EMPTY_BIN; BINS];
            for it in chunk {
                let c = it.centroid();
                let b = &mut bins[bin_of(c[axis])];
                b.bounds = b.bounds.union(&it.bounds);
                b.centroids.grow(c);
                b.count += 1;
            }
            bins
        };
        // Bins merge by min, max and sums of integers, all exact, so the
        // parallel reduction gives the same bins in any order.
        let bins = if slots.len() >= PARALLEL_GRAIN * 4 {
            slots.par_chunks(PARALLEL_GRAIN).map(fill).reduce(
                || [EMPTY_BIN; BINS],
                |a, b| std::array::from_fn(|i| merge(&a[i], &b[i])),
            )
        } else {
            fill(slots)
        };
        // Sweep from the right: cost of everything right of each plane.
        let mut right_cost = [0.0f64; BINS];
        let mut acc = EMPTY_BIN;
        for i in (1..BINS).rev() {
            acc = merge(&acc, &bins[i]);
            right_cost[i] = acc.bounds.half_area() * acc.count as f64;
        }
        let mut best: Option<(f64, usize)> = None;
        let mut acc = EMPTY_BIN;
        for (i, bin) in bins.iter().enumerate().take(BINS - 1) {
            acc = merge(&acc, bin);
            let right_count = t.end - t.start - acc.count;
            if acc.count == 0 || right_count == 0 {
                continue;
            }
            let cost = acc.bounds.half_area() * acc.count as f64 + right_cost[i + 1];
            // Strictly smaller: the leftmost plane wins ties.
            if best.map_or(true, |(c, _)| cost < c) {
                best = Some((cost, i));
            }
        }
        if let Some((_, plane)) = best {
            let mid = partition(slots, |it| bin_of(it.centroid()[axis]) <= plane);
            let (l, r) = bins.split_at(plane + 1);
            let fold = |bs: &[Bin]| bs.iter().fold(EMPTY_BIN, |a, b| merge(&a, b));
            let (lb, rb) = (fold(l), fold(r));
            return halves(
                t,
                t.start + mid,
                (lb.bounds, lb.centroids),
                (rb.bounds, rb.centroids),
            );
        }
    }
    // Coincident or unusable centroids: halve by position in the range.
    let mid = t.start + (t.end - t.start) / 2;
    let measure = |s: &[Item]| {
        let b = s.iter().fold(Aabb::EMPTY, |a, it| a.union(&it.bounds));
        let c = Aabb::from_points(s.iter().map(Item::centroid));
        (b, c)
    };
    let (l, r) = slots.split_at(mid - t.start);
    halves(t, mid, measure(l), measure(r))
}

fn halves(t: &Task, mid: usize, left: (Aabb, Aabb), right: (Aabb, Aabb)) -> (Task, Task) {
    (
        Task {
            node: 0,
            start: t.start,
            end: mid,
            bounds: left.0,
            centroids: left.1,
        },
        Task {
            node: 0,
            start: mid,
            end: t.end,
            bounds: right.0,
            centroids: right.1,
        },
    )
}

#[inline]
fn merge(a: &Bin, b: &Bin) -> Bin {
    Bin {
        bounds: a.bounds.union(&b.bounds),
        centroids: a.centroids.union(&b.centroids),
        count: a.count + b.count,
    }
}

/// Moves the items satisfying `left` to the front; returns how many.
fn partition(items: &mut [Item], left: impl Fn(&Item) -> bool) -> usize {
    let (mut i, mut j) = (0, items.len());
    while i < j {
        if left(&items[i]) {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    i
}
