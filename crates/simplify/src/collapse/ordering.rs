//! Near-tie ordering by recency (Knodt 2024 §3.2, Alg. 1).
//!
//! Greedy QEM imposes a total order on collapses whose costs are equal but
//! for floating-point noise or negligible geometric differences, and in
//! that essentially random order a quad mesh's edge flow is lost. Knodt
//! treats costs within ε_abs as equal (Eq. 4) and, inside such a class,
//! collapses the edge of highest *recency* first: a collapse adds its own
//! recency plus one to the edges opposite it in its quads, so whole quad
//! chords collapse one after the other.
//!
//! Two queues, as in Alg. 1: the main queue (by cost, in [`crate::collapse`]) and
//! this tie queue (by recency, then cost, then edge id). A class starts
//! when the tie queue is empty: its first edge comes from the main queue,
//! recencies reset (an epoch counter makes that O(1)), and every edge the
//! main queue offers within ε of that first cost joins the class. Classes
//! are anchored at their first cost rather than at the last collapsed one,
//! so a chain of near-equal costs cannot drift a class upward by ε per step.
//!
//! Entries are lazy like the main queue's: an edge whose cost changed
//! (generation bumped) leaves the class when its entry comes up and goes
//! back to the main queue; an edge whose recency grew gets a new entry, and
//! the old one is recognized by its outdated recency.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// How far the tie distance grows with the reduction factor: up to a tenth
/// of the vertices. Past that the mesh is coarse next to its features and
/// a collapse's deviation follows their size, not h², so growing further
/// only trades distance for quads that few faces leave room for (on
/// `corpus/quad` at 1% / 0.1%, unbounded growth cost 6% / 12% more Chamfer
/// distance than quads off; bounded here, under 1%).
pub(crate) const MAX_TIE_GROWTH: f64 = 10.0;

/// Knodt's ε as a distance for an input whose median edge collapse
/// deviates by `deviation` at the start (see
/// [`crate::terms::cost::median_collapse_deviation`]): `factor` times that, at
/// most `epsilon` (see [`crate::QuadSettings::tie_factor`]).
///
/// What counts as "about equal" is a share of the errors collapses
/// actually make on this mesh. Those scale with its resolution and its
/// curvature (about κh²/8 on a smooth surface, h² the area per vertex), so
/// a fixed distance is a different share on every mesh: on a generated
/// bumpy sphere of quads at 50%, the distance past which wider ties keep
/// no more quads but cost distance was 8e-4, 2e-4 and 5e-5 at 1.5k, 6k and
/// 25k vertices, each time about the sphere's median initial deviation
/// (7.8e-4, 2.1e-4, 6.5e-5), and a thin curved blade of 22k vertices
/// (median 3.3e-5) paid 3× the best peer's Chamfer distance at 50% under
/// the fixed 1.5e-3. The cap keeps coarse models, whose collapses are all
/// far off, from ties so wide that chords override every cost (joint
/// weights, symmetry).
pub(crate) fn tie_distance(epsilon: f64, factor: f64, deviation: f64) -> f64 {
    let relative = factor * deviation;
    if relative.is_finite() && relative > 0.0 {
        epsilon.min(relative)
    } else {
        epsilon
    }
}

/// Knodt's ε_abs (Eq. 4) as a cost difference, for a distance tolerance
/// `epsilon` (relative to the diagonal), for a collapse whose endpoints
/// carry `area` on average, on a mesh that started with `start` vertices
/// and has `left` now.
///
/// Costs are area-weighted squared distances, and every collapse hands its
/// area to the vertex it keeps, so moving the vertex of a collapse by d
/// costs up to d² times the area it carries. That area is the collapse's
/// own, not the mesh's average: where the mesh is dense (small parts, fine
/// detail) the same cost difference is a much larger distance, and an
/// average would let ties sweep chords across them.
///
/// The distance itself grows with the reduction factor `start / left`. On a
/// smooth surface a collapse deviates by about κh²/8, and h² (the area per
/// vertex) grows as `start / left`, so a fixed distance would be a large
/// share of the typical collapse early on (whole chords swept across curved
/// parts at 50%) and a vanishing one late (classes of one edge, no chords,
/// at 10%). Scaled so, the tolerance stays a steady share of the error a
/// collapse makes at every stage, until [`MAX_TIE_GROWTH`].
pub(crate) fn tie_tolerance(epsilon: f64, area: f64, start: usize, left: usize) -> f64 {
    let growth = (start.max(1) as f64 / left.max(1) as f64).min(MAX_TIE_GROWTH);
    let d = epsilon * growth;
    d * d * area
}

