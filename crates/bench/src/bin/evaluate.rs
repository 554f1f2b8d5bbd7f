//! `evaluate`: the corpus evaluation. Simplifies every mesh of a corpus
//! folder with wildlod (default and classic QEM) and meshoptimizer, at
//! several ratios, and writes a markdown report.
//!
//! ```text
//! cargo run --release -p wildlod-bench --bin evaluate -- ../shared/corpus \
//!     --out docs/evaluation.md
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use wildlod_bench::evaluation::{evaluate, markdown, Config};
use wildlod_bench::methods::Method;

/// Corpus evaluation of wildlod against meshoptimizer.
#[derive(Parser, Debug)]
struct Args {
    /// Corpus folder (categories are its subfolders).
    #[arg(default_value = "../shared/corpus")]
    corpus: PathBuf,
    /// Where to write the markdown report.
    #[arg(long, default_value = "docs/evaluation.md")]
    out: PathBuf,
    /// Ratios, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "0.5,0.1,0.01,0.001")]
    ratios: Vec<f64>,
    /// Categories to include, comma separated (default: all).
    #[arg(long, value_delimiter = ',')]
    categories: Vec<String>,
    /// Methods, comma separated (default: all): wildlod, global, classic,
    /// meshopt, meshopt-update, at-meshopt-count.
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
    /// Sample points per surface.
    #[arg(long, default_value_t = 50_000)]
    samples: usize,
}

fn main() -> ExitCode {
    let a = Args::parse();
    let mut methods = Vec::new();
    for key in &a.methods {
        match Method::from_key(key) {
            Some(m) => methods.push(m),
            None => {
                eprintln!("error: unknown method {key:?}");
                return ExitCode::FAILURE;
            }
        }
    }
    if methods.is_empty() {
        methods = Method::ALL.to_vec();
    }
    let cfg = Config {
        methods,
        corpus: a.corpus.clone(),
        categories: a.categories.clone(),
        ratios: a.ratios.clone(),
        samples: a.samples,
    };
    let rows = match evaluate(&cfg, |r| {
        eprintln!(
            "{:<45} {:>6} {:<30} {:>8} tris  H {:.5}  C {:.6}  {:.1} ms",
            r.file,
            r.ratio,
            r.method.name(),
            r.triangles,
            r.hausdorff,
            r.chamfer_mean,
            r.seconds * 1000.0
        )
    }) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e:#}");
            return ExitCode::FAILURE;
        }
    };
    let mut command = format!(
        "cargo run --release -p wildlod-bench --bin evaluate -- {} --out {} --ratios {} --samples {}",
        a.corpus.display(),
        a.out.display(),
        a.ratios.iter().map(|r| r.to_string()).collect::<Vec<_>>().join(","),
        a.samples
    );
    if !a.categories.is_empty() {
        command += &format!(" --categories {}", a.categories.join(","));
    }
    if !a.methods.is_empty() {
        command += &format!(" --methods {}", a.methods.join(","));
    }
    let md = markdown(&cfg, &rows, &command);
    if let Err(e) = std::fs::write(&a.out, md) {
        eprintln!("error: {}: {e}", a.out.display());
        return ExitCode::FAILURE;
    }
    eprintln!("wrote {}", a.out.display());
    ExitCode::SUCCESS
}
