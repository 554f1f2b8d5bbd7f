//! KTX2 textures with Basis Universal payloads (`KHR_texture_basisu`, what
//! `gltfpack -tc` and `toktx` write), transcoded to 8-bit RGBA for
//! metrics and re-baking by the pure-Rust `basisu` transcoder.
//!
//! Only the base level of a 2D texture is read: a re-bake samples the
//! input at its full resolution and filters it itself.

use basisu::{DecodeFlags, TargetFormat, Transcoder};
use wildlod_mesh::Rgba8Image;

/// The twelve bytes every KTX2 file starts with.
const MAGIC: [u8; 12] = [
    0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// Largest texel count decoded (a 16k × 16k texture, 1 GiB of RGBA): a
/// header declaring more is refused before anything is allocated.
const MAX_TEXELS: u64 = 1 << 28;

/// Whether `bytes` is a KTX2 file.
pub(crate) fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

/// The base level of a KTX2 Basis Universal texture (ETC1S or UASTC, any
/// supercompression) as 8-bit RGBA, values as stored (no color-space
/// conversion, as for PNG).
pub(crate) fn decode_rgba8(bytes: &[u8]) -> Result<Rgba8Image, String> {
    let t = Transcoder::new(bytes).map_err(|e| format!("KTX2 texture: {e:?}"))?;
    if t.face_count() != 1 || t.layer_count() > 1 {
        return Err("KTX2 texture: a cube map or texture array, not a 2D texture".into());
    }
    let (width, height) = t.base_dimensions();
    if width == 0 || height == 0 || u64::from(width) * u64::from(height) > MAX_TEXELS {
        return Err(format!("KTX2 texture of {width} × {height} texels"));
    }
    let raw = t
        .transcode(0, TargetFormat::Rgba32, DecodeFlags::NONE)
        .map_err(|e| format!("KTX2 texture: {e:?}"))?;
    let pixels: Vec<[u8; 4]> = raw
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect();
    if pixels.len() != width as usize * height as usize {
        return Err(format!(
            "KTX2 texture: {} texels transcoded for {width} × {height}",
            pixels.len()
        ));
    }
    Ok(Rgba8Image {
        width,
        height,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ktx2_texture_decodes_to_its_texels() {
        let colors = [
            [255, 0, 0, 255],
            [0, 255, 0, 255],
            [0, 0, 255, 128],
            [10, 20, 30, 40],
        ];
        let bytes = wildlod_testkit::ktx2::solid_astc(8, 8, &colors);
        assert!(is_ktx2(&bytes));
        let img = decode_rgba8(&bytes).expect("decodes");
        assert_eq!((img.width, img.height), (8, 8));
        for y in 0..8 {
            for x in 0..8 {
                let block = (y / 4) * 2 + x / 4;
                assert_eq!(img.pixels[y * 8 + x], colors[block], "texel {x}, {y}");
            }
        }
    }

    #[test]
    fn a_truncated_or_huge_ktx2_texture_is_an_error() {
        let bytes = wildlod_testkit::ktx2::solid_astc(8, 8, &[[0; 4]; 4]);
        assert!(decode_rgba8(&bytes[..100]).is_err());
        let mut huge = bytes.clone();
        huge[20..24].copy_from_slice(&100_000u32.to_le_bytes());
        huge[24..28].copy_from_slice(&100_000u32.to_le_bytes());
        assert!(decode_rgba8(&huge).is_err());
        assert!(!is_ktx2(b"\x89PNG\r\n\x1a\n0000"));
    }
}
