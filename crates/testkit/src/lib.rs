//! Test support: where the shared corpus is, and what to do when it is not.
//!
//! The corpus (real meshes from public sources) is not part of the
//! repository; CI places `shared/` beside the checkout. Tests that read it
//! call [`corpus`]: under `CI=true` a missing corpus fails the test loudly,
//! elsewhere the test says it was skipped and passes.

use std::path::{Path, PathBuf};

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
    eprintln!(
        "{test}: skipped, mesh corpus not found at {}",
        dir.display()
    );
    None
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
