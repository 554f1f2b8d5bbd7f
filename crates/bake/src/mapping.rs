//! Successive mapping (W §4.3.1, App. C.2): from a point of the simplified
//! mesh to the input face and barycentrics it came from.
//!
//! W stores, per collapse, the edge one-ring before it and the vertex
//! one-ring after it. A point `p` of the simplified mesh `M^c` sits on a
//! face. Walking the history backwards, whenever that face is in the vertex
//! one-ring of collapse `k` (the faces around the new vertex), the point is
//! projected to the closest point of collapse `k`'s edge one-ring (the faces
//! around both endpoints before it), which gives a face of `M^{k-1}`. At the
//! input `M^0` the face is an input face. Two details from W make this work:
//!
//! - the closest-point queries always use `p`'s position on the *final*
//!   mesh, not the previous projection, so distortions of many small
//!   projections do not accumulate (W §4.3.1, last paragraph);
//! - only the collapses whose vertex one-ring holds the current face matter,
//!   so each point skips almost the whole history (App. C.2). We index, per
//!   face id, the collapses whose vertex one-ring holds it, and jump from
//!   one to the previous by binary search.
//!
//! Face ids are stable through the history (a face keeps its input index
//! while collapses merge its corners), and a face not in any later vertex
//! one-ring has not changed since the input: its corners neither moved nor
//! merged. So the last projection lands on the input face itself, and its
//! barycentrics are taken on the input polygon (fan-triangulated).

use glam::{DVec3, Vec3};
use wildlod_geometry::closest_point_on_triangle;
use wildlod_mesh::Faces;
use wildlod_simplify::History;

use crate::ring_block::{RingBlock, LANES};
use crate::ring_triangle::RingTriangle;

/// A point of the input surface: an input face, three of its corners and
/// barycentrics over them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Input face index.
    pub face: u32,
    /// Input corner indices (into `Faces::indices`) of the fan triangle of
    /// `face` the point lies on; for a triangle, its three corners.
    pub corners: [u32; 3],
    /// Barycentric weights of `corners`, non-negative, summing to 1.
    pub bary: [f32; 3],
}

/// The map `T: M^c → M^0` of W §4.3.1 for one simplification run.
///
/// Built once from the run's [`History`] and the input it simplified, then
/// queried per point, from any number of threads (it is immutable).
///
/// ```
/// use wildlod_bake::SuccessiveMap;
/// use wildlod_simplify::{simplify_polygons, Options, Record, Target};
///
/// // A 4×4 grid of unit squares in z = 0, reduced to two triangles.
/// let grid = wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::quad_grid(4, 4));
/// let options = Options {
///     target: Target { triangles: Some(2), ..Target::default() },
///     record: Record { history: true, ..Record::default() },
///     ..Options::default()
/// };
/// let lod = simplify_polygons(&grid.positions, &grid.faces, &options)?;
/// let history = lod.history.as_ref().expect("recorded");
/// let map = SuccessiveMap::new(history, &grid.positions, &grid.faces);
/// // A point on the first output face lands on an input face that holds it.
/// let f = lod.faces.face(0);
/// let p = [0, 1, 2].map(|k| lod.positions[f[k] as usize]);
/// let centroid = [0, 1, 2].map(|a| (p[0][a] + p[1][a] + p[2][a]) / 3.0);
/// let hit = map.map(lod.face_origin[0], centroid);
/// let q = map.position(&hit);
/// assert!((0..3).all(|a| (q[a] - centroid[a]).abs() < 1e-5));
/// # Ok::<(), wildlod_simplify::Error>(())
/// ```
#[derive(Debug)]
pub struct SuccessiveMap<'a> {
    history: &'a History,
    positions: &'a [[f32; 3]],
    faces: &'a Faces,
    /// Per face id, `touch[touch_start[f]..touch_start[f + 1]]` are the
    /// collapses (ascending) whose vertex one-ring holds `f`, and
    /// `touch_first` the index within that collapse's ring of `f`'s first
    /// triangle, where a walk's search starts.
    touch_start: Vec<u32>,
    touch: Vec<u32>,
    touch_first: Vec<u32>,
    /// The edge one-ring of every collapse as flat triangles (polygons
    /// fanned), `ring_start[k]..ring_start[k + 1]`: the hot loop reads
    /// them contiguously.
    ring_start: Vec<u32>,
    rings: Vec<RingTriangle>,
    /// The same triangles as blocks of four for measuring distances,
    /// `blocks[block_start[k]..block_start[k + 1]]` for collapse `k`
    /// (each ring starts a new block).
    block_start: Vec<u32>,
    blocks: Vec<RingBlock>,
}

/// Where a walk through the history stands: the current face, the
/// collapses still to visit (those before `bound`), and the ring triangle
/// (index into `rings`) of the last projection, if any.
#[derive(Clone, Copy, Debug)]
struct Walk {
    face: u32,
    bound: u32,
    last: Option<u32>,
    /// Where `bound` is in `face`'s touch list (an index into `touch`),
    /// when it is there: the next step is then the entry before it, with
    /// no search.
    at: u32,
    /// Ring projections made so far (for tests: how much work was
    /// shared).
    steps: u32,
}

/// Batches of at most this many points are walked point by point. A
/// certification measures the ring from the ball's center and weighs every
/// triangle against it, about as much work as some tens of points' own
/// steps (a step measures a ring in blocks of four, `ring_block.rs`);
/// below this size it fails often enough on curved surfaces (where the
/// texels of a triangle part ways) to cost more than it saves. Measured on
/// the bake bench's truck, torus and scan at 10% and 1%: 16, 32 and 64
/// within a few percent of each other, 3 (one certification per step down
/// to three points) 10–40% slower on the curved ones.
const LEAF_POINTS: usize = 32;

/// A batch with at least this many points splits in two where at least
/// `SPLIT_RISKY` ring triangles other than the candidate may be a point's
/// choice, rather than testing each point against all of them.
const SPLIT_POINTS: usize = 32;
const SPLIT_RISKY: usize = 2;

