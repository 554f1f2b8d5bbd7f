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

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use glam::DVec3;
use rayon::prelude::*;
use wildlod_geometry::{triangle_triangle_distance, Aabb, Bvh};
use wildlod_mesh::disjoint_sets::DisjointSets;

use crate::prepare::complex::Complex;

/// Candidate triangle pairs (and component pairs) the search may test, per
/// fan triangle of the input. Ordinary files stay far below it: the most a
/// corpus or hold-out file tests is 35 per triangle (a random soup of 100
/// triangles), most test fewer than 5.
const TESTS_PER_TRIANGLE: usize = 128;

/// Virtual edges the complex may get, per vertex. Physical edges number
/// about 3 per vertex; the most any corpus or hold-out file needs is 4.5
/// per vertex (the random soup), most need fewer than 1.
const EDGES_PER_VERTEX: usize = 8;

/// How many times the radius may halve before the search gives up bridging
/// parts at all (2⁻⁴⁰ of the requested reach is below any gap a float
/// coordinate can tell from contact).
const MAX_HALVINGS: u32 = 40;

/// The outcome of the search: the edges and the reach they were found at.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct VirtualEdges {
    /// Sorted, unique vertex pairs `(a < b)`.
    pub edges: Vec<(u32, u32)>,
    /// The distance below which parts were bridged: the requested
    /// threshold, or less where bridging every gap under it would have
    /// exceeded the work or edge budget ([`TESTS_PER_TRIANGLE`],
    /// [`EDGES_PER_VERTEX`]).
    pub threshold: f64,
}

/// Adds a virtual edge for every pair of triangles of different components
/// within `threshold` (= 2r, normalized units), or within the reach the
/// budget allows (see [`find_virtual_edges`]). Returns the search's outcome
/// with the pairs added.
pub(crate) fn add_virtual_edges(c: &mut Complex, threshold: f64) -> VirtualEdges {
    let mut found = find_virtual_edges(c, threshold);
    found.edges.retain(|&(a, b)| c.add_edge(a, b));
    found
}

/// The virtual edges of W §4.1.1, within a budget linear in the input.
///
/// W bridges every gap under `threshold` between parts. A long row or a
/// dense cloud of parts much smaller than the threshold (a fence's pickets,
/// gravel, leaves) puts each part within reach of hundreds of others, and
/// the edges grow with the square of the part count (16k boxes in a row:
/// 2.4 GB, 32 s). So the search works within budgets proportional to the
/// input ([`TESTS_PER_TRIANGLE`] candidate pairs, [`EDGES_PER_VERTEX`]
/// edges); where bridging every gap under the threshold would exceed them,
/// the reach halves until it fits: the narrowest gaps, which W would merge
/// first anyway, stay bridged. Files within the budget get exactly W's
/// edges. The result does not depend on the thread count.
pub(crate) fn find_virtual_edges(c: &Complex, threshold: f64) -> VirtualEdges {
    if threshold.is_nan() || threshold <= 0.0 {
        return VirtualEdges::default();
    }
    let Some(search) = Search::new(c) else {
        return VirtualEdges {
            edges: Vec::new(),
            threshold,
        };
    };
    let budget = Budget {
        tests: TESTS_PER_TRIANGLE.saturating_mul(search.tris.len()),
        edges: EDGES_PER_VERTEX.saturating_mul(c.pos.len()),
    };
    let mut t = threshold;
    for _ in 0..=MAX_HALVINGS {
        if let Some(edges) = search.edges_within(c, t, &budget) {
            return VirtualEdges {
                edges,
                threshold: t,
            };
        }
        t *= 0.5;
    }
    VirtualEdges::default()
}

/// Limits of one search (see [`find_virtual_edges`]).
struct Budget {
    tests: usize,
    edges: usize,
}

/// What every attempt of the search shares: the fan triangles grouped by
/// component, a BVH per component and one over the components.
struct Search {
    tris: Vec<[u32; 3]>,
    groups: Vec<std::ops::Range<usize>>,
    bvhs: Vec<Bvh>,
    top: Bvh,
}

