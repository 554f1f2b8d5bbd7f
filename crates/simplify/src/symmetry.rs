//! Per-edge soft symmetry weights (Knodt 2024 §3.1 "Soft Symmetry",
//! Appendix Alg. 2).
//!
//! Every edge `e = (e0, e1)` spans a plane: it contains the edge direction
//! `d = normalize(e0 − e1)` and the mean normal of the edge's faces, so its
//! normal is `n⊥ = normalize(n(f0) + n(f1)) × d` for an edge of two faces and
//! `n⊥ = n(f0) × d` for a border edge (Alg. 2 lines 4–8). The edge's weight
//! `s ∈ [0, 1]` is the fraction of all vertices that have a mirror partner
//! across that plane (Knodt §3.1). It feeds the tangent quadrics of
//! [`crate::tangent`] as `w = max(dihedral/π, λ_sym·s, λ_joint·d, 0.01)`
//! (Eq. 2), so edges on a symmetry plane of the model, and edges equidistant
//! from it, keep their place longer.
//!
//! # What counts as matched
//!
//! With `σ(v) = n⊥·(v − e0)` the signed distance of `v` to the plane:
//!
//! - a vertex with `|σ(v)| < δ` lies on the plane and matches itself
//!   (Alg. 2 line 15, which forgets the absolute value);
//! - the others form a bipartite graph between the two sides, `σ ≥ δ` and
//!   `σ ≤ −δ`, with an edge between `a` and `b` when the mirror image of one
//!   is within `δ` of the other (Alg. 2 line 27, which writes a norm of a
//!   sum of squares; we mean the Euclidean distance);
//! - `s = (self-matched + 2 · ν) / |V|`, where `ν` is the size of a
//!   *maximum* matching of that graph: each vertex is used at most once, and
//!   as many vertices as possible have a partner.
//!
//! Alg. 2 matches greedily (pop the vertex farthest from the plane, take the
//! first candidate found). A greedy matching depends on the order it visits
//! candidates and can leave up to half of a cluster unmatched (see the test
//! `maximum_matching_beats_nearest_first_greedy`). The size of a maximum
//! matching is unique, so `s` needs no tie-breaking at all: any maximum
//! matching gives the same count, whatever the visiting order or thread
//! count. We find one with Hopcroft–Karp after a greedy start; the candidate
//! graph is almost always a set of disjoint pairs, which the greedy start
//! already matches, so the augmenting phase usually does nothing.
//!
//! The mirror distance of a pair is computed from its lower-numbered vertex
//! (`|mirror(a) − b|` for `a < b`), so the candidate set does not depend on
//! which side of the plane is called positive, or on which side the search
//! starts from, down to the last bit.
//!
//! # Cost
//!
//! Alg. 2 is `O(|V|·|E|)` (plus a sort per edge). Here:
//!
//! - edges whose planes coincide (within `plane_tolerance · δ` on each
//!   component of the unit normal and on the offset, up to sign) share one
//!   computation: on models with mirror symmetry or regular structure many
//!   edges lie in the same plane (every edge along a symmetry line);
//! - each plane is `O(|V|)` instead of a sort per plane: the vertices sit in
//!   a hash grid built once (cell `4δ`, each vertex listed in every cell its
//!   `δ`-box overlaps), and each vertex on the positive side is mirrored and
//!   looks up the one cell its image falls in, mostly answered by a bit
//!   filter that stays in cache;
//! - `max_work` caps the vertex visits plus candidate pairs examined; planes
//!   are computed largest group first, and once the cap is reached the
//!   remaining edges get weight 0 and the result says `truncated`;
//! - optionally (`min_weight > 0`, off by default), a prefilter tries each
//!   plane on a fixed sample of vertices first and skips the planes whose
//!   weight is clearly below `min_weight`, which only matters when
//!   `λ_sym · s` beats the other terms of `w`: `O(samples)` instead of
//!   `O(|V|)` for most planes.
//!
//! Measured (2 cores, δ = 1e-3, generated meshes; see the ignored test
//! `symmetry_timing_on_generated_meshes`): about 4–7 ns per unit of work,
//! i.e. per vertex and plane. A 20k-vertex height field with 60k distinct
//! planes takes 5 s exact, 1.2 s with the prefilter at 0.05; 100k vertices
//! reach the default cap (2·10⁹, 10–14 s) after ~18k planes.
//!
//! Planes are computed in parallel in batches of fixed size
//! ([`BATCH`]); which planes are kept depends only on the plane order and
//! each plane's own work, never on the thread count.

use glam::DVec3;
use rayon::prelude::*;

/// Marks an unused entry in the grid's hash table and in matching scratch.
const NONE: u32 = u32::MAX;

/// Planes computed per parallel batch. Fixed (not derived from the thread
/// count) so that the work spent past the cap, reported in
/// [`SymmetryResult::work`], does not depend on the machine either.
const BATCH: usize = 64;

/// Below this length the sum `n(f0) + n(f1)` of an edge's two unit normals
/// has no direction: the two faces fold back onto each other (dihedral
/// angle 180°), and the halfway vector of Alg. 2 line 6 is noise.
const MIN_HALFWAY: f64 = 1e-9;

/// Below this length `n × d` (unit vectors) has no direction: the face
/// normal runs along the edge, i.e. the face is degenerate.
const MIN_SINE: f64 = 1e-9;

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

/// Shift of the plane-grouping cells, as a fraction of a cell: 2 − φ, far
/// from every fraction with a small denominator, so that no regular value
/// (0, k/10, k/2^m of a cell) lands within rounding of a cell boundary.
const KEY_SHIFT: f64 = 0.381_966_011_250_105_1;

/// The faces on one edge, as the unit normals Alg. 2 needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum EdgeNormals {
    /// No face uses the edge (a loose or virtual edge): no plane, weight 0.
    NoFace,
    /// A border edge: the normal of its only face (Alg. 2 line 8).
    Border(DVec3),
    /// A manifold edge: the normals of its two faces (Alg. 2 line 6).
    Manifold(DVec3, DVec3),
    /// Three or more faces: Alg. 2 line 10 gives weight 0.
    NonManifold,
}

impl EdgeNormals {
    /// Classifies an edge by the normals of the faces that use it as a side,
    /// as [`crate::tangent`] collects them: 0, 1, 2 or more faces.
    pub(crate) fn from_faces(normals: &[DVec3]) -> Self {
        match normals {
            [] => Self::NoFace,
            [n] => Self::Border(*n),
            [a, b] => Self::Manifold(*a, *b),
            _ => Self::NonManifold,
        }
    }
}

/// The mesh as Alg. 2 reads it (Knodt §3.1).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SymmetryInput<'a> {
    /// Vertex positions, normalized to a unit bounding-box diagonal (so that
    /// `δ` is relative to the model's size). Non-finite positions count in
    /// `|V|` but never match.
    pub positions: &'a [DVec3],
    /// Edges as vertex pairs; an edge with an endpoint out of range gets 0.
    pub edges: &'a [[u32; 2]],
    /// Per edge, its faces' unit normals; missing entries count as
    /// [`EdgeNormals::NoFace`].
    pub edge_normals: &'a [EdgeNormals],
}

