//! Survey coordinates: files whose positions lie so far from the origin
//! (UTM northings of 4·10⁶, site grids, ECEF) that 32-bit floats, which
//! the model holds positions in, would round them visibly.
//!
//! Readers of text and 64-bit formats read such positions relative to a
//! point near them, which the scene's first node holds as its translation
//! (the way glTF files of the same sites do it); writers of those formats
//! place them back in f64, so a file read and written again keeps its
//! coordinates to the digits its f32 offsets hold.

use wildlod_mesh::transform::transformed;
use wildlod_mesh::{Mesh, Scene};

/// A point to hold positions relative to, when coordinates within `lo..hi`
/// lie so far from the origin that f32 rounds them by more than a
/// millionth of their extent. The box's centre, rounded to f32 so that the
/// point itself is exact where it is stored (a node's translation).
pub(crate) fn far_origin(lo: [f64; 3], hi: [f64; 3]) -> Option<[f32; 3]> {
    let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    let reach = (0..3)
        .map(|k| lo[k].abs().max(hi[k].abs()))
        .fold(0.0, f64::max);
    // Rounding to f32 errs by up to 2⁻²⁴ of a coordinate's magnitude.
    let rounding = reach * f64::from(f32::EPSILON) / 2.0;
    let far = diagonal.is_finite() && diagonal > 0.0 && rounding > 1e-6 * diagonal;
    far.then(|| std::array::from_fn(|k| (0.5 * (lo[k] + hi[k])) as f32))
}

/// The bounding box of `points`, `None` when there are none.
pub(crate) fn bounds(points: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(lo, hi), p| {
        (
            std::array::from_fn(|k| lo[k].min(p[k])),
            std::array::from_fn(|k| hi[k].max(p[k])),
        )
    }))
}

/// `exact` (positions as the file holds them, in f64) relative to
/// [`far_origin`] of their box, and that origin; when the positions are
/// not far, `declared` (the same positions as the file's own type rounds
/// them to f32) unchanged and `None`.
pub(crate) fn relative(
    exact: &[[f64; 3]],
    declared: Vec<[f32; 3]>,
) -> (Vec<[f32; 3]>, Option<[f32; 3]>) {
    let Some(origin) = bounds(exact).and_then(|(lo, hi)| far_origin(lo, hi)) else {
        return (declared, None);
    };
    let o = origin.map(f64::from);
    let moved = exact
        .iter()
        .map(|p| std::array::from_fn(|k| (p[k] - o[k]) as f32))
        .collect();
    (moved, Some(origin))
}

/// A mesh's positions placed by `matrix` in f64, when its translation
/// lies so far away that f32 would round the placed positions by more
/// than a millionth of the mesh's size (positions a reader made relative
/// to a [`far_origin`], or a glTF node's translation); `None` otherwise,
/// and the usual f32 placement is written.
pub(crate) fn far_placement(mesh: &Mesh, matrix: &[f32; 16]) -> Option<Vec<[f64; 3]>> {
    let reach = matrix[12..15]
        .iter()
        .fold(0.0f64, |a, &t| a.max(f64::from(t).abs()));
    let rounding = reach * f64::from(f32::EPSILON) / 2.0;
    let size = mesh.diagonal();
    if !(size > 0.0 && rounding > 1e-6 * size) {
        return None;
    }
    let m = matrix.map(f64::from);
    Some(
        mesh.positions
            .iter()
            .map(|p| {
                let p = p.map(f64::from);
                // Column-major, affine (as `transformed` places them).
                std::array::from_fn(|r| m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r])
            })
            .collect(),
    )
}

/// Positions of a placed mesh in f64, where [`far_placement`] needs them.
pub(crate) type Exact = Option<Vec<[f64; 3]>>;

/// Every mesh instance of `scene` moved by its world matrix (formats
/// without a scene graph write them so), with its [`far_placement`].
pub(crate) fn world_meshes(scene: &Scene) -> (Vec<Mesh>, Vec<Exact>) {
    scene
        .instances()
        .iter()
        .filter_map(|(m, matrix)| {
            scene
                .meshes
                .get(*m as usize)
                .map(|x| (transformed(x, matrix), far_placement(x, matrix)))
        })
        .unzip()
}

/// Decimals that keep what f32 positions relative to a far point hold on
/// a mesh of diagonal `size` (a step of 2⁻²³ of it), and no more: the
/// digits past them are the sum's rounding.
pub(crate) fn exact_decimals(size: f64) -> usize {
    let step = size * f64::from(f32::EPSILON);
    if step > 0.0 && step.is_finite() {
        (-step.log10()).ceil().clamp(0.0, 17.0) as usize
    } else {
        6
    }
}

/// `x` with `decimals` decimals, trailing zeros (and a bare point) cut.
pub(crate) fn trimmed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_site_in_utm_is_far_and_a_model_at_the_origin_is_not() {
        // 40 m at northing 4e6: f32 steps by 0.25 m there, 6e-3 of 40 m.
        let lo = [5.0e5, 4.0e6, 0.0];
        let hi = [5.0e5 + 40.0, 4.0e6 + 40.0, 10.0];
        assert_eq!(far_origin(lo, hi), Some([500020.0, 4000020.0, 5.0]));
        assert_eq!(far_origin([-1.0; 3], [1.0; 3]), None);
        // 1e6 units wide at 1e6: rounding 0.03 is 3e-8 of the size.
        assert_eq!(far_origin([1.0e6; 3], [2.0e6; 3]), None);
    }

    #[test]
    fn relative_positions_keep_the_decimals_f32_drops() {
        let exact = [[500000.125, 4000000.375, 1.0], [500010.5, 4000010.25, 2.0]];
        let declared = exact.map(|p| p.map(|c| c as f32)).to_vec();
        let (moved, origin) = relative(&exact, declared);
        let o = origin.expect("far");
        for (m, e) in moved.iter().zip(&exact) {
            for k in 0..3 {
                assert_eq!(f64::from(m[k]) + f64::from(o[k]), e[k]);
            }
        }
        let near = [[0.5, 1.0, 2.0]];
        let (same, none) = relative(&near, vec![[0.5, 1.0, 2.0]]);
        assert_eq!((same, none), (vec![[0.5f32, 1.0, 2.0]], None));
    }

    #[test]
    fn decimals_follow_the_mesh_size() {
        // f32 steps 2⁻²³ ≈ 1.2e-7 of a 40 m mesh: 5e-6 m, 6 decimals.
        assert_eq!(exact_decimals(40.0), 6);
        assert_eq!(trimmed(4000000.250000, 6), "4000000.25");
        assert_eq!(trimmed(12.0, 3), "12");
    }
}
