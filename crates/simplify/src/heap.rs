//! The collapse queue: a binary min-heap of edge costs whose stale entries
//! are recognized by generation counters, never by comparing floats.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

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
    /// Reversed so that `BinaryHeap` pops the cheapest first; a total order
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
    heap: BinaryHeap<Entry>,
}

impl CollapseQueue {
    /// A queue built from initial entries in O(n).
    pub fn from_entries(entries: Vec<Entry>) -> Self {
        CollapseQueue {
            heap: BinaryHeap::from(entries),
        }
    }

    /// Adds an entry.
    #[inline]
    pub fn push(&mut self, e: Entry) {
        self.heap.push(e);
    }

    /// The cheapest entry that is still current (its generation matches
    /// `gens`); stale entries are dropped on the way.
    pub fn pop_current(&mut self, gens: &[u32], alive: &[bool]) -> Option<Entry> {
        while let Some(e) = self.heap.pop() {
            if alive[e.edge as usize] && gens[e.edge as usize] == e.gen {
                return Some(e);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_cheapest_first_and_skips_stale_entries() {
        let mut gens = vec![0u32; 3];
        let alive = vec![true; 3];
        let mut q = CollapseQueue::from_entries(vec![
            Entry {
                cost: 2.0,
                edge: 0,
                gen: 0,
            },
            Entry {
                cost: 1.0,
                edge: 1,
                gen: 0,
            },
            Entry {
                cost: 1.0,
                edge: 2,
                gen: 0,
            },
        ]);
        // Edge 1 was re-evaluated: its old entry is stale.
        gens[1] = 1;
        q.push(Entry {
            cost: 3.0,
            edge: 1,
            gen: 1,
        });
        // Equal costs break by edge id.
        assert_eq!(q.pop_current(&gens, &alive).map(|e| e.edge), Some(2));
        assert_eq!(q.pop_current(&gens, &alive).map(|e| e.edge), Some(0));
        assert_eq!(
            q.pop_current(&gens, &alive).map(|e| (e.edge, e.cost)),
            Some((1, 3.0))
        );
        assert!(q.pop_current(&gens, &alive).is_none());
    }
}
