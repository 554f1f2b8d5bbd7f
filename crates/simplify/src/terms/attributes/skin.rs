//! Joint influences as attributes (Knodt 2024 §3, Eq. 6, after Hoppe 1999):
//! the weight of every joint is a scalar attribute with a linear functional
//! per face, accumulated per vertex in a sparse quadric that holds only the
//! joints that influence it. Copies of one position share one quadric, so
//! they end with one influence set: the seam copies of a skinned vertex can
//! no longer move apart when it animates.
//!
//! Knodt keeps at most 16 joints per vertex, dropping on overflow the joint
//! whose larger fitted weight at the two merged positions is smallest; after
//! simplifying, the top influences are kept and normalized to sum 1.

use glam::DVec3;
use smallvec::SmallVec;

use crate::terms::quadric::Quadric;

/// Joints a vertex quadric holds at most (Knodt §3).
pub(crate) const MAX_JOINTS: usize = 16;

/// One joint's linear-functional sums: `B = Σ a g`, `e = Σ a d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JointTerm {
    pub joint: u16,
    pub grad: DVec3,
    pub offset: f64,
}

/// The sparse attribute quadric of a vertex's joint weights (the layout of
/// `quadric.rs` with one component per joint present).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SkinQuadric {
    pub alpha: f64,
    pub a: [f64; 6],
    pub b: DVec3,
    pub c: f64,
    pub joints: SmallVec<[JointTerm; 4]>,
}

impl SkinQuadric {
    /// Adds a face's functional for `joint`: `w(p) = g·p + d`, area share `a`.
    pub fn add_joint(&mut self, joint: u16, a: f64, g: DVec3, d: f64) {
        let ag = g * a;
        self.a[0] += ag.x * g.x;
        self.a[1] += ag.x * g.y;
        self.a[2] += ag.x * g.z;
        self.a[3] += ag.y * g.y;
        self.a[4] += ag.y * g.z;
        self.a[5] += ag.z * g.z;
        self.b += ag * d;
        self.c += a * d * d;
        match self.joints.iter_mut().find(|t| t.joint == joint) {
            Some(t) => {
                t.grad += ag;
                t.offset += a * d;
            }
            None => self.joints.push(JointTerm {
                joint,
                grad: ag,
                offset: a * d,
            }),
        }
    }

    /// The fitted weight of term `t` at `v`.
    fn weight_at(&self, t: &JointTerm, v: DVec3) -> f64 {
        if self.alpha > 0.0 {
            (t.grad.dot(v) + t.offset) / self.alpha
        } else {
            0.0
        }
    }

    /// Sums `other` (the quadric of the vertex at `p_other`) into `self` (at
    /// `p_self`), keeping at most [`MAX_JOINTS`] joints: on overflow the
    /// joint whose larger fitted weight at the two positions is smallest
    /// goes (Knodt §3). Its share of `A`, `b`, `c` stays: those sums are not
    /// kept per joint, and the joint weighed least where it was dropped.
    pub fn merge(&mut self, other: &SkinQuadric, p_self: DVec3, p_other: DVec3) {
        // Fitted weights before merging, for the overflow rule.
        let mut strength: SmallVec<[(u16, f64); 8]> = SmallVec::new();
        for t in &self.joints {
            strength.push((t.joint, self.weight_at(t, p_self)));
        }
        for t in &other.joints {
            let w = other.weight_at(t, p_other);
            match strength.iter_mut().find(|s| s.0 == t.joint) {
                Some(s) => s.1 = s.1.max(w),
                None => strength.push((t.joint, w)),
            }
        }
        self.alpha += other.alpha;
        for k in 0..6 {
            self.a[k] += other.a[k];
        }
        self.b += other.b;
        self.c += other.c;
        for t in &other.joints {
            match self.joints.iter_mut().find(|s| s.joint == t.joint) {
                Some(s) => {
                    s.grad += t.grad;
                    s.offset += t.offset;
                }
                None => self.joints.push(*t),
            }
        }
        while self.joints.len() > MAX_JOINTS {
            let weakest = self
                .joints
                .iter()
                .enumerate()
                .min_by(|(_, x), (_, y)| {
                    let sx = strength
                        .iter()
                        .find(|s| s.0 == x.joint)
                        .map_or(0.0, |s| s.1);
                    let sy = strength
                        .iter()
                        .find(|s| s.0 == y.joint)
                        .map_or(0.0, |s| s.1);
                    sx.total_cmp(&sy).then(x.joint.cmp(&y.joint))
                })
                .map(|(k, _)| k);
            if let Some(k) = weakest {
                self.joints.remove(k);
            }
        }
    }

