//! Wedges (Hoppe 1999): the corners of one position that carry the same
//! value of a stream. A position with one wedge is inside a chart of that
//! stream; with several it lies on a seam (a UV seam, a hard normal edge, a
//! color or material border). Wedges are found by value, not by index: a
//! glTF vertex split only for its normal still has one UV wedge.

use rayon::prelude::*;

use crate::input::{StreamKind, ABSENT};

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

/// Values of a stream that differ by at most this in every component are
/// one value (see [`build_wedges`]): below what can be seen, above what
/// rounding makes. `range` is the stream's largest component extent.
/// - Directions: 1e-3 (about 0.06°) turns diffuse shading by a quarter of
///   an 8-bit display step (1/255); a hard edge an artist makes is degrees.
/// - Colors: a quarter of an 8-bit step, so colors an 8-bit file can tell
///   apart stay apart.
/// - Texture coordinates and anything else: 1e-5 of the range, a sixth of
///   a texel of a 16k texture that spans it.
/// - Carried values are never compared.
pub(crate) fn value_tolerance(kind: StreamKind, range: f64) -> f32 {
    match kind {
        StreamKind::Direction | StreamKind::Color => 1e-3,
        StreamKind::TexCoord | StreamKind::Generic => (1e-5 * range) as f32,
        StreamKind::Carried => 0.0,
    }
}

/// `near` for [`build_wedges`]: keys of [`stream_key`] whose values differ
/// by at most `tolerance` in every component.
pub(crate) fn within(tolerance: f32) -> impl Fn(&[u32; 4], &[u32; 4]) -> bool {
    move |a, b| {
        a.iter()
            .zip(b)
            .all(|(&x, &y)| (f32::from_bits(x) - f32::from_bits(y)).abs() <= tolerance)
    }
}

/// Above this many distinct values at one vertex, a value is compared with
/// the first this many wedges only: such a vertex holds per-face values (a
/// flat-shaded fan's centre), and comparing all pairs would be quadratic.
const MAX_COMPARED_WEDGES: usize = 64;

/// Groups corners into wedges: corners at the same (welded) vertex whose
/// keys are `near` are one wedge. `corner_vertex[c]` is corner `c`'s welded
/// vertex; `key(c)` its value (up to four components' bits), `None` for a
/// corner without a value. Equal keys are always one wedge; a distinct key
/// joins the first wedge of its vertex (in key order) whose first key it is
/// `near`, so values that differ by rounding noise (exporters write a split
/// vertex's normal twice, a few ulps apart) are not a seam. Wedge ids follow
/// the order of their first corner, so the result does not depend on the
/// thread count.
pub(crate) fn build_wedges(
    corner_vertex: &[u32],
    key: impl Fn(usize) -> Option<[u32; 4]> + Sync,
    near: impl Fn(&[u32; 4], &[u32; 4]) -> bool,
) -> Wedges {
    let mut keyed: Vec<(u32, [u32; 4], u32)> = (0..corner_vertex.len())
        .into_par_iter()
        .filter_map(|c| key(c).map(|k| (corner_vertex[c], k, c as u32)))
        .collect();
    keyed.par_sort_unstable();
    let mut corner_wedge = vec![ABSENT; corner_vertex.len()];
    // Provisional ids in sorted order, renumbered by first corner below.
    let mut provisional_first: Vec<u32> = Vec::new();
    // The wedges of the current vertex: (provisional id, first key).
    let mut at_vertex: Vec<(u32, [u32; 4])> = Vec::new();
    let mut g = 0;
    while g < keyed.len() {
        let mut h = g + 1;
        while h < keyed.len() && keyed[h].0 == keyed[g].0 && keyed[h].1 == keyed[g].1 {
            h += 1;
        }
        if g == 0 || keyed[g - 1].0 != keyed[g].0 {
            at_vertex.clear();
        }
        let joined = at_vertex
            .iter()
            .take(MAX_COMPARED_WEDGES)
            .find(|(_, k)| near(k, &keyed[g].1))
            .map(|&(id, _)| id);
        // Sorted by corner within a key: the group's first is its smallest.
        let first = keyed[g].2;
        let id = match joined {
            Some(id) => {
                let f = &mut provisional_first[id as usize];
                *f = (*f).min(first);
                id
            }
            None => {
                let id = provisional_first.len() as u32;
                provisional_first.push(first);
                at_vertex.push((id, keyed[g].1));
                id
            }
        };
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
        let w = build_wedges(
            &corner_vertex,
            |c| stream_key(&values, &indices, 2, c),
            within(0.0),
        );
        // Wedges by first corner: {0, 1} at vertex 0, {2} at vertex 0, {4}.
        assert_eq!(w.corner_wedge, vec![0, 0, 1, ABSENT, 2]);
        assert_eq!(w.first_corner, vec![0, 2, 4]);
        assert_eq!(w.count(), 3);
    }

    #[test]
    fn values_within_the_tolerance_are_one_wedge_and_others_are_not() {
        // Five corners at vertex 0 with unit normals: (0,0,1) twice a few
        // ulps apart, (0,0.0009,1) within 1e-3 of the first, (0,0.002,1)
        // beyond it; corner 4 at vertex 1 equals corner 0.
        let values = [
            0.0,
            0.002,
            1.0, // index 0
            0.0,
            0.0,
            1.0, // 1
            0.0,
            0.0,
            1.000_000_1, // 2
            0.0,
            0.0009,
            1.0, // 3
        ];
        let indices = [1, 0, 2, 3, 1];
        let corner_vertex = [0, 0, 0, 0, 1];
        let key = |c| stream_key(&values, &indices, 3, c);
        let w = build_wedges(&corner_vertex, key, within(1e-3));
        // Corners 0, 2, 3 are one wedge (first corner 0), corner 1 another.
        assert_eq!(w.corner_wedge, vec![0, 1, 0, 0, 2]);
        assert_eq!(w.first_corner, vec![0, 1, 4]);
        // Exact comparison keeps the four values apart.
        let exact = build_wedges(&corner_vertex, key, within(0.0));
        assert_eq!(exact.count(), 5);
    }

    #[test]
    fn tolerances_by_kind() {
        assert_eq!(value_tolerance(StreamKind::Direction, 2.0), 1e-3);
        assert_eq!(value_tolerance(StreamKind::Color, 1.0), 1e-3);
        assert_eq!(value_tolerance(StreamKind::TexCoord, 2.0), 2e-5);
        assert_eq!(value_tolerance(StreamKind::Generic, 0.5), 5e-6);
        assert_eq!(value_tolerance(StreamKind::Carried, 1.0), 0.0);
        // 1/255 apart (two 8-bit colors) is beyond the color tolerance.
        assert!(!within(value_tolerance(StreamKind::Color, 1.0))(
            &[0, 0, 0, 0],
            &[(1.0f32 / 255.0).to_bits(), 0, 0, 0]
        ));
    }
}
