//! Step 5 of the simplifier: refitting the simplified surface to the input,
//! once the collapses are done.
//!
//! Every vertex was placed where its quadric (the planes of the input faces
//! merged into it, W Eq. 13–14) is smallest *when it was made*. Later
//! collapses around it change the faces it spans, so at the end the output
//! no longer lies where the input does: a vertex that was right for the
//! faces of its day leaves the input's points between it and its newer
//! neighbours farther from the output than they need be. That is one-sided:
//! the quadric measures the output vertices' distance to the input's planes
//! and never the input's distance to the output, which is half of what
//! Chamfer and Hausdorff distances measure.
//!
//! The refit adds that half. A few Jacobi sweeps move every vertex to the
//! minimizer of
//!
//! `Q_v(p) + Σ w_i (b_i n_i·(p − p_v) − r_i)² + λ W_v |p − p_v|²`
//!
//! where `Q_v` is the vertex's own quadric (which keeps it on the input's
//! planes: a sharp corner stays put), the sum runs over the input vertices
//! whose closest point on the output lies on a face of `v` (with weight
//! `w_i` their area share, as in `Q_v`; `b_i` the barycentric weight of `v`
//! at that point, `n_i` the face's normal, `r_i` the signed distance along
//! it), and the last term damps the step. Both terms are area-weighted
//! squared distances, so they balance at every scale. `Q_v` is taken
//! without its regularization part, whose pull toward the merged vertices'
//! centre would move a vertex off the planes that hold it. Input points are
//! matched only to faces around the output vertex they were merged into and
//! only to faces within 60° of their own normal: a crease's other side and
//! a thin part's other side are never pulled in. A point whose closest
//! point lies on the outline of those faces, or beside a face rather than
//! above it, or on a sliver, is not matched: its offset along the face's
//! normal is no distance to the surface, and fitting it pulled exactly
//! simplified flat parts off their planes. Repeated faces and twins
//! of the other orientation count once, as in the quadrics.
//!
//! Three guards keep it safe: a step is at most half the vertex's shortest
//! edge; a vertex never ends farther from the input faces it stands for
//! than it was or than the farthest input point it fits (it trades its own
//! distance for the input's, never beyond the worst it is fitting); and a
//! sweep that would turn a face by more than the flip guard allows (at most
//! a right angle) puts that face's vertices back. Only positions change;
//! attributes are fitted at the new positions like after any collapse.
//!
//! Not part of either paper: measured on the corpus against the peers
//! (`docs/design.md`, "Refit").

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use smallvec::SmallVec;
use wildlod_geometry::closest_point_on_triangle;

use wildlod_mesh::Faces;

use crate::collapse::Collapsed;
use crate::prepare::complex::Complex;
use crate::prepare::geometry::polygon_normal;
use crate::terms::quadric::Quadric;
use crate::terms::stored::{Isotropic, StoredQuadric};

/// The final refit of a finished run against the input (`positions`,
/// and the `faces` over them) that the complex kept (`kept`, per face;
/// empty: all). With the history recorded too: successive mapping projects
/// the final mesh's points onto the recorded one-rings by closest point (W
/// §4.3.1), which a surface moved closer to the input only helps.
pub(crate) fn refit_run(
    run: &mut Collapsed<'_>,
    positions: &[[f32; 3]],
    faces: &Faces,
    kept: &[bool],
) {
    let sweeps = run.options.metric.refit_sweeps;
    // Soft symmetry asks for a mirror-symmetric result: vertices on the
    // mirror plane stay on it, which a fit to the input points around
    // them, never quite symmetric, would undo.
    // Nothing collapsed: the output is the input, already on itself.
    if sweeps == 0
        || run.p.rep.is_empty()
        || run.options.quad.symmetry > 0.0
        || run.report.collapses == 0
    {
        return;
    }
    let root = run.roots();
    let c = &run.p.complex;
    let fixed: Vec<bool> = if run.options.guards.lock_borders && c.has_adjacency() {
        (0..c.pos.len() as u32).map(|v| c.on_boundary(v)).collect()
    } else {
        Vec::new()
    };
    // Never more than a right angle, whatever the flip guard allows.
    let min_cos = run
        .options
        .guards
        .max_normal_turn_degrees
        .map_or(0.0, |d| d.to_radians().cos().max(0.0));
    // What neither the refit nor `assemble` reads, freed first: the
    // refit then fits under the run's earlier peak.
    run.p.complex.clear_adjacency();
    // The input's positions by welded vertex, made now that the run's
    // adjacency is gone.
    let welded: Vec<[f32; 3]> = run.p.rep.iter().map(|&v| positions[v as usize]).collect();
    let origins = run.p.complex.pos.clone();
    let input = RefitInput {
        positions: &welded,
        center: run.p.center,
        scale: run.p.scale,
        offsets: &faces.offsets,
        indices: &faces.indices,
        weld: &run.p.weld,
        kept,
        root: &root,
        quadrics: &run.quadrics,
        origins: &origins,
        regularization: &run.reg,
        fixed: &fixed,
        min_cos,
        exact_flat_borders: run.exact_flat_borders,
    };
    let moved = refit(&mut run.p.complex, &input, sweeps);
    for (m, r) in run.moved.iter_mut().zip(moved) {
        *m |= r;
    }
}

