//! Byte mutations of seed files, for the fuzz runs that `cargo test` makes
//! (libFuzzer brings its own). Each mutation is plain data, so `proptest`
//! can generate, print and shrink a list of them.

/// One edit of a file. Positions are taken modulo the current length, so
/// any value is meaningful on any file.
#[derive(Clone, Debug)]
pub enum Mutation {
    /// Flip one bit.
    FlipBit {
        /// Byte position.
        at: usize,
        /// Bit (0–7).
        bit: u8,
    },
    /// Overwrite one byte.
    SetByte {
        /// Byte position.
        at: usize,
        /// New value.
        value: u8,
    },
    /// Insert bytes.
    Insert {
        /// Byte position.
        at: usize,
        /// What to insert.
        bytes: Vec<u8>,
    },
    /// Delete a range.
    Delete {
        /// Start.
        at: usize,
        /// Length.
        len: usize,
    },
    /// Copy a range elsewhere (repeats a line, a face, a JSON object…).
    Duplicate {
        /// Start of the copied range.
        from: usize,
        /// Its length.
        len: usize,
        /// Where the copy goes.
        to: usize,
    },
    /// Replace the number (or word) at a position by an interesting token:
    /// for the text formats, where a flipped bit rarely makes a new number.
    Token {
        /// Byte position inside or before the token.
        at: usize,
        /// Which token of [`TOKENS`].
        which: usize,
    },
    /// Overwrite four bytes with an interesting little-endian `u32`: for
    /// the binary formats' counts, offsets and lengths.
    Word {
        /// Byte position.
        at: usize,
        /// Which value of [`WORDS`].
        which: usize,
    },
    /// Cut the file short.
    Truncate {
        /// New length.
        at: usize,
    },
}

/// Numbers and words that break parsers: signs, extremes, non-finite
/// values, and counts just past what fits.
pub const TOKENS: &[&str] = &[
    "0",
    "-1",
    "-0",
    "1",
    "3",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "2147483648",
    "1e39",
    "-1e39",
    "1e-45",
    "nan",
    "inf",
    "-inf",
    "0x10",
    "65535",
    "1.5",
    "",
    "100000000",
    "/",
    "//",
    "\"",
    "null",
    "[]",
    "{}",
    "true",
];

/// `u32` values that break binary formats.
pub const WORDS: &[u32] = &[
    0,
    1,
    2,
    3,
    0xff,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_fffe,
    0xffff_ffff,
    0x4e4f_534a, // "JSON"
    0x004e_4942, // "BIN\0"
];

/// Applies `mutations` in order.
pub fn apply(seed: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for m in mutations {
        let n = b.len();
        let at = |p: usize| if n == 0 { 0 } else { p % (n + 1) };
        match m {
            Mutation::FlipBit { at: p, bit } => {
                if n > 0 {
                    b[p % n] ^= 1 << (bit % 8);
                }
            }
            Mutation::SetByte { at: p, value } => {
                if n > 0 {
                    b[p % n] = *value;
                }
            }
            Mutation::Insert { at: p, bytes } => {
                let p = at(*p);
                b.splice(p..p, bytes.iter().copied());
            }
            Mutation::Delete { at: p, len } => {
                let p = at(*p);
                let end = (p + len).min(n);
                b.drain(p..end);
            }
            Mutation::Duplicate { from, len, to } => {
                let from = at(*from);
                let end = (from + len).min(n);
                let chunk = b[from..end].to_vec();
                let to = at(*to);
                b.splice(to..to, chunk);
            }
            Mutation::Token { at: p, which } => {
                let p = at(*p);
                // The token around `p`: a run of number-ish characters.
                let is_num =
                    |c: u8| c.is_ascii_alphanumeric() || c == b'.' || c == b'-' || c == b'+';
                let mut s = p;
                while s > 0 && is_num(b[s - 1]) {
                    s -= 1;
                }
                let mut e = p;
                while e < n && is_num(b[e]) {
                    e += 1;
                }
                let token = TOKENS[which % TOKENS.len()].as_bytes();
                b.splice(s..e, token.iter().copied());
            }
            Mutation::Word { at: p, which } => {
                if n >= 4 {
                    let p = p % (n - 3);
                    let w = WORDS[which % WORDS.len()].to_le_bytes();
                    b[p..p + 4].copy_from_slice(&w);
                }
            }
            Mutation::Truncate { at: p } => {
                let p = at(*p);
                b.truncate(p);
            }
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn token_mutation_replaces_the_whole_number() {
        let out = apply(
            b"f 12 34 56",
            &[Mutation::Token {
                at: 4,
                which: 1, // "-1"
            }],
        );
        assert_eq!(out, b"f -1 34 56");
    }

    #[test]
    fn positions_wrap_so_any_value_applies() {
        let out = apply(
            b"abc",
            &[
                Mutation::Delete {
                    at: 1_000_001,
                    len: 1,
                },
                Mutation::Word { at: 7, which: 0 },
            ],
        );
        // 1_000_001 % 4 = 1: "b" deleted; a 2-byte file has no word.
        assert_eq!(out, b"ac");
    }
}