/// Parameters of the matching (Knodt §3.1: `ϵ_sym`; Alg. 2: `δ`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SymmetryOptions {
    /// Matching distance `δ` in normalized units (fraction of the diagonal).
    /// Default 1e-3: below the spacing of vertices on a 100k-vertex model,
    /// above rounding and modelling noise of mirrored CAD and sculpts.
    /// A non-positive or non-finite `δ` matches nothing: all weights 0.
    pub delta: f64,
    /// Edges whose planes agree within `plane_tolerance · δ` (per component
    /// of the unit normal and on the offset, up to sign) share one plane,
    /// that of their lowest-numbered edge. Default 0.01: the mirror images of
    /// points in the unit-diagonal box then move by under 0.1 δ, far less
    /// than `δ` itself, while edges that differ only by rounding share a
    /// plane. 0 (or non-finite) shares only bit-identical planes, which makes
    /// the result equal to computing every edge on its own.
    pub plane_tolerance: f64,
    /// Cap on the work: vertex visits plus candidate pairs examined, summed
    /// over the planes computed (`|V|` plus a few per vertex for each plane).
    /// Default 2·10⁹, about 10 s on two cores; on a 100k-vertex model with
    /// no shared planes that is ~20k planes. Planes past the cap get
    /// weight 0.
    pub max_work: u64,
    /// Prefilter (not in Knodt): when positive, each plane is first tried
    /// on [`samples`](Self::samples) vertices spread over the model, and
    /// skipped (weight 0) if fewer than `min_weight / 2` of them are on the
    /// plane or have any mirror candidate. Only planes likely to reach
    /// `min_weight` then pay the full `O(|V|)`. Weights below what
    /// `λ_sym · s` needs to beat the floor 0.01 of Eq. 2 change nothing, so
    /// `0.01 / λ_sym` (or a few times it) loses nothing that matters.
    /// Default 0: off, every plane exact.
    pub min_weight: f64,
    /// Vertices tried per plane by the prefilter. Default 1024: a plane at
    /// `s⁺ = min_weight` is skipped with probability ≈ 1e-4 at
    /// `min_weight = 0.05` (binomial tail below half the mean), a plane at
    /// twice that, ≈ 1e-14.
    pub samples: u32,
}

impl Default for SymmetryOptions {
    fn default() -> Self {
        Self {
            delta: 1e-3,
            plane_tolerance: 0.01,
            max_work: 2_000_000_000,
            min_weight: 0.0,
            samples: 1024,
        }
    }
}

/// Per-edge weights and what they cost (house habit 2: report how far the
/// computation got).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SymmetryResult {
    /// `s ∈ [0, 1]` per input edge (Knodt §3.1); 0 for edges without a plane
    /// (no face, non-manifold, degenerate) and for edges past the cap.
    pub weights: Vec<f64>,
    /// Vertex visits plus candidate pairs examined, over all planes computed,
    /// including those of the last batch that were discarded for the cap
    /// (so it can exceed `max_work` by up to one batch of planes).
    pub work: u64,
    /// Some edges with a plane got weight 0 because `max_work` ran out (or,
    /// beyond 2²⁹ vertices, all edges: the grid's indices are 32-bit).
    pub truncated: bool,
    /// Distinct planes after grouping.
    pub planes: usize,
    /// Planes whose weights were kept, exact or skipped by the prefilter
    /// (the rest were past the cap).
    pub planes_computed: usize,
    /// Of those, planes the prefilter skipped (weight 0).
    pub planes_skipped: usize,
}

/// A plane `{x : n·x = c}` with unit normal `n` (Alg. 2's local frame: `x`
/// axis `n⊥`, origin `e0`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Plane {
    /// Unit normal `n⊥`.
    n: DVec3,
    /// Offset `n⊥ · e0`.
    c: f64,
}

impl Plane {
    /// Signed distance `σ(p) = n·p − c` (Alg. 2 line 14, `v_local[0]`).
    fn signed_distance(&self, p: DVec3) -> f64 {
        self.n.dot(p) - self.c
    }

    /// The same plane with its orientation fixed: the first component of `n`
    /// with magnitude above 0.55 is made positive. A unit vector always has
    /// one (its largest is ≥ 1/√3 ≈ 0.577), and 0.55 is not a value that
    /// normals of regular models take (0, ½, 1/√2, 0.6, 0.8, …), so nearly
    /// equal planes get the same orientation. Negation is exact, so `σ`
    /// only changes sign and mirror images are bit-identical.
    fn canonical(self) -> Self {
        let pick = self
            .n
            .to_array()
            .into_iter()
            .find(|x| x.abs() > 0.55)
            .unwrap_or(1.0);
        if pick < 0.0 {
            Self {
                n: -self.n,
                c: -self.c,
            }
        } else {
            self
        }
    }

    /// Grouping key: the canonical plane quantized to cells of `cell`
    /// (`plane_tolerance · δ`), or its exact bits when `cell` is not a
    /// positive finite number. `+ 0.0` maps −0.0 to +0.0 so that the two
    /// zeros share a key.
    ///
    /// The cells are shifted by [`KEY_SHIFT`] of a cell: unshifted, the
    /// values regular models are made of (0 ± rounding noise in a normal,
    /// offsets 0.1, 0.2, … when `cell` divides them) sit exactly on cell
    /// boundaries, and rounding scatters one plane over two keys.
    fn key(&self, cell: f64) -> [u64; 4] {
        let v = [self.n.x, self.n.y, self.n.z, self.c];
        if cell > 0.0 && cell.is_finite() {
            // Saturates far away; far-off planes only share less.
            v.map(|x| floor_i64(x / cell + KEY_SHIFT) as u64)
        } else {
            v.map(|x| (x + 0.0).to_bits())
        }
    }
}

/// The mirror image of `p` (at signed distance `sigma`) across the plane of
/// normal `n`: `p − 2σn`.
fn reflect(p: DVec3, sigma: f64, n: DVec3) -> DVec3 {
    p - n * (2.0 * sigma)
}

/// The mirror distance of vertices `a` and `b` (ids, positions, signed
/// distances), computed from the lower id: `|mirror(a) − b|` if `a < b`.
/// Reflection is an isometry, so mathematically either end gives the same
/// value; fixing the end makes it bit-identical for every caller.
fn pair_error(a: (u32, DVec3, f64), b: (u32, DVec3, f64), n: DVec3) -> f64 {
    let (lo, hi) = if a.0 < b.0 { (a, b) } else { (b, a) };
    (reflect(lo.1, lo.2, n) - hi.1).length()
}

/// The plane of edge `(p0, p1)` with the given faces (Alg. 2 lines 4–11),
/// or `None` where Alg. 2 gives weight 0 (no face, non-manifold) and where
/// the plane is undefined (zero-length edge, faces folded onto each other,
/// a face normal along the edge, non-finite input).
fn edge_plane(p0: DVec3, p1: DVec3, faces: EdgeNormals) -> Option<Plane> {
    let d = p0 - p1;
    let len = d.length();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let d = d / len;
    let axis = match faces {
        EdgeNormals::Manifold(a, b) => {
            // Normalized so that non-unit input normals still give the
            // halfway direction; a zero or non-finite one drops out (the
            // edge then spans the plane of its other face, as a border).
            let h = a.normalize_or_zero() + b.normalize_or_zero();
            let hl = h.length();
            if hl.is_nan() || hl <= MIN_HALFWAY {
                return None;
            }
            h / hl
        }
        EdgeNormals::Border(a) => a.normalize_or_zero(),
        EdgeNormals::NoFace | EdgeNormals::NonManifold => return None,
    };
    let t = axis.cross(d);
    let tl = t.length();
    // A zero or non-finite normal gives tl = 0 or NaN.
    if tl.is_nan() || tl <= MIN_SINE {
        return None;
    }
    let n = t / tl;
    let c = n.dot(p0);
    c.is_finite().then_some(Plane { n, c })
}