    /// The position quadric left after choosing the best weights (see
    /// `quadric.rs`), times `scale`.
    pub fn reduce(&self, scale: f64) -> Quadric {
        if (self.alpha.is_nan() || self.alpha <= 0.0) || scale == 0.0 {
            return Quadric::ZERO;
        }
        let inv = 1.0 / self.alpha;
        let mut a = self.a;
        let mut b = self.b;
        let mut c = self.c;
        for t in &self.joints {
            let g = t.grad;
            let gi = g * inv;
            a[0] -= gi.x * g.x;
            a[1] -= gi.x * g.y;
            a[2] -= gi.x * g.z;
            a[3] -= gi.y * g.y;
            a[4] -= gi.y * g.z;
            a[5] -= gi.z * g.z;
            b -= gi * t.offset;
            c -= t.offset * t.offset * inv;
        }
        Quadric {
            a: a.map(|x| x * scale),
            b: b * scale,
            c: c * scale,
            weight: 0.0,
        }
    }

    /// The influences at `v`: the `k` largest fitted weights (negative ones
    /// are 0), normalized to sum 1, as (joint, weight) sorted by weight then
    /// joint. Empty when the quadric holds no joint.
    pub fn influences(&self, v: DVec3, k: usize) -> SmallVec<[(u16, f64); 8]> {
        let mut w: SmallVec<[(u16, f64); 8]> = self
            .joints
            .iter()
            .map(|t| (t.joint, self.weight_at(t, v).max(0.0)))
            .collect();
        if !w.iter().any(|x| x.1 > 0.0) {
            // Every fitted weight vanished (a far extrapolation): the joint
            // that comes closest takes it all.
            let best = self
                .joints
                .iter()
                .map(|t| (t.joint, self.weight_at(t, v)))
                .max_by(|x, y| x.1.total_cmp(&y.1).then(y.0.cmp(&x.0)));
            w = best.map(|(j, _)| (j, 1.0)).into_iter().collect();
        }
        w.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
        w.truncate(k);
        let kept: f64 = w.iter().map(|x| x.1).sum();
        if kept > 0.0 {
            for x in w.iter_mut() {
                x.1 /= kept;
            }
        } else {
            w.clear();
        }
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_blend_along_x_is_fitted_at_the_new_position() {
        // Joint 0 weight 1 − x, joint 1 weight x, over one face of area 1:
        // at x = 0.25 the influences are 0.75 / 0.25 (hand-computed).
        let mut q = SkinQuadric {
            alpha: 1.0,
            ..SkinQuadric::default()
        };
        q.add_joint(0, 1.0, -DVec3::X, 1.0);
        q.add_joint(1, 1.0, DVec3::X, 0.0);
        let w = q.influences(DVec3::new(0.25, 3.0, 0.0), 4);
        assert_eq!(w.len(), 2);
        assert_eq!(w[0].0, 0);
        assert!((w[0].1 - 0.75).abs() < 1e-12 && (w[1].1 - 0.25).abs() < 1e-12);
        // Linear fields are reproduced: no error anywhere.
        assert!(q.reduce(1.0).eval(DVec3::new(0.7, -1.0, 2.0)).abs() < 1e-12);
    }

    #[test]
    fn top_k_are_kept_and_renormalized() {
        // Constant weights 0.5, 0.3, 0.2 on joints 4, 9, 2; keep two.
        let mut q = SkinQuadric {
            alpha: 1.0,
            ..SkinQuadric::default()
        };
        for (j, w) in [(4u16, 0.5), (9, 0.3), (2, 0.2)] {
            q.add_joint(j, 1.0, DVec3::ZERO, w);
        }
        let w = q.influences(DVec3::ZERO, 2);
        assert_eq!(w.iter().map(|x| x.0).collect::<Vec<_>>(), vec![4, 9]);
        assert!((w[0].1 - 0.625).abs() < 1e-12 && (w[1].1 - 0.375).abs() < 1e-12);
    }

    #[test]
    fn merging_past_sixteen_joints_drops_the_weakest() {
        let mut a = SkinQuadric {
            alpha: 1.0,
            ..SkinQuadric::default()
        };
        let mut b = a.clone();
        // a: joints 0..10 at weight 0.1 each; b: joints 10..17, joint 16
        // weakest (0.001), the others 0.14.
        for j in 0..10u16 {
            a.add_joint(j, 1.0, DVec3::ZERO, 0.1);
        }
        for j in 10..17u16 {
            b.add_joint(j, 1.0, DVec3::ZERO, if j == 16 { 0.001 } else { 0.14 });
        }
        a.merge(&b, DVec3::ZERO, DVec3::X);
        assert_eq!(a.joints.len(), MAX_JOINTS);
        assert!(a.joints.iter().all(|t| t.joint != 16));
        assert_eq!(a.alpha, 2.0);
    }
}
