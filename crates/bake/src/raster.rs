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

/// Texel ownership of rows of one atlas (all of them from [`rasterize`],
/// a band from [`Rasterizer::rows`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coverage {
    /// Width and height of the atlas in texels.
    pub size: u32,
    /// The first row covered; the rows are `first_row..first_row +
    /// triangle.len() / size`.
    pub first_row: u32,
    /// Owning triangle of every texel of the rows (row-major, top row
    /// first), or [`NO_TRIANGLE`].
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
/// triangle, in texels), up to `margin` texels outside them, over the
/// whole atlas ([`Rasterizer::rows`] over every row).
pub fn rasterize(corner_uvs: &[[f32; 2]], size: u32, margin: f32) -> Coverage {
    Rasterizer::new(corner_uvs, size, margin).rows(0..size)
}

/// Texel ownership computed a band of rows at a time: a bake keeps only
/// the band it works on (20 bytes a texel: 320 MiB for a whole 4096²
/// atlas).
///
/// Each band is assigned from the triangles whose box (grown by the
/// margin) reaches it, in parallel over bands of 32 rows; the winner of a
/// texel depends only on distances and indices, so the result is the same
/// on any number of threads and for any split into bands.
#[derive(Clone, Debug)]
pub struct Rasterizer<'a> {
    corner_uvs: &'a [[f32; 2]],
    size: u32,
    margin: f32,
    /// Each triangle's texel box: columns x0..x1, rows y0..y1.
    boxes: Vec<Option<[usize; 4]>>,
    /// The triangles reaching each band of `BAND_ROWS` rows, ascending.
    in_band: Vec<Vec<u32>>,
}

impl<'a> Rasterizer<'a> {
    /// Prepares the assignment of a `size`² atlas to the triangles with
    /// corners `corner_uvs` (three per triangle, in texels), up to `margin`
    /// texels outside them.
    pub fn new(corner_uvs: &'a [[f32; 2]], size: u32, margin: f32) -> Self {
        let s = size as f32;
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
        let mut in_band: Vec<Vec<u32>> = vec![Vec::new(); (size as usize).div_ceil(BAND_ROWS)];
        for (t, b) in boxes.iter().enumerate() {
            if let Some([_, _, y0, y1]) = *b {
                for list in &mut in_band[y0 / BAND_ROWS..=(y1 - 1) / BAND_ROWS] {
                    list.push(t as u32);
                }
            }
        }
        Rasterizer {
            corner_uvs,
            size,
            margin,
            boxes,
            in_band,
        }
    }

    /// The ownership of rows `rows` (clamped to the atlas).
    pub fn rows(&self, rows: std::ops::Range<u32>) -> Coverage {
        use rayon::prelude::*;
        let w = self.size as usize;
        let (y0, y1) = (rows.start.min(self.size), rows.end.min(self.size));
        let n = (y1.saturating_sub(y0)) as usize * w;
        let mut c = Coverage {
            size: self.size,
            first_row: y0,
            triangle: vec![NO_TRIANGLE; n],
            bary: vec![[0.0; 3]; n],
            distance: vec![f32::INFINITY; n],
        };
        if n == 0 {
            return c;
        }
        // Pieces of the rows, each within one band of `in_band`.
        let mut pieces = Vec::new();
        let mut y = y0 as usize;
        while y < y1 as usize {
            let end = ((y / BAND_ROWS + 1) * BAND_ROWS).min(y1 as usize);
            pieces.push(y..end);
            y = end;
        }
        let mut owner: &mut [u32] = &mut c.triangle;
        let mut bary: &mut [[f32; 3]] = &mut c.bary;
        let mut distance: &mut [f32] = &mut c.distance;
        let mut work = Vec::with_capacity(pieces.len());
        for r in pieces {
            let k = r.len() * w;
            let (o, ro) = std::mem::take(&mut owner).split_at_mut(k);
            let (b, rb) = std::mem::take(&mut bary).split_at_mut(k);
            let (d, rd) = std::mem::take(&mut distance).split_at_mut(k);
            (owner, bary, distance) = (ro, rb, rd);
            work.push((r, o, b, d));
        }
        work.into_par_iter().for_each(|(r, owner, bary, distance)| {
            self.assign(r, owner, bary, distance);
        });
        c
    }

    /// Assigns rows `r` (within one band) into the slices, which start at
    /// row `r.start`.
    fn assign(
        &self,
        r: std::ops::Range<usize>,
        owner: &mut [u32],
        bary: &mut [[f32; 3]],
        distance: &mut [f32],
    ) {
        let w = self.size as usize;
        for &t in &self.in_band[r.start / BAND_ROWS] {
            let Some([x0, x1, y0, y1]) = self.boxes[t as usize] else {
                continue;
            };
            let uv = &self.corner_uvs[3 * t as usize..3 * t as usize + 3];
            let q = [uv[0], uv[1], uv[2]];
            for y in y0.max(r.start)..y1.min(r.end) {
                for x in x0..x1 {
                    let p = [x as f32 + 0.5, y as f32 + 0.5];
                    let (d, b) = closest_on_triangle_2d(p, q);
                    if d > self.margin {
                        continue;
                    }
                    let i = (y - r.start) * w + x;
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
    }
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
    fn rows_in_any_bands_equal_the_whole_atlas() {
        // Bands not aligned with the 32-row pieces, one past the end and
        // one empty: stitched together they are the whole coverage.
        let uv: Vec<[f32; 2]> = (0..60)
            .flat_map(|k| {
                let (cx, cy) = ((k * 37 % 97) as f32, (k * 53 % 101) as f32);
                [[cx, cy], [cx + 9.0, cy + 2.0], [cx + 3.0, cy + 11.0]]
            })
            .collect();
        let size = 100u32;
        let whole = rasterize(&uv, size, 1.5);
        let r = Rasterizer::new(&uv, size, 1.5);
        let mut stitched = Coverage {
            size,
            ..Coverage::default()
        };
        for rows in [0..7, 7..7, 7..45, 45..77, 77..130] {
            let band = r.rows(rows.clone());
            assert_eq!(band.first_row, rows.start.min(size));
            assert_eq!(
                band.triangle.len(),
                (rows.end.min(size) - rows.start.min(size)) as usize * 100
            );
            stitched.triangle.extend(band.triangle);
            stitched.bary.extend(band.bary);
            stitched.distance.extend(band.distance);
        }
        assert!(whole.owned() > 2000, "{}", whole.owned());
        assert_eq!(stitched, whole);
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
