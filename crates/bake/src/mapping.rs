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
    /// collapses (ascending) whose vertex one-ring holds `f`.
    touch_start: Vec<u32>,
    touch: Vec<u32>,
    /// The edge one-ring of every collapse as flat triangles (polygons
    /// fanned), `ring_start[k]..ring_start[k + 1]`: the hot loop reads
    /// them contiguously.
    ring_start: Vec<u32>,
    rings: Vec<RingTriangle>,
}

/// A triangle of a recorded edge one-ring, with a bounding sphere for
/// skipping triangles that cannot be the closest.
#[derive(Clone, Copy, Debug)]
struct RingTriangle {
    corners: [Vec3; 3],
    center: Vec3,
    radius: f32,
    /// Unit normal (zero for a degenerate triangle) and `normal · corner`:
    /// the distance to the plane is a second lower bound, tighter than the
    /// sphere for the ring's tilted neighbours of a point on the surface.
    normal: Vec3,
    offset: f32,
    face: u32,
}

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
        for k in 0..history.len() {
            ring_start.push(rings.len() as u32);
            for rf in history.before(k) {
                let c = history.positions(rf);
                for t in 1..c.len().saturating_sub(1) {
                    let corners = [c[0], c[t], c[t + 1]].map(Vec3::from);
                    let center = (corners[0] + corners[1] + corners[2]) / 3.0;
                    let radius = corners
                        .iter()
                        .map(|&q| q.distance(center))
                        .fold(0.0f32, f32::max);
                    let normal = (corners[1] - corners[0])
                        .cross(corners[2] - corners[0])
                        .normalize_or_zero();
                    rings.push(RingTriangle {
                        corners,
                        center,
                        normal,
                        offset: normal.dot(corners[0]),
                        // Rounding of the distances above: a bound a
                        // hair too small would skip the true closest.
                        radius: radius * (1.0 + 1e-5) + 1e-12,
                        face: rf.face,
                    });
                }
            }
        }
        ring_start.push(rings.len() as u32);
        SuccessiveMap {
            history,
            positions,
            faces,
            touch_start,
            touch,
            ring_start,
            rings,
        }
    }

    /// Maps point `p` (input units) of the simplified mesh, lying on the
    /// output face whose input face id is `face` (`Simplified::face_origin`),
    /// to the input surface.
    ///
    /// # Panics
    /// When `face` is not a face id of the input.
    pub fn map(&self, face: u32, p: [f32; 3]) -> SurfacePoint {
        let target = DVec3::from(p.map(f64::from));
        let mut face = face;
        let mut q = target;
        let mut bound = self.history.len() as u32;
        // Each step strictly lowers `bound`: at most one step per collapse.
        while let Some(k) = self.previous_touch(face, bound) {
            if let Some((f, point)) = self.project_on_edge_ring(k as usize, face, target) {
                face = f;
                q = point;
            }
            bound = k;
        }
        self.on_input_face(face, q)
    }

    /// The last collapse before `bound` whose vertex one-ring holds `face`.
    fn previous_touch(&self, face: u32, bound: u32) -> Option<u32> {
        let f = face as usize;
        let list = &self.touch[self.touch_start[f] as usize..self.touch_start[f + 1] as usize];
        let i = list.partition_point(|&k| k < bound);
        i.checked_sub(1).map(|i| list[i])
    }

    /// The closest point to `p` on collapse `k`'s edge one-ring, as the
    /// ring recorded it (positions before the collapse); ties keep the
    /// point's current face, then the earlier triangle, so the answer is
    /// deterministic. The search starts
    /// on the point's current face (in the ring: the vertex one-ring after
    /// a collapse is part of the edge one-ring before it), usually the
    /// answer or close to it, and skips every triangle whose bounding
    /// sphere lies farther than the best distance so far.
    fn project_on_edge_ring(&self, k: usize, face: u32, p: DVec3) -> Option<(u32, DVec3)> {
        let ring = &self.rings[self.ring_start[k] as usize..self.ring_start[k + 1] as usize];
        let pf = p.as_vec3();
        let first = ring.iter().position(|t| t.face == face).unwrap_or(0);
        let t0 = ring.get(first)?;
        let (mut best_i, mut best_q) = (first, closest_on_triangle(pf, &t0.corners));
        let mut best_d2 = pf.distance_squared(best_q);
        // On its own face already (flat regions, untouched geometry):
        // nothing can be closer. The tolerance is far below f32 rounding
        // of the triangle's size, so this only skips exact ties.
        if best_d2 <= (1e-7 * t0.radius).powi(2) {
            return Some((t0.face, best_q.as_dvec3()));
        }
        let mut best_d = best_d2.sqrt();
        for (i, t) in ring.iter().enumerate() {
            // Every point of the triangle is at least |p − c| − r away, and
            // at least as far as its plane (a hair of slack for rounding).
            let reach = t.radius + best_d;
            if i == first
                || pf.distance_squared(t.center) > reach * reach
                || (t.normal.dot(pf) - t.offset).abs() > best_d * (1.0 + 1e-5) + 1e-12
            {
                continue;
            }
            let q = closest_on_triangle(pf, &t.corners);
            let d2 = pf.distance_squared(q);
            if d2 < best_d2 || (d2 == best_d2 && i < best_i) {
                (best_i, best_q, best_d2) = (i, q, d2);
                best_d = d2.sqrt();
            }
        }
        Some((ring[best_i].face, best_q.as_dvec3()))
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

/// The point of triangle `t` closest to `p` (Ericson, *Real-Time Collision
/// Detection*, §5.1.5, by Voronoi regions), in `f32`: the hot path. A
/// degenerate triangle can divide by zero there; it then goes to the exact
/// `f64` routine of `wildlod-geometry`.
#[inline]
fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + ab * v;
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + ac * w;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + (c - b) * w;
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    let q = a + ab * v + ac * w;
    if q.is_finite() {
        q
    } else {
        let (q, _) =
            closest_point_on_triangle(p.as_dvec3(), a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
        q.as_vec3()
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

    #[test]
    fn fast_closest_point_agrees_with_the_exact_one() {
        let t = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.1, 0.0),
            Vec3::new(0.3, 1.5, 0.2),
        ];
        // A grid of query points around the triangle hits every region.
        for i in -4..=8 {
            for j in -4..=8 {
                for k in -2..=2 {
                    let p = Vec3::new(i as f32 * 0.3, j as f32 * 0.3, k as f32 * 0.4);
                    let fast = closest_on_triangle(p, &t);
                    let (exact, _) = closest_point_on_triangle(
                        p.as_dvec3(),
                        t[0].as_dvec3(),
                        t[1].as_dvec3(),
                        t[2].as_dvec3(),
                    );
                    assert!((fast.as_dvec3() - exact).length() < 1e-5, "{p:?}");
                }
            }
        }
        // Degenerate (collinear) triangles still give a point on them.
        let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let q = closest_on_triangle(Vec3::new(1.5, 1.0, 0.0), &flat);
        assert!((q - Vec3::new(1.5, 0.0, 0.0)).length() < 1e-6, "{q:?}");
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
}
