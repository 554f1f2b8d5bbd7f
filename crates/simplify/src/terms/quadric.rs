//! Quadrics: plane quadrics (Garland & Heckbert 1997; W App. A.1), the
//! Lindstrom–Turk area quadric (W App. A.3, Eq. 15–17), probabilistic
//! regularization (Trettner & Kobbelt 2020) and the optimal-point solve
//! (W Eq. 14).
//!
//! A quadric is the triplet (A, b, c) of W Eq. 4: `E(x) = xᵀAx + 2bᵀx + c`,
//! with A symmetric and stored as its upper triangle. It also carries the
//! total weight (area) it accumulated, so that an error can be reported as a
//! distance: `sqrt(E / weight)`.

use glam::DVec3;

/// `E(x) = xᵀAx + 2bᵀx + c`, plus the accumulated weight.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadric {
    /// Upper triangle of A: xx, xy, xz, yy, yz, zz.
    pub a: [f64; 6],
    /// The linear term b.
    pub b: DVec3,
    /// The constant c.
    pub c: f64,
    /// Sum of the weights (areas, lengths) of the terms added in.
    pub weight: f64,
}

impl Quadric {
    /// The zero quadric.
    pub const ZERO: Quadric = Quadric {
        a: [0.0; 6],
        b: DVec3::ZERO,
        c: 0.0,
        weight: 0.0,
    };

    /// The plane quadric 𝒫(n, p) of W Eq. 5–6: squared distance to the plane
    /// through `p` with unit normal `n`, times `weight`.
    pub fn plane(n: DVec3, p: DVec3, weight: f64) -> Quadric {
        let d = -n.dot(p);
        Quadric {
            a: [
                n.x * n.x * weight,
                n.x * n.y * weight,
                n.x * n.z * weight,
                n.y * n.y * weight,
                n.y * n.z * weight,
                n.z * n.z * weight,
            ],
            b: n * (d * weight),
            c: d * d * weight,
            weight,
        }
    }

    /// `weight · |x − p|²`: a point quadric. Added with a tiny weight it is
    /// the isotropic part of Trettner & Kobbelt's probabilistic plane quadric
    /// (normal variance σ²: `E[(nᵀ(x−p))²] = (x−p)ᵀ(n̄n̄ᵀ + σ²I)(x−p)`), which
    /// makes A positive definite without moving the minimum of a
    /// well-conditioned quadric noticeably.
    pub fn point(p: DVec3, weight: f64) -> Quadric {
        Quadric {
            a: [weight, 0.0, 0.0, weight, 0.0, weight],
            b: -p * weight,
            c: p.length_squared() * weight,
            weight: 0.0,
        }
    }

    /// The Lindstrom–Turk area quadric of one boundary edge `(a, b)`
    /// (W Eq. 15–17): with `s = b − a` and `t = a × b`,
    /// `Q = ([s]ₓᵀ[s]ₓ, −[s]ₓ t, tᵀt) / 2`, so that
    /// `E(x) = |s × x + t|² / 2 = 2 · area(a, b, x)²`: it grows with the area
    /// swept when the boundary edge's endpoint moves to `x`.
    pub fn boundary_area(a: DVec3, b: DVec3) -> Quadric {
        let s = b - a;
        let t = a.cross(b);
        // [s]ₓᵀ[s]ₓ = |s|² I − s sᵀ.
        let ss = s.length_squared();
        let h = 0.5;
        Quadric {
            a: [
                (ss - s.x * s.x) * h,
                -s.x * s.y * h,
                -s.x * s.z * h,
                (ss - s.y * s.y) * h,
                -s.y * s.z * h,
                (ss - s.z * s.z) * h,
            ],
            // −[s]ₓ t = −(s × t).
            b: -s.cross(t) * h,
            c: t.length_squared() * h,
            weight: 0.0,
        }
    }

    /// Scales every term (and the weight) by `k`.
    pub fn scaled(&self, k: f64) -> Quadric {
        Quadric {
            a: self.a.map(|v| v * k),
            b: self.b * k,
            c: self.c * k,
            weight: self.weight * k,
        }
    }

    /// `E(x) = xᵀAx + 2bᵀx + c`.
    #[inline]
    pub fn eval(&self, x: DVec3) -> f64 {
        let a = &self.a;
        let ax = sym_mul(a, x);
        x.dot(ax) + 2.0 * self.b.dot(x) + self.c
    }

