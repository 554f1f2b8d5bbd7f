//! The linear functional of an attribute over one face (Hoppe 1999 §3;
//! Knodt 2024 Eq. 7 for polygons): `s(p) = g·p + d` with the gradient `g`
//! in the face's plane (`g·n = 0`), fitted to the corner values by least
//! squares. On a triangle the fit interpolates its three corners exactly;
//! on a planar polygon carrying a linear field it reproduces the field.
//!
//! Knodt writes `g·n = 0` as one more least-squares row; here it is imposed
//! exactly by fitting in a basis of the plane, which is the same on
//! triangles and keeps the gradient tangent on warped polygons too.

use glam::DVec3;

/// A face's plane basis, used to fit every attribute of the face.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceFrame {
    centroid: DVec3,
    t1: DVec3,
    t2: DVec3,
    /// Inverse of the 2×2 normal matrix `[Σuu Σuw; Σuw Σww]` (row-major).
    inv: [f64; 4],
}

impl FaceFrame {
    /// The frame of a face with corners `p` and unit normal `n`; `None` when
    /// the corners do not span the plane (a degenerate face), where no
    /// gradient is defined.
    pub fn new(p: &[DVec3], n: DVec3) -> Option<FaceFrame> {
        if p.len() < 3 || !n.is_finite() {
            return None;
        }
        let centroid = p.iter().copied().sum::<DVec3>() / p.len() as f64;
        let t1 = n.any_orthonormal_vector();
        let t2 = n.cross(t1);
        let (mut uu, mut uw, mut ww) = (0.0, 0.0, 0.0);
        for &q in p {
            let r = q - centroid;
            let (u, w) = (r.dot(t1), r.dot(t2));
            uu += u * u;
            uw += u * w;
            ww += w * w;
        }
        let det = uu * ww - uw * uw;
        // Relative test: the corners must not be (nearly) collinear.
        let scale = (uu + ww) * (uu + ww);
        if det.is_nan() || det <= 1e-12 * scale || !det.is_finite() {
            return None;
        }
        let k = 1.0 / det;
        Some(FaceFrame {
            centroid,
            t1,
            t2,
            inv: [ww * k, -uw * k, -uw * k, uu * k],
        })
    }

    /// Fits one scalar attribute with values `s` (one per corner, in the
    /// order of the corners given to [`FaceFrame::new`]): returns `(g, d)`.
    pub fn fit(&self, p: &[DVec3], s: impl Iterator<Item = f64>) -> (DVec3, f64) {
        let (mut us, mut ws, mut sum, mut n) = (0.0, 0.0, 0.0, 0.0);
        for (&q, v) in p.iter().zip(s) {
            let r = q - self.centroid;
            us += r.dot(self.t1) * v;
            ws += r.dot(self.t2) * v;
            sum += v;
            n += 1.0;
        }
        // Centered coordinates: the constant is the mean, the slopes solve
        // the 2×2 normal equations.
        let a = self.inv[0] * us + self.inv[1] * ws;
        let b = self.inv[2] * us + self.inv[3] * ws;
        let g = a * self.t1 + b * self.t2;
        let mean = sum / n;
        (g, mean - g.dot(self.centroid))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn triangle_fit_interpolates_its_corners() {
        // Triangle (0,0,0), (2,0,0), (0,1,0) in z = 0 with values 1, 5, -1:
        // s = 1 + 2x − 2y, so g = (2, −2, 0), d = 1 (hand-computed).
        let p = [DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::Y];
        let f = FaceFrame::new(&p, DVec3::Z).unwrap();
        let (g, d) = f.fit(&p, [1.0, 5.0, -1.0].into_iter());
        assert!(g.distance(DVec3::new(2.0, -2.0, 0.0)) < 1e-12, "{g}");
        assert!(close(d, 1.0));
    }

    #[test]
    fn gradient_stays_in_the_face_plane() {
        // Tilted triangle in the plane x + y + z = 1; values are x.
        let p = [DVec3::X, DVec3::Y, DVec3::Z];
        let n = DVec3::ONE.normalize();
        let f = FaceFrame::new(&p, n).unwrap();
        let (g, d) = f.fit(&p, p.iter().map(|q| q.x));
        assert!(g.dot(n).abs() < 1e-12);
        // It reproduces the corners: g·p + d = x at each.
        for q in p {
            assert!(close(g.dot(q) + d, q.x));
        }
        // Hand-computed: g = projection of (1,0,0) on the plane
        // = (2/3, −1/3, −1/3), and d = 1 − g·(1,0,0) = 1/3.
        assert!(g.distance(DVec3::new(2.0, -1.0, -1.0) / 3.0) < 1e-12);
        assert!(close(d, 1.0 / 3.0));
    }

    #[test]
    fn quad_fit_is_least_squares() {
        // Unit square in z = 0; values 0, 1, 1, 0 at (0,0), (1,0), (1,1),
        // (0,1) are the field s = x: reproduced exactly.
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let f = FaceFrame::new(&p, DVec3::Z).unwrap();
        let (g, d) = f.fit(&p, [0.0, 1.0, 1.0, 0.0].into_iter());
        assert!(g.distance(DVec3::X) < 1e-12 && close(d, 0.0));
        // Values 0, 0, 1, 0 fit no plane; least squares (hand-computed on
        // the centered square, u, w = ±1/2): slopes Σu·s / Σu² = (1/2)/1
        // = 1/2 in x and y, mean 1/4, so s = −1/4 + x/2 + y/2.
        let (g, d) = f.fit(&p, [0.0, 0.0, 1.0, 0.0].into_iter());
        assert!(g.distance(DVec3::new(0.5, 0.5, 0.0)) < 1e-12, "{g}");
        assert!(close(d, -0.25), "{d}");
    }

    #[test]
    fn collinear_corners_have_no_frame() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0)];
        assert!(FaceFrame::new(&p, DVec3::Z).is_none());
    }
}
