//! `scale`: time and peak memory of `wildlod simplify` as the input grows
//! (issue 15: near-linear to 10 M triangles, at most 200 bytes per input
//! triangle), side by side with meshoptimizer's `simplify` on the same
//! triangles, each in its own process under `/usr/bin/time -v`.
//!
//! ```text
//! cargo build --release -p wildlod-cli -p wildlod-bench --bin scale
//! target/release/scale --sizes 1,2,5,10 --ratio 0.01 --out /tmp/scale.md
//! target/release/scale --files ../shared/corpus/large/dragon_vrip.glb --ratio 0.1
//! ```
//!
//! The generated input is a bumpy torus (a closed manifold whose bumps
//! give every region detail to keep), written as GLB so that reading it is
//! not dominated by text parsing. Peak resident memory covers the whole
//! process: reading, simplifying and writing.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use anyhow::{bail, Context};
use clap::Parser;
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Scene};

/// Scaling measurement of wildlod against meshoptimizer.
#[derive(Parser, Debug)]
struct Args {
    /// Generated input sizes, in millions of triangles.
    #[arg(long, value_delimiter = ',', default_value = "1,2,5,10")]
    sizes: Vec<f64>,
    /// Corpus or other mesh files to measure as well (no generated sizes
    /// when given without --sizes).
    #[arg(long, value_delimiter = ',')]
    files: Vec<PathBuf>,
    /// Target ratio.
    #[arg(long, default_value_t = 0.01)]
    ratio: f64,
    /// The wildlod binary.
    #[arg(long, default_value = "target/release/wildlod")]
    wildlod: PathBuf,
    /// Extra arguments for `wildlod simplify`, space separated.
    #[arg(long, default_value = "")]
    wildlod_args: String,
    /// Where generated inputs and outputs go.
    #[arg(long, default_value = "target/scale")]
    workdir: PathBuf,
    /// Where to write the markdown table (also printed).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Internal: run meshoptimizer on this file in this process.
    #[arg(long, hide = true)]
    child_meshopt: Option<PathBuf>,
}