/// The margin, relative to the coordinates' magnitude, by which a ring
/// triangle must be farther than the candidate to be ruled out for a whole
/// batch: about 80 ulps of `f32`, far above the rounding of a distance as
/// `ring_block.rs` measures it, so every point of the batch picks as its
/// own walk would.
const MARGIN: f32 = 1e-5;

/// Side in texels of the tiles [`SuccessiveMap::map_texels`] groups
/// texels in: small enough that a tile's texels of one triangle are close
/// together (few branches), large enough to share each walk over many.
const TILE: usize = 32;

impl<'a> SuccessiveMap<'a> {
    /// Indexes `history` (recorded while simplifying `faces` over
    /// `positions`, [`wildlod_simplify::Record::history`]).
    pub fn new(history: &'a History, positions: &'a [[f32; 3]], faces: &'a Faces) -> Self {
        let nf = faces.len();
        let mut count = vec![0u32; nf + 1];
        for k in 0..history.len() {
            for &f in history.after(k) {
                if let Some(c) = count.get_mut(f as usize) {
                    *c += 1;
                }
            }
        }
        let mut touch_start = Vec::with_capacity(nf + 1);
        let mut acc = 0u32;
        for c in &count[..nf] {
            touch_start.push(acc);
            acc += c;
        }
        touch_start.push(acc);
        let mut fill = touch_start.clone();
        let mut touch = vec![0u32; acc as usize];
        // Collapses in order: every face's list comes out ascending.
        for k in 0..history.len() {
            for &f in history.after(k) {
                if let Some(at) = fill.get_mut(f as usize).filter(|_| (f as usize) < nf) {
                    touch[*at as usize] = k as u32;
                    *at += 1;
                }
            }
        }
        let mut ring_start = Vec::with_capacity(history.len() + 1);
        let mut rings = Vec::new();
        let mut block_start = Vec::with_capacity(history.len() + 1);
        let mut blocks = Vec::new();
        let mut triangles = Vec::new();
        for k in 0..history.len() {
            ring_start.push(rings.len() as u32);
            block_start.push(blocks.len() as u32);
            triangles.clear();
            for rf in history.before(k) {
                let c = history.positions(rf);
                for t in 1..c.len().saturating_sub(1) {
                    let corners = [c[0], c[t], c[t + 1]].map(Vec3::from);
                    rings.push(RingTriangle::new(corners, rf.face));
                    triangles.push(corners);
                }
            }
            RingBlock::pack(&triangles, &mut blocks);
        }
        ring_start.push(rings.len() as u32);
        block_start.push(blocks.len() as u32);
        let mut touch_first = vec![0u32; touch.len()];
        for f in 0..nf {
            let (a, b) = (touch_start[f] as usize, touch_start[f + 1] as usize);
            for (first, &k) in touch_first[a..b].iter_mut().zip(&touch[a..b]) {
                let ring =
                    &rings[ring_start[k as usize] as usize..ring_start[k as usize + 1] as usize];
                *first = ring.iter().position(|t| t.face == f as u32).unwrap_or(0) as u32;
            }
        }
        SuccessiveMap {
            history,
            positions,
            faces,
            touch_start,
            touch,
            touch_first,
            ring_start,
            rings,
            block_start,
            blocks,
        }
    }

    /// Maps point `p` (input units) of the simplified mesh, lying on the
    /// output face whose input face id is `face` (`Simplified::face_origin`),
    /// to the input surface.
    ///
    /// # Panics
    /// When `face` is not a face id of the input.
    pub fn map(&self, face: u32, p: [f32; 3]) -> SurfacePoint {
        let pf = Vec3::from(p);
        let w = self.walk(self.start(face), pf);
        self.finish(w, pf)
    }

    /// Maps many points that all lie on the output face whose input face
    /// id is `face` (the texels of one output triangle, say) into `out`,
    /// with the same result as [`SuccessiveMap::map`] on each, bit for
    /// bit, but walking the history once for every group of points that
    /// follows one path through it (on flat and gently curved surfaces
    /// texels of a triangle share much of their walk; on bumpy ones they
    /// part ways every few texels and are walked point by point).
    ///
    /// Every step of a walk picks the ring triangle closest to the point.
    /// The batch takes each step once for a ball around its points: the
    /// triangle closest to the ball's center is the candidate, and another
    /// triangle is ruled out for every point when it is farther from the
    /// center by more than twice the radius (distances change by at most
    /// the radius within the ball), or, where the ball hovers over the
    /// candidate's interior, by the plane and in-plane parts of the squared
    /// distances (`Above`); margins cover the `f32` rounding of the
    /// per-point distances. When nothing remains the step is shared. Else
    /// a large batch splits in two across its longest extent (a smaller
    /// ball rules out more), or each point takes this step of its own walk,
    /// measuring only the triangles left (the others are farther from it
    /// than the candidate), and the batch goes on in groups of equal
    /// picks: the walk is shared up to where paths really part. Batches of at most 32 points are
    /// walked point by point. At the end each point needs only its closest
    /// point on the last ring triangle and its barycentrics on the input
    /// face, as [`SuccessiveMap::map`] does last.
    ///
    /// # Panics
    /// When `face` is not a face id of the input, or `out` is not as long
    /// as `points`.
    pub fn map_many(&self, face: u32, points: &[[f32; 3]], out: &mut [SurfacePoint]) {
        assert_eq!(points.len(), out.len(), "one output per point");
        self.map_many_counted(face, points, out);
    }

    /// [`SuccessiveMap::map_many`], returning how many ring projections
    /// it made point by point (for tests: how much of the work was shared;
    /// [`SuccessiveMap::map`] makes one per step of every point's walk).
    fn map_many_counted(&self, face: u32, points: &[[f32; 3]], out: &mut [SurfacePoint]) -> usize {
        assert_eq!(points.len(), out.len(), "one output per point");
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        self.map_batch(self.start(face), points, &mut order, out)
    }