/// Key of the tie queue: highest recency first, then lowest cost, then
/// edge id (a total, deterministic order).
#[inline]
fn tie_key(recency: u32, cost: f64, edge: u32) -> u128 {
    let c = if cost > 0.0 { cost.to_bits() } else { 0 };
    (((u32::MAX - recency) as u128) << 96) | ((c as u128) << 32) | edge as u128
}

/// A collapse candidate served by the tie queue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Tie {
    /// The edge.
    pub edge: u32,
    /// Its cost when it joined the class.
    pub cost: f64,
    /// The edge generation it joined at.
    pub gen: u32,
    /// Its recency.
    pub recency: u32,
}

/// The tie queue and recencies.
#[derive(Clone, Debug)]
pub(crate) struct TieOrder {
    relative: f64,
    use_recency: bool,
    queue: BinaryHeap<Reverse<(bool, u128, u32)>>,
    recency: Vec<u32>,
    epoch_of: Vec<u32>,
    epoch: u32,
    cost: Vec<f64>,
    in_tie: Vec<bool>,
    bare: Vec<bool>,
    class_cost: f64,
}

impl TieOrder {
    /// For edges `0..edges`, with ε_rel and recency on or off (ε_abs comes
    /// with each candidate).
    pub fn new(edges: usize, relative: f64, use_recency: bool) -> Self {
        TieOrder {
            relative,
            use_recency,
            queue: BinaryHeap::new(),
            recency: vec![0; edges],
            epoch_of: vec![0; edges],
            epoch: 1,
            cost: vec![0.0; edges],
            in_tie: vec![false; edges],
            bare: vec![false; edges],
            class_cost: 0.0,
        }
    }

    /// Recency of edge `e` in the current class.
    #[inline]
    pub fn recency(&self, e: u32) -> u32 {
        if self.epoch_of[e as usize] == self.epoch {
            self.recency[e as usize]
        } else {
            0
        }
    }

    /// Starts a class at `cost`: every recency resets (Alg. 1 line 16).
    pub fn new_class(&mut self, cost: f64) {
        self.epoch = self.epoch.wrapping_add(1);
        self.class_cost = cost;
    }

    /// Eq. 4, with Dawson's relative tolerance beside the absolute one
    /// (the comparison Knodt cites, ablated there as ε_abs and ε_rel):
    /// whether `cost` is approximately equal to the class's, with the
    /// absolute tolerance `epsilon` (cost units) of the collapse it is the
    /// cost of (see [`tie_tolerance`]).
    #[inline]
    pub fn same_class(&self, cost: f64, epsilon: f64) -> bool {
        let d = (cost - self.class_cost).abs();
        d < epsilon || d <= self.relative * cost.max(self.class_cost)
    }

    /// Edge `e` joins the class with its cost and generation; `bare` when
    /// its collapse would take the last face of its part somewhere (see
    /// `Complex::collapse_leaves_a_bare_vertex`). Bare edges come after
    /// every other member of the class, whatever their recency: among
    /// costs taken as equal, shrinking a part beats deleting one (a chord
    /// that runs through a lone quad would otherwise take the whole part
    /// while another part of the same cost only had to lose a corner).
    pub fn push(&mut self, e: u32, cost: f64, gen: u32, bare: bool) {
        self.cost[e as usize] = cost;
        self.in_tie[e as usize] = true;
        self.bare[e as usize] = bare;
        let r = self.recency(e);
        self.queue.push(Reverse((bare, tie_key(r, cost, e), gen)));
    }

    /// Alg. 1 line 23: `recency(e) += by`; an edge waiting in the queue is
    /// re-queued under its new recency.
    pub fn bump(&mut self, e: u32, by: u32, gen: u32) {
        if !self.use_recency {
            return;
        }
        let r = self.recency(e).saturating_add(by);
        self.recency[e as usize] = r;
        self.epoch_of[e as usize] = self.epoch;
        if self.in_tie[e as usize] {
            let c = self.cost[e as usize];
            self.queue
                .push(Reverse((self.bare[e as usize], tie_key(r, c, e), gen)));
        }
    }

