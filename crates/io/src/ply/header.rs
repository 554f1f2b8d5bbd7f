//! The PLY header: encoding, elements, their counts and property types.

use crate::obj::text::{show, split_keyword, tokens, trim, trim_start};
use crate::ErrorKind;

/// How the body is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Encoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &[u8]) -> Option<Scalar> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Bytes in binary encodings.
    pub(crate) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// Whether values are integers.
    pub(crate) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The inclusive range of an integer type.
    pub(crate) fn range(self) -> (f64, f64) {
        match self {
            Scalar::I8 => (i8::MIN as f64, i8::MAX as f64),
            Scalar::U8 => (0.0, u8::MAX as f64),
            Scalar::I16 => (i16::MIN as f64, i16::MAX as f64),
            Scalar::U16 => (0.0, u16::MAX as f64),
            Scalar::I32 => (i32::MIN as f64, i32::MAX as f64),
            Scalar::U32 => (0.0, u32::MAX as f64),
            Scalar::F32 | Scalar::F64 => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }
}

/// A property's type: one value, or a counted list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// One property of an element.
#[derive(Clone, Debug)]
pub(crate) struct Property {
    pub name: String,
    pub kind: Kind,
}

/// One element: a name, how many instances the body holds, their layout.
#[derive(Clone, Debug)]
pub(crate) struct Element {
    pub name: String,
    pub count: u64,
    pub properties: Vec<Property>,
}

impl Element {
    /// The fewest bytes one instance can take: binary lists may be empty;
    /// ASCII values take at least a character and a separator.
    fn min_bytes(&self, encoding: Encoding) -> u64 {
        self.properties
            .iter()
            .map(|p| match (encoding, p.kind) {
                (Encoding::Ascii, _) => 2,
                (_, Kind::Scalar(s)) => s.size() as u64,
                (_, Kind::List { count, .. }) => count.size() as u64,
            })
            .sum()
    }

    /// The error location of instance `index`.
    pub(crate) fn at(&self, index: u64) -> String {
        format!("PLY element '{}' {index}", self.name)
    }
}

/// A parsed header and where the body starts.
#[derive(Debug)]
pub(crate) struct Header {
    pub encoding: Encoding,
    pub elements: Vec<Element>,
    pub body: usize,
}

/// Parses the header, and checks that the body can hold the declared
/// counts before anything is allocated for them.
pub(crate) fn parse(data: &[u8]) -> Result<Header, ErrorKind> {
    let mut pos = 0;
    let mut line_no = 0;
    let mut next_line = || -> Option<(usize, &[u8])> {
        let rest = data.get(pos..).filter(|r| !r.is_empty())?;
        let (line, adv) = match rest.iter().position(|&b| b == b'\n') {
            Some(e) => (&rest[..e], e + 1),
            None => (rest, rest.len()),
        };
        pos += adv;
        line_no += 1;
        Some((line_no, line.strip_suffix(b"\r").unwrap_or(line)))
    };
    match next_line() {
        Some((_, l)) if trim(l) == b"ply" => {}
        _ => {
            return Err(ErrorKind::malformed(
                "PLY header",
                "the file does not start with the line 'ply'",
            ))
        }
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some((ln, line)) = next_line() else {
            return Err(ErrorKind::malformed(
                "PLY header",
                "the file ends before 'end_header'",
            ));
        };
        let (kw, rest) = split_keyword(trim_start(line));
        let syntax = |msg: String| ErrorKind::syntax(ln, format!("PLY header: {msg}"));
        let args: Vec<&[u8]> = tokens(rest).collect();
        match kw {
            b"" | b"comment" | b"obj_info" => {}
            b"format" => {
                let e = match args.first().copied() {
                    Some(b"ascii") => Encoding::Ascii,
                    Some(b"binary_little_endian") => Encoding::BinaryLittleEndian,
                    Some(b"binary_big_endian") => Encoding::BinaryBigEndian,
                    other => {
                        return Err(syntax(format!(
                            "unknown format '{}' (expected ascii, binary_little_endian or binary_big_endian)",
                            show(other.unwrap_or_default())
                        )))
                    }
                };
                match args.get(1).copied() {
                    Some(b"1.0") | Some(b"1") => {}
                    v => {
                        return Err(syntax(format!(
                            "unsupported format version '{}' (expected 1.0)",
                            show(v.unwrap_or_default())
                        )))
                    }
                }
                encoding = Some(e);
            }
            b"element" => {
                let [name, count] = args[..] else {
                    return Err(syntax("'element' needs a name and a count".into()));
                };
                let count = std::str::from_utf8(count)
                    .ok()
                    .and_then(|c| c.parse::<u64>().ok())
                    .ok_or_else(|| {
                        syntax(format!("element count '{}' is not a number", show(count)))
                    })?;
                elements.push(Element {
                    name: String::from_utf8_lossy(name).into_owned(),
                    count,
                    properties: Vec::new(),
                });
            }
            b"property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(syntax("'property' before any 'element'".into()));
                };
                let ty = |t: &[u8]| {
                    Scalar::parse(t).ok_or_else(|| syntax(format!("unknown type '{}'", show(t))))
                };
                let (kind, name) = match args[..] {
                    [b"list", count, item, name] => {
                        let count = ty(count)?;
                        if !count.is_integer() {
                            return Err(syntax("a list count must have an integer type".into()));
                        }
                        (
                            Kind::List {
                                count,
                                item: ty(item)?,
                            },
                            name,
                        )
                    }
                    [t, name] if t != b"list" => (Kind::Scalar(ty(t)?), name),
                    _ => {
                        return Err(syntax(
                            "expected 'property <type> <name>' or 'property list <count type> <item type> <name>'"
                                .into(),
                        ))
                    }
                };
                element.properties.push(Property {
                    name: String::from_utf8_lossy(name).into_owned(),
                    kind,
                });
            }
            b"end_header" => break,
            other => return Err(syntax(format!("unknown keyword '{}'", show(other)))),
        }
    }
    let Some(encoding) = encoding else {
        return Err(ErrorKind::malformed("PLY header", "no 'format' line"));
    };
    let header = Header {
        encoding,
        elements,
        body: pos,
    };
    check_counts(&header, data.len())?;
    Ok(header)
}

/// Refuses counts the body cannot hold, so that a header declaring
/// billions of vertices in a small file fails before allocating.
fn check_counts(h: &Header, len: usize) -> Result<(), ErrorKind> {
    let mut remaining = len.saturating_sub(h.body) as u64;
    if h.encoding == Encoding::Ascii {
        // The last value needs no separator after it.
        remaining += 1;
    }
    for e in &h.elements {
        let min = e.min_bytes(h.encoding);
        if min == 0 {
            continue;
        }
        let need = (min as u128) * (e.count as u128);
        if need > remaining as u128 {
            return Err(ErrorKind::ImplausibleCount {
                element: format!("PLY element '{}'", e.name),
                count: e.count,
                max: remaining / min,
            });
        }
        remaining -= need as u64;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn body_starts_after_the_end_header_line() {
        let data = b"ply\r\nformat binary_little_endian 1.0\r\nelement vertex 1\r\nproperty float x\r\nend_header\r\n\x00\x00\x80\x3f";
        let h = parse(data).unwrap();
        assert_eq!(h.encoding, Encoding::BinaryLittleEndian);
        assert_eq!(h.body, data.len() - 4);
        assert_eq!(h.elements[0].count, 1);
    }

    #[test]
    fn list_needs_an_integer_count_type() {
        let data = b"ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n";
        assert!(matches!(
            parse(data),
            Err(ErrorKind::Syntax { line: 4, .. })
        ));
    }
}
