//! `wildlod batch` and `wildlod.batch`: every mesh file below a folder,
//! simplified (or made into a chain of levels) into another folder with
//! the same tree, several files at once. A file that fails is recorded and
//! the run goes on; the summary ([`BatchSummary`], written as JSON and CSV)
//! lists every file. `skip_existing` resumes an interrupted run.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use wildlod_io::{Format, OutputFiles, WriteOptions};
use wildlod_simplify::Options;

use crate::{
    build_chain, chain_json, chain_paths, file_stem, rebake_levels, simplify_document, write_chain,
    Error, FileTargets, Levels, MeshProgress, TextureSettings,
};

/// What each file becomes.
#[derive(Clone, Debug, PartialEq)]
pub enum BatchJob {
    /// One simplified file (the targets are checked: none means ratio 0.5).
    Simplify(FileTargets),
    /// A chain of levels (one glTF file with `MSFT_lod` unless `split`).
    Chain {
        /// The levels below the input.
        levels: Levels,
        /// One file per level even for glTF.
        split: bool,
    },
}

/// How a batch runs.
#[derive(Clone, Debug)]
pub struct BatchSettings {
    /// What each file becomes.
    pub job: BatchJob,
    /// How to simplify.
    pub options: Options,
    /// Keep, re-bake or choose textures per file (and per level of a
    /// chain), as `simplify` and `lod` do.
    pub textures: TextureSettings,
    /// Every mesh of a file to its own share (`simplify --per-mesh`)
    /// instead of the whole file under one budget.
    pub per_mesh: bool,
    /// Write every output in this format (else each input's own).
    pub format: Option<Format>,
    /// Files at once (at least 1).
    pub jobs: usize,
    /// Skip files whose outputs all exist.
    pub skip_existing: bool,
}

/// What happened to one file (a row of the summary).
#[derive(Clone, Debug, serde::Serialize)]
pub struct FileResult {
    /// The file, relative to the input folder.
    pub file: String,
    /// `ok`, `failed` or `skipped`.
    pub status: &'static str,
    /// The files written (or that would be).
    pub outputs: Vec<String>,
    /// Triangles of the input (drawn, as `simplify --json` counts them).
    pub triangles_in: Option<usize>,
    /// Triangles of the output (of a chain: its last level).
    pub triangles_out: Option<usize>,
    /// Error reached (of a chain: its last level's).
    pub error: Option<f64>,
    /// Wall time.
    pub seconds: f64,
    /// Why it failed or was skipped.
    pub message: String,
}

/// `wildlod-summary.json` (and `batch --json`): the whole run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BatchSummary {
    /// The input folder.
    pub input: String,
    /// The output folder.
    pub output: String,
    /// Files found.
    pub files: usize,
    /// Files done.
    pub ok: usize,
    /// Files that failed.
    pub failed: usize,
    /// Files skipped (`skip_existing`).
    pub skipped: usize,
    /// Wall time of the run.
    pub seconds: f64,
    /// One row per file, sorted by path.
    pub results: Vec<FileResult>,
}