/// Damping λ of a vertex's step, relative to the weight it carries: small
/// enough that a vertex goes nearly all the way to its minimizer, large
/// enough to keep the solve well conditioned where the planes are flat.
const DAMPING: f64 = 0.05;

/// A step is at most this fraction of the vertex's shortest edge, so that
/// a sweep, where every vertex moves at once, cannot fold a face over.
const MAX_STEP: f64 = 0.5;

/// An input point is matched only to output faces whose normal is within
/// 60° of its own: a face turned farther away stands for another part of
/// the surface (the other side of a crease or of a thin part), and pulling
/// the point onto it would round the crease off.
const FACING: f64 = 0.5;

/// A face whose area is at most this share of its longest side squared (a
/// height under a millionth of that side, its corners in a line up to
/// rounding) has no normal to measure a distance along: its computed
/// normal is rounding noise. No point is matched to it. On a box with
/// raised panels reduced exactly, such a sliver along an edge came out 45°
/// off and points 10⁻² above it pulled the box off its planes.
const SLIVER: f64 = 1e-6;

/// A barycentric weight at most this puts a closest point on the side of
/// its triangle opposite that corner.
const ON_SIDE: f64 = 1e-12;

/// Input points handled per parallel block: bounds the memory of the
/// matches, which are applied block by block.
const BLOCK: usize = 1 << 14;

/// What the refit works from: the input surface, and where each input
/// vertex went.
pub(crate) struct RefitInput<'a> {
    /// Input positions, one per welded vertex, in the input's coordinates.
    pub positions: &'a [[f32; 3]],
    /// The complex's coordinates are `(p − center) / scale`.
    pub center: DVec3,
    pub scale: f64,
    /// Input faces: `offsets` (one past the last too) into `indices`, which
    /// are input vertex ids, welded by `weld` (empty: already welded).
    pub offsets: &'a [u32],
    pub indices: &'a [u32],
    pub weld: &'a [u32],
    /// Which input faces count (empty: all): those the complex kept, so
    /// that a repeated face or a twin of the other orientation counts once,
    /// as in the quadrics.
    pub kept: &'a [bool],
    /// The output vertex every welded vertex was merged into (itself when
    /// it survived).
    pub root: &'a [u32],
    /// The output vertices' quadrics, and the regularization part of each
    /// (taken back out: its pull toward the input vertices' centre would
    /// move a vertex off the planes that hold it; the damping steadies the
    /// solve instead).
    pub quadrics: &'a [StoredQuadric],
    /// The positions the quadrics were stored about (see `stored.rs`): the
    /// vertices' before the refit moves them.
    pub origins: &'a [DVec3],
    pub regularization: &'a [Isotropic],
    /// Vertices that must not move (locked borders); empty: none.
    pub fixed: &'a [bool],
    /// Whether border vertices of planar regions stay (see
    /// [`on_a_flat_border`]); as `CostModel::exact_flat_borders`.
    pub exact_flat_borders: bool,
    /// The flip guard's bound: a face's normal may turn by at most this
    /// cosine in one sweep.
    pub min_cos: f64,
}

impl RefitInput<'_> {
    /// Welded input vertex `w` in the complex's coordinates.
    fn point(&self, w: u32) -> DVec3 {
        (DVec3::from(self.positions[w as usize].map(f64::from)) - self.center) / self.scale
    }

    fn face_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether input face `f` counts.
    fn counts(&self, f: usize) -> bool {
        self.kept.get(f).copied().unwrap_or(true)
    }

    /// The welded vertices of input face `f`.
    fn face(&self, f: usize) -> impl Iterator<Item = u32> + '_ {
        let (a, b) = (self.offsets[f] as usize, self.offsets[f + 1] as usize);
        self.indices[a..b]
            .iter()
            .map(|&v| self.weld.get(v as usize).copied().unwrap_or(v))
    }
}

/// One input point's match on the output: the face triangle's corners,
/// their barycentric weights, the face normal and the signed distance.
#[derive(Clone, Copy)]
struct Match {
    corners: [u32; 3],
    bary: [f64; 3],
    normal: DVec3,
    distance: f64,
    weight: f64,
}

