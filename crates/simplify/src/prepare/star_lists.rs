//! Star lists (the faces or the edges around each vertex) kept in one
//! shared pool: 8 bytes of span per vertex and 4 per entry, where a small
//! vector per vertex took 40 bytes inline and a heap block for every star
//! that outgrew it (issue 15: the chunks' star lists were the largest part
//! of a large run's peak).
//!
//! A star that grows past its span moves to the end of the pool with room
//! to spare; the space it leaves is garbage, reclaimed by sliding every
//! span down when the pool is full and enough of it is garbage. Stars keep
//! the order of their entries exactly as a vector would (pushes append,
//! removals swap the last entry in, `retain` keeps the order), so every
//! walk over a star sees what it saw before.
//!
//! A star of more than `MAX_POOLED` entries (a fan's centre, a vertex
//! shared by a whole soup) lives in a vector of its own, with an index from
//! each entry to its position; its span then only points there. Without
//! the index every face or edge leaving such a star cost a scan of it, and
//! a fan of n triangles took O(n²) (a 200,000-triangle fan: 20 s).

use std::collections::HashMap;

/// Where a star lives in the pool, or (`cap == LARGE`) which large star
/// it is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Span {
    start: u32,
    len: u16,
    cap: u16,
}

/// The `cap` of a span whose star lives in `StarLists::large`.
const LARGE: u16 = u16::MAX;

/// The most entries a star keeps in the pool (a span counts up to
/// `LARGE - 1`). Below it a removal's scan costs less than a hash lookup
/// would save; no vertex of a regular mesh comes near it.
const MAX_POOLED: usize = 1024;

/// A star too large for the pool, with where each entry sits.
#[derive(Clone, Debug, Default)]
struct LargeStar {
    entries: Vec<u32>,
    /// Entry → its position in `entries`. `None` while an entry repeats
    /// (a face holding the vertex at two corners, for a moment): then a
    /// removal scans for the first occurrence, as a vector's would.
    at: Option<HashMap<u32, u32>>,
}

impl LargeStar {
    fn new(entries: Vec<u32>) -> LargeStar {
        let mut star = LargeStar { entries, at: None };
        star.reindex();
        star
    }

    /// Rebuilds the index, or drops it if an entry repeats.
    fn reindex(&mut self) {
        let mut at = HashMap::with_capacity(self.entries.capacity());
        for (p, &x) in self.entries.iter().enumerate() {
            if at.insert(x, p as u32).is_some() {
                self.at = None;
                return;
            }
        }
        self.at = Some(at);
    }

    fn push(&mut self, x: u32) {
        if let Some(at) = &mut self.at {
            if at.insert(x, self.entries.len() as u32).is_some() {
                self.at = None;
            }
        }
        self.entries.push(x);
    }

    /// Removes the first occurrence of `x`, the last entry taking its
    /// place.
    fn remove(&mut self, x: u32) {
        match &mut self.at {
            Some(at) => {
                let Some(p) = at.remove(&x) else {
                    return;
                };
                let p = p as usize;
                self.entries.swap_remove(p);
                if let Some(&moved) = self.entries.get(p) {
                    at.insert(moved, p as u32);
                }
            }
            None => {
                if let Some(p) = self.entries.iter().position(|&y| y == x) {
                    self.entries.swap_remove(p);
                    // The repeat may have been the one removed.
                    self.reindex();
                }
            }
        }
    }

    fn retain(&mut self, keep: impl FnMut(&u32) -> bool) {
        self.entries.retain(keep);
        self.reindex();
    }
}

/// One star per vertex, in a shared pool.
#[derive(Clone, Debug, Default)]
pub(crate) struct StarLists {
    span: Vec<Span>,
    pool: Vec<u32>,
    /// Pool entries no span owns.
    garbage: usize,
    /// The stars too large for the pool.
    large: Vec<LargeStar>,
}

impl StarLists {
    /// Empty stars, one per count, each with room for exactly its count.
    pub fn with_capacities(counts: impl ExactSizeIterator<Item = u32>) -> StarLists {
        let mut span = Vec::with_capacity(counts.len());
        let mut large = Vec::new();
        let mut next = 0usize;
        for cap in counts {
            let cap = cap as usize;
            if cap > MAX_POOLED {
                span.push(Span {
                    start: large.len() as u32,
                    len: 0,
                    cap: LARGE,
                });
                large.push(LargeStar::new(Vec::with_capacity(cap)));
            } else {
                span.push(Span {
                    start: next as u32,
                    len: 0,
                    cap: cap as u16,
                });
                next += cap;
            }
        }
        assert!(next <= u32::MAX as usize, "star lists beyond 2³² entries");
        StarLists {
            span,
            pool: vec![0; next],
            garbage: 0,
            large,
        }
    }

