//! KTX2 textures made in code: no encoder is needed for constant-color
//! ASTC blocks, which every KTX2 reader decodes exactly.

/// The twelve bytes every KTX2 file starts with.
const MAGIC: [u8; 12] = [
    0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// A KTX2 file of raw ASTC 4×4 LDR blocks, each a constant-color
/// ("void-extent") block of `colors[block]` (blocks in rows), `width` ×
/// `height` texels (multiples of 4): a texture any KTX2 reader decodes
/// exactly (the Basis Universal transcoder reads raw ASTC sources too).
pub fn solid_astc(width: u32, height: u32, colors: &[[u8; 4]]) -> Vec<u8> {
    const ASTC_4X4_UNORM: u32 = 157;
    const MODEL_ASTC: u32 = 162;
    const TRANSFER_LINEAR: u32 = 1;
    let mut level = Vec::new();
    for c in colors {
        // Void-extent marker, LDR, no extent; then RGBA as UNORM16.
        level.extend_from_slice(&[0xFC, 0xFD, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]);
        for &v in c {
            level.extend_from_slice(&(u16::from(v) * 257).to_le_bytes());
        }
    }
    let dfd_offset: usize = 80 + 24;
    let dfd: Vec<u32> = vec![
        44,
        0,
        2 | (40 << 16),
        MODEL_ASTC | (1 << 8) | (TRANSFER_LINEAR << 16),
        3 | (3 << 8),
        16,
        0,
        // One sample: bits 0..127, channel RGBA (15 would be "data").
        127 << 16,
        0,
        0,
        u32::MAX,
    ];
    let level_offset = (dfd_offset + 44).next_multiple_of(16);
    let mut out = Vec::new();
    out.extend_from_slice(&MAGIC);
    for word in [
        ASTC_4X4_UNORM,
        1,
        width,
        height,
        0,
        0,
        1,
        1,
        0,
        dfd_offset as u32,
        44,
        0,
        0,
    ] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    for long in [
        0u64,
        0,
        level_offset as u64,
        level.len() as u64,
        level.len() as u64,
    ] {
        out.extend_from_slice(&long.to_le_bytes());
    }
    for word in dfd {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.resize(level_offset, 0);
    out.extend_from_slice(&level);
    out
}