    /// Maps the texels of rows `rows` of an atlas `width` texels wide:
    /// `texel(i)` gives texel `i`'s output triangle (any id that groups
    /// texels lying on one output face), the input face id of that output
    /// face, and the texel's surface point, or `None` for a texel no
    /// triangle owns. The result holds one entry per texel of the rows,
    /// `rows.start * width` first, equal to [`SuccessiveMap::map`] on each.
    ///
    /// Texels are taken in tiles of 32×32, grouped by triangle within a
    /// tile and mapped together ([`SuccessiveMap::map_many`]); tiles in
    /// parallel.
    pub fn map_texels<F>(
        &self,
        width: usize,
        rows: std::ops::Range<usize>,
        texel: F,
    ) -> Vec<Option<SurfacePoint>>
    where
        F: Fn(usize) -> Option<(u32, u32, [f32; 3])> + Sync,
    {
        use rayon::prelude::*;
        let first = rows.start * width;
        let mut out = vec![None; rows.len() * width];
        let tiles: Vec<(usize, usize)> = rows
            .clone()
            .step_by(TILE)
            .flat_map(|y| (0..width).step_by(TILE).map(move |x| (y, x)))
            .collect();
        let mapped: Vec<Vec<(usize, SurfacePoint)>> = tiles
            .par_iter()
            .map(|&(y, x)| {
                let mut items: Vec<(u32, u32, [f32; 3], usize)> = Vec::new();
                for yy in y..(y + TILE).min(rows.end) {
                    for xx in x..(x + TILE).min(width) {
                        let i = yy * width + xx;
                        if let Some((group, face, p)) = texel(i) {
                            items.push((group, face, p, i));
                        }
                    }
                }
                // Stable: texels of a group stay in scan order.
                items.sort_by_key(|it| it.0);
                let mut done = Vec::with_capacity(items.len());
                let mut points = Vec::new();
                let mut hits = Vec::new();
                for run in items.chunk_by(|a, b| a.0 == b.0) {
                    points.clear();
                    points.extend(run.iter().map(|it| it.2));
                    hits.clear();
                    hits.resize(run.len(), self.placeholder());
                    self.map_many(run[0].1, &points, &mut hits);
                    done.extend(run.iter().map(|it| it.3).zip(hits.iter().copied()));
                }
                done
            })
            .collect();
        for (i, hit) in mapped.into_iter().flatten() {
            out[i - first] = Some(hit);
        }
        out
    }

    /// A value to fill output slots with before they are mapped.
    fn placeholder(&self) -> SurfacePoint {
        SurfacePoint {
            face: 0,
            corners: [0; 3],
            bary: [1.0, 0.0, 0.0],
        }
    }

    /// The walk of a point on the output face with input face id `face`,
    /// before its first step.
    fn start(&self, face: u32) -> Walk {
        Walk {
            face,
            bound: self.history.len() as u32,
            last: None,
            at: u32::MAX,
            steps: 0,
        }
    }

    /// Walks `pf` from `w` down to the input.
    fn walk(&self, mut w: Walk, pf: Vec3) -> Walk {
        // Each step strictly lowers `bound`: at most one step per collapse.
        while let Some((k, first, at)) = self.previous_touch(&w) {
            if let Some(i) = self.project_on_edge_ring(k as usize, first, pf) {
                w.face = self.rings[i].face;
                w.last = Some(i as u32);
                w.steps += 1;
            }
            w.bound = k;
            w.at = at;
        }
        w
    }

    /// The input point of `pf` once its walk `w` reached the input: its
    /// closest point on the last ring triangle it was projected to (the
    /// queries always use the final position), else the point itself.
    fn finish(&self, w: Walk, pf: Vec3) -> SurfacePoint {
        let q = match w.last {
            Some(i) => self.rings[i as usize].closest(pf).as_dvec3(),
            None => pf.as_dvec3(),
        };
        self.on_input_face(w.face, q)
    }

