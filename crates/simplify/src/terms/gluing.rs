//! The gluing term: what merging two separate parts across a virtual edge
//! (W §4.1.1) costs. Not in either paper: W ranks a virtual edge by the
//! plane quadrics alone, which are blind to travel within each part's own
//! planes, so a flat part could slide onto another for free
//! ([`crate::Metric::gluing_weight`]; `docs/design.md`, "Virtual edges and the gluing term").

use crate::terms::quadric::Quadric;
use crate::terms::term::{Candidate, CollapseTerm};

/// On a virtual edge with no face (two parts that only come close): each
/// endpoint's area times the squared distance it travels, times `weight`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Gluing {
    pub weight: f64,
}

impl CollapseTerm for Gluing {
    fn evaluate(&self, cand: &Candidate<'_>, _: &mut Vec<u32>, total: &mut Quadric) {
        let c = cand.c;
        if c.edges[cand.e as usize].is_virtual() && c.edge_face_count(cand.i, cand.j) == 0 {
            *total += Quadric::point(cand.pi, self.weight * cand.qi.weight);
            *total += Quadric::point(cand.pj, self.weight * cand.qj.weight);
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::prepare::complex::Complex;

    /// Two triangles apart along x, a virtual edge between vertex 1 at
    /// (1,0,0) and vertex 3 at (3,0,0).
    fn apart() -> Complex {
        let pos = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(3.0, 1.0, 0.0),
        ];
        let (mut c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 3, 4, 5]);
        c.add_edge(1, 3);
        c
    }

    fn charge(c: &Complex, i: u32, j: u32) -> Quadric {
        let e = c.edge_between(i, j).expect("edge");
        let (qi, qj) = (
            Quadric {
                weight: 0.5,
                ..Quadric::ZERO
            },
            Quadric {
                weight: 2.0,
                ..Quadric::ZERO
            },
        );
        let cand = Candidate {
            c,
            e,
            i,
            j,
            pi: c.pos[i as usize],
            pj: c.pos[j as usize],
            qi: &qi,
            qj: &qj,
            border_i: &[],
            border_j: &[],
            crease: &[],
        };
        let mut total = Quadric::ZERO;
        Gluing { weight: 10.0 }.evaluate(&cand, &mut Vec::new(), &mut total);
        total
    }

    #[test]
    fn charges_each_endpoints_area_times_its_squared_travel_on_a_virtual_edge() {
        let c = apart();
        let q = charge(&c, 1, 3);
        // Meeting at (2,0,0): each travels 1; 10·(0.5·1 + 2·1) = 25.
        assert!((q.eval(DVec3::new(2.0, 0.0, 0.0)) - 25.0).abs() < 1e-12);
        // At vertex 3: only vertex 1 travels, by 2: 10·0.5·4 = 20.
        assert!((q.eval(DVec3::new(3.0, 0.0, 0.0)) - 20.0).abs() < 1e-12);
    }

    #[test]
    fn a_physical_edge_is_not_charged() {
        let c = apart();
        assert_eq!(charge(&c, 0, 1).eval(DVec3::new(0.5, 0.0, 0.0)), 0.0);
    }
}
