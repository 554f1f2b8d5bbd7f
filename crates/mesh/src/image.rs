//! Decoded texture images, for texture metrics and re-baking.

/// An RGBA image with channels in [0, 1], rows top to bottom, as stored
/// in the file (no color-space conversion: sRGB stays sRGB), read through
/// [`Image::texel`] and [`Image::sample_bilinear`].
///
/// Its pixels are held either as `f32` (`pixels`: images made in code,
/// 16-bit files) or, for 8-bit files, as the bytes themselves (`bytes`,
/// each read as `byte / 255`): a quarter of the memory, the same values.
/// Exactly one of the two is filled.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels, row-major, first row at the top; empty when
    /// `bytes` holds them.
    pub pixels: Vec<[f32; 4]>,
    /// `width × height` 8-bit pixels, row-major, first row at the top;
    /// empty when `pixels` holds them.
    pub bytes: Vec<[u8; 4]>,
}

impl Image {
    /// An image filled with one color.
    pub fn filled(width: u32, height: u32, color: [f32; 4]) -> Self {
        Image {
            width,
            height,
            pixels: vec![color; width as usize * height as usize],
            bytes: Vec::new(),
        }
    }

    /// An image of 8-bit pixels (`width × height`, rows top to bottom),
    /// held as they are.
    pub fn from_rgba8(width: u32, height: u32, bytes: Vec<[u8; 4]>) -> Self {
        Image {
            width,
            height,
            pixels: Vec::new(),
            bytes,
        }
    }

    /// The pixel at column `x`, row `y` (clamped to the image).
    #[inline]
    pub fn texel(&self, x: i64, y: i64) -> [f32; 4] {
        let xi = x.clamp(0, self.width as i64 - 1) as usize;
        let yi = y.clamp(0, self.height as i64 - 1) as usize;
        let i = yi * self.width as usize + xi;
        match self.bytes.get(i) {
            Some(b) => b.map(|c| f32::from(c) / 255.0),
            None => self.pixels[i],
        }
    }

    /// Bilinear lookup at texture coordinate `uv` with repeat wrapping, the
    /// glTF default sampler: u = 0 is the left edge, v = 0 the top row, and
    /// texel centers sit at half-integer positions.
    pub fn sample_bilinear(&self, uv: [f32; 2]) -> [f32; 4] {
        if self.width == 0 || self.height == 0 {
            return [0.0; 4];
        }
        let (w, h) = (self.width as f64, self.height as f64);
        let u = (uv[0] as f64).rem_euclid(1.0) * w - 0.5;
        let v = (uv[1] as f64).rem_euclid(1.0) * h - 0.5;
        let (x0, y0) = (u.floor(), v.floor());
        let (fx, fy) = ((u - x0) as f32, (v - y0) as f32);
        let wrap = |i: f64, n: u32| (i as i64).rem_euclid(n as i64);
        let (xa, xb) = (wrap(x0, self.width), wrap(x0 + 1.0, self.width));
        let (ya, yb) = (wrap(y0, self.height), wrap(y0 + 1.0, self.height));
        let (p00, p10, p01, p11) = (
            self.texel(xa, ya),
            self.texel(xb, ya),
            self.texel(xa, yb),
            self.texel(xb, yb),
        );
        let mut out = [0.0; 4];
        for k in 0..4 {
            let top = p00[k] + (p10[k] - p00[k]) * fx;
            let bottom = p01[k] + (p11[k] - p01[k]) * fx;
            out[k] = top + (bottom - top) * fy;
        }
        out
    }
}

/// An RGBA image with 8 bits per channel, rows top to bottom, for textures
/// that are baked from or into (a 8192² texture takes 256 MiB here, 1 GiB
/// as `f32`); [`Image`] is what metrics sample. Values are as stored: sRGB
/// stays sRGB.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rgba8Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels, row-major, first row at the top.
    pub pixels: Vec<[u8; 4]>,
}

impl Rgba8Image {
    /// An image filled with one color.
    pub fn filled(width: u32, height: u32, color: [u8; 4]) -> Self {
        Rgba8Image {
            width,
            height,
            pixels: vec![color; width as usize * height as usize],
        }
    }

    /// The pixel at column `x`, row `y`, or `None` outside the image.
    pub fn get(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        (x < self.width && y < self.height)
            .then(|| self.pixels[y as usize * self.width as usize + x as usize])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_blends_neighbouring_texel_centers() {
        // 2×1 image: black | white. u = 0.5 lies halfway between the centers.
        let img = Image {
            width: 2,
            height: 1,
            pixels: vec![[0.0; 4], [1.0; 4]],
            bytes: Vec::new(),
        };
        // The same image as bytes samples the same.
        let bytes = Image::from_rgba8(2, 1, vec![[0; 4], [255; 4]]);
        for u in [0.25, 0.5, 0.6, 0.75, 1.25] {
            assert_eq!(
                img.sample_bilinear([u, 0.5]),
                bytes.sample_bilinear([u, 0.5])
            );
        }
        assert_eq!(img.sample_bilinear([0.25, 0.5]), [0.0; 4]);
        assert_eq!(img.sample_bilinear([0.5, 0.5]), [0.5; 4]);
        assert_eq!(img.sample_bilinear([0.75, 0.5]), [1.0; 4]);
        // Repeat wrapping: u = 1.25 is u = 0.25.
        assert_eq!(img.sample_bilinear([1.25, 0.5]), [0.0; 4]);
    }
}
