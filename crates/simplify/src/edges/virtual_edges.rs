//! Virtual edges from triangle distances (W §4.1.1).
//!
//! Parts of one object that touch without sharing vertices (a lamp's shade
//! resting on its stand, a soup of triangles) cannot merge through physical
//! edges alone. W connects them like a Čech complex: every pair of triangles
//! of *different* connected components closer than `2r` gets an edge between
//! their closest vertex pair. Vertex-to-vertex distance (Garland & Heckbert
//! 1997) misses parts that touch along a face (W Fig. 15).
//!
//! Cost: one BVH per component, a BVH over the component boxes to find the
//! component pairs that come within `2r`, then a dual-tree walk per such
//! pair. Same-component triangle pairs, the vast majority of nearby pairs,
//! are never visited.

use glam::DVec3;
use rayon::prelude::*;
use wildlod_geometry::{triangle_triangle_distance, Aabb, Bvh};
use wildlod_mesh::disjoint_sets::DisjointSets;

use crate::prepare::complex::Complex;

/// Adds a virtual edge for every pair of triangles of different components
/// within `threshold` (= 2r, normalized units). Returns the pairs added.
pub(crate) fn add_virtual_edges(c: &mut Complex, threshold: f64) -> Vec<(u32, u32)> {
    let mut edges = find_virtual_edges(c, threshold);
    edges.retain(|&(a, b)| c.add_edge(a, b));
    edges
}