/// `⌊x⌋` as an integer, saturating far away and mapping NaN to 0 (which
/// only makes distant points share a cell; the exact distance test sorts
/// them out). Inline instead of `f64::floor`, which is a libm call on the
/// baseline x86-64 target and took a tenth of the time.
fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

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
struct Grid {
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
    fn new(positions: &[DVec3], delta: f64) -> Self {
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
struct PlaneMatch {
    /// Matched vertices: self-matched plus two per matched pair.
    matched: u64,
    /// Vertex visits plus candidate pairs examined.
    work: u64,
    /// False if the plane was abandoned because its work passed the budget.
    complete: bool,
    /// The prefilter skipped the plane (`matched` is 0).
    skipped: bool,
}

/// Reusable per-thread memory of [`match_plane`].
#[derive(Default)]
struct Scratch {
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
fn match_plane(grid: &Grid, plane: Plane, delta: f64, budget: u64, sc: &mut Scratch) -> PlaneMatch {
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
fn plane_outcome(
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

/// Scratch of [`max_matching`].
#[derive(Default)]
struct MatchingScratch {
    /// Right vertex matched to each left vertex, or [`NONE`].
    left_match: Vec<u32>,
    /// BFS layer of each left vertex ([`NONE`] = unreached or dead).
    layer: Vec<u32>,
    /// Next adjacency position each left vertex's DFS will try.
    next: Vec<u32>,
    /// BFS queue.
    queue: Vec<u32>,
    /// DFS path (left vertices), kept on the heap: components can be long
    /// chains, too deep for recursion.
    stack: Vec<u32>,
}

/// Size of a maximum matching of the bipartite candidate graph (the pairs
/// counted twice by Alg. 2 line 28), by Hopcroft–Karp, `O(E √V)`.
///
/// Left vertices are `0..adj_start.len() − 1`, with right neighbours
/// `adj[adj_start[u]..adj_start[u + 1]]` indexing `right_match`, which must
/// be all [`NONE`] on entry (the caller resets what it used). The count is
/// the same for every maximum matching, so the order of the search only
/// affects speed, never the result.
fn max_matching(
    adj_start: &[u32],
    adj: &[u32],
    right_match: &mut [u32],
    m: &mut MatchingScratch,
) -> u64 {
    let left = adj_start.len().saturating_sub(1);
    let nbrs = |u: usize| adj_start[u] as usize..adj_start[u + 1] as usize;
    m.left_match.clear();
    m.left_match.resize(left, NONE);
    let mut size = 0u64;
    // Greedy start: on a symmetry plane nearly every component is a single
    // pair, which this matches outright.
    for u in 0..left {
        if let Some(&v) = adj[nbrs(u)]
            .iter()
            .find(|&&v| right_match[v as usize] == NONE)
        {
            right_match[v as usize] = u as u32;
            m.left_match[u] = v;
            size += 1;
        }
    }
    loop {
        // BFS from the free left vertices along alternating paths; stop at
        // the layer where a free right vertex first appears.
        m.queue.clear();
        m.layer.clear();
        for u in 0..left {
            if m.left_match[u] == NONE {
                m.layer.push(0);
                m.queue.push(u as u32);
            } else {
                m.layer.push(NONE);
            }
        }
        let mut found = false;
        let mut head = 0;
        while head < m.queue.len() {
            let u = m.queue[head] as usize;
            head += 1;
            for &v in &adj[nbrs(u)] {
                let w = right_match[v as usize];
                if w == NONE {
                    found = true;
                } else if m.layer[w as usize] == NONE {
                    m.layer[w as usize] = m.layer[u] + 1;
                    if !found {
                        m.queue.push(w);
                    }
                }
            }
        }
        if !found {
            return size;
        }
        // DFS from each free left vertex along increasing layers; augment
        // along the first path that ends at a free right vertex.
        m.next.clear();
        m.next.extend_from_slice(&adj_start[..left]);
        for root in 0..left {
            if m.left_match[root] != NONE {
                continue;
            }
            m.stack.clear();
            m.stack.push(root as u32);
            while let Some(&u) = m.stack.last() {
                let u = u as usize;
                if m.next[u] == adj_start[u + 1] {
                    // Dead end for the rest of this phase.
                    m.layer[u] = NONE;
                    m.stack.pop();
                    continue;
                }
                let v = adj[m.next[u] as usize];
                m.next[u] += 1;
                let w = right_match[v as usize];
                if w == NONE {
                    // Flip the path: each left vertex on the stack takes
                    // the right vertex its successor was matched to.
                    let mut v = v;
                    for &p in m.stack.iter().rev() {
                        let prev = m.left_match[p as usize];
                        m.left_match[p as usize] = v;
                        right_match[v as usize] = p;
                        v = prev;
                    }
                    size += 1;
                    break;
                }
                let (lu, lw) = (m.layer[u], m.layer[w as usize]);
                if lw != NONE && lu != NONE && lw == lu + 1 {
                    m.stack.push(w);
                }
            }
        }
    }
}

/// Edges sharing one plane (Knodt §3.1: each shares the same `s`).
#[derive(Clone, Debug, PartialEq)]
struct PlaneGroup {
    /// The plane of the group's lowest-numbered edge, canonically oriented.
    plane: Plane,
    /// The group's edges, ascending.
    edges: Vec<u32>,
}

/// The distinct planes of the edges (Alg. 2 lines 3–11 for every edge, then
/// grouped by [`Plane::key`]), in the order they are computed: larger
/// groups first (they carry more edges per unit of work, and on real models
/// the planes shared by many edges are the symmetry planes), then by lowest
/// edge.
fn plane_groups(input: &SymmetryInput<'_>, options: &SymmetryOptions) -> Vec<PlaneGroup> {
    let cell = options.plane_tolerance * options.delta;
    let mut keyed: Vec<([u64; 4], u32, Plane)> = (0..input.edges.len())
        .into_par_iter()
        .filter_map(|e| {
            let [a, b] = input.edges[e];
            let p0 = *input.positions.get(a as usize)?;
            let p1 = *input.positions.get(b as usize)?;
            let faces = input
                .edge_normals
                .get(e)
                .copied()
                .unwrap_or(EdgeNormals::NoFace);
            let plane = edge_plane(p0, p1, faces)?.canonical();
            Some((plane.key(cell), u32::try_from(e).ok()?, plane))
        })
        .collect();
    keyed.par_sort_unstable_by(|x, y| x.0.cmp(&y.0).then(x.1.cmp(&y.1)));
    let mut groups: Vec<PlaneGroup> = Vec::new();
    let mut last_key = None;
    for (key, e, plane) in keyed {
        match groups.last_mut() {
            Some(g) if last_key == Some(key) => g.edges.push(e),
            _ => groups.push(PlaneGroup {
                plane,
                edges: vec![e],
            }),
        }
        last_key = Some(key);
    }
    groups.sort_by(|a, b| {
        b.edges
            .len()
            .cmp(&a.edges.len())
            .then(a.edges[0].cmp(&b.edges[0]))
    });
    groups
}

/// Per-edge soft symmetry weights `s ∈ [0, 1]` (Knodt 2024 §3.1, Alg. 2),
/// with edges of one plane computed once and the total work capped by
/// `options.max_work`. See the module documentation for the matching rule
/// and the cost.
///
/// Deterministic: weights, work and truncation do not depend on the number
/// of rayon threads.
pub(crate) fn edge_symmetry_weights(
    input: &SymmetryInput<'_>,
    options: &SymmetryOptions,
) -> SymmetryResult {
    let mut result = SymmetryResult {
        weights: vec![0.0; input.edges.len()],
        ..SymmetryResult::default()
    };
    let delta = options.delta;
    if !(delta > 0.0 && delta.is_finite()) || input.positions.is_empty() {
        return result;
    }
    // The grid numbers its ≤ 8 listings per vertex with u32.
    if input.positions.len() > (u32::MAX / 8) as usize {
        result.truncated = true;
        return result;
    }
    let groups = plane_groups(input, options);
    result.planes = groups.len();
    let grid = Grid::new(input.positions, delta);
    let vertices = input.positions.len() as f64;
    // Work of the planes kept so far; a plane is kept iff every plane
    // before it was kept and this sum stays within the cap, which depends
    // only on the group order and each plane's own work.
    let mut kept_work = 0u64;
    for batch in groups.chunks(BATCH) {
        // A plane that alone would pass what is left cannot be kept, so it
        // may stop early; the budget is fixed per batch, hence the same
        // whatever order the threads run in.
        let budget = options.max_work.saturating_sub(kept_work);
        let outcomes: Vec<PlaneMatch> = batch
            .par_iter()
            .map_init(Scratch::default, |sc, g| {
                plane_outcome(&grid, g.plane, options, budget, sc)
            })
            .collect();
        for (g, m) in batch.iter().zip(outcomes) {
            result.work = result.work.saturating_add(m.work);
            if result.truncated {
                continue;
            }
            let total = kept_work.saturating_add(m.work);
            if !m.complete || total > options.max_work {
                result.truncated = true;
                continue;
            }
            kept_work = total;
            result.planes_computed += 1;
            result.planes_skipped += usize::from(m.skipped);
            let s = (m.matched as f64 / vertices).clamp(0.0, 1.0);
            for &e in &g.edges {
                result.weights[e as usize] = s;
            }
        }
        if result.truncated {
            break;
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tiny xorshift64* generator for seeded property tests (no `rand`).
    struct Rng(u64);

    impl Rng {
        /// Next 64 random bits.
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
        /// Uniform in [0, 1).
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
        /// Uniform in [lo, hi).
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.unit()
        }
        /// Uniform in 0..n.
        fn below(&mut self, n: usize) -> usize {
            (self.next() % n as u64) as usize
        }
        /// A random unit vector.
        fn direction(&mut self) -> DVec3 {
            loop {
                let v = DVec3::new(
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                );
                let l = v.length();
                if l > 0.1 && l <= 1.0 {
                    return v / l;
                }
            }
        }
    }

    /// A mesh as plain arrays, with edges and per-edge face normals derived
    /// from its faces (each polygon's normal by Newell's method).
    struct TestMesh {
        positions: Vec<DVec3>,
        edges: Vec<[u32; 2]>,
        normals: Vec<EdgeNormals>,
    }

    impl TestMesh {
        /// Builds the edge list (in order of first appearance) and each
        /// edge's faces from polygon faces.
        fn new(positions: Vec<DVec3>, faces: &[Vec<u32>]) -> Self {
            let mut index = std::collections::HashMap::new();
            let mut edges = Vec::new();
            let mut face_normals: Vec<Vec<DVec3>> = Vec::new();
            for f in faces {
                let mut n = DVec3::ZERO;
                for i in 0..f.len() {
                    let a = positions[f[i] as usize];
                    let b = positions[f[(i + 1) % f.len()] as usize];
                    n += a.cross(b);
                }
                let n = n.normalize();
                for i in 0..f.len() {
                    let (a, b) = (f[i], f[(i + 1) % f.len()]);
                    let e = *index.entry((a.min(b), a.max(b))).or_insert_with(|| {
                        edges.push([a, b]);
                        face_normals.push(Vec::new());
                        edges.len() - 1
                    });
                    face_normals[e].push(n);
                }
            }
            let normals = face_normals
                .iter()
                .map(|n| EdgeNormals::from_faces(n))
                .collect();
            Self {
                positions,
                edges,
                normals,
            }
        }

        /// The input view of this mesh.
        fn input(&self) -> SymmetryInput<'_> {
            SymmetryInput {
                positions: &self.positions,
                edges: &self.edges,
                edge_normals: &self.normals,
            }
        }

        /// Index of the edge between vertices `a` and `b`.
        fn edge(&self, a: u32, b: u32) -> usize {
            self.edges
                .iter()
                .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
                .unwrap()
        }
    }

    /// A flat grid of quads in z = 0, `nx × ny` vertices at spacing 1 with
    /// x running over `x0, x0 + 1, …`; vertex `(i, j)` is `j · nx + i`.
    fn flat_grid(nx: u32, ny: u32, x0: f64) -> TestMesh {
        let mut positions = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                positions.push(DVec3::new(x0 + i as f64, j as f64, 0.0));
            }
        }
        let mut faces = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let v = j * nx + i;
                faces.push(vec![v, v + 1, v + nx + 1, v + nx]);
            }
        }
        TestMesh::new(positions, &faces)
    }

    /// Options with a given `δ` and no cap.
    fn opts(delta: f64) -> SymmetryOptions {
        SymmetryOptions {
            delta,
            max_work: u64::MAX,
            ..SymmetryOptions::default()
        }
    }

    /// Reference: every edge on its own, every vertex pair examined, and the
    /// maximum matching by Kuhn's algorithm. Shares with the fast path only
    /// the formulas ([`edge_plane`], [`Plane::signed_distance`],
    /// [`pair_error`]), each tested by hand below.
    fn brute_weights(input: &SymmetryInput<'_>, delta: f64) -> Vec<f64> {
        (0..input.edges.len())
            .map(|e| {
                let [a, b] = input.edges[e];
                let (Some(&p0), Some(&p1)) = (
                    input.positions.get(a as usize),
                    input.positions.get(b as usize),
                ) else {
                    return 0.0;
                };
                let faces = input
                    .edge_normals
                    .get(e)
                    .copied()
                    .unwrap_or(EdgeNormals::NoFace);
                match edge_plane(p0, p1, faces) {
                    Some(plane) if delta > 0.0 && delta.is_finite() => {
                        brute_matched(input.positions, plane, delta) as f64
                            / input.positions.len() as f64
                    }
                    _ => 0.0,
                }
            })
            .collect()
    }

    /// Reference matched count of one plane: O(|V|²) candidate pairs, then
    /// a maximum matching by Kuhn's algorithm.
    fn brute_matched(positions: &[DVec3], plane: Plane, delta: f64) -> u64 {
        let sigma: Vec<f64> = positions
            .iter()
            .map(|&p| plane.signed_distance(p))
            .collect();
        let on_plane = positions
            .iter()
            .zip(&sigma)
            .filter(|(p, s)| p.is_finite() && s.abs() < delta)
            .count() as u64;
        let side = |sign: f64| -> Vec<usize> {
            (0..positions.len())
                .filter(|&i| positions[i].is_finite() && sign * sigma[i] >= delta)
                .collect()
        };
        let (pos, neg) = (side(1.0), side(-1.0));
        let adj: Vec<Vec<usize>> = pos
            .iter()
            .map(|&a| {
                (0..neg.len())
                    .filter(|&j| {
                        let b = neg[j];
                        pair_error(
                            (a as u32, positions[a], sigma[a]),
                            (b as u32, positions[b], sigma[b]),
                            plane.n,
                        ) < delta
                    })
                    .collect()
            })
            .collect();
        on_plane + 2 * kuhn_matching(&adj, neg.len())
    }

    /// Maximum matching by Kuhn's algorithm: for each left vertex, look
    /// for an augmenting path by recursive search (Berge: none left means
    /// maximum). The textbook method, independent of [`max_matching`].
    fn kuhn_matching(adj: &[Vec<usize>], right: usize) -> u64 {
        fn augment(u: usize, adj: &[Vec<usize>], seen: &mut [bool], owner: &mut [usize]) -> bool {
            for &v in &adj[u] {
                if !seen[v] {
                    seen[v] = true;
                    if owner[v] == usize::MAX || augment(owner[v], adj, seen, owner) {
                        owner[v] = u;
                        return true;
                    }
                }
            }
            false
        }
        let mut owner = vec![usize::MAX; right];
        (0..adj.len())
            .filter(|&u| augment(u, adj, &mut vec![false; right], &mut owner))
            .count() as u64
    }

    /// Maximum matching by trying, for each left vertex in turn, to leave it
    /// unmatched or to match it to each free neighbour (`used` is a bitmask
    /// of right vertices). Exponential; for graphs of a few dozen edges.
    fn exhaustive_matching(adj: &[Vec<usize>], u: usize, used: u64) -> u64 {
        if u == adj.len() {
            return 0;
        }
        let mut best = exhaustive_matching(adj, u + 1, used);
        for &v in &adj[u] {
            if used & (1 << v) == 0 {
                best = best.max(1 + exhaustive_matching(adj, u + 1, used | (1 << v)));
            }
        }
        best
    }

    /// Asserts two weight vectors are equal to the last bit, naming the edge.
    fn assert_same(got: &[f64], want: &[f64]) {
        assert_eq!(got.len(), want.len());
        for (e, (g, w)) in got.iter().zip(want).enumerate() {
            assert_eq!(g.to_bits(), w.to_bits(), "edge {e}: {g} vs {w}");
        }
    }

    /// Plane formulas of Alg. 2 lines 4–8 on hand-computed cases.
    #[test]
    fn edge_plane_spans_the_edge_and_the_halfway_normal() {
        // Manifold edge along y at x = 1 between two faces facing +z:
        // halfway z, n⊥ = z × (0,−1,0) = (1,0,0), plane x = 1.
        let p = edge_plane(
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            EdgeNormals::Manifold(DVec3::Z, DVec3::Z),
        )
        .unwrap();
        assert_eq!((p.n, p.c), (DVec3::X, 1.0));
        // Ridge of a roof: normals (±1, 0, 1)/√2 sum to √2·z, d = (0, −1, 0),
        // n⊥ = z × (0, −1, 0) = (1, 0, 0): plane x = 0.
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let p = edge_plane(
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
            EdgeNormals::Manifold(DVec3::new(r, 0.0, r), DVec3::new(-r, 0.0, r)),
        )
        .unwrap();
        assert!((p.n - DVec3::X).length() < 1e-15);
        assert!(p.c.abs() < 1e-15);
        // Border edge along y on the face of normal (1, 0, 1)/√2:
        // n⊥ = (r, 0, r) × (0, −1, 0) = (r, 0, −r), through (1, 0, 0).
        let p = edge_plane(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            EdgeNormals::Border(DVec3::new(r, 0.0, r)),
        )
        .unwrap();
        assert!((p.n - DVec3::new(r, 0.0, -r)).length() < 1e-15);
        assert!((p.c - r).abs() < 1e-15);
        // Signed distance and mirror image: (3, 5, 7) is 2 from x = 1 and
        // mirrors to (−1, 5, 7).
        let plane = Plane {
            n: DVec3::X,
            c: 1.0,
        };
        let q = DVec3::new(3.0, 5.0, 7.0);
        assert_eq!(plane.signed_distance(q), 2.0);
        assert_eq!(reflect(q, 2.0, DVec3::X), DVec3::new(-1.0, 5.0, 7.0));
        // Mirror error of (3,5,7) and (−1.3, 5.4, 7): |(−1,5,7) − b| = 0.5,
        // whichever way round the pair is given.
        let a = (0, q, 2.0);
        let b = (1, DVec3::new(-1.3, 5.4, 7.0), -2.3);
        assert!((pair_error(a, b, DVec3::X) - 0.5).abs() < 1e-12);
        assert_eq!(pair_error(a, b, DVec3::X), pair_error(b, a, DVec3::X));
    }

    /// Alg. 2 line 10 and the degenerate cases: no plane, weight 0.
    #[test]
    fn edges_without_a_plane_get_no_plane() {
        let (a, b) = (DVec3::ZERO, DVec3::X);
        assert_eq!(edge_plane(a, b, EdgeNormals::NonManifold), None);
        assert_eq!(edge_plane(a, b, EdgeNormals::NoFace), None);
        // Zero-length edge.
        assert_eq!(edge_plane(a, a, EdgeNormals::Border(DVec3::Z)), None);
        // Faces folded onto each other: no halfway vector.
        assert_eq!(
            edge_plane(a, b, EdgeNormals::Manifold(DVec3::Z, -DVec3::Z)),
            None
        );
        // A face normal along the edge (degenerate face).
        assert_eq!(edge_plane(a, b, EdgeNormals::Border(DVec3::X)), None);
        // Non-finite input.
        assert_eq!(edge_plane(a, b, EdgeNormals::Border(DVec3::NAN)), None);
        assert_eq!(
            edge_plane(a, DVec3::NAN, EdgeNormals::Border(DVec3::Z)),
            None
        );
        assert_eq!(edge_plane(a, b, EdgeNormals::Border(DVec3::ZERO)), None);
        // One unusable normal of two: the plane of the other face.
        assert_eq!(
            edge_plane(a, b, EdgeNormals::Manifold(DVec3::Z, DVec3::NAN)),
            edge_plane(a, b, EdgeNormals::Border(DVec3::Z))
        );
        assert_eq!(
            edge_plane(
                DVec3::splat(f64::MAX),
                DVec3::ZERO,
                EdgeNormals::Border(DVec3::Z)
            ),
            None
        );
        // Classification of face lists.
        assert_eq!(EdgeNormals::from_faces(&[]), EdgeNormals::NoFace);
        assert_eq!(
            EdgeNormals::from_faces(&[DVec3::Z; 3]),
            EdgeNormals::NonManifold
        );
    }

    /// Knodt Fig. 3: on a grid symmetric about x = 0, the edges on that line
    /// get s = 1; other lines get the hand-counted fraction.
    ///
    /// ```text
    ///  y=3  o---o---o---o---o      5 × 4 vertices at x = −2 … 2,
    ///  y=2  o---o---o---o---o      y = 0 … 3, z = 0; every quad faces +z.
    ///  y=1  o---o---o---o---o
    ///  y=0  o---o---o---o---o
    ///      x=-2 -1   0   1   2
    /// ```
    #[test]
    fn grid_edges_on_the_symmetry_line_get_one() {
        let m = flat_grid(5, 4, -2.0);
        let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
        assert!(!w.truncated);
        // Vertex (i, j) is 5j + i; x = i − 2.
        let v = |i: u32, j: u32| 5 * j + i;
        // Column x = 0 (interior, manifold): plane x = 0, all 20 match.
        assert_eq!(w.weights[m.edge(v(2, 1), v(2, 2))], 1.0);
        assert_eq!(w.weights[m.edge(v(2, 0), v(2, 1))], 1.0);
        // Column x = 1: 4 on the plane, x = 0 ↔ x = 2 gives 8, x = −1 and
        // x = −2 have no partner (x = 3, 4): 12 / 20.
        assert_eq!(w.weights[m.edge(v(3, 1), v(3, 2))], 0.6);
        // Row y = 1 (plane y = 1): 5 on it, rows 0 ↔ 2 give 10: 15 / 20.
        assert_eq!(w.weights[m.edge(v(1, 1), v(2, 1))], 0.75);
        // Row y = 0 is a border (one face, normal +z): plane y = 0, only
        // the 5 on it: 5 / 20.
        assert_eq!(w.weights[m.edge(v(1, 0), v(2, 0))], 0.25);
        // Column x = −2 border: 4 on it, nothing beyond: 4 / 20.
        assert_eq!(w.weights[m.edge(v(0, 1), v(0, 2))], 0.2);
        // The four column lines share a plane each, the four row lines too:
        // 5 + 4 distinct planes for 31 edges.
        assert_eq!(w.planes, 9);
        assert_eq!(w.planes_computed, 9);
        assert_same(&w.weights, &brute_weights(&m.input(), 1e-3));
    }

    /// A symmetric roof: the ridge uses the halfway normal of its two
    /// sloped faces; an eave is a border edge whose plane is orthogonal to
    /// its face.
    ///
    /// ```text
    ///        1 (0,0,1) ---- 4 (0,1,1)        ridge along y at x = 0, z = 1
    ///       /                    \
    ///  0 (−1,0,0) - 3 (−1,1,0)  2 (1,0,0) - 5 (1,1,0)   eaves at x = ±1
    /// ```
    #[test]
    fn roof_ridge_is_symmetric_and_eave_matches_only_itself() {
        let positions = vec![
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::new(1.0, 1.0, 0.0),
        ];
        let m = TestMesh::new(positions, &[vec![0, 1, 4, 3], vec![1, 2, 5, 4]]);
        let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
        // Ridge: plane x = 0; 1 and 4 on it, 0 ↔ 2 and 3 ↔ 5: 6 / 6.
        assert_eq!(w.weights[m.edge(1, 4)], 1.0);
        // Eave 2–5: plane through (1, 0, 0) with normal (−1, 0, 1)/√2 (up
        // to sign). 2 and 5 on it; the ridge (σ = √2) mirrors to
        // (0, y, 1) − 2(−1, 0, 1) = (2, y, −1), the far eave to (1, y, −2):
        // no partners. 2 / 6.
        assert_eq!(w.weights[m.edge(2, 5)], 2.0 / 6.0);
        // Gable edge 1–2 (border, plane y = 0): 0, 1, 2 on it; y = 1 would
        // mirror to y = −1: 3 / 6.
        assert_eq!(w.weights[m.edge(1, 2)], 0.5);
        assert_same(&w.weights, &brute_weights(&m.input(), 1e-3));
    }

    /// Alg. 2 line 10: an edge of three faces gets 0, as does an edge of no
    /// face, even when its line is a symmetry line.
    #[test]
    fn non_manifold_and_faceless_edges_get_zero() {
        let mut m = flat_grid(5, 4, -2.0);
        let e = m.edge(12, 7); // on x = 0: s = 1 as a manifold edge
        m.normals[e] = EdgeNormals::NonManifold;
        let f = m.edge(2, 7);
        m.normals[f] = EdgeNormals::NoFace;
        let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
        assert_eq!((w.weights[e], w.weights[f]), (0.0, 0.0));
        // The other edges on x = 0 still share the plane.
        assert_eq!(w.weights[m.edge(12, 17)], 1.0);
    }

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

    /// Two vertices mirroring onto one partner: only one pair counts.
    #[test]
    fn each_vertex_is_matched_at_most_once() {
        let plane = Plane {
            n: DVec3::X,
            c: 0.0,
        };
        let points = [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.05, 0.0),
            DVec3::new(-1.0, 0.02, 0.0),
        ];
        let grid = Grid::new(&points, 0.1);
        let m = match_plane(&grid, plane, 0.1, u64::MAX, &mut Scratch::default());
        assert_eq!(m.matched, 2, "one pair of the three vertices");
        assert_eq!(brute_matched(&points, plane, 0.1), 2);
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

    /// Where nearest-first greedy (Alg. 2's spirit) pairs `a` with its exact
    /// mirror `b` and strands `c` and `d`, the maximum matching pairs
    /// `a–d` and `c–b`: all four have a partner.
    ///
    /// ```text
    ///   d (−0.92)   b (−1.00)  |  a (1.00)   c (1.08)     δ = 0.1
    /// ```
    #[test]
    fn maximum_matching_beats_nearest_first_greedy() {
        let plane = Plane {
            n: DVec3::X,
            c: 0.0,
        };
        let points = [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.08, 0.0, 0.0),
            DVec3::new(-0.92, 0.0, 0.0),
        ];
        let grid = Grid::new(&points, 0.1);
        let m = match_plane(&grid, plane, 0.1, u64::MAX, &mut Scratch::default());
        assert_eq!(m.matched, 4);
    }