    /// Number of stars (vertices).
    #[inline]
    pub fn len(&self) -> usize {
        self.span.len()
    }

    /// The star of `v`.
    #[inline]
    pub fn get(&self, v: usize) -> &[u32] {
        let s = self.span[v];
        if s.cap == LARGE {
            return &self.large[s.start as usize].entries;
        }
        &self.pool[s.start as usize..s.start as usize + s.len as usize]
    }

    /// The star of `v`, mutable, if it is in the pool (else `None`, and
    /// `large` has it).
    #[inline]
    fn pooled_mut(&mut self, v: usize) -> Option<(&mut [u32], &mut u16)> {
        let s = &mut self.span[v];
        if s.cap == LARGE {
            return None;
        }
        let (start, len) = (s.start as usize, s.len as usize);
        Some((&mut self.pool[start..start + len], &mut s.len))
    }

    /// The star of `v` if it lives outside the pool.
    #[inline]
    fn large_mut(&mut self, v: usize) -> Option<&mut LargeStar> {
        let s = self.span[v];
        (s.cap == LARGE).then(|| &mut self.large[s.start as usize])
    }

    /// Every star, in vertex order.
    #[cfg(test)]
    pub fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        (0..self.span.len()).map(|v| self.get(v))
    }

    /// Appends `x` to the star of `v`.
    #[inline]
    pub fn push(&mut self, v: usize, x: u32) {
        if self.span[v].len == self.span[v].cap && self.span[v].cap != LARGE {
            self.grow(v);
        }
        if let Some(star) = self.large_mut(v) {
            star.push(x);
            return;
        }
        let s = &mut self.span[v];
        self.pool[s.start as usize + s.len as usize] = x;
        s.len += 1;
    }

    /// Removes one occurrence of `x` from the star of `v`, the last entry
    /// taking its place (a vector's `swap_remove`).
    #[inline]
    pub fn remove(&mut self, v: usize, x: u32) {
        match self.pooled_mut(v) {
            Some((star, len)) => {
                if let Some(p) = star.iter().position(|&y| y == x) {
                    star[p] = star[star.len() - 1];
                    *len -= 1;
                }
            }
            None => self.large[self.span[v].start as usize].remove(x),
        }
    }

    /// Keeps the entries of `v`'s star for which `keep` holds, in order.
    pub fn retain(&mut self, v: usize, mut keep: impl FnMut(u32) -> bool) {
        match self.pooled_mut(v) {
            Some((star, len)) => {
                let mut w = 0;
                for r in 0..star.len() {
                    if keep(star[r]) {
                        star[w] = star[r];
                        w += 1;
                    }
                }
                *len = w as u16;
            }
            None => self.large[self.span[v].start as usize].retain(|&x| keep(x)),
        }
    }

    /// Moves the star of `v` into `out` (cleared first), leaving it empty
    /// and without room: a vertex merged away.
    pub fn take(&mut self, v: usize, out: &mut Vec<u32>) {
        out.clear();
        out.extend_from_slice(self.get(v));
        let s = self.span[v];
        if s.cap == LARGE {
            self.large[s.start as usize] = LargeStar::default();
        } else {
            self.garbage += s.cap as usize;
        }
        self.span[v] = Span::default();
    }

    /// Moves the star of `v` to the end of the pool with room to grow, or
    /// out of the pool when it outgrows a span.
    #[cold]
    fn grow(&mut self, v: usize) {
        let old = self.span[v];
        let len = old.len as usize;
        // Half as much again, and at least four: a vertex that gains a
        // star in a collapse gains a few faces, rarely many.
        let cap = (len + 4).max(len + len / 2);
        if cap > MAX_POOLED {
            let mut star = Vec::with_capacity(cap);
            star.extend_from_slice(self.get(v));
            self.garbage += old.cap as usize;
            self.span[v] = Span {
                start: self.large.len() as u32,
                len: 0,
                cap: LARGE,
            };
            self.large.push(LargeStar::new(star));
            return;
        }
        if self.pool.len() + cap > self.pool.capacity() {
            self.make_room(cap);
        }
        let old = self.span[v];
        let start = self.pool.len();
        assert!(
            start + cap <= u32::MAX as usize,
            "star lists beyond 2³² entries"
        );
        if old.len > 0 {
            let from = old.start as usize;
            self.pool.extend_from_within(from..from + len);
        }
        self.pool.resize(start + cap, 0);
        self.garbage += old.cap as usize;
        self.span[v] = Span {
            start: start as u32,
            len: old.len,
            cap: cap as u16,
        };
    }

    /// Before the pool grows past its allocation: compacts it when that
    /// frees at least an eighth of the pool, and gives it an eighth more
    /// room (not double: the pool is the largest array of a run) when it
    /// does not or that is not enough.
    fn make_room(&mut self, need: usize) {
        if self.garbage >= self.pool.len() / 8 {
            self.compact(need);
        }
        if self.pool.len() + need > self.pool.capacity() {
            self.pool.reserve_exact(need + self.pool.len() / 8);
        }
    }

    /// Copies every star into a new pool in vertex order, leaving no
    /// garbage; each keeps its room. Spans without room point at the
    /// start, which any pool has (an empty range there), wherever they
    /// pointed before. The new pool is allocated with the room the caller
    /// needs, as `make_room` would reserve it.
    ///
    /// A copy, not a slide in place: sliding needs the spans in pool
    /// order, and sorting them was most of the cost of a compaction; the
    /// copy lives as long as the compaction (the old pool is freed at
    /// once), and a star's place in the pool changes nothing else.
    fn compact(&mut self, need: usize) {
        let live = self.pool.len() - self.garbage;
        let cap = if live + need > self.pool.capacity() {
            live + need + live / 8
        } else {
            self.pool.capacity()
        };
        let mut pool = Vec::with_capacity(cap);
        for s in &mut self.span {
            if s.cap == 0 {
                s.start = 0;
                continue;
            }
            if s.cap == LARGE {
                continue;
            }
            let (from, len) = (s.start as usize, s.len as usize);
            s.start = pool.len() as u32;
            pool.extend_from_slice(&self.pool[from..from + len]);
            pool.resize(pool.len() + (s.cap as usize - len), 0);
        }
        self.pool = pool;
        self.garbage = 0;
    }
}