    /// [`SuccessiveMap::map_many`] on the points `order` names, all of
    /// which follow the same path down to `w`; returns how many were
    /// walked on their own.
    fn map_batch(
        &self,
        mut w: Walk,
        points: &[[f32; 3]],
        order: &mut [u32],
        out: &mut [SurfacePoint],
    ) -> usize {
        let each = |w: Walk, order: &[u32], out: &mut [SurfacePoint]| {
            let mut steps = 0;
            for &i in order {
                let pf = Vec3::from(points[i as usize]);
                let end = self.walk(w, pf);
                steps += (end.steps - w.steps) as usize;
                out[i as usize] = self.finish(end, pf);
            }
            steps
        };
        if order.len() <= LEAF_POINTS {
            return each(w, order, out);
        }
        // The ball around the points: center of their box, radius to the
        // farthest (a hair more, for its rounding).
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for &i in order.iter() {
            let p = Vec3::from(points[i as usize]);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let c = (lo + hi) * 0.5;
        let radius = order
            .iter()
            .map(|&i| {
                Vec3::from(points[i as usize])
                    .as_dvec3()
                    .distance_squared(c.as_dvec3())
            })
            .fold(0.0f64, f64::max)
            .sqrt()
            * (1.0 + 1e-6);
        if !(c.is_finite() && radius.is_finite()) {
            return each(w, order, out);
        }
        let radius = radius as f32;
        let cmag = c.abs().max_element() + radius;
        let mut dc: Vec<f32> = Vec::new();
        let mut risky: Vec<usize> = Vec::new();
        // Steps taken point by point so far.
        let mut alone = 0;
        while let Some((k, first, at)) = self.previous_touch(&w) {
            let start = self.ring_start[k as usize] as usize;
            let ring = &self.rings[start..self.ring_start[k as usize + 1] as usize];
            let Some(i) = self.project_on_edge_ring(k as usize, first, c) else {
                w.bound = k;
                w.at = at;
                continue;
            };
            // Every ring triangle is within `radius` of its distance from
            // the center at any point of the ball: those farther from the
            // center than the candidate by more than twice that (and a
            // margin) are no point's choice.
            self.ring_distances(k as usize, c, &mut dc);
            let first = first as usize;
            let best = &self.rings[i];
            let d = dc[i - start].sqrt();
            let above = Above::new(best, c.as_dvec3(), radius as f64);
            // Ring triangles that may be some point's choice.
            risky.clear();
            for (j, t) in ring.iter().enumerate() {
                if start + j == i {
                    continue;
                }
                let margin = 1e-7 * ring[first].radius + MARGIN * (cmag + best.mag + t.mag);
                let tau = d + 2.0 * radius + margin;
                // `!(x > y)` keeps NaN as risky.
                if c.distance(t.center) - t.radius > tau * (1.0 + 1e-5) + 1e-12 {
                    continue;
                }
                if dc[j].sqrt() > tau {
                    continue;
                }
                if !above.as_ref().is_some_and(|a| a.clears(t, margin as f64)) {
                    risky.push(j);
                }
            }
            if risky.is_empty() {
                w.face = best.face;
                w.last = Some(i as u32);
                w.bound = k;
                w.at = at;
                continue;
            }
            if risky.len() >= SPLIT_RISKY && order.len() >= SPLIT_POINTS {
                // Many candidates: a smaller ball has fewer.
                let axis = (hi - lo).max_position();
                let mid = c[axis];
                let mut split = 0;
                for j in 0..order.len() {
                    if points[order[j] as usize][axis] < mid {
                        order.swap(j, split);
                        split += 1;
                    }
                }
                if split == 0 || split == order.len() {
                    return alone + each(w, order, out);
                }
                let (a, b) = order.split_at_mut(split);
                return alone
                    + self.map_batch(w, points, a, out)
                    + self.map_batch(w, points, b, out);
            }
            // A few candidates: each point takes its own step among them
            // (every other triangle is farther from every point of the
            // ball), and the points part by their pick.
            let candidates = Candidates::new(
                &self.blocks[self.block_start[k as usize] as usize..],
                i - start,
                &risky,
            );
            let mut picks: Vec<(u32, u32)> = order
                .iter()
                .map(|&p| {
                    let pf = Vec3::from(points[p as usize]);
                    let pick = match candidates.pick(pf, first, ring[first].radius) {
                        Some(j) => Some(start + j),
                        None => self.project_on_edge_ring(k as usize, first as u32, pf),
                    };
                    // Some: the ring holds the center's pick.
                    (pick.unwrap_or(i) as u32, p)
                })
                .collect();
            alone += order.len();
            if picks.iter().all(|p| p.0 == picks[0].0) {
                // No branch here after all: go on together.
                let t = picks[0].0;
                w.face = self.rings[t as usize].face;
                w.last = Some(t);
                w.bound = k;
                w.at = at;
                continue;
            }
            picks.sort_unstable();
            for (slot, pick) in order.iter_mut().zip(&picks) {
                *slot = pick.1;
            }
            let mut from = 0;
            for run in picks.chunk_by(|a, b| a.0 == b.0) {
                let t = run[0].0;
                let next = Walk {
                    face: self.rings[t as usize].face,
                    bound: k,
                    last: Some(t),
                    at,
                    steps: w.steps,
                };
                alone += self.map_batch(next, points, &mut order[from..from + run.len()], out);
                from += run.len();
            }
            return alone;
        }
        for &i in order.iter() {
            let pf = Vec3::from(points[i as usize]);
            out[i as usize] = self.finish(w, pf);
        }
        alone
    }

    /// The last collapse before `w.bound` whose vertex one-ring holds
    /// `w.face`, the index within its ring of the face's first triangle,
    /// and the collapse's index in `touch`.
    #[inline]
    fn previous_touch(&self, w: &Walk) -> Option<(u32, u32, u32)> {
        let f = w.face as usize;
        let (lo, hi) = (
            self.touch_start[f] as usize,
            self.touch_start[f + 1] as usize,
        );
        let at = w.at as usize;
        // Lists are ascending: entries before `bound`'s own are the
        // earlier collapses. Else (the face changed) search.
        let end = if (lo..hi).contains(&at) && self.touch[at] == w.bound {
            at
        } else {
            lo + self.touch[lo..hi].partition_point(|&k| k < w.bound)
        };
        let i = end.checked_sub(1).filter(|&i| i >= lo)?;
        Some((self.touch[i], self.touch_first[i], i as u32))
    }

    /// The triangle (index into `rings`) of collapse `k`'s edge one-ring,
    /// as the ring recorded it (positions before the collapse), holding
    /// the point closest to `pf`: the least distance, ties to the earlier
    /// triangle, so the answer is deterministic, except that a point on
    /// triangle `first` of the ring (its current face's: the vertex
    /// one-ring after a collapse is part of the edge one-ring before it)
    /// stays there. `None` for an empty ring.
    fn project_on_edge_ring(&self, k: usize, first: u32, pf: Vec3) -> Option<usize> {
        let start = self.ring_start[k] as usize;
        let n = self.ring_start[k + 1] as usize - start;
        let first = first as usize;
        if first >= n {
            return None;
        }
        let blocks = &self.blocks[self.block_start[k] as usize..self.block_start[k + 1] as usize];
        // The current face's block first: a point on its own face (flat
        // regions, untouched geometry) stays there. The tolerance is far
        // below `f32` rounding of the triangle's size, so this only settles
        // exact ties.
        let fb = first / LANES;
        let d = blocks[fb].distances(pf);
        if d[first % LANES] <= (1e-7 * self.rings[start + first].radius).powi(2) {
            return Some(start + first);
        }
        // Else the least distance, ties to the earlier triangle.
        let (mut best_d2, mut best_i) = (f32::INFINITY, usize::MAX);
        let mut take = |b: usize, d: [f32; LANES]| {
            for (l, &d2) in d.iter().enumerate() {
                let i = b * LANES + l;
                if i >= n {
                    break;
                }
                if d2 < best_d2 || (d2 == best_d2 && i < best_i) || best_i == usize::MAX {
                    (best_i, best_d2) = (i, d2);
                }
            }
        };
        take(fb, d);
        for (b, block) in blocks.iter().enumerate() {
            if b != fb {
                take(b, block.distances(pf));
            }
        }
        Some(start + best_i)
    }

    /// The squared distances from `p` to the triangles of collapse `k`'s
    /// ring, as [`SuccessiveMap::project_on_edge_ring`] measures them.
    fn ring_distances(&self, k: usize, p: Vec3, out: &mut Vec<f32>) {
        let n = (self.ring_start[k + 1] - self.ring_start[k]) as usize;
        out.clear();
        for block in &self.blocks[self.block_start[k] as usize..self.block_start[k + 1] as usize] {
            out.extend_from_slice(&block.distances(p));
        }
        out.truncate(n);
    }

    /// Barycentrics of `q` on input face `face` (fan-triangulated; the
    /// closest fan triangle, ties to the first).
    fn on_input_face(&self, face: u32, q: DVec3) -> SurfacePoint {
        let f = face as usize;
        let start = self.faces.offsets[f];
        let corners = self.faces.face(f);
        let at = |k: usize| DVec3::from(self.positions[corners[k] as usize].map(f64::from));
        let mut best = (f64::INFINITY, 1usize, [1.0, 0.0, 0.0]);
        for t in 1..corners.len().saturating_sub(1) {
            let (point, bary) = closest_point_on_triangle(q, at(0), at(t), at(t + 1));
            let d2 = (point - q).length_squared();
            if d2 < best.0 {
                best = (d2, t, bary);
            }
        }
        let (_, t, b) = best;
        SurfacePoint {
            face,
            corners: [start, start + t as u32, start + t as u32 + 1],
            bary: [b[0] as f32, b[1] as f32, b[2] as f32],
        }
    }

    /// The input position of a mapped point.
    pub fn position(&self, s: &SurfacePoint) -> [f32; 3] {
        let mut out = [0.0f32; 3];
        for (k, &c) in s.corners.iter().enumerate() {
            let p = self.positions[self.faces.indices[c as usize] as usize];
            for a in 0..3 {
                out[a] += s.bary[k] * p[a];
            }
        }
        out
    }

    /// How many collapses the walk for `face` would visit at most: the
    /// length of its touch list (for statistics and tests).
    pub fn touches(&self, face: u32) -> usize {
        let f = face as usize;
        (self.touch_start[f + 1] - self.touch_start[f]) as usize
    }
}

/// The triangles of a ring that may be the closest to some point of a
/// ball (the center's pick and those no bound rules out), gathered into
/// blocks of their own: a point of the ball measures only them, and picks
/// as [`SuccessiveMap::project_on_edge_ring`] does over the whole ring
/// (every other triangle is farther from it by a margin).
struct Candidates {
    /// Ring-local indices, ascending.
    index: Vec<usize>,
    blocks: Vec<RingBlock>,
}

impl Candidates {
    /// The candidates `pick` and `risky` (ring-local) of the ring whose
    /// blocks start `blocks`.
    fn new(blocks: &[RingBlock], pick: usize, risky: &[usize]) -> Candidates {
        let mut index = Vec::with_capacity(risky.len() + 1);
        index.push(pick);
        index.extend_from_slice(risky);
        index.sort_unstable();
        let mut gathered = vec![RingBlock::default(); index.len().div_ceil(LANES)];
        for (c, &j) in index.iter().enumerate() {
            blocks[j / LANES].copy_lane(j % LANES, &mut gathered[c / LANES], c % LANES);
        }
        Candidates {
            index,
            blocks: gathered,
        }
    }

