//! Where the partitioned phase keeps a per-item array (per vertex: the
//! quadrics; per wedge: the attribute quadrics) while its chunks run: in
//! the run's array itself, rearranged so that the chunks' ranges follow
//! one another, each in its local order. The values are moved there and
//! back in place, not copied: the run's arrays alive beside the chunks'
//! copies were the phase's peak.

use crate::prepare::complex::NONE;

/// The chunks' ranges of one rearranged array.
pub(super) struct Slots {
    /// Start of each chunk's range (in items), and the end of the last.
    pub start: Vec<usize>,
    /// Each item's slot: its one copy, or the first of its copies for an
    /// item in several chunks (a vertex on a cut, read-only in all);
    /// `NONE` for an item in no chunk.
    pub slot: Vec<u32>,
}

impl Slots {
    /// The slots of `n` items when each chunk holds the items of its list
    /// (run ids, in local order).
    pub fn new<'a, I>(lists: I, n: usize) -> Slots
    where
        I: Iterator<Item = &'a [u32]> + Clone,
    {
        let mut start = Vec::new();
        let mut next = 0usize;
        for l in lists.clone() {
            start.push(next);
            next += l.len();
        }
        start.push(next);
        Slots {
            start,
            slot: first_slots(lists, n),
        }
    }

    /// Length of the rearranged array, in items: the chunks' ranges, or
    /// more where items in no chunk make the run's array longer.
    pub fn len(&self) -> usize {
        self.slot.len().max(self.start.last().copied().unwrap_or(0))
    }

    /// Rearranges `g` (`stride` values per item) into the chunks' ranges,
    /// `lists` being the lists the slots were made from. Values of items in
    /// no chunk are lost: the caller sets aside the ones it needs.
    pub fn move_to_chunks<'a, T: Copy + Default>(
        &self,
        g: &mut Vec<T>,
        stride: usize,
        lists: impl Iterator<Item = &'a [u32]>,
    ) {
        let n = g.len() / stride;
        // Exactly: `resize` alone would double the capacity.
        g.reserve_exact(self.len() * stride - g.len());
        g.resize(self.len() * stride, T::default());
        // Each item's value to its slot; a chain ends at a slot whose
        // value is no longer needed.
        let slot = &self.slot;
        permute(g, stride, |at| {
            (at < n && slot[at] != NONE).then(|| slot[at] as usize)
        });
        // The further copies of items in several chunks.
        for (list, &start) in lists.zip(&self.start) {
            for (k, &v) in list.iter().enumerate() {
                let first = self.slot[v as usize] as usize;
                if first != start + k {
                    g.copy_within(first * stride..(first + 1) * stride, (start + k) * stride);
                }
            }
        }
    }

    /// Puts the values back in item order (undoes
    /// [`Slots::move_to_chunks`]), each item taking its first copy; items
    /// in no chunk get the default value.
    pub fn move_back<T: Copy + Default>(&self, g: &mut Vec<T>, stride: usize) {
        let n = self.slot.len();
        let mut item = vec![NONE; g.len() / stride];
        for (v, &s) in self.slot.iter().enumerate() {
            if s != NONE {
                item[s as usize] = v as u32;
            }
        }
        permute(g, stride, |at| {
            (item[at] != NONE).then(|| item[at] as usize)
        });
        g.truncate(n * stride);
        g.shrink_to_fit();
        for (v, &s) in self.slot.iter().enumerate() {
            if s == NONE {
                g[v * stride..(v + 1) * stride].fill(T::default());
            }
        }
    }
}

/// Each item's first slot when the chunks' lists (in chunk order) follow
/// one another; `NONE` for an item in none.
pub(super) fn first_slots<'a>(lists: impl Iterator<Item = &'a [u32]>, n: usize) -> Vec<u32> {
    let mut slot = vec![NONE; n];
    let mut next = 0u32;
    for list in lists {
        for &v in list {
            if slot[v as usize] == NONE {
                slot[v as usize] = next;
            }
            next += 1;
        }
    }
    slot
}

/// Moves every item of `g` (`stride` values each) at an index with a
/// destination there, in place: each cycle or chain of displaced items is
/// followed once, and a chain ends at an index without a destination,
/// whose item is dropped.
fn permute<T: Copy>(g: &mut [T], stride: usize, dest: impl Fn(usize) -> Option<usize>) {
    let n = g.len() / stride;
    let mut done = vec![false; n];
    let mut value: Vec<T> = Vec::with_capacity(stride);
    let mut next: Vec<T> = Vec::with_capacity(stride);
    for start in 0..n {
        if done[start] || dest(start).is_none() {
            continue;
        }
        done[start] = true;
        value.clear();
        value.extend_from_slice(&g[start * stride..(start + 1) * stride]);
        let mut at = start;
        while let Some(to) = dest(at) {
            let block = &mut g[to * stride..(to + 1) * stride];
            if !done[to] && dest(to).is_some() {
                done[to] = true;
                next.clear();
                next.extend_from_slice(block);
                block.copy_from_slice(&value);
                std::mem::swap(&mut value, &mut next);
                at = to;
            } else {
                block.copy_from_slice(&value);
                break;
            }
        }
    }
}

/// `s` cut into consecutive ranges, `start` giving their bounds in items
/// of `stride` values.
pub(super) fn split_ranges<'a, T>(
    mut s: &'a mut [T],
    start: &[usize],
    stride: usize,
) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(start.len().saturating_sub(1));
    for w in start.windows(2) {
        let (range, rest) = std::mem::take(&mut s).split_at_mut((w[1] - w[0]) * stride);
        out.push(range);
        s = rest;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strided_items_move_to_the_chunks_and_back() {
        // Items 0..6, three values each; chunk 0 holds 4, 1; chunk 1 holds
        // 1 (shared, read-only), 2, 5; items 0 and 3 are in no chunk.
        let lists: [&[u32]; 2] = [&[4, 1], &[1, 2, 5]];
        let slots = Slots::new(lists.iter().copied(), 6);
        assert_eq!(slots.start, vec![0, 2, 5]);
        assert_eq!(slots.slot, vec![NONE, 1, 3, NONE, 0, 4]);
        let values: Vec<u32> = (0..18).map(|x| 100 + x).collect();
        let mut g = values.clone();
        slots.move_to_chunks(&mut g, 3, lists.iter().copied());
        let item = |v: u32| values[3 * v as usize..3 * v as usize + 3].to_vec();
        let mut ranges = split_ranges(&mut g, &slots.start, 3);
        assert_eq!(ranges[0], [item(4), item(1)].concat());
        assert_eq!(ranges[1], [item(1), item(2), item(5)].concat());
        // A chunk changes its own items; the shared one only in its first
        // copy's chunk would be read back.
        ranges[1][3] = 7; // item 2's first value
        slots.move_back(&mut g, 3);
        let mut expected = values;
        expected[6] = 7;
        expected[0..3].fill(0);
        expected[9..12].fill(0);
        assert_eq!(g, expected);
    }
}
