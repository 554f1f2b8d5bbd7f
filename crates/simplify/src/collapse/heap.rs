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

/// Four keys on one 64-byte cache line: with the root alone on the first
/// line (three slots unused), the children of every node fill exactly one
/// line, so a sift step reads one line, not two.
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct Line([u128; ARITY]);

/// Slot of entry `i`: entries are stored three places on.
const SKEW: usize = ARITY - 1;

/// The queue of candidate collapses: a 4-ary min-heap of packed keys.
#[derive(Default)]
pub(crate) struct CollapseQueue {
    lines: Vec<Line>,
    len: usize,
}

impl CollapseQueue {
    #[inline]
    fn get(&self, i: usize) -> u128 {
        let s = i + SKEW;
        self.lines[s / ARITY].0[s % ARITY]
    }

    #[inline]
    fn set(&mut self, i: usize, k: u128) {
        let s = i + SKEW;
        self.lines[s / ARITY].0[s % ARITY] = k;
    }

    fn push_key(&mut self, k: u128) {
        let s = self.len + SKEW;
        if s / ARITY >= self.lines.len() {
            self.lines.push(Line::default());
        }
        self.len += 1;
        self.set(self.len - 1, k);
    }

    /// A queue built from initial entries in O(n).
    pub fn from_entries(entries: Vec<Entry>) -> Self {
        let mut q = CollapseQueue::default();
        q.lines.reserve((entries.len() + SKEW).div_ceil(ARITY));
        for e in entries {
            q.push_key(e.key());
        }
        if q.len > 1 {
            for i in (0..=(q.len - 2) / ARITY).rev() {
                q.sift_down(i);
            }
        }
        q
    }

    /// Adds an entry.
    #[inline]
    pub fn push(&mut self, e: Entry) {
        self.push_key(e.key());
        self.sift_up(self.len - 1);
    }

    /// The cheapest entry, without removing it.
    #[inline]
    pub fn peek(&self) -> Option<Entry> {
        (self.len > 0).then(|| Entry::from_key(self.get(0)))
    }

    /// Removes and returns the cheapest entry.
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            return None;
        }
        let last = self.get(self.len - 1);
        self.len -= 1;
        if self.len == 0 {
            return Some(Entry::from_key(last));
        }
        let top = self.get(0);
        self.set(0, last);
        self.sift_down(0);
        Some(Entry::from_key(top))
    }

    /// Replaces the cheapest entry (a stale one just re-evaluated): one
    /// sift-down instead of a pop and a push.
    #[inline]
    pub fn replace_top(&mut self, e: Entry) {
        if self.len == 0 {
            self.push_key(e.key());
        } else {
            self.set(0, e.key());
            self.sift_down(0);
        }
    }

    fn sift_up(&mut self, mut i: usize) {
        let k = self.get(i);
        while i > 0 {
            let p = (i - 1) / ARITY;
            let kp = self.get(p);
            if kp <= k {
                break;
            }
            self.set(i, kp);
            i = p;
        }
        self.set(i, k);
    }

    fn sift_down(&mut self, mut i: usize) {
        let n = self.len;
        let k = self.get(i);
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let (best, kb) = if first + ARITY <= n {
                // A full line: the children of i are line i + 1.
                let line = &self.lines[i + 1].0;
                let mut b = 0;
                for c in 1..ARITY {
                    if line[c] < line[b] {
                        b = c;
                    }
                }
                (first + b, line[b])
            } else {
                let mut b = first;
                for c in first + 1..n {
                    if self.get(c) < self.get(b) {
                        b = c;
                    }
                }
                (b, self.get(b))
            };
            if kb >= k {
                break;
            }
            self.set(i, kb);
            i = best;
        }
        self.set(i, k);
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
