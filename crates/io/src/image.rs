//! Decoding texture images (PNG, JPEG, WebP, and KTX2 with Basis
//! Universal payloads) for metrics and re-baking.

use std::path::Path;

use wildlod_mesh::{Image, ImageSource, Rgba8Image};

use crate::{Error, ErrorKind};

/// Decodes a texture's image into RGBA `f32` channels in [0, 1], as stored
/// in the file: 8-bit values are divided by 255, 16-bit by 65535, and no
/// color-space conversion is applied (sRGB stays sRGB). Gray and RGB
/// images get alpha 1.
///
/// The `image` crate's default limits apply, so a header declaring a
/// gigapixel image fails instead of allocating.
///
/// # Errors
/// An error naming the file (or "embedded image") when it cannot be read or
/// is not a PNG, JPEG, WebP or KTX2 (Basis Universal) image.
pub fn decode_image(source: &ImageSource) -> Result<Image, Error> {
    match source {
        ImageSource::Path(p) => {
            let bytes =
                crate::regular::read(p, crate::MAX_FILE_BYTES).map_err(|e| Error::new(p, e))?;
            decode_bytes(&bytes).map_err(|m| Error::new(p, ErrorKind::malformed("image", m)))
        }
        ImageSource::Embedded { bytes, mime_type } => decode_bytes(bytes).map_err(|m| {
            Error::new(
                Path::new("embedded image"),
                ErrorKind::malformed(format!("image ({mime_type})"), m),
            )
        }),
    }
}

/// Decodes a texture's image into 8-bit RGBA, as stored (no color-space
/// conversion; 16-bit channels are rounded to 8 bits, gray and RGB get
/// alpha 255): a quarter of [`decode_image`]'s memory, for re-baking.
///
/// # Errors
/// As [`decode_image`].
pub fn decode_image_rgba8(source: &ImageSource) -> Result<Rgba8Image, Error> {
    match source {
        ImageSource::Path(p) => {
            let bytes = std::fs::read(p).map_err(|e| Error::new(p, ErrorKind::Io(e)))?;
            decode_rgba8(&bytes).map_err(|m| Error::new(p, ErrorKind::malformed("image", m)))
        }
        ImageSource::Embedded { bytes, mime_type } => decode_rgba8(bytes).map_err(|m| {
            Error::new(
                Path::new("embedded image"),
                ErrorKind::malformed(format!("image ({mime_type})"), m),
            )
        }),
    }
}

fn decode_rgba8(bytes: &[u8]) -> Result<Rgba8Image, String> {
    if crate::ktx2::is_ktx2(bytes) {
        return crate::ktx2::decode_rgba8(bytes);
    }
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    if reader.format().is_none() {
        return Err("not a PNG, JPEG, WebP or KTX2 image".into());
    }
    let rgba = reader.decode().map_err(|e| e.to_string())?.into_rgba8();
    let (width, height) = rgba.dimensions();
    let pixels = rgba
        .into_raw()
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect();
    Ok(Rgba8Image {
        width,
        height,
        pixels,
    })
}

/// How [`encode_image`] stores an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageEncoding {
    /// Lossless PNG, with alpha.
    Png,
    /// JPEG at a quality from 1 to 100 (alpha dropped).
    Jpeg {
        /// 1 (smallest) to 100 (best).
        quality: u8,
    },
}

impl ImageEncoding {
    /// The MIME type of the encoded bytes.
    pub fn mime_type(&self) -> &'static str {
        match self {
            ImageEncoding::Png => "image/png",
            ImageEncoding::Jpeg { .. } => "image/jpeg",
        }
    }
}

