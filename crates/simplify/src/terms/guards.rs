//! Guards: tests a collapse must pass before it is made. Each is optional
//! (see [`crate::options::Guards`]); none assumes a manifold.

use glam::DVec3;

use crate::prepare::complex::Complex;
use crate::prepare::geometry::polygon_normal;

/// Every position of a list of `n` from `start` outwards, alternately
/// after and before it (`start`, `start + 1`, `start - 1`, …, wrapping),
/// each once: a witness next to the last is found in as many steps as it
/// is away, on either side.
fn outwards(start: usize, n: usize) -> impl Iterator<Item = usize> {
    (0..n).map(move |d| {
        let step = d.div_ceil(2);
        if d % 2 == 1 {
            (start + step) % n
        } else {
            (start + n - step % n) % n
        }
    })
}

/// What a refused collapse would do to its witness face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Degrades {
    /// The face would lose its area (see [`flattens`]).
    Flattens,
    /// The face would turn past the normal limit (see [`flips`]).
    Flips,
}

/// The face tests a collapse must pass: no surviving face flattened to a
/// line ([`flattens`]) and none turned past the normal limit (the cosine
/// of the largest turn, [`flips`]), each where asked.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceTests {
    pub flatten: bool,
    pub min_cos: Option<f64>,
}

/// Where each vertex's face tests start reading its faces (see
/// [`first_moved_failing`]), and how many faces they read.
#[derive(Clone, Debug, Default)]
pub(crate) struct FaceScans {
    /// Per vertex: the position in its face list of the last witness found
    /// there, or [`NO_WITNESS`].
    pub from: Vec<u32>,
    /// Faces read by the tests: the guards' share of the loop's work.
    pub tested: usize,
}

/// A vertex none of whose faces has been a witness yet: its scan reads
/// its faces in order.
const NO_WITNESS: u32 = u32::MAX;

impl FaceScans {
    /// Every vertex's scan reading its faces in order.
    pub fn new(vertices: usize) -> Self {
        FaceScans {
            from: vec![NO_WITNESS; vertices],
            tested: 0,
        }
    }
}

/// The first surviving face of their star (in [`Complex::star_faces`]'
/// order, but `i`'s faces from `scans.from[i]`: see
/// [`first_moved_failing`]) that collapsing `i`–`j` to `x` flattens or
/// turns too far, and which; the collapse loop keeps it as the witness the refused edge waits
/// on (see `collapse::witness_waits`). Both tests are made in one pass over
/// the faces that move, so a refusal costs the faces read up to its
/// witness: around a fan's center with nothing flattened but a sliver
/// flipped next to the edge, a pass per test would read every face first.
pub(crate) fn degraded_face(
    c: &Complex,
    i: u32,
    j: u32,
    x: DVec3,
    tests: FaceTests,
    scans: &mut FaceScans,
) -> Option<(u32, Degrades)> {
    let mut corners = Corners::default();
    let mut tested = 0;
    let resume = &mut scans.from[i as usize];
    let judge = |f: u32, corners: &mut Corners| {
        let (old, new) = turn(c, f, i, j, x, corners)?;
        if tests.flatten && (flattens(old, new) || pinches_corners(c, f, i, j, x)) {
            Some(Degrades::Flattens)
        } else if tests.min_cos.is_some_and(|mc| flips(old, new, mc)) {
            Some(Degrades::Flips)
        } else {
            None
        }
    };
    let face = first_moved_failing(c, i, j, x, resume, |f| {
        tested += 1;
        judge(f, &mut corners).is_some()
    });
    scans.tested += tested;
    let face = face?;
    // Which test it failed, asked again of the witness alone: the scan
    // may judge faces after it (see `first_moved_failing`).
    let why = judge(face, &mut corners)?;
    Some((face, why))
}

/// Two corners of a face closer than this share of their distance before
/// a collapse are one point once written: `f32` positions resolve about
/// 6e-8 of a coordinate.
const PINCH: f64 = 1e-7;

/// Whether collapsing `i`–`j` to `x` brings the merged corner of surviving
/// face `f` onto another of its corners (to [`PINCH`] of their distance
/// before). The area test cannot see it where the solve lands a hair off
/// a third vertex (a box's corner, where three sides' planes meet: 4e-13
/// away on the demo's table): a triangle keeps 1e-11 of its area, and a
/// quad its whole area with two corners in one place. Written as `f32`,
/// both are degenerate faces.
fn pinches_corners(c: &Complex, f: u32, i: u32, j: u32, x: DVec3) -> bool {
    let face = c.face(f);
    let moving = |v: u32| v == i || v == j;
    face.iter().filter(|&&m| moving(m)).any(|&m| {
        let from = c.pos[m as usize];
        face.iter().filter(|&&v| !moving(v)).any(|&v| {
            let p = c.pos[v as usize];
            x.distance_squared(p) <= PINCH * PINCH * from.distance_squared(p)
                && from.distance_squared(p) > 0.0
        })
    })
}

/// A face's corners before and after a collapse (scratch for polygons).
#[derive(Default)]
struct Corners {
    old: smallvec::SmallVec<[DVec3; 8]>,
    new: smallvec::SmallVec<[DVec3; 8]>,
}

impl Corners {
    /// Face `f`'s corners, with `i` and `j` at `x` in `new`.
    fn read(&mut self, c: &Complex, f: u32, i: u32, j: u32, x: DVec3) {
        self.old.clear();
        self.new.clear();
        for &v in c.face(f) {
            let p = c.pos[v as usize];
            self.old.push(p);
            self.new.push(if v == i || v == j { x } else { p });
        }
    }
}

/// Surviving face `f`'s normal (scaled by twice its area) before and
/// after collapsing `i`–`j` to `x`; `None` for a triangle holding both
/// endpoints, which vanishes.
fn turn(c: &Complex, f: u32, i: u32, j: u32, x: DVec3, s: &mut Corners) -> Option<(DVec3, DVec3)> {
    let face = c.face(f);
    if let [a, b, d] = *face {
        let has = |v: u32| a == v || b == v || d == v;
        if has(i) && has(j) {
            return None;
        }
        let p = |v: u32| c.pos[v as usize];
        let m = |v: u32| if v == i || v == j { x } else { p(v) };
        Some((
            (p(b) - p(a)).cross(p(d) - p(a)),
            (m(b) - m(a)).cross(m(d) - m(a)),
        ))
    } else {
        s.read(c, f, i, j, x);
        Some((polygon_normal(&s.old), polygon_normal(&s.new)))
    }
}

