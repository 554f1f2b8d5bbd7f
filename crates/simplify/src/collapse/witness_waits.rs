//! Edges refused for what would become of one face of their star (it
//! would flip past the normal limit, or flatten to a line on a flat
//! border), each waiting on that face.
//!
//! A refused edge used to be tried again after every collapse one ring
//! out. Around a vertex of high valence that is a quadratic walk: on a
//! disc written as one fan from a rim vertex (coordinates rounded to 6
//! decimals), a few hundred edges of the fan's center were refused for a
//! sliver they would flip, and every collapse along the rim (each rim
//! vertex is a neighbour of the center) queued them all again, each try
//! costing the center's valence, to be refused by the same sliver. The
//! flat-border rule's refusals walk the same way around the center of a
//! flat disc written as a fan from its center.
//!
//! A retry cannot pass while nothing it reads changed. The edge's cost and
//! position change only with its generation (the loop bumps it for every
//! edge whose cost a collapse changed), and with the same position the
//! face that flipped (or flattened) does so again as long as that face
//! keeps its corners where they were: both verdicts read only its corners
//! and the position. A face changes only in a collapse of one of its
//! vertices, that is a collapse whose star holds it. So a refused edge
//! waits on that face, its witness, and goes back into the
//! queue when a collapse's star holds the witness or when its generation
//! is bumped: the same collapses are made as before, without the retries
//! that could only fail again. Every retry is then paid for by a collapse
//! that changed its witness, and every collapse wakes at most the edges
//! waiting on the faces of its star, each once.
//!
//! The old retries one ring out did one more thing: they evaluated the
//! edge again, and the memoryless terms (the crease sides of an endpoint,
//! swept to where its neighbours are now) read the neighbours, which a
//! collapse next door moves without bumping the edge's generation. To keep
//! that (and every output of ordinary meshes), an edge is still tried
//! again after a collapse one ring out, but at most [`NEIGHBOUR_RETRIES`]
//! times until its own cost changes; then it waits on its witness alone.
//! A refusal thus costs at most that many retries beside the ones its
//! witness pays for.

use std::collections::HashMap;

use smallvec::SmallVec;

/// How many times a collapse one ring out puts an edge refused for a face
/// back into the queue before its cost changes (see the module's note).
pub(crate) const NEIGHBOUR_RETRIES: u8 = 8;

/// Edges waiting for their witness face to change.
#[derive(Default)]
pub(crate) struct WitnessWaits {
    /// The face each waiting edge waits on, and whether collapses one ring
    /// out may still try it again (it is then counted in the loop's
    /// `refused_around`).
    witness: HashMap<u32, (u32, bool)>,
    /// The edges waiting on each face. May list an edge that stopped
    /// waiting (or now waits on another face): `witness` decides.
    waiting: HashMap<u32, SmallVec<[u32; 2]>>,
    /// Retries one ring out made for each edge since its cost last changed.
    tries: HashMap<u32, u8>,
}

impl WitnessWaits {
    /// `edge` was refused for what would become of face `face`. Returns whether
    /// collapses one ring out may still try it again.
    pub fn wait(&mut self, edge: u32, face: u32) -> bool {
        let near = self.tries.get(&edge).copied().unwrap_or(0) < NEIGHBOUR_RETRIES;
        self.witness.insert(edge, (face, near));
        self.waiting.entry(face).or_default().push(edge);
        near
    }

    /// Whether a collapse one ring out may try `edge` again: it does not
    /// wait here, or has retries left.
    pub fn near_retry(&self, edge: u32) -> bool {
        !matches!(self.witness.get(&edge), Some(&(_, false)))
    }

    /// `edge` stops waiting (it goes back into the queue, or died).
    /// Returns whether it was waiting here, and if so whether it was
    /// counted as retried one ring out.
    pub fn forget(&mut self, edge: u32) -> Option<bool> {
        self.witness.remove(&edge).map(|(_, near)| near)
    }

    /// A collapse one ring out tries `edge` again.
    pub fn retried_near(&mut self, edge: u32) {
        *self.tries.entry(edge).or_default() += 1;
    }

    /// `edge`'s cost changed (or it died): its retries start over.
    pub fn cost_changed(&mut self, edge: u32) {
        if !self.tries.is_empty() {
            self.tries.remove(&edge);
        }
    }

    /// Face `face` changed: the edges still waiting on it, appended to
    /// `out`. They keep waiting until the caller [`forget`](Self::forget)s
    /// them.
    pub fn wake(&mut self, face: u32, out: &mut Vec<u32>) {
        if self.witness.is_empty() {
            return;
        }
        if let Some(mut edges) = self.waiting.remove(&face) {
            // An edge refused for this face again before it changed is
            // listed once per refusal.
            edges.sort_unstable();
            edges.dedup();
            out.extend(
                edges
                    .into_iter()
                    .filter(|e| self.witness.get(e).is_some_and(|w| w.0 == face)),
            );
        }
    }

    /// Whether no edge waits and none has retries counted.
    pub fn is_empty(&self) -> bool {
        self.witness.is_empty() && self.tries.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edge_wakes_once_and_only_for_its_current_witness() {
        let mut w = WitnessWaits::default();
        w.wait(7, 1);
        w.wait(8, 1);
        // Edge 8 goes back into the queue and is refused again for face 2.
        assert!(w.forget(8).is_some());
        w.wait(8, 2);
        let mut out = Vec::new();
        w.wake(1, &mut out);
        assert_eq!(out, vec![7]);
        // Face 1's list is spent: a second change wakes nothing.
        out.clear();
        w.wake(1, &mut out);
        assert!(out.is_empty());
        w.wake(2, &mut out);
        assert_eq!(out, vec![8]);
        assert!(w.forget(7).is_some() && w.forget(8).is_some());
        assert!(w.forget(7).is_none());
        assert!(w.is_empty());
    }

    #[test]
    fn retries_one_ring_out_run_out_until_the_cost_changes() {
        let mut w = WitnessWaits::default();
        for _ in 0..NEIGHBOUR_RETRIES {
            assert!(w.wait(3, 9));
            assert!(w.near_retry(3));
            assert_eq!(w.forget(3), Some(true));
            w.retried_near(3);
        }
        // Out of retries: only its witness wakes it now.
        assert!(!w.wait(3, 9));
        assert!(!w.near_retry(3));
        let mut out = Vec::new();
        w.wake(9, &mut out);
        assert_eq!(out, vec![3]);
        assert_eq!(w.forget(3), Some(false));
        // Its cost changed: retries start over.
        w.cost_changed(3);
        assert!(w.wait(3, 9));
        assert!(w.forget(3).is_some());
        assert!(w.is_empty());
    }
}