/// Refits `c`'s vertex positions to the input in `sweeps` Jacobi sweeps
/// (see the module documentation). Returns which vertices moved.
pub(crate) fn refit(c: &mut Complex, input: &RefitInput<'_>, sweeps: u32) -> Vec<bool> {
    let nv = c.pos.len();
    let mut moved = vec![false; nv];
    if sweeps == 0 || input.positions.is_empty() {
        return moved;
    }
    let (weight, normal) = input_vertex_area_and_normal(input);
    let class = class_faces(input, nv);
    for _ in 0..sweeps {
        let star = output_stars(c);
        // The output's vertices, numbered compactly: at a low target most
        // of the complex's vertices are gone.
        let live: Vec<u32> = (0..nv as u32).filter(|&v| !star.of(v).is_empty()).collect();
        let mut slot = vec![u32::MAX; nv];
        for (k, &v) in live.iter().enumerate() {
            slot[v as usize] = k as u32;
        }
        // Per output vertex: the data terms as one quadric, and the
        // largest distance of an input point pulling on it.
        let mut data = vec![Quadric::ZERO; live.len()];
        let mut reach = vec![0.0f64; live.len()];
        let n = input.positions.len();
        for block in (0..n).step_by(BLOCK) {
            let matches: Vec<Option<Match>> = (block..(block + BLOCK).min(n))
                .into_par_iter()
                .map(|i| match_point(c, &star, input, &weight, &normal, i as u32))
                .collect();
            for m in matches.into_iter().flatten() {
                for k in 0..3 {
                    let b = m.bary[k];
                    if b <= 1e-6 {
                        continue;
                    }
                    let v = m.corners[k] as usize;
                    let s = slot[v] as usize;
                    // b n·(p − p_v) = r  ⇔  n·p = n·p_v + r / b, weighed
                    // by w b².
                    let target = c.pos[v] + m.normal * (m.distance / b);
                    data[s] += Quadric::plane(m.normal, target, m.weight * b * b);
                    reach[s] = reach[s].max(m.distance.abs());
                }
            }
        }
        let placed: Vec<DVec3> = live
            .par_iter()
            .zip(&data)
            .zip(&reach)
            .map(|((&v, d), &reach)| place(c, &star, &class, input, v, d, reach))
            .collect();
        drop(data);
        // Every live face with its unit normal before the sweep.
        let faces: Vec<u32> = c.live_faces().collect();
        let before: Vec<DVec3> = faces
            .par_iter()
            .map(|&f| face_normal(c, &c.pos, f).normalize_or_zero())
            .collect();
        let old: Vec<DVec3> = live.iter().map(|&v| c.pos[v as usize]).collect();
        for (&v, &p) in live.iter().zip(&placed) {
            c.pos[v as usize] = p;
        }
        keep_faces_unfolded(c, &faces, &before, &slot, &old, input.min_cos);
        for (k, &v) in live.iter().enumerate() {
            if c.pos[v as usize] != old[k] {
                moved[v as usize] = true;
            }
        }
    }
    moved
}

/// Where vertex `v` goes: the minimizer of its quadric plus its data terms
/// `d`, damped, the step bounded by its shortest edge; and not farther from
/// the input faces it stands for than it was or than the farthest input
/// point it fits (`reach`): it trades its own distance for the input's,
/// never beyond the worst it is fitting.
fn place(
    c: &Complex,
    star: &Stars,
    class: &Stars,
    input: &RefitInput<'_>,
    v: u32,
    d: &Quadric,
    reach: f64,
) -> DVec3 {
    let here = c.pos[v as usize];
    if d.weight <= 0.0
        || input.fixed.get(v as usize).copied().unwrap_or(false)
        || (input.exact_flat_borders && on_a_flat_border(c, star, v))
    {
        return here;
    }
    let q = input
        .quadrics
        .get(v as usize)
        .map_or(Quadric::ZERO, |q| q.quadric(input.origins[v as usize]));
    let q = match input.regularization.get(v as usize) {
        Some(r) => q.minus(&r.quadric()),
        None => q,
    };
    let total = q + *d + Quadric::point(here, DAMPING * (q.weight + d.weight));
    let Some(p) = total.minimizer() else {
        return here;
    };
    let limit = MAX_STEP * shortest_edge(c, star, v);
    let step = p - here;
    let len = step.length();
    if !len.is_finite() {
        return here;
    }
    let p = if len > limit {
        here + step * (limit / len)
    } else {
        here + step
    };
    let faces = class.of(v);
    // Usually some face is within reach at once, and the distances
    // themselves are never needed.
    if !within(input, faces, p, reach)
        && distance_to(input, faces, p) > distance_to(input, faces, here)
    {
        return here;
    }
    p
}