    /// The ring-local index of `pf`'s pick, as the whole ring's: a point
    /// on the current face's triangle `first` (radius `first_radius`)
    /// stays there, else the least distance, ties to the earlier
    /// triangle. `None` where a distance is not finite: the whole ring then
    /// decides, in its own order.
    #[inline]
    fn pick(&self, pf: Vec3, first: usize, first_radius: f32) -> Option<usize> {
        let (mut best_d2, mut best) = (f32::INFINITY, usize::MAX);
        let mut own = false;
        for (b, block) in self.blocks.iter().enumerate() {
            let d = block.distances(pf);
            for (l, &d2) in d.iter().enumerate() {
                let Some(&j) = self.index.get(b * LANES + l) else {
                    break;
                };
                if !d2.is_finite() {
                    return None;
                }
                if j == first && d2 <= (1e-7 * first_radius).powi(2) {
                    own = true;
                }
                if d2 < best_d2 || (d2 == best_d2 && j < best) {
                    (best_d2, best) = (d2, j);
                }
            }
        }
        Some(if own { first } else { best })
    }
}

/// A ball of points whose closest points on a ring triangle `T` all lie
/// inside it (the ball's shadow on `T`'s plane is inside `T`): the distance
/// to `T` is then the distance to its plane, `|h|`, an affine function
/// over the ball, and another triangle `T'` at `d'² = h'² + e'²` (`h'` to
/// its plane, `e'` in its plane) is farther from every point when
/// `h'² − h² + e'²` stays positive. That is far tighter than comparing
/// distances at the center with twice the radius for a point hovering over
/// a patch of small triangles, as a coarse LOD's surface does: there the
/// two distances differ by about `e'²/2h`, and a ball of any useful size
/// would never clear the neighbours.
struct Above {
    center: DVec3,
    radius: f64,
    normal: DVec3,
    /// Signed distance of the center to `T`'s plane.
    h: f64,
}

impl Above {
    /// `None` when `T` is degenerate or the ball's shadow leaves it.
    fn new(t: &RingTriangle, center: DVec3, radius: f64) -> Option<Above> {
        let [a, b, c] = t.corners.map(|q| q.as_dvec3());
        let normal = (b - a).cross(c - a).try_normalize()?;
        for (p, q, r) in [(a, b, c), (b, c, a), (c, a, b)] {
            let m = normal.cross(q - p).try_normalize()?;
            // Inward edge normal: the shadow is inside when the center is
            // at least `radius` inside every edge line.
            let m = if m.dot(r - p) < 0.0 { -m } else { m };
            // (NaN refuses too.)
            if m.dot(center - p).partial_cmp(&radius) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
        }
        Some(Above {
            center,
            radius,
            normal,
            h: normal.dot(center - a),
        })
    }

