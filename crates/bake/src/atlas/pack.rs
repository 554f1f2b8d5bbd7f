//! Packing charts into one square atlas with gutters.
//!
//! First as rectangles (below), then, where the search is affordable, as
//! shapes at the largest scale that fits (`bitmap.rs`): xatlas-level atlas
//! use (the truck's body at 10%: 55% → 75%).
//!
//! Each chart is turned so that its bounding rectangle is smallest (the
//! best rectangle has a side on the convex hull, so trying the hull's edge
//! directions is exact), then all charts get one common scale, as large as
//! lets their rectangles, plus `padding` texels on two sides, fit into the
//! atlas less `padding` (`rectangle-pack`, a deterministic guillotine
//! packer). Shifting everything by `padding` leaves at least `padding`
//! empty texels between any two charts and along the border.

use std::collections::BTreeMap;

use rectangle_pack::{
    contains_smallest_box, pack_rects, volume_heuristic, GroupedRectsToPlace, RectToInsert,
    TargetBin,
};

use super::bitmap::{pack_shapes, place_point, Spot};
use super::charts::Chart;
use super::{Atlas, AtlasOptions};

/// A chart turned to its smallest bounding rectangle, with its corners
/// relative to the rectangle's lower corner.
struct Placed {
    coords: Vec<[f64; 2]>,
    width: f64,
    height: f64,
}

pub(crate) fn pack_charts(charts: &[Chart], triangle_count: usize, o: &AtlasOptions) -> Atlas {
    let placed: Vec<Placed> = charts.iter().map(|c| turn(&c.coords)).collect();
    let pad = o.padding.min(o.size / 4);
    let room = o.size.saturating_sub(2 * pad).max(1) as f64;
    let area: f64 = placed.iter().map(|p| p.width * p.height).sum();
    let longest = placed
        .iter()
        .map(|p| p.width.max(p.height))
        .fold(0.0, f64::max);
    // Upper bound: the charts' rectangles cannot hold more than the atlas,
    // nor can one chart be longer than it.
    let mut hi = if area > 0.0 {
        (room * room / area).sqrt()
    } else {
        1.0
    };
    if longest > 0.0 {
        hi = hi.min(room / longest);
    }
    let mut scale = hi;
    let mut best: Option<(f64, Vec<[u32; 2]>)> = None;
    // Every chart takes at least one texel and its padding whatever the
    // scale: past the bin's area no scale fits, and trying each would cost
    // seconds on tens of thousands of charts.
    let bin = f64::from(o.size.saturating_sub(pad));
    let least: f64 = placed.iter().map(|_| f64::from(1 + pad).powi(2)).sum();
    if least > bin * bin {
        scale = 0.0;
    }
    // A useful packing has charts of at least as many texels as their
    // padding, so the padding (at least `pad²` per chart) takes at most
    // half the bin.
    if o.useful_only && placed.len() as f64 * f64::from(pad).powi(2) > 0.5 * bin * bin {
        scale = 0.0;
    }
    let mut failed = hi * 1.0001;
    // Shrink until everything fits, then bisect towards the last failure.
    for _ in 0..if scale > 0.0 { 60 } else { 0 } {
        match try_pack(&placed, scale, pad, o.size) {
            Some(at) => {
                best = Some((scale, at));
                break;
            }
            None => {
                failed = scale;
                // Every chart already at its least (one texel): smaller
                // scales pack the same rectangles and fail the same way.
                if scale * longest < 1.0 {
                    break;
                }
                scale *= 0.85;
            }
        }
    }
    if let Some((mut good, _)) = best.as_ref().map(|b| (b.0, ())) {
        for _ in 0..6 {
            let mid = 0.5 * (good + failed);
            match try_pack(&placed, mid, pad, o.size) {
                Some(at) => {
                    good = mid;
                    best = Some((mid, at));
                }
                None => failed = mid,
            }
        }
    }
    let best_found = best.is_some();
    let (mut scale, at) = best.unwrap_or_else(|| (0.0, vec![[pad, pad]; placed.len()]));
    // Then the charts' shapes, which hold the same charts at a larger
    // scale where the rectangles leave room (`bitmap.rs`).
    let mut spots = None;
    // On a grid of `cell`² texels where the texel grid would cost too much.
    let cell = [1u32, 2, 4, 8]
        .into_iter()
        .find(|&c| placed.len() * (o.size / c) as usize <= MAX_SHAPE_WORK);
    if let (true, Some(cell)) = (best_found && !placed.is_empty(), cell) {
        if let Some((s, found)) = pack_shapes_largest(&placed, scale, pad, o.size, cell) {
            scale = s;
            spots = Some(found);
        }
    }
    // Placed is not enough: at a scale where the padding around the charts
    // takes more texels than the charts themselves (tens of thousands of
    // charts squeezed to a texel or two), the atlas holds mostly gutter
    // and no chart keeps its texture.
    let content: f64 = placed
        .iter()
        .map(|p| p.width * p.height * scale * scale)
        .sum();
    let padded: f64 = placed
        .iter()
        .map(|p| {
            let w = (p.width * scale).ceil().max(1.0) + f64::from(pad);
            let h = (p.height * scale).ceil().max(1.0) + f64::from(pad);
            w * h
        })
        .sum();
    let all_placed = best_found || placed.is_empty();
    let fits = all_placed && (placed.is_empty() || content >= padded - content);
    let mut corner_uvs = vec![[0.0f32; 2]; 3 * triangle_count];
    let mut triangle_chart = vec![0u32; triangle_count];
    for (c, (chart, p)) in charts.iter().zip(&placed).enumerate() {
        let (origin, turns) = match &spots {
            Some(spots) => {
                let s: &Spot = &spots[c];
                (s.origin, s.turns)
            }
            None => (at[c], 0),
        };
        for (k, &t) in chart.triangles.iter().enumerate() {
            triangle_chart[t as usize] = c as u32;
            for j in 0..3 {
                let q = place_point(p.coords[3 * k + j], [p.width, p.height], scale, turns);
                corner_uvs[3 * t as usize + j] = [
                    (origin[0] as f64 + q[0]) as f32,
                    (origin[1] as f64 + q[1]) as f32,
                ];
            }
        }
    }
    Atlas {
        size: o.size,
        corner_uvs,
        triangle_chart,
        chart_count: charts.len(),
        texels_per_unit: scale,
        placed: all_placed,
        fits,
    }
}

