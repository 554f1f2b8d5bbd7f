//! Star lists (the faces or the edges around each vertex) kept in one
//! shared pool: 12 bytes of span per vertex and 4 per entry, where a
//! small vector per vertex took 40 bytes inline and a heap block for every
//! star that outgrew it (issue 15: the chunks' star lists were the largest
//! part of a large run's peak).
//!
//! A star that grows past its span moves to the end of the pool with room
//! to spare; the space it leaves is garbage, reclaimed by sliding every
//! span down when the pool is full and enough of it is garbage. Stars keep
//! the order of their entries exactly as a vector would (pushes append,
//! removals swap the last entry in, `retain` keeps the order), so every
//! walk over a star sees what it saw before.

/// Where a star lives in the pool.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Span {
    start: u32,
    len: u32,
    cap: u32,
}

/// One star per vertex, in a shared pool.
#[derive(Clone, Debug, Default)]
pub(crate) struct StarLists {
    span: Vec<Span>,
    pool: Vec<u32>,
    /// Pool entries no span owns.
    garbage: usize,
}

impl StarLists {
    /// Empty stars, one per count, each with room for exactly its count.
    pub fn with_capacities(counts: impl ExactSizeIterator<Item = u32>) -> StarLists {
        let mut span = Vec::with_capacity(counts.len());
        let mut next = 0u32;
        for cap in counts {
            span.push(Span {
                start: next,
                len: 0,
                cap,
            });
            next += cap;
        }
        StarLists {
            span,
            pool: vec![0; next as usize],
            garbage: 0,
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
        &self.pool[s.start as usize..(s.start + s.len) as usize]
    }

    /// Every star, in vertex order.
    #[cfg(test)]
    pub fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        (0..self.span.len()).map(|v| self.get(v))
    }

    /// Appends `x` to the star of `v`.
    #[inline]
    pub fn push(&mut self, v: usize, x: u32) {
        if self.span[v].len == self.span[v].cap {
            self.grow(v);
        }
        let s = &mut self.span[v];
        self.pool[(s.start + s.len) as usize] = x;
        s.len += 1;
    }

    /// Removes one occurrence of `x` from the star of `v`, the last entry
    /// taking its place (a vector's `swap_remove`).
    #[inline]
    pub fn remove(&mut self, v: usize, x: u32) {
        let s = &mut self.span[v];
        let star = &mut self.pool[s.start as usize..(s.start + s.len) as usize];
        if let Some(p) = star.iter().position(|&y| y == x) {
            star[p] = star[star.len() - 1];
            s.len -= 1;
        }
    }

    /// Keeps the entries of `v`'s star for which `keep` holds, in order.
    pub fn retain(&mut self, v: usize, mut keep: impl FnMut(u32) -> bool) {
        let s = &mut self.span[v];
        let star = &mut self.pool[s.start as usize..(s.start + s.len) as usize];
        let mut w = 0;
        for r in 0..star.len() {
            if keep(star[r]) {
                star[w] = star[r];
                w += 1;
            }
        }
        s.len = w as u32;
    }

    /// Moves the star of `v` into `out` (cleared first), leaving it empty
    /// and without room: a vertex merged away.
    pub fn take(&mut self, v: usize, out: &mut Vec<u32>) {
        out.clear();
        out.extend_from_slice(self.get(v));
        self.garbage += self.span[v].cap as usize;
        self.span[v] = Span::default();
    }

    /// Moves the star of `v` to the end of the pool with room to grow.
    #[cold]
    fn grow(&mut self, v: usize) {
        let old = self.span[v];
        // Half as much again, and at least four: a vertex that gains a
        // star in a collapse gains a few faces, rarely many.
        let cap = (old.len + 4).max(old.len + old.len / 2);
        if self.pool.len() + cap as usize > self.pool.capacity() {
            self.make_room(cap as usize);
        }
        let old = self.span[v];
        let start = self.pool.len();
        assert!(
            start + cap as usize <= u32::MAX as usize,
            "star lists beyond 2³² entries"
        );
        self.pool
            .extend_from_within(old.start as usize..(old.start + old.len) as usize);
        self.pool.resize(start + cap as usize, 0);
        self.garbage += old.cap as usize;
        self.span[v] = Span {
            start: start as u32,
            len: old.len,
            cap,
        };
    }

    /// Before the pool grows past its allocation: slides every span down
    /// over the garbage when that frees at least an eighth of the pool,
    /// and reserves an eighth more (not double: the pool is the largest
    /// array of a run) when it does not or that is not enough.
    fn make_room(&mut self, need: usize) {
        if self.garbage >= self.pool.len() / 8 {
            self.compact();
        }
        if self.pool.len() + need > self.pool.capacity() {
            self.pool.reserve_exact(need + self.pool.len() / 8);
        }
    }

    /// Slides every span down in pool order, leaving no garbage; each
    /// keeps its room. Spans without room point at the start, which any
    /// pool has (an empty range there), wherever they pointed before.
    fn compact(&mut self) {
        for s in &mut self.span {
            if s.cap == 0 {
                s.start = 0;
            }
        }
        let mut order: Vec<u32> = (0..self.span.len() as u32)
            .filter(|&v| self.span[v as usize].cap > 0)
            .collect();
        order.sort_unstable_by_key(|&v| self.span[v as usize].start);
        let mut next = 0u32;
        for v in order {
            let s = &mut self.span[v as usize];
            if s.start != next {
                self.pool
                    .copy_within(s.start as usize..(s.start + s.len) as usize, next as usize);
                s.start = next;
            }
            next += s.cap;
        }
        self.pool.truncate(next as usize);
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
        let mut x = 12345u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
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
            let owned: usize = stars.span.iter().map(|s| s.cap as usize).sum();
            assert_eq!(owned + stars.garbage, stars.pool.len(), "step {step}");
        }
        assert_eq!(as_vecs(&stars), reference);
        assert!(compactions > 10, "only {compactions} compactions");
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
