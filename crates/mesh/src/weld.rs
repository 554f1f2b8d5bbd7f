//! Welding: one id per distinct position, so that connectivity survives
//! attribute seams (a glTF vertex duplicated for two UVs) and triangle soups
//! (an STL file's three private vertices per triangle).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Maps every position to the id of its first exact duplicate, ids counted
/// in order of first appearance. Returns `(remap, distinct count)`.
///
/// Equality is exact on the `f32` bits, with `-0.0` treated as `0.0`; a
/// tolerance would merge vertices that the author kept apart, and changes
/// the mesh: welding within a distance is what virtual edges are for.
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
    fn nearly_equal_positions_stay_apart() {
        let p = [[1.0, 0.0, 0.0], [1.0 + f32::EPSILON, 0.0, 0.0]];
        assert_eq!(weld_positions(&p).1, 2);
    }
}