/// Most charts × grid side packed by shape: the search costs up to a scan
/// of the grid's rows per chart, orientation and trial scale (the sofa's
/// 127 charts in 2048², on a grid of 2² texels: 0.15 s, against 0.6 s and
/// 2 points more atlas use on the texel grid). Larger atlases are packed
/// on a grid of 2², 4² or 8² texels (charts that large lose little to the
/// coarser grid);
/// beyond, the rectangles' packing stays (a noisy scan's thousands of
/// charts are mostly a texel or two anyway).
const MAX_SHAPE_WORK: usize = 150_000;

/// [`pack_shapes`] on a grid of `cell` × `cell` texels: every grid cell a
/// chart touches is its own, the padding rounded up to whole cells.
fn pack_cells(
    shapes: &[(&[[f64; 2]], f64, f64)],
    scale: f64,
    pad: u32,
    size: u32,
    cell: u32,
) -> Option<Vec<Spot>> {
    let spots = pack_shapes(
        shapes,
        scale / f64::from(cell),
        pad.div_ceil(cell),
        size / cell,
    )?;
    Some(
        spots
            .into_iter()
            .map(|s| Spot {
                origin: s.origin.map(|v| v * cell),
                turns: s.turns,
            })
            .collect(),
    )
}

/// The largest scale, from `start` (where the rectangles fit) up, at which
/// the charts' shapes fit (to within 1%), and their spots; `None` when
/// they do not fit even at `start`.
fn pack_shapes_largest(
    placed: &[Placed],
    start: f64,
    pad: u32,
    size: u32,
    cell: u32,
) -> Option<(f64, Vec<Spot>)> {
    let shapes: Vec<(&[[f64; 2]], f64, f64)> = placed
        .iter()
        .map(|p| (&p.coords[..], p.width, p.height))
        .collect();
    // Upper bound: the charts' own area fills the atlas inside its border.
    let area: f64 = placed
        .iter()
        .flat_map(|p| p.coords.chunks_exact(3))
        .map(|t| {
            0.5 * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1])
                - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]))
                .abs()
        })
        .sum();
    let room = f64::from(size.saturating_sub(2 * pad));
    let hi = if area > 0.0 {
        room / area.sqrt()
    } else {
        start
    };
    // The search runs on a grid twice as coarse where the atlas is large
    // (a quarter of the bits to scan, and most packings a search tries
    // fail, each scanning the whole atlas for a chart that has no place).
    // Its packing holds on the fine grid as it is: whole cells and
    // rounded-up padding only waste room. Measured against searching the
    // 2% above it on the fine grid: the same atlas use or up to two points
    // less (sofa, truck, tea set, Avocado, CesiumMan, the 20k torus in
    // 2048², the sofa in 4096²), for 2 to 5 times less layout time (the
    // torus's 0.42 s became 0.09 s).
    let coarse = 2 * cell;
    if size / coarse >= MIN_COARSE_SIDE {
        if let Some(found) = pack_cells(&shapes, start, pad, size, coarse) {
            let (s, more) = largest_fit(&shapes, start, hi, pad, size, coarse);
            return Some((s, more.unwrap_or(found)));
        }
    }
    let found = pack_cells(&shapes, start, pad, size, cell)?;
    let (s, more) = largest_fit(&shapes, start, hi, pad, size, cell);
    Some((s, more.unwrap_or(found)))
}