/// Every input vertex's area share (its faces' areas over their corner
/// counts, as in the vertex quadrics) and area-weighted normal.
fn input_vertex_area_and_normal(input: &RefitInput<'_>) -> (Vec<f32>, Vec<Vec3>) {
    let n = input.positions.len();
    let mut area = vec![0.0f32; n];
    let mut normal = vec![Vec3::ZERO; n];
    let mut corners: SmallVec<[DVec3; 8]> = SmallVec::new();
    for f in (0..input.face_count()).filter(|&f| input.counts(f)) {
        corners.clear();
        corners.extend(input.face(f).map(|w| input.point(w)));
        if corners.len() < 3 {
            continue;
        }
        let n2 = polygon_normal(&corners);
        let share = 0.5 * n2.length() / corners.len() as f64;
        if !share.is_finite() {
            continue;
        }
        for w in input.face(f) {
            area[w as usize] += share as f32;
            normal[w as usize] += n2.as_vec3();
        }
    }
    (area, normal)
}

/// A compact index of lists per vertex: `start[v]..start[v + 1]` into
/// `list` (with a value per entry in `normal` where kept).
struct Stars {
    start: Vec<u32>,
    list: Vec<u32>,
    /// Unit normal of each listed face (output stars only).
    normal: Vec<DVec3>,
}

impl Stars {
    fn range(&self, v: u32) -> std::ops::Range<usize> {
        let v = v as usize;
        match (self.start.get(v), self.start.get(v + 1)) {
            (Some(&a), Some(&b)) => a as usize..b as usize,
            _ => 0..0,
        }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.list[self.range(v)]
    }

    /// Fills an index from `count(visit)` calls of `visit(vertex, item)`,
    /// made twice (once to count, once to fill).
    fn build(nv: usize, each: impl Fn(&mut dyn FnMut(u32, u32))) -> Stars {
        let mut start = vec![0u32; nv + 1];
        each(&mut |v, _| start[v as usize + 1] += 1);
        for v in 0..nv {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; start[nv] as usize];
        each(&mut |v, item| {
            list[fill[v as usize] as usize] = item;
            fill[v as usize] += 1;
        });
        Stars {
            start,
            list,
            normal: Vec::new(),
        }
    }
}

/// Whether `v` is on the border of a planar region: every face around it
/// in one plane and a side of it used by one face only. Such a vertex
/// stays (issue 31, decision 3: flat stays flat): its quadric's border
/// planes hold it only in a least-squares sense, and the data terms pull
/// it off the input's border line, so the output would cover area the
/// input does not. The collapses keep it on the border the same way (see
/// `CostModel::evaluate`).
fn on_a_flat_border(c: &Complex, star: &Stars, v: u32) -> bool {
    let range = star.range(v);
    let mut first: Option<DVec3> = None;
    for n in &star.normal[range.clone()] {
        if *n == DVec3::ZERO {
            continue;
        }
        match first {
            None => first = Some(*n),
            Some(n0) if !crate::prepare::geometry::coplanar(n0, *n) => return false,
            Some(_) => {}
        }
    }
    // A side v–k used by one face: count v's neighbours along face sides.
    let mut sides: SmallVec<[(u32, u32); 16]> = SmallVec::new();
    for &f in &star.list[range] {
        let face = c.face(f);
        let len = face.len();
        for (k, &x) in face.iter().enumerate() {
            if x != v {
                continue;
            }
            for y in [face[(k + 1) % len], face[(k + len - 1) % len]] {
                match sides.iter_mut().find(|(z, _)| *z == y) {
                    Some((_, n)) => *n += 1,
                    None => sides.push((y, 1)),
                }
            }
        }
    }
    sides.iter().any(|&(_, n)| n == 1)
}

/// The live faces around every output vertex, with their unit normals (a
/// zero vector for a face without area or a sliver, see [`SLIVER`]).
fn output_stars(c: &Complex) -> Stars {
    let (start, list) = c.vertex_face_index();
    let normal = list
        .par_iter()
        .map(|&f| {
            let n = face_normal(c, &c.pos, f);
            if n.length() <= SLIVER * longest_side_squared(c, f) {
                DVec3::ZERO
            } else {
                n.normalize_or_zero()
            }
        })
        .collect();
    Stars {
        start,
        list,
        normal,
    }
}

/// The input faces around the input vertices merged into each output
/// vertex (each face once per output vertex).
fn class_faces(input: &RefitInput<'_>, nv: usize) -> Stars {
    Stars::build(nv, |visit| {
        let mut roots: SmallVec<[u32; 8]> = SmallVec::new();
        for f in (0..input.face_count()).filter(|&f| input.counts(f)) {
            roots.clear();
            for w in input.face(f) {
                if let Some(&r) = input.root.get(w as usize) {
                    if (r as usize) < nv && !roots.contains(&r) {
                        roots.push(r);
                    }
                }
            }
            for &r in &roots {
                visit(r, f as u32);
            }
        }
    })
}

/// Squared distances from `p` to each triangle of the input `faces`
/// (polygons as fans), in order.
fn squared_distances<'a>(
    input: &'a RefitInput<'_>,
    faces: &'a [u32],
    p: DVec3,
) -> impl Iterator<Item = f64> + 'a {
    faces.iter().flat_map(move |&f| {
        let corners: SmallVec<[DVec3; 8]> =
            input.face(f as usize).map(|w| input.point(w)).collect();
        (1..corners.len().saturating_sub(1)).map(move |k| {
            let (q, _) = closest_point_on_triangle(p, corners[0], corners[k], corners[k + 1]);
            (p - q).length_squared()
        })
    })
}