    /// Hopcroft–Karp against exhaustive search on random bipartite graphs,
    /// including long chains that need several augmenting phases.
    #[test]
    fn hopcroft_karp_matches_exhaustive_search_on_random_graphs() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let mut scratch = MatchingScratch::default();
        for case in 0..500 {
            let left = rng.below(9);
            let right = 1 + rng.below(12);
            let density = rng.unit();
            let adj: Vec<Vec<usize>> = (0..left)
                .map(|_| (0..right).filter(|_| rng.unit() < density * 0.5).collect())
                .collect();
            let mut adj_start = vec![0u32];
            let mut flat = Vec::new();
            for a in &adj {
                flat.extend(a.iter().map(|&v| v as u32));
                adj_start.push(flat.len() as u32);
            }
            let mut right_match = vec![NONE; right];
            let got = max_matching(&adj_start, &flat, &mut right_match, &mut scratch);
            assert_eq!(got, exhaustive_matching(&adj, 0, 0), "case {case}: {adj:?}");
            assert_eq!(got, kuhn_matching(&adj, right), "case {case}: {adj:?}");
            // A valid matching: each right vertex used once, by a neighbour.
            let used: Vec<_> = right_match.iter().filter(|&&u| u != NONE).collect();
            assert_eq!(used.len() as u64, got);
            for (v, &u) in right_match.iter().enumerate() {
                if u != NONE {
                    assert!(adj[u as usize].contains(&v));
                }
            }
        }
        // A chain where u_i – {v_i, v_{i+1}} and the last u only – v_0: the
        // greedy start gives every u_i its v_i and leaves the last u free,
        // with one augmenting path through all 2000 pairs (too deep for a
        // recursive search on a small stack).
        let n = 2000usize;
        let mut adj_start = vec![0u32];
        let mut flat = Vec::new();
        for i in 0..n {
            if i + 1 < n {
                flat.extend([i as u32, i as u32 + 1]);
            } else {
                flat.push(0);
            }
            adj_start.push(flat.len() as u32);
        }
        let mut right_match = vec![NONE; n];
        assert_eq!(
            max_matching(&adj_start, &flat, &mut right_match, &mut scratch),
            n as u64
        );
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