/// Encodes an 8-bit RGBA image as PNG (RGBA, or RGB when every alpha is
/// 255) or JPEG.
///
/// # Errors
/// [`ErrorKind::Unsupported`] when the image is empty or the encoder fails
/// (`name` says which image).
pub fn encode_image(
    img: &Rgba8Image,
    encoding: ImageEncoding,
    name: &str,
) -> Result<Vec<u8>, Error> {
    let fail = |m: String| Error::new(Path::new(name), ErrorKind::Unsupported(m));
    if img.width == 0
        || img.height == 0
        || img.pixels.len() != img.width as usize * img.height as usize
    {
        return Err(fail(format!(
            "cannot encode a {}×{} image",
            img.width, img.height
        )));
    }
    let opaque = img.pixels.iter().all(|p| p[3] == 255);
    let mut out = std::io::Cursor::new(Vec::new());
    let result = match encoding {
        ImageEncoding::Png if !opaque => {
            let raw: Vec<u8> = img.pixels.iter().flatten().copied().collect();
            image::RgbaImage::from_raw(img.width, img.height, raw)
                .ok_or_else(|| fail("image size mismatch".into()))?
                .write_to(&mut out, image::ImageFormat::Png)
        }
        ImageEncoding::Png => rgb(img)
            .ok_or_else(|| fail("image size mismatch".into()))?
            .write_to(&mut out, image::ImageFormat::Png),
        ImageEncoding::Jpeg { quality } => {
            let rgb = rgb(img).ok_or_else(|| fail("image size mismatch".into()))?;
            let enc =
                image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, quality.clamp(1, 100));
            rgb.write_with_encoder(enc)
        }
    };
    result.map_err(|e| fail(e.to_string()))?;
    Ok(out.into_inner())
}

fn rgb(img: &Rgba8Image) -> Option<image::RgbImage> {
    let raw: Vec<u8> = img.pixels.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    image::RgbImage::from_raw(img.width, img.height, raw)
}

