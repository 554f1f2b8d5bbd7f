//! Which wedges a collapse merges, and what it must not do to seams.
//!
//! A collapse of `(i, j)` merges the wedges the faces on the edge join: a
//! face holding both endpoints has one wedge at each, and those two become
//! one (their values meet at the new vertex). Wedges no such face joins stay
//! apart. The rules that keep seams, as in meshoptimizer's vertex kinds but
//! for any vertex pair:
//!
//! - **No seam closes**: a merged group may hold at most one wedge of each
//!   endpoint. Two wedges of one vertex in one group would mean the two
//!   sides of a seam take one value (a UV chart glued to its neighbour).
//! - **No seam moves**: a vertex with several wedges (on a seam) of which
//!   one is left out of every merge keeps its position: the other endpoint
//!   comes to it. This is how a vertex next to a seam collapses onto it, and
//!   how a seam's corners and junctions stay put. When both endpoints must
//!   stay, the collapse is refused.
//! - A vertex with one wedge may always move (its value is refitted where it
//!   goes), including across a virtual edge, which joins no faces.
//!
//! A seam vertex whose every wedge merges (a collapse along the seam) moves
//! freely; the seam's constraint planes (see `seam_planes`) keep it on the
//! seam's curve.

use smallvec::SmallVec;

/// The merges one stream's wedges undergo in a collapse.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct StreamPlan {
    /// Groups of wedges that end up as one wedge, each listed with its
    /// members; single wedges are groups of one. The first member is the
    /// wedge that survives.
    pub groups: SmallVec<[SmallVec<[u32; 2]>; 4]>,
    /// The first endpoint must not move.
    pub fixed_i: bool,
    /// The second endpoint must not move.
    pub fixed_j: bool,
}

/// Why a collapse may not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SeamViolation {
    /// It would give both sides of a seam one value.
    Closes,
    /// Both endpoints are on seams the collapse would move.
    Moves,
}

/// Plans the merges of one stream for collapsing `(i, j)`: `wi` and `wj`
/// are the distinct wedges at `i` and at `j`, `pairs` the (wedge at `i`,
/// wedge at `j`) of every face holding both. With `strict` off (the seams
/// were relaxed to reach a target) nothing is refused and nothing fixed.
pub(crate) fn plan_stream(
    wi: &[u32],
    wj: &[u32],
    pairs: &[(u32, u32)],
    strict: bool,
) -> Result<StreamPlan, SeamViolation> {
    let n = wi.len() + wj.len();
    let mut parent: SmallVec<[usize; 8]> = (0..n).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut related: SmallVec<[bool; 8]> = smallvec::smallvec![false; n];
    for &(a, b) in pairs {
        let (Some(x), Some(y)) = (
            wi.iter().position(|&w| w == a),
            wj.iter().position(|&w| w == b).map(|p| p + wi.len()),
        ) else {
            continue;
        };
        related[x] = true;
        related[y] = true;
        let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
        if rx != ry {
            // The smaller index is the root, so an i wedge leads its group.
            parent[rx.max(ry)] = rx.min(ry);
        }
    }
    let mut plan = StreamPlan::default();
    let mut group_of: SmallVec<[usize; 8]> = smallvec::smallvec![usize::MAX; n];
    for x in 0..n {
        let r = root(&mut parent, x);
        let w = if x < wi.len() {
            wi[x]
        } else {
            wj[x - wi.len()]
        };
        if group_of[r] == usize::MAX {
            group_of[r] = plan.groups.len();
            plan.groups.push(SmallVec::new());
        }
        plan.groups[group_of[r]].push(w);
    }
    if !strict {
        return Ok(plan);
    }
    for x in 0..n {
        let r = root(&mut parent, x);
        let from_i = (0..wi.len()).filter(|&y| root(&mut parent, y) == r).count();
        let from_j = (wi.len()..n).filter(|&y| root(&mut parent, y) == r).count();
        if from_i > 1 || from_j > 1 {
            return Err(SeamViolation::Closes);
        }
    }
    plan.fixed_i = wi.len() > 1 && related[..wi.len()].iter().any(|r| !r);
    plan.fixed_j = wj.len() > 1 && related[wi.len()..].iter().any(|r| !r);
    if plan.fixed_i && plan.fixed_j {
        return Err(SeamViolation::Moves);
    }
    Ok(plan)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn groups(p: &StreamPlan) -> Vec<Vec<u32>> {
        p.groups.iter().map(|g| g.to_vec()).collect()
    }

    #[test]
    fn interior_collapse_merges_the_one_wedge_of_each_end() {
        // i: wedge 1, j: wedge 7, both faces on the edge join them.
        let p = plan_stream(&[1], &[7], &[(1, 7), (1, 7)], true).unwrap();
        assert_eq!(groups(&p), vec![vec![1, 7]]);
        assert!(!p.fixed_i && !p.fixed_j);
    }

    #[test]
    fn collapse_along_a_seam_merges_each_side_with_its_side() {
        // ```text
        //   side A:  iA ── jA
        //   ───────  i ─── j   (the seam)
        //   side B:  iB ── jB
        // ```
        let p = plan_stream(&[1, 2], &[5, 6], &[(1, 5), (2, 6)], true).unwrap();
        assert_eq!(groups(&p), vec![vec![1, 5], vec![2, 6]]);
        assert!(!p.fixed_i && !p.fixed_j);
    }

    #[test]
    fn a_neighbour_collapses_onto_a_seam_vertex_which_stays() {
        // j is beside the seam on side A; i is on it with wedges A (1), B (2).
        let p = plan_stream(&[1, 2], &[5], &[(1, 5), (1, 5)], true).unwrap();
        assert_eq!(groups(&p), vec![vec![1, 5], vec![2]]);
        assert!(p.fixed_i && !p.fixed_j);
    }

    #[test]
    fn an_edge_across_a_chart_between_two_seam_vertices_is_refused() {
        // Both on seams; the edge's faces are all on side A.
        assert_eq!(
            plan_stream(&[1, 2], &[5, 6], &[(1, 5), (1, 5)], true),
            Err(SeamViolation::Moves)
        );
        // Relaxed, it is allowed and nothing is fixed.
        let p = plan_stream(&[1, 2], &[5, 6], &[(1, 5), (1, 5)], false).unwrap();
        assert!(!p.fixed_i && !p.fixed_j);
    }

    #[test]
    fn a_collapse_that_would_close_a_seam_is_refused() {
        // i has one wedge; the faces on the edge see two different wedges at
        // j (the seam ends at i): both of j's wedges would join i's.
        assert_eq!(
            plan_stream(&[1], &[5, 6], &[(1, 5), (1, 6)], true),
            Err(SeamViolation::Closes)
        );
        let p = plan_stream(&[1], &[5, 6], &[(1, 5), (1, 6)], false).unwrap();
        assert_eq!(groups(&p), vec![vec![1, 5, 6]]);
    }

    #[test]
    fn a_virtual_edge_keeps_every_wedge_apart() {
        // No face joins the endpoints: single-wedge ends move freely.
        let p = plan_stream(&[1], &[5], &[], true).unwrap();
        assert_eq!(groups(&p), vec![vec![1], vec![5]]);
        assert!(!p.fixed_i && !p.fixed_j);
        // A seam vertex across a virtual edge stays where it is.
        let p = plan_stream(&[1, 2], &[5], &[], true).unwrap();
        assert!(p.fixed_i && !p.fixed_j);
    }
}
