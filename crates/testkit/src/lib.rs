//! Test support: where the shared corpus is, and what to do when it is not;
//! a deterministic random generator for meshes made in tests; scenes
//! generated in code that are unlike the corpus ([`scenes`]).
//!
//! The corpus (real meshes from public sources) is not part of the
//! repository; CI places `shared/` beside the checkout. Tests that read it
//! call [`corpus`]: under `CI=true` a missing corpus fails the test loudly,
//! elsewhere the test says it was skipped and passes.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

pub mod ktx2;
pub mod scenes;

pub use scenes::{
    bent_tube, border_segments, city_block, distance_to_segments, double_sided_sheet,
    filleted_block, flat_tiling, height_field_triangles, house, outlier_terrain, terrain_outliers,
    uv_fold_mesh,
};

/// The corpus root: `$WILDLOD_CORPUS` if set, else `../shared/corpus` beside
/// the repository root. `None` when it does not exist and we are not in CI.
///
/// # Panics
/// When the corpus is missing and the environment variable `CI` is `true`:
/// a CI run must not silently skip the tests that matter most.
pub fn corpus(test: &str) -> Option<PathBuf> {
    let dir = match std::env::var_os("WILDLOD_CORPUS") {
        Some(d) => PathBuf::from(d),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus"),
    };
    if dir.join("README.md").is_file() {
        return Some(dir.canonicalize().unwrap_or(dir));
    }
    if std::env::var("CI").map(|v| v == "true").unwrap_or(false) {
        panic!(
            "{test}: the mesh corpus is missing at {} (set WILDLOD_CORPUS); CI must not skip it",
            dir.display()
        );
    }
    skipped(&format!(
        "{test}: the mesh corpus is not at {} (set WILDLOD_CORPUS)",
        dir.display()
    ));
    None
}

/// Says that a check did not run, and why, where the normal `cargo test`
/// output shows it: `SKIPPED <test>: <reason>`.
///
/// The test harness captures what `eprintln!` prints and shows it only for
/// failed tests (or with `--nocapture`), so a skipped check used to look
/// like a pass. Writing to the stderr handle itself is not captured. The
/// test's name is its thread's: the harness names each test's thread
/// after it.
pub fn skipped(reason: &str) {
    use std::io::Write;
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "SKIPPED {test}: {reason}");
}

/// Mesh files of the corpus (extensions gltf, glb, obj, ply, stl) under
/// `category` (e.g. `"wild"`, or `""` for all), sorted by path.
pub fn mesh_files(corpus: &Path, category: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![corpus.join(category)];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if is_mesh(&p) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn is_mesh(p: &Path) -> bool {
    let ext = p
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    matches!(ext.as_deref(), Some("gltf" | "glb" | "obj" | "ply" | "stl"))
}

/// A path relative to the corpus root, for messages.
pub fn short(corpus: &Path, p: &Path) -> String {
    p.strip_prefix(corpus).unwrap_or(p).display().to_string()
}

/// Face counts by arity (triangles, quads, n-gons) of every file of the
/// corpus README's per-category tables, keyed by path relative to the
/// corpus root. glTF rows count an instanced mesh once per instance.
///
/// # Panics
/// When the README is missing or a table row cannot be parsed: the tests
/// that call this check against it and must not silently pass.
pub fn readme_face_counts(root: &Path) -> HashMap<PathBuf, (usize, usize, usize)> {
    let text = std::fs::read_to_string(root.join("README.md")).expect("corpus README");
    let mut category = String::new();
    let mut out = HashMap::new();
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            category = h.trim().trim_end_matches('/').to_string();
            continue;
        }
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        // Only the per-category tables; the attribution table also lists files.
        if category.contains(' ') || cols.len() < 3 || !cols[1].starts_with('`') {
            continue;
        }
        let file = cols[1].split('`').nth(1).expect("file in backticks");
        let mut counts = (0, 0, 0);
        for term in cols[2].split('+') {
            let mut words = term.split_whitespace();
            let n: usize = words
                .next()
                .and_then(|n| n.replace(',', "").parse().ok())
                .expect("a face count");
            match words.next().expect("a face kind") {
                "tri" | "tris" => counts.0 = n,
                "quad" => counts.1 = n,
                "n-gon" => counts.2 = n,
                other => panic!("unknown face kind {other} in README row {line}"),
            }
        }
        out.insert(Path::new(&category).join(file), counts);
    }
    out
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny deterministic generator
/// for generated test meshes, the same numbers on every machine.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), from the top 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_gives_the_reference_sequence() {
        // The first outputs for seed 0 (the reference implementation's
        // published values).
        let mut r = SplitMix64(0);
        assert_eq!(r.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(r.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        let x = SplitMix64(7).next_f64();
        assert!((0.0..1.0).contains(&x));
    }
}
