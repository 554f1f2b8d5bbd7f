//! Wedges (Hoppe 1999): the corners of one position that carry the same
//! value of a stream. A position with one wedge is inside a chart of that
//! stream; with several it lies on a seam (a UV seam, a hard normal edge, a
//! color or material border). Wedges are found by value, not by index: a
//! glTF vertex split only for its normal still has one UV wedge.

use rayon::prelude::*;

use super::input::ABSENT;

/// The wedges of one stream.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Wedges {
    /// Wedge of every input corner, or [`ABSENT`].
    pub corner_wedge: Vec<u32>,
    /// For every wedge, one input corner of it (the first).
    pub first_corner: Vec<u32>,
}

impl Wedges {
    /// Number of wedges.
    pub fn count(&self) -> usize {
        self.first_corner.len()
    }
}

/// Bits of a value component, with −0 and +0 the same value.
#[inline]
pub(crate) fn value_bits(x: f32) -> u32 {
    if x == 0.0 {
        0
    } else {
        x.to_bits()
    }
}

/// Groups corners into wedges: corners at the same (welded) vertex with the
/// same key are one wedge. `corner_vertex[c]` is corner `c`'s welded vertex;
/// `key(c)` its value (up to four components' bits), `None` for a corner
/// without a value. Wedge ids follow the order of their first corner, so
/// the result does not depend on the thread count.
pub(crate) fn build_wedges(
    corner_vertex: &[u32],
    key: impl Fn(usize) -> Option<[u32; 4]> + Sync,
) -> Wedges {
    let mut keyed: Vec<(u32, [u32; 4], u32)> = (0..corner_vertex.len())
        .into_par_iter()
        .filter_map(|c| key(c).map(|k| (corner_vertex[c], k, c as u32)))
        .collect();
    keyed.par_sort_unstable();
    let mut corner_wedge = vec![ABSENT; corner_vertex.len()];
    // Provisional ids in sorted order, renumbered by first corner below.
    let mut provisional_first: Vec<u32> = Vec::new();
    let mut g = 0;
    while g < keyed.len() {
        let mut h = g + 1;
        while h < keyed.len() && keyed[h].0 == keyed[g].0 && keyed[h].1 == keyed[g].1 {
            h += 1;
        }
        let id = provisional_first.len() as u32;
        // Sorted by corner within a key: the first is the smallest.
        provisional_first.push(keyed[g].2);
        for item in &keyed[g..h] {
            corner_wedge[item.2 as usize] = id;
        }
        g = h;
    }
    let mut order: Vec<u32> = (0..provisional_first.len() as u32).collect();
    order.sort_unstable_by_key(|&w| provisional_first[w as usize]);
    let mut renumber = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        renumber[old as usize] = new as u32;
    }
    for w in corner_wedge.iter_mut() {
        if *w != ABSENT {
            *w = renumber[*w as usize];
        }
    }
    let first_corner = order
        .iter()
        .map(|&w| provisional_first[w as usize])
        .collect();
    Wedges {
        corner_wedge,
        first_corner,
    }
}

/// The key of a stream value: its components' bits, padded with zeros.
pub(crate) fn stream_key(values: &[f32], indices: &[u32], m: usize, c: usize) -> Option<[u32; 4]> {
    let i = indices[c];
    if i == ABSENT {
        return None;
    }
    let v = values.get(i as usize * m..i as usize * m + m)?;
    let mut k = [0u32; 4];
    for (slot, &x) in k.iter_mut().zip(v) {
        *slot = value_bits(x);
    }
    Some(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_split_by_value_not_by_index() {
        // Four corners at vertex 0: UV values (0,0) [index 0], (0,0) [index 2,
        // an equal copy], (1,0) [index 1], absent; one corner at vertex 1
        // with value (0,0).
        let values = [0.0, 0.0, 1.0, 0.0, -0.0, 0.0];
        let indices = [0, 2, 1, ABSENT, 0];
        let corner_vertex = [0, 0, 0, 0, 1];
        let w = build_wedges(&corner_vertex, |c| stream_key(&values, &indices, 2, c));
        // Wedges by first corner: {0, 1} at vertex 0, {2} at vertex 0, {4}.
        assert_eq!(w.corner_wedge, vec![0, 0, 1, ABSENT, 2]);
        assert_eq!(w.first_corner, vec![0, 2, 4]);
        assert_eq!(w.count(), 3);
    }
}
