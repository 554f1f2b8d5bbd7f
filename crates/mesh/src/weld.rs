//! Welding: one id per distinct position, so that connectivity survives
//! attribute seams (a glTF vertex duplicated for two UVs) and triangle soups
//! (an STL file's three private vertices per triangle); and merging points
//! that differ by rounding noise only.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Maps every position to the id of its first exact duplicate, ids counted
/// in order of first appearance. Returns `(remap, distinct count)`.
///
/// Equality is exact on the `f32` bits, with `-0.0` treated as `0.0`; a
/// tolerance of real size would merge vertices that the author kept apart,
/// and changes the mesh: welding across a gap is what virtual edges are
/// for. Differences below what the numbers can hold are
/// [`merge_within`]'s.
pub fn weld_positions(positions: &[[f32; 3]]) -> (Vec<u32>, usize) {
    let mut map: HashMap<[u32; 3], u32, BuildHasherDefault<PositionHasher>> =
        HashMap::with_capacity_and_hasher(positions.len(), Default::default());
    let mut remap = Vec::with_capacity(positions.len());
    for p in positions {
        let next = map.len() as u32;
        let id = *map.entry(position_key(p)).or_insert(next);
        remap.push(id);
    }
    let n = map.len();
    (remap, n)
}

/// Merges points closer than `tol` in every coordinate: `points` are
/// `(id, position)` with ids below `n`, ascending; each point goes to the
/// first earlier point within `tol` of it, if any (no chains: a point joins
/// a representative, never a point that itself joined one). Returns every
/// id's new id, numbered in order of first appearance, and their count;
/// `None` when nothing merges.
///
/// For positions that are equal to the precision of their numbers but not
/// bit for bit (a height computed as `sin(π)`, `1e-17` on one side of a
/// grid line and `-1e-17` on the other); the simplifier passes a quarter of
/// the `f32` spacing at the model's largest coordinate.
pub fn merge_within(points: &[(u32, [f64; 3])], n: usize, tol: f64) -> Option<(Vec<u32>, usize)> {
    if !(tol > 0.0 && tol.is_finite()) {
        return None;
    }
    // Cells far wider than the tolerance: a point looks into a neighbour
    // cell only where it lies within the tolerance of that side, so almost
    // every point costs one lookup. Representatives of a cell are chained
    // through `next` (no allocation per cell).
    let size = 64.0 * tol;
    let inverse = 1.0 / size;
    // A cell's key: its three indices mixed into one word. Two cells may
    // share a key; their points then share a chain, and the distance test
    // tells them apart.
    let key = |c: [i64; 3]| -> u64 {
        (c[0] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (c[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (c[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9)
    };
    let mut head: HashMap<u64, u32, BuildHasherDefault<PositionHasher>> =
        HashMap::with_capacity_and_hasher(points.len(), Default::default());
    let mut reps: Vec<(u32, [f64; 3], u32)> = Vec::with_capacity(points.len());
    let mut target: Vec<u32> = (0..n as u32).collect();
    let mut merged = false;
    for &(id, p) in points {
        if !p.iter().all(|c| c.is_finite()) {
            continue;
        }
        let k = p.map(|c| (c * inverse).floor() as i64);
        // Per axis, the cells within the tolerance: this one, and the one
        // before or after where the point is that close to the side.
        let near = |a: usize| -> [i64; 3] {
            let f = p[a] - k[a] as f64 * size;
            [
                0,
                if f <= tol { -1 } else { 0 },
                if f >= size - tol { 1 } else { 0 },
            ]
        };
        let (nx, ny, nz) = (near(0), near(1), near(2));
        let chain = |mut at: Option<u32>| {
            while let Some(r) = at {
                let (rid, q, next) = reps[r as usize];
                if (0..3).all(|a| (p[a] - q[a]).abs() <= tol) {
                    return Some(rid);
                }
                at = (next != u32::MAX).then_some(next);
            }
            None
        };
        // The neighbour cells first (rare: only near a side), then the
        // point's own cell through one entry, which also files it there.
        let mut found = None;
        'search: for (i, &dx) in nx.iter().enumerate() {
            for (j, &dy) in ny.iter().enumerate() {
                for (l, &dz) in nz.iter().enumerate() {
                    // Offsets that repeat 0 name the same cell again; the
                    // cell itself comes last.
                    if (i > 0 && dx == 0) || (j > 0 && dy == 0) || (l > 0 && dz == 0) {
                        continue;
                    }
                    if (dx, dy, dz) == (0, 0, 0) {
                        continue;
                    }
                    found = chain(head.get(&key([k[0] + dx, k[1] + dy, k[2] + dz])).copied());
                    if found.is_some() {
                        break 'search;
                    }
                }
            }
        }
        let slot = reps.len() as u32;
        let mut previous = u32::MAX;
        match head.entry(key(k)) {
            std::collections::hash_map::Entry::Occupied(mut e) => {
                if found.is_none() {
                    found = chain(Some(*e.get()));
                }
                if found.is_none() {
                    previous = e.insert(slot);
                }
            }
            std::collections::hash_map::Entry::Vacant(e) => {
                if found.is_none() {
                    e.insert(slot);
                }
            }
        }
        match found {
            Some(r) => {
                target[id as usize] = r;
                merged = true;
            }
            None => reps.push((id, p, previous)),
        }
    }
    if !merged {
        return None;
    }
    let mut new_id = vec![u32::MAX; n];
    let mut count = 0u32;
    for id in 0..n {
        let t = target[id] as usize;
        if t == id {
            new_id[id] = count;
            count += 1;
        }
    }
    let remap = (0..n).map(|id| new_id[target[id] as usize]).collect();
    Some((remap, count as usize))
}

/// Bit pattern of a position with signed zeros folded together.
#[inline]
pub fn position_key(p: &[f32; 3]) -> [u32; 3] {
    // Adding 0.0 turns -0.0 into +0.0 and leaves every other value alone.
    [
        (p[0] + 0.0).to_bits(),
        (p[1] + 0.0).to_bits(),
        (p[2] + 0.0).to_bits(),
    ]
}

/// A cheap multiplicative hasher for position keys: SipHash's DoS
/// resistance buys nothing here and costs a third of the welding time.
#[derive(Default)]
pub struct PositionHasher(u64);

impl Hasher for PositionHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_positions_share_an_id_and_signed_zero_is_zero() {
        let p = [
            [0.0, 1.0, 2.0],
            [-0.0, 1.0, 2.0],
            [3.0, 0.0, 0.0],
            [0.0, 1.0, 2.0],
        ];
        let (remap, n) = weld_positions(&p);
        assert_eq!(remap, vec![0, 0, 1, 0]);
        assert_eq!(n, 2);
    }

    #[test]
    fn points_within_the_tolerance_join_the_first_and_do_not_chain() {
        // 0 and 1 are 0.6 apart, 1 and 2 too, 0 and 2 are 1.2 apart; 3 is
        // far. With a tolerance of 1, 1 joins 0, and 2 stays: it is within
        // the tolerance of 1 only, which is not a representative.
        let pts = [
            (0, [0.0, 0.0, 0.0]),
            (1, [0.6, 0.0, 0.0]),
            (2, [1.2, 0.0, 0.0]),
            (4, [5.0, 5.0, 5.0]),
        ];
        let (remap, n) = merge_within(&pts, 5, 1.0).expect("one merge");
        // Id 3 is not among the points: it keeps its own new id.
        assert_eq!(remap, vec![0, 0, 1, 2, 3]);
        assert_eq!(n, 4);
        // Every coordinate must be within it: 0.6 in x and 1.1 in y is not.
        let apart = [(0, [0.0, 0.0, 0.0]), (1, [0.6, 1.1, 0.0])];
        assert_eq!(merge_within(&apart, 2, 1.0), None);
        // Across a cell border: -1e-17 and 1e-17 with cells of 1e-6.
        let grid = [(0, [4.4, 1.5, -1e-17]), (1, [4.4, 1.5, 1e-17])];
        assert_eq!(merge_within(&grid, 2, 1e-6), Some((vec![0, 0], 1)));
        let flipped = [(0, [4.4, 1.5, 1e-17]), (1, [4.4, 1.5, -1e-17])];
        assert_eq!(merge_within(&flipped, 2, 1e-6), Some((vec![0, 0], 1)));
        // Diagonally across a cell corner.
        let corner = [(0, [-1e-9, -1e-9, -1e-9]), (1, [1e-9, 1e-9, 1e-9])];
        assert_eq!(merge_within(&corner, 2, 1e-6), Some((vec![0, 0], 1)));
        // No tolerance, no merge.
        assert_eq!(merge_within(&grid, 2, 0.0), None);
    }

    #[test]
    fn nearly_equal_positions_stay_apart() {
        let p = [[1.0, 0.0, 0.0], [1.0 + f32::EPSILON, 0.0, 0.0]];
        assert_eq!(weld_positions(&p).1, 2);
    }
}