/// Whether a face whose normal goes from `old` to `new` turns by more than
/// the angle whose cosine is `min_cos`. Faces without area before or
/// after are not judged (their normal means nothing): [`flattens`] keeps
/// surviving faces from losing their area.
fn flips(old: DVec3, new: DVec3, min_cos: f64) -> bool {
    let (lo, ln) = (old.length_squared(), new.length_squared());
    // Areas below ~1e-15 of the unit-diagonal mesh are numerical dust.
    lo > 1e-30 && ln > 1e-30 && old.dot(new) < min_cos * (lo * ln).sqrt()
}

/// Whether a face vanishes when `i` and `j` merge: a triangle on the edge.
#[inline]
pub(crate) fn vanishes(face: &[u32], i: u32, j: u32) -> bool {
    face.len() == 3 && face.contains(&i) && face.contains(&j)
}

/// Whether a face whose normal goes from `old` to `new` had area and has
/// none after (its corners on one line, to 1e-12 of its area). [`flips`]
/// cannot judge a face without area, so a face flattened to a line could
/// later be given area again the wrong way unseen: across a step's corner
/// of a staircase, or folded over a flat region's border. Every collapse
/// refuses to flatten a surviving face (as meshoptimizer's flip test,
/// which counts a face without area as flipped, does); faces the input
/// had without area stay unjudged.
fn flattens(old: DVec3, new: DVec3) -> bool {
    let (lo, ln) = (old.length_squared(), new.length_squared());
    lo > 1e-30 && ln <= 1e-24 * lo
}

/// The first face, in the order of [`Complex::star_faces`], that collapsing
/// `i`–`j` to `x` moves and `fails`, except that `i`'s faces are read
/// from position `resume` outwards (see [`outwards`]; in order if none
/// was a witness yet), which is then set to where the witness was found. Faces that do not move (around an endpoint already
/// at `x`) cannot flip or flatten, so they are not read: a rim vertex
/// merging into a fan's center at the center reads its own two faces, not
/// the center's hundred thousand.
///
/// Any face that fails refuses the collapse, so where the scan starts
/// changes only which one is the witness. Starting where the vertex's
/// last refusal found one makes a vertex tried towards its neighbours in
/// turn (a fan's center towards each rim vertex) find each witness next to
/// the last, instead of reading every face before it each time: on a
/// flat fan of 85,000 that is the difference between a linear and a
/// quadratic run.
fn first_moved_failing(
    c: &Complex,
    i: u32,
    j: u32,
    x: DVec3,
    resume: &mut u32,
    mut fails: impl FnMut(u32) -> bool,
) -> Option<u32> {
    let (i_moves, j_moves) = (c.pos[i as usize] != x, c.pos[j as usize] != x);
    let around_j_only = |f: &u32| !c.face(*f).contains(&i);
    if i_moves {
        let faces = &c.vert_faces[i as usize];
        let n = faces.len();
        let at = if *resume == NO_WITNESS || n == 0 {
            (0..n).find(|&k| fails(faces[k]))
        } else {
            outwards(*resume as usize % n, n).find(|&k| fails(faces[k]))
        };
        if let Some(k) = at {
            *resume = k as u32;
            return Some(faces[k]);
        }
        if !j_moves {
            return None;
        }
        return c.vert_faces[j as usize]
            .iter()
            .filter(|f| around_j_only(f))
            .copied()
            .find(|&f| fails(f));
    }
    if !j_moves {
        return None;
    }
    // Only `j` moves: its faces that also hold `i` come first, in `i`'s
    // order, then the others in `j`'s.
    let mut with_i: smallvec::SmallVec<[u32; 4]> = smallvec::SmallVec::new();
    let mut alone = None;
    for &f in &c.vert_faces[j as usize] {
        if !around_j_only(&f) {
            if fails(f) {
                with_i.push(f);
            }
        } else if alone.is_none() && fails(f) {
            alone = Some(f);
        }
    }
    match with_i.len() {
        0 => alone,
        1 => with_i.first().copied(),
        _ => c.vert_faces[i as usize]
            .iter()
            .copied()
            .find(|f| with_i.contains(f)),
    }
}

/// The link condition for polygon complexes (Dey et al. 1999; W App. B),
/// with the boundary rule: true when collapsing `i`–`j` keeps the topology.
///
/// - every common neighbor `k` of `i` and `j` closes a triangle (i, j, k);
/// - no side shared by the faces of `i` and of `j` except through faces
///   holding both (for triangles: the tetrahedron case);
/// - if both are on the boundary, `i`–`j` is a boundary edge;
/// - the edge is used by at most two faces, and the collapse does not delete
///   an isolated triangle (a whole component).
///
/// Every rule is symmetric in `i` and `j`, so each is read from the smaller
/// star and the stars of its neighbours, never from the larger one: this
/// runs at every pop of the queue, and a vertex with a hundred thousand
/// faces (a flat fan's center) would otherwise cost that much each time
/// one of its edges is tried.
pub(crate) fn keeps_topology(c: &Complex, i: u32, j: u32) -> bool {
    let faces_on_edge = c.edge_face_count(i, j);
    if faces_on_edge > 2 {
        return false;
    }
    let (s, l) = smaller_star(c, i, j);
    // Common neighbors through edges.
    for &e in &c.vert_edges[s as usize] {
        let k = c.other(e, s);
        if k == l || c.edge_between(k, l).is_none() {
            continue;
        }
        if !has_triangle(c, s, k, [i, j, k]) {
            return false;
        }
    }
    // Sides of faces of i (not holding j) and of j (not holding i).
    let mut shared = false;
    for_far_sides(c, s, l, &mut |_, a, b| {
        shared = faces_with_far_side(c, l, s, a, b).next().is_some();
        shared
    });
    if shared {
        return false;
    }
    let (bi, bj) = (c.on_boundary(i), c.on_boundary(j));
    if bi && bj && faces_on_edge != 1 {
        return false;
    }
    // An isolated triangle on the edge would vanish with its component.
    for &f in &c.vert_faces[s as usize] {
        let face = c.face(f);
        if face.len() == 3 && face.contains(&l) {
            let isolated = (0..3).all(|k| c.edge_face_count(face[k], face[(k + 1) % 3]) == 1);
            if isolated {
                return false;
            }
        }
    }
    true
}