impl Search {
    /// `None` when the complex is one piece: nothing to bridge.
    fn new(c: &Complex) -> Option<Search> {
        // Components of the face complex (faces sharing a vertex are
        // connected).
        let mut sets = DisjointSets::new(c.pos.len());
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
            return None;
        }
        let mut labelled: Vec<(u32, [u32; 3])> = Vec::new();
        for f in c.live_faces() {
            let face = c.face(f);
            for k in 1..face.len() - 1 {
                labelled.push((label[face[0] as usize], [face[0], face[k], face[k + 1]]));
            }
        }
        labelled.sort_by_key(|t| t.0);
        let mut groups: Vec<std::ops::Range<usize>> = Vec::new();
        let mut s = 0;
        while s < labelled.len() {
            let mut e = s + 1;
            while e < labelled.len() && labelled[e].0 == labelled[s].0 {
                e += 1;
            }
            groups.push(s..e);
            s = e;
        }
        if groups.len() < 2 {
            return None;
        }
        let tris: Vec<[u32; 3]> = labelled.into_iter().map(|(_, t)| t).collect();
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| {
                let [a, b, d] = corners(c, t);
                Aabb::from_triangle(a, b, d)
            })
            .collect();
        let bvhs: Vec<Bvh> = groups
            .par_iter()
            .map(|g| Bvh::build(&boxes[g.clone()]))
            .collect();
        let comp_boxes: Vec<Aabb> = bvhs.iter().map(Bvh::bounds).collect();
        let top = Bvh::build(&comp_boxes);
        Some(Search {
            tris,
            groups,
            bvhs,
            top,
        })
    }

    /// Every virtual edge under `t`, sorted and unique, or `None` when
    /// finding them would exceed `budget`.
    fn edges_within(&self, c: &Complex, t: f64, budget: &Budget) -> Option<Vec<(u32, u32)>> {
        let mut comp_pairs = Vec::new();
        let flow = self.top.self_pairs_within_until(t, |a, b| {
            comp_pairs.push((a, b));
            if comp_pairs.len() > budget.tests {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        if flow.is_break() {
            return None;
        }
        comp_pairs.sort_unstable();
        // Shared counts, so that every task stops once the budget is gone.
        // Whether it is gone is decided on the final totals, which do not
        // depend on the threads' interleaving.
        let tests = AtomicUsize::new(comp_pairs.len());
        let edge_count = AtomicUsize::new(0);
        let over = |tests: usize, edges: usize| tests > budget.tests || edges > budget.edges;
        let chunks: Vec<Vec<(u32, u32)>> = comp_pairs
            .par_iter()
            .map(|&(ga, gb)| {
                let mut out = Vec::new();
                if over(tests.load(Relaxed), edge_count.load(Relaxed)) {
                    return out;
                }
                let (ra, rb) = (&self.groups[ga as usize], &self.groups[gb as usize]);
                let mut local = 0usize;
                let flow = self.bvhs[ga as usize].pairs_within_until(
                    &self.bvhs[gb as usize],
                    t,
                    |i, j| {
                        local += 1;
                        if local == FLUSH {
                            local = 0;
                            let done = tests.fetch_add(FLUSH, Relaxed) + FLUSH;
                            if over(done, edge_count.load(Relaxed)) {
                                return ControlFlow::Break(());
                            }
                        }
                        let ta = &self.tris[ra.start + i as usize];
                        let tb = &self.tris[rb.start + j as usize];
                        let (pa, pb) = (corners(c, ta), corners(c, tb));
                        // Two triangles are at most as far apart as any two
                        // of their vertices: when the closest vertex pair is
                        // within reach, the exact distance need not be
                        // computed (parts in contact: most pairs).
                        let (d2, pair) = closest_vertex_pair(ta, &pa, tb, &pb);
                        if d2 < t * t
                            || (!beyond_plane(&pa, &pb, t)
                                && !beyond_plane(&pb, &pa, t)
                                && triangle_triangle_distance(&pa, &pb) < t)
                        {
                            out.push(pair);
                        }
                        ControlFlow::Continue(())
                    },
                );
                tests.fetch_add(local, Relaxed);
                if flow.is_break() {
                    return Vec::new();
                }
                // Many triangle pairs of two parts share their closest
                // vertices.
                out.sort_unstable();
                out.dedup();
                edge_count.fetch_add(out.len(), Relaxed);
                out
            })
            .collect();
        if over(tests.into_inner(), edge_count.into_inner()) {
            return None;
        }
        // A vertex belongs to one component, so the pairs of two component
        // pairs never repeat each other.
        let mut edges: Vec<(u32, u32)> = chunks.into_iter().flatten().collect();
        edges.sort_unstable();
        edges.dedup();
        Some(edges)
    }
}

/// Tests a task counts before adding them to the shared total.
const FLUSH: usize = 1024;

fn corners(c: &Complex, t: &[u32; 3]) -> [DVec3; 3] {
    t.map(|v| c.pos[v as usize])
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
        let e = find_virtual_edges(&c, 0.1).edges;
        // Square A's right side (1, 2) faces square B's left side (4, 7):
        // the closest vertex pairs are 1–4 and 2–7.
        assert_eq!(e, vec![(1, 4), (2, 7)]);
    }

    /// `n` unit cubes (six quads each) in a row along x, one apart.
    fn row_of_boxes(n: usize) -> Complex {
        let mut pos = Vec::new();
        let mut offsets = vec![0];
        let mut idx = Vec::new();
        for k in 0..n {
            let base = pos.len() as u32;
            for c in 0..8 {
                let (x, y, z) = ((c & 1) as f64, ((c >> 1) & 1) as f64, (c >> 2) as f64);
                pos.push(DVec3::new(2.0 * k as f64 + x, y, z));
            }
            for q in [
                [0, 2, 3, 1],
                [4, 5, 7, 6],
                [0, 1, 5, 4],
                [2, 6, 7, 3],
                [0, 4, 6, 2],
                [1, 3, 7, 5],
            ] {
                idx.extend(q.map(|v| base + v));
                offsets.push(idx.len() as u32);
            }
        }
        Complex::new(pos, &offsets, &idx).0
    }

    #[test]
    fn a_row_of_many_small_parts_stays_within_the_budget() {
        let n = 300;
        let c = row_of_boxes(n);
        let nv = c.pos.len();
        // Within reach of 50 boxes on each side: every box pair up to 50
        // apart would be bridged, 27 edges per pair (as measured on the
        // 8k row: 138 per vertex), beyond the budget of 8 per vertex.
        let asked = 100.0;
        let found = find_virtual_edges(&c, asked);
        assert!(
            found.edges.len() <= EDGES_PER_VERTEX * nv,
            "{}",
            found.edges.len()
        );
        // The reach was halved, no more than needed: at twice the reach
        // found, the search would not have fitted.
        assert!(found.threshold < asked && found.threshold > 1.0);
        let at_double = Search::new(&c).expect("300 parts").edges_within(
            &c,
            2.0 * found.threshold,
            &Budget {
                tests: TESTS_PER_TRIANGLE * n * 12,
                edges: EDGES_PER_VERTEX * nv,
            },
        );
        assert!(at_double.is_none(), "the reach need not have been halved");
        // The narrowest gaps stay bridged: every box reaches the next one
        // (its right face, vertices 1, 3, 5, 7, faces the next box's left).
        for k in 0..n as u32 - 1 {
            let (a, b) = (8 * k + 1, 8 * (k + 1));
            assert!(
                found.edges.binary_search(&(a, b)).is_ok(),
                "box {k}: {a}–{b}"
            );
        }
        // The same edges as W's own rule at the reach found.
        assert_eq!(find_virtual_edges(&c, found.threshold), found);
    }

    #[test]
    fn a_file_within_the_budget_gets_ws_edges_at_the_asked_reach() {
        // Reach 1.5: each box bridges to its neighbours (gap 1), not to the
        // boxes beyond (gap 3); at most 19 × 27 edges, within 8 × 160.
        let c = row_of_boxes(20);
        let found = find_virtual_edges(&c, 1.5);
        assert_eq!(found.threshold, 1.5);
        let box_of = |v: u32| v / 8;
        assert!(found.edges.iter().all(|&(a, b)| box_of(b) == box_of(a) + 1));
        for k in 0..19u32 {
            let (a, b) = (8 * k + 1, 8 * (k + 1));
            assert!(found.edges.binary_search(&(a, b)).is_ok(), "{k}");
        }
    }

    #[test]
    fn the_budgeted_search_does_not_depend_on_the_thread_count() {
        let c = row_of_boxes(300);
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool")
                .install(|| find_virtual_edges(&c, 100.0))
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn parts_farther_than_the_threshold_stay_apart() {
        let c = squares(0.2);
        assert!(find_virtual_edges(&c, 0.1).edges.is_empty());
        assert!(find_virtual_edges(&c, 0.0).edges.is_empty());
    }

    #[test]
    fn a_single_component_gets_no_virtual_edge() {
        let pos = (0..4)
            .map(|i| DVec3::new((i % 2) as f64, (i / 2) as f64, 0.0))
            .collect();
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 3, 2]);
        assert!(find_virtual_edges(&c, 10.0).edges.is_empty());
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
        let e = find_virtual_edges(&c, 0.05).edges;
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
