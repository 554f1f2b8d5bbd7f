//! Alpha-tested coverage kept through a re-bake (after Castaño 2010,
//! "Computing alpha mipmaps").
//!
//! A `MASK` material draws a point where its alpha passes the cutoff. A
//! re-baked texel averages the input texels its footprint covers, and an
//! average of thin opaque strokes over a transparent background falls
//! under the cutoff: a chain-link fence re-baked at 10% kept half of its
//! wires (alpha-tested coverage 0.11 of the surface against the input's
//! 0.234), foliage thins out, hair cards go bald. Colour metrics see none
//! of it: the colour under the strokes is usually the strokes' own.
//!
//! The fix keeps the fraction of the surface that passes the test. Every
//! owned texel's input point is also alpha-tested unfiltered (a point
//! sample: over the texels of an atlas, the fraction passing estimates the
//! input's coverage of the surface they show). What a renderer tests is
//! the atlas's alpha interpolated bilinearly between texel centres (the
//! level is drawn at about a texel a pixel), where a stroke one texel wide
//! passes over a fraction of its texel only; so the baked alphas are
//! sampled that way, 4 × 4 points a texel, and scaled (which keeps their
//! order: the strokes that pass are the most opaque, where the input's
//! strokes are) until the same fraction of those points passes.

/// The smallest 8-bit alpha that passes `cutoff` (glTF: a point is drawn
/// where alpha ≥ cutoff).
fn first_passing(cutoff: f32) -> u32 {
    ((cutoff * 255.0 - 1e-4).ceil().max(1.0) as u32).min(255)
}

/// Sub-texel sample offsets along each axis, from the texel centre.
const OFFSETS: [f32; 4] = [-0.375, -0.125, 0.125, 0.375];

/// Histogram bins per 8-bit step of interpolated alpha.
const BINS_PER_STEP: usize = 4;