/// `i` and `j` ordered by the size of their stars, the smaller first.
fn smaller_star(c: &Complex, i: u32, j: u32) -> (u32, u32) {
    if c.vert_faces[i as usize].len() <= c.vert_faces[j as usize].len() {
        (i, j)
    } else {
        (j, i)
    }
}

/// Whether a triangle has the three corners `tri`, read from the smaller
/// star of `a` and `b` (two of them).
fn has_triangle(c: &Complex, a: u32, b: u32, tri: [u32; 3]) -> bool {
    let (s, _) = smaller_star(c, a, b);
    c.vert_faces[s as usize].iter().any(|&f| {
        let face = c.face(f);
        face.len() == 3 && tri.iter().all(|v| face.contains(v))
    })
}

/// Whether `a` and `b` are consecutive corners of `face`.
fn has_side(face: &[u32], a: u32, b: u32) -> bool {
    let n = face.len();
    (0..n).any(|k| {
        let (p, q) = (face[k], face[(k + 1) % n]);
        (p == a && q == b) || (p == b && q == a)
    })
}

/// Whether `w` and `v` are consecutive corners of some face.
fn side_neighbours(c: &Complex, w: u32, v: u32) -> bool {
    let (s, _) = smaller_star(c, w, v);
    c.vert_faces[s as usize]
        .iter()
        .any(|&f| has_side(c.face(f), w, v))
}

/// Calls `visit(face, a, b)` for each side `a`–`b` of each face of `v`
/// without `other` that does not touch `v` (for a triangle fan, the rim
/// of `v`'s star), until it returns true.
fn for_far_sides(c: &Complex, v: u32, other: u32, visit: &mut dyn FnMut(u32, u32, u32) -> bool) {
    for &f in &c.vert_faces[v as usize] {
        let face = c.face(f);
        if face.contains(&other) {
            continue;
        }
        let n = face.len();
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            if a != v && b != v && visit(f, a, b) {
                return;
            }
        }
    }
}

/// The faces of `v` without `other` of which `a`–`b` (neither of them `v`)
/// is a side, read from the smaller star of `a` and `b`.
fn faces_with_far_side(
    c: &Complex,
    v: u32,
    other: u32,
    a: u32,
    b: u32,
) -> impl Iterator<Item = u32> + '_ {
    let (s, _) = smaller_star(c, a, b);
    c.vert_faces[s as usize].iter().copied().filter(move |&f| {
        let face = c.face(f);
        face.contains(&v) && !face.contains(&other) && has_side(face, a, b)
    })
}

/// How clearly a face must turn towards a ring's center (cosine of the
/// angle between its normal and the direction to the center) for the ring
/// to count as wrapping air. Flat strips and twin-faced sheets sit near 0
/// either way; they count as material.
const FACES_AIR: f64 = 0.2;

/// Whether the surface at face `f` wraps material around `center` rather
/// than air: false only when the face clearly turns towards the center,
/// as a hole's wall does; a solid strand's faces turn away from it, and a
/// flat strip's (or a twin-faced sheet's) neither way.
fn faces_away(c: &Complex, f: u32, center: DVec3) -> bool {
    let p: smallvec::SmallVec<[DVec3; 8]> = c.face(f).iter().map(|&v| c.pos[v as usize]).collect();
    let centroid = p.iter().copied().sum::<DVec3>() / p.len().max(1) as f64;
    let n = polygon_normal(&p);
    let d = centroid - center;
    let scale = n.length() * d.length();
    scale.is_nan() || scale <= 0.0 || n.dot(d) > -FACES_AIR * scale
}

/// Whether collapsing the face side `i`–`j` flattens material, by the
/// first two rules of the link condition (see [`keeps_topology`])
/// restricted to face sides, so that virtual edges, which merge parts,
/// never count: some vertex `k` is a face-side neighbour of both without a
/// triangle (i, j, k) (a thin tube's ring, a strip's width), or a side far
/// from both belongs to faces of each (a tube's closed end folding flat);
/// and the surface there faces away from the ring or cap, so it wraps
/// material (a solid strand) rather than air (a hole through a plate,
/// whose closing is W's ordinary simplification). Repeated, such collapses
/// flatten a thin part into edges no face uses, which the output cannot
/// show. False when `i`–`j` is no face's side.
pub(crate) fn pinches(c: &Complex, i: u32, j: u32) -> bool {
    // Checked once per collapse the loop pops. Two ordinary stars are read
    // fastest whole, once each; where one is large (a fan's centre), from
    // the smaller star and its neighbours' stars, like the link condition.
    let larger = c.vert_faces[i as usize]
        .len()
        .max(c.vert_faces[j as usize].len());
    if larger > c.high_valence {
        pinches_local(c, i, j)
    } else {
        pinches_whole(c, i, j)
    }
}