    /// Whether `t` is farther than `T` from every point of the ball by
    /// more than `margin`.
    fn clears(&self, t: &RingTriangle, margin: f64) -> bool {
        let [a, b, c] = t.corners.map(|q| q.as_dvec3());
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            return false;
        };
        let (ctr, r) = (self.center, self.radius);
        // h' − h and h' + h over the ball: affine, within their gradient's
        // length times the radius of the center's values.
        let hj = n.dot(ctr - a);
        let (da, db) = (hj - self.h, hj + self.h);
        let (ra, rb) = (
            (n - self.normal).length() * r,
            (n + self.normal).length() * r,
        );
        let planes = [
            (da - ra) * (db - rb),
            (da - ra) * (db + rb),
            (da + ra) * (db - rb),
            (da + ra) * (db + rb),
        ]
        .into_iter()
        .fold(f64::INFINITY, f64::min);
        // e' is at least the ball's distance beyond an edge line of `t`.
        let mut sep = 0.0f64;
        for (p, q, o) in [(a, b, c), (b, c, a), (c, a, b)] {
            let Some(m) = n.cross(q - p).try_normalize() else {
                continue;
            };
            let m = if m.dot(o - p) > 0.0 { -m } else { m };
            sep = sep.max(m.dot(ctr - p) - r);
        }
        let gap2 = planes + sep * sep;
        // d ≤ |h| + r over the ball; d' ≥ √(d² + gap2), and √(x + g) − √x
        // falls as x grows.
        let far = self.h.abs() + r;
        gap2 > 0.0 && (far * far + gap2).sqrt() - far > margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_simplify::RingInput;