    /// The minimizer of E: the solution of `A x = −b` (W Eq. 14), or `None`
    /// when A is singular or too ill-conditioned for the solution to mean
    /// anything (a flat or linear neighborhood without regularization).
    pub fn minimizer(&self) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        // Cofactors of the symmetric matrix.
        let c00 = yy * zz - yz * yz;
        let c01 = xz * yz - xy * zz;
        let c02 = xy * yz - xz * yy;
        let det = xx * c00 + xy * c01 + xz * c02;
        // Scale-free conditioning test: compare det with the cube of the
        // largest diagonal entry. 1e-12 keeps solutions whose relative error
        // stays below ~1e-4 in f64.
        let scale = xx.abs().max(yy.abs()).max(zz.abs());
        if scale.is_nan() || scale <= 0.0 || det.abs() <= 1e-12 * scale * scale * scale {
            return None;
        }
        let c11 = xx * zz - xz * xz;
        let c12 = xy * xz - xx * yz;
        let c22 = xx * yy - xy * xy;
        let inv = 1.0 / det;
        let b = -self.b;
        let x = DVec3::new(
            (c00 * b.x + c01 * b.y + c02 * b.z) * inv,
            (c01 * b.x + c11 * b.y + c12 * b.z) * inv,
            (c02 * b.x + c12 * b.y + c22 * b.z) * inv,
        );
        x.is_finite().then_some(x)
    }
}

impl Quadric {
    /// `self − o`, term by term (weights too): takes a part that was added
    /// in back out, such as the regularization of a summed quadric.
    pub fn minus(&self, o: &Quadric) -> Quadric {
        *self + o.scaled(-1.0)
    }

    /// The minimizer of E closest to `reference`: `A⁺(−b − A r) + r`, with
    /// the pseudo-inverse of A over its eigenvalues above `tolerance` times
    /// the largest (Lindstrom 2000's truncated solve). Where A constrains
    /// the point (a plane's normal, a crease's two normals, a corner), the
    /// result is the exact minimizer; along the directions A leaves free it
    /// stays at `reference`. `None` when A is zero or not finite.
    ///
    /// This is the limit, as the weight goes to zero, of adding the point
    /// quadric `ε |x − r|²` and solving (Trettner & Kobbelt's regularization
    /// with `r` its center): the same point where the regularized solve is
    /// well defined, without the bias of order ε that pulls a constrained
    /// vertex (a border corner, a point on a plane) off its constraint.
    pub fn pseudo_minimizer(&self, reference: DVec3, tolerance: f64) -> Option<DVec3> {
        self.truncated_step(reference, tolerance).flatten()
    }

    /// `x` moved to the minimizer of E along the directions whose
    /// eigenvalue is above `firm` times the largest, and left alone along
    /// the others: `x + Σ v vᵀ(−b − A x) / λ` over the firm eigenpairs.
    pub fn firm_step(&self, x: DVec3, firm: f64) -> Option<DVec3> {
        self.truncated_step(x, firm)
            .unwrap_or_else(|| x.is_finite().then_some(x))
    }

    /// The step of [`Self::pseudo_minimizer`] and [`Self::firm_step`]: `x`
    /// plus the Newton step restricted to the eigenpairs above `relative`
    /// times the largest eigenvalue. Outer `None` when A is zero or not
    /// finite; inner `None` when the result is not finite.
    fn truncated_step(&self, x: DVec3, relative: f64) -> Option<Option<DVec3>> {
        let a = &self.a;
        // Gradient residual at x: −(A x + b).
        let ax = sym_mul(a, x);
        let g = -(ax + self.b);
        // The cases without the iterative decomposition (a fifth of a
        // large run's time when it was always taken): every direction firm,
        // where the step is the plain Newton step; one firm direction well
        // apart from the others (a smooth surface's normal), whose
        // eigenvector the other two eigenvalues, at most `relative` of it,
        // leave well defined; one free direction, projected out. Jacobi
        // rotations remain for what is left: large negative eigenvalues of
        // a quadric rounding made indefinite.
        let [l0, l1, l2] = symmetric_eigenvalues(*a);
        let largest = l0.abs().max(l2.abs());
        if !(largest > 0.0 && largest.is_finite()) {
            return None;
        }
        let tau = relative * largest;
        if l2 > tau {
            if let Some(d) = solve_symmetric(*a, g) {
                let y = x + d;
                return Some(y.is_finite().then_some(y));
            }
        } else if l0 > tau && l1 <= tau && l1.abs() <= tau && l2.abs() <= tau {
            if let Some(v) = eigenvector_of_separated(*a, l0) {
                let y = x + v * (v.dot(g) / l0);
                return Some(y.is_finite().then_some(y));
            }
        } else if l1 > tau && l2.abs() <= tau {
            // Two firm directions (a crease, a border line): drop the free
            // one's component and solve with it deflated up to l0, which
            // leaves the firm eigenpairs as they are.
            // The closed-form eigenvalue loses digits when l1 is close;
            // its Rayleigh quotient, exact to second order, recovers them.
            let refined = eigenvector_of_separated(*a, l2)
                .and_then(|v| eigenvector_of_separated(*a, rayleigh(a, v)));
            if let Some(v) = refined {
                let h = g - v * v.dot(g);
                let mut b = *a;
                for (k, (r, c)) in [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]
                    .into_iter()
                    .enumerate()
                {
                    b[k] += l0 * v[r] * v[c];
                }
                if let Some(d) = solve_symmetric(b, h) {
                    let d = d - v * v.dot(d);
                    let y = x + d;
                    return Some(y.is_finite().then_some(y));
                }
            }
        }
        let (values, vectors) = symmetric_eigen(self.a);
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !(largest > 0.0 && largest.is_finite()) {
            return None;
        }
        let mut y = x;
        for (l, v) in values.iter().zip(vectors) {
            if *l > relative * largest {
                y += v * (v.dot(g) / l);
            }
        }
        Some(y.is_finite().then_some(y))
    }
}