/// [`pinches`] from the smaller star and its neighbours' stars.
fn pinches_local(c: &Complex, i: u32, j: u32) -> bool {
    if c.edge_face_count(i, j) == 0 {
        return false;
    }
    let (s, l) = smaller_star(c, i, j);
    let (pi, pj) = (c.pos[i as usize], c.pos[j as usize]);
    // First rule: a common face-side neighbour `w` with no triangle
    // (i, j, w), judged at the first face of `i` on the edge.
    for &f in &c.vert_faces[s as usize] {
        let face = c.face(f);
        let n = face.len();
        let Some(k) = face.iter().position(|&v| v == s) else {
            continue;
        };
        for w in [face[(k + n - 1) % n], face[(k + 1) % n]] {
            if w == l || !side_neighbours(c, w, l) || has_triangle(c, s, w, [i, j, w]) {
                continue;
            }
            let ring = (pi + pj + c.pos[w as usize]) / 3.0;
            // Rare (a tube's ring): reading all of `i`'s star is fine here.
            let on_edge = c.vert_faces[i as usize]
                .iter()
                .copied()
                .find(|&g| has_side(c.face(g), i, j));
            if on_edge.is_some_and(|g| faces_away(c, g, ring)) {
                return true;
            }
        }
    }
    // Second rule: a far side of a face of each (triangles: the side
    // opposite the center; other polygons: every side not touching it),
    // judged at the face of `i`.
    let mut found = false;
    for_far_sides(c, s, l, &mut |f, a, b| {
        let cap = (pi + pj + c.pos[a as usize] + c.pos[b as usize]) / 4.0;
        found = faces_with_far_side(c, l, s, a, b)
            .any(|g| faces_away(c, if s == i { f } else { g }, cap));
        found
    });
    found
}

/// [`pinches`] from both whole stars, each read once.
fn pinches_whole(c: &Complex, i: u32, j: u32) -> bool {
    // Checked once per collapse the loop pops, so from one pass over each
    // star: each face's neighbours of the star's center (`prev`, `next`),
    // which for a triangle are also its far side.
    let corners = |v: u32| {
        let mut out: smallvec::SmallVec<[(u32, u32, u32, usize); 12]> = smallvec::SmallVec::new();
        for &f in &c.vert_faces[v as usize] {
            let face = c.face(f);
            let n = face.len();
            if let Some(k) = face.iter().position(|&w| w == v) {
                out.push((f, face[(k + n - 1) % n], face[(k + 1) % n], n));
            }
        }
        out
    };
    let si = corners(i);
    if !si.iter().any(|&(_, p, q, _)| p == j || q == j) {
        return false;
    }
    let sj = corners(j);
    let (pi, pj) = (c.pos[i as usize], c.pos[j as usize]);
    let neighbour_of_i = |w: u32| si.iter().any(|&(_, p, q, _)| p == w || q == w);
    // First rule: a common neighbour `w` with no triangle (i, j, w).
    for &(_, p, q, _) in &sj {
        for w in [p, q] {
            if w == i || !neighbour_of_i(w) {
                continue;
            }
            let closed = si
                .iter()
                .any(|&(_, a, b, n)| n == 3 && ((a == j && b == w) || (a == w && b == j)));
            if closed {
                continue;
            }
            let ring = (pi + pj + c.pos[w as usize]) / 3.0;
            let on_edge = si.iter().find(|&&(_, a, b, _)| a == j || b == j);
            if on_edge.is_some_and(|&(g, ..)| faces_away(c, g, ring)) {
                return true;
            }
        }
    }
    // Second rule: a far side of a face of each (triangles: the side
    // opposite the center; other polygons: every side not touching it).
    // Sides are reported to `visit` in order, without a list per face:
    // this check runs at every pop of the queue.
    let far = |v: u32,
               other: u32,
               &(f, p, q, n): &(u32, u32, u32, usize),
               visit: &mut dyn FnMut(u32, u32) -> bool|
     -> bool {
        let face = c.face(f);
        if face.contains(&other) {
            return false;
        }
        if n == 3 {
            return visit(p.min(q), p.max(q));
        }
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            if a != v && b != v && visit(a.min(b), a.max(b)) {
                return true;
            }
        }
        false
    };
    // `j`'s far sides once, not once per face of `i`.
    let mut far_j: smallvec::SmallVec<[(u32, u32); 16]> = smallvec::SmallVec::new();
    for cj in &sj {
        far(j, i, cj, &mut |a, b| {
            far_j.push((a, b));
            false
        });
    }
    for ci in &si {
        let found = far(i, j, ci, &mut |a, b| {
            if !far_j.contains(&(a, b)) {
                return false;
            }
            let cap = (pi + pj + c.pos[a as usize] + c.pos[b as usize]) / 4.0;
            faces_away(c, ci.0, cap)
        });
        if found {
            return true;
        }
    }
    false
}

/// The fewest triangles a closed part can keep its topology with (a
/// tetrahedron).
const CLOSED_MINIMUM: f64 = 4.0;

/// What a pinch costs (see `Metric::pinch_cost`), from the parts of the
/// complex, `area` per vertex, and the run's `budget` of triangles.
///
/// A part too small for the budget (its share of it, by area, is below
/// what the smallest closed surface needs) pays what its vanishing costs
/// measured like an ordinary collapse at the target. Its pinches are W's
/// ordinary topology changes, not the loss of a thin feature: at the
/// target it could not stay a closed surface anyway. But whether it should
/// go is a matter of distance, not area: a side mirror has a thousandth of
/// a truck's area and sticks out by a twentieth of its size. A collapse at
/// the target moving the surface by `e` costs about `4 · (A / target) · e²`
/// (both endpoints carry two target faces' area); a part of diagonal `d`
/// vanishing moves its surface by about `d / 2`, so it pays
/// `(A / target) · d²`: it goes when it is smaller than the error the rest
/// of the mesh reaches.
///
/// Every other part pays the same for a `distance` (`Metric::pinch_distance`),
/// `(A / target) · distance²`: its thin parts go once the rest would move
/// by about half of it. Only when `distance` is given (the run has a
/// triangle target; an error limit alone has no target face) and above 0;
/// otherwise they pay `pinch`.
///
/// Every price is at most `pinch`.
///
/// `scale` is what moving a unit of area by a unit of distance costs a
/// collapse, relative to the memory planes alone: 1 plus the weight of the
/// present faces' planes ([`crate::Metric::current_face_weight`]), which
/// see the same move again. The prices scale with it, so that a part
/// vanishes at the same distance whatever ranks the ordinary collapses.
pub(crate) fn pinch_prices(
    c: &Complex,
    area: &[f64],
    budget: usize,
    pinch: f64,
    distance: Option<f64>,
    scale: f64,
) -> PinchPrices {
    let full = PinchPrices {
        base: pinch,
        per_vertex: Vec::new(),
    };
    let (label, parts) = c.part_labels();
    let mut part_area = vec![0.0f64; parts];
    let mut lo = vec![DVec3::splat(f64::INFINITY); parts];
    let mut hi = vec![DVec3::splat(f64::NEG_INFINITY); parts];
    for (v, &l) in label.iter().enumerate() {
        let l = l as usize;
        part_area[l] += area.get(v).copied().unwrap_or(0.0);
        lo[l] = lo[l].min(c.pos[v]);
        hi[l] = hi[l].max(c.pos[v]);
    }
    let total: f64 = part_area.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return full;
    }
    let face_area = scale * total / budget.max(1) as f64;
    let base = match distance {
        Some(d) if d > 0.0 => (face_area * d * d).min(pinch),
        _ => pinch,
    };
    let price: Vec<f64> = (0..parts)
        .map(|l| {
            if !too_small_for_budget(part_area[l], total, budget) {
                return base;
            }
            let d2 = (hi[l] - lo[l]).length_squared();
            (face_area * d2).min(pinch)
        })
        .collect();
    // One number when every vertex pays the same: a price per vertex is 4
    // bytes a vertex of a large run would carry for nothing.
    let per_vertex = if price.iter().all(|&p| p == base) {
        Vec::new()
    } else {
        label.iter().map(|&l| price[l as usize] as f32).collect()
    };
    PinchPrices { base, per_vertex }
}