/// Atlases whose side is at least this many coarse cells search the
/// scale on the coarse grid first.
const MIN_COARSE_SIDE: u32 = 256;

/// The largest scale in `lo..hi` (to within 1%) at which the shapes fit
/// on the grid of `cell`² texels, given that they fit at `lo`, and the
/// spots of the last packing that fit above `lo` (`None`: none did).
fn largest_fit(
    shapes: &[(&[[f64; 2]], f64, f64)],
    mut lo: f64,
    mut hi: f64,
    pad: u32,
    size: u32,
    cell: u32,
) -> (f64, Option<Vec<Spot>>) {
    let mut found = None;
    // Two trial scales a round, a third and two thirds of the way (in
    // log scale), packed at once: on two cores a round costs one packing
    // and narrows the range three times rather than two.
    while hi > lo * 1.01 {
        let step = (hi / lo).cbrt();
        let (a, b) = (lo * step, lo * step * step);
        let (at_a, at_b) = rayon::join(
            || pack_cells(shapes, a, pad, size, cell),
            || pack_cells(shapes, b, pad, size, cell),
        );
        match (at_a, at_b) {
            (_, Some(s)) => {
                lo = b;
                found = Some(s);
            }
            (Some(s), None) => {
                (lo, hi) = (a, b);
                found = Some(s);
            }
            (None, None) => hi = a,
        }
    }
    (lo, found)
}

/// Texel origin of every chart's content at `scale`, or `None` when the
/// charts do not fit.
fn try_pack(placed: &[Placed], scale: f64, pad: u32, size: u32) -> Option<Vec<[u32; 2]>> {
    let bin = size.checked_sub(pad)?;
    let mut rects: GroupedRectsToPlace<usize, ()> = GroupedRectsToPlace::new();
    for (i, p) in placed.iter().enumerate() {
        let w = ((p.width * scale).ceil() as u32).max(1) + pad;
        let h = ((p.height * scale).ceil() as u32).max(1) + pad;
        rects.push_rect(i, None, RectToInsert::new(w, h, 1));
    }
    let mut bins = BTreeMap::new();
    bins.insert(0u8, TargetBin::new(bin, bin, 1));
    let packed = pack_rects(&rects, &mut bins, &volume_heuristic, &contains_smallest_box).ok()?;
    let locations = packed.packed_locations();
    (0..placed.len())
        .map(|i| locations.get(&i).map(|(_, l)| [l.x() + pad, l.y() + pad]))
        .collect()
}

