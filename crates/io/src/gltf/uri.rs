//! glTF URIs: `data:` URIs, percent-encoding, and where a relative URI
//! points on disk.

use std::path::{Component, Path, PathBuf};

use base64::engine::general_purpose::{GeneralPurpose, GeneralPurposeConfig};
use base64::engine::DecodePaddingMode;
use base64::Engine;

/// Base64 as glTF writers emit it: standard alphabet, with or without the
/// trailing `=` (both occur in the wild and neither is ambiguous).
const BASE64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
);

/// What a glTF `uri` refers to.
pub(crate) enum UriKind<'a> {
    /// `data:<mime>;base64,<payload>`.
    Data {
        /// MIME type, possibly empty.
        mime: &'a str,
        /// The base64 payload, or `None` when the URI is not base64.
        base64: Option<&'a str>,
    },
    /// A URI with a scheme (`http:`, `file:`…): not read.
    Remote,
    /// A path relative to the glTF file, percent-decoded.
    Relative(String),
}

/// Classifies a URI.
pub(crate) fn classify(uri: &str) -> UriKind<'_> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, payload) = rest.split_once(',').unwrap_or((rest, ""));
        let (mime, is_base64) = match header.strip_suffix(";base64") {
            Some(m) => (m, true),
            None => (header, false),
        };
        return UriKind::Data {
            mime,
            base64: is_base64.then_some(payload),
        };
    }
    if has_scheme(uri) {
        return UriKind::Remote;
    }
    UriKind::Relative(percent_decode(uri))
}

/// Decodes a base64 payload, tolerating whitespace some writers wrap it in.
pub(crate) fn decode_base64(payload: &str) -> Result<Vec<u8>, String> {
    let result = if payload.bytes().any(|b| b.is_ascii_whitespace()) {
        let compact: String = payload
            .chars()
            .filter(|c| !c.is_ascii_whitespace())
            .collect();
        BASE64.decode(compact)
    } else {
        BASE64.decode(payload)
    };
    result.map_err(|e| format!("the data URI is not valid base64 ({e})"))
}

/// RFC 3986 scheme followed by `:`, at least two characters long so that a
/// Windows drive letter (`C:\…`) is not mistaken for one.
fn has_scheme(uri: &str) -> bool {
    let Some((scheme, _)) = uri.split_once(':') else {
        return false;
    };
    scheme.len() >= 2
        && scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// Decodes `%XX` escapes; malformed escapes are kept literally, as browsers do.
pub(crate) fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Percent-encodes a relative path for a URI: path separators stay, every
/// byte outside RFC 3986's unreserved set is escaped.
pub(crate) fn percent_encode_path(path: &Path) -> String {
    let parts: Vec<String> = path
        .components()
        .filter_map(|c| match c {
            Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
            Component::ParentDir => Some("..".to_string()),
            _ => None,
        })
        .collect();
    let mut out = String::new();
    for (i, part) in parts.iter().enumerate() {
        if i > 0 {
            out.push('/');
        }
        for b in part.bytes() {
            if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.' | b'~') {
                out.push(b as char);
            } else {
                out.push_str(&format!("%{b:02X}"));
            }
        }
    }
    out
}

/// A relative path made only of normal components: it stays inside the
/// directory it is resolved against. `None` for `..`, absolute paths or
/// Windows prefixes.
pub(crate) fn contained_relative(rel: &str) -> Option<PathBuf> {
    // Windows exporters write backslashes; a URI means '/'.
    let rel = rel.replace('\\', "/");
    let p = Path::new(&rel);
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::Normal(s) => out.push(s),
            Component::CurDir => {}
            _ => return None,
        }
    }
    (!out.as_os_str().is_empty()).then_some(out)
}

/// Resolves a decoded relative URI against the glTF file's directory.
pub(crate) fn resolve(dir: &Path, rel: &str) -> PathBuf {
    let rel = rel.replace('\\', "/");
    let joined = dir.join(rel);
    // Lexically drop `.` and fold `..` so that paths compare equal when the
    // files do not exist (yet).
    let mut out = PathBuf::new();
    for c in joined.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

/// MIME type of an encoded image, from its magic bytes.
pub(crate) fn sniff_image_mime(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        Some("image/webp")
    } else if bytes.starts_with(b"\xABKTX 20\xBB\r\n\x1A\n") {
        Some("image/ktx2")
    } else {
        None
    }
}

/// MIME type of an image file from its extension.
pub(crate) fn mime_from_extension(path: &Path) -> Option<&'static str> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    Some(match ext.as_str() {
        "png" => "image/png",
        "jpg" | "jpeg" => "image/jpeg",
        "webp" => "image/webp",
        "ktx2" => "image/ktx2",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uri_round_trips_and_non_base64_is_recognized() {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            BASE64.encode([0, 1, 2, 250])
        );
        let UriKind::Data { mime, base64 } = classify(&uri) else {
            panic!("not a data URI");
        };
        assert_eq!(mime, "application/octet-stream");
        assert_eq!(decode_base64(base64.unwrap()).unwrap(), vec![0, 1, 2, 250]);
        assert!(matches!(
            classify("data:text/plain,hello"),
            UriKind::Data { base64: None, .. }
        ));
        assert!(decode_base64("not base64!").is_err());
    }

    #[test]
    fn percent_escapes_decode_and_paths_encode() {
        assert_eq!(percent_decode("a%20b%2Fc%zz%4"), "a b/c%zz%4");
        assert_eq!(
            percent_encode_path(Path::new("tex dir/ä.png")),
            "tex%20dir/%C3%A4.png"
        );
    }

    #[test]
    fn schemes_are_remote_but_drive_letters_are_not() {
        assert!(matches!(classify("https://x/y.bin"), UriKind::Remote));
        assert!(matches!(classify("C:\\x.bin"), UriKind::Relative(_)));
        assert!(matches!(classify("sub/x.bin"), UriKind::Relative(_)));
    }

    #[test]
    fn only_contained_relative_paths_are_accepted() {
        assert_eq!(
            contained_relative("./textures\\a.png"),
            Some(PathBuf::from("textures/a.png"))
        );
        assert_eq!(contained_relative("../a.png"), None);
        assert_eq!(contained_relative("/etc/a.png"), None);
        assert_eq!(
            resolve(Path::new("/m/x"), "../t/./a.png"),
            PathBuf::from("/m/t/a.png")
        );
    }
}