/// Distance from `p` to the nearest of the input `faces` (polygons as
/// fans); infinite when there are none.
fn distance_to(input: &RefitInput<'_>, faces: &[u32], p: DVec3) -> f64 {
    squared_distances(input, faces, p)
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// Whether `p` is within `limit` of one of the input `faces`: the same
/// test as `distance_to(..) <= limit`, stopping at the first face that
/// passes.
fn within(input: &RefitInput<'_>, faces: &[u32], p: DVec3, limit: f64) -> bool {
    squared_distances(input, faces, p).any(|d2| d2.sqrt() <= limit)
}

/// The longest side of face `f`, squared.
fn longest_side_squared(c: &Complex, f: u32) -> f64 {
    let face = c.face(f);
    (0..face.len())
        .map(|k| {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            c.pos[a as usize].distance_squared(c.pos[b as usize])
        })
        .fold(0.0, f64::max)
}

/// Normal (length twice the area) of face `f` at positions `pos`.
fn face_normal(c: &Complex, pos: &[DVec3], f: u32) -> DVec3 {
    let p: SmallVec<[DVec3; 8]> = c.face(f).iter().map(|&u| pos[u as usize]).collect();
    polygon_normal(&p)
}

/// Margin by which a triangle's plane must be farther than the best match
/// so far for the triangle to be skipped (see `match_point`): relative to
/// that match and, for matches at rounding level (a point on the output
/// surface), to the point's squared distance from the triangle's corner;
/// rounding in the distances is ~10⁻¹⁶ of those.
const PLANE_MARGIN: f64 = 1e-9;

/// Whether the plane through `p0` with unit normal `n` is so far from `x`
/// that no point of a triangle in it can be nearer than `best` (a squared
/// distance), rounding included.
fn plane_rules_out(n: DVec3, p0: DVec3, x: DVec3, best: f64) -> bool {
    let r = x - p0;
    let across = n.dot(r);
    across * across > best * (1.0 + PLANE_MARGIN) + PLANE_MARGIN * r.length_squared()
}

/// The closest point to input vertex `i` on the faces around the output
/// vertex it went to, among faces that face its way (within 60°, see
/// [`FACING`]; polygons as fans). None when that point is on the outline
/// of those faces ([`beyond_the_star`]) or beside the face it is on
/// ([`beside_the_face`]): such a point is not fitted.
fn match_point(
    c: &Complex,
    star: &Stars,
    input: &RefitInput<'_>,
    weight: &[f32],
    normal: &[Vec3],
    i: u32,
) -> Option<Match> {
    let w = f64::from(weight[i as usize]);
    if w.is_nan() || w <= 0.0 {
        return None;
    }
    let x = input.point(i);
    let own = normal[i as usize].as_dvec3();
    let v = *input.root.get(i as usize)?;
    let mut best: Option<(f64, Match, bool)> = None;
    for k in star.range(v) {
        let (f, n) = (star.list[k], star.normal[k]);
        if n.dot(own) <= FACING * own.length() {
            continue;
        }
        let face = c.face(f);
        let p0 = c.pos[face[0] as usize];
        // A triangle is no nearer than its plane: when the plane is
        // already farther than the best match (with a margin far above
        // rounding, so that no match changes), the closest point on it,
        // the costly part of a match, is not needed. Polygons may be
        // warped, their fan triangles off the face's plane.
        if let (3, Some((best, _, _))) = (face.len(), &best) {
            if plane_rules_out(n, p0, x, *best) {
                continue;
            }
        }
        for t in 1..face.len() - 1 {
            let (a, b) = (c.pos[face[t] as usize], c.pos[face[t + 1] as usize]);
            let (q, bary) = closest_point_on_triangle(x, p0, a, b);
            let d2 = (x - q).length_squared();
            if best.as_ref().map_or(true, |(b, _, _)| d2 < *b) {
                let corners = [face[0], face[t], face[t + 1]];
                let beyond = beyond_the_star(v, corners, bary, t, face.len());
                best = Some((
                    d2,
                    Match {
                        corners,
                        bary,
                        normal: n,
                        distance: n.dot(x - q),
                        weight: w,
                    },
                    beyond,
                ));
            }
        }
    }
    match best {
        Some((d2, m, false)) if !beside_the_face(&m, d2) => Some(m),
        _ => None,
    }
}

/// Whether input point `m` (squared distance `d2` to its closest point)
/// lies beside its face rather than above it: the closest point on the
/// face's outline and the offset more along the face than across it. The
/// data term measures the offset along the face's normal, which for such a
/// point is no distance to the surface (a panel's step point matched to
/// the flat face next to the step, 10⁻² off along its normal, pulled an
/// exactly simplified box off its planes).
fn beside_the_face(m: &Match, d2: f64) -> bool {
    let across = m.distance.abs();
    let along = (d2 - across * across).max(0.0).sqrt();
    m.bary.iter().any(|&b| b <= ON_SIDE) && along > across
}

/// Whether a closest point with barycentric weights `bary` on the fan
/// triangle `corners` (triangle `t` of a polygon of `len` corners, fanned
/// from its first) lies on a side of the polygon away from the output
/// vertex `v`: on the outline of `v`'s faces. The input point is then
/// beyond them, where another vertex's faces stand for it, and its
/// distance to this outline is no distance to the surface: on a box
/// with raised panels simplified exactly, points of a panel's step
/// matched so pulled flat neighbours off their planes (Hausdorff 0 →
/// 1.7·10⁻³ of the diagonal at 10%). A fan diagonal is inside the
/// polygon, and a side through `v` is shared with its next face.
fn beyond_the_star(v: u32, corners: [u32; 3], bary: [f64; 3], t: usize, len: usize) -> bool {
    let Some(z) = (0..3).find(|&k| bary[k] <= ON_SIDE) else {
        return false;
    };
    // The side opposite corner z, and whether it is a side of the polygon.
    let polygon_side = match z {
        0 => true,
        1 => t + 1 == len - 1,
        _ => t == 1,
    };
    let (a, b) = (corners[(z + 1) % 3], corners[(z + 2) % 3]);
    polygon_side && a != v && b != v
}

/// The shortest edge from `v` to the other corners of its faces.
fn shortest_edge(c: &Complex, star: &Stars, v: u32) -> f64 {
    let p = c.pos[v as usize];
    let mut shortest = f64::INFINITY;
    for &f in star.of(v) {
        for &u in c.face(f) {
            if u != v {
                shortest = shortest.min(p.distance(c.pos[u as usize]));
            }
        }
    }
    if shortest.is_finite() {
        shortest
    } else {
        0.0
    }
}

/// Puts back where they were (`old`, indexed by `slot`) the corners of
/// every face whose normal turned from its unit normal `before` by more
/// than the bound, until no face does.
fn keep_faces_unfolded(
    c: &mut Complex,
    faces: &[u32],
    before: &[DVec3],
    slot: &[u32],
    old: &[DVec3],
    min_cos: f64,
) {
    // Each round only puts vertices back, so it ends.
    loop {
        let bad: Vec<u32> = faces
            .par_iter()
            .zip(before)
            .filter(|&(&f, &a)| {
                let b = face_normal(c, &c.pos, f);
                let lb = b.length();
                // A face with no area before is judged by its corners'
                // other faces.
                a != DVec3::ZERO && !(lb > 0.0 && a.dot(b) >= min_cos * lb)
            })
            .map(|(&f, _)| f)
            .collect();
        let mut reverted = false;
        for f in bad {
            let face: SmallVec<[u32; 8]> = c.face(f).iter().copied().collect();
            for u in face {
                let was = old[slot[u as usize] as usize];
                if c.pos[u as usize] != was {
                    c.pos[u as usize] = was;
                    reverted = true;
                }
            }
        }
        if !reverted {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_rules_out_only_triangles_farther_than_the_best_match() {
        // Hand case: the plane z = 0, a point 2 above it: nothing in the
        // plane is nearer than 4 (squared), so a best match of 3.9 rules
        // the plane out and one of 4 (a tie at best) does not.
        let (n, p0, x) = (DVec3::Z, DVec3::ZERO, DVec3::new(5.0, 1.0, 2.0));
        assert!(plane_rules_out(n, p0, x, 3.9));
        assert!(!plane_rules_out(n, p0, x, 4.0));
        // A point on the plane, far from the corner, with a best match at
        // rounding level: not ruled out.
        assert!(!plane_rules_out(n, p0, DVec3::new(1e3, 0.0, 1e-14), 0.0));
        // Sound on many triangles: whenever the plane rules a triangle
        // out, its closest point is farther than the best match.
        let mut rng = wildlod_testkit::SplitMix64(29);
        let mut u = || rng.next_f64() * 2.0 - 1.0;
        let mut ruled_out = 0;
        for _ in 0..20_000 {
            let [a, b, c, x] = [(); 4].map(|_| DVec3::new(u(), u(), u()));
            let Some(n) = (b - a).cross(c - a).try_normalize() else {
                continue;
            };
            let (q, _) = closest_point_on_triangle(x, a, b, c);
            let d2 = (x - q).length_squared();
            let best = d2 * (0.5 + u().abs());
            if plane_rules_out(n, a, x, best) {
                ruled_out += 1;
                assert!(d2 > best, "ruled out at {d2} against {best}");
            }
        }
        assert!(ruled_out > 1_000, "the bound ruled out only {ruled_out}");
    }

    #[test]
    fn slivers_have_no_normal_to_match_along() {
        // Face 0: a proper triangle; face 1: its corners in a line but for
        // 1e-9 (height a 2e-9 share of its longest side, 2).
        let pos = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 1e-9, 0.0),
        ];
        let c = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 0, 3]).0;
        let star = output_stars(&c);
        for k in star.range(0) {
            let (f, n) = (star.list[k], star.normal[k]);
            if f == 0 {
                assert!((n - DVec3::Z).length() < 1e-12, "{n:?}");
            } else {
                assert_eq!(n, DVec3::ZERO);
            }
        }
        assert_eq!(star.range(0).len(), 2);
    }

    #[test]
    fn points_beyond_their_vertex_faces_or_beside_a_face_are_not_fitted() {
        // Quad [v, a, b, c] = [0, 1, 2, 3] fanned from v; its triangle
        // t = 1 is [v, a, b]. On side a–b (v's weight 0): the quad's
        // outline away from v, so beyond v's faces.
        assert!(beyond_the_star(0, [0, 1, 2], [0.0, 0.5, 0.5], 1, 4));
        // On side v–a (b's weight 0): through v, shared with v's next face.
        assert!(!beyond_the_star(0, [0, 1, 2], [0.5, 0.5, 0.0], 1, 4));
        // On v–b (a's weight 0): the fan's diagonal, inside the quad.
        assert!(!beyond_the_star(0, [0, 1, 2], [0.5, 0.0, 0.5], 1, 4));
        // Quad [a, v, b, c] = [0, 1, 2, 3]: its triangle t = 2 is
        // [a, b, c]. On b–c: a side of the quad without v.
        assert!(beyond_the_star(1, [0, 2, 3], [0.0, 0.5, 0.5], 2, 4));
        // On a–b: the diagonal.
        assert!(!beyond_the_star(1, [0, 2, 3], [0.5, 0.5, 0.0], 2, 4));
        // On c–a: a side of the quad without v.
        assert!(beyond_the_star(1, [0, 2, 3], [0.5, 0.0, 0.5], 2, 4));
        // Inside a triangle: never.
        assert!(!beyond_the_star(0, [0, 1, 2], [0.2, 0.3, 0.5], 1, 3));

        let m = |bary: [f64; 3], distance: f64| Match {
            corners: [0, 1, 2],
            bary,
            normal: DVec3::Z,
            distance,
            weight: 1.0,
        };
        // On an edge, 0.1 across the face and 0.2 along it: beside.
        let d2 = 0.1f64.powi(2) + 0.2f64.powi(2);
        assert!(beside_the_face(&m([0.0, 0.5, 0.5], -0.1), d2));
        // 0.1 across and 0.05 along: above the edge, fitted.
        let d2 = 0.1f64.powi(2) + 0.05f64.powi(2);
        assert!(!beside_the_face(&m([0.0, 0.5, 0.5], 0.1), d2));
        // Projected inside the face: fitted whatever the offset.
        assert!(!beside_the_face(&m([0.2, 0.3, 0.5], 0.1), 0.01));
    }

    /// A flat 5 × 5 grid of input vertices in z = 0 over [−1, 1]², as
    /// triangles.
    fn flat_input() -> (Vec<[f32; 3]>, Vec<u32>, Vec<u32>) {
        let n = 5;
        let origin: Vec<[f32; 3]> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                [-1.0 + 0.5 * i as f32, -1.0 + 0.5 * j as f32, 0.0]
            })
            .collect();
        let mut indices = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = (j * n + i) as u32;
                let n = n as u32;
                indices.extend_from_slice(&[v, v + 1, v + n + 1, v, v + n + 1, v + n]);
            }
        }
        let offsets = (0..=indices.len() as u32 / 3).map(|f| 3 * f).collect();
        (origin, offsets, indices)
    }

    /// The output: a tent over the square whose apex (vertex 4) stands
    /// `h` above the centre, the four corners on the plane.
    fn tent(h: f64) -> Complex {
        let pos = vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, h),
        ];
        Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
        )
        .0
    }

    /// Input grid vertex → output vertex: the corners to the tent's
    /// corners, everything else merged into the apex.
    fn roots() -> Vec<u32> {
        (0..25)
            .map(|k| match k {
                0 => 0,
                4 => 1,
                24 => 2,
                20 => 3,
                _ => 4,
            })
            .collect()
    }

    /// Refits `c` against the flat input with `indices` (its triangles).
    fn refit_against(
        c: &mut Complex,
        indices: &[u32],
        quadrics: &[Quadric],
        fixed: &[bool],
        min_cos: f64,
        sweeps: u32,
    ) -> Vec<bool> {
        let (origin, offsets, _) = flat_input();
        let root = roots();
        let quadrics: Vec<StoredQuadric> = quadrics
            .iter()
            .zip(&c.pos)
            .map(|(q, &p)| StoredQuadric::new(q, p))
            .collect();
        let origins = c.pos.clone();
        let input = RefitInput {
            positions: &origin,
            center: DVec3::ZERO,
            scale: 1.0,
            offsets: &offsets,
            indices,
            weld: &[],
            kept: &[],
            root: &root,
            quadrics: &quadrics,
            origins: &origins,
            regularization: &[],
            fixed,
            min_cos,
            exact_flat_borders: true,
        };
        refit(c, &input, sweeps)
    }

    fn run(c: &mut Complex, quadrics: &[Quadric], fixed: &[bool], sweeps: u32) -> Vec<bool> {
        refit_against(c, &flat_input().2, quadrics, fixed, 0.0, sweeps)
    }

    #[test]
    fn refit_lowers_an_apex_onto_the_input_it_stands_for() {
        // Nothing holds the apex but the input's points, all in z = 0 and
        // all matched to the tent's faces: it comes down. The corners'
        // quadrics (the plane z = 0, as the input's faces merged into them
        // give) keep them on the plane: the pull they share with the apex
        // only slides them a little, on the plane.
        let mut c = tent(0.2);
        let mut q = vec![Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0); 4];
        q.push(Quadric::ZERO);
        let moved = run(&mut c, &q, &[], 4);
        assert!(moved[4]);
        assert!(c.pos[4].z.abs() < 0.02, "apex at {}", c.pos[4].z);
        for v in 0..4 {
            assert!(c.pos[v].z.abs() < 0.01, "corner {v} at {}", c.pos[v]);
        }
        // It comes down, not sideways: the pulls are along the faces'
        // normals, which lean in from all four sides.
        let drift = c.pos[4].truncate().length();
        assert!(drift < 0.05, "apex drifted {drift}");
    }

    #[test]
    fn a_step_is_at_most_half_the_shortest_edge() {
        // One sweep from 0.2 above a plane: the minimizer is 0.2 away and
        // the apex's shortest edge (to a corner) about 1.43, so the bound
        // does not bind, and the apex lands near the plane in one sweep:
        // the damping keeps it a little above.
        let mut c = tent(0.2);
        run(&mut c, &[], &[], 1);
        let z = c.pos[4].z;
        assert!(z > 0.0 && z < 0.2 * DAMPING * 4.0, "apex at {z}");
        // A tent of height 1.5 over the same square (its faces 56° from
        // the plane, within the 60° a match allows): the minimizer is 1.5
        // away, the shortest edge sqrt(2 + 2.25) ≈ 2.06, so one sweep
        // moves the apex by at most 1.03.
        let mut c = tent(1.5);
        run(&mut c, &[], &[], 1);
        let step = 1.5 - c.pos[4].z;
        assert!(step <= 0.5 * 4.25f64.sqrt() + 1e-9, "step {step}");
        assert!(step > 0.9, "step {step}");
    }

    #[test]
    fn a_vertex_its_quadric_holds_stays() {
        // The apex's quadric: three orthogonal planes through its position
        // (a corner), each far heavier than the input's pull.
        let mut c = tent(0.2);
        let apex = c.pos[4];
        let mut q = vec![Quadric::ZERO; 5];
        for n in [DVec3::X, DVec3::Y, DVec3::Z] {
            q[4] += Quadric::plane(n, apex, 1e4);
        }
        run(&mut c, &q, &[], 2);
        assert!(c.pos[4].distance(apex) < 1e-3, "moved to {}", c.pos[4]);
    }

    #[test]
    fn fixed_vertices_do_not_move() {
        let mut c = tent(0.2);
        let before = c.pos.clone();
        let moved = run(&mut c, &[], &[true; 5], 2);
        assert!(!moved.iter().any(|&m| m));
        assert_eq!(c.pos, before);
    }

    #[test]
    fn a_sweep_that_would_fold_a_face_is_undone() {
        // The apex pulled from 0.2 above to the plane turns each face by
        // about 11°: allowed under a right angle, refused under 5°.
        let mut c = tent(0.2);
        let indices = flat_input().2;
        let moved = refit_against(&mut c, &indices, &[], &[], 5f64.to_radians().cos(), 1);
        assert!(!moved[4]);
        assert_eq!(c.pos[4], DVec3::new(0.0, 0.0, 0.2));
    }

    #[test]
    fn points_on_the_other_side_of_a_sheet_are_not_matched() {
        // Input faces turned over (facing −z) do not pull on a tent facing
        // +z: a thin part's two sides stay apart.
        let mut c = tent(0.2);
        let mut indices = flat_input().2;
        for t in indices.chunks_mut(3) {
            t.swap(1, 2);
        }
        let moved = refit_against(&mut c, &indices, &[], &[], 0.0, 2);
        assert!(!moved.iter().any(|&m| m));
    }
}
