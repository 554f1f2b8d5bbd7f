//! A node's transform as translation, rotation and scale (glTF 2.0 §3.5.3)
//! and as a column-major matrix, both ways: reading turns a node's TRS
//! into the scene's matrix, writing turns a matrix back into TRS where
//! glTF asks for it (animated nodes).

use wildlod_mesh::IDENTITY;

/// The column-major matrix T·R·S of a node's translation, rotation
/// (quaternion x, y, z, w) and scale.
pub(crate) fn trs_matrix(t: [f32; 3], r: [f32; 4], s: [f32; 3]) -> [f32; 16] {
    if t == [0.0; 3] && r == [0.0, 0.0, 0.0, 1.0] && s == [1.0; 3] {
        return IDENTITY;
    }
    let [x, y, z, w] = r.map(|c| c as f64);
    let cols = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y + z * w),
            2.0 * (x * z - y * w),
        ],
        [
            2.0 * (x * y - z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z + x * w),
        ],
        [
            2.0 * (x * z + y * w),
            2.0 * (y * z - x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let mut m = IDENTITY;
    for c in 0..3 {
        for r in 0..3 {
            m[c * 4 + r] = (cols[c][r] * s[c] as f64) as f32;
        }
    }
    m[12..15].copy_from_slice(&t);
    m
}

/// Translation, rotation (unit quaternion x, y, z, w) and scale of a
/// column-major matrix T·R·S; a negative determinant goes into the x
/// scale. A matrix with shear has no such form: the result is the nearest
/// one this method finds, and `exact` says whether it rebuilds the matrix.
pub(crate) struct Trs {
    pub translation: [f32; 3],
    pub rotation: [f32; 4],
    pub scale: [f32; 3],
    pub exact: bool,
}

/// See [`Trs`].
pub(crate) fn decompose(m: &[f32; 16]) -> Trs {
    let col = |c: usize| [0, 1, 2].map(|r| m[c * 4 + r] as f64);
    let mut cols = [col(0), col(1), col(2)];
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let mut scale = cols.map(len);
    let det = cols[0][0] * (cols[1][1] * cols[2][2] - cols[2][1] * cols[1][2])
        - cols[1][0] * (cols[0][1] * cols[2][2] - cols[2][1] * cols[0][2])
        + cols[2][0] * (cols[0][1] * cols[1][2] - cols[1][1] * cols[0][2]);
    if det < 0.0 {
        scale[0] = -scale[0];
    }
    for (c, s) in cols.iter_mut().zip(scale) {
        if s != 0.0 {
            *c = c.map(|x| x / s);
        }
    }
    // The rotation matrix R[r][c] = cols[c][r] to a quaternion
    // (Shepperd's method: divide by the largest of the four candidates).
    let r = |row: usize, c: usize| cols[c][row];
    let trace = r(0, 0) + r(1, 1) + r(2, 2);
    let q = if scale.contains(&0.0) {
        [0.0, 0.0, 0.0, 1.0]
    } else if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            (r(2, 1) - r(1, 2)) / s,
            (r(0, 2) - r(2, 0)) / s,
            (r(1, 0) - r(0, 1)) / s,
            0.25 * s,
        ]
    } else if r(0, 0) > r(1, 1) && r(0, 0) > r(2, 2) {
        let s = (1.0 + r(0, 0) - r(1, 1) - r(2, 2)).sqrt() * 2.0;
        [
            0.25 * s,
            (r(0, 1) + r(1, 0)) / s,
            (r(0, 2) + r(2, 0)) / s,
            (r(2, 1) - r(1, 2)) / s,
        ]
    } else if r(1, 1) > r(2, 2) {
        let s = (1.0 + r(1, 1) - r(0, 0) - r(2, 2)).sqrt() * 2.0;
        [
            (r(0, 1) + r(1, 0)) / s,
            0.25 * s,
            (r(1, 2) + r(2, 1)) / s,
            (r(0, 2) - r(2, 0)) / s,
        ]
    } else {
        let s = (1.0 + r(2, 2) - r(0, 0) - r(1, 1)).sqrt() * 2.0;
        [
            (r(0, 2) + r(2, 0)) / s,
            (r(1, 2) + r(2, 1)) / s,
            0.25 * s,
            (r(1, 0) - r(0, 1)) / s,
        ]
    };
    let n = len([q[0], q[1], q[2]]).hypot(q[3]);
    let rotation = q.map(|x| (x / n) as f32);
    let translation = [m[12], m[13], m[14]];
    let scale = scale.map(|s| s as f32);
    let back = trs_matrix(translation, rotation, scale);
    let exact = back
        .iter()
        .zip(m)
        .all(|(a, b)| (a - b).abs() <= 1e-5 * b.abs().max(1.0));
    Trs {
        translation,
        rotation,
        scale,
        exact,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::transform::apply_point;

    #[test]
    fn trs_applies_scale_then_rotation_then_translation() {
        // 90° about z: x → y.
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let m = trs_matrix([10.0, 0.0, 0.0], [0.0, 0.0, h, h], [2.0, 1.0, 1.0]);
        let p = apply_point(&m, [1.0, 0.0, 0.0]);
        assert!(
            (p[0] - 10.0).abs() < 1e-6 && (p[1] - 2.0).abs() < 1e-6,
            "{p:?}"
        );
        assert_eq!(
            trs_matrix([0.0; 3], [0.0, 0.0, 0.0, 1.0], [1.0; 3]),
            IDENTITY
        );
    }

    #[test]
    fn decompose_recovers_translation_rotation_and_scale() {
        // 90° about z (q = (0, 0, sin 45°, cos 45°)), scale (2, 1, 3),
        // translation (1, 2, 3).
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let m = trs_matrix([1.0, 2.0, 3.0], [0.0, 0.0, h, h], [2.0, 1.0, 3.0]);
        let t = decompose(&m);
        assert!(t.exact);
        assert_eq!(t.translation, [1.0, 2.0, 3.0]);
        for (a, b) in t.rotation.iter().zip([0.0, 0.0, h, h]) {
            assert!((a - b).abs() < 1e-6, "{:?}", t.rotation);
        }
        for (a, b) in t.scale.iter().zip([2.0, 1.0, 3.0]) {
            assert!((a - b).abs() < 1e-6, "{:?}", t.scale);
        }
    }

    #[test]
    fn decompose_of_a_translation_is_exact() {
        let mut m = IDENTITY;
        m[13] = 3.0;
        let t = decompose(&m);
        assert_eq!(t.translation, [0.0, 3.0, 0.0]);
        assert_eq!(t.rotation, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(t.scale, [1.0; 3]);
    }

    #[test]
    fn decompose_flags_a_shear() {
        let mut m = IDENTITY;
        m[4] = 0.5; // column 1 leans along x
        assert!(!decompose(&m).exact);
    }
}
