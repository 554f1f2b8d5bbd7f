//! Byte-level scanning shared by the text readers (OBJ, MTL, ASCII PLY,
//! ASCII STL): numbered lines, whitespace tokens and numbers, without an
//! allocation per line or token.
//!
//! The readers work on bytes rather than `str` because real files carry
//! Latin-1 names and comments that are not UTF-8; only tokens that must be
//! numbers are converted, and names are decoded lossily.

/// Lines of a text file with their 1-based numbers. `\n` and `\r\n` both
/// end a line. With `continuations`, a line ending in a backslash is joined
/// with the next one (OBJ and MTL allow this) and reported under the number
/// of its first line.
pub(crate) struct Lines<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
    continuations: bool,
    joined: Vec<u8>,
}

impl<'a> Lines<'a> {
    /// Lines of `data`.
    pub(crate) fn new(data: &'a [u8], continuations: bool) -> Self {
        Lines {
            data,
            pos: 0,
            line: 0,
            continuations,
            joined: Vec::new(),
        }
    }

    fn raw_line(&mut self) -> Option<&'a [u8]> {
        let rest = self.data.get(self.pos..).filter(|r| !r.is_empty())?;
        let (line, advance) = match rest.iter().position(|&b| b == b'\n') {
            Some(end) => (&rest[..end], end + 1),
            None => (rest, rest.len()),
        };
        self.pos += advance;
        self.line += 1;
        Some(line.strip_suffix(b"\r").unwrap_or(line))
    }

    /// The next line without its terminator, and its number.
    pub(crate) fn next_line(&mut self) -> Option<(usize, &[u8])> {
        let first = self.raw_line()?;
        let number = self.line;
        if !self.continuations || !trim_end(first).ends_with(b"\\") {
            return Some((number, first));
        }
        self.joined.clear();
        let mut current = first;
        loop {
            match trim_end(current).strip_suffix(b"\\") {
                Some(body) => {
                    self.joined.extend_from_slice(body);
                    self.joined.push(b' ');
                    match self.raw_line() {
                        Some(next) => current = next,
                        None => break,
                    }
                }
                None => {
                    self.joined.extend_from_slice(current);
                    break;
                }
            }
        }
        Some((number, &self.joined))
    }
}

/// Whitespace as the text formats mean it: space, tab, CR, LF, form feed,
/// vertical tab.
#[inline]
pub(crate) fn is_space(b: u8) -> bool {
    b.is_ascii_whitespace() || b == 0x0b
}

/// `s` without leading whitespace.
#[inline]
pub(crate) fn trim_start(s: &[u8]) -> &[u8] {
    let n = s.iter().take_while(|&&b| is_space(b)).count();
    &s[n..]
}

/// `s` without trailing whitespace.
#[inline]
pub(crate) fn trim_end(s: &[u8]) -> &[u8] {
    let n = s.iter().rev().take_while(|&&b| is_space(b)).count();
    &s[..s.len() - n]
}

/// `s` without surrounding whitespace.
#[inline]
pub(crate) fn trim(s: &[u8]) -> &[u8] {
    trim_end(trim_start(s))
}

/// Splits a (left-trimmed) line into its first token and the rest.
#[inline]
pub(crate) fn split_keyword(line: &[u8]) -> (&[u8], &[u8]) {
    match line.iter().position(|&b| is_space(b)) {
        Some(i) => (&line[..i], &line[i..]),
        None => (line, &[]),
    }
}

/// The whitespace-separated tokens of `s`.
#[inline]
pub(crate) fn tokens(s: &[u8]) -> impl Iterator<Item = &[u8]> {
    s.split(|&b| is_space(b)).filter(|t| !t.is_empty())
}

/// `s` up to a `#` comment.
#[inline]
pub(crate) fn cut_comment(s: &[u8]) -> &[u8] {
    match s.iter().position(|&b| b == b'#') {
        Some(i) => &s[..i],
        None => s,
    }
}

