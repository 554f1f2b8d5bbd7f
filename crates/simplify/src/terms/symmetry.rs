//! Per-edge soft symmetry weights (Knodt 2024 §3.1 "Soft Symmetry",
//! Appendix Alg. 2).
//!
//! Every edge `e = (e0, e1)` spans a plane: it contains the edge direction
//! `d = normalize(e0 − e1)` and the mean normal of the edge's faces, so its
//! normal is `n⊥ = normalize(n(f0) + n(f1)) × d` for an edge of two faces and
//! `n⊥ = n(f0) × d` for a border edge (Alg. 2 lines 4–8). The edge's weight
//! `s ∈ [0, 1]` is the fraction of all vertices that have a mirror partner
//! across that plane (Knodt §3.1). It feeds the tangent quadrics of
//! [`crate::terms::tangent`] as `w = max(dihedral/π, λ_sym·s, λ_joint·d, 0.01)`
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
//! Measured once (2 cores, δ = 1e-3, generated meshes, by a timing
//! harness since replaced by the `wildlod symmetry` cases of
//! `crates/bench/benches/simplify.rs`, which time whole runs on the corpus
//! quad meshes): about 4–7 ns per unit of work, i.e. per vertex and plane. A 20k-vertex height field with 60k
//! distinct planes takes 5 s exact, 1.2 s with the prefilter at 0.05; 100k
//! vertices reach the default cap (2·10⁹, 10–14 s) after ~18k planes.
//!
//! Planes are computed in parallel in batches of fixed size
//! ([`BATCH`]); which planes are kept depends only on the plane order and
//! each plane's own work, never on the thread count.

use glam::DVec3;
use rayon::prelude::*;

use grid::{plane_outcome, Grid, PlaneMatch, Scratch};
use plane::{edge_plane, Plane};

mod grid;
mod matching;
mod plane;
#[cfg(test)]
mod test_support;
#[cfg(test)]
mod tests;

/// Marks an unused entry in the grid's hash table and in matching scratch.
const NONE: u32 = u32::MAX;

/// Planes computed per parallel batch. Fixed (not derived from the thread
/// count) so that the work spent past the cap, reported in
/// [`SymmetryResult::work`], does not depend on the machine either.
const BATCH: usize = 64;

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
    /// as [`crate::terms::tangent`] collects them: 0, 1, 2 or more faces.
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
