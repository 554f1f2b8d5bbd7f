//! Splitting large polygons into small pieces along diagonals, in
//! O(k log k) for a k-gon, and triangulating a mesh's polygons
//! ([`triangulate`]).
//!
//! CAD exports and scanned caps carry polygons of thousands of corners.
//! Anything that is linear per face and runs once per corner of the face
//! is quadratic on them, and a fan triangulation makes one vertex of
//! valence k and k slivers whose bounding boxes all overlap. Both the
//! simplifier (pieces of at most 32 corners) and [`triangulate`] (triangles)
//! split such polygons here instead.
//!
//! The split is a balanced recursion: cut the polygon by a diagonal between
//! two corners about half its size apart, then cut both halves the same
//! way, until every piece is small. Each level costs O(k), there are
//! log₂(k / max) levels. Among a few candidate diagonals, one that stays
//! inside the polygon (checked in its best-fit plane) is preferred, so
//! planar non-convex polygons get non-overlapping pieces whenever such a
//! diagonal is among the candidates; when none is (deeply spiralled
//! outlines), the shortest candidate is used and pieces may overlap, which
//! costs accuracy but never time.

use crate::faces::Faces;
use crate::mesh::Mesh;

/// Polygons up to this many corners are fan-triangulated by
/// [`triangulate`] where the fan covers them (as they always were: the
/// corpus's largest polygon has 16); larger ones, and those a fan would
/// fold, are split here into triangles.
pub const FAN_MAX_CORNERS: usize = 32;

/// Diagonals tried per cut: enough that one stays inside most non-convex
/// outlines, few enough that a cut stays O(k).
const CANDIDATES: usize = 8;

/// Splits one polygon, given by the positions of its corners in order, into
/// pieces of at most `max_corners` corners (at least 3), and appends them to
/// `out` as local corner numbers (`0..points.len()`), in the polygon's
/// orientation. The pieces' triangle counts add up to the polygon's
/// (`k − 2`). A polygon of at most `max_corners` corners is appended whole.
pub fn split_polygon(points: &[[f32; 3]], max_corners: usize, out: &mut Faces) {
    let k = points.len();
    let max = max_corners.max(3);
    if k < 3 {
        return;
    }
    if k <= max {
        out.push(&(0..k as u32).collect::<Vec<u32>>());
        return;
    }
    let plane = Plane::fit(points);
    let uv: Vec<[f64; 2]> = points.iter().map(|p| plane.project(*p)).collect();
    // Sub-polygons of a convex polygon are convex: then any diagonal is
    // inside, and the checks are skipped at every level.
    let convex = is_convex(&uv);
    // Work allowed for ear cuts (see `ear_diagonal`): they can be as
    // unbalanced as 3 and m − 1, so they are bounded to keep O(k log k).
    let mut ear_budget = 32 * k;
    let mut stack: Vec<Vec<u32>> = vec![(0..k as u32).collect()];
    while let Some(piece) = stack.pop() {
        let m = piece.len();
        if m <= max {
            out.push(&piece);
            continue;
        }
        let (a, b) = match choose_diagonal(&piece, &uv, convex) {
            (a, b, true) => (a, b),
            (a, b, false) if ear_budget < m => (a, b),
            (a, b, false) => {
                ear_budget -= m;
                ear_diagonal(&piece, &uv).unwrap_or((a, b))
            }
        };
        // a < b; the pieces are a..=b and b..=a (wrapping).
        let first: Vec<u32> = piece[a..=b].to_vec();
        let mut second: Vec<u32> = piece[b..].to_vec();
        second.extend_from_slice(&piece[..=a]);
        stack.push(second);
        stack.push(first);
    }
}

