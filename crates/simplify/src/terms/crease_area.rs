//! The crease-area term: W's boundary-area quadric (Eq. 15) applied at
//! sharp creases, whose sides sweep area as their end moves just as a
//! border's do ([`crate::Metric::crease_area_weight`]). Not in either
//! paper: a crease is a border between two smooth regions, and the plane
//! quadrics alone let a crease vertex slide along the crease's sharper side
//! (`docs/design.md`, "Creases swept like borders").

use glam::DVec3;

use crate::prepare::neighbour_moments::NeighbourMoments;
use crate::terms::quadric::Quadric;
use crate::terms::term::{swept, Candidate, CollapseTerm, FAR};

/// Sum over the sharp sides at either endpoint (dihedral above the crease
/// angle) of the area they sweep, times `weight`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CreaseArea {
    /// `boundary_area_weight × crease_area_weight`.
    pub weight: f64,
    /// Cosine of [`crate::Metric::crease_angle`].
    pub cos: f64,
}

/// Above this many crease sides at a vertex, their swept areas are summed
/// from the moments of their ends' positions (see `neighbour_moments`) in
/// constant time instead of one by one. Summed the other way round, the
/// same sum rounds differently; below it (every vertex of an ordinary
/// mesh: 64 creases meet only at a fan's centre) the outputs stay as they
/// were.
const MOMENTS_ABOVE: usize = 64;

impl CreaseArea {
    /// The area vertex `v` at `p` sweeps against its crease sides, from
    /// their moments when it keeps them and has many; `None` otherwise.
    fn swept_by_moments(&self, cand: &Candidate<'_>, v: u32, p: DVec3) -> Option<Quadric> {
        let (len, m) = cand.c.crease_moments(v, self.cos)?;
        // Past `FAR` a side adds nothing (see `swept`): an outlier among
        // the ends is summed one by one.
        let reach = p.length() + m.max_norm_sq.sqrt();
        (len > MOMENTS_ABOVE && reach <= FAR).then(|| swept_sum(p, m))
    }
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
            if let Some(q) = self.swept_by_moments(cand, i, cand.pi) {
                area += q;
            } else {
                c.crease_neighbors(i, self.cos, sides);
            }
        }
        for &k in sides.iter() {
            area += swept(cand.pi, c.pos[k as usize]);
        }
        sides.clear();
        if cand.at_crease(j) {
            if let Some(q) = self.swept_by_moments(cand, j, cand.pj) {
                // The edge (i, j) itself was counted from i's side.
                area += q;
                if c.side_is_crease(j, i, self.cos) {
                    area += swept(cand.pj, cand.pi).scaled(-1.0);
                }
            } else {
                c.crease_neighbors(j, self.cos, sides);
            }
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

/// Σₖ of W's boundary-area quadric (Eq. 15) of the side from `p` to `k`,
/// over the points `k` whose moments are `m`: with s = k − p and
/// t = p × k, the quadric of one side is ½(|s|² I − s sᵀ, −s × t, |t|²),
/// and each part sums from the count n, the sum M₁ and the outer-product
/// sum M₂:
/// Σ s sᵀ = M₂ − p M₁ᵀ − M₁ pᵀ + n p pᵀ,
/// Σ s × t = p tr M₂ − M₂ p − p (p · M₁) + |p|² M₁,
/// Σ |t|² = |p|² tr M₂ − pᵀ M₂ p.
fn swept_sum(p: DVec3, m: &NeighbourMoments) -> Quadric {
    let (n, m1) = (m.count, m.sum);
    let tr = m.outer_trace();
    let m2p = m.outer_times(p);
    let pp = p.length_squared();
    let ss = tr - 2.0 * p.dot(m1) + n * pp;
    let pa = p.to_array();
    let ma = m1.to_array();
    let outer = |a: usize, b: usize, o: f64| o - pa[a] * ma[b] - ma[a] * pa[b] + n * pa[a] * pa[b];
    let [xx, xy, xz, yy, yz, zz] = m.outer;
    let h = 0.5;
    Quadric {
        a: [
            (ss - outer(0, 0, xx)) * h,
            -outer(0, 1, xy) * h,
            -outer(0, 2, xz) * h,
            (ss - outer(1, 1, yy)) * h,
            -outer(1, 2, yz) * h,
            (ss - outer(2, 2, zz)) * h,
        ],
        b: -(p * tr - m2p - p * p.dot(m1) + pp * m1) * h,
        c: (pp * tr - p.dot(m2p)) * h,
        weight: 0.0,
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

    #[test]
    fn swept_areas_summed_from_moments_equal_the_sum_side_by_side() {
        // One side by hand: p at the origin, k = (1, 0, 0): the triangle
        // (p, k, x) has area √(y² + z²) / 2, and the quadric is twice its
        // square (Eq. 15–17), ½ (y² + z²): a = ½ diag(0, 1, 1), b = 0, c = 0.
        let one = swept_sum(DVec3::ZERO, &NeighbourMoments::of([DVec3::X]));
        assert_eq!(one.a, [0.0, 0.0, 0.0, 0.5, 0.0, 0.5]);
        assert_eq!(one.b, DVec3::ZERO);
        assert_eq!(one.c, 0.0);
        // Many sides from an off-origin vertex, some points added and
        // removed again: the same quadric as summing them one by one.
        let p = DVec3::new(0.3, -0.2, 0.7);
        let ks: Vec<DVec3> = (0..50)
            .map(|t| {
                let a = t as f64 * 0.37;
                DVec3::new(a.cos(), a.sin(), 0.1 * (3.0 * a).sin()) * (0.2 + 0.01 * t as f64)
            })
            .collect();
        let mut m = NeighbourMoments::of(ks.iter().copied());
        m.add(DVec3::new(5.0, 5.0, 5.0));
        m.remove(DVec3::new(5.0, 5.0, 5.0));
        let mut direct = Quadric::ZERO;
        for &k in &ks {
            direct += Quadric::boundary_area(p, k);
        }
        let sum = swept_sum(p, &m);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs());
        assert!(
            (0..6).all(|t| close(sum.a[t], direct.a[t])),
            "{sum:?} {direct:?}"
        );
        assert!(
            (0..3).all(|t| close(sum.b[t], direct.b[t])),
            "{sum:?} {direct:?}"
        );
        assert!(close(sum.c, direct.c), "{sum:?} {direct:?}");
        // And at any position the two agree on the cost.
        for x in [DVec3::ZERO, p, DVec3::new(-1.0, 2.0, 0.5)] {
            let (a, b) = (sum.eval(x), direct.eval(x));
            assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} {b}");
        }
    }
}
