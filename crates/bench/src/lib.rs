//! Measuring wildlod the way the papers do, side by side with
//! meshoptimizer: the corpus evaluation ([`evaluation`]) behind
//! `cargo run --release -p wildlod-bench --bin evaluate`, and the shared
//! pieces of the criterion benchmarks.

pub mod evaluation;
pub mod methods;