    /// Random small meshes (random edges, including repeated ones with
    /// negated normals that share a plane, and reversed ones; random face
    /// normals and kinds): the full function equals the per-edge brute
    /// force bit for bit when only exact planes are shared.
    #[test]
    fn weights_equal_brute_force_on_random_meshes() {
        let mut rng = Rng(0x94D0_49BB_1331_11EB);
        let (mut planes, mut with_plane) = (0, 0);
        for case in 0..150 {
            let delta = [0.02, 0.1][rng.below(2)];
            let nv = 1 + rng.below(16);
            let mut positions: Vec<DVec3> = (0..nv)
                .map(|_| DVec3::new(rng.unit(), rng.unit(), rng.unit()))
                .collect();
            // Mirror some vertices across x = ½ (jittered) so that some
            // planes are nearly symmetry planes.
            for i in 0..nv {
                if rng.below(2) == 0 {
                    let p = positions[i];
                    let j = rng.direction() * rng.range(0.0, delta);
                    positions.push(DVec3::new(1.0 - p.x, p.y, p.z) + j);
                }
            }
            let nv = positions.len() as u32;
            let mut edges = Vec::new();
            let mut normals = Vec::new();
            for _ in 0..1 + rng.below(12) {
                let e = [rng.below(nv as usize) as u32, rng.below(nv as usize) as u32];
                let kind = match rng.below(6) {
                    0 => EdgeNormals::NoFace,
                    1 => EdgeNormals::NonManifold,
                    2 | 3 => EdgeNormals::Border(rng.direction()),
                    _ => EdgeNormals::Manifold(rng.direction(), rng.direction()),
                };
                edges.push(e);
                normals.push(kind);
                if rng.below(3) == 0 {
                    // The same edge with its faces' normals negated: the
                    // same plane with the opposite orientation, to the bit
                    // (n⊥ and the offset only change sign), so grouped.
                    edges.push(e);
                    normals.push(match kind {
                        EdgeNormals::Border(n) => EdgeNormals::Border(-n),
                        EdgeNormals::Manifold(a, b) => EdgeNormals::Manifold(-a, -b),
                        other => other,
                    });
                }
                if rng.below(3) == 0 {
                    // The same edge reversed: the same plane mathematically,
                    // with the offset taken at the other end.
                    edges.push([e[1], e[0]]);
                    normals.push(kind);
                }
            }
            // An out-of-range edge and one without normals.
            edges.push([0, nv + 3]);
            edges.push([0, nv - 1]);
            let input = SymmetryInput {
                positions: &positions,
                edges: &edges,
                edge_normals: &normals,
            };
            let options = SymmetryOptions {
                plane_tolerance: 0.0,
                ..opts(delta)
            };
            let got = edge_symmetry_weights(&input, &options);
            assert_same(&got.weights, &brute_weights(&input, delta));
            assert!(
                got.weights.iter().all(|&s| (0.0..=1.0).contains(&s)),
                "case {case}"
            );
            planes += got.planes;
            with_plane += (0..edges.len())
                .filter(|&e| {
                    let [a, b] = edges[e];
                    let (Some(&p0), Some(&p1)) =
                        (positions.get(a as usize), positions.get(b as usize))
                    else {
                        return false;
                    };
                    let faces = normals.get(e).copied().unwrap_or(EdgeNormals::NoFace);
                    edge_plane(p0, p1, faces).is_some()
                })
                .count();
        }
        // Grouping happened: fewer planes than edges with a plane.
        assert!(
            planes < with_plane,
            "{planes} planes for {with_plane} edges"
        );
    }

