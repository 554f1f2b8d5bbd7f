//! Decoding texture images (PNG, JPEG) for metrics and re-baking.

use std::path::Path;

use wildlod_mesh::{Image, ImageSource};

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
/// is not a PNG or JPEG image.
pub fn decode_image(source: &ImageSource) -> Result<Image, Error> {
    match source {
        ImageSource::Path(p) => {
            let bytes = std::fs::read(p).map_err(|e| Error::new(p, ErrorKind::Io(e)))?;
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

fn decode_bytes(bytes: &[u8]) -> Result<Image, String> {
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    if reader.format().is_none() {
        return Err("not a PNG or JPEG image".into());
    }
    let decoded = reader.decode().map_err(|e| e.to_string())?;
    let rgba = decoded.to_rgba32f();
    let (width, height) = rgba.dimensions();
    let pixels = rgba
        .into_raw()
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect();
    Ok(Image {
        width,
        height,
        pixels,
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
        assert_eq!(img.pixels[0], [1.0, 0.0, 128.0 / 255.0, 1.0]);
        // 51/255 = 0.2 exactly in sRGB terms: no linearization happened.
        assert_eq!(img.pixels[1], [0.0, 0.2, 0.0, 0.0]);
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
    fn missing_file_names_the_path() {
        let e = decode_image(&ImageSource::Path("/nonexistent/wildlod/x.png".into()))
            .expect_err("missing");
        assert!(e.to_string().contains("/nonexistent/wildlod/x.png"), "{e}");
    }
}
