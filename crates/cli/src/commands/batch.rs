//! `wildlod batch`: every mesh file below a folder, simplified (or made
//! into a chain of levels) into another folder with the same tree, several
//! files at once. A file that fails is recorded and the run goes on; the
//! summary (JSON and CSV) lists every file, and the exit code is 1 when any
//! failed. `--skip-existing` resumes an interrupted run.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use wildlod_io::{Format, OutputFiles, WriteOptions};
use wildlod_mesh::Mesh;
use wildlod_simplify::Options;

use wildlod_pipeline::{
    build_chain, chain_paths, file_stem, simplify_scene, targets_for, write_chain, FileTargets,
    Levels,
};

use super::simplify::tuning_options;
use super::with_flag_names;
use crate::args_assets::BatchArgs;
use crate::progress::Progress;
use crate::stdout::emit;

/// What each file becomes.
#[derive(Clone, Debug)]
enum Job {
    /// One simplified file.
    Simplify {
        ratio: Option<f64>,
        faces: Option<usize>,
        error: Option<f64>,
    },
    /// A chain of levels.
    Chain { levels: Levels, split: bool },
}

/// Validated settings of one `batch` run.
struct Config {
    input: PathBuf,
    output: PathBuf,
    job: Job,
    options: Options,
    format: Option<Format>,
    jobs: usize,
    skip_existing: bool,
    summary: Option<PathBuf>,
    json: bool,
    quiet: bool,
}

impl Config {
    fn from_args(a: BatchArgs) -> anyhow::Result<Config> {
        if !a.input.is_dir() {
            bail!("{}: is not a folder", a.input.display());
        }
        let chain = !(a.lod_ratios.is_empty() && a.lod_errors.is_empty() && a.lod_faces.is_empty());
        let job = if chain {
            Job::Chain {
                levels: Levels::from_lists(&a.lod_ratios, &a.lod_errors, &a.lod_faces, "--lod-")
                    .map_err(with_flag_names)?,
                split: a.split,
            }
        } else {
            let t = FileTargets {
                ratio: a.ratio,
                faces: a.faces,
                error: a.error,
            }
            .checked()
            .map_err(with_flag_names)?;
            Job::Simplify {
                ratio: t.ratio,
                faces: t.faces,
                error: t.error,
            }
        };
        let format = match &a.format {
            None => None,
            Some(ext) => Some(
                Format::from_path(Path::new(&format!("x.{}", ext.trim_start_matches('.'))))
                    .with_context(|| format!("--format {ext}"))?,
            ),
        };
        let jobs = match a.jobs {
            Some(0) => bail!("--jobs must be at least 1"),
            Some(n) => n,
            None => std::thread::available_parallelism().map_or(1, |n| n.get()),
        };
        if let Some(s) = &a.summary {
            let ext = s.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !ext.eq_ignore_ascii_case("json") && !ext.eq_ignore_ascii_case("csv") {
                bail!("--summary must end in .json or .csv, got {}", s.display());
            }
        }
        Ok(Config {
            options: tuning_options(&a.tuning)?,
            input: a.input,
            output: a.output,
            job,
            format,
            jobs,
            skip_existing: a.skip_existing,
            summary: a.summary,
            json: a.json,
            quiet: a.quiet,
        })
    }
}

/// Mesh files below `root`, sorted, as paths relative to it; never inside
/// `skip` (the output folder, when it lies below the input) and never
/// through symbolic links to folders (no cycles).
fn mesh_files(root: &Path, skip: Option<&Path>) -> anyhow::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        if skip.is_some_and(|s| dir.canonicalize().is_ok_and(|d| d == s)) {
            continue;
        }
        let entries =
            std::fs::read_dir(&dir).with_context(|| format!("{}: cannot list", dir.display()))?;
        for e in entries {
            let e = e.with_context(|| format!("{}: cannot list", dir.display()))?;
            let path = e.path();
            let kind = e
                .file_type()
                .with_context(|| format!("{}: cannot read", path.display()))?;
            let hidden = e.file_name().to_string_lossy().starts_with('.');
            if kind.is_dir() {
                if !hidden {
                    stack.push(path);
                }
            } else if !hidden && Format::from_path(&path).is_ok() {
                if let Ok(rel) = path.strip_prefix(root) {
                    out.push(rel.to_path_buf());
                }
            }
        }
    }
    out.sort();
    Ok(out)
}