    /// A grid symmetric about several lines, jittered and rotated so that
    /// the planes of edges on one line differ in their last bits: the
    /// default tolerance groups them, and the weights equal computing every
    /// edge on its own.
    #[test]
    fn plane_grouping_gives_the_same_weights_as_no_grouping() {
        let mut m = flat_grid(9, 7, -4.0);
        // Scale into the unit box and rotate about an oblique axis, so that
        // the normals are no longer exact axis vectors.
        let rot = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        for p in &mut m.positions {
            *p = rot * (*p * 0.1);
        }
        for n in &mut m.normals {
            *n = match *n {
                EdgeNormals::Border(a) => EdgeNormals::Border(rot * a),
                EdgeNormals::Manifold(a, b) => EdgeNormals::Manifold(rot * a, rot * b),
                other => other,
            };
        }
        let input = m.input();
        let grouped = edge_symmetry_weights(&input, &opts(1e-3));
        let exact = edge_symmetry_weights(
            &input,
            &SymmetryOptions {
                plane_tolerance: 0.0,
                ..opts(1e-3)
            },
        );
        let brute = brute_weights(&input, 1e-3);
        assert_same(&grouped.weights, &brute);
        assert_same(&exact.weights, &brute);
        // 9 column lines + 7 row lines; the rotation made exact sharing
        // rarer than the tolerance's.
        assert_eq!(grouped.planes, 16);
        assert!(exact.planes >= grouped.planes);
        // Column x = 0 (i = 4) is the symmetry line.
        assert_eq!(grouped.weights[m.edge(4 + 9, 4 + 18)], 1.0);
    }

