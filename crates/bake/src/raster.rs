//! Which texels of an atlas a bake computes, and where on the surface each
//! one is.
//!
//! A texel belongs to the triangle whose UV footprint is closest to its
//! center, when that distance is at most `margin` texels: 0 inside a chart,
//! up to the margin in its gutter. Its surface point is the closest point of
//! that triangle, so gutter texels carry the surface's own color at the
//! chart edge (W: "every texel (chart interior plus gutter)"). Bilinear
//! filtering of a point in a chart reads texels whose centers lie within
//! one texel along each axis, at most √2 ≈ 1.42 away: a margin of 1.5
//! covers everything level 0 can fetch. Ties go to the lower triangle
//! index, so the result does not depend on the order of work.

/// No triangle owns the texel.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// Texel ownership of one atlas.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coverage {
    /// Width and height in texels.
    pub size: u32,
    /// Owning triangle of every texel (row-major, top row first), or
    /// [`NO_TRIANGLE`].
    pub triangle: Vec<u32>,
    /// Barycentrics of the texel's surface point on its triangle.
    pub bary: Vec<[f32; 3]>,
    /// Distance in texels from the texel center to the triangle's UV
    /// footprint (0 inside).
    pub distance: Vec<f32>,
}

impl Coverage {
    /// Texels owned by a triangle.
    pub fn owned(&self) -> usize {
        self.triangle.iter().filter(|&&t| t != NO_TRIANGLE).count()
    }

    /// Texels whose center lies inside a triangle: the atlas space the
    /// charts use.
    pub fn inside(&self) -> usize {
        self.distance
            .iter()
            .zip(&self.triangle)
            .filter(|(&d, &t)| t != NO_TRIANGLE && d == 0.0)
            .count()
    }
}

/// Rows of the atlas one thread assigns at a time.
const BAND_ROWS: usize = 32;

/// Assigns texels to the triangles with corners `corner_uvs` (three per
/// triangle, in texels), up to `margin` texels outside them.
///
/// Bands of rows are assigned in parallel, each from the triangles whose
/// box (grown by the margin) reaches it; the winner of a texel depends only
/// on distances and indices, so the result is the same on any number of
/// threads.
pub fn rasterize(corner_uvs: &[[f32; 2]], size: u32, margin: f32) -> Coverage {
    use rayon::prelude::*;
    let n = size as usize * size as usize;
    let mut c = Coverage {
        size,
        triangle: vec![NO_TRIANGLE; n],
        bary: vec![[0.0; 3]; n],
        distance: vec![f32::INFINITY; n],
    };
    if n == 0 {
        return c;
    }
    let s = size as f32;
    let w = size as usize;
    // Each triangle's texel box: columns x0..x1, rows y0..y1.
    let boxes: Vec<Option<[usize; 4]>> = corner_uvs
        .chunks_exact(3)
        .map(|q| {
            if q.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
                return None;
            }
            let lo_x = q.iter().map(|p| p[0]).fold(f32::INFINITY, f32::min) - margin;
            let hi_x = q.iter().map(|p| p[0]).fold(f32::NEG_INFINITY, f32::max) + margin;
            let lo_y = q.iter().map(|p| p[1]).fold(f32::INFINITY, f32::min) - margin;
            let hi_y = q.iter().map(|p| p[1]).fold(f32::NEG_INFINITY, f32::max) + margin;
            // Texel x has its center at x + 0.5.
            let x0 = (lo_x - 0.5).ceil().clamp(0.0, s) as usize;
            let x1 = ((hi_x - 0.5).floor() + 1.0).clamp(0.0, s) as usize;
            let y0 = (lo_y - 0.5).ceil().clamp(0.0, s) as usize;
            let y1 = ((hi_y - 0.5).floor() + 1.0).clamp(0.0, s) as usize;
            (x0 < x1 && y0 < y1).then_some([x0, x1, y0, y1])
        })
        .collect();
    // Triangles by band, in ascending order.
    let bands = w.div_ceil(BAND_ROWS);
    let mut in_band: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (t, b) in boxes.iter().enumerate() {
        if let Some([_, _, y0, y1]) = *b {
            for list in &mut in_band[y0 / BAND_ROWS..=(y1 - 1) / BAND_ROWS] {
                list.push(t as u32);
            }
        }
    }
    let rows = BAND_ROWS * w;
    c.triangle
        .par_chunks_mut(rows)
        .zip(c.bary.par_chunks_mut(rows))
        .zip(c.distance.par_chunks_mut(rows))
        .zip(in_band.par_iter())
        .enumerate()
        .for_each(|(band, (((owner, bary), distance), tris))| {
            let first_row = band * BAND_ROWS;
            let last_row = first_row + owner.len() / w;
            for &t in tris {
                let Some([x0, x1, y0, y1]) = boxes[t as usize] else {
                    continue;
                };
                let uv = &corner_uvs[3 * t as usize..3 * t as usize + 3];
                let q = [uv[0], uv[1], uv[2]];
                for y in y0.max(first_row)..y1.min(last_row) {
                    for x in x0..x1 {
                        let p = [x as f32 + 0.5, y as f32 + 0.5];
                        let (d, b) = closest_on_triangle_2d(p, q);
                        if d > margin {
                            continue;
                        }
                        let i = (y - first_row) * w + x;
                        let cur = distance[i];
                        // Lower distance wins; ties keep the lower triangle.
                        if d < cur || (d == cur && t < owner[i]) {
                            distance[i] = d;
                            owner[i] = t;
                            bary[i] = b;
                        }
                    }
                }
            }
        });
    c
}

