//! The crease-area term: W's boundary-area quadric (Eq. 15) applied at
//! sharp creases, whose sides sweep area as their end moves just as a
//! border's do ([`crate::Metric::crease_area_weight`]). Not in either
//! paper: a crease is a border between two smooth regions, and the plane
//! quadrics alone let a crease vertex slide along the crease's sharper side
//! (`docs/design.md`, "Creases swept like borders").

use crate::terms::quadric::Quadric;
use crate::terms::term::{swept, Candidate, CollapseTerm};

/// Sum over the sharp sides at either endpoint (dihedral above the crease
/// angle) of the area they sweep, times `weight`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CreaseArea {
    /// `boundary_area_weight × crease_area_weight`.
    pub weight: f64,
    /// Cosine of [`crate::Metric::crease_angle`].
    pub cos: f64,
}

impl CollapseTerm for CreaseArea {
    fn evaluate(&self, cand: &Candidate<'_>, sides: &mut Vec<u32>, total: &mut Quadric) {
        let (i, j) = (cand.i, cand.j);
        if !(cand.at_crease(i) || cand.at_crease(j)) {
            return;
        }
        let c = cand.c;
        let mut area = Quadric::ZERO;
        sides.clear();
        if cand.at_crease(i) {
            c.crease_neighbors(i, self.cos, sides);
        }
        for &k in sides.iter() {
            area += swept(cand.pi, c.pos[k as usize]);
        }
        sides.clear();
        if cand.at_crease(j) {
            c.crease_neighbors(j, self.cos, sides);
        }
        for &k in sides.iter() {
            // The edge (i, j) itself was counted from i's side.
            if k != i {
                area += swept(cand.pj, c.pos[k as usize]);
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
    fn charges_the_area_swept_against_the_sharp_side_of_a_flagged_endpoint() {
        // A 90° fold: side 0–1 is a crease. Collapsing edge (0, 2) with 0
        // at the crease, moved to (0,1,0): side 0–1 sweeps a triangle of
        // area 1/2, so 2·(1/2)² = 1/2, times the weight 4.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, -1.0)];
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 0, 3]);
        let e = c.edge_between(0, 2).expect("edge");
        let q = Quadric::ZERO;
        let term = CreaseArea {
            weight: 4.0,
            cos: 78f64.to_radians().cos(),
        };
        let charge = |crease: &[bool]| {
            let cand = Candidate {
                c: &c,
                e,
                i: 0,
                j: 2,
                pi: DVec3::ZERO,
                pj: DVec3::Y,
                qi: &q,
                qj: &q,
                border_i: &[],
                border_j: &[],
                crease,
            };
            let mut total = Quadric::ZERO;
            term.evaluate(&cand, &mut Vec::new(), &mut total);
            total.eval(DVec3::Y)
        };
        assert!((charge(&[true, true, false, false]) - 2.0).abs() < 1e-12);
        // No endpoint flagged: nothing, whatever the mesh's creases.
        assert_eq!(charge(&[false, true, false, false]), 0.0);
        assert_eq!(charge(&[]), 0.0);
    }
}