/// Eigenvalues of the symmetric 3×3 matrix given by its upper triangle, in
/// decreasing order, in closed form (Smith 1961: the trigonometric solution
/// of the characteristic cubic of the shifted, scaled matrix). Accurate to
/// rounding relative to the largest; close eigenvalues lose digits, which
/// is why [`symmetric_eigen`] stays the reference where they matter.
fn symmetric_eigenvalues(u: [f64; 6]) -> [f64; 3] {
    let [xx, xy, xz, yy, yz, zz] = u;
    let off = xy * xy + xz * xz + yz * yz;
    if off == 0.0 {
        let mut d = [xx, yy, zz];
        d.sort_by(|a, b| b.total_cmp(a));
        return d;
    }
    let q = (xx + yy + zz) / 3.0;
    let (dx, dy, dz) = (xx - q, yy - q, zz - q);
    let p2 = dx * dx + dy * dy + dz * dz + 2.0 * off;
    let p = (p2 / 6.0).sqrt();
    // det((A − qI) / p) / 2, clamped into acos's domain.
    let det = dx * (dy * dz - yz * yz) - xy * (xy * dz - yz * xz) + xz * (xy * yz - dy * xz);
    let r = (det / (2.0 * p * p * p)).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let l0 = q + 2.0 * p * phi.cos();
    let l2 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let l1 = 3.0 * q - l0 - l2;
    [l0, l1, l2]
}

/// The solution of `A d = g` for the symmetric A given by its upper
/// triangle, by cofactors; `None` when A is singular.
fn solve_symmetric(u: [f64; 6], g: DVec3) -> Option<DVec3> {
    let [xx, xy, xz, yy, yz, zz] = u;
    let c00 = yy * zz - yz * yz;
    let c01 = xz * yz - xy * zz;
    let c02 = xy * yz - xz * yy;
    let det = xx * c00 + xy * c01 + xz * c02;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let c11 = xx * zz - xz * xz;
    let c12 = xy * xz - xx * yz;
    let c22 = xx * yy - xy * xy;
    let inv = 1.0 / det;
    Some(DVec3::new(
        (c00 * g.x + c01 * g.y + c02 * g.z) * inv,
        (c01 * g.x + c11 * g.y + c12 * g.z) * inv,
        (c02 * g.x + c12 * g.y + c22 * g.z) * inv,
    ))
}

/// `vᵀ A v` for a unit `v`: the eigenvalue `v` best stands for.
fn rayleigh(a: &[f64; 6], v: DVec3) -> f64 {
    v.dot(sym_mul(a, v))
}

/// `A x` for the symmetric 3×3 matrix given by its upper triangle (xx, xy,
/// xz, yy, yz, zz).
#[inline]
pub(crate) fn sym_mul(a: &[f64; 6], x: DVec3) -> DVec3 {
    DVec3::new(
        a[0] * x.x + a[1] * x.y + a[2] * x.z,
        a[1] * x.x + a[3] * x.y + a[4] * x.z,
        a[2] * x.x + a[4] * x.y + a[5] * x.z,
    )
}

