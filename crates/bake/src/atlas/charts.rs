//! Charts: triangles grown into regions of similar normal, each projected
//! orthographically along its own direction, and cut where the projection
//! folds.
//!
//! Growth starts at the largest unassigned triangle. A first pass takes
//! neighbours (across edges shared by exactly two triangles, with the same
//! key) nearest normal first while they stay within the cone of the
//! chart's running mean normal; the mean of what it took is the chart's
//! direction. A second pass grows the chart again from its member best
//! aligned with that direction, taking every connected triangle within the
//! cone of the direction: each triangle faces the direction it is
//! projected along by less than the cone angle (below 90°: none flips), so
//! it is stretched by at most 1/cos of it.
//!
//! Projection can still fold a chart over itself (a gently sloped spiral
//! ramp). A chart is kept when its triangles are all positively oriented
//! and its boundary does not cross itself: a locally injective map of a
//! surface whose boundary is embedded is injective. Otherwise the
//! triangles it turns over, or else those whose boundary sides cross, are
//! dropped and each connected rest is projected again. Dropped triangles,
//! and those outside every chart's cone, make charts among themselves at
//! the same cone while they are a minority, else at half the cone, down to
//! single triangles, which are always injective.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::DVec3;

/// A chart: its triangles and the 2D coordinates (surface units) of their
/// corners, three per triangle, in the order of `triangles`.
#[derive(Clone, Debug)]
pub(crate) struct Chart {
    pub triangles: Vec<u32>,
    pub coords: Vec<[f64; 2]>,
}

const NONE: u32 = u32::MAX;

struct Surface<'a> {
    positions: &'a [[f32; 3]],
    triangles: &'a [[u32; 3]],
    normals: Vec<DVec3>,
    areas: Vec<f64>,
    /// Per triangle, the triangles across each of its three edges (or NONE).
    neighbours: Vec<[u32; 3]>,
    keys: &'a [u32],
}

impl Surface<'_> {
    fn point(&self, v: u32) -> DVec3 {
        DVec3::from(self.positions[v as usize].map(f64::from))
    }

    fn key(&self, t: u32) -> u32 {
        self.keys.get(t as usize).copied().unwrap_or(0)
    }
}

/// Charts covering every triangle once; `cos` is the cosine of the cone
/// angle.
pub(crate) fn make_charts(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    keys: &[u32],
    cos: f64,
) -> Vec<Chart> {
    let mut normals = Vec::with_capacity(triangles.len());
    let mut areas = Vec::with_capacity(triangles.len());
    for t in triangles {
        let p = t.map(|v| DVec3::from(positions[v as usize].map(f64::from)));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let len = n.length();
        areas.push(0.5 * len);
        // Degenerate triangles have no normal: they go with any chart.
        normals.push(if len > 0.0 && len.is_finite() {
            n / len
        } else {
            DVec3::ZERO
        });
    }
    let surface = Surface {
        positions,
        triangles,
        neighbours: neighbours(triangles),
        normals,
        areas,
        keys,
    };
    let all: Vec<u32> = (0..triangles.len() as u32).collect();
    let mut out = Vec::new();
    charts_of(&surface, &all, cos, &mut out);
    out
}

/// Triangles across each edge, for edges used by exactly two triangles.
fn neighbours(triangles: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut edges: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a != b {
                edges.push((a.min(b), a.max(b), t as u32, k as u8));
            }
        }
    }
    edges.sort_unstable();
    let mut out = vec![[NONE; 3]; triangles.len()];
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && (edges[j].0, edges[j].1) == (edges[i].0, edges[i].1) {
            j += 1;
        }
        // Non-manifold edges (three or more triangles) join nothing: a
        // chart across them could not be flattened without a fold.
        if j - i == 2 && edges[i].2 != edges[i + 1].2 {
            let (x, y) = (edges[i], edges[i + 1]);
            out[x.2 as usize][x.3 as usize] = y.2;
            out[y.2 as usize][y.3 as usize] = x.2;
        }
        i = j;
    }
    out
}

/// A triangle waiting to join a chart, nearest normal first.
#[derive(PartialEq)]
struct Candidate {
    cos: f64,
    triangle: u32,
}

impl Eq for Candidate {}