/// One process's measurement.
#[derive(Clone, Copy, Debug, Default)]
struct Measured {
    wall_s: f64,
    peak_bytes: u64,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let result = match &args.child_meshopt {
        Some(f) => child_meshopt(f, args.ratio),
        None => run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// A bumpy torus of about `triangles` triangles.
fn bumpy_torus(triangles: usize) -> Scene {
    // nu × nv quads, two triangles each, tube 4× finer around than along.
    let quads = (triangles / 2).max(16);
    let nv = ((quads as f64 / 4.0).sqrt().round() as usize).max(4);
    let nu = (quads / nv).max(4);
    let mut m = shapes::triangulate(&shapes::torus(nu, nv, 1.0, 0.3));
    for p in &mut m.positions {
        let bump = 1.0
            + 0.04 * (23.0 * p[0]).sin() * (19.0 * p[1]).cos() * (17.0 * p[2]).sin()
            + 0.01 * (97.0 * p[0] + 53.0 * p[2]).sin();
        let (x, y) = (p[0], p[1]);
        let ring = (x * x + y * y).sqrt().max(1e-6);
        // Displace along the tube's radial direction.
        let (cx, cy) = (x / ring, y / ring);
        let (dx, dy, dz) = (x - cx, y - cy, p[2]);
        p[0] = cx + dx * bump;
        p[1] = cy + dy * bump;
        p[2] = dz * bump;
    }
    Scene::from_mesh(m)
}

fn run(args: &Args) -> anyhow::Result<()> {
    if !(args.ratio > 0.0 && args.ratio <= 1.0) {
        bail!("--ratio must be in (0, 1], got {}", args.ratio);
    }
    std::fs::create_dir_all(&args.workdir)
        .with_context(|| format!("creating {}", args.workdir.display()))?;
    let mut inputs: Vec<(String, PathBuf)> = Vec::new();
    let generate = args.files.is_empty() || std::env::args().any(|a| a.starts_with("--sizes"));
    if generate {
        for &millions in &args.sizes {
            let n = (millions * 1e6).round() as usize;
            let path = args.workdir.join(format!("torus_{millions}M.glb"));
            if !path.exists() {
                let t = Instant::now();
                let doc = Document::from_scene(bumpy_torus(n));
                wildlod_io::write(&doc, &path, &WriteOptions::default())
                    .with_context(|| format!("writing {}", path.display()))?;
                eprintln!(
                    "generated {} in {:.1} s",
                    path.display(),
                    t.elapsed().as_secs_f64()
                );
            }
            inputs.push((format!("bumpy torus {millions} M"), path));
        }
    }
    for f in &args.files {
        let name = f
            .file_name()
            .map_or_else(|| f.display().to_string(), |n| n.to_string_lossy().into());
        inputs.push((name, f.clone()));
    }
    let me = std::env::current_exe().context("finding this program")?;
    let mut rows = Vec::new();
    for (name, path) in &inputs {
        let tris = wildlod_io::read(path)
            .with_context(|| format!("reading {}", path.display()))?
            .scene
            .meshes
            .iter()
            .map(|m| m.triangle_count())
            .sum::<usize>();
        let out = args.workdir.join("out.glb");
        let mut cmd = vec![
            args.wildlod.display().to_string(),
            "simplify".into(),
            path.display().to_string(),
            "-o".into(),
            out.display().to_string(),
            "--ratio".into(),
            args.ratio.to_string(),
            "--quiet".into(),
            "--overwrite".into(),
        ];
        cmd.extend(args.wildlod_args.split_whitespace().map(str::to_string));
        let w = timed(&cmd)?;
        let m = timed(&[
            me.display().to_string(),
            "--child-meshopt".into(),
            path.display().to_string(),
            "--ratio".into(),
            args.ratio.to_string(),
        ])?;
        eprintln!(
            "{name}: {tris} triangles: wildlod {:.2} s, {:.0} MB; meshopt {:.2} s, {:.0} MB",
            w.wall_s,
            w.peak_bytes as f64 / 1e6,
            m.wall_s,
            m.peak_bytes as f64 / 1e6
        );
        rows.push((name.clone(), tris, w, m));
    }
    let table = markdown(&rows, args.ratio);
    println!("{table}");
    if let Some(o) = &args.out {
        std::fs::write(o, &table).with_context(|| format!("writing {}", o.display()))?;
    }
    Ok(())
}

/// Runs `cmd` under `/usr/bin/time -v`: wall-clock seconds and peak RSS.
fn timed(cmd: &[String]) -> anyhow::Result<Measured> {
    let out = Command::new("/usr/bin/time")
        .arg("-v")
        .args(cmd)
        .output()
        .with_context(|| format!("running /usr/bin/time -v {}", cmd.join(" ")))?;
    let err = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        bail!("{} failed:\n{err}", cmd.join(" "));
    }
    let field = |key: &str| -> Option<&str> {
        err.lines()
            .find_map(|l| l.trim().strip_prefix(key))
            .map(str::trim)
    };
    let kb: u64 = field("Maximum resident set size (kbytes):")
        .and_then(|v| v.parse().ok())
        .context("no peak memory in /usr/bin/time's report")?;
    let wall = field("Elapsed (wall clock) time (h:mm:ss or m:ss):")
        .and_then(parse_clock)
        .context("no wall time in /usr/bin/time's report")?;
    Ok(Measured {
        wall_s: wall,
        peak_bytes: kb * 1024,
    })
}

/// `h:mm:ss` or `m:ss.ss` in seconds.
fn parse_clock(s: &str) -> Option<f64> {
    s.split(':').try_fold(0.0, |acc, part| {
        Some(acc * 60.0 + part.parse::<f64>().ok()?)
    })
}

/// meshoptimizer's `simplify` on every mesh of `path`, in this process, so
/// that its peak memory is measured the same way (reading the file
/// included; no writing, which favours meshoptimizer slightly).
fn child_meshopt(path: &Path, ratio: f64) -> anyhow::Result<()> {
    let doc = wildlod_io::read(path).with_context(|| format!("reading {}", path.display()))?;
    let mut kept = 0usize;
    for m in &doc.scene.meshes {
        let tri = shapes::triangulate(m);
        let target = ((tri.faces.indices.len() / 3) as f64 * ratio).round() as usize;
        let out =
            wildlod_bench::methods::meshopt_simplify(&tri.positions, &tri.faces.indices, target);
        kept += out.len() / 3;
    }
    eprintln!("meshopt kept {kept} triangles");
    Ok(())
}

fn markdown(rows: &[(String, usize, Measured, Measured)], ratio: f64) -> String {
    let mut s = format!(
        "| input | triangles | wildlod to {r}% | meshopt to {r}% | wildlod ÷ meshopt | wildlod peak RSS | bytes / triangle | meshopt peak RSS |\n|---|---|---|---|---|---|---|---|\n",
        r = ratio * 100.0
    );
    for (name, tris, w, m) in rows {
        s.push_str(&format!(
            "| {name} | {tris} | {:.2} s | {:.2} s | {:.2}× | {:.0} MB | {:.0} | {:.0} MB |\n",
            w.wall_s,
            m.wall_s,
            w.wall_s / m.wall_s.max(1e-9),
            w.peak_bytes as f64 / 1e6,
            w.peak_bytes as f64 / (*tris).max(1) as f64,
            m.peak_bytes as f64 / 1e6,
        ));
    }
    if let [(_, t0, w0, _), .., (_, t1, w1, _)] = rows {
        if t1 > t0 {
            s.push_str(&format!(
                "\nFrom the first row to the last: {:.1}× the triangles, {:.1}× wildlod's time, {:.1}× its peak memory.\n",
                *t1 as f64 / *t0 as f64,
                w1.wall_s / w0.wall_s.max(1e-9),
                w1.peak_bytes as f64 / w0.peak_bytes.max(1) as f64
            ));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_strings_parse_to_seconds() {
        assert_eq!(parse_clock("0:01.50"), Some(1.5));
        assert_eq!(parse_clock("1:02:03"), Some(3723.0));
        assert_eq!(parse_clock("x"), None);
    }

    #[test]
    fn the_torus_has_the_asked_size_within_a_percent() {
        for n in [10_000usize, 123_456] {
            let s = bumpy_torus(n);
            let t = s.meshes[0].triangle_count();
            assert!(
                (t as f64 - n as f64).abs() <= 0.01 * n as f64,
                "{t} for {n}"
            );
            assert!(s.meshes[0]
                .positions
                .iter()
                .flatten()
                .all(|c| c.is_finite()));
        }
    }
}