    /// The cap keeps a prefix of the planes in computing order (largest
    /// group first): those planes have their weights, later ones 0, and
    /// `truncated` says so.
    #[test]
    fn max_work_keeps_a_prefix_of_planes_and_zeroes_the_rest() {
        let m = flat_grid(6, 5, -2.5);
        let input = m.input();
        let options = opts(1e-3);
        let full = edge_symmetry_weights(&input, &options);
        assert!(!full.truncated);
        assert_eq!(full.planes_computed, full.planes);
        // Per-plane work, computed alone.
        let groups = plane_groups(&input, &options);
        let grid = Grid::new(&m.positions, 1e-3);
        let works: Vec<u64> = groups
            .iter()
            .map(|g| match_plane(&grid, g.plane, 1e-3, u64::MAX, &mut Scratch::default()).work)
            .collect();
        assert_eq!(full.work, works.iter().sum::<u64>());
        // Group sizes never increase along the computing order.
        assert!(groups
            .windows(2)
            .all(|w| w[0].edges.len() >= w[1].edges.len()));
        for kept in 0..groups.len() {
            let budget: u64 = works[..kept].iter().sum();
            // Exactly enough for `kept` planes, and one short of `kept + 1`.
            for max_work in [budget, budget + works[kept] - 1] {
                let w = edge_symmetry_weights(
                    &input,
                    &SymmetryOptions {
                        max_work,
                        ..options
                    },
                );
                assert!(w.truncated);
                assert_eq!(w.planes_computed, kept);
                for (i, g) in groups.iter().enumerate() {
                    for &e in &g.edges {
                        let want = if i < kept {
                            full.weights[e as usize]
                        } else {
                            0.0
                        };
                        assert_eq!(w.weights[e as usize], want, "kept {kept}, edge {e}");
                    }
                }
            }
        }
        // No work at all: nothing computed, nothing examined.
        let none = edge_symmetry_weights(
            &input,
            &SymmetryOptions {
                max_work: 0,
                ..options
            },
        );
        assert!(none.truncated);
        assert_eq!(none.work, 0);
        assert!(none.weights.iter().all(|&s| s == 0.0));
    }