/// The alpha of a `size`-wide square atlas interpolated bilinearly at
/// texel coordinates `(x, y)` (texel centres at half-integers, edges
/// clamped).
fn bilinear_alpha(pixels: &[[u8; 4]], size: usize, x: f32, y: f32) -> f32 {
    let (x, y) = (x - 0.5, y - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let clamp = |v: f32| (v.max(0.0) as usize).min(size - 1);
    let (xa, xb) = (clamp(x0), clamp(x0 + 1.0));
    let (ya, yb) = (clamp(y0), clamp(y0 + 1.0));
    let a = |xi: usize, yi: usize| f32::from(pixels[yi * size + xi][3]);
    let top = a(xa, ya) + (a(xb, ya) - a(xa, ya)) * fx;
    let bottom = a(xa, yb) + (a(xb, yb) - a(xa, yb)) * fx;
    top + (bottom - top) * fy
}

/// Scales the alpha of `pixels` (a square atlas `size` texels wide, its
/// gutter already filled; `owned` marks the texels that show the surface)
/// so that, interpolated bilinearly as a renderer draws it, a `passing`
/// fraction of the owned texels' area passes `cutoff`. Nothing changes
/// where it passes that often already, nor for a cutoff outside (0, 1].
pub(crate) fn keep_coverage(
    pixels: &mut [[u8; 4]],
    size: usize,
    owned: &[bool],
    passing: f64,
    cutoff: f32,
) {
    if !(cutoff > 0.0 && cutoff <= 1.0) || size == 0 || pixels.len() != size * size {
        return;
    }
    const BINS: usize = 256 * BINS_PER_STEP;
    let mut hist = vec![0usize; BINS + 1];
    let mut samples = 0usize;
    for (i, _) in owned.iter().enumerate().filter(|(_, &o)| o) {
        let (x, y) = ((i % size) as f32 + 0.5, (i / size) as f32 + 0.5);
        for dy in OFFSETS {
            for dx in OFFSETS {
                let a = bilinear_alpha(pixels, size, x + dx, y + dy);
                hist[((a * BINS_PER_STEP as f32) as usize).min(BINS)] += 1;
                samples += 1;
            }
        }
    }
    if samples == 0 {
        return;
    }
    let want = (passing.clamp(0.0, 1.0) * samples as f64).round() as usize;
    // at_least[b]: samples whose alpha is at least bin b's lower edge.
    let mut at_least = vec![0usize; BINS + 2];
    for b in (0..=BINS).rev() {
        at_least[b] = at_least[b + 1] + hist[b];
    }
    let c = first_passing(cutoff) as usize * BINS_PER_STEP;
    // The threshold whose pass count is nearest the wanted one; between
    // equals, the one nearest the cutoff's own (no change where that one
    // is best).
    let best = (1..=BINS)
        .min_by_key(|&b| (at_least[b].abs_diff(want), b.abs_diff(c)))
        .unwrap_or(c);
    if best == c {
        return;
    }
    // Alpha at the threshold maps onto the cutoff's first passing value.
    let scale = c as f32 / best as f32;
    for p in pixels.iter_mut() {
        p[3] = (f32::from(p[3]) * scale).round().min(255.0) as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An 8 × 8 atlas, every texel owned, transparent but for column 3 at
    /// `alpha`.
    fn line(alpha: u8) -> Vec<[u8; 4]> {
        (0..64)
            .map(|i| [7, 7, 7, if i % 8 == 3 { alpha } else { 0 }])
            .collect()
    }

    /// The fraction of the 4 × 4 sub-texel points that pass 0.5.
    fn drawn(pixels: &[[u8; 4]]) -> f64 {
        let mut n = 0;
        for i in 0..64 {
            let (x, y) = ((i % 8) as f32 + 0.5, (i / 8) as f32 + 0.5);
            for dy in OFFSETS {
                for dx in OFFSETS {
                    n += usize::from(bilinear_alpha(pixels, 8, x + dx, y + dy) >= 128.0);
                }
            }
        }
        n as f64 / (64 * 16) as f64
    }

    #[test]
    fn a_line_of_a_texel_is_drawn_as_wide_as_the_input_s() {
        // Column 3 at 200: interpolated, it passes 128 within 0.36 of a
        // texel of its centre, so only its points at ±1/8 do: a sixteenth
        // of the area. The input's line was a whole texel wide (1/8).
        let mut pixels = line(200);
        assert_eq!(drawn(&pixels), 1.0 / 16.0);
        keep_coverage(&mut pixels, 8, &[true; 64], 1.0 / 8.0, 0.5);
        // Its points at ±3/8 now pass (200 · 5/8 = 125 before), those of
        // the next columns (at 5/8 from it: 200 · 3/8 = 75) do not: the
        // line is scaled to 205 = round(200 · 128/125).
        assert_eq!(pixels[3][3], 205);
        assert_eq!(drawn(&pixels), 1.0 / 8.0);
        // Colour and the transparent texels are untouched.
        assert!(pixels.iter().all(|p| p[..3] == [7, 7, 7]));
        assert!(pixels
            .iter()
            .enumerate()
            .all(|(i, p)| i % 8 == 3 || p[3] == 0));
    }

    #[test]
    fn alphas_are_lowered_where_too_much_passes() {
        // An opaque line of a texel where the input had none: nothing may
        // pass, so the line drops under the cutoff.
        let mut pixels = line(255);
        keep_coverage(&mut pixels, 8, &[true; 64], 0.0, 0.5);
        assert_eq!(drawn(&pixels), 0.0);
    }

    #[test]
    fn nothing_changes_where_the_bake_already_passes_as_often() {
        let mut pixels = line(200);
        let before = pixels.clone();
        keep_coverage(&mut pixels, 8, &[true; 64], 1.0 / 16.0, 0.5);
        assert_eq!(pixels, before);
        let mut opaque = vec![[1, 2, 3, 255]; 64];
        keep_coverage(&mut opaque, 8, &[true; 64], 1.0, 0.5);
        assert_eq!(opaque, vec![[1, 2, 3, 255]; 64]);
    }

    #[test]
    fn texels_that_show_no_surface_are_not_counted() {
        // Only column 3 is owned: all of its area should pass, and its
        // points at ±3/8 (125) do not yet.
        let mut pixels = line(200);
        let owned: Vec<bool> = (0..64).map(|i| i % 8 == 3).collect();
        keep_coverage(&mut pixels, 8, &owned, 1.0, 0.5);
        assert_eq!(pixels[3][3], 205);
    }

    #[test]
    fn the_first_passing_value_follows_gltf_s_greater_or_equal() {
        assert_eq!(first_passing(0.5), 128);
        assert_eq!(first_passing(1.0), 255);
        assert_eq!(first_passing(0.2), 51);
        assert_eq!(first_passing(1e-6), 1);
    }
}