/// The chart turned so that its bounding rectangle is smallest, corners
/// relative to the rectangle's lower corner.
fn turn(coords: &[[f64; 2]]) -> Placed {
    let hull = convex_hull(coords);
    let mut best = (f64::INFINITY, 1.0, 0.0);
    for i in 0..hull.len() {
        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt();
        if len <= 0.0 || !len.is_finite() {
            continue;
        }
        let (c, s) = (dx / len, dy / len);
        let (w, h) = extent(&hull, c, s);
        if w * h < best.0 {
            best = (w * h, c, s);
        }
    }
    let (_, c, s) = best;
    let rotated: Vec<[f64; 2]> = coords
        .iter()
        .map(|p| [c * p[0] + s * p[1], -s * p[0] + c * p[1]])
        .collect();
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &rotated {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    if !(lo[0].is_finite() && hi[0].is_finite() && lo[1].is_finite() && hi[1].is_finite()) {
        return Placed {
            coords: vec![[0.0; 2]; coords.len()],
            width: 0.0,
            height: 0.0,
        };
    }
    Placed {
        coords: rotated
            .iter()
            .map(|p| [p[0] - lo[0], p[1] - lo[1]])
            .collect(),
        width: hi[0] - lo[0],
        height: hi[1] - lo[1],
    }
}

fn extent(points: &[[f64; 2]], c: f64, s: f64) -> (f64, f64) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        let q = [c * p[0] + s * p[1], -s * p[0] + c * p[1]];
        for a in 0..2 {
            lo[a] = lo[a].min(q[a]);
            hi[a] = hi[a].max(q[a]);
        }
    }
    (hi[0] - lo[0], hi[1] - lo[1])
}

