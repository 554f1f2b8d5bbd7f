//! GLB framing: a 12-byte header, a JSON chunk, an optional BIN chunk.
//! Every length is checked against the bytes actually present, so a header
//! that declares gigabytes fails before anything is allocated.

use crate::ErrorKind;

/// The magic bytes of a GLB file.
pub(crate) const MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// The chunks of a GLB file, borrowed from its bytes.
pub(crate) struct Glb<'a> {
    /// The JSON chunk.
    pub json: &'a [u8],
    /// The BIN chunk, when present.
    pub bin: Option<&'a [u8]>,
    /// Non-fatal oddities (trailing bytes, unknown chunks).
    pub warnings: Vec<String>,
}

fn u32_at(data: &[u8], at: usize) -> Option<u32> {
    let b = data.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB file into its chunks.
pub(crate) fn parse(data: &[u8]) -> Result<Glb<'_>, ErrorKind> {
    let header = |m: String| ErrorKind::malformed("GLB header", m);
    if data.len() < 12 {
        return Err(header(format!(
            "the file is {} bytes, shorter than the 12-byte header",
            data.len()
        )));
    }
    if &data[..4] != MAGIC {
        return Err(header(
            "the file does not start with the magic bytes 'glTF'".into(),
        ));
    }
    let version = u32_at(data, 4).unwrap_or(0);
    if version != 2 {
        return Err(ErrorKind::Unsupported(format!(
            "GLB header: version {version}; only glTF 2.0 is supported"
        )));
    }
    let declared = u32_at(data, 8).unwrap_or(0) as usize;
    let mut warnings = Vec::new();
    // A cut file is reported at the chunk it cuts, which says more than
    // the header's total length does.
    let truncated = declared > data.len();
    let note = if truncated {
        format!(
            " (the header declares {declared} bytes, the file has {}: truncated)",
            data.len()
        )
    } else {
        String::new()
    };
    if declared < data.len() {
        warnings.push(format!(
            "GLB header declares {declared} bytes; the {} bytes after that are ignored",
            data.len() - declared
        ));
    }
    let data = &data[..declared.min(data.len())];
    let mut at = 12usize;
    let mut json = None;
    let mut bin = None;
    let mut index = 0usize;
    while at < data.len() {
        let name = match (index, json.is_some()) {
            (0, _) => "JSON chunk".to_string(),
            (1, true) => "BIN chunk".to_string(),
            _ => format!("chunk {index}"),
        };
        let (Some(len), Some(kind)) = (u32_at(data, at), u32_at(data, at + 4)) else {
            return Err(ErrorKind::malformed(
                name,
                format!(
                    "its 8-byte header starts at byte {at}, but the file ends at byte {}{note}",
                    data.len()
                ),
            ));
        };
        let start = at + 8;
        let end = start.checked_add(len as usize).filter(|&e| e <= data.len());
        let Some(end) = end else {
            return Err(ErrorKind::malformed(
                name,
                format!(
                    "declares {len} bytes, but only {} remain in the file{note}",
                    data.len() - start
                ),
            ));
        };
        let body = &data[start..end];
        match (index, kind) {
            (0, CHUNK_JSON) => json = Some(body),
            (0, _) => {
                return Err(ErrorKind::malformed(
                    "JSON chunk",
                    format!("the first chunk has type {kind:#010x}, not JSON"),
                ))
            }
            (1, CHUNK_BIN) => bin = Some(body),
            (_, CHUNK_BIN) => warnings.push(format!("GLB chunk {index}: extra BIN chunk ignored")),
            (_, CHUNK_JSON) => {
                return Err(ErrorKind::malformed(name, "a second JSON chunk"));
            }
            // The specification tells readers to skip chunks they do not know.
            _ => warnings.push(format!(
                "GLB chunk {index}: unknown chunk type {kind:#010x} ignored"
            )),
        }
        // Chunks start on 4-byte boundaries; padding past the end is fine.
        at = end.div_ceil(4) * 4;
        index += 1;
    }
    let Some(json) = json else {
        return Err(ErrorKind::malformed(
            "JSON chunk",
            format!("missing: the file ends after the GLB header{note}"),
        ));
    };
    if truncated {
        return Err(header(format!(
            "declares a length of {declared} bytes, but the file has {} (truncated)",
            data.len()
        )));
    }
    Ok(Glb {
        json,
        bin,
        warnings,
    })
}

/// Builds a GLB file: the JSON padded with spaces and the BIN chunk with
/// zeros, each to a multiple of four bytes, as the specification requires.
pub(crate) fn build(json: &[u8], bin: &[u8]) -> Result<Vec<u8>, ErrorKind> {
    let json_len = json.len().div_ceil(4) * 4;
    let bin_len = bin.len().div_ceil(4) * 4;
    let total = 12 + 8 + json_len + if bin.is_empty() { 0 } else { 8 + bin_len };
    let too_big = || {
        ErrorKind::Unsupported(format!(
            "the GLB would be {total} bytes; the format is limited to 4 GiB"
        ))
    };
    let total32 = u32::try_from(total).map_err(|_| too_big())?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_glb_parses_back_with_padded_chunks() {
        let glb = build(br#"{"a":1}"#, &[1, 2, 3, 4, 5]).unwrap();
        assert_eq!(glb.len() % 4, 0);
        let g = parse(&glb).unwrap();
        assert_eq!(g.json, br#"{"a":1} "#);
        assert_eq!(g.bin.unwrap(), &[1, 2, 3, 4, 5, 0, 0, 0]);
        assert!(g.warnings.is_empty());
    }

    #[test]
    fn chunk_longer_than_file_is_an_error_naming_the_chunk() {
        let mut glb = build(b"{}  ", &[0; 8]).unwrap();
        // Claim a 4 GB BIN chunk.
        let bin_header = 12 + 8 + 4;
        glb[bin_header..bin_header + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = parse(&glb).err().unwrap().to_string();
        assert!(e.contains("BIN chunk"), "{e}");
        assert!(e.contains("4294967295"), "{e}");
    }

    #[test]
    fn header_declaring_more_than_the_file_is_an_error() {
        let mut glb = build(b"{}  ", &[]).unwrap();
        glb[8..12].copy_from_slice(&1000u32.to_le_bytes());
        let e = parse(&glb).err().unwrap().to_string();
        assert!(e.contains("GLB header") && e.contains("1000"), "{e}");
    }

    #[test]
    fn short_and_foreign_files_are_rejected() {
        assert!(parse(b"glTF").is_err());
        assert!(parse(b"PK\x03\x04 not a glb at all").is_err());
        let mut v1 = build(b"{}  ", &[]).unwrap();
        v1[4] = 1;
        assert!(matches!(parse(&v1), Err(ErrorKind::Unsupported(_))));
    }
}
