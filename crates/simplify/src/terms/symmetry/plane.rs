//! The plane of an edge (Alg. 2 lines 4–11) and reflection across it.

use glam::DVec3;

use super::EdgeNormals;

/// Below this length the sum `n(f0) + n(f1)` of an edge's two unit normals
/// has no direction: the two faces fold back onto each other (dihedral
/// angle 180°), and the halfway vector of Alg. 2 line 6 is noise.
const MIN_HALFWAY: f64 = 1e-9;

/// Below this length `n × d` (unit vectors) has no direction: the face
/// normal runs along the edge, i.e. the face is degenerate.
const MIN_SINE: f64 = 1e-9;

/// Shift of the plane-grouping cells, as a fraction of a cell: 2 − φ, far
/// from every fraction with a small denominator, so that no regular value
/// (0, k/10, k/2^m of a cell) lands within rounding of a cell boundary.
const KEY_SHIFT: f64 = 0.381_966_011_250_105_1;

/// `⌊x⌋` as an integer, saturating far away and mapping NaN to 0 (which
/// only makes distant points share a cell; the exact distance test sorts
/// them out). Inline instead of `f64::floor`, which is a libm call on the
/// baseline x86-64 target and took a tenth of the time. Shared by the
/// planes' grouping keys ([`Plane::key`]) and the grid's cells.
pub(super) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// A plane `{x : n·x = c}` with unit normal `n` (Alg. 2's local frame: `x`
/// axis `n⊥`, origin `e0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Plane {
    /// Unit normal `n⊥`.
    pub(super) n: DVec3,
    /// Offset `n⊥ · e0`.
    pub(super) c: f64,
}

impl Plane {
    /// Signed distance `σ(p) = n·p − c` (Alg. 2 line 14, `v_local[0]`).
    pub(super) fn signed_distance(&self, p: DVec3) -> f64 {
        self.n.dot(p) - self.c
    }

    /// The same plane with its orientation fixed: the first component of `n`
    /// with magnitude above 0.55 is made positive. A unit vector always has
    /// one (its largest is ≥ 1/√3 ≈ 0.577), and 0.55 is not a value that
    /// normals of regular models take (0, ½, 1/√2, 0.6, 0.8, …), so nearly
    /// equal planes get the same orientation. Negation is exact, so `σ`
    /// only changes sign and mirror images are bit-identical.
    pub(super) fn canonical(self) -> Self {
        let pick = self
            .n
            .to_array()
            .into_iter()
            .find(|x| x.abs() > 0.55)
            .unwrap_or(1.0);
        if pick < 0.0 {
            Self {
                n: -self.n,
                c: -self.c,
            }
        } else {
            self
        }
    }

    /// Grouping key: the canonical plane quantized to cells of `cell`
    /// (`plane_tolerance · δ`), or its exact bits when `cell` is not a
    /// positive finite number. `+ 0.0` maps −0.0 to +0.0 so that the two
    /// zeros share a key.
    ///
    /// The cells are shifted by [`KEY_SHIFT`] of a cell: unshifted, the
    /// values regular models are made of (0 ± rounding noise in a normal,
    /// offsets 0.1, 0.2, … when `cell` divides them) sit exactly on cell
    /// boundaries, and rounding scatters one plane over two keys.
    pub(super) fn key(&self, cell: f64) -> [u64; 4] {
        let v = [self.n.x, self.n.y, self.n.z, self.c];
        if cell > 0.0 && cell.is_finite() {
            // Saturates far away; far-off planes only share less.
            v.map(|x| floor_i64(x / cell + KEY_SHIFT) as u64)
        } else {
            v.map(|x| (x + 0.0).to_bits())
        }
    }
}

/// The mirror image of `p` (at signed distance `sigma`) across the plane of
/// normal `n`: `p − 2σn`.
pub(super) fn reflect(p: DVec3, sigma: f64, n: DVec3) -> DVec3 {
    p - n * (2.0 * sigma)
}

/// The mirror distance of vertices `a` and `b` (ids, positions, signed
/// distances), computed from the lower id: `|mirror(a) − b|` if `a < b`.
/// Reflection is an isometry, so mathematically either end gives the same
/// value; fixing the end makes it bit-identical for every caller.
pub(super) fn pair_error(a: (u32, DVec3, f64), b: (u32, DVec3, f64), n: DVec3) -> f64 {
    let (lo, hi) = if a.0 < b.0 { (a, b) } else { (b, a) };
    (reflect(lo.1, lo.2, n) - hi.1).length()
}