/// The unit eigenvector of eigenvalue `l` of the symmetric matrix given by
/// its upper triangle, when `l` is simple and well apart from the others:
/// the longest cross product of two rows of `A − l I`, which spans its
/// null space. `None` when every cross product vanishes.
fn eigenvector_of_separated(u: [f64; 6], l: f64) -> Option<DVec3> {
    let [xx, xy, xz, yy, yz, zz] = u;
    let r0 = DVec3::new(xx - l, xy, xz);
    let r1 = DVec3::new(xy, yy - l, yz);
    let r2 = DVec3::new(xz, yz, zz - l);
    let candidates = [r0.cross(r1), r0.cross(r2), r1.cross(r2)];
    let best = candidates
        .into_iter()
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))?;
    let len = best.length();
    (len > 0.0 && len.is_finite()).then(|| best / len)
}

/// Eigenvalues and unit eigenvectors of the symmetric 3×3 matrix given by
/// its upper triangle (xx, xy, xz, yy, yz, zz), by cyclic Jacobi rotations:
/// a handful of sweeps reach f64 precision on 3×3 matrices, and unlike a
/// closed-form cubic it stays accurate for repeated and tiny eigenvalues,
/// which are the cases the truncated solve is for.
fn symmetric_eigen(u: [f64; 6]) -> ([f64; 3], [DVec3; 3]) {
    let mut m = [[u[0], u[1], u[2]], [u[1], u[3], u[4]], [u[2], u[4], u[5]]];
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..16 {
        let off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        let diag = m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2];
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            // The rotation that zeroes m[p][q] (Golub & Van Loan, Alg. 8.4.1).
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in m.iter_mut() {
                let (mkp, mkq) = (row[p], row[q]);
                row[p] = c * mkp - s * mkq;
                row[q] = s * mkp + c * mkq;
            }
            let (rp, rq) = (m[p], m[q]);
            for k in 0..3 {
                m[p][k] = c * rp[k] - s * rq[k];
                m[q][k] = s * rp[k] + c * rq[k];
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let col = |k: usize| DVec3::new(v[0][k], v[1][k], v[2][k]);
    ([m[0][0], m[1][1], m[2][2]], [col(0), col(1), col(2)])
}

impl std::ops::Add for Quadric {
    type Output = Quadric;
    #[inline]
    fn add(self, o: Quadric) -> Quadric {
        let mut a = self.a;
        for (x, y) in a.iter_mut().zip(o.a) {
            *x += y;
        }
        Quadric {
            a,
            b: self.b + o.b,
            c: self.c + o.c,
            weight: self.weight + o.weight,
        }
    }
}

impl std::ops::AddAssign for Quadric {
    #[inline]
    fn add_assign(&mut self, o: Quadric) {
        *self = *self + o;
    }
}

/// Where the collapse of an edge puts the new vertex, and at what error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The new position.
    pub position: DVec3,
    /// `E(position)`.
    pub error: f64,
    /// True when the quadric's minimizer was used; false when the solve was
    /// singular or unsafe and the best of the endpoints and the midpoint was
    /// taken instead.
    pub optimal: bool,
}

/// Places the vertex that replaces edge `(p, q)` under quadric `e`: the
/// minimizer of `e` when it is well defined, not farther from the edge
/// than `reach` times its length (a nearly singular solve can land far
/// away; `reach` is large enough for virtual edges between separate parts),
/// and no worse than the candidates below; otherwise the best of `p`, `q`
/// and their midpoint (CGAL's and Garland–Heckbert's fallback).
pub fn place(e: &Quadric, p: DVec3, q: DVec3, reach: f64) -> Placement {
    let mid = 0.5 * (p + q);
    if let Some(x) = e.minimizer() {
        let len = (q - p).length();
        if x.distance(mid) <= reach * len.max(f64::MIN_POSITIVE) {
            let err = e.eval(x);
            // The minimizer of a positive semi-definite quadric is no worse
            // than any candidate below; only a numerically broken solve is.
            if err.is_finite() && err <= e.eval(mid) {
                return Placement {
                    position: x,
                    error: err.max(0.0),
                    optimal: true,
                };
            }
        }
    }
    let mut best = Placement {
        position: p,
        error: e.eval(p),
        optimal: false,
    };
    for c in [q, mid] {
        let err = e.eval(c);
        if err < best.error {
            best = Placement {
                position: c,
                error: err,
                optimal: false,
            };
        }
    }
    best.error = best.error.max(0.0);
    best
}

/// Relative size under which an eigenvalue of a quadric counts as zero in
/// [`place_exact`] when the regularized solve fails: the scale of the
/// regularization the engine adds (`Metric::regularization`, 1e-4 of the
/// plane weight), so that the directions that term steadies stay free.
pub const FREE_DIRECTION: f64 = 1e-4;