/// Mesh files below `root`, sorted, as paths relative to it; never inside
/// `skip` (the output folder, when it lies below the input), never hidden
/// files or folders, and never through symbolic links to folders (no
/// cycles).
pub fn mesh_files(root: &Path, skip: Option<&Path>) -> Result<Vec<PathBuf>, Error> {
    let listing = |dir: &Path, e: std::io::Error| {
        Error::Io(wildlod_io::Error::new(dir, wildlod_io::ErrorKind::Io(e)))
    };
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        if skip.is_some_and(|s| dir.canonicalize().is_ok_and(|d| d == s)) {
            continue;
        }
        for e in std::fs::read_dir(&dir).map_err(|e| listing(&dir, e))? {
            let e = e.map_err(|e| listing(&dir, e))?;
            let path = e.path();
            let kind = e.file_type().map_err(|e| listing(&path, e))?;
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

/// The path handed to the writer for `rel`: the `-o` of `simplify` or of
/// `lod` (split chains derive their files from it).
fn target_path(output: &Path, settings: &BatchSettings, rel: &Path) -> PathBuf {
    let mut out = output.join(rel);
    if let Some(f) = settings.format {
        out.set_extension(f.extension());
    }
    out
}

/// Every file written for `rel`.
fn outputs_for(output: &Path, settings: &BatchSettings, rel: &Path) -> Result<Vec<PathBuf>, Error> {
    let out = target_path(output, settings, rel);
    Ok(match &settings.job {
        BatchJob::Simplify(_) => vec![out],
        BatchJob::Chain { levels, split } => chain_paths(&out, levels.len(), *split)?,
    })
}

/// Simplifies one file; returns (triangles in, out, error), counted as
/// the reports of `simplify --json` and `lod --json` count them.
fn process<P: MeshProgress>(
    settings: &BatchSettings,
    input: &Path,
    output: &Path,
    progress: &dyn Fn(&str) -> P,
) -> Result<(usize, usize, f64), Error> {
    let t0 = Instant::now();
    let doc = wildlod_io::read(input)?;
    if let Some(dir) = output.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| wildlod_io::Error::new(dir, wildlod_io::ErrorKind::Io(e)))?;
    }
    let stem = file_stem(input);
    let textures = settings.textures.checked()?;
    match &settings.job {
        BatchJob::Simplify(targets) => {
            let t = targets.checked()?;
            let done = simplify_document(
                doc,
                input,
                output,
                &t,
                settings.per_mesh,
                &settings.options,
                &textures,
                progress,
            )?;
            wildlod_io::write(&done.doc, output, &WriteOptions::default())?;
            let r = done.json(input, output, t0.elapsed().as_secs_f64());
            Ok((r.input_triangles, r.output_triangles, r.error))
        }
        BatchJob::Chain { levels, split } => {
            let mut chain = build_chain(
                &doc.scene,
                input,
                &settings.options,
                levels,
                &stem,
                progress,
            )?;
            rebake_levels(
                &doc,
                &mut chain,
                input,
                output,
                &settings.options,
                &textures,
                &stem,
            )?;
            let (files, _) = write_chain(&doc, &chain, output, *split, false)?;
            let j = chain_json(input, &doc.scene, &chain, &files, None, 0.0);
            let first = j.levels.first().map_or(0, |l| l.triangles);
            let last = j.levels.last();
            Ok((
                first,
                last.map_or(first, |l| l.triangles),
                last.map_or(0.0, |l| l.error),
            ))
        }
    }
}

