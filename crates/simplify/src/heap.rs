//! The collapse queue: a min-heap of edge costs whose stale entries are
//! recognized by generation counters, never by comparing floats.
//!
//! Quaternary rather than binary: with 16-byte entries a node's four
//! children share a 64-byte cache line, and the tree is half as deep, so a
//! pop or re-key on a million-edge queue misses the cache about half as
//! often (the queue is a third of the collapse loop's time on large scans).

use std::cmp::Ordering;

use dary_heap::QuaternaryHeap;

/// One candidate collapse, as it was evaluated.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    /// Cost at evaluation time.
    pub cost: f64,
    /// The edge.
    pub edge: u32,
    /// The edge's generation at evaluation time.
    pub gen: u32,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    /// Reversed so that the max-heap pops the cheapest first; a total order
    /// (`total_cmp`, then edge id, then generation) makes runs deterministic.
    fn cmp(&self, o: &Self) -> Ordering {
        o.cost
            .total_cmp(&self.cost)
            .then_with(|| o.edge.cmp(&self.edge))
            .then_with(|| o.gen.cmp(&self.gen))
    }
}

/// The queue of candidate collapses.
#[derive(Default)]
pub(crate) struct CollapseQueue {
    heap: QuaternaryHeap<Entry>,
}

impl CollapseQueue {
    /// A queue built from initial entries in O(n).
    pub fn from_entries(entries: Vec<Entry>) -> Self {
        CollapseQueue {
            heap: QuaternaryHeap::from(entries),
        }
    }

    /// Adds an entry.
    #[inline]
    pub fn push(&mut self, e: Entry) {
        self.heap.push(e);
    }

    /// The cheapest entry, current or stale: the caller compares its
    /// generation with the edge's.
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        self.heap.pop()
    }

    /// The cheapest entry, without removing it.
    #[inline]
    pub fn peek(&self) -> Option<Entry> {
        self.heap.peek().copied()
    }

    /// Replaces the cheapest entry (a stale one just re-evaluated): one
    /// sift-down instead of a pop and a push.
    #[inline]
    pub fn replace_top(&mut self, e: Entry) {
        if self.heap.is_empty() {
            self.heap.push(e);
        } else if let Some(mut top) = self.heap.peek_mut() {
            *top = e;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_cheapest_first_with_ties_broken_by_edge_then_generation() {
        let e = |cost, edge, gen| Entry { cost, edge, gen };
        let mut q = CollapseQueue::from_entries(vec![e(2.0, 0, 0), e(1.0, 2, 0), e(1.0, 1, 5)]);
        q.push(e(1.0, 1, 4));
        // Re-keying the top moves it to its place.
        q.replace_top(e(1.5, 1, 6));
        q.push(e(1.0, 1, 4));
        let order: Vec<(u32, u32)> = std::iter::from_fn(|| q.pop())
            .map(|e| (e.edge, e.gen))
            .collect();
        assert_eq!(order, vec![(1, 4), (1, 5), (2, 0), (1, 6), (0, 0)]);
    }
}
