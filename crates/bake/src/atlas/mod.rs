//! A new injective UV layout for the simplified mesh (W §4.3: "our mapping
//! approach is compatible with any injective texture mapping"): charts grown
//! by normal (`charts.rs`), each projected orthographically onto its mean
//! plane and checked for injectivity, turned to its smallest bounding
//! rectangle and packed with gutters into one square atlas (`pack.rs`).
//! `stats.rs` measures what a layout costs: stretch and atlas use.

mod bitmap;
mod charts;
mod pack;
mod stats;

pub use stats::{atlas_stats, AtlasStats};

use charts::{make_charts, Chart};
use pack::pack_charts;

/// How the atlas is laid out.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasOptions {
    /// Width and height of the atlas, in texels.
    pub size: u32,
    /// Empty texels kept between charts and along the atlas border, so that
    /// bilinear filtering (and the first mip levels) of one chart never
    /// reads another's texels. Default 4: safe at mip levels 0 and 1.
    pub padding: u32,
    /// Largest angle, in degrees, between a triangle's normal and the
    /// direction its chart is projected along (the mean normal of the
    /// region grown around the chart's seed). Orthographic projection
    /// stretches a triangle by at most 1/cos of this angle. Default 50°.
    pub max_chart_angle: f64,
    /// Only a packing that fits usefully ([`Atlas::fits`]) is wanted: when
    /// none can exist (the padding alone, a `padding²` per chart, would
    /// take over half the atlas), the search is skipped and nothing is
    /// placed. For a caller that tries a larger size next. Default off.
    pub useful_only: bool,
}

impl Default for AtlasOptions {
    fn default() -> Self {
        AtlasOptions {
            size: 1024,
            padding: 4,
            max_chart_angle: 50.0,
            useful_only: false,
        }
    }
}

/// A packed layout: UVs for every triangle corner.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Atlas {
    /// Width and height in texels.
    pub size: u32,
    /// UV of every triangle corner, three per triangle, in texels: texel
    /// `(x, y)` covers `[x, x + 1) × [y, y + 1)`, `y` down the image.
    pub corner_uvs: Vec<[f32; 2]>,
    /// Chart of every triangle.
    pub triangle_chart: Vec<u32>,
    /// Number of charts.
    pub chart_count: usize,
    /// Texels per unit of length on the surface of a chart at the typical
    /// density (every chart's, unless [`build_atlas_weighted`] was given
    /// densities).
    pub texels_per_unit: f64,
    /// Whether every chart got its own place (false: the charts, each at
    /// least a texel plus padding, cannot fit at any scale, and every UV is
    /// at the padding corner).
    pub placed: bool,
    /// Whether they were placed at a scale where the charts hold at least
    /// as many texels as the padding around them (false: tens of thousands
    /// of charts squeezed to a texel or two, the atlas mostly gutter).
    pub fits: bool,
}

/// Lays out `triangles` over `positions` in one square atlas, every chart
/// at the same texel density.
///
/// `keys` (one per triangle, or empty) keeps triangles with different keys
/// in different charts: an input material or UV island boundary becomes a
/// chart boundary. Degenerate triangles get UVs too (of zero area).
pub fn build_atlas(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    keys: &[u32],
    options: &AtlasOptions,
) -> Atlas {
    build_atlas_weighted(positions, triangles, keys, &[], options)
}

/// Most a chart's linear texel density may differ from the typical chart's
/// ([`build_atlas_weighted`]): a tiled texture (UVs repeating a hundred
/// times) or a sliver with a large UV area would otherwise take the whole
/// atlas from everything else.
pub const MAX_DENSITY_RATIO: f64 = 8.0;

/// [`build_atlas`] with each chart's texel density following `densities`
/// (one per triangle, or empty: all equal): a chart's linear scale is
/// proportional to the square root of the area-weighted mean density of
/// its triangles (texels per unit area), so a chart over a part of the
/// surface the input gave many texels (a logo, a face) gets as many in the
/// atlas. Triangles whose density is not a positive finite number count as
/// the typical density (the area-weighted geometric mean); charts made only
/// of those keep the area-proportional share. Within
/// [`MAX_DENSITY_RATIO`] of the typical chart. The common scale still
/// fills the atlas.
pub fn build_atlas_weighted(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    keys: &[u32],
    densities: &[f64],
    options: &AtlasOptions,
) -> Atlas {
    let cos = options.max_chart_angle.clamp(1.0, 89.0).to_radians().cos();
    let mut charts = make_charts(positions, triangles, keys, cos);
    if densities.len() == triangles.len() {
        let scales = chart_scales(&charts, positions, triangles, densities);
        for (chart, f) in charts.iter_mut().zip(scales) {
            for q in &mut chart.coords {
                *q = [q[0] * f, q[1] * f];
            }
        }
    }
    let mut atlas = pack_charts(&charts, triangles.len(), options);
    atlas.size = options.size;
    atlas
}

/// The linear scale of every chart against the typical density (see
/// [`build_atlas_weighted`]).
fn chart_scales(
    charts: &[Chart],
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    densities: &[f64],
) -> Vec<f64> {
    let area = |t: u32| {
        let p =
            triangles[t as usize].map(|v| glam::DVec3::from(positions[v as usize].map(f64::from)));
        let a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        if a.is_finite() {
            a
        } else {
            0.0
        }
    };
    let valid = |d: f64| d.is_finite() && d > 0.0;
    let (mut log_sum, mut weight) = (0.0, 0.0);
    for (t, &d) in densities.iter().enumerate() {
        if valid(d) {
            let a = area(t as u32);
            log_sum += a * d.ln();
            weight += a;
        }
    }
    if weight <= 0.0 {
        return vec![1.0; charts.len()];
    }
    let typical = (log_sum / weight).exp();
    charts
        .iter()
        .map(|c| {
            let (mut sum, mut total) = (0.0, 0.0);
            for &t in &c.triangles {
                let a = area(t);
                let d = densities[t as usize];
                sum += a * if valid(d) { d } else { typical };
                total += a;
            }
            let ratio = if total > 0.0 {
                sum / total / typical
            } else {
                1.0
            };
            ratio
                .sqrt()
                .clamp(1.0 / MAX_DENSITY_RATIO, MAX_DENSITY_RATIO)
        })
        .collect()
}
