//! Fuzz harnesses of wildlod: what every reader and the simplifier must
//! keep on hostile input, checked the same way by two drivers.
//!
//! - libFuzzer (`fuzz/` at the repository root, `cargo fuzz run <target>`)
//!   for long campaigns: each target hands its bytes to a `check_*`
//!   function here.
//! - The property tests of this crate (`tests/properties.rs`), which run
//!   under `cargo test` and therefore in CI: the seeds of [`seeds`] mutated
//!   by [`mutate`] (driven by `proptest`), and [`SimplifyCase`]s built by
//!   `arbitrary` from random bytes.
//!
//! The properties, checked on every input (a violation panics, which both
//! drivers report):
//!
//! 1. no panic, in reading, simplifying or writing;
//! 2. an error names the file it is about;
//! 3. every mesh that comes out of a reader or the simplifier passes
//!    `validate()`;
//! 4. the simplifier's report is honest: the output has the triangles it
//!    says, and no more than the target when it says the target was reached;
//! 5. the simplifier is deterministic;
//! 6. the input files are unchanged, whatever happened;
//! 7. a failed write leaves no file behind; a successful one reads back.

pub mod files;
pub mod mutate;
pub mod seeds;
mod simplify_case;

pub use files::{check_file, InputFormat};
pub use simplify_case::{check_simplify, SimplifyCase};

/// Separates a main file from its sidecar (an OBJ from its MTL, a `.gltf`
/// from its `.bin`) in one fuzz input. Chosen to be unlikely in the seeds'
/// own text, so that mutations rarely create a second one.
pub const SIDECAR_MARKER: &[u8] = b"\n#~~sidecar~~#\n";

/// FNV-1a: a stable hash of an input, from which the options of a run are
/// drawn (so that one input always means one run).
pub fn fnv1a(data: &[u8]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for &b in data {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}
