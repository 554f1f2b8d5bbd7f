//! The refused edges a collapse tries again one ring out, found from the
//! vertices around it.
//!
//! After a collapse, the loop tries again the refused edges of the kept
//! vertex's neighbours (those with retries one ring out left, see
//! `witness_waits`). It used to find them by reading every edge of each
//! neighbour with a refusal counted: the count made the usual case (none)
//! free, but a fan's center, with one refused edge counted among a hundred
//! thousand, had all of them read at every collapse along the rim. So each
//! vertex also lists the refused edges counted at it, and only those are
//! read. The lists are hints: an edge in one may have stopped being refused
//! or run out of retries, and is dropped when read; every edge counted at
//! a vertex is in its list.

use std::collections::HashMap;

use crate::prepare::complex::Complex;

/// Refused edges around each vertex: how many (so that the usual vertex,
/// with none, costs an index to check) and which.
#[derive(Clone, Debug, Default)]
pub(crate) struct RefusedAround {
    count: Vec<u32>,
    edges: HashMap<u32, Vec<u32>>,
}

impl RefusedAround {
    /// None around any of `vertices` vertices.
    pub fn new(vertices: usize) -> Self {
        RefusedAround {
            count: vec![0; vertices],
            edges: HashMap::new(),
        }
    }

    /// Whether no refusal is counted anywhere (and nothing is listed).
    pub fn is_clear(&self) -> bool {
        self.count.iter().all(|&n| n == 0)
    }

    /// Edge `e`, between `a` and `b`, was refused.
    pub fn add(&mut self, e: u32, [a, b]: [u32; 2]) {
        for v in [a, b] {
            self.count[v as usize] += 1;
            self.edges.entry(v).or_default().push(e);
        }
    }

    /// An edge between `ends` is no longer refused. The counts are hints
    /// for finding refused edges near a collapse; an edge whose ends moved
    /// under it may be counted at the old end, so they never go below zero.
    pub fn remove(&mut self, ends: [u32; 2]) {
        for v in ends {
            let n = &mut self.count[v as usize];
            *n = n.saturating_sub(1);
        }
    }

    /// `j` merged into `i`: `j`'s edges are `i`'s now, and so are their
    /// refusals.
    pub fn merge(&mut self, i: u32, j: u32) {
        let moved = std::mem::take(&mut self.count[j as usize]);
        self.count[i as usize] += moved;
        if let Some(list) = self.edges.remove(&j) {
            self.edges.entry(i).or_default().extend(list);
        }
    }

    /// Appends to `out` the edges of `v` that are refused and pass `retry`
    /// (each once), dropping the others from `v`'s list. An edge refused
    /// that fails `retry` (out of retries one ring out) can pass it again
    /// only by being refused anew, which lists it again.
    pub fn collect(
        &mut self,
        c: &Complex,
        v: u32,
        retry: impl Fn(u32) -> bool,
        out: &mut Vec<u32>,
    ) {
        if self.count[v as usize] == 0 {
            return;
        }
        let Some(list) = self.edges.get_mut(&v) else {
            return;
        };
        list.sort_unstable();
        list.dedup();
        list.retain(|&e| {
            let edge = &c.edges[e as usize];
            edge.alive() && edge.ends.contains(&v) && edge.refused() && retry(e)
        });
        out.extend_from_slice(list);
        if list.is_empty() {
            self.edges.remove(&v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn lists_follow_merges_and_drop_what_is_no_longer_refused() {
        // A strip of two triangles 0-1-2 and 1-3-2: edges 0-1, 1-2, 0-2,
        // 1-3, 2-3.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        let (mut c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 3, 2]);
        let edge = |c: &Complex, a: u32, b: u32| c.edge_between(a, b).unwrap_or(u32::MAX);
        let (e01, e13, e23) = (edge(&c, 0, 1), edge(&c, 1, 3), edge(&c, 2, 3));
        let mut r = RefusedAround::new(4);
        for e in [e01, e13, e23] {
            c.edges[e as usize].set_refused(true);
            r.add(e, c.edges[e as usize].ends);
        }
        let all = |_| true;
        let mut out = Vec::new();
        r.collect(&c, 1, all, &mut out);
        out.sort_unstable();
        let mut want = vec![e01, e13];
        want.sort_unstable();
        assert_eq!(out, want);
        // Vertex 0, without a refusal counted, reads nothing; `retry`
        // filters.
        out.clear();
        r.collect(&c, 3, |e| e != e23, &mut out);
        assert_eq!(out, vec![e13]);
        // and drops what it filtered out (it would be listed again when
        // refused anew).
        assert_eq!(r.edges[&3], vec![e13]);
        // 0-1 no longer refused: dropped from both lists.
        c.edges[e01 as usize].set_refused(false);
        r.remove(c.edges[e01 as usize].ends);
        out.clear();
        r.collect(&c, 1, all, &mut out);
        assert_eq!(out, vec![e13]);
        // 3 merged into 2 (as the loop records it): 3's refusals are 2's.
        r.merge(2, 3);
        assert_eq!(r.count[3], 0);
        assert_eq!(r.count[2], 3);
        assert!(!r.edges.contains_key(&3));
        assert!(!r.is_clear());
    }
}