/// Distance from `p` to triangle `q` and barycentrics of the closest point
/// (exact in `f64`; a degenerate triangle is the union of its edges).
pub fn closest_on_triangle_2d(p: [f32; 2], q: [[f32; 2]; 3]) -> (f32, [f32; 3]) {
    let p = [p[0] as f64, p[1] as f64];
    let q = q.map(|v| [v[0] as f64, v[1] as f64]);
    let cross = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let area = cross(q[0], q[1], q[2]);
    if area != 0.0 {
        let w0 = cross(q[1], q[2], p) / area;
        let w1 = cross(q[2], q[0], p) / area;
        let w2 = 1.0 - w0 - w1;
        if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
            return (0.0, [w0 as f32, w1 as f32, w2 as f32]);
        }
    }
    let mut best = (f64::INFINITY, [1.0f32, 0.0, 0.0]);
    for k in 0..3 {
        let (a, b) = (q[k], q[(k + 1) % 3]);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c = [a[0] + t * ab[0], a[1] + t * ab[1]];
        let d2 = (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2);
        if d2 < best.0 {
            let mut b = [0.0f32; 3];
            b[k] = (1.0 - t) as f32;
            b[(k + 1) % 3] += t as f32;
            best = (d2, b);
        }
    }
    (best.0.sqrt() as f32, best.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_give_what_every_texel_against_every_triangle_gives() {
        // Overlapping triangles over several bands, some reaching past the
        // atlas, and one degenerate: a brute-force search over all
        // triangles for each texel picks the same owner, distance and
        // barycentrics.
        let size = 100u32;
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as f32 / (1u64 << 31) as f32
        };
        let mut uv = Vec::new();
        for _ in 0..40 {
            let (cx, cy) = (next() * 110.0 - 5.0, next() * 110.0 - 5.0);
            for _ in 0..3 {
                uv.push([cx + next() * 30.0 - 15.0, cy + next() * 30.0 - 15.0]);
            }
        }
        uv.extend([[10.0, 10.0], [40.0, 70.0], [25.0, 40.0]]);
        let c = rasterize(&uv, size, 1.5);
        let mut owned = 0;
        for y in 0..size as usize {
            for x in 0..size as usize {
                let p = [x as f32 + 0.5, y as f32 + 0.5];
                let mut best = (f32::INFINITY, NO_TRIANGLE, [0.0f32; 3]);
                for (t, q) in uv.chunks_exact(3).enumerate() {
                    let (d, b) = closest_on_triangle_2d(p, [q[0], q[1], q[2]]);
                    if d <= 1.5 && d < best.0 {
                        best = (d, t as u32, b);
                    }
                }
                let i = y * size as usize + x;
                assert_eq!(c.triangle[i], best.1, "texel ({x}, {y})");
                if best.1 != NO_TRIANGLE {
                    owned += 1;
                    assert_eq!((c.distance[i], c.bary[i]), (best.0, best.2));
                }
            }
        }
        assert!(
            owned > 3000,
            "the triangles cover much of the atlas: {owned}"
        );
    }

    #[test]
    fn texel_centers_inside_get_distance_zero_and_their_barycentrics() {
        // Right triangle (0,0), (4,0), (0,4) in an 8-texel atlas.
        let c = rasterize(&[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]], 8, 1.5);
        // Texel (1, 1): center (1.5, 1.5): weights (1 − 3/8 − 3/8, 3/8, 3/8).
        let i = 8 + 1;
        assert_eq!((c.triangle[i], c.distance[i]), (0, 0.0));
        let b = c.bary[i];
        assert!(
            (b[0] - 0.25).abs() < 1e-6 && (b[1] - 0.375).abs() < 1e-6,
            "{b:?}"
        );
        // Centers (i + ½, j + ½) with x + y ≤ 4 are inside: i + j ≤ 3, so
        // 4 + 3 + 2 + 1 texels (the hypotenuse's own centers included).
        assert_eq!(c.inside(), 10);
    }

    #[test]
    fn gutter_texels_within_the_margin_take_the_closest_edge_point() {
        let c = rasterize(&[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]], 8, 1.5);
        // Texel (5, 0): center (5.5, 0.5); its closest point is the corner
        // (4, 0), √(1.5² + 0.5²) ≈ 1.58 away: beyond the margin.
        assert_eq!(c.triangle[5], NO_TRIANGLE);
        // Texel (4, 0): center (4.5, 0.5), closest point the corner (4, 0),
        // √0.5 away.
        let i = 4;
        assert_eq!(c.triangle[i], 0);
        assert!((c.distance[i] - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
    }

    #[test]
    fn shared_texels_go_to_the_nearer_triangle_then_the_lower_index() {
        // Two triangles sharing the diagonal of a 4×4 square.
        let uv = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [0.0, 0.0],
            [4.0, 4.0],
            [0.0, 4.0],
        ];
        let c = rasterize(&uv, 4, 1.5);
        // Every texel is inside one of them; the diagonal's centers (x = y)
        // lie on both and go to triangle 0.
        assert_eq!(c.inside(), 16);
        for k in 0..4 {
            assert_eq!(c.triangle[k * 4 + k], 0);
        }
        assert_eq!(c.triangle[3 * 4], 1);
    }
}