/// What happened to one file.
#[derive(Clone, Debug, serde::Serialize)]
struct FileResult {
    file: String,
    status: &'static str,
    outputs: Vec<String>,
    triangles_in: Option<usize>,
    triangles_out: Option<usize>,
    error: Option<f64>,
    seconds: f64,
    message: String,
}

/// The summary of a run.
#[derive(Clone, Debug, serde::Serialize)]
struct Summary {
    input: String,
    output: String,
    files: usize,
    ok: usize,
    failed: usize,
    skipped: usize,
    seconds: f64,
    results: Vec<FileResult>,
}

/// Where a file's outputs go.
fn outputs_for(cfg: &Config, rel: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut out = cfg.output.join(rel);
    if let Some(f) = cfg.format {
        out.set_extension(f.extension());
    }
    Ok(match &cfg.job {
        Job::Simplify { .. } => vec![out],
        Job::Chain { levels, split } => chain_paths(&out, levels.len(), *split)?,
    })
}

/// Simplifies one file; returns (triangles in, out, error, warnings).
fn process(
    cfg: &Config,
    input: &Path,
    output: &Path,
    progress: &dyn Fn(&str) -> Progress,
) -> anyhow::Result<(usize, usize, f64)> {
    let mut doc = wildlod_io::read(input)?;
    let tris_in: usize = doc.scene.meshes.iter().map(Mesh::triangle_count).sum();
    if let Some(dir) = output.parent() {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    }
    let stem = file_stem(input);
    match &cfg.job {
        Job::Simplify {
            ratio,
            faces,
            error,
        } => {
            let targets = targets_for(&doc.scene, *ratio, *faces, *error);
            let runs = simplify_scene(
                &mut doc.scene,
                input,
                &cfg.options,
                &targets,
                &stem,
                progress,
            )?;
            wildlod_io::write(&doc, output, &WriteOptions::default())?;
            let tris_out = doc.scene.meshes.iter().map(Mesh::triangle_count).sum();
            let err = runs.iter().map(|r| r.report.error).fold(0.0, f64::max);
            Ok((tris_in, tris_out, err))
        }
        Job::Chain { levels, split } => {
            let chain = build_chain(&doc.scene, input, &cfg.options, levels, &stem, progress)?;
            write_chain(&doc, &chain, output, *split, false)?;
            let last = chain.last();
            Ok((
                tris_in,
                last.map_or(tris_in, |l| l.triangles),
                last.map_or(0.0, |l| l.error),
            ))
        }
    }
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn csv(summary: &Summary) -> String {
    let mut s =
        String::from("file,status,triangles_in,triangles_out,error,seconds,outputs,message\n");
    let opt = |v: Option<usize>| v.map(|x| x.to_string()).unwrap_or_default();
    for r in &summary.results {
        s += &format!(
            "{},{},{},{},{},{:.3},{},{}\n",
            csv_field(&r.file),
            r.status,
            opt(r.triangles_in),
            opt(r.triangles_out),
            r.error.map(|e| format!("{e:.6}")).unwrap_or_default(),
            r.seconds,
            csv_field(&r.outputs.join(";")),
            csv_field(&r.message)
        );
    }
    s
}

/// Runs `batch`.
pub fn run(a: BatchArgs) -> anyhow::Result<()> {
    let cfg = Config::from_args(a)?;
    let t0 = Instant::now();
    std::fs::create_dir_all(&cfg.output)
        .with_context(|| format!("{}: cannot create the output folder", cfg.output.display()))?;
    let out_abs = cfg.output.canonicalize().ok();
    let files = mesh_files(&cfg.input, out_abs.as_deref())?;
    let show = !cfg.quiet && std::io::IsTerminal::is_terminal(&std::io::stderr());
    let multi = MultiProgress::with_draw_target(if show {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let bar = multi.add(ProgressBar::new(files.len() as u64));
    if let Ok(style) = ProgressStyle::with_template("files [{bar:30}] {pos}/{len} {elapsed} {msg}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(cfg.jobs)
        .build()
        .context("starting the worker threads")?;
    let results: Vec<FileResult> = pool.install(|| {
        files
            .par_iter()
            .map(|rel| {
                let r = one_file(&cfg, rel, &multi, show);
                bar.inc(1);
                bar.set_message(rel.display().to_string());
                if r.status == "failed" && !cfg.quiet {
                    // Above the bars, so it stays on screen.
                    let line = format!("error: {}", r.message);
                    if multi.println(&line).is_err() || !show {
                        eprintln!("{line}");
                    }
                }
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    let count = |s: &str| results.iter().filter(|r| r.status == s).count();
    let summary = Summary {
        input: cfg.input.display().to_string(),
        output: cfg.output.display().to_string(),
        files: results.len(),
        ok: count("ok"),
        failed: count("failed"),
        skipped: count("skipped"),
        seconds: t0.elapsed().as_secs_f64(),
        results,
    };
    let json = serde_json::to_string_pretty(&summary).context("serializing the summary")?;
    let written = write_summary(&cfg, &summary, &json)?;
    if cfg.json {
        emit(&(json + "\n"))?;
    } else if !cfg.quiet {
        emit(&format!(
            "{} files: {} done, {} failed, {} skipped in {:.1} s; summary in {}\n",
            summary.files,
            summary.ok,
            summary.failed,
            summary.skipped,
            summary.seconds,
            written
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(" and ")
        ))?;
    }
    if summary.failed > 0 {
        bail!(
            "{} of {} files failed (listed in the summary)",
            summary.failed,
            summary.files
        );
    }
    Ok(())
}

/// Processes one file, turning every error and panic into a failed entry.
fn one_file(cfg: &Config, rel: &Path, multi: &MultiProgress, show: bool) -> FileResult {
    let t0 = Instant::now();
    let input = cfg.input.join(rel);
    let mut result = FileResult {
        file: rel.display().to_string(),
        status: "failed",
        outputs: Vec::new(),
        triangles_in: None,
        triangles_out: None,
        error: None,
        seconds: 0.0,
        message: String::new(),
    };
    let outputs = match outputs_for(cfg, rel) {
        Ok(o) => o,
        Err(e) => {
            result.message = format!("{}: {e:#}", input.display());
            return result;
        }
    };
    result.outputs = outputs.iter().map(|p| p.display().to_string()).collect();
    if cfg.skip_existing && outputs.iter().all(|p| p.exists()) {
        result.status = "skipped";
        result.message = "outputs exist".into();
        return result;
    }
    let Some(first) = outputs.first() else {
        result.message = format!("{}: no output path", input.display());
        return result;
    };
    // For a chain, the path handed on is the -o of `lod` (the split files
    // derive from it).
    let target = match &cfg.job {
        Job::Chain { .. } => {
            let mut p = cfg.output.join(rel);
            if let Some(f) = cfg.format {
                p.set_extension(f.extension());
            }
            p
        }
        Job::Simplify { .. } => first.clone(),
    };
    let progress = |name: &str| Progress::in_multi(name, multi, show);
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        process(cfg, &input, &target, &progress)
    }));
    result.seconds = t0.elapsed().as_secs_f64();
    match outcome {
        Ok(Ok((tin, tout, err))) => {
            result.status = "ok";
            result.triangles_in = Some(tin);
            result.triangles_out = Some(tout);
            result.error = Some(err);
        }
        Ok(Err(e)) => result.message = format!("{e:#}"),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            result.message = format!("{}: internal error: {what}", input.display());
        }
    }
    result
}

/// Writes the summary files; returns their paths.
fn write_summary(cfg: &Config, summary: &Summary, json: &str) -> anyhow::Result<Vec<PathBuf>> {
    let paths: Vec<PathBuf> = match &cfg.summary {
        Some(p) => vec![p.clone()],
        None => vec![
            cfg.output.join("wildlod-summary.json"),
            cfg.output.join("wildlod-summary.csv"),
        ],
    };
    let mut files = OutputFiles::new(None, false);
    for p in &paths {
        let is_csv = p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let bytes = if is_csv {
            csv(summary).into_bytes()
        } else {
            format!("{json}\n").into_bytes()
        };
        files
            .add(p, bytes)
            .map_err(|e| wildlod_io::Error::new(p, e))?;
    }
    let at = paths.first().cloned().unwrap_or_default();
    files.commit().map_err(|e| wildlod_io::Error::new(&at, e))?;
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quotes_fields_with_commas_and_quotes() {
        assert_eq!(csv_field("a.obj"), "a.obj");
        assert_eq!(csv_field("a, b"), "\"a, b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }
}
