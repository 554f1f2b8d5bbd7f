//! The hash grid of the vertices, built once for all planes, and the
//! search of one plane through it: its candidate pairs and their
//! maximum matching, or the prefilter's sample.

use glam::DVec3;
use rayon::prelude::*;

use super::matching::{max_matching, MatchingScratch};
use super::plane::{floor_i64, pair_error, reflect, Plane};
use super::{SymmetryOptions, NONE};

/// Each vertex is listed in the grid cells of its box of half-width
/// `δ · (1 + SEARCH_MARGIN) + ROUNDING · (1 + max |coordinate|)`, so that a
/// pair whose canonical mirror distance (computed from the other end) is
/// just under `δ` is still found despite rounding in the reflection and
/// the cell computation.
const SEARCH_MARGIN: f64 = 1e-9;

/// Absolute rounding allowance per unit of coordinate magnitude: ~450 ulps,
/// far above the few ulps a reflection and a distance lose.
const ROUNDING: f64 = 1e-13;

/// Candidates kept per vertex. Keeping any `L` of a vertex's candidates,
/// where `L` is the number of positive-side vertices in its cluster (its
/// connected component of the candidate graph), preserves the maximum
/// matching size: the other `L − 1` matched vertices block at most `L − 1`
/// of them. So the count is exact unless a cluster has more than 64
/// vertices on one side (duplicated geometry, or `δ` far above the vertex
/// spacing), where it is a lower bound; and memory stays `O(|V|)`.
const MAX_CANDIDATES: usize = 64;

/// Cell of `p` in a grid of inverse cell size `inv_h`. Monotone in each
/// coordinate, which is all the grid's correctness needs.
fn cell_of(p: DVec3, inv_h: f64) -> [i64; 3] {
    [
        floor_i64(p.x * inv_h),
        floor_i64(p.y * inv_h),
        floor_i64(p.z * inv_h),
    ]
}

