//! `wildlod batch`: every mesh file below a folder, simplified (or made
//! into a chain of levels) into another folder with the same tree, several
//! files at once (`wildlod_pipeline::run_batch`, shared with the Python
//! package). A file that fails is recorded and the run goes on; the
//! summary (JSON and CSV) lists every file, and the exit code is 1 when any
//! failed. `--skip-existing` resumes an interrupted run.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use wildlod_io::Format;
use wildlod_pipeline::{BatchJob, BatchSettings, FileTargets, Levels};

use super::simplify::{texture_settings, tuning_options};
use super::with_flag_names;
use crate::args_assets::BatchArgs;
use crate::progress::Progress;
use crate::stdout::emit;

/// Validated settings of one `batch` run.
struct Config {
    input: PathBuf,
    output: PathBuf,
    settings: BatchSettings,
    summary: Vec<PathBuf>,
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
            BatchJob::Chain {
                levels: Levels::from_lists(&a.lod_ratios, &a.lod_errors, &a.lod_faces, "--lod-")
                    .map_err(with_flag_names)?,
                split: a.split,
            }
        } else {
            BatchJob::Simplify(
                FileTargets {
                    ratio: a.ratio,
                    faces: a.faces,
                    error: a.error,
                }
                .checked()
                .map_err(with_flag_names)?,
            )
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
        let summary =
            wildlod_pipeline::summary_paths(&a.output, a.summary.as_deref()).map_err(|_| {
                anyhow::anyhow!(
                    "--summary must end in .json or .csv, got {}",
                    a.summary.as_deref().unwrap_or(Path::new("")).display()
                )
            })?;
        Ok(Config {
            settings: BatchSettings {
                job,
                options: tuning_options(&a.tuning)?,
                textures: texture_settings(&a.textures)?,
                per_mesh: a.per_mesh,
                format,
                jobs,
                skip_existing: a.skip_existing,
            },
            input: a.input,
            output: a.output,
            summary,
            json: a.json,
            quiet: a.quiet,
        })
    }
}

/// Runs `batch`.
pub fn run(a: BatchArgs) -> anyhow::Result<()> {
    let cfg = Config::from_args(a)?;
    let show = !cfg.quiet && std::io::IsTerminal::is_terminal(&std::io::stderr());
    let multi = MultiProgress::with_draw_target(if show {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let bar = multi.add(ProgressBar::new(0));
    if let Ok(style) = ProgressStyle::with_template("files [{bar:30}] {pos}/{len} {elapsed} {msg}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    if show {
        // The count is known once the folder is listed; listing twice is
        // cheap next to simplifying.
        let out_abs = std::fs::create_dir_all(&cfg.output)
            .ok()
            .and_then(|_| cfg.output.canonicalize().ok());
        if let Ok(files) = wildlod_pipeline::mesh_files(&cfg.input, out_abs.as_deref()) {
            bar.set_length(files.len() as u64);
        }
    }
    let progress = |name: &str| Progress::in_multi(name, &multi, show);
    let done = |r: &wildlod_pipeline::FileResult| {
        bar.inc(1);
        bar.set_message(r.file.clone());
        if r.status == "failed" && !cfg.quiet {
            // Above the bars, so it stays on screen.
            let line = format!("error: {}", r.message);
            if multi.println(&line).is_err() || !show {
                eprintln!("{line}");
            }
        }
    };
    let summary =
        wildlod_pipeline::run_batch(&cfg.input, &cfg.output, &cfg.settings, &progress, &done)
            .map_err(with_flag_names)?;
    bar.finish_and_clear();
    wildlod_pipeline::write_summary(&summary, &cfg.summary)?;
    if cfg.json {
        let json = serde_json::to_string_pretty(&summary).context("serializing the summary")?;
        emit(&(json + "\n"))?;
    } else if !cfg.quiet {
        emit(&format!(
            "{} files: {} done, {} failed, {} skipped in {:.1} s; summary in {}\n",
            summary.files,
            summary.ok,
            summary.failed,
            summary.skipped,
            summary.seconds,
            cfg.summary
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