/// What a pinch costs in a run (see [`pinch_prices`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PinchPrices {
    /// The price of every vertex not in `per_vertex`.
    pub base: f64,
    /// The price at each vertex; empty when every vertex pays `base`.
    pub per_vertex: Vec<f32>,
}

impl PinchPrices {
    /// The price of a pinch at vertex `v`.
    #[inline]
    pub fn at(&self, v: u32) -> f64 {
        self.per_vertex
            .get(v as usize)
            .map_or(self.base, |&p| f64::from(p))
    }
}

/// Whether a part of `area`, out of `total`, gets less than the smallest
/// closed surface (a tetrahedron) of a `budget`-triangle target when the
/// budget is shared by area.
pub(crate) fn too_small_for_budget(area: f64, total: f64, budget: usize) -> bool {
    budget.max(1) as f64 * area / total < CLOSED_MINIMUM
}

/// Exactly how many triangles collapsing `i`–`j` removes, without making
/// it: faces that lose corners or vanish, and duplicates that appear.
pub(crate) fn removed_triangles(c: &Complex, star: &[u32], i: u32, j: u32) -> usize {
    let mut removed = 0;
    let mut keys: Vec<(Vec<u32>, u32, usize)> = Vec::with_capacity(star.len());
    for &f in star {
        let face = c.face(f);
        let old = face.len();
        let merged: Vec<u32> = face.iter().map(|&v| if v == j { i } else { v }).collect();
        let kept = surviving_cycle(&merged);
        let copies = c.copies(f);
        if kept.len() < 3 {
            removed += (old - 2) * copies;
            continue;
        }
        removed += (old - kept.len()) * copies;
        if kept.contains(&i) {
            let k = (0..kept.len()).min_by_key(|&k| kept[k]).unwrap_or(0);
            keys.push((
                (0..kept.len())
                    .map(|t| kept[(k + t) % kept.len()])
                    .collect(),
                f,
                copies,
            ));
        }
    }
    keys.sort_unstable();
    // Of two equal faces the collapse removes the later, with its twins.
    for w in 1..keys.len() {
        if keys[w].0 == keys[w - 1].0 {
            removed += (keys[w].0.len() - 2) * keys[w].2;
        }
    }
    removed
}

