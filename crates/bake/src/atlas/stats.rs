//! What a layout costs: how much it stretches the surface and how much of
//! the atlas it uses. Used to choose between layouts (docs/evaluation-
//! appearance.md) and by tests.

use glam::DVec3;

use crate::raster::Rasterizer;

use super::Atlas;

/// Rows of the atlas counted at a time.
const STATS_ROWS: u32 = 256;

/// Distortion and atlas use of a layout.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AtlasStats {
    /// Number of charts.
    pub charts: usize,
    /// Fraction of atlas texels whose center lies inside a chart.
    pub utilization: f64,
    /// Sander et al. 2001's L² stretch, normalized per chart so that 1 is
    /// an isometry up to each chart's scale (charts get different texel
    /// densities on purpose, [`crate::build_atlas_weighted`]), then
    /// averaged (L², by area) over the charts (≥ 1).
    pub stretch_l2: f64,
    /// Area-weighted mean of the ratio of a triangle's larger to smaller
    /// singular value (1: no angle distortion).
    pub angle_distortion: f64,
}

/// Measures `atlas`, a layout of `triangles` over `positions`.
pub fn atlas_stats(positions: &[[f32; 3]], triangles: &[[u32; 3]], atlas: &Atlas) -> AtlasStats {
    let (mut area3, mut angle) = (0.0, 0.0);
    // Per chart: 3D area, UV area, Σ area × stretch².
    let mut per_chart = vec![[0.0f64; 3]; atlas.chart_count.max(1)];
    for (t, tri) in triangles.iter().enumerate() {
        let p = tri.map(|v| DVec3::from(positions[v as usize].map(f64::from)));
        let q = [0, 1, 2].map(|k| atlas.corner_uvs[3 * t + k].map(f64::from));
        let a3 = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        let a2 = 0.5
            * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]));
        if a3.is_nan() || a3 <= 0.0 || a2 == 0.0 || !a2.is_finite() {
            continue;
        }
        // Partial derivatives of the surface over the UV triangle (Sander
        // et al. 2001, §3).
        let ss =
            (p[0] * (q[1][1] - q[2][1]) + p[1] * (q[2][1] - q[0][1]) + p[2] * (q[0][1] - q[1][1]))
                / (2.0 * a2);
        let st =
            (p[0] * (q[2][0] - q[1][0]) + p[1] * (q[0][0] - q[2][0]) + p[2] * (q[1][0] - q[0][0]))
                / (2.0 * a2);
        let (a, b, c) = (ss.dot(ss), ss.dot(st), st.dot(st));
        let root = ((a - c).powi(2) + 4.0 * b * b).sqrt();
        let big = (0.5 * (a + c + root)).sqrt();
        let small = (0.5 * (a + c - root)).max(0.0).sqrt();
        area3 += a3;
        let chart = atlas.triangle_chart.get(t).map_or(0, |&c| c as usize);
        let last = per_chart.len() - 1;
        let acc = &mut per_chart[chart.min(last)];
        acc[0] += a3;
        acc[1] += a2.abs();
        acc[2] += a3 * 0.5 * (a + c);
        angle += a3 * if small > 0.0 { big / small } else { 1e6 };
    }
    // Counted a band at a time: the whole map would be 20 bytes a texel.
    let raster = Rasterizer::new(&atlas.corner_uvs, atlas.size, 0.0);
    let inside: usize = (0..atlas.size)
        .step_by(STATS_ROWS as usize)
        .map(|y| raster.rows(y..y + STATS_ROWS).inside())
        .sum();
    let texels = atlas.size as f64 * atlas.size as f64;
    AtlasStats {
        charts: atlas.chart_count,
        utilization: if texels > 0.0 {
            inside as f64 / texels
        } else {
            0.0
        },
        stretch_l2: if area3 > 0.0 {
            // Σ over charts of area × (chart's normalized stretch)².
            let sum: f64 = per_chart
                .iter()
                .filter(|c| c[0] > 0.0)
                .map(|c| c[2] * c[1] / c[0])
                .sum();
            (sum / area3).sqrt()
        } else {
            1.0
        },
        angle_distortion: if area3 > 0.0 { angle / area3 } else { 1.0 },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isometric_layout_has_stretch_one_and_sheared_layout_more() {
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let t = [[0u32, 1, 2]];
        let mut a = Atlas {
            size: 16,
            corner_uvs: vec![[2.0, 2.0], [10.0, 2.0], [2.0, 10.0]],
            triangle_chart: vec![0],
            chart_count: 1,
            texels_per_unit: 8.0,
            placed: true,
            fits: true,
        };
        let s = atlas_stats(&p, &t, &a);
        assert!((s.stretch_l2 - 1.0).abs() < 1e-12, "{s:?}");
        assert!((s.angle_distortion - 1.0).abs() < 1e-12);
        // Centers (2.5 + i, 2.5 + j) are inside when i + j ≤ 7: 8 + 7 + … +
        // 1 = 36 texels.
        assert!((s.utilization - 36.0 / 256.0).abs() < 1e-12, "{s:?}");
        // Stretch u by 2: singular values 2 and 1 (up to scale).
        a.corner_uvs = vec![[2.0, 2.0], [14.0, 2.0], [2.0, 8.0]];
        let s = atlas_stats(&p, &t, &a);
        assert!((s.angle_distortion - 2.0).abs() < 1e-9, "{s:?}");
        // L² stretch of singular values (1/2, 1) of the inverse map at
        // unit area: √((¼ + 1)/2) · √(area ratio 2) = √1.25 ≈ 1.118.
        assert!((s.stretch_l2 - 1.25f64.sqrt()).abs() < 1e-9, "{s:?}");
    }

    #[test]
    fn charts_at_different_densities_are_not_stretched() {
        // Two unit right triangles, each laid out isometrically, one at 4
        // texels per unit and one at 8.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        let t = [[0u32, 1, 2], [3, 4, 5]];
        let mut a = Atlas {
            size: 32,
            corner_uvs: vec![
                [1.0, 1.0],
                [5.0, 1.0],
                [1.0, 5.0],
                [10.0, 10.0],
                [18.0, 10.0],
                [10.0, 18.0],
            ],
            triangle_chart: vec![0, 1],
            chart_count: 2,
            texels_per_unit: 4.0,
            placed: true,
            fits: true,
        };
        let s = atlas_stats(&p, &t, &a);
        assert!((s.stretch_l2 - 1.0).abs() < 1e-12, "{s:?}");
        // As one chart, the two densities are a stretch.
        a.triangle_chart = vec![0, 0];
        a.chart_count = 1;
        assert!(atlas_stats(&p, &t, &a).stretch_l2 > 1.05);
    }
}