/// Processes one file of the run, turning every error and panic into a
/// failed row.
pub fn batch_file<P: MeshProgress>(
    input_dir: &Path,
    output_dir: &Path,
    settings: &BatchSettings,
    rel: &Path,
    progress: &dyn Fn(&str) -> P,
) -> FileResult {
    let t0 = Instant::now();
    let input = input_dir.join(rel);
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
    let outputs = match outputs_for(output_dir, settings, rel) {
        Ok(o) => o,
        Err(e) => {
            result.message = format!("{}: {e}", input.display());
            return result;
        }
    };
    result.outputs = outputs.iter().map(|p| p.display().to_string()).collect();
    if settings.skip_existing && outputs.iter().all(|p| p.exists()) {
        result.status = "skipped";
        result.message = "outputs exist".into();
        return result;
    }
    let target = target_path(output_dir, settings, rel);
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        process(settings, &input, &target, progress)
    }));
    result.seconds = t0.elapsed().as_secs_f64();
    match outcome {
        Ok(Ok((tin, tout, err))) => {
            result.status = "ok";
            result.triangles_in = Some(tin);
            result.triangles_out = Some(tout);
            result.error = Some(err);
        }
        Ok(Err(e)) => result.message = crate::error::error_chain(&e),
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

/// Runs a batch: every mesh file below `input` into `output` (created),
/// `settings.jobs` at once. `progress` makes the progress display of a
/// mesh, `done` hears of every file as it ends. Errors only for the run
/// as a whole (folders that cannot be made or listed); files that fail
/// are rows.
pub fn run_batch<P: MeshProgress>(
    input: &Path,
    output: &Path,
    settings: &BatchSettings,
    progress: &(dyn Fn(&str) -> P + Sync),
    done: &(dyn Fn(&FileResult) + Sync),
) -> Result<BatchSummary, Error> {
    let t0 = Instant::now();
    if !input.is_dir() {
        return Err(Error::Usage(format!(
            "{}: is not a folder",
            input.display()
        )));
    }
    if settings.jobs == 0 {
        return Err(Error::setting("jobs", "at least 1", 0.0));
    }
    std::fs::create_dir_all(output)
        .map_err(|e| wildlod_io::Error::new(output, wildlod_io::ErrorKind::Io(e)))?;
    let out_abs = output.canonicalize().ok();
    let files = mesh_files(input, out_abs.as_deref())?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.jobs)
        .build()?;
    let results: Vec<FileResult> = pool.install(|| {
        files
            .par_iter()
            .map(|rel| {
                let r = batch_file(input, output, settings, rel, progress);
                done(&r);
                r
            })
            .collect()
    });
    let count = |s: &str| results.iter().filter(|r| r.status == s).count();
    Ok(BatchSummary {
        input: input.display().to_string(),
        output: output.display().to_string(),
        files: results.len(),
        ok: count("ok"),
        failed: count("failed"),
        skipped: count("skipped"),
        seconds: t0.elapsed().as_secs_f64(),
        results,
    })
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The summary as CSV: one row per file, the columns of [`FileResult`]
/// (`outputs` joined by `;`).
pub fn summary_csv(summary: &BatchSummary) -> String {
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

/// Where the summary goes: `path` (`.json` or `.csv`), or
/// `OUTPUT/wildlod-summary.json` and `.csv`.
pub fn summary_paths(output: &Path, path: Option<&Path>) -> Result<Vec<PathBuf>, Error> {
    match path {
        Some(p) => {
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !ext.eq_ignore_ascii_case("json") && !ext.eq_ignore_ascii_case("csv") {
                return Err(Error::Usage(format!(
                    "the summary must end in .json or .csv, got {}",
                    p.display()
                )));
            }
            Ok(vec![p.to_path_buf()])
        }
        None => Ok(vec![
            output.join("wildlod-summary.json"),
            output.join("wildlod-summary.csv"),
        ]),
    }
}

/// Writes the summary to `paths` (JSON or CSV by extension), all or
/// nothing.
pub fn write_summary(summary: &BatchSummary, paths: &[PathBuf]) -> Result<(), Error> {
    let json = serde_json::to_string_pretty(summary)?;
    let mut files = OutputFiles::new(None, false);
    for p in paths {
        let is_csv = p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let bytes = if is_csv {
            summary_csv(summary).into_bytes()
        } else {
            format!("{json}\n").into_bytes()
        };
        files
            .add(p, bytes)
            .map_err(|e| wildlod_io::Error::new(p, e))?;
    }
    let at = paths.first().cloned().unwrap_or_default();
    files.commit().map_err(|e| wildlod_io::Error::new(&at, e))?;
    Ok(())
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

    #[test]
    fn a_summary_goes_to_json_or_csv_only() {
        let out = Path::new("out");
        assert_eq!(
            summary_paths(out, None).ok(),
            Some(vec![
                out.join("wildlod-summary.json"),
                out.join("wildlod-summary.csv")
            ])
        );
        assert!(summary_paths(out, Some(Path::new("s.CSV"))).is_ok());
        assert!(matches!(
            summary_paths(out, Some(Path::new("s.txt"))),
            Err(Error::Usage(_))
        ));
    }
}