fn decode_bytes(bytes: &[u8]) -> Result<Image, String> {
    if crate::ktx2::is_ktx2(bytes) {
        let rgba = crate::ktx2::decode_rgba8(bytes)?;
        return Ok(Image::from_rgba8(rgba.width, rgba.height, rgba.pixels));
    }
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    if reader.format().is_none() {
        return Err("not a PNG, JPEG, WebP or KTX2 image".into());
    }
    let decoded = reader.decode().map_err(|e| e.to_string())?;
    let (width, height) = (decoded.width(), decoded.height());
    // One byte a channel (PNG, JPEG and WebP mostly) stays bytes; deeper
    // files become one `f32` buffer straight from the decoder's own depth.
    let pixels = match decoded {
        image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_) => {
            decoded.into_rgba32f().pixels().map(|p| p.0).collect()
        }
        d if d.color().bytes_per_pixel() == d.color().channel_count() => {
            let bytes = d.into_rgba8().pixels().map(|p| p.0).collect();
            return Ok(Image::from_rgba8(width, height, bytes));
        }
        d => d
            .into_rgba16()
            .pixels()
            .map(|p| p.0.map(|c| f32::from(c) / 65535.0))
            .collect(),
    };
    Ok(Image {
        width,
        height,
        pixels,
        bytes: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(pixels: &[[u8; 4]], width: u32) -> Vec<u8> {
        let height = pixels.len() as u32 / width;
        let raw: Vec<u8> = pixels.iter().flatten().copied().collect();
        let img = image::RgbaImage::from_raw(width, height, raw).expect("size matches");
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .expect("encode png");
        out.into_inner()
    }

    #[test]
    fn png_pixels_become_unit_floats_without_color_conversion() {
        let bytes = png(&[[255, 0, 128, 255], [0, 51, 0, 0]], 2);
        let img = decode_image(&ImageSource::Embedded {
            bytes,
            mime_type: "image/png".into(),
        })
        .expect("decodes");
        assert_eq!((img.width, img.height), (2, 1));
        assert_eq!(img.texel(0, 0), [1.0, 0.0, 128.0 / 255.0, 1.0]);
        // 51/255 = 0.2 exactly in sRGB terms: no linearization happened.
        assert_eq!(img.texel(1, 0), [0.0, 0.2, 0.0, 0.0]);
        // Held as the file's bytes: a quarter of the memory.
        assert!(img.pixels.is_empty() && img.bytes.len() == 2);
    }

    /// `img` written as a PNG and decoded back.
    fn through_png(img: image::DynamicImage) -> Image {
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .expect("encode png");
        decode_image(&ImageSource::Embedded {
            bytes: out.into_inner(),
            mime_type: "image/png".into(),
        })
        .expect("decodes")
    }

    #[test]
    fn sixteen_bit_and_gray_pngs_keep_their_depth_and_fill_rgba() {
        // A 16-bit RGB PNG: channels over 65535, alpha 1.
        let rgb16 = image::ImageBuffer::<image::Rgb<u16>, Vec<u16>>::from_raw(
            2,
            1,
            vec![65535, 1, 32768, 0, 13107, 0],
        )
        .expect("buffer");
        let img = through_png(image::DynamicImage::ImageRgb16(rgb16));
        assert_eq!(
            img.texel(0, 0),
            [1.0, 1.0 / 65535.0, 32768.0 / 65535.0, 1.0]
        );
        assert_eq!(img.texel(1, 0), [0.0, 0.2, 0.0, 1.0]);
        // An 8-bit gray PNG: gray in R, G and B.
        let gray = image::GrayImage::from_raw(1, 1, vec![51]).expect("buffer");
        let img = through_png(image::DynamicImage::ImageLuma8(gray));
        assert_eq!(img.texel(0, 0), [0.2, 0.2, 0.2, 1.0]);
    }

    #[test]
    fn webp_textures_decode_like_png() {
        // Lossless WebP (EXT_texture_webp's images): the same pixels as
        // the PNG of them, for metrics and for re-baking.
        let pixels = [
            [255, 0, 128, 255],
            [0, 51, 0, 255],
            [9, 8, 7, 255],
            [1, 2, 3, 255],
        ];
        let raw: Vec<u8> = pixels.iter().flatten().copied().collect();
        let mut webp = Vec::new();
        image::codecs::webp::WebPEncoder::new_lossless(&mut webp)
            .encode(&raw, 2, 2, image::ExtendedColorType::Rgba8)
            .expect("encode webp");
        let source = ImageSource::Embedded {
            bytes: webp,
            mime_type: "image/webp".into(),
        };
        let img = decode_image_rgba8(&source).expect("decodes");
        assert_eq!((img.width, img.height), (2, 2));
        assert_eq!(img.pixels, pixels.to_vec());
        let png_source = ImageSource::Embedded {
            bytes: png(&pixels, 2),
            mime_type: "image/png".into(),
        };
        assert_eq!(
            decode_image(&source).expect("decodes"),
            decode_image(&png_source).expect("decodes")
        );
    }

    #[test]
    fn undecodable_bytes_name_the_embedded_image() {
        let e = decode_image(&ImageSource::Embedded {
            bytes: b"definitely not an image".to_vec(),
            mime_type: "image/png".into(),
        })
        .expect_err("garbage");
        let s = e.to_string();
        assert!(s.starts_with("embedded image"), "{s}");
    }

    #[test]
    fn png_round_trip_keeps_8_bit_pixels_and_alpha() {
        let img = Rgba8Image {
            width: 2,
            height: 1,
            pixels: vec![[255, 0, 128, 255], [1, 2, 3, 4]],
        };
        let bytes = encode_image(&img, ImageEncoding::Png, "t").expect("encodes");
        let back = decode_image_rgba8(&ImageSource::Embedded {
            bytes,
            mime_type: "image/png".into(),
        })
        .expect("decodes");
        assert_eq!(back, img);
    }

    #[test]
    fn jpeg_round_trip_is_close_and_opaque() {
        let img = Rgba8Image::filled(16, 16, [200, 100, 50, 255]);
        let bytes = encode_image(&img, ImageEncoding::Jpeg { quality: 95 }, "t").expect("encodes");
        assert_eq!(&bytes[..2], &[0xFF, 0xD8]);
        let back = decode_image_rgba8(&ImageSource::Embedded {
            bytes,
            mime_type: "image/jpeg".into(),
        })
        .expect("decodes");
        for p in &back.pixels {
            for k in 0..3 {
                assert!((p[k] as i32 - img.pixels[0][k] as i32).abs() <= 3, "{p:?}");
            }
            assert_eq!(p[3], 255);
        }
    }

    #[test]
    fn missing_file_names_the_path() {
        let e = decode_image(&ImageSource::Path("/nonexistent/wildlod/x.png".into()))
            .expect_err("missing");
        assert!(e.to_string().contains("/nonexistent/wildlod/x.png"), "{e}");
    }
}
