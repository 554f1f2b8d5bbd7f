//! `holdout`: writes the meshes of [`wildlod_bench::holdout`] as OBJ
//! files, one folder per category, for `../shared/peers` to score wildlod
//! and the peers on assets outside the corpus.
//!
//! ```text
//! cargo run --release -p wildlod-bench --bin holdout -- /tmp/holdout
//! P=../shared/peers; $P/py $P/run_eval.py --inputs /tmp/holdout --ratios 0.5,0.1,0.01 \
//!    --peers meshopt,pymeshlab,blender,open3d,pyfqmr \
//!    --project-cmd "$PWD/target/release/wildlod simplify {input} -o {output} --ratio {ratio}" \
//!    --out /tmp/holdout.csv
//! $P/py $P/scoreboard.py /tmp/holdout.csv
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Parser;

/// Writes the holdout meshes.
#[derive(Parser, Debug)]
struct Args {
    /// Folder to write into (created; existing files of the same names are
    /// replaced).
    out: PathBuf,
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("holdout: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> anyhow::Result<()> {
    for g in wildlod_bench::holdout::all() {
        let dir = args.out.join(g.category);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join(format!("{}.obj", g.name));
        std::fs::write(&path, g.to_obj()).with_context(|| format!("writing {}", path.display()))?;
        println!("{} ({} triangles)", path.display(), g.triangles());
    }
    Ok(())
}