/// 64-bit hash of a cell key (splitmix64's finalizer over a multiply–xor
/// of the coordinates): the keys are small correlated integers, and the
/// grid takes its table index, tag and filter bit from different bits.
fn cell_hash(key: [i64; 3]) -> u64 {
    let mut h = (key[0] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (key[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (key[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^= h >> 30;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 27;
    h = h.wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 31)
}

/// The vertices in a uniform hash grid of cell `4δ` (more only for
/// coordinates beyond ~10¹⁰ δ, where rounding is that coarse), built once
/// for all planes, where each vertex is listed in every cell that its
/// `δ`-box overlaps (≤ 2 per axis, ~3.4 cells on average). A mirrored vertex then
/// needs a single cell, the one it falls in, instead of the ≤ 8 its own
/// `δ`-ball overlaps: one lookup per vertex and plane, which is the cost
/// that dominates.
///
/// Most lookups miss (off a symmetry plane, mirror images land in empty
/// space), so an occupancy bitmap answers them before the hash table is
/// touched. It is indexed by the Morton code of the cell's low
/// [`FILTER_BITS`] bits per axis (relative to the lowest cell): exact when
/// the model spans at most 256 cells per axis (δ ≥ 1/1000 of a unit
/// diagonal), aliased (a few false hits, never a false miss) beyond; and
/// nearby cells share cache lines, so the lookups of a run of nearby
/// vertices, whose mirror images are nearby too, mostly hit the cache.
pub(super) struct Grid {
    /// `1 / h` for the cell size `h`.
    inv_h: f64,
    /// Lowest cell key, the origin of the filter's Morton codes.
    origin: [i64; 3],
    /// Bits per axis of the filter's Morton codes.
    filter_bits: u32,
    /// One bit per Morton code: set if some cell has it.
    filter: Vec<u64>,
    /// Open-addressing table (linear probing, load ≤ 1/2): per entry, the
    /// cell index in the low 32 bits (`NONE` = empty) and a 32-bit tag of the
    /// hash in the high bits, so most probes of other cells are rejected
    /// without reading their key.
    table: Vec<u64>,
    /// Key of each cell.
    cell_keys: Vec<[i64; 3]>,
    /// Entry range of cell `i`: `cell_start[i]..cell_start[i + 1]`.
    cell_start: Vec<u32>,
    /// Slots listed in each cell, ascending within a cell.
    entries: Vec<u32>,
    /// Vertex id of each slot.
    ids: Vec<u32>,
    /// Position of each slot; slots are in order of the vertex's own cell,
    /// so a plane's pass over them, and the lookups of their mirror images
    /// (reflection is an isometry), touch nearby memory in turn.
    pos: Vec<DVec3>,
}

/// Bits per axis of the grid's occupancy filter: 2^24 bits, 2 MiB, exact
/// for 256 cells of 4δ per axis, i.e. δ = 1/1000 of a unit diagonal.
const FILTER_BITS: u32 = 8;

/// Morton code of the low `bits` bits per axis of `key − origin`: the
/// filter index of a cell. Keys farther than `2^bits` cells alias, which is
/// harmless for a filter.
fn morton(key: [i64; 3], origin: [i64; 3], bits: u32) -> usize {
    /// Spreads the low 10 bits of `x` to every third bit.
    fn spread(x: u64) -> u64 {
        let mut x = x & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        (x | (x << 2)) & 0x0924_9249
    }
    let low = |i: usize| key[i].wrapping_sub(origin[i]) as u64 & ((1 << bits) - 1);
    (spread(low(0)) | (spread(low(1)) << 1) | (spread(low(2)) << 2)) as usize
}

/// An empty table entry.
const EMPTY: u64 = NONE as u64;

impl Grid {
    /// Bins the finite positions (non-finite ones are left out: they match
    /// nothing). Everything is sorted by (cell, id), so the layout is
    /// deterministic.
    pub(super) fn new(positions: &[DVec3], delta: f64) -> Self {
        let magnitude = positions
            .iter()
            .filter(|p| p.is_finite())
            .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
        let reach = delta * (1.0 + SEARCH_MARGIN) + ROUNDING * (1.0 + magnitude);
        // A box of width 2·reach < h overlaps at most 2 cells per axis.
        let inv_h = 1.0 / (4.0 * delta).max(2.5 * reach);
        let mut own: Vec<([i64; 3], u32)> = positions
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_finite())
            .filter_map(|(i, &p)| Some((cell_of(p, inv_h), u32::try_from(i).ok()?)))
            .collect();
        own.par_sort_unstable();
        let ids: Vec<u32> = own.iter().map(|&(_, id)| id).collect();
        let pos: Vec<DVec3> = ids.iter().map(|&id| positions[id as usize]).collect();
        drop(own);
        let mut listed: Vec<([i64; 3], u32)> = Vec::with_capacity(4 * pos.len());
        for (slot, &p) in pos.iter().enumerate() {
            let lo = cell_of(p - DVec3::splat(reach), inv_h);
            let hi = cell_of(p + DVec3::splat(reach), inv_h);
            // At most 1 by the choice of h (and cell numbers stay far from
            // saturation: |p| / h < 10¹³); the clamp only keeps a bug from
            // turning into a huge loop.
            let span = |i: usize| hi[i].saturating_sub(lo[i]).clamp(0, 1);
            for dx in 0..=span(0) {
                for dy in 0..=span(1) {
                    for dz in 0..=span(2) {
                        listed.push(([lo[0] + dx, lo[1] + dy, lo[2] + dz], slot as u32));
                    }
                }
            }
        }
        listed.par_sort_unstable();
        let mut cell_keys = Vec::new();
        let mut cell_start = Vec::new();
        for (i, (key, _)) in listed.iter().enumerate() {
            if cell_keys.last() != Some(key) {
                cell_keys.push(*key);
                cell_start.push(i as u32);
            }
        }
        cell_start.push(listed.len() as u32);
        let entries = listed.iter().map(|&(_, slot)| slot).collect();
        let size = (2 * cell_keys.len()).next_power_of_two().max(2);
        let mut table = vec![EMPTY; size];
        let mask = size - 1;
        let origin = cell_keys.iter().fold([i64::MAX; 3], |o, k| {
            [o[0].min(k[0]), o[1].min(k[1]), o[2].min(k[2])]
        });
        let extent = cell_keys.iter().fold(1u64, |e, k| {
            (0..3).fold(e, |e, i| e.max(k[i].wrapping_sub(origin[i]) as u64 + 1))
        });
        // Enough bits for the extent, at most FILTER_BITS (2 MiB).
        let filter_bits = (64 - (extent - 1).leading_zeros()).clamp(1, FILTER_BITS);
        let mut filter = vec![0u64; ((1usize << (3 * filter_bits)) / 64).max(1)];
        for (i, key) in cell_keys.iter().enumerate() {
            let b = morton(*key, origin, filter_bits);
            filter[b / 64] |= 1 << (b % 64);
            let h = cell_hash(*key);
            let mut at = h as usize & mask;
            while table[at] != EMPTY {
                at = (at + 1) & mask;
            }
            table[at] = (h & !0xFFFF_FFFF) | i as u64;
        }
        Self {
            inv_h,
            origin,
            filter_bits,
            filter,
            table,
            cell_keys,
            cell_start,
            entries,
            ids,
            pos,
        }
    }

    /// Slots listed in the cell containing `q`: a superset of the vertices
    /// within `δ` of `q`.
    fn near(&self, q: DVec3) -> &[u32] {
        let key = cell_of(q, self.inv_h);
        let b = morton(key, self.origin, self.filter_bits);
        if self.filter[b / 64] & (1 << (b % 64)) == 0 {
            return &[];
        }
        let h = cell_hash(key);
        let mask = self.table.len() - 1;
        let mut at = h as usize & mask;
        loop {
            let entry = self.table[at];
            if entry == EMPTY {
                return &[];
            }
            let i = (entry & 0xFFFF_FFFF) as usize;
            if entry >> 32 == h >> 32 && self.cell_keys[i] == key {
                return &self.entries[self.cell_start[i] as usize..self.cell_start[i + 1] as usize];
            }
            at = (at + 1) & mask;
        }
    }
}

/// Outcome of one plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct PlaneMatch {
    /// Matched vertices: self-matched plus two per matched pair.
    pub(super) matched: u64,
    /// Vertex visits plus candidate pairs examined.
    pub(super) work: u64,
    /// False if the plane was abandoned because its work passed the budget.
    pub(super) complete: bool,
    /// The prefilter skipped the plane (`matched` is 0).
    pub(super) skipped: bool,
}

/// Reusable per-thread memory of [`match_plane`].
#[derive(Default)]
pub(super) struct Scratch {
    /// Candidate graph in CSR form: positive-side vertices that have a
    /// candidate ("left"), and for each the negative-side slots ("right").
    adj_start: Vec<u32>,
    /// Right-hand slots of the candidate pairs.
    adj: Vec<u32>,
    /// Left vertex matched to each slot, [`NONE`] between calls.
    right_match: Vec<u32>,
    /// Hopcroft–Karp state.
    matching: MatchingScratch,
}

/// The matched-vertex count of one plane (Knodt §3.1, Alg. 2 lines 12–32):
/// one pass over the vertices counts the self-matches and collects the
/// candidate pairs across the plane through the grid (up to
/// [`MAX_CANDIDATES`] per vertex), then a maximum matching pairs them.
/// Gives up (`complete = false`) as soon as the work passes `budget`.
pub(super) fn match_plane(
    grid: &Grid,
    plane: Plane,
    delta: f64,
    budget: u64,
    sc: &mut Scratch,
) -> PlaneMatch {
    let slots = grid.pos.len();
    let mut work = slots as u64;
    if work > budget {
        return PlaneMatch {
            matched: 0,
            work: 0,
            complete: false,
            skipped: false,
        };
    }
    let mut matched = 0u64;
    sc.adj_start.clear();
    sc.adj.clear();
    sc.adj_start.push(0);
    for k in 0..slots {
        let pk = grid.pos[k];
        let sk = plane.signed_distance(pk);
        if sk.abs() < delta {
            matched += 1;
            continue;
        }
        // Only the positive side searches: every pair has one end there.
        // (Here |σ| ≥ δ, or σ is NaN.)
        if sk.is_nan() || sk < delta {
            continue;
        }
        let near = grid.near(reflect(pk, sk, plane.n));
        if near.is_empty() {
            continue;
        }
        let before = sc.adj.len();
        for &l in near {
            work += 1;
            let pl = grid.pos[l as usize];
            // Recomputed rather than stored: only candidates need it.
            let sl = plane.signed_distance(pl);
            if sl <= -delta
                && pair_error(
                    (grid.ids[k], pk, sk),
                    (grid.ids[l as usize], pl, sl),
                    plane.n,
                ) < delta
            {
                sc.adj.push(l);
                if sc.adj.len() - before == MAX_CANDIDATES {
                    break;
                }
            }
        }
        if sc.adj.len() > before {
            sc.adj_start.push(sc.adj.len() as u32);
        }
        if work > budget {
            return PlaneMatch {
                matched: 0,
                work,
                complete: false,
                skipped: false,
            };
        }
    }
    if sc.right_match.len() < slots {
        sc.right_match.resize(slots, NONE);
    }
    let pairs = max_matching(
        &sc.adj_start,
        &sc.adj,
        &mut sc.right_match,
        &mut sc.matching,
    );
    // Leave `right_match` all NONE for the next plane, touching only what
    // this one used.
    for &l in &sc.adj {
        sc.right_match[l as usize] = NONE;
    }
    matched += 2 * pairs;
    PlaneMatch {
        matched,
        work,
        complete: true,
        skipped: false,
    }
}

/// The prefilter's count for one plane (see
/// [`SymmetryOptions::min_weight`]; an estimate, not part of Alg. 2): of
/// `samples` slots spread evenly over all (slots are in cell order, so the
/// sample is spread over space), how many lie on the plane or have at least
/// one candidate partner on the other side. The matched vertices are a
/// subset of those, so the fraction estimates an upper bound of `s`.
/// Returns (count, work, complete) with work counted as in [`match_plane`].
fn sample_plane(
    grid: &Grid,
    plane: Plane,
    delta: f64,
    samples: usize,
    budget: u64,
) -> (u64, u64, bool) {
    let slots = grid.pos.len();
    let mut work = samples as u64;
    if work > budget {
        return (0, 0, false);
    }
    let mut hits = 0;
    for i in 0..samples {
        // Midpoints of `samples` equal strata (u128: the product can pass
        // u64 for huge inputs).
        let k = ((2 * i as u128 + 1) * slots as u128 / (2 * samples as u128)) as usize;
        let Some(&pk) = grid.pos.get(k) else {
            continue;
        };
        let sk = plane.signed_distance(pk);
        if sk.abs() < delta {
            hits += 1;
            continue;
        }
        let near = grid.near(reflect(pk, sk, plane.n));
        work += near.len() as u64;
        // Either side searches here: `side · σ ≥ δ` is the other side.
        let side = -sk.signum();
        let found = near.iter().any(|&l| {
            let pl = grid.pos[l as usize];
            let sl = plane.signed_distance(pl);
            side * sl >= delta
                && pair_error(
                    (grid.ids[k], pk, sk),
                    (grid.ids[l as usize], pl, sl),
                    plane.n,
                ) < delta
        });
        hits += u64::from(found);
        if work > budget {
            return (hits, work, false);
        }
    }
    (hits, work, true)
}

/// One plane's outcome: the prefilter when it is on and cheaper than the
/// full pass, then, unless it skips the plane, [`match_plane`] with what is
/// left of the budget.
pub(super) fn plane_outcome(
    grid: &Grid,
    plane: Plane,
    options: &SymmetryOptions,
    budget: u64,
    sc: &mut Scratch,
) -> PlaneMatch {
    let samples = options.samples as usize;
    let prefilter = options.min_weight > 0.0 && samples > 0 && samples < grid.pos.len();
    let mut spent = 0;
    if prefilter {
        let (hits, work, complete) = sample_plane(grid, plane, options.delta, samples, budget);
        if !complete {
            return PlaneMatch {
                matched: 0,
                work,
                complete: false,
                skipped: false,
            };
        }
        // Skip below half of `min_weight`: the margin that makes a miss
        // of a plane at `min_weight` a ~4σ event at the default sample.
        if 2.0 * (hits as f64) < options.min_weight * samples as f64 {
            return PlaneMatch {
                matched: 0,
                work,
                complete: true,
                skipped: true,
            };
        }
        spent = work;
    }
    let mut m = match_plane(grid, plane, options.delta, budget - spent, sc);
    m.work += spent;
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terms::symmetry::test_support::{brute_matched, opts, Rng};

    /// A vertex closer than δ to the plane matches itself; at exactly δ it
    /// does not (strict, as Alg. 2 line 15), and then needs a partner.
    #[test]
    fn vertex_within_delta_of_the_plane_matches_itself() {
        let plane = Plane {
            n: DVec3::X,
            c: 0.0,
        };
        let delta = 0.125; // exact in binary, so σ = δ is exact
        let points = [
            DVec3::new(0.1, 0.0, 0.0),   // |σ| < δ: self
            DVec3::new(-0.1, 5.0, 0.0),  // self
            DVec3::new(0.125, 9.0, 0.0), // σ = δ: positive side
            DVec3::new(3.0, 0.0, 0.0),   // no partner
        ];
        let grid = Grid::new(&points, delta);
        let m = match_plane(&grid, plane, delta, u64::MAX, &mut Scratch::default());
        assert_eq!(m.matched, 2);
        assert!(m.complete);
        // Give 2 a partner at σ = −0.2, mirror error 0.075 < δ: pair (+2).
        let mut more = points.to_vec();
        more.push(DVec3::new(-0.2, 9.0, 0.0));
        let grid = Grid::new(&more, delta);
        let m = match_plane(&grid, plane, delta, u64::MAX, &mut Scratch::default());
        assert_eq!(m.matched, 4);
    }

    /// Up to [`MAX_CANDIDATES`] vertices crowding one mirror image, the count
    /// is exact; beyond, it is a lower bound and memory stays bounded.
    #[test]
    fn dense_clusters_keep_memory_bounded() {
        let plane = Plane {
            n: DVec3::X,
            c: 0.0,
        };
        let cluster = |n: usize| -> Vec<DVec3> {
            let mut points = vec![DVec3::new(1.0, 0.0, 0.0); n];
            points.extend(vec![DVec3::new(-1.0, 0.0, 0.0); n]);
            points
        };
        let mut sc = Scratch::default();
        let exact = cluster(MAX_CANDIDATES);
        let grid = Grid::new(&exact, 0.1);
        let m = match_plane(&grid, plane, 0.1, u64::MAX, &mut sc);
        assert_eq!(m.matched, 2 * MAX_CANDIDATES as u64);
        let dense = cluster(3 * MAX_CANDIDATES);
        let grid = Grid::new(&dense, 0.1);
        let m = match_plane(&grid, plane, 0.1, u64::MAX, &mut sc);
        assert!(m.matched >= 2 * MAX_CANDIDATES as u64);
        assert!(m.matched <= brute_matched(&dense, plane, 0.1));
        assert!(sc.adj.len() <= 3 * MAX_CANDIDATES * MAX_CANDIDATES);
    }

    /// Random point sets near a random plane, with mirrored copies jittered
    /// by up to 1.5 δ so that candidate clusters overlap (some duplicated,
    /// some far from the origin): the grid matcher equals the O(|V|²) brute
    /// force with Kuhn's matching.
    #[test]
    fn grid_matcher_equals_brute_force_on_random_point_sets() {
        let mut rng = Rng(0xD1B5_4A32_D192_ED03);
        let mut scratch = Scratch::default();
        for case in 0..400 {
            let delta = [0.05, 0.1, 0.3][rng.below(3)];
            let n = rng.direction();
            let plane = Plane {
                n,
                c: rng.range(-0.5, 0.5),
            };
            let mut points = Vec::new();
            let count = 2 + rng.below(14);
            while points.len() < count {
                let p = DVec3::new(rng.unit(), rng.unit(), rng.unit()) - 0.5;
                points.push(p);
                match rng.below(3) {
                    0 => {
                        let s = plane.signed_distance(p);
                        let jitter = rng.direction() * rng.range(0.0, 1.5 * delta);
                        points.push(reflect(p, s, n) + jitter);
                    }
                    1 => {
                        let s = plane.signed_distance(p);
                        points.push(p - n * s + rng.direction() * rng.range(0.0, delta));
                    }
                    _ => {}
                }
            }
            if rng.below(10) == 0 {
                points.push(DVec3::NAN);
            }
            if rng.below(5) == 0 {
                // Duplicated vertices, as at seams.
                let i = rng.below(points.len());
                points.push(points[i]);
            }
            let mut plane = plane;
            if rng.below(4) == 0 {
                // Far from the origin: the rounding margin must scale.
                let t = rng.direction() * 1e6;
                points.iter_mut().for_each(|p| *p += t);
                plane.c += n.dot(t);
            }
            let grid = Grid::new(&points, delta);
            let got = match_plane(&grid, plane, delta, u64::MAX, &mut scratch);
            let want = brute_matched(&points, plane, delta);
            assert_eq!(got.matched, want, "case {case}");
            assert!(got.complete);
        }
    }

    /// Morton codes interleave x, y, z bits from the lowest, relative to the
    /// origin, and wrap beyond `2^bits` cells.
    #[test]
    fn morton_interleaves_axis_bits() {
        let o = [10, -5, 0];
        assert_eq!(morton([11, -5, 0], o, 8), 0b001);
        assert_eq!(morton([10, -4, 0], o, 8), 0b010);
        assert_eq!(morton([10, -5, 1], o, 8), 0b100);
        // x = 3 → bits 0 and 3; z = 2 → bit 5.
        assert_eq!(morton([13, -5, 2], o, 8), 0b101001);
        assert_eq!(morton([265, 250, 255], o, 8), (1 << 24) - 1);
        // 256 cells away wraps to the same code.
        assert_eq!(morton([266, -5, 0], o, 8), morton([10, -5, 0], o, 8));
    }

    /// The prefilter on a hand-counted case.
    ///
    /// ```text
    ///   0   1   2   3   4   5 | 6   7      points on the x axis, δ = 1/8;
    ///                         5.5          plane x = 5.5
    /// ```
    ///
    /// Samples 4 of 8 take slots 1, 3, 5, 7 (x = 1, 3, 5, 7): 5 ↔ 6 and
    /// 7 ↔ 4 have partners, 1 and 3 do not (9, 10 are empty): 2 hits, work
    /// 4 visits + 2 candidates. The exact weight is 4 / 8 (5–6, 4–7).
    #[test]
    fn prefilter_counts_sampled_vertices_with_a_candidate() {
        let points: Vec<DVec3> = (0..8).map(|x| DVec3::new(x as f64, 0.0, 0.0)).collect();
        let grid = Grid::new(&points, 0.125);
        let plane = Plane {
            n: DVec3::X,
            c: 5.5,
        };
        assert_eq!(sample_plane(&grid, plane, 0.125, 4, u64::MAX), (2, 6, true));
        assert_eq!(sample_plane(&grid, plane, 0.125, 4, 5), (2, 6, false));
        let options = |min_weight| SymmetryOptions {
            delta: 0.125,
            min_weight,
            samples: 4,
            ..opts(0.125)
        };
        let mut sc = Scratch::default();
        // 2 of 4 sampled: kept for min_weight ≤ 1, then exact: 8 visits,
        // 6 and 7 find 5 and 4 (2 candidates), 4 matched.
        let kept = plane_outcome(&grid, plane, &options(1.0), u64::MAX, &mut sc);
        assert_eq!(
            (kept.matched, kept.skipped, kept.work),
            (4, false, 6 + 8 + 2)
        );
        let skipped = plane_outcome(&grid, plane, &options(1.01), u64::MAX, &mut sc);
        assert_eq!(
            (skipped.matched, skipped.skipped, skipped.work),
            (0, true, 6)
        );
    }
}