    /// The unit square as four triangles around its center, vertex 4:
    ///
    /// ```text
    ///  3 ────── 2
    ///  │ ╲ f2 ╱ │
    ///  │f3  4 f1│      f0 = [0,1,4]  f1 = [1,2,4]
    ///  │ ╱ f0 ╲ │      f2 = [2,3,4]  f3 = [3,0,4]
    ///  0 ────── 1
    /// ```
    fn square() -> (Vec<[f32; 3]>, Faces) {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 0.0],
        ];
        let f = Faces::from_triangles(&[0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4]);
        (p, f)
    }

    /// Collapse 0: vertex 4 into vertex 0, which stays at (0,0). f0 and f3
    /// degenerate; f1 = [1,2,0] and f2 = [2,3,0] remain around vertex 0.
    /// Collapse 1 (when `two`): vertex 2 into vertex 1 at (1,0). f1
    /// degenerates; f2 = [1,3,0] remains.
    fn history(p: &[[f32; 3]], two: bool) -> History {
        let mut h = History::default();
        let ring0: Vec<(u32, Vec<u32>)> = vec![
            (0, vec![0, 1, 4]),
            (1, vec![1, 2, 4]),
            (2, vec![2, 3, 4]),
            (3, vec![3, 0, 4]),
        ];
        let pos = |v: &[u32]| v.iter().map(|&i| p[i as usize]).collect::<Vec<_>>();
        let owned: Vec<(u32, Vec<u32>, Vec<[f32; 3]>)> =
            ring0.iter().map(|(f, v)| (*f, v.clone(), pos(v))).collect();
        let before: Vec<RingInput> = owned
            .iter()
            .map(|(f, v, q)| (*f, v.as_slice(), q.as_slice()))
            .collect();
        h.push(0, 4, &before, &[1, 2]);
        if two {
            // Level 1 geometry: vertex 0 at (0,0), 4 gone.
            let ring1: Vec<(u32, Vec<u32>)> = vec![(1, vec![1, 2, 0]), (2, vec![2, 3, 0])];
            let owned: Vec<(u32, Vec<u32>, Vec<[f32; 3]>)> =
                ring1.iter().map(|(f, v)| (*f, v.clone(), pos(v))).collect();
            let before: Vec<RingInput> = owned
                .iter()
                .map(|(f, v, q)| (*f, v.as_slice(), q.as_slice()))
                .collect();
            h.push(1, 2, &before, &[2]);
        }
        h
    }

    fn assert_point(s: SurfacePoint, face: u32, corners: [u32; 3], bary: [f32; 3]) {
        assert_eq!((s.face, s.corners), (face, corners), "{s:?}");
        for k in 0..3 {
            assert!((s.bary[k] - bary[k]).abs() < 1e-6, "{s:?} vs {bary:?}");
        }
    }

    #[test]
    fn point_on_a_surviving_face_maps_to_the_input_face_holding_it() {
        let (p, f) = square();
        let h = history(&p, false);
        let map = SuccessiveMap::new(&h, &p, &f);
        // (0.75, 0.5) on output face 1 = (1,0),(1,1),(0,0). In the input it
        // lies on f1 = (1,0),(1,1),(½,½): a + b + ½c = ¾, b + ½c = ½,
        // a + b + c = 1 → a = ¼, b = ¼, c = ½.
        assert_point(
            map.map(1, [0.75, 0.5, 0.0]),
            1,
            [3, 4, 5],
            [0.25, 0.25, 0.5],
        );
    }

    #[test]
    fn point_can_land_on_a_face_the_collapse_deleted() {
        let (p, f) = square();
        let h = history(&p, false);
        let map = SuccessiveMap::new(&h, &p, &f);
        // (0.4, 0.1) on output face 1 lies on input f0 = (0,0),(1,0),(½,½):
        // ½c = 0.1 → c = 0.2; b + 0.1 = 0.4 → b = 0.3; a = 0.5.
        assert_point(map.map(1, [0.4, 0.1, 0.0]), 0, [0, 1, 2], [0.5, 0.3, 0.2]);
    }

    #[test]
    fn walk_visits_every_collapse_whose_vertex_ring_holds_the_face() {
        let (p, f) = square();
        let h = history(&p, true);
        let map = SuccessiveMap::new(&h, &p, &f);
        assert_eq!((map.touches(1), map.touches(2), map.touches(0)), (1, 2, 0));
        // (0.3, 0.6) on the last face, 2 = (1,0),(0,1),(0,0). Collapse 1
        // puts it on f2 = (1,1),(0,1),(0,0); collapse 0 on input
        // f3 = (0,1),(0,0),(½,½): ½c = 0.3 → c = 0.6; a + 0.3 = 0.6 →
        // a = 0.3; b = 0.1.
        assert_point(map.map(2, [0.3, 0.6, 0.0]), 3, [9, 10, 11], [0.3, 0.1, 0.6]);
    }

    /// A ball's candidates pick as the whole ring does: with every ring
    /// triangle a candidate, on and off the ring's plane, on shared edges
    /// (ties go to the earlier triangle) and on the current face's own
    /// triangle (it stays there).
    #[test]
    fn candidates_pick_as_the_whole_ring() {
        let (p, f) = square();
        let h = history(&p, false);
        let map = SuccessiveMap::new(&h, &p, &f);
        let blocks = &map.blocks[map.block_start[0] as usize..map.block_start[1] as usize];
        let ring = &map.rings[map.ring_start[0] as usize..map.ring_start[1] as usize];
        assert_eq!(ring.len(), 4);
        let mut picked = std::collections::BTreeSet::new();
        for pick in 0..4 {
            let risky: Vec<usize> = (0..4).filter(|&j| j != pick).collect();
            let candidates = Candidates::new(blocks, pick, &risky);
            for (first, own) in ring.iter().enumerate() {
                for i in -2..=12 {
                    for j in -2..=12 {
                        for z in [0.0, 0.05, -0.3] {
                            let q = Vec3::new(i as f32 / 10.0, j as f32 / 10.0, z);
                            let whole = map.project_on_edge_ring(0, first as u32, q);
                            let some = candidates.pick(q, first, own.radius);
                            assert_eq!(some, whole, "pick {pick} first {first} at {q:?}");
                            picked.insert(whole);
                        }
                    }
                }
            }
        }
        // Every triangle is some point's pick.
        assert_eq!(picked.len(), 4, "{picked:?}");
    }

    #[test]
    fn queries_use_the_final_position_even_off_the_input_plane() {
        let (p, f) = square();
        let h = history(&p, true);
        let map = SuccessiveMap::new(&h, &p, &f);
        // The same point lifted off the plane projects to the same place.
        assert_point(
            map.map(2, [0.3, 0.6, 0.25]),
            3,
            [9, 10, 11],
            [0.3, 0.1, 0.6],
        );
    }

    #[test]
    fn untouched_face_keeps_its_own_barycentrics() {
        let (p, f) = square();
        let h = History::default();
        let map = SuccessiveMap::new(&h, &p, &f);
        // No collapse: f2 = (1,1),(0,1),(½,½); its centroid has ⅓ each.
        let c = [0.5, 2.5 / 3.0, 0.0];
        assert_point(map.map(2, c), 2, [6, 7, 8], [1.0 / 3.0; 3]);
    }

    #[test]
    fn quad_input_face_gets_the_fan_triangle_holding_the_point() {
        // One quad 0-1-2-3; no collapse. (0.25, 0.75) is in fan triangle
        // (0, 2, 3): a(0,0) + b(1,1) + c(0,1) → x: b = ¼, y: b + c = ¾ →
        // c = ½, a = ¼.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mut f = Faces::new();
        f.push(&[0, 1, 2, 3]);
        let h = History::default();
        let map = SuccessiveMap::new(&h, &p, &f);
        assert_point(
            map.map(0, [0.25, 0.75, 0.0]),
            0,
            [0, 2, 3],
            [0.25, 0.25, 0.5],
        );
    }

    /// W Fig. 17: a thin shell (two sheets 0.01 apart, the lower one
    /// collapsed first). A point on the upper sheet's face stays on the
    /// upper sheet's faces even where the lower sheet is as close.
    #[test]
    fn thin_shell_point_stays_on_its_sheet() {
        // Lower sheet: triangle 0 at z = 0; upper sheet: triangles 1, 2 at
        // z = 0.01. Collapse 0 touches only the upper sheet's faces.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.01],
            [1.0, 0.0, 0.01],
            [0.0, 1.0, 0.01],
            [0.3, 0.3, 0.01],
        ];
        let f = Faces::from_triangles(&[0, 1, 2, 3, 4, 6, 3, 6, 5]);
        let mut h = History::default();
        let r1: [u32; 3] = [3, 4, 6];
        let r2: [u32; 3] = [3, 6, 5];
        let pos = |v: &[u32; 3]| v.map(|i| p[i as usize]);
        let (q1, q2) = (pos(&r1), pos(&r2));
        h.push(3, 6, &[(1, &r1, &q1), (2, &r2, &q2)], &[1]);
        let map = SuccessiveMap::new(&h, &p, &f);
        // A point below the upper sheet (closer to the lower one) on
        // output face 1 still maps onto the upper sheet.
        let s = map.map(1, [0.2, 0.1, 0.004]);
        assert!(s.face == 1 || s.face == 2, "{s:?}");
    }

    fn assert_same(a: &SurfacePoint, b: &SurfacePoint, what: &str) {
        assert_eq!(
            (a.face, a.corners),
            (b.face, b.corners),
            "{what}: {a:?} vs {b:?}"
        );
        for k in 0..3 {
            assert!(
                (a.bary[k] - b.bary[k]).abs() <= 1e-6,
                "{what}: {a:?} vs {b:?}"
            );
        }
    }

    /// A bumpy quad sphere (polygon faces: fan triangles on both sides of
    /// the map) with a deterministic jitter on every vertex, like a scan.
    fn scan_like(n: usize) -> wildlod_mesh::Mesh {
        let mut m = wildlod_mesh::shapes::bumpy_quad_sphere(n);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for p in &mut m.positions {
            for c in p.iter_mut() {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                *c += ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.01;
            }
        }
        m
    }

    /// Every texel of a `size`² atlas of the LOD of `mesh` with `triangles`
    /// left, mapped texel by texel and tile by tile ([`SuccessiveMap::map_texels`]):
    /// the same input face and corners, barycentrics within 1e-6. Returns
    /// (point steps of the per-texel walks, the same made point by point
    /// by [`SuccessiveMap::map_many`]).
    fn coherent_equals_per_texel(
        mesh: &wildlod_mesh::Mesh,
        triangles: usize,
        size: u32,
    ) -> (usize, usize) {
        use wildlod_simplify::{simplify_polygons, Options, Record, Target};
        let options = Options {
            target: Target {
                triangles: Some(triangles),
                ..Target::default()
            },
            record: Record {
                history: true,
                ..Record::default()
            },
            ..Options::default()
        };
        let lod = simplify_polygons(&mesh.positions, &mesh.faces, &options).expect("simplifies");
        let history = lod.history.as_ref().expect("recorded");
        let map = SuccessiveMap::new(history, &mesh.positions, &mesh.faces);
        let mut tris = Vec::new();
        let mut tri_face = Vec::new();
        for f in 0..lod.faces.len() {
            let face = lod.faces.face(f);
            for k in 1..face.len() - 1 {
                tris.push([face[0], face[k], face[k + 1]]);
                tri_face.push(lod.face_origin[f]);
            }
        }
        let atlas = crate::atlas::build_atlas(
            &lod.positions,
            &tris,
            &[],
            &crate::atlas::AtlasOptions {
                size,
                ..crate::atlas::AtlasOptions::default()
            },
        );
        let cov = crate::raster::rasterize(&atlas.corner_uvs, size, 1.5);
        let texel = |i: usize| {
            let t = cov.triangle[i];
            if t == crate::raster::NO_TRIANGLE {
                return None;
            }
            let (b, tri) = (cov.bary[i], tris[t as usize]);
            let mut p = [0.0f32; 3];
            for (&v, &wk) in tri.iter().zip(&b) {
                for (pa, &qa) in p.iter_mut().zip(&lod.positions[v as usize]) {
                    *pa += wk * qa;
                }
            }
            Some((t, tri_face[t as usize], p))
        };
        let n = size as usize;
        let coherent = map.map_texels(n, 0..n, texel);
        let (mut texels, mut steps) = (0, 0);
        for (i, hit) in coherent.iter().enumerate() {
            match (texel(i), hit) {
                (Some((_, face, p)), Some(hit)) => {
                    texels += 1;
                    steps += map.walk(map.start(face), Vec3::from(p)).steps as usize;
                    assert_same(hit, &map.map(face, p), &format!("texel {i}"));
                }
                (None, None) => {}
                (a, b) => panic!("texel {i}: owner {a:?}, mapped {b:?}"),
            }
        }
        // Once more triangle by triangle, counting the lone walks.
        let mut alone = 0;
        for t in 0..tris.len() as u32 {
            let points: Vec<[f32; 3]> = (0..n * n)
                .filter_map(texel)
                .filter(|x| x.0 == t)
                .map(|x| x.2)
                .collect();
            let mut out = vec![map.placeholder(); points.len()];
            alone += map.map_many_counted(tri_face[t as usize], &points, &mut out);
        }
        assert!(texels > 10_000, "{texels}");
        (steps, alone)
    }

    #[test]
    fn coherent_mapping_equals_per_texel_mapping_at_a_coarse_target() {
        let (steps, alone) = coherent_equals_per_texel(&scan_like(8), 12, 512);
        assert!(alone <= steps, "{alone} of {steps} steps taken alone");
    }

    #[test]
    fn coherent_mapping_equals_per_texel_mapping_at_a_fine_target() {
        let (steps, alone) = coherent_equals_per_texel(&scan_like(8), 300, 512);
        assert!(alone <= steps, "{alone} of {steps} steps taken alone");
    }

    /// The square after both collapses: output face 2 = (1,0),(0,1),(0,0)
    /// came from input faces 0..4; a grid of points over it parts into
    /// several input faces, and every one maps as on its own.
    #[test]
    fn coherent_mapping_follows_paths_that_branch_inside_a_triangle() {
        let (p, f) = square();
        let h = history(&p, true);
        let map = SuccessiveMap::new(&h, &p, &f);
        let n = 40;
        let mut points = Vec::new();
        for i in 0..=n {
            for j in 0..=n - i {
                let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
                // Lifted off the plane a little, as a LOD's surface is.
                points.push([x, y, 0.05 * x * y]);
            }
        }
        let mut out = vec![map.placeholder(); points.len()];
        let alone = map.map_many_counted(2, &points, &mut out);
        let mut faces = std::collections::BTreeSet::new();
        let mut steps = 0;
        for (k, &q) in points.iter().enumerate() {
            assert_same(&out[k], &map.map(2, q), &format!("{q:?}"));
            faces.insert(out[k].face);
            steps += map.walk(map.start(2), Vec3::from(q)).steps as usize;
        }
        assert!(faces.len() >= 3, "{faces:?}");
        assert!(alone <= steps, "{alone} of {steps} steps taken alone");
    }

    /// A patch of texels well inside what one input face became, lifted
    /// off it as a LOD's surface is, follows one path: the batch takes
    /// every step once, no point walks alone.
    #[test]
    fn coherent_mapping_shares_the_walk_of_a_patch_that_does_not_branch() {
        let (p, f) = square();
        let h = history(&p, true);
        let map = SuccessiveMap::new(&h, &p, &f);
        let mut points = Vec::new();
        for i in 0..10 {
            for j in 0..10 {
                let (x, y) = (0.1 + 0.002 * i as f32, 0.4 + 0.002 * j as f32);
                points.push([x, y, 0.01]);
            }
        }
        let mut out = vec![map.placeholder(); points.len()];
        let alone = map.map_many_counted(2, &points, &mut out);
        let mut steps = 0;
        for (k, &q) in points.iter().enumerate() {
            assert_same(&out[k], &map.map(2, q), &format!("{q:?}"));
            steps += map.walk(map.start(2), Vec3::from(q)).steps as usize;
        }
        assert!(steps >= points.len(), "every point steps at least once");
        assert_eq!(alone, 0, "of {steps} steps");
    }
}