/// Relative size above which an eigenvalue marks a direction the planes
/// hold firmly (a face's normal, a border's or crease's plane): there the
/// regularization's pull, 1e-4 of the plane weight, is pure bias, and
/// [`place_exact`] takes it back out. Below it the regularized solve's soft
/// choice stands, which on curved surfaces keeps vertices near the input
/// (a hard solve along weak directions lets them slide: +3% Chamfer on the
/// quad corpus at 10%).
pub const FIRM_DIRECTION: f64 = 1e-2;

/// Like [`place`], but exact along the directions the quadric without its
/// regularization part `reg` holds firmly (eigenvalues above
/// `FIRM_DIRECTION` of the largest): the regularized minimizer, then one
/// Newton step of `e − reg` restricted to those directions. A vertex held
/// by constraints (a plane, a border line, a corner) lands exactly on them,
/// which the regularized solve misses by about `reg / constraint` times the
/// distance to the regularization's center; elsewhere the two agree. When
/// the regularized solve is singular, the truncated pseudo-inverse around
/// the center of `reg` (see [`Quadric::pseudo_minimizer`]). Same fallback
/// as [`place`].
pub fn place_exact(e: &Quadric, reg: &Quadric, p: DVec3, q: DVec3, reach: f64) -> Placement {
    let mid = 0.5 * (p + q);
    let plain = e.minus(reg);
    let solved = match e.minimizer() {
        Some(x) => plain.firm_step(x, FIRM_DIRECTION),
        None => {
            let center = if reg.a[0] > 0.0 {
                -reg.b / reg.a[0]
            } else {
                mid
            };
            plain.pseudo_minimizer(center, FREE_DIRECTION)
        }
    };
    if let Some(x) = solved {
        let len = (q - p).length();
        if x.distance(mid) <= reach * len.max(f64::MIN_POSITIVE) {
            let err = e.eval(x);
            if err.is_finite() && err <= e.eval(mid) {
                return Placement {
                    position: x,
                    error: err.max(0.0),
                    optimal: true,
                };
            }
        }
    }
    place(e, p, q, reach)
}