impl std::ops::Index<usize> for StarLists {
    type Output = [u32];
    #[inline]
    fn index(&self, v: usize) -> &[u32] {
        self.get(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed pseudo-random sequence (xorshift64) from `seed`.
    fn xorshift(mut x: u64) -> impl FnMut() -> u64 {
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        }
    }

    /// The stars as vectors, for comparison.
    fn as_vecs(s: &StarLists) -> Vec<Vec<u32>> {
        s.iter().map(<[u32]>::to_vec).collect()
    }

    #[test]
    fn stars_behave_like_vectors_through_growth_and_compaction() {
        // A reference of plain vectors driven through the same operations
        // by a fixed pseudo-random sequence: pushes that outgrow spans,
        // swap-removals, retains and takes, enough to compact many times.
        let n = 50usize;
        let mut stars = StarLists::with_capacities((0..n as u32).map(|v| v % 4));
        let mut reference: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut next = xorshift(12345u64);
        let mut out = Vec::new();
        let mut compactions = 0;
        for step in 0..20_000u32 {
            let v = (next() % n as u64) as usize;
            // Only a compaction shortens the pool.
            let pool_before = stars.pool.len();
            match next() % 10 {
                0..=4 => {
                    stars.push(v, step);
                    reference[v].push(step);
                }
                5..=6 => {
                    if let Some(&y) = reference[v].get((next() % 8) as usize) {
                        stars.remove(v, y);
                        let p = reference[v].iter().position(|&z| z == y).unwrap();
                        reference[v].swap_remove(p);
                    }
                }
                7 => {
                    stars.retain(v, |y| y % 3 != 0);
                    reference[v].retain(|y| y % 3 != 0);
                }
                _ => {
                    stars.take(v, &mut out);
                    assert_eq!(out, std::mem::take(&mut reference[v]));
                }
            }
            if stars.pool.len() < pool_before {
                compactions += 1;
            }
            // Every pool entry is some span's room or counted garbage.
            let owned: usize = stars
                .span
                .iter()
                .filter(|s| s.cap != LARGE)
                .map(|s| s.cap as usize)
                .sum();
            assert_eq!(owned + stars.garbage, stars.pool.len(), "step {step}");
        }
        assert_eq!(as_vecs(&stars), reference);
        assert!(compactions > 10, "only {compactions} compactions");
    }

    #[test]
    fn a_star_larger_than_a_span_lives_outside_the_pool() {
        // One star grows past what a span counts (a fan's centre), beside
        // small ones that keep compacting around it; another starts large.
        let n = 8usize;
        let mut counts = vec![2u32; n];
        counts[5] = 70_000;
        let mut stars = StarLists::with_capacities(counts.into_iter());
        let mut reference: Vec<Vec<u32>> = vec![Vec::new(); n];
        for x in 0..150_000u32 {
            let v = if x % 3 == 0 { (x as usize / 3) % n } else { 2 };
            let v = if x % 7 == 0 { 5 } else { v };
            stars.push(v, x);
            reference[v].push(x);
            if x % 10 == 0 {
                let y = reference[v][reference[v].len() / 2];
                stars.remove(v, y);
                let p = reference[v].iter().position(|&z| z == y).unwrap();
                reference[v].swap_remove(p);
            }
        }
        assert!(reference[2].len() > MAX_POOLED);
        assert_eq!(stars.span[2].cap, LARGE);
        assert_eq!(stars.span[5].cap, LARGE);
        stars.retain(2, |x| x % 2 == 0);
        reference[2].retain(|x| x % 2 == 0);
        assert_eq!(as_vecs(&stars), reference);
        let mut out = Vec::new();
        stars.take(2, &mut out);
        assert_eq!(out, std::mem::take(&mut reference[2]));
        // Star 5 was made large first, star 2 grew out of the pool second.
        assert_eq!(stars.large[1].entries.capacity(), 0);
        stars.push(2, 1);
        reference[2].push(1);
        assert_eq!(as_vecs(&stars), reference);
    }

    #[test]
    fn large_stars_with_repeats_behave_like_vectors() {
        // Three stars far past the pool, fed entries from a small range so
        // that entries repeat (the index gives way to a scan) and stop
        // repeating again (it comes back), through pushes, removals of
        // present and absent entries, and retains.
        let n = 3usize;
        let mut stars = StarLists::with_capacities([0u32, 2000, 5].into_iter());
        let mut reference: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut next = xorshift(987654321u64);
        let (mut indexed, mut scanned) = (0, 0);
        for step in 0..60_000u32 {
            let v = (next() % n as u64) as usize;
            match next() % 4096 {
                0..=2399 => {
                    // Mostly fresh entries, now and then a repeat.
                    let y = if next() % 50 == 0 {
                        (next() % 64) as u32
                    } else {
                        1000 + step
                    };
                    stars.push(v, y);
                    reference[v].push(y);
                }
                2400..=4094 => {
                    let y = match reference[v].len() {
                        0 => 7,
                        len => reference[v][(next() % len as u64) as usize],
                    };
                    let y = if next() % 10 == 0 { u32::MAX } else { y };
                    stars.remove(v, y);
                    if let Some(p) = reference[v].iter().position(|&z| z == y) {
                        reference[v].swap_remove(p);
                    }
                }
                _ => {
                    let m = 5 + (next() % 5) as u32;
                    stars.retain(v, |y| y % m != 0);
                    reference[v].retain(|y| y % m != 0);
                }
            }
            assert_eq!(stars.get(v), &reference[v][..], "step {step}");
            if let Some(star) = stars.large_mut(v) {
                match &star.at {
                    Some(at) => {
                        indexed += 1;
                        // The index says where every entry is.
                        assert_eq!(at.len(), star.entries.len());
                        for (&y, &p) in at {
                            assert_eq!(star.entries[p as usize], y);
                        }
                    }
                    None => scanned += 1,
                }
            }
        }
        assert!(reference.iter().all(|r| r.len() > MAX_POOLED));
        assert!(indexed > 1000 && scanned > 1000, "{indexed} {scanned}");
    }

    #[test]
    fn removal_swaps_the_last_entry_in_and_retain_keeps_order() {
        let mut s = StarLists::with_capacities([5u32, 0].into_iter());
        for x in [10, 11, 12, 13, 14] {
            s.push(0, x);
        }
        s.remove(0, 11);
        assert_eq!(&s[0], &[10, 14, 12, 13]);
        s.remove(0, 99);
        assert_eq!(&s[0], &[10, 14, 12, 13]);
        s.retain(0, |x| x != 14);
        assert_eq!(&s[0], &[10, 12, 13]);
        // A push into a star without room moves it to the end.
        s.push(1, 7);
        assert_eq!(&s[1], &[7]);
        assert_eq!(s.span[1].start, 5);
        assert_eq!(s.span[1].cap, 4);
        let mut out = vec![1, 2];
        s.take(0, &mut out);
        assert_eq!(out, vec![10, 12, 13]);
        assert!(s[0].is_empty());
        assert_eq!(s.garbage, 5);
    }
}