/// Triangulates every polygon: a polygon of up to
/// [`FAN_MAX_CORNERS`] corners by a fan (face `[a, b, c, d]`
/// becomes `[a, b, c]` and `[a, c, d]`) when the fan covers it or the
/// polygon is warped (it has no outline: the fan is what draws it), a
/// larger one, or a flat one whose fan would fold ([`fan_covers`]: a
/// non-convex outline, an L-shaped wall, a letter's cap, a dart), by
/// [`split_polygon`] (a fan of a large polygon gives one vertex of valence
/// k and k overlapping slivers). Attribute and skinning indices follow their
/// corners; parts are kept. Triangles are returned unchanged.
pub fn triangulate(mesh: &Mesh) -> Mesh {
    let tri = mesh.faces.triangulated_count();
    let mut faces = Faces::with_capacity(tri, 3 * tri);
    let mut corner_src: Vec<usize> = Vec::with_capacity(3 * tri);
    let mut face_parts = Vec::with_capacity(tri);
    let mut pieces = Faces::new();
    let mut points = Vec::new();
    for f in 0..mesh.faces.len() {
        let r = mesh.faces.corner_range(f);
        let part = mesh.face_parts.get(f).copied().unwrap_or(0);
        points.clear();
        if r.len() > 3 {
            points.extend(r.clone().map(|c| {
                mesh.positions
                    .get(mesh.faces.indices[c] as usize)
                    .copied()
                    .unwrap_or([0.0; 3])
            }));
        }
        if r.len() <= 3 || (r.len() <= FAN_MAX_CORNERS && (fan_covers(&points) || !planar(&points)))
        {
            for k in 1..r.len().saturating_sub(1) {
                let cs = [r.start, r.start + k, r.start + k + 1];
                faces.push(&cs.map(|c| mesh.faces.indices[c]));
                corner_src.extend_from_slice(&cs);
                face_parts.push(part);
            }
            continue;
        }
        pieces.offsets.truncate(1);
        pieces.indices.clear();
        split_polygon(&points, 3, &mut pieces);
        for t in pieces.iter() {
            let cs = [0, 1, 2].map(|i| r.start + t[i] as usize);
            faces.push(&cs.map(|c| mesh.faces.indices[c]));
            corner_src.extend_from_slice(&cs);
            face_parts.push(part);
        }
    }
    let mut out = Mesh {
        name: mesh.name.clone(),
        positions: mesh.positions.clone(),
        faces,
        face_parts,
        parts: mesh.parts.clone(),
        attributes: mesh.attributes.clone(),
        skinning: mesh.skinning.clone(),
    };
    for a in &mut out.attributes {
        a.indices = corner_src.iter().map(|&c| a.indices[c]).collect();
    }
    if let Some(s) = &mut out.skinning {
        s.indices = corner_src.iter().map(|&c| s.indices[c]).collect();
    }
    out
}

/// Whether the fan from the first corner triangulates the polygon: no fan
/// triangle turns against the polygon's (Newell) normal by more than
/// rounding. The fan's signed areas always add up to the polygon's, so
/// with none negative they do not overlap and cover it exactly; a
/// negative one (the first corner cannot see past a reflex corner) folds
/// over its neighbours and pokes out of the outline. Convex polygons,
/// with or without corners on a straight side, keep their fan.
pub fn fan_covers(points: &[[f32; 3]]) -> bool {
    let k = points.len();
    if k <= 3 {
        return true;
    }
    let at = |i: usize| points[i].map(f64::from);
    let n = newell(points);
    let nn = dot(n, n);
    if !(nn > 0.0 && nn.is_finite()) {
        // No area: nothing a triangulation could fold.
        return true;
    }
    let o = at(0);
    let sub = |a: [f64; 3]| [a[0] - o[0], a[1] - o[1], a[2] - o[2]];
    // Twice a fan triangle's area along n, against 1e-9 of the polygon's.
    (1..k - 1).all(|i| dot(cross(sub(at(i)), sub(at(i + 1))), n) >= -1e-9 * nn)
}

/// A polygon's corners deviate from its (Newell) plane through their
/// centroid by at most this share of its extent: below it, the polygon is
/// flat to any screen and has an outline a triangulation must cover;
/// above it (a warped quad of a coarse cage), it has no plane, and the fan
/// from its first corner is what draws it (`cost::face_share` simplifies
/// it as that fan, and renderers and readers draw it so).
const PLANAR: f64 = 1e-3;

/// Whether the corners lie in one plane to [`PLANAR`] of their extent.
fn planar(points: &[[f32; 3]]) -> bool {
    let k = points.len();
    let at = |i: usize| points[i].map(f64::from);
    let n = newell(points);
    let mut c = [0.0f64; 3];
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for i in 0..k {
        let a = at(i);
        for x in 0..3 {
            c[x] += a[x] / k as f64;
            lo[x] = lo[x].min(a[x]);
            hi[x] = hi[x].max(a[x]);
        }
    }
    let len = dot(n, n).sqrt();
    let extent = (0..3).map(|x| hi[x] - lo[x]).fold(0.0, f64::max);
    if !(len > 0.0 && extent > 0.0) {
        // No area or no extent: nothing to warp.
        return true;
    }
    (0..k).all(|i| {
        let p = at(i);
        let d = dot([p[0] - c[0], p[1] - c[1], p[2] - c[2]], n) / len;
        d.abs() <= PLANAR * extent
    })
}

