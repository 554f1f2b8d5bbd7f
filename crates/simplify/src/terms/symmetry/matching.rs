//! Maximum bipartite matching of a plane's candidate pairs (Hopcroft–Karp).

use super::NONE;

/// Scratch of [`max_matching`].
#[derive(Default)]
pub(super) struct MatchingScratch {
    /// Right vertex matched to each left vertex, or [`NONE`].
    left_match: Vec<u32>,
    /// BFS layer of each left vertex ([`NONE`] = unreached or dead).
    layer: Vec<u32>,
    /// Next adjacency position each left vertex's DFS will try.
    next: Vec<u32>,
    /// BFS queue.
    queue: Vec<u32>,
    /// DFS path (left vertices), kept on the heap: components can be long
    /// chains, too deep for recursion.
    stack: Vec<u32>,
}

/// Size of a maximum matching of the bipartite candidate graph (the pairs
/// counted twice by Alg. 2 line 28), by Hopcroft–Karp, `O(E √V)`.
///
/// Left vertices are `0..adj_start.len() − 1`, with right neighbours
/// `adj[adj_start[u]..adj_start[u + 1]]` indexing `right_match`, which must
/// be all [`NONE`] on entry (the caller resets what it used). The count is
/// the same for every maximum matching, so the order of the search only
/// affects speed, never the result.
pub(super) fn max_matching(
    adj_start: &[u32],
    adj: &[u32],
    right_match: &mut [u32],
    m: &mut MatchingScratch,
) -> u64 {
    let left = adj_start.len().saturating_sub(1);
    let nbrs = |u: usize| adj_start[u] as usize..adj_start[u + 1] as usize;
    m.left_match.clear();
    m.left_match.resize(left, NONE);
    let mut size = 0u64;
    // Greedy start: on a symmetry plane nearly every component is a single
    // pair, which this matches outright.
    for u in 0..left {
        if let Some(&v) = adj[nbrs(u)]
            .iter()
            .find(|&&v| right_match[v as usize] == NONE)
        {
            right_match[v as usize] = u as u32;
            m.left_match[u] = v;
            size += 1;
        }
    }
    loop {
        // BFS from the free left vertices along alternating paths; stop at
        // the layer where a free right vertex first appears.
        m.queue.clear();
        m.layer.clear();
        for u in 0..left {
            if m.left_match[u] == NONE {
                m.layer.push(0);
                m.queue.push(u as u32);
            } else {
                m.layer.push(NONE);
            }
        }
        let mut found = false;
        let mut head = 0;
        while head < m.queue.len() {
            let u = m.queue[head] as usize;
            head += 1;
            for &v in &adj[nbrs(u)] {
                let w = right_match[v as usize];
                if w == NONE {
                    found = true;
                } else if m.layer[w as usize] == NONE {
                    m.layer[w as usize] = m.layer[u] + 1;
                    if !found {
                        m.queue.push(w);
                    }
                }
            }
        }
        if !found {
            return size;
        }
        // DFS from each free left vertex along increasing layers; augment
        // along the first path that ends at a free right vertex.
        m.next.clear();
        m.next.extend_from_slice(&adj_start[..left]);
        for root in 0..left {
            if m.left_match[root] != NONE {
                continue;
            }
            m.stack.clear();
            m.stack.push(root as u32);
            while let Some(&u) = m.stack.last() {
                let u = u as usize;
                if m.next[u] == adj_start[u + 1] {
                    // Dead end for the rest of this phase.
                    m.layer[u] = NONE;
                    m.stack.pop();
                    continue;
                }
                let v = adj[m.next[u] as usize];
                m.next[u] += 1;
                let w = right_match[v as usize];
                if w == NONE {
                    // Flip the path: each left vertex on the stack takes
                    // the right vertex its successor was matched to.
                    let mut v = v;
                    for &p in m.stack.iter().rev() {
                        let prev = m.left_match[p as usize];
                        m.left_match[p as usize] = v;
                        right_match[v as usize] = p;
                        v = prev;
                    }
                    size += 1;
                    break;
                }
                let (lu, lw) = (m.layer[u], m.layer[w as usize]);
                if lw != NONE && lu != NONE && lw == lu + 1 {
                    m.stack.push(w);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terms::symmetry::grid::{match_plane, Grid, Scratch};
    use crate::terms::symmetry::plane::Plane;
    use crate::terms::symmetry::test_support::{brute_matched, kuhn_matching, Rng};
    use glam::DVec3;

    /// Maximum matching by trying, for each left vertex in turn, to leave it
    /// unmatched or to match it to each free neighbour (`used` is a bitmask
    /// of right vertices). Exponential; for graphs of a few dozen edges.
    fn exhaustive_matching(adj: &[Vec<usize>], u: usize, used: u64) -> u64 {
        if u == adj.len() {
            return 0;
        }
        let mut best = exhaustive_matching(adj, u + 1, used);
        for &v in &adj[u] {
            if used & (1 << v) == 0 {
                best = best.max(1 + exhaustive_matching(adj, u + 1, used | (1 << v)));
            }
        }
        best
    }

    /// Two vertices mirroring onto one partner: only one pair counts.
    #[test]
    fn each_vertex_is_matched_at_most_once() {
        let plane = Plane {
            n: DVec3::X,
            c: 0.0,
        };
        let points = [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.05, 0.0),
            DVec3::new(-1.0, 0.02, 0.0),
        ];
        let grid = Grid::new(&points, 0.1);
        let m = match_plane(&grid, plane, 0.1, u64::MAX, &mut Scratch::default());
        assert_eq!(m.matched, 2, "one pair of the three vertices");
        assert_eq!(brute_matched(&points, plane, 0.1), 2);
    }

    /// Where nearest-first greedy (Alg. 2's spirit) pairs `a` with its exact
    /// mirror `b` and strands `c` and `d`, the maximum matching pairs
    /// `a–d` and `c–b`: all four have a partner.
    ///
    /// ```text
    ///   d (−0.92)   b (−1.00)  |  a (1.00)   c (1.08)     δ = 0.1
    /// ```
    #[test]
    fn maximum_matching_beats_nearest_first_greedy() {
        let plane = Plane {
            n: DVec3::X,
            c: 0.0,
        };
        let points = [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.08, 0.0, 0.0),
            DVec3::new(-0.92, 0.0, 0.0),
        ];
        let grid = Grid::new(&points, 0.1);
        let m = match_plane(&grid, plane, 0.1, u64::MAX, &mut Scratch::default());
        assert_eq!(m.matched, 4);
    }

    /// Hopcroft–Karp against exhaustive search on random bipartite graphs,
    /// including long chains that need several augmenting phases.
    #[test]
    fn hopcroft_karp_matches_exhaustive_search_on_random_graphs() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let mut scratch = MatchingScratch::default();
        for case in 0..500 {
            let left = rng.below(9);
            let right = 1 + rng.below(12);
            let density = rng.unit();
            let adj: Vec<Vec<usize>> = (0..left)
                .map(|_| (0..right).filter(|_| rng.unit() < density * 0.5).collect())
                .collect();
            let mut adj_start = vec![0u32];
            let mut flat = Vec::new();
            for a in &adj {
                flat.extend(a.iter().map(|&v| v as u32));
                adj_start.push(flat.len() as u32);
            }
            let mut right_match = vec![NONE; right];
            let got = max_matching(&adj_start, &flat, &mut right_match, &mut scratch);
            assert_eq!(got, exhaustive_matching(&adj, 0, 0), "case {case}: {adj:?}");
            assert_eq!(got, kuhn_matching(&adj, right), "case {case}: {adj:?}");
            // A valid matching: each right vertex used once, by a neighbour.
            let used: Vec<_> = right_match.iter().filter(|&&u| u != NONE).collect();
            assert_eq!(used.len() as u64, got);
            for (v, &u) in right_match.iter().enumerate() {
                if u != NONE {
                    assert!(adj[u as usize].contains(&v));
                }
            }
        }
        // A chain where u_i – {v_i, v_{i+1}} and the last u only – v_0: the
        // greedy start gives every u_i its v_i and leaves the last u free,
        // with one augmenting path through all 2000 pairs (too deep for a
        // recursive search on a small stack).
        let n = 2000usize;
        let mut adj_start = vec![0u32];
        let mut flat = Vec::new();
        for i in 0..n {
            if i + 1 < n {
                flat.extend([i as u32, i as u32 + 1]);
            } else {
                flat.push(0);
            }
            adj_start.push(flat.len() as u32);
        }
        let mut right_match = vec![NONE; n];
        assert_eq!(
            max_matching(&adj_start, &flat, &mut right_match, &mut scratch),
            n as u64
        );
    }
}
