//! The boundary-area term (W §4.2, Eq. 15–17; Lindstrom & Turk 1998): the
//! area a border edge of the candidate's one-ring sweeps as its end moves,
//! so that open borders keep their outline. Memoryless: recomputed on the
//! current mesh ([`crate::Metric::boundary_area`]).

use crate::terms::quadric::Quadric;
use crate::terms::term::{swept, Candidate, CollapseTerm};

/// Sum over the boundary edges at either endpoint of the area they sweep,
/// times `weight` ([`crate::Metric::boundary_area_weight`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoundaryArea {
    pub weight: f64,
}

impl CollapseTerm for BoundaryArea {
    fn evaluate(&self, cand: &Candidate<'_>, _: &mut Vec<u32>, total: &mut Quadric) {
        if cand.border_i.is_empty() && cand.border_j.is_empty() {
            return;
        }
        let mut area = Quadric::ZERO;
        for &k in cand.border_i {
            area += swept(cand.pi, cand.c.pos[k as usize]);
        }
        for &k in cand.border_j {
            // The edge (i, j) itself was counted from i's side.
            if k != cand.i {
                area += swept(cand.pj, cand.c.pos[k as usize]);
            }
        }
        *total += area.scaled(self.weight);
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::prepare::complex::Complex;

    #[test]
    fn charges_weight_times_twice_the_squared_swept_area_once_per_side() {
        // One triangle: i = 0 at the origin, j = 1 at (1,0,0), k = 2 at
        // (0,1,0). The side (i, k) swept to x = (1,0,0) spans a triangle of
        // area 1/2: 2·(1/2)² = 1/2, times the weight 3. The side (j, i) is
        // the candidate's own edge, counted from i's side only.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        let (c, _) = Complex::new(pos, &[0, 3], &[0, 1, 2]);
        let (qi, qj) = (Quadric::ZERO, Quadric::ZERO);
        let cand = Candidate {
            c: &c,
            e: 0,
            i: 0,
            j: 1,
            pi: DVec3::ZERO,
            pj: DVec3::X,
            qi: &qi,
            qj: &qj,
            border_i: &[2],
            border_j: &[0],
            crease: &[],
        };
        let mut total = Quadric::ZERO;
        BoundaryArea { weight: 3.0 }.evaluate(&cand, &mut Vec::new(), &mut total);
        assert!((total.eval(DVec3::X) - 1.5).abs() < 1e-12);
        // Moving along the side itself sweeps nothing.
        assert!(total.eval(DVec3::new(0.0, 0.5, 0.0)).abs() < 1e-12);
        // Off every border: nothing.
        let inner = Candidate {
            border_i: &[],
            border_j: &[],
            ..cand
        };
        let mut none = Quadric::ZERO;
        BoundaryArea { weight: 3.0 }.evaluate(&inner, &mut Vec::new(), &mut none);
        assert_eq!(none.eval(DVec3::X), 0.0);
    }
}