    /// The next entry, skipping those superseded by a recency change.
    /// The caller checks the generation (a changed cost sends the edge back
    /// to the main queue) and whether the edge is alive.
    pub fn pop(&mut self) -> Option<Tie> {
        while let Some(Reverse((_, key, gen))) = self.queue.pop() {
            let e = key as u32;
            if !self.in_tie[e as usize] {
                continue;
            }
            let r = u32::MAX - (key >> 96) as u32;
            if r != self.recency(e) {
                continue;
            }
            self.in_tie[e as usize] = false;
            return Some(Tie {
                edge: e,
                cost: self.cost[e as usize],
                gen,
                recency: r,
            });
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tie_distance_is_a_share_of_the_meshs_own_deviation_at_most_epsilon() {
        // Twice a median deviation of 2e-4: 4e-4, under the cap.
        assert!((tie_distance(1.5e-3, 2.0, 2e-4) - 4e-4).abs() < 1e-18);
        // A coarse mesh (deviation 1e-2): the cap.
        assert_eq!(tie_distance(1.5e-3, 2.0, 1e-2), 1.5e-3);
        // No deviation to measure (a flat mesh, no edges): the cap.
        assert_eq!(tie_distance(1.5e-3, 2.0, 0.0), 1.5e-3);
        assert_eq!(tie_distance(1.5e-3, 2.0, f64::NAN), 1.5e-3);
        // Factor 0: the cap alone, as before the factor existed.
        assert_eq!(tie_distance(1.5e-3, 0.0, 2e-4), 1.5e-3);
    }

    #[test]
    fn tie_tolerance_is_a_growing_distance_over_the_collapse_area() {
        // At the start: ε² × area = 1e-4 × 0.08.
        assert!((tie_tolerance(1e-2, 0.08, 100, 100) - 8e-6).abs() < 1e-18);
        // Half the vertices gone: the distance doubles (2e-2), 4e-4 × 0.16
        // for a vertex that took over a neighbour's area.
        assert!((tie_tolerance(1e-2, 0.16, 100, 50) - 6.4e-5).abs() < 1e-17);
        // Past a tenth of the vertices the distance stops growing: 10ε.
        assert!((tie_tolerance(1e-2, 0.5, 1000, 10) - 5e-3).abs() < 1e-15);
        // Nothing left counts as one vertex, not a division by zero.
        assert!(tie_tolerance(1e-2, 8.0, 100, 0).is_finite());
        assert_eq!(tie_tolerance(0.0, 8.0, 100, 10), 0.0);
    }

    #[test]
    fn serves_highest_recency_then_lowest_cost() {
        let mut t = TieOrder::new(5, 0.0, true);
        t.new_class(1.0);
        t.push(0, 1.0002, 0, false);
        t.push(1, 1.0001, 0, false);
        t.push(2, 1.0003, 0, false);
        // Edge 2 becomes most recent: it jumps ahead.
        t.bump(2, 3, 0);
        let order: Vec<(u32, u32)> = std::iter::from_fn(|| t.pop())
            .map(|x| (x.edge, x.recency))
            .collect();
        assert_eq!(order, vec![(2, 3), (1, 0), (0, 0)]);
    }

    #[test]
    fn a_collapse_that_deletes_a_part_comes_last_in_its_class() {
        let mut t = TieOrder::new(3, 0.0, true);
        t.new_class(1.0);
        // Edge 0 is the chord's next side but would take its part's last
        // face; edge 1 costs a little more and only shrinks its part.
        t.push(0, 1.0, 0, true);
        t.push(1, 1.0001, 0, false);
        t.push(2, 1.0002, 0, false);
        t.bump(0, 5, 0);
        t.bump(2, 1, 0);
        let order: Vec<u32> = std::iter::from_fn(|| t.pop()).map(|x| x.edge).collect();
        assert_eq!(order, vec![2, 1, 0]);
    }

    #[test]
    fn new_class_resets_recency_and_eq4_is_strict() {
        let mut t = TieOrder::new(2, 0.0, true);
        t.new_class(2.0);
        t.bump(1, 4, 0);
        assert_eq!(t.recency(1), 4);
        assert!(t.same_class(2.4, 0.5) && t.same_class(1.6, 0.5));
        assert!(!t.same_class(2.5, 0.5));
        // Each candidate brings its own tolerance.
        assert!(t.same_class(2.5, 0.6) && !t.same_class(2.05, 0.01));
        t.new_class(7.0);
        assert_eq!(t.recency(1), 0);
        assert!(t.same_class(7.09, 0.1) && !t.same_class(7.2, 0.1));
        // Relative tolerance: within 10% of the larger cost.
        let mut r = TieOrder::new(1, 0.1, true);
        r.new_class(100.0);
        assert!(r.same_class(109.0, 0.0) && r.same_class(91.0, 0.0));
        assert!(!r.same_class(112.0, 0.0) && !r.same_class(89.0, 0.0));
    }

    #[test]
    fn without_recency_the_class_is_served_by_cost() {
        let mut t = TieOrder::new(3, 0.0, false);
        t.new_class(0.0);
        t.push(0, 0.3, 0, false);
        t.push(1, 0.1, 0, false);
        t.bump(0, 9, 0);
        let order: Vec<u32> = std::iter::from_fn(|| t.pop()).map(|x| x.edge).collect();
        assert_eq!(order, vec![1, 0]);
    }
}