/// A token for an error message: decoded lossily and shortened, so that a
/// binary blob does not become a megabyte of message.
pub(crate) fn show(tok: &[u8]) -> String {
    const MAX: usize = 40;
    let s = String::from_utf8_lossy(&tok[..tok.len().min(MAX)]);
    let s: String = s
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    if tok.len() > MAX {
        format!("{s}…")
    } else {
        s
    }
}

/// A name (object, group, material, solid) as written in the file: trimmed,
/// lossily decoded.
pub(crate) fn name(s: &[u8]) -> String {
    String::from_utf8_lossy(trim(s)).into_owned()
}

/// Parses a finite `f32` directly from its decimal text (no detour through
/// `f64`, which could round twice), so that text written with the shortest
/// round-trip representation reads back bit-exactly. The error says what is
/// wrong with the token.
#[inline]
pub(crate) fn parse_f32(tok: &[u8]) -> Result<f32, String> {
    parse_finite(tok, f32::is_finite)
}

/// Like [`parse_f32`] for `f64`.
#[inline]
pub(crate) fn parse_f64(tok: &[u8]) -> Result<f64, String> {
    parse_finite(tok, f64::is_finite)
}

#[inline]
fn parse_finite<T: std::str::FromStr + Copy>(
    tok: &[u8],
    finite: fn(T) -> bool,
) -> Result<T, String> {
    let v: T = std::str::from_utf8(tok)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| format!("'{}' is not a number", show(tok)))?;
    if finite(v) {
        Ok(v)
    } else {
        Err(format!("'{}' is not a finite number", show(tok)))
    }
}

/// Parses a decimal integer with an optional sign; `None` when the token is
/// not one or does not fit an `i64`.
#[inline]
pub(crate) fn parse_i64(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok.first()? {
        b'-' => (true, &tok[1..]),
        b'+' => (false, &tok[1..]),
        _ => (false, tok),
    };
    if digits.is_empty() {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v.checked_mul(10)?.checked_sub((d - b'0') as i64)?;
    }
    // Accumulated negatively so that i64::MIN parses too.
    if neg {
        Some(v)
    } else {
        v.checked_neg()
    }
}

/// Texture coordinate v as the model holds it, from v as OBJ and PLY store
/// it. Those formats put v = 0 at the bottom of the image; the model, like
/// glTF, at the top (see `wildlod_mesh::Image::sample_bilinear`), so a
/// texture looks the same whichever format the mesh came from.
#[inline]
pub(crate) fn v_from_file(v: f64) -> f32 {
    (1.0 - v) as f32
}

/// The text of a file v that [`v_from_file`] reads back to exactly `v`, so
/// that an unchanged mesh round-trips bit for bit. The shortest `f32` text
/// of 1 − v usually does; the exact `f64` text of 1 − v does for all but
/// nonzero |v| < 2⁻²⁹, where the nearest is written.
pub(crate) fn v_to_text(v: f32) -> String {
    let reads_back = |t: &str| {
        t.parse::<f64>()
            .is_ok_and(|x| v_from_file(x).to_bits() == v.to_bits())
    };
    let short = format!("{}", v_from_file(v as f64));
    if reads_back(&short) {
        return short;
    }
    let exact = format!("{}", 1.0 - v as f64);
    if reads_back(&exact) {
        exact
    } else {
        short
    }
}

/// A 32-bit file v that [`v_from_file`] reads back to exactly `v` (binary
/// PLY). Every model v read from such a file has one among the nearest
/// floats to 1 − v; other values get the nearest.
pub(crate) fn v_to_f32(v: f32) -> f32 {
    let t = v_from_file(v as f64);
    let bits = t.to_bits();
    [bits, bits.wrapping_add(1), bits.wrapping_sub(1)]
        .into_iter()
        .map(f32::from_bits)
        .find(|c| c.is_finite() && v_from_file(*c as f64).to_bits() == v.to_bits())
        .unwrap_or(t)
}