/// The plane of edge `(p0, p1)` with the given faces (Alg. 2 lines 4–11),
/// or `None` where Alg. 2 gives weight 0 (no face, non-manifold) and where
/// the plane is undefined (zero-length edge, faces folded onto each other,
/// a face normal along the edge, non-finite input).
pub(super) fn edge_plane(p0: DVec3, p1: DVec3, faces: EdgeNormals) -> Option<Plane> {
    let d = p0 - p1;
    let len = d.length();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let d = d / len;
    let axis = match faces {
        EdgeNormals::Manifold(a, b) => {
            // Normalized so that non-unit input normals still give the
            // halfway direction; a zero or non-finite one drops out (the
            // edge then spans the plane of its other face, as a border).
            let h = a.normalize_or_zero() + b.normalize_or_zero();
            let hl = h.length();
            if hl.is_nan() || hl <= MIN_HALFWAY {
                return None;
            }
            h / hl
        }
        EdgeNormals::Border(a) => a.normalize_or_zero(),
        EdgeNormals::NoFace | EdgeNormals::NonManifold => return None,
    };
    let t = axis.cross(d);
    let tl = t.length();
    // A zero or non-finite normal gives tl = 0 or NaN.
    if tl.is_nan() || tl <= MIN_SINE {
        return None;
    }
    let n = t / tl;
    let c = n.dot(p0);
    c.is_finite().then_some(Plane { n, c })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plane formulas of Alg. 2 lines 4–8 on hand-computed cases.
    #[test]
    fn edge_plane_spans_the_edge_and_the_halfway_normal() {
        // Manifold edge along y at x = 1 between two faces facing +z:
        // halfway z, n⊥ = z × (0,−1,0) = (1,0,0), plane x = 1.
        let p = edge_plane(
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            EdgeNormals::Manifold(DVec3::Z, DVec3::Z),
        )
        .unwrap();
        assert_eq!((p.n, p.c), (DVec3::X, 1.0));
        // Ridge of a roof: normals (±1, 0, 1)/√2 sum to √2·z, d = (0, −1, 0),
        // n⊥ = z × (0, −1, 0) = (1, 0, 0): plane x = 0.
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let p = edge_plane(
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
            EdgeNormals::Manifold(DVec3::new(r, 0.0, r), DVec3::new(-r, 0.0, r)),
        )
        .unwrap();
        assert!((p.n - DVec3::X).length() < 1e-15);
        assert!(p.c.abs() < 1e-15);
        // Border edge along y on the face of normal (1, 0, 1)/√2:
        // n⊥ = (r, 0, r) × (0, −1, 0) = (r, 0, −r), through (1, 0, 0).
        let p = edge_plane(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            EdgeNormals::Border(DVec3::new(r, 0.0, r)),
        )
        .unwrap();
        assert!((p.n - DVec3::new(r, 0.0, -r)).length() < 1e-15);
        assert!((p.c - r).abs() < 1e-15);
        // Signed distance and mirror image: (3, 5, 7) is 2 from x = 1 and
        // mirrors to (−1, 5, 7).
        let plane = Plane {
            n: DVec3::X,
            c: 1.0,
        };
        let q = DVec3::new(3.0, 5.0, 7.0);
        assert_eq!(plane.signed_distance(q), 2.0);
        assert_eq!(reflect(q, 2.0, DVec3::X), DVec3::new(-1.0, 5.0, 7.0));
        // Mirror error of (3,5,7) and (−1.3, 5.4, 7): |(−1,5,7) − b| = 0.5,
        // whichever way round the pair is given.
        let a = (0, q, 2.0);
        let b = (1, DVec3::new(-1.3, 5.4, 7.0), -2.3);
        assert!((pair_error(a, b, DVec3::X) - 0.5).abs() < 1e-12);
        assert_eq!(pair_error(a, b, DVec3::X), pair_error(b, a, DVec3::X));
    }

    /// Alg. 2 line 10 and the degenerate cases: no plane, weight 0.
    #[test]
    fn edges_without_a_plane_get_no_plane() {
        let (a, b) = (DVec3::ZERO, DVec3::X);
        assert_eq!(edge_plane(a, b, EdgeNormals::NonManifold), None);
        assert_eq!(edge_plane(a, b, EdgeNormals::NoFace), None);
        // Zero-length edge.
        assert_eq!(edge_plane(a, a, EdgeNormals::Border(DVec3::Z)), None);
        // Faces folded onto each other: no halfway vector.
        assert_eq!(
            edge_plane(a, b, EdgeNormals::Manifold(DVec3::Z, -DVec3::Z)),
            None
        );
        // A face normal along the edge (degenerate face).
        assert_eq!(edge_plane(a, b, EdgeNormals::Border(DVec3::X)), None);
        // Non-finite input.
        assert_eq!(edge_plane(a, b, EdgeNormals::Border(DVec3::NAN)), None);
        assert_eq!(
            edge_plane(a, DVec3::NAN, EdgeNormals::Border(DVec3::Z)),
            None
        );
        assert_eq!(edge_plane(a, b, EdgeNormals::Border(DVec3::ZERO)), None);
        // One unusable normal of two: the plane of the other face.
        assert_eq!(
            edge_plane(a, b, EdgeNormals::Manifold(DVec3::Z, DVec3::NAN)),
            edge_plane(a, b, EdgeNormals::Border(DVec3::Z))
        );
        assert_eq!(
            edge_plane(
                DVec3::splat(f64::MAX),
                DVec3::ZERO,
                EdgeNormals::Border(DVec3::Z)
            ),
            None
        );
        // Classification of face lists.
        assert_eq!(EdgeNormals::from_faces(&[]), EdgeNormals::NoFace);
        assert_eq!(
            EdgeNormals::from_faces(&[DVec3::Z; 3]),
            EdgeNormals::NonManifold
        );
    }
}