/// The cycle a face keeps after merging vertices: consecutive repeats
/// dropped, then the longest loop between repeats (as
/// `Complex::normalize_face` does).
fn surviving_cycle(v: &[u32]) -> Vec<u32> {
    let mut runs: Vec<u32> = Vec::with_capacity(v.len());
    for &x in v {
        if runs.last() != Some(&x) {
            runs.push(x);
        }
    }
    while runs.len() > 1 && runs[0] == runs[runs.len() - 1] {
        runs.pop();
    }
    'split: loop {
        for a in 0..runs.len() {
            for b in a + 1..runs.len() {
                if runs[a] == runs[b] {
                    let inner = runs[a..b].to_vec();
                    let mut outer = runs[b..].to_vec();
                    outer.extend_from_slice(&runs[..a]);
                    runs = if inner.len() >= outer.len() {
                        inner
                    } else {
                        outer
                    };
                    continue 'split;
                }
            }
        }
        break;
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The witness of the flip test alone (normal limit `min_cos`).
    fn flipped_face(c: &Complex, i: u32, j: u32, x: DVec3, min_cos: f64) -> Option<u32> {
        let tests = FaceTests {
            flatten: false,
            min_cos: Some(min_cos),
        };
        degraded_face(c, i, j, x, tests, &mut FaceScans::new(c.pos.len())).map(|(f, _)| f)
    }

    /// The witness of the flatten test alone.
    fn flattens_a_face(c: &Complex, i: u32, j: u32, x: DVec3) -> Option<u32> {
        let tests = FaceTests {
            flatten: true,
            min_cos: None,
        };
        degraded_face(c, i, j, x, tests, &mut FaceScans::new(c.pos.len())).map(|(f, _)| f)
    }

    fn tetra() -> Complex {
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
        )
        .0
    }

    #[test]
    fn tetrahedron_edges_fail_the_link_condition() {
        let c = tetra();
        for e in 0..c.edges.len() {
            let [i, j] = c.edges[e].ends;
            assert!(!keeps_topology(&c, i, j), "edge {i}-{j}");
        }
    }

    /// Two tetrahedra, the second half as large and far away, with
    /// per-vertex areas giving the first 99 times the second's area.
    fn two_tetrahedra() -> (Complex, [f64; 8]) {
        let t = tetra();
        let mut pos = t.pos.clone();
        pos.extend(t.pos.iter().map(|p| *p * 0.5 + DVec3::splat(5.0)));
        let idx: Vec<u32> = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]
            .iter()
            .chain([4, 6, 5, 4, 5, 7, 4, 7, 6, 5, 6, 7].iter())
            .copied()
            .collect();
        let off: Vec<u32> = (0..=8).map(|k| 3 * k).collect();
        let c = Complex::new(pos, &off, &idx).0;
        (c, [24.75, 24.75, 24.75, 24.75, 0.25, 0.25, 0.25, 0.25])
    }

    #[test]
    fn parts_too_small_for_a_closed_shape_pay_for_their_size() {
        // Two tetrahedra, one with 99 times the other's area (per-vertex
        // areas given directly), the small one half as large. At 100
        // triangles the small one's share is 1 triangle, below a
        // tetrahedron's 4: it pays a target face's area (100 / 100 = 1)
        // times its squared diagonal (3 / 4), the large one the full
        // price. At 1000 triangles the small one's 10 is enough to keep:
        // everyone pays the full price (no list).
        let (c, area) = two_tetrahedra();
        let prices = pinch_prices(&c, &area, 100, 10.0, None, 1.0);
        assert_eq!(prices.base, 10.0);
        assert_eq!(
            prices.per_vertex,
            [10.0, 10.0, 10.0, 10.0, 0.75, 0.75, 0.75, 0.75]
        );
        assert_eq!((prices.at(0), prices.at(5)), (10.0, 0.75));
        // Never above the full price.
        let capped = pinch_prices(&c, &area, 100, 0.5, None, 1.0);
        assert!(capped.per_vertex.is_empty(), "{capped:?}");
        assert_eq!(capped.base, 0.5);
        let enough = pinch_prices(&c, &area, 1000, 10.0, None, 1.0);
        assert!(enough.per_vertex.is_empty());
        assert_eq!(enough.base, 10.0);
    }

    #[test]
    fn a_pinch_distance_prices_large_parts_like_a_collapse_at_the_target() {
        // The two tetrahedra above. With a pinch distance of 0.1 the large
        // one pays a target face's area (100 / 100 = 1) times 0.1²; the
        // small one still pays for its own size (0.75), which is larger.
        let (c, area) = two_tetrahedra();
        let prices = pinch_prices(&c, &area, 100, 10.0, Some(0.1), 1.0);
        assert!((prices.base - 0.01).abs() < 1e-12, "{}", prices.base);
        assert!((prices.at(0) - 0.01).abs() < 1e-9);
        assert!((prices.at(7) - 0.75).abs() < 1e-9);
        // At 1000 triangles a target face is 0.1: everyone pays 0.1 · 0.1²,
        // as one number.
        let all = pinch_prices(&c, &area, 1000, 10.0, Some(0.1), 1.0);
        assert!(all.per_vertex.is_empty());
        assert!((all.base - 0.001).abs() < 1e-12, "{}", all.base);
        // Never above the full price; 0 or no target is the full price.
        assert_eq!(
            pinch_prices(&c, &area, 100, 0.005, Some(0.1), 1.0).base,
            0.005
        );
        assert_eq!(
            pinch_prices(&c, &area, 100, 10.0, Some(0.0), 1.0).base,
            10.0
        );
        // Where the present faces rank too (scale 2), a collapse moving
        // the surface by a distance costs twice as much, and so does every
        // price below the cap: 0.02 and 1.5.
        let doubled = pinch_prices(&c, &area, 100, 10.0, Some(0.1), 2.0);
        assert!((doubled.at(0) - 0.02).abs() < 1e-9);
        assert!((doubled.at(7) - 1.5).abs() < 1e-9);
    }

    #[test]
    fn a_triangular_tube_pinches_and_a_closed_surface_does_not() {
        // An open tube of triangular cross-section: rings (0,1,2) and
        // (3,4,5), each side a quad split in two. Collapsing a ring edge
        // pinches (the third ring vertex is a neighbour of both with no
        // triangle); an edge along the tube does not.
        let pos = vec![
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-0.5, 0.87, 0.0),
            DVec3::new(-0.5, -0.87, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(-0.5, 0.87, 1.0),
            DVec3::new(-0.5, -0.87, 1.0),
        ];
        let mut idx = Vec::new();
        for a in 0..3u32 {
            let b = (a + 1) % 3;
            idx.extend([a, b, b + 3, a, b + 3, a + 3]);
        }
        let offsets: Vec<u32> = (0..=6).map(|k| 3 * k).collect();
        let c = Complex::new(pos, &offsets, &idx).0;
        assert!(pinches(&c, 0, 1));
        assert!(!pinches(&c, 0, 3));
        // Turned inside out it is a hole's wall: closing it wraps air,
        // not material, and is no pinch.
        let flipped: Vec<u32> = idx.chunks(3).flat_map(|t| [t[0], t[2], t[1]]).collect();
        let hole = Complex::new(c.pos.clone(), &offsets, &flipped).0;
        assert!(!pinches(&hole, 0, 1));
        // Not a face side: nothing to pinch.
        assert!(!pinches(&c, 0, 4));
        // A closed end folds: the tetrahedron's edges all fold it flat;
        // the octahedron's edges neither pinch nor fold.
        let t = tetra();
        assert!(pinches(&t, 0, 1));
        let o = octahedron();
        for e in 0..o.edges.len() {
            let [i, j] = o.edges[e].ends;
            assert!(!pinches(&o, i, j), "{i}-{j}");
        }
    }

    fn octahedron() -> Complex {
        let pos = vec![
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ];
        let tris = [
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        let idx: Vec<u32> = tris.iter().flatten().copied().collect();
        let off: Vec<u32> = (0..=8).map(|k| 3 * k).collect();
        Complex::new(pos, &off, &idx).0
    }

    #[test]
    fn octahedron_edges_pass_the_link_condition() {
        let c = octahedron();
        for e in 0..c.edges.len() {
            let [i, j] = c.edges[e].ends;
            assert!(keeps_topology(&c, i, j));
        }
    }

    #[test]
    fn pinching_two_border_vertices_across_the_interior_is_refused() {
        // A strip of two triangles 0-1-2, 1-3-2: all vertices on the border;
        // the inner edge 1-2 is not a border edge.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 3, 2]);
        assert!(!keeps_topology(&c, 1, 2));
        assert!(keeps_topology(&c, 0, 1));
    }

    #[test]
    fn flip_test_catches_a_vertex_pushed_through_its_fan() {
        // Fan around vertex 0 at the origin, all faces facing +z.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
        let (c, _) = Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1],
        );
        // Collapsing 0 onto 1 at 1: faces 0-2-3 and 0-3-4 stay convex-ish.
        assert_eq!(flipped_face(&c, 0, 1, DVec3::X, 0.0), None);
        // Moving 0 past vertex 3 on the far side flips face (0, 2, 3):
        // (-3,0), (0,1), (-1,0) winds clockwise.
        // (The collapse removes faces 0 and 3, which hold edge 0-1.)
        assert_eq!(
            flipped_face(&c, 0, 1, DVec3::new(-3.0, 0.0, 0.0), 0.0),
            Some(1)
        );
    }

    #[test]
    fn a_face_pressed_onto_a_line_counts_as_flattened() {
        // The fan of the flip test. Collapsing 0–1 onto -x gives face
        // (0, 2, 3) two equal corners (no area); onto +x every surviving
        // face keeps its area.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
        let (c, _) = Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1],
        );
        assert_eq!(flattens_a_face(&c, 0, 1, DVec3::X), None);
        // Face 1, (0, 2, 3), is the first that flattens: it is the witness.
        assert_eq!(flattens_a_face(&c, 0, 1, -DVec3::X), Some(1));
        // Onto the line through 2 and 3, between them: face (0, 2, 3) has
        // its three corners on one line.
        assert_eq!(
            flattens_a_face(&c, 0, 1, DVec3::new(-0.5, 0.5, 0.0)),
            Some(1)
        );
    }

    #[test]
    fn a_corner_brought_a_hair_off_another_counts_as_flattened() {
        // A unit quad (0, 1, 2, 3) and a triangle (1, 4, 2) beside it.
        // Collapsing 1–4 to 1e-12 off corner 2 keeps the quad's area (it
        // becomes a triangle with two corners in one place) and the area
        // test alone passes it; written as f32 the two corners are one.
        let pos = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::Y,
            DVec3::new(2.0, 0.5, 0.0),
        ];
        let (c, _) = Complex::new(pos, &[0, 4, 7], &[0, 1, 2, 3, 1, 4, 2]);
        let hair = DVec3::new(1.0 + 1e-12, 1.0, 0.0);
        assert_eq!(flattens_a_face(&c, 1, 4, hair), Some(0));
        // Half way to the corner, or 1e-6 of the way short of it: kept.
        assert_eq!(flattens_a_face(&c, 1, 4, DVec3::new(1.0, 0.5, 0.0)), None);
        assert_eq!(
            flattens_a_face(&c, 1, 4, DVec3::new(1.0, 1.0 - 1e-6, 0.0)),
            None
        );
    }

    #[test]
    fn removed_triangle_prediction_counts_dead_faces_and_duplicates() {
        let c = tetra();
        let mut star = Vec::new();
        c.star_faces(0, 1, &mut star);
        // Two faces on the edge die; the other two become (0,3,2)/(0,2,3):
        // opposite orientations, kept as twins.
        assert_eq!(removed_triangles(&c, &star, 0, 1), 2);
        assert_eq!(surviving_cycle(&[0, 1, 2, 0, 4]), vec![0, 1, 2]);
        assert_eq!(surviving_cycle(&[5, 5, 6, 7, 5]), vec![5, 6, 7]);
    }

    /// A complex with something for every rule: a bumpy grid of triangles
    /// and quads, some turned over, a fin of two triangles on an inner
    /// edge (non-manifold), a fan of 40 around the grid's corner, and a
    /// closed triangular tube (rings of three).
    fn rich_complex() -> Complex {
        let n = 8u32;
        let mut pos = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let z = 0.25 * (((x * 5 + y * 3) % 4) as f64 - 1.5);
                pos.push(DVec3::new(x as f64, y as f64, z));
            }
        }
        let (mut offsets, mut idx) = (vec![0u32], Vec::new());
        let mut face = |idx: &mut Vec<u32>, f: &[u32]| {
            idx.extend_from_slice(f);
            offsets.push(idx.len() as u32);
        };
        for y in 0..n - 1 {
            for x in 0..n - 1 {
                let v = y * n + x;
                let (a, b, c, d) = (v, v + 1, v + 1 + n, v + n);
                match (x * 7 + y * 3) % 5 {
                    0 => face(&mut idx, &[a, b, c, d]),
                    1 => {
                        face(&mut idx, &[a, c, b]);
                        face(&mut idx, &[a, d, c]);
                    }
                    _ => {
                        face(&mut idx, &[a, b, c]);
                        face(&mut idx, &[a, c, d]);
                    }
                }
            }
        }
        // A fin on the inner edge 9-10.
        let fin = pos.len() as u32;
        pos.push(DVec3::new(1.5, 1.0, 1.0));
        pos.push(DVec3::new(1.5, 0.5, 1.5));
        face(&mut idx, &[9, 10, fin]);
        face(&mut idx, &[10, fin + 1, fin]);
        // A fan of 40 around the grid's corner 0, outside the grid.
        let hub = 0u32;
        let rim = pos.len() as u32;
        for k in 0..=40 {
            let t = std::f64::consts::PI * (1.0 + 0.5 * k as f64 / 40.0);
            pos.push(DVec3::new(t.cos() * 3.0, t.sin() * 3.0, 0.0));
        }
        for k in 0..40 {
            face(&mut idx, &[hub, rim + k + 1, rim + k]);
        }
        // A closed tube of rings of three, capped.
        let tube = pos.len() as u32;
        for r in 0..5 {
            for k in 0..3 {
                let t = 2.0 * std::f64::consts::PI * k as f64 / 3.0;
                pos.push(DVec3::new(20.0 + 0.1 * t.cos(), 0.1 * t.sin(), r as f64));
            }
        }
        for r in 0..4 {
            for k in 0..3 {
                let (a, b) = (tube + 3 * r + k, tube + 3 * r + (k + 1) % 3);
                face(&mut idx, &[a, b, b + 3]);
                face(&mut idx, &[a, b + 3, a + 3]);
            }
        }
        face(&mut idx, &[tube + 2, tube + 1, tube]);
        face(&mut idx, &[tube + 12, tube + 13, tube + 14]);
        Complex::new(pos, &offsets, &idx).0
    }

    #[test]
    fn outwards_visits_every_position_once_nearest_first() {
        let seq: Vec<usize> = outwards(2, 6).collect();
        assert_eq!(seq, [2, 3, 1, 4, 0, 5]);
        assert_eq!(outwards(0, 5).collect::<Vec<_>>(), [0, 1, 4, 2, 3]);
        assert_eq!(outwards(0, 1).collect::<Vec<_>>(), [0]);
        assert_eq!(outwards(0, 0).count(), 0);
        for n in 1..40 {
            for start in 0..n {
                let mut seen: Vec<usize> = outwards(start, n).collect();
                seen.sort_unstable();
                assert_eq!(seen, (0..n).collect::<Vec<_>>(), "{start} of {n}");
            }
        }
    }

    #[test]
    fn local_guards_agree_with_reading_whole_stars() {
        // Every guard reads only the faces it must (the smaller star, the
        // faces that move); the versions reading both whole stars are the
        // reference. Same verdicts and the same witness faces on every
        // edge, both ways round, for positions at either end, between them,
        // lifted off, and on other vertices (where faces flatten), through
        // random collapses that shrink and merge the stars.
        use crate::terms::guards_oracle as whole;
        let mut c = rich_complex();
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let (mut star, mut changed) = (Vec::new(), Vec::new());
        let (mut checked, mut refused, mut flipped, mut flat, mut pinched) = (0, 0, 0, 0, 0);
        for _round in 0..40 {
            for e in 0..c.edges.len() {
                if !c.edges[e].alive() {
                    continue;
                }
                let [a, b] = c.edges[e].ends;
                for (i, j) in [(a, b), (b, a)] {
                    let want = whole::keeps_topology(&c, i, j);
                    assert_eq!(keeps_topology(&c, i, j), want, "link {i}-{j}");
                    refused += usize::from(!want);
                    let want = pinches_whole(&c, i, j);
                    assert_eq!(pinches_local(&c, i, j), want, "pinch {i}-{j}");
                    assert_eq!(pinches(&c, i, j), want, "pinch {i}-{j}");
                    pinched += usize::from(want);
                    c.star_faces(i, j, &mut star);
                    let (pi, pj) = (c.pos[i as usize], c.pos[j as usize]);
                    let other = c.pos[(next() % c.pos.len() as u64) as usize];
                    let mid = 0.5 * (pi + pj);
                    for x in [pi, pj, mid, mid + DVec3::new(0.3, -0.2, 0.7), other] {
                        for min_cos in [0.0, 0.7] {
                            let want = whole::flipped_face(&c, &star, i, j, x, min_cos);
                            assert_eq!(flipped_face(&c, i, j, x, min_cos), want, "flip {i}-{j}");
                            flipped += usize::from(want.is_some());
                        }
                        let want = whole::flattens_a_face(&c, &star, i, j, x);
                        assert_eq!(flattens_a_face(&c, i, j, x), want, "flat {i}-{j}");
                        flat += usize::from(want.is_some());
                        // Both in one pass: the earlier witness in the
                        // star's order, flattening first on the same face.
                        let at = |f: Option<u32>| f.and_then(|f| star.iter().position(|&g| g == f));
                        let (fl, fp) = (at(want), at(whole::flipped_face(&c, &star, i, j, x, 0.7)));
                        let both = match (fl, fp) {
                            (Some(a), Some(b)) if b < a => Some((star[b], Degrades::Flips)),
                            (Some(a), _) => Some((star[a], Degrades::Flattens)),
                            (None, Some(b)) => Some((star[b], Degrades::Flips)),
                            (None, None) => None,
                        };
                        let tests = FaceTests {
                            flatten: true,
                            min_cos: Some(0.7),
                        };
                        let mut scans = FaceScans::new(c.pos.len());
                        let got = degraded_face(&c, i, j, x, tests, &mut scans);
                        assert_eq!(got, both, "both {i}-{j}");
                        // From anywhere in `i`'s list: the same verdict,
                        // and a witness that fails the tests from the start.
                        scans.from[i as usize] = next() as u32;
                        let from = degraded_face(&c, i, j, x, tests, &mut scans);
                        assert_eq!(from.is_some(), both.is_some(), "resumed {i}-{j}");
                        if let Some((f, why)) = from {
                            assert!(star.contains(&f), "witness {f} of {i}-{j}");
                            // Found among `i`'s moving faces: `resume` is
                            // where, and scanning from there finds it first.
                            let list = &c.vert_faces[i as usize];
                            if c.pos[i as usize] != x && list.contains(&f) {
                                assert_eq!(list[scans.from[i as usize] as usize], f);
                                let again = degraded_face(&c, i, j, x, tests, &mut scans);
                                assert_eq!(again, Some((f, why)), "witness {i}-{j}");
                            }
                        }
                        checked += 1;
                    }
                }
            }
            // Collapse a few random edges (guards aside: any complex will do).
            for _ in 0..6 {
                let e = (next() % c.edges.len() as u64) as u32;
                if !c.edges[e as usize].alive() {
                    continue;
                }
                let [i, j] = c.edges[e as usize].ends;
                let x = match next() % 3 {
                    0 => c.pos[i as usize],
                    1 => c.pos[j as usize],
                    _ => 0.5 * (c.pos[i as usize] + c.pos[j as usize]),
                };
                c.collapse(e, i, x, false, &mut changed);
            }
        }
        // The cases were all there to disagree on.
        assert!(checked > 10_000, "{checked}");
        assert!(
            refused > 100 && flipped > 100 && flat > 100 && pinched > 10,
            "link {refused}, flip {flipped}, flat {flat}, pinch {pinched}"
        );
    }
}