/// The diagonal (local positions `a < b` in `piece`) to cut along: the
/// first candidate inside the polygon, else the shortest candidate (and
/// `false`: the caller may look for an inner one the slow way).
/// Candidates start at eight corners spread around the piece and end about
/// half the piece further (then a third or two thirds): pieces shrink by a
/// constant factor per cut whatever is chosen, so the depth stays
/// logarithmic. The offsets next to one half catch outlines with a short
/// period (a comb's teeth).
fn choose_diagonal(piece: &[u32], uv: &[[f64; 2]], convex: bool) -> (usize, usize, bool) {
    let m = piece.len();
    let half = m / 2;
    if convex {
        return (0, half, true);
    }
    let offsets = [
        half,
        half - 1,
        half + 1,
        half - 2,
        half + 2,
        m / 3,
        2 * m / 3,
    ];
    let starts = CANDIDATES.min(m);
    let mut shortest: Option<(f64, usize, usize)> = None;
    for &offset in &offsets {
        if offset < 2 || offset + 2 > m {
            continue;
        }
        for t in 0..starts {
            let a = t * m / starts;
            let b = (a + offset) % m;
            let (a, b) = (a.min(b), a.max(b));
            if diagonal_inside(piece, uv, a, b) {
                return (a, b, true);
            }
            let p = uv[piece[a] as usize];
            let q = uv[piece[b] as usize];
            let len = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
            // NaN lengths (degenerate projections) never win over a number.
            if shortest.map_or(true, |(l, _, _)| len < l) {
                shortest = Some((len, a, b));
            }
        }
    }
    match shortest {
        Some((_, a, b)) => (a, b, false),
        None => (0, half, false),
    }
}

/// An inner diagonal of a simple polygon in O(m), however unbalanced: the
/// leftmost corner v is convex; with neighbours u and w, either no corner
/// lies in triangle uvw and uw is a diagonal, or the corner in it farthest
/// from uw sees v (the classic two-ears argument).
fn ear_diagonal(piece: &[u32], uv: &[[f64; 2]]) -> Option<(usize, usize)> {
    let m = piece.len();
    let at = |i: usize| uv[piece[i] as usize];
    let v = (0..m).min_by(|&a, &b| {
        let (p, q) = (at(a), at(b));
        p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1]))
    })?;
    let u = (v + m - 1) % m;
    let w = (v + 1) % m;
    let (pu, pv, pw) = (at(u), at(v), at(w));
    let mut farthest: Option<(f64, usize)> = None;
    for i in 0..m {
        if i == u || i == v || i == w {
            continue;
        }
        let p = at(i);
        let s = [orient(pu, pv, p), orient(pv, pw, p), orient(pw, pu, p)];
        let inside = s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0);
        if inside {
            let d = orient(pu, pw, p).abs();
            if farthest.map_or(true, |(fd, _)| d > fd) {
                farthest = Some((d, i));
            }
        }
    }
    let (a, b) = match farthest {
        None => (u, w),
        Some((_, z)) => (v, z),
    };
    let (a, b) = (a.min(b), a.max(b));
    // Both pieces need three corners.
    (b - a >= 2 && m - (b - a) >= 2).then_some((a, b))
}

/// Whether the segment between corners `a` and `b` of `piece` crosses no
/// side of the piece and its midpoint lies inside it (in the plane).
fn diagonal_inside(piece: &[u32], uv: &[[f64; 2]], a: usize, b: usize) -> bool {
    let m = piece.len();
    let p = uv[piece[a] as usize];
    let q = uv[piece[b] as usize];
    for s in 0..m {
        let t = if s + 1 == m { 0 } else { s + 1 };
        if s == a || t == a || s == b || t == b {
            continue;
        }
        if segments_cross(p, q, uv[piece[s] as usize], uv[piece[t] as usize]) {
            return false;
        }
    }
    let mid = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
    contains(piece, uv, mid)
}

