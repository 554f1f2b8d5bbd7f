//! Robust bounds: the box the bulk of a point set spans, with far-away
//! outliers left out and named.
//!
//! Real files carry the odd vertex far from everything else (a terrain with
//! three heights at −1e30, a stray point an exporter wrote at the float
//! limit). A plain bounding box is then set by that one point, and every
//! size taken from it (the unit of reported errors, the simplifier's
//! normalization) makes the rest of the file vanish. [`robust_bounds`] takes
//! the size from the bulk instead.
//!
//! # The rule
//!
//! Over the finite points, per axis: the median `m` and the quantiles
//! `Q(q)` and `Q(1 − q)` (nearest rank; `q` = [`OutlierRule::quantile`],
//! 1/4 by default: the quartiles). The *bulk extent* `D` is the diagonal of
//! the box `[Q(q), Q(1 − q)]`: along every axis the central half of the
//! points lies in it, so up to a quarter of the points beyond either end of
//! an axis can be anywhere without moving it (a breakdown point of 25%). A
//! point is an **outlier** when it lies farther than `k · D` from `m`
//! (Euclidean; `k` = [`OutlierRule::factor`], 100 by default), or when a
//! coordinate is not finite. The robust bounds are the bounding box of the
//! other points.
//!
//! Why `k` = 100: for points spread evenly over a box, `D` is half the box's
//! diagonal and no point lies farther than `D` from the median; over the 40
//! files of the development corpus the farthest vertex lies 2.2 `D` from the
//! median (a figure's outstretched arms). Real assets whose vertices crowd
//! into a small part (a detailed object on a large ground plane, a town
//! under a sky dome) stay well inside 100 `D`, while a vertex far enough
//! away to shrink every error by two orders of magnitude is caught.
//!
//! Where the rule cannot measure a bulk it finds no outlier (other than
//! non-finite points): fewer than [`OutlierRule::min_points`] finite points,
//! or a bulk extent of 0 (half the points on one spot). A point set without
//! outliers gets exactly its plain bounding box, so files without outliers
//! are measured as before.

/// How far from the bulk a point must lie to be an outlier (see the
/// [module docs](self) for the rule and the reasons for the defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlierRule {
    /// Lower quantile `q` of the bulk box per axis (the upper is `1 − q`),
    /// in `(0, 1/2)`. Default 0.25: the quartiles.
    pub quantile: f64,
    /// `k`: a point farther than `k` times the bulk extent from the median
    /// is an outlier. Default 100.
    pub factor: f64,
    /// Below this many finite points no bulk is measured and only
    /// non-finite points are outliers. Default 4.
    pub min_points: usize,
}

impl Default for OutlierRule {
    fn default() -> Self {
        OutlierRule {
            quantile: 0.25,
            factor: 100.0,
            min_points: 4,
        }
    }
}

/// The result of [`robust_bounds`].
#[derive(Clone, Debug, PartialEq)]
pub struct RobustBounds {
    /// Smallest corner of the box of the points that are not outliers
    /// (`+∞` on every axis when there is none).
    pub min: [f64; 3],
    /// Largest corner of that box (`−∞` when there is none).
    pub max: [f64; 3],
    /// Per-axis median of the finite points (0 when there is none).
    pub median: [f64; 3],
    /// Bulk extent `D`: the diagonal of the per-axis quantile box (0 when
    /// no bulk was measured).
    pub bulk_extent: f64,
    /// Distance from the median beyond which a finite point is an outlier:
    /// `k · D`, or `+∞` when no bulk was measured.
    pub limit: f64,
    /// Indices (in the order the points came) of the outliers, ascending.
    pub outliers: Vec<usize>,
    /// Number of points examined.
    pub points: usize,
}