    /// Empty and degenerate inputs give zeros, never a panic.
    #[test]
    fn degenerate_inputs_give_zero_weights() {
        let empty = SymmetryInput {
            positions: &[],
            edges: &[[0, 1]],
            edge_normals: &[EdgeNormals::Border(DVec3::Z)],
        };
        let w = edge_symmetry_weights(&empty, &SymmetryOptions::default());
        assert_eq!(w.weights, vec![0.0]);
        let m = flat_grid(3, 3, -1.0);
        for delta in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let w = edge_symmetry_weights(&m.input(), &opts(delta));
            assert!(w.weights.iter().all(|&s| s == 0.0), "delta {delta}");
            assert!(!w.truncated);
        }
        // NaN and huge positions, a zero-length edge, fewer normals than
        // edges: still weights in [0, 1] and equal to brute force.
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::NAN,
            DVec3::splat(1e300),
            DVec3::new(-1e300, 0.0, 0.0),
            DVec3::Y,
        ];
        let edges = [[0, 1], [0, 0], [0, 2], [3, 4], [1, 5], [5, 0]];
        let normals = [
            EdgeNormals::Border(DVec3::Z),
            EdgeNormals::Border(DVec3::Z),
            EdgeNormals::Border(DVec3::Z),
            EdgeNormals::Manifold(DVec3::Z, DVec3::Y),
            EdgeNormals::Manifold(DVec3::Z, DVec3::Z),
        ];
        let input = SymmetryInput {
            positions: &positions,
            edges: &edges,
            edge_normals: &normals,
        };
        let w = edge_symmetry_weights(&input, &opts(1e-3));
        assert_same(&w.weights, &brute_weights(&input, 1e-3));
        assert_eq!(w.weights[1], 0.0);
        assert_eq!(w.weights[5], 0.0);
        // Edge 0–1 (plane y = 0): 0, 1 and (−1e300, 0, 0) lie on it;
        // 5 = (0, 1, 0) would need (0, −1, 0); NaN never matches: 3 of 6.
        assert_eq!(w.weights[0], 0.5);
    }

    /// The same weights, work and truncation with 1, 2 and 3 rayon threads:
    /// uncapped, with a cap that cuts a batch in the middle, and with the
    /// prefilter.
    #[test]
    fn results_do_not_depend_on_thread_count() {
        let mesh = wavy_mesh(40, 0.2);
        let input = mesh.input();
        let full = edge_symmetry_weights(&input, &SymmetryOptions::default());
        let capped = SymmetryOptions {
            max_work: full.work / 3,
            ..SymmetryOptions::default()
        };
        let prefiltered = SymmetryOptions {
            min_weight: 0.05,
            samples: 256,
            ..capped
        };
        for options in [SymmetryOptions::default(), capped, prefiltered] {
            let run = |threads| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| edge_symmetry_weights(&input, &options))
            };
            let one = run(1);
            for threads in [2, 3] {
                let other = run(threads);
                assert_same(&one.weights, &other.weights);
                assert_eq!(
                    (
                        one.work,
                        one.truncated,
                        one.planes_computed,
                        one.planes_skipped
                    ),
                    (
                        other.work,
                        other.truncated,
                        other.planes_computed,
                        other.planes_skipped
                    )
                );
            }
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

    /// With the prefilter on, every edge's weight is its exact weight or 0
    /// (skipped); on a symmetric height field no edge whose exact weight
    /// reaches `min_weight` is skipped, and most planes are.
    #[test]
    fn prefilter_keeps_exact_weights_or_skips_low_ones() {
        let m = wavy_mesh(41, 0.2);
        let exact = edge_symmetry_weights(&m.input(), &opts(1e-3));
        let options = SymmetryOptions {
            min_weight: 0.1,
            samples: 256,
            ..opts(1e-3)
        };
        let filtered = edge_symmetry_weights(&m.input(), &options);
        for (e, (&f, &x)) in filtered.weights.iter().zip(&exact.weights).enumerate() {
            assert!(f == x || f == 0.0, "edge {e}: {f} vs exact {x}");
            assert!(x < 0.1 || f == x, "edge {e} skipped at exact {x}");
        }
        assert!(filtered.planes_skipped * 2 > filtered.planes);
        assert!(filtered.work * 2 < exact.work);
        assert_eq!(filtered.planes_computed, filtered.planes);
    }

    /// A triangulated height field on `n × n` vertices in the unit box,
    /// mirror-symmetric about x = ½ with a wave of relative height `amp`
    /// (so the planes of most edges are distinct and a few are symmetry
    /// planes), normalized to a unit diagonal.
    fn wavy_mesh(n: u32, amp: f64) -> TestMesh {
        let mut positions = Vec::new();
        let k = 1.0 / (n - 1) as f64;
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (i as f64 * k, j as f64 * k);
                let z = amp * ((6.0 * (x - 0.5)).powi(2) * 0.3 + (7.0 * y).sin() * 0.5);
                positions.push(DVec3::new(x, y, z));
            }
        }
        let diag = {
            let (lo, hi) = positions.iter().fold(
                (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
                |(lo, hi), &p| (lo.min(p), hi.max(p)),
            );
            (hi - lo).length()
        };
        for p in &mut positions {
            *p /= diag;
        }
        let mut faces = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = j * n + i;
                // Diagonals mirrored across x = ½ as well.
                if 2 * i < n - 1 {
                    faces.push(vec![v, v + 1, v + n + 1]);
                    faces.push(vec![v, v + n + 1, v + n]);
                } else {
                    faces.push(vec![v, v + 1, v + n]);
                    faces.push(vec![v + 1, v + n + 1, v + n]);
                }
            }
        }
        TestMesh::new(positions, &faces)
    }

    /// The wavy mesh's centre column is its symmetry line: s = 1 there.
    #[test]
    fn wavy_mesh_centre_column_is_a_symmetry_plane() {
        let m = wavy_mesh(21, 0.2);
        let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
        // Column i = 10 is x = ½; its vertical edges lie in the plane.
        assert_eq!(w.weights[m.edge(10 + 21 * 5, 10 + 21 * 6)], 1.0);
        assert_same(&w.weights, &brute_weights(&m.input(), 1e-3));
    }

    /// Timing on generated meshes of 20k and 100k vertices (run with
    /// `cargo test --release -p wildlod-simplify symmetry -- --ignored
    /// --nocapture`): a height field mirror-symmetric about one plane (most
    /// edge planes distinct) and a torus (many shared planes), each with
    /// the default options, with the prefilter at `min_weight` 0.05, and
    /// without a cap; the prefilter's misses are counted against the
    /// uncapped exact weights.
    #[test]
    #[ignore]
    fn symmetry_timing_on_generated_meshes() {
        let meshes = [
            ("height field", wavy_mesh(142, 0.2)),
            ("torus", torus(200, 100)),
            ("height field", wavy_mesh(317, 0.2)),
            ("torus", torus(500, 200)),
        ];
        for (name, m) in &meshes {
            println!(
                "{name}: {} vertices, {} edges",
                m.positions.len(),
                m.edges.len()
            );
            let default = SymmetryOptions::default();
            report_timing("  default", m, &default);
            let filtered = report_timing(
                "  prefilter 0.05",
                m,
                &SymmetryOptions {
                    min_weight: 0.05,
                    ..default
                },
            );
            let exact = report_timing(
                "  uncapped",
                m,
                &SymmetryOptions {
                    max_work: u64::MAX,
                    ..default
                },
            );
            let misses = (0..m.edges.len())
                .filter(|&e| exact.weights[e] >= 0.05 && filtered.weights[e] != exact.weights[e])
                .count();
            let above = exact.weights.iter().filter(|&&s| s >= 0.05).count();
            println!("  prefilter misses {misses} of {above} edges with exact s ≥ 0.05");
        }
    }

    /// A torus of `nu × nv` quads, normalized to a unit diagonal.
    fn torus(nu: u32, nv: u32) -> TestMesh {
        let tau = std::f64::consts::TAU;
        let mut positions = Vec::new();
        for i in 0..nu {
            let u = tau * i as f64 / nu as f64;
            for j in 0..nv {
                let v = tau * j as f64 / nv as f64;
                let w = 1.0 + 0.3 * v.cos();
                positions
                    .push(DVec3::new(w * u.cos(), w * u.sin(), 0.3 * v.sin()) / 2.6_f64.hypot(0.6));
            }
        }
        let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
        let mut faces = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TestMesh::new(positions, &faces)
    }

    /// Runs once and prints the time, work and truncation.
    fn report_timing(name: &str, m: &TestMesh, options: &SymmetryOptions) -> SymmetryResult {
        let start = std::time::Instant::now();
        let w = edge_symmetry_weights(&m.input(), options);
        let t = start.elapsed().as_secs_f64();
        println!(
            "{name}: {:.2} s, {} planes ({} computed, {} skipped), work {:.3e} ({:.1} ns/work), truncated {}",
            t,
            w.planes,
            w.planes_computed,
            w.planes_skipped,
            w.work as f64,
            t * 1e9 / w.work.max(1) as f64,
            w.truncated,
        );
        w
    }
}