/// Proper or touching intersection of segments pq and rs.
fn segments_cross(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let d1 = orient(r, s, p);
    let d2 = orient(r, s, q);
    let d3 = orient(p, q, r);
    let d4 = orient(p, q, s);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    // A corner of the side lying on the diagonal blocks it too.
    (d3 == 0.0 && on_segment(p, q, r)) || (d4 == 0.0 && on_segment(p, q, s))
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn on_segment(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> bool {
    r[0] >= p[0].min(q[0])
        && r[0] <= p[0].max(q[0])
        && r[1] >= p[1].min(q[1])
        && r[1] <= p[1].max(q[1])
}

/// Even-odd point-in-polygon test.
fn contains(piece: &[u32], uv: &[[f64; 2]], x: [f64; 2]) -> bool {
    let m = piece.len();
    let mut inside = false;
    for s in 0..m {
        let a = uv[piece[s] as usize];
        let b = uv[piece[(s + 1) % m] as usize];
        if (a[1] > x[1]) != (b[1] > x[1]) {
            let t = (x[1] - a[1]) / (b[1] - a[1]);
            if x[0] < a[0] + t * (b[0] - a[0]) {
                inside = !inside;
            }
        }
    }
    inside
}

/// Strictly convex and simple in the plane: every turn has the same sign
/// and the outline winds once.
fn is_convex(uv: &[[f64; 2]]) -> bool {
    let k = uv.len();
    let mut sign = 0.0f64;
    let mut winding = 0.0f64;
    for i in 0..k {
        let a = uv[i];
        let b = uv[(i + 1) % k];
        let c = uv[(i + 2) % k];
        let turn = orient(a, b, c);
        if !turn.is_finite() || turn == 0.0 {
            return false;
        }
        if sign == 0.0 {
            sign = turn.signum();
        } else if turn.signum() != sign {
            return false;
        }
        let e1 = [b[0] - a[0], b[1] - a[1]];
        let e2 = [c[0] - b[0], c[1] - b[1]];
        winding += (e1[0] * e2[1] - e1[1] * e2[0]).atan2(e1[0] * e2[0] + e1[1] * e2[1]);
    }
    // One full turn (2π); a star polygon turns several times.
    (winding.abs() - std::f64::consts::TAU).abs() < 1e-6
}

/// The polygon's best-fit plane (Newell normal) as an orthonormal basis.
struct Plane {
    u: [f64; 3],
    v: [f64; 3],
}

impl Plane {
    fn fit(points: &[[f32; 3]]) -> Plane {
        let n = newell(points);
        let len = dot(n, n).sqrt();
        let n = if len > 0.0 && len.is_finite() {
            n.map(|c| c / len)
        } else {
            // No area (a line, a point): any plane serves; diagonals then
            // fall back to the shortest, which is all a line allows.
            [0.0, 0.0, 1.0]
        };
        // A unit vector orthogonal to n from the axis n is least along,
        // then the third completes a right-handed basis, so the projection
        // keeps the polygon's orientation.
        let axis = if n[0].abs() <= n[1].abs() && n[0].abs() <= n[2].abs() {
            [1.0, 0.0, 0.0]
        } else if n[1].abs() <= n[2].abs() {
            [0.0, 1.0, 0.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        let u = cross(n, axis);
        let ul = dot(u, u).sqrt();
        let u = u.map(|c| c / ul);
        Plane { u, v: cross(n, u) }
    }

    fn project(&self, p: [f32; 3]) -> [f64; 2] {
        let p = p.map(f64::from);
        [dot(p, self.u), dot(p, self.v)]
    }
}

/// The polygon's Newell normal (twice its area along the normal), in
/// double precision.
fn newell(points: &[[f32; 3]]) -> [f64; 3] {
    let k = points.len();
    let mut n = [0.0f64; 3];
    for i in 0..k {
        let a = points[i].map(f64::from);
        let b = points[(i + 1) % k].map(f64::from);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::quad_grid;

    fn circle(k: usize) -> Vec<[f32; 3]> {
        (0..k)
            .map(|i| {
                let a = i as f32 / k as f32 * std::f32::consts::TAU;
                [a.cos(), a.sin(), 0.0]
            })
            .collect()
    }

    fn pieces(points: &[[f32; 3]], max: usize) -> Faces {
        let mut out = Faces::new();
        split_polygon(points, max, &mut out);
        out
    }

    #[test]
    fn split_keeps_the_triangle_count_and_the_piece_bound() {
        for k in [3, 4, 5, 33, 100, 1000] {
            for max in [3, 4, 32] {
                let f = pieces(&circle(k), max);
                assert_eq!(f.triangulated_count(), k - 2, "k {k} max {max}");
                assert!(f.iter().all(|p| p.len() <= max.max(3) && p.len() >= 3));
            }
        }
    }

    #[test]
    fn every_side_of_the_polygon_is_a_side_of_exactly_one_piece() {
        let k = 257;
        let f = pieces(&circle(k), 5);
        let mut count = vec![0; k];
        for p in f.iter() {
            for s in 0..p.len() {
                let (a, b) = (p[s] as usize, p[(s + 1) % p.len()] as usize);
                if b == (a + 1) % k {
                    count[a] += 1;
                }
            }
        }
        assert!(count.iter().all(|&c| c == 1), "{count:?}");
    }

    #[test]
    fn large_triangulation_has_no_vertex_of_high_valence() {
        // A fan gives corner 0 valence k; the balanced split keeps every
        // corner in O(log k) triangles.
        let k = 4096;
        let f = pieces(&circle(k), 3);
        let mut valence = vec![0usize; k];
        for t in f.iter() {
            for &v in t {
                valence[v as usize] += 1;
            }
        }
        let worst = valence.iter().copied().max().unwrap_or(0);
        assert!(worst <= 2 * 13 + 2, "a corner is in {worst} triangles");
    }

    #[test]
    fn concave_comb_is_cut_inside_the_outline() {
        // A comb: a base and 20 thin teeth. Every piece's centroid must lie
        // inside the outline, which a fan from corner 0 would break.
        let mut pts = vec![[0.0f32, 0.0, 0.0], [40.0, 0.0, 0.0]];
        for t in (0..20).rev() {
            let x = 2.0 * t as f32;
            pts.push([x + 2.0, 10.0, 0.0]);
            pts.push([x + 1.0, 10.0, 0.0]);
            pts.push([x + 1.0, 1.0, 0.0]);
            pts.push([x, 1.0, 0.0]);
        }
        pts.pop();
        let f = pieces(&pts, 3);
        let uv: Vec<[f64; 2]> = pts.iter().map(|p| [p[0] as f64, p[1] as f64]).collect();
        let all: Vec<u32> = (0..pts.len() as u32).collect();
        let outside = f
            .iter()
            .filter(|t| {
                let c = t.iter().fold([0.0, 0.0], |s, &v| {
                    [
                        s[0] + uv[v as usize][0] / 3.0,
                        s[1] + uv[v as usize][1] / 3.0,
                    ]
                });
                !contains(&all, &uv, c)
            })
            .count();
        assert_eq!(f.triangulated_count(), pts.len() - 2);
        assert_eq!(outside, 0, "{outside} triangles outside the comb");
    }

    /// One mesh holding `polygons` (each its own positions, in the plane
    /// z = 0), triangulated; per polygon its triangles' signed areas.
    fn triangle_areas(polygons: &[Vec<[f32; 2]>]) -> Vec<Vec<f64>> {
        let mut positions = Vec::new();
        let mut faces = Faces::new();
        for poly in polygons {
            let base = positions.len() as u32;
            positions.extend(poly.iter().map(|p| [p[0], p[1], 0.0]));
            faces.push(&(base..base + poly.len() as u32).collect::<Vec<u32>>());
        }
        let tri = triangulate(&Mesh::from_polygons(positions, faces));
        let mut out = vec![Vec::new(); polygons.len()];
        let mut first = 0;
        for (k, poly) in polygons.iter().enumerate() {
            for t in first..first + poly.len() - 2 {
                let [a, b, c] = [0, 1, 2].map(|i| tri.positions[tri.faces.face(t)[i] as usize]);
                let area = 0.5
                    * ((b[0] - a[0]) as f64 * (c[1] - a[1]) as f64
                        - (b[1] - a[1]) as f64 * (c[0] - a[0]) as f64);
                out[k].push(area);
            }
            first += poly.len() - 2;
        }
        out
    }

    fn shoelace(poly: &[[f32; 2]]) -> f64 {
        let k = poly.len();
        0.5 * (0..k)
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % k]);
                a[0] as f64 * b[1] as f64 - b[0] as f64 * a[1] as f64
            })
            .sum::<f64>()
    }

    #[test]
    fn a_polygon_the_fan_would_fold_is_cut_along_inner_diagonals() {
        // An L-shaped wall face starting at a corner that cannot see the
        // far arm; a dart-shaped quad whose first corner's diagonal runs
        // outside; a star of 20 corners. The fan from corner 0 folds each:
        // a triangle turned over and the rest poking out of the outline.
        let l_shape = vec![
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
            [0.0, 0.0],
        ];
        let dart = vec![[0.0, 0.0], [1.0, 0.4], [2.0, 0.0], [1.0, 2.0]];
        let star: Vec<[f32; 2]> = (0..20)
            .map(|i| {
                let a = i as f32 / 20.0 * std::f32::consts::TAU + 0.1;
                let r = if i % 2 == 0 { 1.0 } else { 0.4 };
                [r * a.cos(), r * a.sin()]
            })
            .collect();
        let polys = [l_shape, dart, star];
        for poly in &polys {
            let pts: Vec<[f32; 3]> = poly.iter().map(|p| [p[0], p[1], 0.0]).collect();
            assert!(!fan_covers(&pts), "the fan should fold {poly:?}");
        }
        for (poly, areas) in polys.iter().zip(triangle_areas(&polys)) {
            let want = shoelace(poly);
            assert!(want > 0.0);
            // No triangle turned over, so none overlaps another, and
            // together they cover exactly the outline's area.
            assert!(areas.iter().all(|&a| a >= 0.0), "{poly:?}: {areas:?}");
            let got: f64 = areas.iter().sum();
            assert!((got - want).abs() <= 1e-6 * want, "{poly:?}: {got} {want}");
        }
    }

    #[test]
    fn convex_polygons_keep_their_fan() {
        // A hexagon with a corner on a straight side, an L-shape starting
        // at the corner that sees every other, and a warped quad.
        let hexagon = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 2.0],
            [0.0, 1.0],
        ];
        let l_seen = vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        for poly in [hexagon, l_seen] {
            let pts: Vec<[f32; 3]> = poly.iter().map(|p| [p[0], p[1], 0.0]).collect();
            assert!(fan_covers(&pts), "{poly:?}");
        }
        let warped = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.2],
        ];
        assert!(fan_covers(&warped));
        let mut faces = Faces::new();
        faces.push(&[0, 1, 2, 3]);
        let tri = triangulate(&Mesh::from_polygons(warped.to_vec(), faces));
        assert_eq!(tri.faces.indices, vec![0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn a_warped_quad_keeps_its_fan_even_where_it_folds() {
        // One of spot_control_mesh's quads at 50%, warped by a fifth of
        // its size: its fan from corner 0 turns a triangle against the
        // Newell normal, but it has no outline to cover, and the fan is
        // what the simplifier measured and readers draw.
        let warped = vec![
            [-0.088, 0.694, -0.232],
            [-0.58, 0.69, -0.004],
            [-0.377, 0.511, -0.26],
            [-0.268, 0.537, -0.046],
        ];
        assert!(!fan_covers(&warped));
        assert!(!planar(&warped));
        let mut faces = Faces::new();
        faces.push(&[0, 1, 2, 3]);
        let tri = triangulate(&Mesh::from_polygons(warped, faces));
        assert_eq!(tri.faces.indices, vec![0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn degenerate_polygons_split_without_panicking() {
        let same = vec![[1.0f32, 1.0, 1.0]; 50];
        assert_eq!(pieces(&same, 4).triangulated_count(), 48);
        let line: Vec<[f32; 3]> = (0..50).map(|i| [i as f32, 0.0, 0.0]).collect();
        assert_eq!(pieces(&line, 3).triangulated_count(), 48);
    }

    #[test]
    fn triangulate_grid_keeps_uvs_per_corner() {
        let g = quad_grid(2, 1);
        let t = triangulate(&g);
        assert_eq!(t.faces.len(), 4);
        assert_eq!(t.faces.face(1), &[0, 4, 3]);
        let uv = &t.attributes[0];
        assert_eq!(uv.indices.len(), 12);
        // Corner 4 is vertex 4 at (0.5, 1).
        assert_eq!(uv.corner_value(4), Some(&[0.5, 1.0][..]));
        t.validate().unwrap();
    }
}