impl Ord for Candidate {
    fn cmp(&self, o: &Self) -> Ordering {
        self.cos
            .total_cmp(&o.cos)
            .then(o.triangle.cmp(&self.triangle))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Charts of the triangles `set` (an ascending list), appended to `out`.
fn charts_of(s: &Surface, set: &[u32], cos: f64, out: &mut Vec<Chart>) {
    let mut in_set = std::collections::HashSet::with_capacity(set.len());
    in_set.extend(set.iter().copied());
    let mut order = set.to_vec();
    // Largest first, ties by index: deterministic seeds.
    order.sort_by(|&a, &b| {
        s.areas[b as usize]
            .total_cmp(&s.areas[a as usize])
            .then(a.cmp(&b))
    });
    let mut taken = std::collections::HashSet::with_capacity(set.len());
    for &seed in &order {
        if taken.contains(&seed) {
            continue;
        }
        let (members, axis) = grow(s, seed, cos, &in_set, &mut taken);
        for t in settle(s, members, axis, out) {
            taken.remove(&t);
        }
    }
    // What no chart kept: triangles outside every axis's cone that came
    // back after their seed's turn (a noisy surface's spikes), and those
    // that fold a projection.
    let left: Vec<u32> = set.iter().copied().filter(|t| !taken.contains(t)).collect();
    if left.is_empty() {
        return;
    }
    // A minority charts again at the same cone; a set that keeps folding
    // goes to half the cone, and below 2° every triangle is its own chart.
    if 2 * left.len() <= set.len() {
        return charts_of(s, &left, cos, out);
    }
    let half = ((cos.acos()) * 0.5).cos();
    if half > (2f64).to_radians().cos() {
        out.extend(left.iter().map(|&t| single(s, t)));
    } else {
        charts_of(s, &left, half, out);
    }
}

/// At most this many rounds of dropping the triangles that fold a chart's
/// projection; a chart still folded after them is given up whole.
const SETTLE_ROUNDS: usize = 8;

/// Appends the chart of `members` projected along `axis` to `out`, or,
/// where the projection folds, the charts of what is left once the
/// triangles that fold it are dropped (each connected rest projected
/// anew). Returns the triangles dropped.
///
/// A noisy surface (a scan, a terrain) folds a chart at a few spikes: all
/// the rest of it projects injectively. Charting the whole chart again at
/// a narrower cone, as a fold used to cause, cut such surfaces into tens of
/// thousands of charts of three triangles, mostly padding in the atlas.
fn settle(s: &Surface, members: Vec<u32>, axis: DVec3, out: &mut Vec<Chart>) -> Vec<u32> {
    let mut dropped = Vec::new();
    let mut pending = vec![(members, 0usize)];
    while let Some((m, round)) = pending.pop() {
        match project(s, &m, axis) {
            Ok(chart) => out.push(chart),
            Err(_) if m.len() == 1 => out.push(single(s, m[0])),
            Err(folding) if round < SETTLE_ROUNDS && folding.len() < m.len() => {
                let rest: Vec<u32> = m
                    .iter()
                    .copied()
                    .filter(|t| folding.binary_search(t).is_err())
                    .collect();
                dropped.extend(folding);
                pending.extend(components(s, &rest).into_iter().map(|c| (c, round + 1)));
            }
            Err(_) => dropped.extend(m),
        }
    }
    dropped
}

/// The connected parts of `members` (across edges of two triangles).
fn components(s: &Surface, members: &[u32]) -> Vec<Vec<u32>> {
    let mut left: std::collections::HashSet<u32> = members.iter().copied().collect();
    let mut parts = Vec::new();
    for &t in members {
        if !left.remove(&t) {
            continue;
        }
        let mut part = vec![t];
        let mut k = 0;
        while k < part.len() {
            for &n in &s.neighbours[part[k] as usize] {
                if n != NONE && left.remove(&n) {
                    part.push(n);
                }
            }
            k += 1;
        }
        parts.push(part);
    }
    parts
}

/// The chart grown from `seed` (its triangles, taken) and the direction it
/// is projected along.
///
/// Two passes. The first finds the direction: neighbours join nearest
/// normal first while within the cone of the chart's running mean normal
/// (not of the seed's: on a noisy surface the largest triangle may be
/// tilted by the noise, and a cone around it cut the chart short). The
/// second grows the chart again from its member best aligned with that
/// direction, taking every connected triangle within the cone of the
/// direction itself, so each is stretched by at most 1/cos as promised,
/// against the direction it is projected along.
fn grow(
    s: &Surface,
    seed: u32,
    cos: f64,
    in_set: &std::collections::HashSet<u32>,
    taken: &mut std::collections::HashSet<u32>,
) -> (Vec<u32>, DVec3) {
    let n_seed = s.normals[seed as usize];
    let first = spread(s, seed, in_set, taken, |n, sum| {
        let mean = sum.normalize_or_zero();
        n == DVec3::ZERO || mean == DVec3::ZERO || n.dot(mean) >= cos
    });
    let sum: DVec3 = first
        .iter()
        .map(|&t| s.normals[t as usize] * s.areas[t as usize])
        .sum();
    let axis = match sum.try_normalize() {
        Some(a) => a,
        None => return (first, n_seed),
    };
    for t in &first {
        taken.remove(t);
    }
    let start = first
        .iter()
        .copied()
        .max_by(|&a, &b| {
            let (na, nb) = (s.normals[a as usize], s.normals[b as usize]);
            na.dot(axis).total_cmp(&nb.dot(axis)).then(b.cmp(&a))
        })
        .unwrap_or(seed);
    if s.normals[start as usize] != DVec3::ZERO && s.normals[start as usize].dot(axis) < cos {
        // No member within the cone of the mean (normals that cancel):
        // the seed alone.
        taken.insert(seed);
        return (vec![seed], n_seed);
    }
    let members = spread(s, start, in_set, taken, |n, _| {
        n == DVec3::ZERO || n.dot(axis) >= cos
    });
    (members, axis)
}

/// The triangles reached from `start` across edges of two triangles, among
/// `in_set`, not `taken` and with `start`'s key, nearest normal to the
/// running mean first, each joining when `fits(normal, area-weighted sum of
/// the members' normals)`; all of them taken.
fn spread(
    s: &Surface,
    start: u32,
    in_set: &std::collections::HashSet<u32>,
    taken: &mut std::collections::HashSet<u32>,
    fits: impl Fn(DVec3, DVec3) -> bool,
) -> Vec<u32> {
    let key = s.key(start);
    let mut sum = s.normals[start as usize] * s.areas[start as usize];
    let mut members = vec![start];
    taken.insert(start);
    let mut heap = BinaryHeap::new();
    let push = |heap: &mut BinaryHeap<Candidate>, t: u32, mean: DVec3| {
        for &n in &s.neighbours[t as usize] {
            if n != NONE {
                heap.push(Candidate {
                    cos: s.normals[n as usize].dot(mean),
                    triangle: n,
                });
            }
        }
    };
    push(&mut heap, start, s.normals[start as usize]);
    while let Some(Candidate { triangle: t, .. }) = heap.pop() {
        if taken.contains(&t) || !in_set.contains(&t) || s.key(t) != key {
            continue;
        }
        let n = s.normals[t as usize];
        if !fits(n, sum) {
            continue;
        }
        taken.insert(t);
        members.push(t);
        sum += n * s.areas[t as usize];
        push(&mut heap, t, sum.normalize_or_zero());
    }
    members
}

/// An orthonormal basis `(u, v)` of the plane normal to `n`, with
/// `u × v = n`.
fn basis(n: DVec3) -> (DVec3, DVec3) {
    let n = if n == DVec3::ZERO { DVec3::Z } else { n };
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = helper.cross(n).normalize();
    (u, n.cross(u))
}

fn single(s: &Surface, t: u32) -> Chart {
    let tri = s.triangles[t as usize];
    let (u, v) = basis(s.normals[t as usize]);
    Chart {
        triangles: vec![t],
        coords: tri
            .iter()
            .map(|&i| {
                let p = s.point(i);
                [p.dot(u), p.dot(v)]
            })
            .collect(),
    }
}

/// The chart of `members` projected along `axis`, or, when the projection
/// is not injective, the triangles that make it fold (sorted): those it
/// turns over, else those whose boundary sides cross.
fn project(s: &Surface, members: &[u32], axis: DVec3) -> Result<Chart, Vec<u32>> {
    let (u, v) = basis(axis);
    let mut coords = Vec::with_capacity(3 * members.len());
    for &t in members {
        for &i in &s.triangles[t as usize] {
            let p = s.point(i);
            coords.push([p.dot(u), p.dot(v)]);
        }
    }
    // Every non-degenerate triangle must keep its orientation.
    let mut folding: Vec<u32> = members
        .iter()
        .enumerate()
        .filter(|&(k, &t)| {
            s.normals[t as usize] != DVec3::ZERO
                && cross2(coords[3 * k], coords[3 * k + 1], coords[3 * k + 2]) <= 0.0
        })
        .map(|(_, &t)| t)
        .collect();
    if folding.is_empty() {
        folding = boundary_crossings(s, members, &coords);
    }
    if !folding.is_empty() {
        folding.sort_unstable();
        folding.dedup();
        return Err(folding);
    }
    Ok(Chart {
        triangles: members.to_vec(),
        coords,
    })
}

fn cross2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The triangles of the chart's boundary sides that cross another boundary
/// side sharing no vertex with them (none: the boundary is embedded).
fn boundary_crossings(s: &Surface, members: &[u32], coords: &[[f64; 2]]) -> Vec<u32> {
    let mut inside = std::collections::HashSet::with_capacity(members.len());
    inside.extend(members.iter().copied());
    // Boundary edges (whose neighbour is not in the chart): ends, their
    // coordinates and the triangle they belong to.
    type Side = (u32, u32, [f64; 2], [f64; 2], u32);
    let mut edges: Vec<Side> = Vec::new();
    for (k, &t) in members.iter().enumerate() {
        let tri = s.triangles[t as usize];
        for e in 0..3 {
            let n = s.neighbours[t as usize][e];
            if n == NONE || !inside.contains(&n) {
                edges.push((
                    tri[e],
                    tri[(e + 1) % 3],
                    coords[3 * k + e],
                    coords[3 * k + (e + 1) % 3],
                    t,
                ));
            }
        }
    }
    let mut crossing = Vec::new();
    if edges.len() < 4 {
        return crossing;
    }
    // Sweep along x: only edges whose x ranges overlap are compared.
    let lo = |e: &Side| e.2[0].min(e.3[0]);
    let hi = |e: &Side| e.2[0].max(e.3[0]);
    edges.sort_by(|a, b| lo(a).total_cmp(&lo(b)));
    for i in 0..edges.len() {
        let a = edges[i];
        for b in &edges[i + 1..] {
            if lo(b) > hi(&a) {
                break;
            }
            let shares = a.0 == b.0 || a.0 == b.1 || a.1 == b.0 || a.1 == b.1;
            if !shares && segments_cross(a.2, a.3, b.2, b.3) {
                crossing.extend([a.4, b.4]);
            }
        }
    }
    crossing
}

/// Whether segments `ab` and `cd` intersect (touching counts).
fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (cross2(a, b, c), cross2(a, b, d));
    let (d3, d4) = (cross2(c, d, a), cross2(c, d, b));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    (d1 == 0.0 && on(a, b, c))
        || (d2 == 0.0 && on(a, b, d))
        || (d3 == 0.0 && on(c, d, a))
        || (d4 == 0.0 && on(c, d, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_triangles() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let m = wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::cube());
        let t = m
            .faces
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        (m.positions, t)
    }

    #[test]
    fn cube_faces_become_six_charts_at_fifty_degrees() {
        let (p, t) = cube_triangles();
        let charts = make_charts(&p, &t, &[], 50f64.to_radians().cos());
        assert_eq!(charts.len(), 6);
        for c in &charts {
            assert_eq!(c.triangles.len(), 2);
        }
    }

    #[test]
    fn keys_split_charts() {
        let (p, t) = cube_triangles();
        // Every triangle its own key: twelve charts even at a wide angle.
        let keys: Vec<u32> = (0..t.len() as u32).collect();
        let charts = make_charts(&p, &t, &keys, 80f64.to_radians().cos());
        assert_eq!(charts.len(), 12);
    }

    #[test]
    fn orthographic_projection_of_a_flat_triangle_keeps_lengths() {
        let p = vec![[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
        let charts = make_charts(&p, &[[0, 1, 2]], &[], 0.5);
        let c = &charts[0].coords;
        let d = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        assert!((d(c[0], c[1]) - 3.0).abs() < 1e-12);
        assert!((d(c[0], c[2]) - 4.0).abs() < 1e-12);
        assert!((d(c[1], c[2]) - 5.0).abs() < 1e-12);
        // Counter-clockwise seen from the normal stays counter-clockwise.
        assert!(cross2(c[0], c[1], c[2]) > 0.0);
    }

    #[test]
    fn crossing_boundary_is_detected() {
        assert!(segments_cross(
            [0.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [1.0, 0.0]
        ));
        assert!(!segments_cross(
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [1.0, 1.0]
        ));
    }

    /// A height field of `n × n` cells, hills plus a deterministic jitter
    /// of `noise` (in cell sizes) on every height, as a scan or a terrain
    /// survey gives.
    fn noisy_height_field(n: usize, noise: f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let r = (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5;
                let (x, z) = (i as f32, j as f32);
                let y = 3.0 * (0.2 * x).sin() * (0.15 * z).cos() + noise * r;
                p.push([x, y, z]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                t.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
                t.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            }
        }
        (p, t)
    }

    /// Every triangle of every chart keeps its orientation and faces the
    /// chart's projection within the cone: its projected area is at least
    /// `cos` times its area (the 1/cos stretch bound the option promises).
    fn assert_within_cone(p: &[[f32; 3]], t: &[[u32; 3]], charts: &[Chart], cos: f64) {
        let mut seen = vec![false; t.len()];
        for c in charts {
            for (k, &tri) in c.triangles.iter().enumerate() {
                assert!(!seen[tri as usize], "triangle {tri} in two charts");
                seen[tri as usize] = true;
                let q = t[tri as usize].map(|v| DVec3::from(p[v as usize].map(f64::from)));
                let area = 0.5 * (q[1] - q[0]).cross(q[2] - q[0]).length();
                let flat = 0.5 * cross2(c.coords[3 * k], c.coords[3 * k + 1], c.coords[3 * k + 2]);
                assert!(
                    flat >= cos * area * (1.0 - 1e-9),
                    "triangle {tri}: projected {flat} of {area}"
                );
            }
        }
        assert!(seen.iter().all(|&s| s), "a triangle in no chart");
    }

    /// A noisy surface folds a chart at a few spikes, and its largest
    /// triangle may be tilted by the noise: neither may cut the surface
    /// into charts of a few triangles (a noisy 1M-triangle terrain's LOD
    /// had 37,747 charts filling 30% of its atlas).
    #[test]
    fn noisy_height_field_keeps_large_charts_within_the_cone() {
        let (p, t) = noisy_height_field(48, 1.0);
        let cos = 50f64.to_radians().cos();
        let charts = make_charts(&p, &t, &[], cos);
        assert_within_cone(&p, &t, &charts, cos);
        let steep = t
            .iter()
            .filter(|tri| {
                let q = tri.map(|v| DVec3::from(p[v as usize].map(f64::from)));
                (q[1] - q[0]).cross(q[2] - q[0]).normalize().y.abs() < cos
            })
            .count();
        let mean = t.len() as f64 / charts.len() as f64;
        eprintln!(
            "{} triangles ({steep} steeper than the cone), {} charts",
            t.len(),
            charts.len()
        );
        assert!(
            mean >= 16.0,
            "{} charts, {mean:.1} triangles each",
            charts.len()
        );
    }

    #[test]
    fn charts_of_a_torus_stay_within_the_cone() {
        let m = wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::torus(48, 16, 1.0, 0.3));
        let t: Vec<[u32; 3]> = m
            .faces
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let cos = 50f64.to_radians().cos();
        let charts = make_charts(&m.positions, &t, &[], cos);
        assert_within_cone(&m.positions, &t, &charts, cos);
        assert!(charts.len() <= 32, "{} charts", charts.len());
    }

    /// A spiral ramp: one full turn and a bit more of a gently sloped strip
    /// projects onto itself along its axis; the chart must be split so
    /// that no two triangles overlap in UV space.
    #[test]
    fn spiral_ramp_is_split_until_injective() {
        let (mut p, mut t) = (Vec::new(), Vec::new());
        let steps = 48;
        for i in 0..=steps {
            let a = i as f32 * 1.5 * std::f32::consts::TAU / steps as f32;
            let z = 0.02 * a;
            p.push([a.cos(), a.sin(), z]);
            p.push([2.0 * a.cos(), 2.0 * a.sin(), z]);
        }
        for i in 0..steps as u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
            t.push([a, b, d]);
            t.push([a, d, c]);
        }
        let charts = make_charts(&p, &t, &[], 50f64.to_radians().cos());
        assert!(charts.len() >= 2, "{} charts", charts.len());
        for c in &charts {
            let tri: Vec<u32> = c.triangles.clone();
            // Triangle centroids of one chart never fall inside another
            // triangle of the same chart.
            for (i, _) in tri.iter().enumerate() {
                let ci = [
                    (c.coords[3 * i][0] + c.coords[3 * i + 1][0] + c.coords[3 * i + 2][0]) / 3.0,
                    (c.coords[3 * i][1] + c.coords[3 * i + 1][1] + c.coords[3 * i + 2][1]) / 3.0,
                ];
                for j in 0..tri.len() {
                    if i == j {
                        continue;
                    }
                    let (a, b, cc) = (c.coords[3 * j], c.coords[3 * j + 1], c.coords[3 * j + 2]);
                    let inside = cross2(a, b, ci) > 0.0
                        && cross2(b, cc, ci) > 0.0
                        && cross2(cc, a, ci) > 0.0;
                    assert!(!inside, "triangles {i} and {j} overlap");
                }
            }
        }
    }
}