/// Whether a 32-bit file v can give back exactly `v` ([`v_to_f32`] finds
/// one). It cannot for most v below 0.5 or outside [0, 1] that did not come
/// from a 32-bit file: their 1 − v needs more bits than `f32` has. The exact 64-bit `1 − v`
/// can for every v but nonzero |v| < 2⁻²⁹, as OBJ text can.
pub(crate) fn v_fits_f32(v: f32) -> bool {
    v_from_file(v_to_f32(v) as f64).to_bits() == v.to_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_strip_crlf_and_join_continuations_under_first_number() {
        let mut l = Lines::new(b"a\r\nf 1 2 \\\n 3\nlast", true);
        assert_eq!(l.next_line(), Some((1, &b"a"[..])));
        let (n, s) = l.next_line().unwrap();
        assert_eq!((n, trim(s)), (2, &b"f 1 2   3"[..]));
        assert_eq!(l.next_line(), Some((4, &b"last"[..])));
        assert_eq!(l.next_line(), None);
    }

    #[test]
    fn continuation_at_end_of_file_ends_the_line() {
        let mut l = Lines::new(b"g a \\", true);
        assert_eq!(
            l.next_line().map(|(n, s)| (n, trim(s).to_vec())),
            Some((1, b"g a".to_vec()))
        );
        assert_eq!(l.next_line(), None);
    }

    #[test]
    fn flipped_v_round_trips_bit_exactly_through_text_and_f32() {
        let samples = [
            0.0f32,
            1.0,
            0.5,
            0.1,
            0.9,
            0.123_456_79,
            0.999_999_9,
            2.75,
            -3.1,
            1e-3,
            1e-8,
            7e5,
        ];
        for v in samples {
            let t = v_to_text(v);
            let back = v_from_file(t.parse().unwrap());
            assert_eq!(back.to_bits(), v.to_bits(), "{v} via '{t}'");
        }
        // Values read from a 32-bit file always have a 32-bit preimage.
        for t in [0.0f32, 0.3, 0.7, 0.123_456_79, 1.0, 1.5, -2.25, 3e-5] {
            let v = v_from_file(t as f64);
            assert_eq!(
                v_from_file(v_to_f32(v) as f64).to_bits(),
                v.to_bits(),
                "{t}"
            );
        }
        assert_eq!(v_to_text(0.25), "0.75");
    }

    #[test]
    fn v_below_one_half_from_text_needs_a_64_bit_file_v() {
        // An OBJ `vt` v of 0.876543 reads as the f32 nearest 0.123457; no
        // f32 t gives it back, the exact f64 1 − v does.
        let v = v_from_file(0.876_543);
        assert!(!v_fits_f32(v));
        assert_eq!(v_from_file(1.0 - v as f64).to_bits(), v.to_bits());
        for v in [0.0f32, 0.5, 0.75, 1.0, 1.5, v_from_file(0.3f32 as f64)] {
            assert!(v_fits_f32(v), "{v}");
        }
        for v in [2f32.powi(-29), -(2f32.powi(-29)), 0.123_456_79, 7e5, -3.1] {
            assert_eq!(v_from_file(1.0 - v as f64).to_bits(), v.to_bits(), "{v}");
        }
    }

    #[test]
    fn integers_parse_with_sign_and_reject_overflow() {
        assert_eq!(parse_i64(b"-12"), Some(-12));
        assert_eq!(parse_i64(b"+7"), Some(7));
        assert_eq!(parse_i64(b"-9223372036854775808"), Some(i64::MIN));
        assert_eq!(parse_i64(b"9223372036854775808"), None);
        assert_eq!(parse_i64(b"1.5"), None);
        assert_eq!(parse_i64(b"-"), None);
    }

    #[test]
    fn non_finite_and_garbage_numbers_are_named() {
        assert!(parse_f32(b"nan").unwrap_err().contains("finite"));
        assert!(parse_f32(b"-inf").unwrap_err().contains("finite"));
        assert!(parse_f32(b"1e39").unwrap_err().contains("finite"));
        assert!(parse_f32(b"x1").unwrap_err().contains("not a number"));
        assert_eq!(parse_f32(b"0.1").unwrap(), 0.1f32);
    }
}
