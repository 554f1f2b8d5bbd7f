//! The interface every memoryless cost term implements (W §4.2: terms
//! "recomputed on the current mesh" for each candidate, unlike the vertex
//! quadrics, which carry memory through the collapses, W Eq. 13).
//!
//! A term sees one candidate collapse ([`Candidate`]) and adds what it
//! charges, as a quadric in the new vertex's position, to the candidate's
//! total before the optimal point is solved; so every term shapes both
//! the rank and the placement, as W's boundary-area quadric does. A term
//! keeps no state between collapses: what carries over (the vertex
//! quadrics, the attributes' wedges) is updated by the collapse itself.
//! The terms a run uses are listed in one place, [`crate::terms`]'s
//! `collapse_terms`, each in its own file.

use std::fmt::Debug;

use glam::DVec3;

use crate::prepare::complex::Complex;
use crate::terms::quadric::Quadric;

/// No edge longer than this (in diagonals of the bulk of the input, see
/// `Prepared::outliers`) collapses, and no side longer than it adds area:
/// only an edge to an outlier vertex is that long, and a quadric evaluated
/// that far from where it was stored is rounding noise (single-precision
/// entries times the squared travel: a collapse into a vertex at -1e30 came
/// out at cost -3.5e51).
pub(crate) const FAR: f64 = 10.0;

/// The Lindstrom–Turk area quadric of the side from `p` to `k` (W Eq. 15),
/// or nothing for a side longer than [`FAR`]: one reaching an outlier
/// vertex, whose quadric would be rounding noise of order 1e54.
#[inline]
pub(crate) fn swept(p: DVec3, k: DVec3) -> Quadric {
    if p.distance_squared(k) <= FAR * FAR {
        Quadric::boundary_area(p, k)
    } else {
        Quadric::ZERO
    }
}

/// One candidate collapse of edge `e = (i, j)`, as every term sees it: the
/// current mesh, the endpoints and their summed-so-far quadrics, and what
/// the evaluation gathered once for all terms.
pub(crate) struct Candidate<'a> {
    pub c: &'a Complex,
    pub e: u32,
    pub i: u32,
    pub j: u32,
    pub pi: DVec3,
    pub pj: DVec3,
    /// The endpoints' vertex quadrics (their weights are the area each
    /// stands for).
    pub qi: &'a Quadric,
    pub qj: &'a Quadric,
    /// The endpoints' neighbours across boundary edges (empty off a border,
    /// and when no term or guard asks for borders).
    pub border_i: &'a [u32],
    pub border_j: &'a [u32],
    /// Which vertices are at a sharp crease (empty: none tracked).
    pub crease: &'a [bool],
}

impl Candidate<'_> {
    /// Whether vertex `v` is at a sharp crease.
    #[inline]
    pub fn at_crease(&self, v: u32) -> bool {
        self.crease.get(v as usize).copied().unwrap_or(false)
    }
}

/// A memoryless term of the cost of a collapse.
pub(crate) trait CollapseTerm: Debug + Send + Sync {
    /// Adds what collapsing `cand` costs under this term, as a quadric in
    /// the merged vertex's position, to `total` (a term that does not apply
    /// to the candidate adds nothing). `scratch` is a buffer the term may
    /// reuse between calls.
    fn evaluate(&self, cand: &Candidate<'_>, scratch: &mut Vec<u32>, total: &mut Quadric);
}
