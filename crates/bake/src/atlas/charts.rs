//! Charts: triangles grown into regions of similar normal, each projected
//! orthographically onto its mean plane, and split until the projection is
//! injective.
//!
//! Growth starts at the largest unassigned triangle and takes neighbours
//! (across edges shared by exactly two triangles, with the same key) in
//! order of their normal's angle to the chart's, while that angle stays
//! within the cone both to the seed and to the chart's mean normal. Every
//! triangle of a chart then faces the projection direction by less than
//! twice the cone angle, below 90°: no triangle flips.
//!
//! Projection can still fold a chart over itself (a gently sloped spiral
//! ramp). A chart is kept when its triangles are all positively oriented
//! and its boundary does not cross itself: a locally injective map of a
//! surface whose boundary is embedded is injective. Otherwise it is grown
//! again with half the angle, down to single triangles, which are always
//! injective.

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
        let members = grow(s, seed, cos, &in_set, &mut taken);
        match project(s, &members) {
            Some(chart) => out.push(chart),
            None if members.len() == 1 => out.push(single(s, members[0])),
            None => {
                let mut sorted = members;
                sorted.sort_unstable();
                // Half the cone; below 2° every triangle is its own chart.
                let half = ((cos.acos()) * 0.5).cos();
                if half > (2f64).to_radians().cos() {
                    for &t in &sorted {
                        out.push(single(s, t));
                    }
                } else {
                    charts_of(s, &sorted, half, out);
                }
            }
        }
    }
}

fn grow(
    s: &Surface,
    seed: u32,
    cos: f64,
    in_set: &std::collections::HashSet<u32>,
    taken: &mut std::collections::HashSet<u32>,
) -> Vec<u32> {
    let n_seed = s.normals[seed as usize];
    let key = s.key(seed);
    let mut sum = n_seed * s.areas[seed as usize];
    let mut members = vec![seed];
    taken.insert(seed);
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
    push(&mut heap, seed, n_seed);
    while let Some(Candidate { triangle: t, .. }) = heap.pop() {
        if taken.contains(&t) || !in_set.contains(&t) || s.key(t) != key {
            continue;
        }
        let n = s.normals[t as usize];
        let mean = sum.normalize_or_zero();
        let fits = n == DVec3::ZERO
            || n_seed == DVec3::ZERO
            || (n.dot(n_seed) >= cos && (mean == DVec3::ZERO || n.dot(mean) >= cos));
        if !fits {
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

/// The chart of `members` projected onto their mean plane, or `None` when
/// the projection is not injective.
fn project(s: &Surface, members: &[u32]) -> Option<Chart> {
    let mut sum = DVec3::ZERO;
    for &t in members {
        sum += s.normals[t as usize] * s.areas[t as usize];
    }
    let (u, v) = basis(sum.normalize_or_zero());
    let mut coords = Vec::with_capacity(3 * members.len());
    for &t in members {
        for &i in &s.triangles[t as usize] {
            let p = s.point(i);
            coords.push([p.dot(u), p.dot(v)]);
        }
    }
    // Every non-degenerate triangle must keep its orientation.
    for (k, &t) in members.iter().enumerate() {
        if s.normals[t as usize] == DVec3::ZERO {
            continue;
        }
        if cross2(coords[3 * k], coords[3 * k + 1], coords[3 * k + 2]) <= 0.0 {
            return None;
        }
    }
    if boundary_crosses_itself(s, members, &coords) {
        return None;
    }
    Some(Chart {
        triangles: members.to_vec(),
        coords,
    })
}

fn cross2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether two boundary edges of the chart that share no vertex cross.
fn boundary_crosses_itself(s: &Surface, members: &[u32], coords: &[[f64; 2]]) -> bool {
    let mut inside = std::collections::HashSet::with_capacity(members.len());
    inside.extend(members.iter().copied());
    // Boundary edges: edges whose neighbour is not in the chart.
    let mut edges: Vec<(u32, u32, [f64; 2], [f64; 2])> = Vec::new();
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
                ));
            }
        }
    }
    if edges.len() < 4 {
        return false;
    }
    // Sweep along x: only edges whose x ranges overlap are compared.
    let lo = |e: &(u32, u32, [f64; 2], [f64; 2])| e.2[0].min(e.3[0]);
    let hi = |e: &(u32, u32, [f64; 2], [f64; 2])| e.2[0].max(e.3[0]);
    edges.sort_by(|a, b| lo(a).total_cmp(&lo(b)));
    for i in 0..edges.len() {
        let a = edges[i];
        for b in &edges[i + 1..] {
            if lo(b) > hi(&a) {
                break;
            }
            let shares = a.0 == b.0 || a.0 == b.1 || a.1 == b.0 || a.1 == b.1;
            if !shares && segments_cross(a.2, a.3, b.2, b.3) {
                return true;
            }
        }
    }
    false
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
