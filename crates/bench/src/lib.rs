//! Measuring wildlod the way the papers do, side by side with
//! meshoptimizer: the corpus evaluation ([`evaluation`]) behind
//! `cargo run --release -p wildlod-bench --bin evaluate`, the shared
//! pieces of the criterion benchmarks, and meshes made in code to check
//! defaults outside the corpus ([`holdout`]).

pub mod appearance;
pub mod bake_inputs;
pub mod evaluation;
pub mod holdout;
pub mod methods;

/// Mean time of a benchmark from criterion's saved estimates (under
/// `target/criterion`), in seconds: how the benchmarks print ratios of two
/// runs measured together.
pub fn mean_seconds(group: &str, function: &str, param: &str) -> Option<f64> {
    let dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    // Criterion keeps spaces and '%' in its directory names and replaces
    // the characters file systems reject.
    let safe = |s: &str| s.replace(['?', '"', '/', '\\', '*', '<', '>', ':', '|', '^'], "_");
    let path = dir
        .join("criterion")
        .join(safe(group))
        .join(safe(function))
        .join(safe(param))
        .join("new/estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let key = "\"mean\":{\"confidence_interval\":";
    let rest = &text[text.find(key)?..];
    let pe = "\"point_estimate\":";
    let start = rest.find(pe)? + pe.len();
    let end = rest[start..].find([',', '}'])? + start;
    rest[start..end].parse::<f64>().ok().map(|ns| ns * 1e-9)
}