/// Places a collapse's vertex by the planes alone (`e` minus the
/// regularization `reg` it includes) wherever they determine a point
/// within `reach` edge lengths of the edge's midpoint, as Garland &
/// Heckbert do, and by [`place_exact`] where they do not. The
/// returned error is the planes' alone (see
/// [`crate::Metric::regularized_choice`]).
pub fn place_by_planes(e: &Quadric, reg: &Quadric, p: DVec3, q: DVec3, reach: f64) -> Placement {
    let plain = e.minus(reg);
    let mid = 0.5 * (p + q);
    // As in `place`: a point far beyond the edge comes from a nearly
    // singular solve (a straight border's planes and its memoryless area
    // term leave one direction almost free), whose error, evaluated there,
    // is lost to cancellation; and only a numerically broken solve is
    // worse than the midpoint.
    let reach = reach * (q - p).length().max(f64::MIN_POSITIVE);
    if let Some(x) = plain.minimizer().filter(|x| x.distance(mid) <= reach) {
        let err = plain.eval(x);
        if err.is_finite() && err <= plain.eval(mid) {
            return Placement {
                position: x,
                error: err.max(0.0),
                optimal: true,
            };
        }
    }
    let pl = place_exact(e, reg, p, q, reach);
    Placement {
        error: plain.eval(pl.position).max(0.0),
        ..pl
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn placing_by_planes_ignores_the_regularization_where_the_planes_decide() {
        // Planes x = 1 and y = 2 (weight 1) and a faint z = 3 (weight 1e-6),
        // plus the regularization 1e-4·|x|² toward the origin.
        let reg = Quadric::point(DVec3::ZERO, 1e-4);
        let e = Quadric::plane(DVec3::X, DVec3::new(1.0, 0.0, 0.0), 1.0)
            + Quadric::plane(DVec3::Y, DVec3::new(0.0, 2.0, 0.0), 1.0)
            + Quadric::plane(DVec3::Z, DVec3::new(0.0, 0.0, 3.0), 1e-6)
            + reg;
        let (p, q) = (DVec3::ZERO, DVec3::new(2.0, 4.0, 6.0));
        let by_planes = place_by_planes(&e, &reg, p, q, 4.0);
        // The planes meet at (1, 2, 3), where their error is 0.
        assert!(by_planes.position.distance(DVec3::new(1.0, 2.0, 3.0)) < 1e-9);
        assert!(by_planes.error < 1e-15);
        assert!(by_planes.optimal);
        // The regularized choice keeps the faint direction near the
        // origin: z = 3e-6 / (1e-6 + 1e-4) ≈ 0.0297.
        let soft = place_exact(&e, &reg, p, q, 4.0);
        assert!((soft.position.z - 3e-6 / 1.01e-4).abs() < 1e-6, "{soft:?}");
    }

    #[test]
    fn placing_by_planes_distrusts_a_minimizer_far_beyond_the_edge() {
        // Planes z = 0 and x = 0 hold a line; a faint y = 100 (weight 1e-9)
        // makes the system solvable with its minimizer a hundred edge
        // lengths away: the regularized solve (centred on the edge) places.
        let reg = Quadric::point(DVec3::new(0.0, 0.5, 0.0), 1e-4);
        let e = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0)
            + Quadric::plane(DVec3::X, DVec3::ZERO, 1.0)
            + Quadric::plane(DVec3::Y, DVec3::new(0.0, 100.0, 0.0), 1e-9)
            + reg;
        let (p, q) = (DVec3::ZERO, DVec3::Y);
        assert!(e.minus(&reg).minimizer().is_some_and(|x| x.y > 99.0));
        let by_planes = place_by_planes(&e, &reg, p, q, 4.0);
        assert!(
            by_planes.position.distance(0.5 * (p + q)) < 1.0,
            "{by_planes:?}"
        );
    }

    #[test]
    fn placing_by_planes_falls_back_to_the_regularized_solve_on_a_flat_star() {
        // One plane z = 0: no point is determined; the regularization
        // (centred at (0.3, 0.4, 0)) decides, and the planes' error there
        // is 0.
        let reg = Quadric::point(DVec3::new(0.3, 0.4, 0.0), 1e-4);
        let e = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0) + reg;
        let (p, q) = (DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.6, 0.8, 0.0));
        let by_planes = place_by_planes(&e, &reg, p, q, 4.0);
        let soft = place_exact(&e, &reg, p, q, 4.0);
        assert_eq!(by_planes.position, soft.position);
        assert!(by_planes.position.distance(DVec3::new(0.3, 0.4, 0.0)) < 1e-9);
        assert!(by_planes.error < 1e-15);
    }

    #[test]
    fn plane_quadric_is_weighted_squared_distance() {
        // Plane z = 2 (normal +z through (5, -1, 2)), weight 3.
        let q = Quadric::plane(DVec3::Z, DVec3::new(5.0, -1.0, 2.0), 3.0);
        // Hand-computed: A = diag(0, 0, 3), b = (0, 0, -6), c = 12.
        assert_eq!(q.a, [0.0, 0.0, 0.0, 0.0, 0.0, 3.0]);
        assert_eq!(q.b, DVec3::new(0.0, 0.0, -6.0));
        assert_eq!(q.c, 12.0);
        // Point (7, 7, 5) is 3 above the plane: 3 · 3² = 27.
        assert!(close(q.eval(DVec3::new(7.0, 7.0, 5.0)), 27.0));
        assert_eq!(q.weight, 3.0);
    }

    #[test]
    fn oblique_plane_quadric_matches_distance() {
        let n = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        let q = Quadric::plane(n, DVec3::new(1.0, 0.0, 0.0), 1.0);
        // x = (1,0,0) + 4n is at distance 4.
        let x = DVec3::new(1.0, 0.0, 0.0) + 4.0 * n;
        assert!(close(q.eval(x), 16.0));
        // A point in the plane: (1,0,0) + (2,-1,0) (orthogonal to n).
        assert!(q.eval(DVec3::new(3.0, -1.0, 0.0)).abs() < 1e-12);
    }

    #[test]
    fn area_quadric_is_twice_squared_triangle_area() {
        // Boundary edge from (0,0,0) to (2,0,0); x = (1, 3, 4): the triangle
        // has base 2 and height 5, area 5, so E = 2 · 25 = 50.
        let q = Quadric::boundary_area(DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        assert!(close(q.eval(DVec3::new(1.0, 3.0, 4.0)), 50.0));
        // Any x on the edge's line sweeps no area.
        assert!(q.eval(DVec3::new(-7.0, 0.0, 0.0)).abs() < 1e-12);
        // Edge not through the origin: a = (1,1,1), b = (1,1,4) (length 3),
        // x = (1, 5, 1) at distance 4 from the line: area 6, E = 72.
        let q = Quadric::boundary_area(DVec3::ONE, DVec3::new(1.0, 1.0, 4.0));
        assert!(close(q.eval(DVec3::new(1.0, 5.0, 1.0)), 72.0));
    }

    #[test]
    fn point_quadric_regularizes_and_pulls_to_point() {
        let q = Quadric::point(DVec3::new(1.0, 2.0, 3.0), 0.5);
        assert!(close(q.eval(DVec3::new(1.0, 2.0, 5.0)), 0.5 * 4.0));
        assert_eq!(q.minimizer(), Some(DVec3::new(1.0, 2.0, 3.0)));
        // Probabilistic form: plane z=0 plus σ² point term at the origin.
        let pq = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0) + Quadric::point(DVec3::ZERO, 1e-4);
        assert!(close(pq.eval(DVec3::new(1.0, 0.0, 2.0)), 4.0 + 1e-4 * 5.0));
    }

    #[test]
    fn three_orthogonal_planes_meet_at_their_corner() {
        let corner = DVec3::new(1.0, -2.0, 0.5);
        let q = Quadric::plane(DVec3::X, corner, 1.0)
            + Quadric::plane(DVec3::Y, corner, 2.0)
            + Quadric::plane(DVec3::Z, corner, 0.25);
        let x = q.minimizer().unwrap();
        assert!(x.distance(corner) < 1e-12);
        assert!(q.eval(x).abs() < 1e-12);
    }

    #[test]
    fn single_plane_is_singular_and_placement_falls_back() {
        let q = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0);
        assert_eq!(q.minimizer(), None);
        // Endpoint p lies in the plane, q one above: p is best.
        let pl = place(
            &q,
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            4.0,
        );
        assert!(!pl.optimal);
        assert_eq!(pl.position, DVec3::ZERO);
        assert_eq!(pl.error, 0.0);
        // Endpoints at heights 1 and -1: the midpoint (height 0) wins.
        let pl = place(
            &q,
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(2.0, 0.0, -1.0),
            4.0,
        );
        assert_eq!(pl.position, DVec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn far_minimizer_is_rejected_for_the_edge_candidates() {
        // Two nearly parallel planes meet far away from the short edge.
        let n1 = DVec3::new(0.0, 1e-3, 1.0).normalize();
        let q = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0)
            + Quadric::plane(n1, DVec3::ZERO, 1.0)
            + Quadric::plane(DVec3::X, DVec3::new(0.0, 0.0, 0.0), 1.0)
            + Quadric::plane(DVec3::Z, DVec3::new(0.0, 0.0, 0.01), 1.0);
        let x = q.minimizer().unwrap();
        let p = DVec3::new(0.0, 0.0, 0.0);
        let r = DVec3::new(0.0, 0.01, 0.0);
        assert!(x.distance(p) > 1.0, "minimizer should be far: {x}");
        let pl = place(&q, p, r, 4.0);
        assert!(!pl.optimal);
        assert!(pl.position.distance(p) < 0.02);
    }

    #[test]
    fn eigen_decomposition_of_a_rotated_diagonal_matrix() {
        // A = R diag(3, 2, 0) Rᵀ with R a rotation by 45° about z:
        // xx = yy = 2.5, xy = 0.5, zz = 0.
        let (values, vectors) = symmetric_eigen([2.5, 0.5, 0.0, 2.5, 0.0, 0.0]);
        let mut pairs: Vec<(f64, DVec3)> = values.into_iter().zip(vectors).collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert!(pairs[0].0.abs() < 1e-15 && close(pairs[1].0, 2.0) && close(pairs[2].0, 3.0));
        assert!((pairs[0].1.z.abs() - 1.0).abs() < 1e-15);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((pairs[2].1.dot(DVec3::new(h, h, 0.0)).abs() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn closed_form_eigenvalues_of_a_rotated_diagonal_matrix() {
        // The same A = R diag(3, 2, 0) Rᵀ, and a diagonal one out of order.
        let l = symmetric_eigenvalues([2.5, 0.5, 0.0, 2.5, 0.0, 0.0]);
        assert!(
            close(l[0], 3.0) && close(l[1], 2.0) && l[2].abs() < 1e-15,
            "{l:?}"
        );
        assert_eq!(
            symmetric_eigenvalues([1.0, 0.0, 0.0, 5.0, 0.0, -2.0]),
            [5.0, 1.0, -2.0]
        );
    }

    /// The truncated step computed only by Jacobi rotations: the reference
    /// the closed-form fast paths must agree with.
    fn jacobi_step(q: &Quadric, x: DVec3, relative: f64) -> DVec3 {
        let (values, vectors) = symmetric_eigen(q.a);
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let a = &q.a;
        let ax = sym_mul(a, x);
        let g = -(ax + q.b);
        let mut y = x;
        for (l, v) in values.iter().zip(vectors) {
            if *l > relative * largest {
                y += v * (v.dot(g) / l);
            }
        }
        y
    }

    #[test]
    fn fast_truncated_steps_agree_with_jacobi_rotations() {
        // Sums of one to four planes with random normals and weights, some
        // nearly parallel (a smooth surface's one-ring), from random
        // points: every path of `truncated_step` against the reference.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut paths = [0usize; 3];
        for case in 0..4000 {
            let planes = 1 + case % 4;
            let spread = [1.0, 0.3, 0.02, 1e-3][(case / 4) % 4];
            let base = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::Z);
            let mut q = Quadric::ZERO;
            for _ in 0..planes {
                let n = (base + spread * DVec3::new(rnd(), rnd(), rnd())).normalize_or(DVec3::X);
                let p = DVec3::new(rnd(), rnd(), rnd());
                q += Quadric::plane(n, p, 0.1 + rnd().abs());
            }
            let x = DVec3::new(rnd(), rnd(), rnd()) * 3.0;
            for relative in [FIRM_DIRECTION, FREE_DIRECTION] {
                let fast = q.truncated_step(x, relative).flatten().unwrap();
                let reference = jacobi_step(&q, x, relative);
                let [l0, l1, l2] = symmetric_eigenvalues(q.a);
                let tau = relative * l0;
                // Near the threshold the two may count a direction
                // differently, both rightly: only compare clear cases.
                let clear = [l0, l1, l2]
                    .iter()
                    .all(|l| (l - tau).abs() > 1e-3 * tau.max(1e-300));
                if !clear {
                    continue;
                }
                paths[[l1 > tau, l2 > tau].iter().filter(|&&f| f).count()] += 1;
                let scale = 1.0 + x.length() + reference.length();
                assert!(
                    fast.distance(reference) <= 1e-8 * scale,
                    "case {case}: {fast} vs {reference}, eigenvalues {:?}",
                    [l0, l1, l2]
                );
            }
        }
        // Every path was taken: one firm direction, two, three.
        assert!(paths.iter().all(|&n| n > 100), "{paths:?}");
    }

    #[test]
    fn pseudo_minimizer_projects_the_reference_onto_the_constraints() {
        // Planes z = 0 and y = 1 leave the line (t, 1, 0) free: the point
        // on it nearest the reference (3, 5, 7) is (3, 1, 0).
        let q =
            Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0) + Quadric::plane(DVec3::Y, DVec3::Y, 2.0);
        let x = q.pseudo_minimizer(DVec3::new(3.0, 5.0, 7.0), 1e-4).unwrap();
        assert!(x.distance(DVec3::new(3.0, 1.0, 0.0)) < 1e-12, "{x}");
        // A plane weighing less than the tolerance counts as absent.
        let weak = q + Quadric::plane(DVec3::X, DVec3::ZERO, 1e-6);
        let x = weak
            .pseudo_minimizer(DVec3::new(3.0, 5.0, 7.0), 1e-4)
            .unwrap();
        assert!(x.distance(DVec3::new(3.0, 1.0, 0.0)) < 1e-12, "{x}");
        // Full rank: the ordinary minimizer, whatever the reference.
        let full = q + Quadric::plane(DVec3::X, DVec3::new(-2.0, 0.0, 0.0), 1.0);
        let x = full
            .pseudo_minimizer(DVec3::new(9.0, 9.0, 9.0), 1e-4)
            .unwrap();
        assert!(x.distance(DVec3::new(-2.0, 1.0, 0.0)) < 1e-12, "{x}");
        assert_eq!(Quadric::ZERO.pseudo_minimizer(DVec3::ZERO, 1e-4), None);
    }

    #[test]
    fn exact_placement_keeps_a_corner_the_regularized_solve_pulls_off() {
        // A corner at the origin (three unit planes) and a regularization
        // of weight 1e-4 centered at (1, 1, 1): the regularized minimizer is
        // (1e-4 / (1 + 1e-4)) · (1, 1, 1), off the corner by ~1.7e-4; the
        // exact placement stays on it.
        let reg = Quadric::point(DVec3::ONE, 1e-4);
        let q = Quadric::plane(DVec3::X, DVec3::ZERO, 1.0)
            + Quadric::plane(DVec3::Y, DVec3::ZERO, 1.0)
            + Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0)
            + reg;
        let (p, r) = (DVec3::ZERO, DVec3::new(0.1, 0.0, 0.0));
        let loose = place(&q, p, r, 4.0);
        let off = 1e-4 / (1.0 + 1e-4);
        assert!(loose.position.distance(DVec3::splat(off)) < 1e-15);
        let exact = place_exact(&q, &reg, p, r, 4.0);
        assert_eq!(exact.position, DVec3::ZERO);
        assert!(exact.optimal);
        // Its error is the regularization's at the corner: 1e-4 · 3.
        assert!(close(exact.error, 3e-4));
    }
}