impl RobustBounds {
    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }

    /// Length of the box's diagonal (0 when empty).
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        (0..3)
            .map(|k| (self.max[k] - self.min[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// True when `p` is an outlier by the rule these bounds were measured
    /// with: not finite, or farther than [`RobustBounds::limit`] from the
    /// median. Classifies points of another set (a simplified copy) the
    /// same way as this one's.
    pub fn is_outlier(&self, p: [f64; 3]) -> bool {
        if !p.iter().all(|c| c.is_finite()) {
            return true;
        }
        // Squares of coordinates near the f64 limit overflow to +∞, which
        // still compares as farther than any finite limit.
        let d2: f64 = (0..3).map(|k| (p[k] - self.median[k]).powi(2)).sum();
        d2.sqrt() > self.limit
    }
}

/// Nearest-rank quantile `q` of `values` (reordered in place; not empty).
fn quantile(values: &mut [f64], q: f64) -> f64 {
    let i = ((values.len() - 1) as f64 * q).round() as usize;
    *values.select_nth_unstable_by(i, f64::total_cmp).1
}

/// The bounds of the bulk of `points` and the outliers left out of them,
/// by the rule of the [module docs](self).
///
/// Takes any iterator of points (map `[f32; 3]` positions with
/// `p.map(f64::from)`); outliers are named by their index in it. Runs in
/// O(n) time (selection, not sorting) with 24 bytes per point.
///
/// ```
/// use wildlod_mesh::bounds::{robust_bounds, OutlierRule};
///
/// // A 10 × 10 grid in the unit square, and one height at −1e30.
/// let mut points: Vec<[f64; 3]> = (0..100)
///     .map(|i| [(i % 10) as f64 / 9.0, (i / 10) as f64 / 9.0, 0.0])
///     .collect();
/// points[42][2] = -1e30;
/// let b = robust_bounds(points.iter().copied(), &OutlierRule::default());
/// assert_eq!(b.outliers, vec![42]);
/// assert!((b.diagonal() - 2f64.sqrt()).abs() < 1e-12);
/// ```
pub fn robust_bounds(
    points: impl IntoIterator<Item = [f64; 3]>,
    rule: &OutlierRule,
) -> RobustBounds {
    let mut columns: [Vec<f64>; 3] = Default::default();
    let mut points_seen = 0usize;
    let mut finite: Vec<bool> = Vec::new();
    for p in points {
        let ok = p.iter().all(|c| c.is_finite());
        finite.push(ok);
        points_seen += 1;
        // Every point keeps its place in the columns (non-finite ones as
        // NaN), so that indices survive the classification below.
        for k in 0..3 {
            columns[k].push(if ok { p[k] } else { f64::NAN });
        }
    }
    let finite_count = finite.iter().filter(|&&f| f).count();
    let mut median = [0.0; 3];
    let mut bulk_extent = 0.0;
    if finite_count > 0 {
        let mut scratch: Vec<f64> = Vec::with_capacity(finite_count);
        let mut extent2 = 0.0;
        let q = rule.quantile.clamp(0.0, 0.5);
        for k in 0..3 {
            scratch.clear();
            scratch.extend(
                columns[k]
                    .iter()
                    .zip(&finite)
                    .filter(|(_, &f)| f)
                    .map(|(&c, _)| c),
            );
            median[k] = quantile(&mut scratch, 0.5);
            let lo = quantile(&mut scratch, q);
            let hi = quantile(&mut scratch, 1.0 - q);
            extent2 += (hi - lo) * (hi - lo);
        }
        bulk_extent = extent2.sqrt();
    }
    let measured = finite_count >= rule.min_points && bulk_extent > 0.0;
    let limit = if measured {
        rule.factor * bulk_extent
    } else {
        bulk_extent = 0.0;
        f64::INFINITY
    };
    let mut out = RobustBounds {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
        median,
        bulk_extent,
        limit,
        outliers: Vec::new(),
        points: points_seen,
    };
    let [xs, ys, zs] = &columns;
    for (i, ((&x, &y), &z)) in xs.iter().zip(ys).zip(zs).enumerate() {
        let p = [x, y, z];
        if out.is_outlier(p) {
            out.outliers.push(i);
            continue;
        }
        for ((lo, hi), c) in out.min.iter_mut().zip(&mut out.max).zip(p) {
            *lo = lo.min(c);
            *hi = hi.max(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rule() -> OutlierRule {
        OutlierRule::default()
    }

    /// An `n × n` heightfield over the unit square, `z = h(x, y)`.
    fn heightfield(n: usize, h: impl Fn(f64, f64) -> f64) -> Vec<[f64; 3]> {
        (0..n * n)
            .map(|i| {
                let (x, y) = (
                    (i % n) as f64 / (n - 1) as f64,
                    (i / n) as f64 / (n - 1) as f64,
                );
                [x, y, h(x, y)]
            })
            .collect()
    }

    #[test]
    fn without_outliers_the_bounds_are_the_plain_box() {
        let pts = heightfield(20, |x, y| 0.3 * (6.0 * x).sin() * y);
        let b = robust_bounds(pts.iter().copied(), &rule());
        assert!(b.outliers.is_empty());
        for k in 0..3 {
            let lo = pts.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
            let hi = pts.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
            assert_eq!((b.min[k], b.max[k]), (lo, hi), "axis {k}");
        }
        assert_eq!(b.points, 400);
    }

    #[test]
    fn quartiles_and_median_are_hand_computed_on_a_small_set() {
        // x takes 0, 1, …, 8 (nine points), y = 2x, z = 0. Nearest rank:
        // the median is element 4 (x = 4), the quartiles elements 2 and 6
        // (x = 2 and 6). D = √(4² + 8²) = √80; k · D ≈ 894.4.
        let mut pts: Vec<[f64; 3]> = (0..9).map(|i| [i as f64, 2.0 * i as f64, 0.0]).collect();
        let b = robust_bounds(pts.iter().copied(), &rule());
        assert_eq!(b.median, [4.0, 8.0, 0.0]);
        assert!((b.bulk_extent - 80f64.sqrt()).abs() < 1e-12);
        assert!((b.limit - 100.0 * 80f64.sqrt()).abs() < 1e-9);
        // Moving the last point to just inside and just beyond the limit
        // (measured from the median, along z) decides it; the quartiles
        // do not move since the point stays the largest in x and y.
        pts[8] = [8.0, 16.0, 0.0];
        let reach = |z: f64| ((8.0f64 - 4.0).powi(2) + (16.0f64 - 8.0).powi(2) + z * z).sqrt();
        let z_at_limit = (b.limit.powi(2) - 80.0).sqrt();
        assert!((reach(z_at_limit) - b.limit).abs() < 1e-9);
        pts[8][2] = 0.999 * z_at_limit;
        assert!(robust_bounds(pts.iter().copied(), &rule())
            .outliers
            .is_empty());
        pts[8][2] = 1.001 * z_at_limit;
        assert_eq!(
            robust_bounds(pts.iter().copied(), &rule()).outliers,
            vec![8]
        );
    }

    #[test]
    fn three_heights_at_minus_1e30_are_named_and_left_out() {
        let mut pts = heightfield(33, |x, y| 0.1 * (5.0 * x).cos() + 0.05 * y);
        let clean = robust_bounds(pts.iter().copied(), &rule());
        for &i in &[5usize, 400, 1000] {
            pts[i][2] = -1e30;
        }
        let b = robust_bounds(pts.iter().copied(), &rule());
        assert_eq!(b.outliers, vec![5, 400, 1000]);
        // The remaining points still reach the clean box's corners (the
        // moved ones are not on its boundary in z), so the box is the same.
        assert_eq!((b.min, b.max), (clean.min, clean.max));
        assert!(b.diagonal() < 2.0 && b.diagonal() > 1.4);
        assert!(b.is_outlier([0.5, 0.5, -1e30]));
        assert!(!b.is_outlier([0.5, 0.5, 0.0]));
    }

    #[test]
    fn flat_sets_and_far_but_plausible_parts_are_no_outliers() {
        // A flat grid: z has no extent, but the bulk extent is the whole
        // diagonal of the quartile box, so a small height is no outlier.
        let mut pts = heightfield(10, |_, _| 0.0);
        pts[3][2] = 0.5;
        assert!(robust_bounds(pts.iter().copied(), &rule())
            .outliers
            .is_empty());
        // A dense object (900 points in a 0.1 cube) on a ground quad 20
        // times its size: the quad's corners stay in.
        let mut scene: Vec<[f64; 3]> = (0..900)
            .map(|i| {
                let (a, b, c) = (i % 10, (i / 10) % 10, i / 100);
                [a as f64 / 90.0, b as f64 / 90.0, c as f64 / 90.0]
            })
            .collect();
        scene.extend([
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ]);
        let b = robust_bounds(scene.iter().copied(), &rule());
        assert!(b.outliers.is_empty(), "{:?}", b.outliers);
        assert_eq!((b.min[0], b.max[0]), (-1.0, 1.0));
    }

    #[test]
    fn non_finite_points_are_outliers_and_do_not_move_the_bulk() {
        let mut pts = heightfield(5, |x, _| x);
        pts[7] = [f64::NAN, 0.0, 0.0];
        pts[9] = [0.0, f64::INFINITY, 0.0];
        let b = robust_bounds(pts.iter().copied(), &rule());
        assert_eq!(b.outliers, vec![7, 9]);
        assert_eq!((b.min, b.max), ([0.0; 3], [1.0; 3]));
        // Coordinates near the f64 limit: their squares overflow, and they
        // are still outliers rather than NaN comparisons.
        pts[7] = [1e300, 1e300, 0.0];
        pts[9] = [0.5, 0.5, f64::MAX];
        assert_eq!(
            robust_bounds(pts.iter().copied(), &rule()).outliers,
            vec![7, 9]
        );
    }

    #[test]
    fn too_few_points_or_no_bulk_extent_find_no_finite_outlier() {
        let three = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1e30, 0.0]];
        let b = robust_bounds(three, &rule());
        assert!(b.outliers.is_empty());
        assert_eq!(b.limit, f64::INFINITY);
        assert_eq!(b.max[1], 1e30);
        // Nine points on one spot and one far away: the bulk has no size
        // to measure the distance with.
        let mut spot = vec![[1.0, 2.0, 3.0]; 9];
        spot.push([1e30, 0.0, 0.0]);
        let b = robust_bounds(spot, &rule());
        assert!(b.outliers.is_empty());
        assert_eq!(b.bulk_extent, 0.0);
        // Nothing at all.
        let b = robust_bounds(std::iter::empty(), &rule());
        assert!(b.is_empty());
        assert_eq!(b.diagonal(), 0.0);
        assert_eq!(b.points, 0);
    }

    #[test]
    fn a_quarter_of_the_points_far_away_does_not_move_the_bulk() {
        // 3 of every 13 points (23%) at 1e20 along x: the quartile box is
        // still the grid's, so all of them are outliers.
        let mut pts = heightfield(26, |x, y| x * y);
        let mut far = Vec::new();
        for (i, p) in pts.iter_mut().enumerate() {
            if i % 13 < 3 {
                p[0] = 1e20;
                far.push(i);
            }
        }
        let b = robust_bounds(pts.iter().copied(), &rule());
        assert_eq!(b.outliers, far);
        assert!(b.max[0] <= 1.0);
    }
}
