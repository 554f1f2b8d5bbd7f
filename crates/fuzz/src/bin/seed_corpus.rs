//! Writes the seed corpus generated in code where `cargo fuzz` reads it:
//! `seed-corpus DIR` fills `DIR/<target>/seed-<n>` for every target.

use std::path::PathBuf;

use wildlod_fuzz::seeds::seeds;
use wildlod_fuzz::InputFormat;

fn main() -> std::process::ExitCode {
    let Some(root) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: seed-corpus DIR   (writes DIR/<target>/seed-<n>)");
        return std::process::ExitCode::FAILURE;
    };
    for format in InputFormat::ALL {
        let dir = root.join(format.extension());
        if let Err(e) = std::fs::create_dir_all(&dir) {
            eprintln!("error: creating {}: {e}", dir.display());
            return std::process::ExitCode::FAILURE;
        }
        for (k, seed) in seeds(format).iter().enumerate() {
            let path = dir.join(format!("seed-{k}"));
            if let Err(e) = std::fs::write(&path, seed) {
                eprintln!("error: writing {}: {e}", path.display());
                return std::process::ExitCode::FAILURE;
            }
        }
    }
    // The simplify target starts from nothing: `arbitrary` turns any bytes
    // into a case, and libFuzzer grows the corpus by coverage.
    if let Err(e) = std::fs::create_dir_all(root.join("simplify")) {
        eprintln!("error: creating {}: {e}", root.join("simplify").display());
        return std::process::ExitCode::FAILURE;
    }
    std::process::ExitCode::SUCCESS
}