/// Andrew's monotone chain; collinear points dropped.
fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|q| q[0].is_finite() && q[1].is_finite())
        .collect();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` charts, each a unit square of two triangles.
    fn unit_squares(n: u32) -> Vec<Chart> {
        let square = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
        ];
        (0..n)
            .map(|i| Chart {
                triangles: vec![2 * i, 2 * i + 1],
                coords: square.clone(),
            })
            .collect()
    }

    #[test]
    fn triangle_charts_pack_by_shape_past_half_the_atlas() {
        // Right triangles with unit legs: as rectangles each leaves half of
        // its box empty, so the charts could cover at most half the atlas;
        // packed by shape, pairs share their boxes. 400 charts in 2048²
        // are packed on a grid of 4² texels.
        for (n, size) in [(32u32, 512u32), (400, 2048)] {
            let charts: Vec<Chart> = (0..n)
                .map(|i| Chart {
                    triangles: vec![i],
                    coords: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
                })
                .collect();
            let o = AtlasOptions {
                size,
                padding: 2,
                ..AtlasOptions::default()
            };
            let a = pack_charts(&charts, n as usize, &o);
            assert!(a.placed && a.fits);
            let covered = f64::from(n) * 0.5 * a.texels_per_unit.powi(2) / f64::from(size).powi(2);
            assert!(covered > 0.6, "{n} charts cover {covered:.3} of the atlas");
            // No two charts' triangles come within the padding (the
            // closest points of two triangles include a corner of one),
            // nor any within the padding of the border.
            let tri = |c: usize| [0, 1, 2].map(|k| a.corner_uvs[3 * c + k]);
            for c in 0..n as usize {
                for p in tri(c) {
                    let lo = 2.0 - 1e-3;
                    assert!(p[0] >= lo && p[1] >= lo, "{p:?}");
                    assert!(
                        p[0] <= size as f32 - lo && p[1] <= size as f32 - lo,
                        "{p:?}"
                    );
                }
                for d in 0..n as usize {
                    if c == d {
                        continue;
                    }
                    for p in tri(d) {
                        let (dist, _) = crate::raster::closest_on_triangle_2d(p, tri(c));
                        assert!(dist >= 2.0 - 1e-3, "charts {c} and {d}: {dist}");
                    }
                }
            }
        }
    }

    #[test]
    fn tilted_rectangle_turns_to_its_own_sides() {
        // A 4 × 1 rectangle turned by 30°: its smallest bounding
        // rectangle is itself, 4 × 1 (or 1 × 4).
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let r = |x: f64, y: f64| [c * x - s * y, s * x + c * y];
        let coords = vec![
            r(0.0, 0.0),
            r(4.0, 0.0),
            r(4.0, 1.0),
            r(0.0, 0.0),
            r(4.0, 1.0),
            r(0.0, 1.0),
        ];
        let p = turn(&coords);
        let (w, h) = (p.width.max(p.height), p.width.min(p.height));
        assert!(
            (w - 4.0).abs() < 1e-9 && (h - 1.0).abs() < 1e-9,
            "{w} × {h}"
        );
    }

    #[test]
    fn packed_charts_keep_the_padding_between_them_and_the_border() {
        // Four unit squares (two triangles each) in a 64-texel atlas with
        // padding 4.
        let charts = unit_squares(4);
        let o = AtlasOptions {
            size: 64,
            padding: 4,
            ..AtlasOptions::default()
        };
        let a = pack_charts(&charts, 8, &o);
        let boxes: Vec<[f32; 4]> = (0..4)
            .map(|c| {
                let uv = &a.corner_uvs[6 * c..6 * c + 6];
                let f =
                    |k: usize, m: fn(f32, f32) -> f32| uv.iter().map(|p| p[k]).fold(uv[0][k], m);
                [
                    f(0, f32::min),
                    f(1, f32::min),
                    f(0, f32::max),
                    f(1, f32::max),
                ]
            })
            .collect();
        for b in &boxes {
            assert!(
                b[0] >= 4.0 && b[1] >= 4.0 && b[2] <= 60.0 && b[3] <= 60.0,
                "{b:?}"
            );
            // The scale fills a good part of the atlas: each square is over
            // 16 texels wide.
            assert!(b[2] - b[0] > 16.0, "{b:?}");
        }
        for i in 0..4 {
            for j in i + 1..4 {
                let (p, q) = (boxes[i], boxes[j]);
                let gap_x = (q[0] - p[2]).max(p[0] - q[2]);
                let gap_y = (q[1] - p[3]).max(p[1] - q[3]);
                assert!(gap_x.max(gap_y) >= 4.0 - 1e-4, "{p:?} {q:?}");
            }
        }
    }

    #[test]
    fn many_charts_are_placed_but_do_not_fit_usefully_and_useful_only_skips_them() {
        // 120 unit squares in a 64² atlas with padding 4 (a 60² bin): each
        // takes at least 5 × 5 texels (a texel and its padding), 3,000 ≤
        // 3,600, so they can be placed, but only as charts of a texel or
        // two inside their padding: not useful.
        let charts = unit_squares;
        let o = AtlasOptions {
            size: 64,
            padding: 4,
            ..AtlasOptions::default()
        };
        let a = pack_charts(&charts(120), 240, &o);
        assert!(a.placed && !a.fits, "{} {}", a.placed, a.fits);
        // Asked for a useful packing only: 120 × 4² = 1,920 > 3,600 / 2,
        // none can exist, nothing is placed.
        let b = pack_charts(
            &charts(120),
            240,
            &AtlasOptions {
                useful_only: true,
                ..o
            },
        );
        assert!(!b.placed && !b.fits);
        // More than the bin can hold at any scale (200 × 25 > 3,600).
        let c = pack_charts(&charts(200), 400, &o);
        assert!(!c.placed && !c.fits);
        // A few charts: placed and useful.
        let d = pack_charts(&charts(4), 8, &o);
        assert!(d.placed && d.fits);
    }
}