/// The virtual edges as sorted, unique vertex pairs `(a < b)`.
pub(crate) fn find_virtual_edges(c: &Complex, threshold: f64) -> Vec<(u32, u32)> {
    if threshold.is_nan() || threshold <= 0.0 {
        return Vec::new();
    }
    // Components of the face complex (faces sharing a vertex are connected).
    let nv = c.pos.len();
    let mut sets = DisjointSets::new(nv);
    for f in c.live_faces() {
        let face = c.face(f);
        for w in face.windows(2) {
            sets.union(w[0], w[1]);
        }
    }
    let (label, _) = sets.labels();
    // Most meshes are one piece: stop before building anything.
    let mut first = None;
    let one_piece = c.live_faces().all(|f| {
        let l = label[c.face(f)[0] as usize];
        *first.get_or_insert(l) == l
    });
    if one_piece {
        return Vec::new();
    }
    // Fan triangles, grouped by component.
    let mut tris: Vec<(u32, [u32; 3])> = Vec::new();
    for f in c.live_faces() {
        let face = c.face(f);
        for k in 1..face.len() - 1 {
            tris.push((label[face[0] as usize], [face[0], face[k], face[k + 1]]));
        }
    }
    tris.sort_by_key(|t| t.0);
    let mut groups: Vec<std::ops::Range<usize>> = Vec::new();
    let mut s = 0;
    while s < tris.len() {
        let mut e = s + 1;
        while e < tris.len() && tris[e].0 == tris[s].0 {
            e += 1;
        }
        groups.push(s..e);
        s = e;
    }
    if groups.len() < 2 {
        return Vec::new();
    }
    let corners = |t: &[u32; 3]| t.map(|v| c.pos[v as usize]);
    let boxes: Vec<Aabb> = tris
        .iter()
        .map(|(_, t)| {
            let [a, b, d] = corners(t);
            Aabb::from_triangle(a, b, d)
        })
        .collect();
    let bvhs: Vec<Bvh> = groups
        .par_iter()
        .map(|g| Bvh::build(&boxes[g.clone()]))
        .collect();
    let comp_boxes: Vec<Aabb> = bvhs.iter().map(Bvh::bounds).collect();
    let top = Bvh::build(&comp_boxes);
    let mut comp_pairs = Vec::new();
    top.self_pairs_within(threshold, |a, b| comp_pairs.push((a, b)));
    comp_pairs.sort_unstable();
    let t2 = threshold;
    let mut edges: Vec<(u32, u32)> = comp_pairs
        .par_iter()
        .flat_map_iter(|&(ga, gb)| {
            let (ra, rb) = (&groups[ga as usize], &groups[gb as usize]);
            let mut out = Vec::new();
            bvhs[ga as usize].pairs_within(&bvhs[gb as usize], t2, |i, j| {
                let ta = &tris[ra.start + i as usize].1;
                let tb = &tris[rb.start + j as usize].1;
                let (pa, pb) = (corners(ta), corners(tb));
                // Two triangles are at most as far apart as any two of their
                // vertices: when the closest vertex pair is within reach, the
                // exact distance need not be computed (parts in contact:
                // most pairs).
                let (d2, pair) = closest_vertex_pair(ta, &pa, tb, &pb);
                if d2 < t2 * t2
                    || (!beyond_plane(&pa, &pb, t2)
                        && !beyond_plane(&pb, &pa, t2)
                        && triangle_triangle_distance(&pa, &pb) < t2)
                {
                    out.push(pair);
                }
            });
            // Many triangle pairs of two parts share their closest vertices.
            out.sort_unstable();
            out.dedup();
            out
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Whether all of `b` lies farther than `t` on one side of `a`'s plane: then
/// the triangles are farther apart than `t` (a cheap test that rejects most
/// pairs of parts whose boxes overlap, before the exact distance).
fn beyond_plane(a: &[DVec3; 3], b: &[DVec3; 3], t: f64) -> bool {
    let n = (a[1] - a[0]).cross(a[2] - a[0]);
    let len = n.length();
    if len.is_nan() || len <= 0.0 {
        return false;
    }
    let d = b.map(|p| n.dot(p - a[0]) / len);
    d.iter().all(|&x| x > t) || d.iter().all(|&x| x < -t)
}

/// The closest pair among the 3 × 3 vertex pairs of two triangles, as
/// `(min, max)` ids, with its squared distance; ties go to the first pair in
/// index order.
fn closest_vertex_pair(
    ta: &[u32; 3],
    pa: &[DVec3; 3],
    tb: &[u32; 3],
    pb: &[DVec3; 3],
) -> (f64, (u32, u32)) {
    let mut best = (f64::INFINITY, 0u32, 0u32);
    for (x, p) in ta.iter().zip(pa) {
        for (y, q) in tb.iter().zip(pb) {
            let d = p.distance_squared(*q);
            if d < best.0 {
                best = (d, *x, *y);
            }
        }
    }
    (best.0, (best.1.min(best.2), best.1.max(best.2)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit squares (two triangles each) side by side along x, with a
    /// gap `gap` between them, plus an optional far square.
    fn squares(gap: f64) -> Complex {
        let mut pos = Vec::new();
        for x0 in [0.0, 1.0 + gap] {
            for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                pos.push(DVec3::new(x0 + x, y, 0.0));
            }
        }
        // Normalize-ish scale does not matter for the test.
        Complex::new(pos, &[0, 4, 8], &[0, 1, 2, 3, 4, 5, 6, 7]).0
    }

    #[test]
    fn touching_parts_get_an_edge_between_their_closest_vertices() {
        let c = squares(0.05);
        let e = find_virtual_edges(&c, 0.1);
        // Square A's right side (1, 2) faces square B's left side (4, 7):
        // the closest vertex pairs are 1–4 and 2–7.
        assert_eq!(e, vec![(1, 4), (2, 7)]);
    }

    #[test]
    fn parts_farther_than_the_threshold_stay_apart() {
        let c = squares(0.2);
        assert!(find_virtual_edges(&c, 0.1).is_empty());
        assert!(find_virtual_edges(&c, 0.0).is_empty());
    }

    #[test]
    fn a_single_component_gets_no_virtual_edge() {
        let pos = (0..4)
            .map(|i| DVec3::new((i % 2) as f64, (i / 2) as f64, 0.0))
            .collect();
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 3, 2]);
        assert!(find_virtual_edges(&c, 10.0).is_empty());
    }

    #[test]
    fn face_contact_without_nearby_vertices_is_found() {
        // W Fig. 15: a small triangle touching the middle of a big one, all
        // its vertices far from the big one's vertices (vertex distance ≥ 4)
        // but its tip 0.01 above the big face.
        let pos = vec![
            DVec3::new(-10.0, -10.0, 0.0),
            DVec3::new(10.0, -10.0, 0.0),
            DVec3::new(0.0, 10.0, 0.0),
            DVec3::new(0.0, 0.0, 0.01),
            DVec3::new(1.0, 0.0, 3.0),
            DVec3::new(0.0, 1.0, 3.0),
        ];
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 3, 4, 5]);
        let e = find_virtual_edges(&c, 0.05);
        assert_eq!(e.len(), 1);
        // The closest of the nine vertex pairs: 5 = (0,1,3) and 2 = (0,10,0),
        // |(0,9,-3)| = 9.49, closer than the tip to 2 (10.0).
        assert_eq!(e, vec![(2, 5)]);
    }

    #[test]
    fn a_triangle_wholly_beyond_the_plane_is_rejected_cheaply() {
        let a = [DVec3::ZERO, DVec3::X, DVec3::Y]; // the plane z = 0
        let up = |z: f64| {
            [
                DVec3::new(5.0, 5.0, z),
                DVec3::new(6.0, 5.0, z + 1.0),
                DVec3::new(5.0, 6.0, z),
            ]
        };
        assert!(beyond_plane(&a, &up(0.2), 0.1));
        assert!(beyond_plane(&a, &up(-2.0), 0.1)); // all below -0.1
        assert!(!beyond_plane(&a, &up(0.05), 0.1)); // a corner within reach
                                                    // Straddling the plane: no conclusion.
        let across = [
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::Y,
        ];
        assert!(!beyond_plane(&a, &across, 0.1));
        // A degenerate plane proves nothing.
        assert!(!beyond_plane(
            &[DVec3::ZERO, DVec3::X, DVec3::X],
            &up(9.0),
            0.1
        ));
    }
}
