//! No bleeding (W App. B): every texel a renderer can fetch holds a surface
//! color.
//!
//! W's guarantee is that every texel of the simplified surface is mapped to
//! a point of the input surface, so none picks up the background. Texture
//! filtering reads more than the chart: bilinear filtering reads texels up
//! to one away, and mip level `k` averages `2^k × 2^k` blocks. The raster
//! step already gives every texel within 1.5 of a chart its own surface
//! point (`raster.rs`); here every remaining texel takes the value of the
//! nearest such texel (a breadth-first flood from all of them at once, in
//! 8-neighbour steps, so "nearest" is in the L∞ sense, ties to the earlier
//! texel in row order). Then no texel of the atlas holds background, and
//! neither does any texel of any mip level down to 1×1. Charts are
//! `padding` texels apart, so down to mip level `log2(padding) − 1` a
//! chart's bilinear footprint reads only its own colors.

use std::collections::VecDeque;

use wildlod_mesh::Rgba8Image;

/// Fills every texel with `owned[i] == false` from the nearest owned texel.
/// Leaves the image unchanged when nothing is owned.
pub fn dilate(image: &mut Rgba8Image, owned: &[bool]) {
    apply_fill(image, &nearest_owned(image.width, image.height, owned));
}

/// For every texel of a `width × height` atlas, the index of the nearest
/// owned texel (itself when owned; `u32::MAX` when nothing is owned):
/// computed once, applied to every channel of an atlas.
pub fn nearest_owned(width: u32, height: u32, owned: &[bool]) -> Vec<u32> {
    let (w, h) = (width as usize, height as usize);
    let mut source = vec![u32::MAX; w * h];
    let mut queue: VecDeque<usize> = VecDeque::new();
    for (i, &o) in owned.iter().enumerate().take(w * h) {
        if o {
            source[i] = i as u32;
            queue.push_back(i);
        }
    }
    while let Some(i) = queue.pop_front() {
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        for dy in -1..=1i64 {
            for dx in -1..=1i64 {
                let (nx, ny) = (x + dx, y + dy);
                if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if source[j] == u32::MAX {
                    source[j] = source[i];
                    queue.push_back(j);
                }
            }
        }
    }
    source
}

/// Copies into every texel the value of its source texel
/// ([`nearest_owned`]).
pub fn apply_fill(image: &mut Rgba8Image, source: &[u32]) {
    for (i, &s) in source.iter().enumerate().take(image.pixels.len()) {
        let s = s as usize;
        if s != i && s < image.pixels.len() {
            image.pixels[i] = image.pixels[s];
        }
    }
}

/// The mip chain of `image` (level 0 first) down to 1×1, each level the
/// 2×2 box average of the one above (odd sizes: the last row/column
/// averaged with itself), as GPUs generate mips.
pub fn mip_chain(image: &Rgba8Image) -> Vec<Rgba8Image> {
    let mut out = vec![image.clone()];
    loop {
        let prev = out.last().map(|l| (l.width, l.height)).unwrap_or((1, 1));
        if prev.0 <= 1 && prev.1 <= 1 {
            break;
        }
        let Some(l) = out.last() else { break };
        let (w, h) = ((l.width / 2).max(1), (l.height / 2).max(1));
        let mut next = Rgba8Image::filled(w, h, [0; 4]);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 4];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (2 * x + dx).min(l.width - 1);
                    let sy = (2 * y + dy).min(l.height - 1);
                    let p = l.pixels[(sy * l.width + sx) as usize];
                    for k in 0..4 {
                        sum[k] += p[k] as u32;
                    }
                }
                next.pixels[(y * w + x) as usize] = sum.map(|s| ((s + 2) / 4) as u8);
            }
        }
        out.push(next);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dilation_fills_every_texel_from_the_nearest_owner() {
        // 5×1: owned red at x = 0, owned blue at x = 4.
        let mut img = Rgba8Image::filled(5, 1, [0; 4]);
        img.pixels[0] = [255, 0, 0, 255];
        img.pixels[4] = [0, 0, 255, 255];
        let owned = [true, false, false, false, true];
        dilate(&mut img, &owned);
        assert_eq!(img.pixels[1], [255, 0, 0, 255]);
        assert_eq!(img.pixels[3], [0, 0, 255, 255]);
        // x = 2 is as near to both: the earlier texel wins.
        assert_eq!(img.pixels[2], [255, 0, 0, 255]);
    }

    #[test]
    fn mip_levels_average_two_by_two_blocks_down_to_one_texel() {
        let img = Rgba8Image {
            width: 2,
            height: 2,
            pixels: vec![[0; 4], [100; 4], [200; 4], [100; 4]],
        };
        let chain = mip_chain(&img);
        assert_eq!(chain.len(), 2);
        assert_eq!(chain[1].pixels, vec![[100; 4]]);
        assert_eq!(mip_chain(&Rgba8Image::filled(8, 4, [9; 4])).len(), 4);
    }
}
