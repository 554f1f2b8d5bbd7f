//! The collapse queue: a min-heap of edge costs whose stale entries are
//! recognized by generation counters, never by comparing floats.
//!
//! Entries are single `u128` keys — cost bits, edge, generation — so the
//! total order the loop needs (cost, then edge id, then generation) is one
//! integer comparison. Costs are finite and non-negative, whose IEEE bit
//! patterns order like the numbers. The heap is quaternary: a node's four
//! children share a 64-byte cache line and the tree is half as deep as a
//! binary one, which matters on million-edge queues where every level is a
//! cache miss.

/// One candidate collapse, as it was evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Entry {
    /// Cost at evaluation time (finite; negative values count as 0).
    pub cost: f64,
    /// The edge.
    pub edge: u32,
    /// The edge's generation at evaluation time.
    pub gen: u32,
}

impl Entry {
    #[inline]
    fn key(self) -> u128 {
        // `cost > 0.0` also maps -0.0, negatives and NaN to 0.
        let c = if self.cost > 0.0 {
            self.cost.to_bits()
        } else {
            0
        };
        ((c as u128) << 64) | ((self.edge as u128) << 32) | self.gen as u128
    }

    #[inline]
    fn from_key(k: u128) -> Entry {
        Entry {
            cost: f64::from_bits((k >> 64) as u64),
            edge: (k >> 32) as u32,
            gen: k as u32,
        }
    }
}

const ARITY: usize = 4;

/// The queue of candidate collapses: a 4-ary min-heap of packed keys.
#[derive(Default)]
pub(crate) struct CollapseQueue {
    heap: Vec<u128>,
}

impl CollapseQueue {
    /// A queue built from initial entries in O(n).
    pub fn from_entries(entries: Vec<Entry>) -> Self {
        let mut q = CollapseQueue {
            heap: entries.into_iter().map(Entry::key).collect(),
        };
        if q.heap.len() > 1 {
            for i in (0..=(q.heap.len() - 2) / ARITY).rev() {
                q.sift_down(i);
            }
        }
        q
    }

    /// Adds an entry.
    #[inline]
    pub fn push(&mut self, e: Entry) {
        self.heap.push(e.key());
        self.sift_up(self.heap.len() - 1);
    }

    /// The cheapest entry, without removing it.
    #[inline]
    pub fn peek(&self) -> Option<Entry> {
        self.heap.first().map(|&k| Entry::from_key(k))
    }

    /// Removes and returns the cheapest entry.
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        let last = self.heap.pop()?;
        if self.heap.is_empty() {
            return Some(Entry::from_key(last));
        }
        let top = std::mem::replace(&mut self.heap[0], last);
        self.sift_down(0);
        Some(Entry::from_key(top))
    }

    /// Replaces the cheapest entry (a stale one just re-evaluated): one
    /// sift-down instead of a pop and a push.
    #[inline]
    pub fn replace_top(&mut self, e: Entry) {
        match self.heap.first_mut() {
            Some(top) => {
                *top = e.key();
                self.sift_down(0);
            }
            None => self.heap.push(e.key()),
        }
    }

    fn sift_up(&mut self, mut i: usize) {
        let k = self.heap[i];
        while i > 0 {
            let p = (i - 1) / ARITY;
            if self.heap[p] <= k {
                break;
            }
            self.heap[i] = self.heap[p];
            i = p;
        }
        self.heap[i] = k;
    }

    fn sift_down(&mut self, mut i: usize) {
        let n = self.heap.len();
        let k = self.heap[i];
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let last = (first + ARITY).min(n);
            let mut best = first;
            for c in first + 1..last {
                if self.heap[c] < self.heap[best] {
                    best = c;
                }
            }
            if self.heap[best] >= k {
                break;
            }
            self.heap[i] = self.heap[best];
            i = best;
        }
        self.heap[i] = k;
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

    #[test]
    fn matches_a_sorted_order_on_many_random_entries() {
        // Deterministic pseudo-random costs over several magnitudes.
        let mut x: u64 = 0x2545_F491_4F6C_DD1D;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let entries: Vec<Entry> = (0..5000)
            .map(|i| Entry {
                cost: (rnd() % 1000) as f64 * 10f64.powi((rnd() % 7) as i32 - 3),
                edge: i,
                gen: (rnd() % 3) as u32,
            })
            .collect();
        let mut q = CollapseQueue::from_entries(entries[..2500].to_vec());
        for &e in &entries[2500..] {
            q.push(e);
        }
        let popped: Vec<(u64, u32)> = std::iter::from_fn(|| q.pop())
            .map(|e| (e.cost.to_bits(), e.edge))
            .collect();
        let mut expected: Vec<(u64, u32)> =
            entries.iter().map(|e| (e.cost.to_bits(), e.edge)).collect();
        expected.sort_unstable();
        assert_eq!(popped, expected);
    }

    #[test]
    fn negative_and_signed_zero_costs_count_as_zero() {
        let mut q = CollapseQueue::default();
        q.push(Entry {
            cost: 0.5,
            edge: 0,
            gen: 0,
        });
        q.push(Entry {
            cost: -0.0,
            edge: 2,
            gen: 0,
        });
        q.push(Entry {
            cost: -3.0,
            edge: 1,
            gen: 0,
        });
        let order: Vec<u32> = std::iter::from_fn(|| q.pop()).map(|e| e.edge).collect();
        assert_eq!(order, vec![1, 2, 0]);
    }
}
