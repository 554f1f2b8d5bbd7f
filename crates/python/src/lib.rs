//! The native part of the `wildlod` Python package (`wildlod._wildlod`).
//!
//! Thin bindings over `wildlod_pipeline`, the library behind the CLI, so a
//! Python call and the matching command give the same result and the same
//! report keys. Every call copies its inputs out of Python objects, then
//! releases the GIL for the work ([`Python::detach`]), so threads can
//! simplify at once. The pure Python part (`python/wildlod`) shapes the
//! arguments, holds the exception classes and the Ray helper.

mod arrays;
mod convert;

use std::path::PathBuf;

use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wildlod_pipeline::{
    BakeSettings, BatchJob, BatchSettings, CompareFilesOptions, FileTargets, Levels, NoProgress,
    ReportOptions, TextureMode, TextureSettings,
};

use crate::convert::{report_dict, to_py, to_pyerr, tuning};

/// Simplifies a mesh given as arrays (see `wildlod.simplify`, which shapes
/// the faces into `indices` and `face_sizes`).
#[pyfunction]
#[pyo3(signature = (
    positions, indices, face_sizes, *, ratio=None, faces_target=None, error=None,
    uvs=None, normals=None, colors=None, joints=None, weights=None, vertex_weights=None,
    **options
))]
#[allow(clippy::too_many_arguments)]
fn _simplify<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f32>,
    indices: PyReadonlyArray1<'py, u32>,
    face_sizes: PyReadonlyArray1<'py, u32>,
    ratio: Option<f64>,
    faces_target: Option<usize>,
    error: Option<f64>,
    uvs: Option<PyReadonlyArray2<'py, f32>>,
    normals: Option<PyReadonlyArray2<'py, f32>>,
    colors: Option<PyReadonlyArray2<'py, f32>>,
    joints: Option<PyReadonlyArray2<'py, u16>>,
    weights: Option<PyReadonlyArray2<'py, f32>>,
    vertex_weights: Option<PyReadonlyArray1<'py, f32>>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let tuning = tuning(py, options)?;
    let mesh = arrays::ArrayMesh::new(
        py,
        positions,
        indices,
        face_sizes,
        uvs,
        normals,
        colors,
        (joints, weights),
        vertex_weights,
    )?;
    let targets = FileTargets {
        ratio,
        faces: faces_target,
        error,
    };
    let (unwelded, run) = py
        .detach(|| arrays::run(&mesh, targets, &tuning))
        .map_err(|e| e.into_pyerr(py))?;
    arrays::result_dict(py, unwelded, &run)
}

/// Simplifies every mesh of a file into another file, as `wildlod
/// simplify` does; the output's extension picks its format.
///
/// Targets (the first reached stops; none: `ratio=0.5`): `ratio` of the
/// file's triangles, `faces_target` triangles for the file, `error` as a
/// fraction of the file's diagonal; the whole file under one budget in
/// world space, as `wildlod simplify` does, or with `per_mesh` every mesh
/// to its share (`--per-mesh`). `overwrite` allows `dst`
/// to be `src`. `textures`: 'auto' (keep the UVs unless the result shows
/// the texture visibly off and a re-bake measures better), 'keep' or
/// 'bake', with `texture_size` the re-baked atlas's size (default: the
/// input's texel density) and `normal_bake` a normal map of the input's
/// shading normals for every re-baked material (default on). A `.gltf`/`.glb` `dst` writes reversed twin
/// faces once with a double-sided material. `**options`: the tuning
/// options (`wildlod.option_names()`).
///
/// Returns the dict of `wildlod simplify --json` (`input`, `output`,
/// `input_triangles`, `output_triangles`, `error`, `seconds`, `meshes`,
/// `textures` for textured files, `double_sided_twins`) plus `warnings`. Raises `WildlodOSError` when a file cannot be read or
/// written, `WildlodError` for content or settings refused.
#[pyfunction]
#[pyo3(signature = (
    src, dst, *, ratio=None, faces_target=None, error=None, per_mesh=false, textures="auto",
    texture_size=None, normal_bake=true, overwrite=false, **options
))]
#[allow(clippy::too_many_arguments)]
fn simplify_file<'py>(
    py: Python<'py>,
    src: PathBuf,
    dst: PathBuf,
    ratio: Option<f64>,
    faces_target: Option<usize>,
    error: Option<f64>,
    per_mesh: bool,
    textures: &str,
    texture_size: Option<u32>,
    normal_bake: bool,
    overwrite: bool,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let tuning = tuning(py, options)?;
    let textures = texture_settings(py, textures, texture_size, normal_bake)?;
    let targets = FileTargets {
        ratio,
        faces: faces_target,
        error,
    };
    let (report, warnings) = py
        .detach(|| {
            wildlod_pipeline::simplify_file(
                &src, &dst, &targets, per_mesh, &tuning, &textures, overwrite,
            )
        })
        .map_err(|e| to_pyerr(py, e))?;
    with_warnings(py, report_dict(py, &report)?, warnings)
}

/// Makes a chain of levels of detail of a file, as `wildlod lod` does:
/// each level simplified from the one before.
///
/// Give one list, finest first (none: `ratios=[0.5, 0.25, 0.1]`):
/// `ratios` of the input's triangles, accumulated `errors` relative to the
/// file's diagonal, or `faces_targets` triangle budgets. A `.gltf`/`.glb`
/// `dst` holds every level as `MSFT_lod` with `MSFT_screencoverage` hints
/// unless `split`; other formats and `split` write `NAME_lod0…NAME_lodN`
/// beside `dst`. `textures` and `texture_size` as in `simplify_file`:
/// with 'auto', levels share the input's textures down to the first level
/// that would be re-baked, which and every coarser level are re-baked.
///
/// Returns the dict of `wildlod lod --json` (`input`, `files`, `report`,
/// `seconds`, `levels`) plus `warnings`.
#[pyfunction]
#[pyo3(signature = (
    src, dst, *, ratios=None, errors=None, faces_targets=None, textures="auto",
    texture_size=None, normal_bake=true, split=false, overwrite=false, **options
))]
#[allow(clippy::too_many_arguments)]
fn lod_chain<'py>(
    py: Python<'py>,
    src: PathBuf,
    dst: PathBuf,
    ratios: Option<Vec<f64>>,
    errors: Option<Vec<f64>>,
    faces_targets: Option<Vec<usize>>,
    textures: &str,
    texture_size: Option<u32>,
    normal_bake: bool,
    split: bool,
    overwrite: bool,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let tuning = tuning(py, options)?;
    let textures = texture_settings(py, textures, texture_size, normal_bake)?;
    let levels = Levels::from_lists(
        &ratios.unwrap_or_default(),
        &errors.unwrap_or_default(),
        &faces_targets.unwrap_or_default(),
        "",
    )
    .map_err(|e| to_pyerr(py, e))?;
    let (report, warnings) = py
        .detach(|| {
            wildlod_pipeline::lod_file(&src, &dst, &levels, &tuning, &textures, split, overwrite)
        })
        .map_err(|e| to_pyerr(py, e))?;
    with_warnings(py, report_dict(py, &report)?, warnings)
}

/// `textures=` and `texture_size=` as the pipeline takes them, checked.
fn texture_settings(
    py: Python<'_>,
    textures: &str,
    texture_size: Option<u32>,
    normal_bake: bool,
) -> PyResult<TextureSettings> {
    let mode = match textures {
        "auto" => TextureMode::Auto,
        "keep" => TextureMode::Keep,
        "bake" => TextureMode::Bake,
        other => {
            return Err(PyValueError::new_err(format!(
                "textures must be 'auto', 'keep' or 'bake', got {other:?}"
            )))
        }
    };
    TextureSettings {
        mode,
        bake: BakeSettings {
            texture_size,
            normal_maps: normal_bake,
            ..BakeSettings::default()
        },
    }
    .checked()
    .map_err(|e| to_pyerr(py, e))
}

/// Describes a mesh file: the dict of `wildlod info --json` (face counts
/// by arity, topology, UV islands, materials, skins, `per_mesh`,
/// `warnings`).
#[pyfunction]
fn info<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let info = py
        .detach(|| {
            wildlod_io::read(&path)
                .map(|doc| wildlod_pipeline::describe(&doc, &path.display().to_string()))
        })
        .map_err(|e| to_pyerr(py, e.into()))?;
    report_dict(py, &info)
}

/// Measures how far a candidate (a level of detail) is from a reference:
/// the dict of `wildlod compare --json` (`hausdorff`, `chamfer_mean`,
/// `chamfer_squared`, `quad_ratio`, `texture_chamfer`, … relative to the
/// reference's diagonal), plus `animation` when `animation` is an index,
/// plus `warnings`. Deterministic for a given `seed`.
#[pyfunction]
#[pyo3(signature = (
    reference, candidate, *, samples=100_000, texture_samples=10_000, seed=None,
    animation=None, frames=50, fps=30.0
))]
#[allow(clippy::too_many_arguments)]
fn compare<'py>(
    py: Python<'py>,
    reference: PathBuf,
    candidate: PathBuf,
    samples: usize,
    texture_samples: usize,
    seed: Option<u64>,
    animation: Option<usize>,
    frames: usize,
    fps: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let options = CompareFilesOptions {
        samples,
        texture_samples,
        seed: seed.unwrap_or(CompareFilesOptions::default().seed),
        animation,
        frames,
        fps,
    };
    let result = py
        .detach(|| {
            wildlod_pipeline::compare_files(&reference, &candidate, &options)
                .and_then(|c| Ok((c.to_json()?, c.warnings)))
        })
        .map_err(|e| to_pyerr(py, e))?;
    with_warnings(py, to_py(py, &result.0)?, result.1)
}

/// Simplifies every mesh file below `src_dir` into `dst_dir` with the same
/// tree, `jobs` files at once (default: the cores), as `wildlod batch`
/// does; or, given one of `lod_ratios`, `lod_errors`, `lod_faces_targets`
/// (finest level first), makes a chain of levels of each (`split` as in
/// `lod_chain`). Targets of a simplified file as in `simplify_file`
/// (none: `ratio=0.5`); `format` ('glb', 'obj'…) writes every output in
/// one format; `skip_existing` skips files whose outputs all exist;
/// `per_mesh` as in `simplify_file`;
/// `textures` and `texture_size` as in `simplify_file` and `lod_chain`.
///
/// The summary is written to `summary` (`.json` or `.csv`) or to
/// `dst_dir/wildlod-summary.json` and `.csv`, and returned: the dict of
/// `wildlod batch --json` (`input`, `output`, `files`, `ok`, `failed`,
/// `skipped`, `seconds`, `results`, one dict per file with `file`,
/// `status`, `outputs`, `triangles_in`, `triangles_out`, `error`,
/// `seconds`, `message`). A file that fails is a row with status 'failed'
/// and the run goes on; only a run that cannot start raises.
#[pyfunction]
#[pyo3(signature = (
    src_dir, dst_dir, *, ratio=None, faces_target=None, error=None, lod_ratios=None,
    lod_errors=None, lod_faces_targets=None, split=false, per_mesh=false, textures="auto",
    texture_size=None, normal_bake=true, format=None, jobs=None, skip_existing=false, summary=None, **options
))]
#[allow(clippy::too_many_arguments)]
fn batch<'py>(
    py: Python<'py>,
    src_dir: PathBuf,
    dst_dir: PathBuf,
    ratio: Option<f64>,
    faces_target: Option<usize>,
    error: Option<f64>,
    lod_ratios: Option<Vec<f64>>,
    lod_errors: Option<Vec<f64>>,
    lod_faces_targets: Option<Vec<usize>>,
    split: bool,
    per_mesh: bool,
    textures: &str,
    texture_size: Option<u32>,
    normal_bake: bool,
    format: Option<String>,
    jobs: Option<usize>,
    skip_existing: bool,
    summary: Option<PathBuf>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let tuning = tuning(py, options)?;
    let (lr, le, lf) = (
        lod_ratios.unwrap_or_default(),
        lod_errors.unwrap_or_default(),
        lod_faces_targets.unwrap_or_default(),
    );
    let job = if lr.is_empty() && le.is_empty() && lf.is_empty() {
        let targets = FileTargets {
            ratio,
            faces: faces_target,
            error,
        };
        BatchJob::Simplify(targets.checked().map_err(|e| to_pyerr(py, e))?)
    } else {
        BatchJob::Chain {
            levels: Levels::from_lists(&lr, &le, &lf, "lod_").map_err(|e| to_pyerr(py, e))?,
            split,
        }
    };
    let format = match format {
        None => None,
        Some(ext) => {
            let probe = PathBuf::from(format!("x.{}", ext.trim_start_matches('.')));
            Some(
                wildlod_io::Format::from_path(&probe)
                    .map_err(|k| to_pyerr(py, wildlod_io::Error::new(&probe, k).into()))?,
            )
        }
    };
    let settings = BatchSettings {
        job,
        options: tuning.options().map_err(|e| to_pyerr(py, e))?,
        textures: texture_settings(py, textures, texture_size, normal_bake)?,
        per_mesh,
        format,
        jobs: jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
        skip_existing,
    };
    let paths = wildlod_pipeline::summary_paths(&dst_dir, summary.as_deref())
        .map_err(|e| to_pyerr(py, e))?;
    let result = py
        .detach(|| {
            let s = wildlod_pipeline::run_batch(
                &src_dir,
                &dst_dir,
                &settings,
                &|_| NoProgress,
                &|_| {},
            )?;
            wildlod_pipeline::write_summary(&s, &paths)?;
            Ok(s)
        })
        .map_err(|e| to_pyerr(py, e))?;
    report_dict(py, &result)
}

/// Writes the HTML report of a candidate (a level of detail) against a
/// reference to `output`, as `wildlod report` does: both models side by
/// side, textured, as an error heat map or as a wireframe, with the
/// metrics of `compare` (`samples` per surface). `overwrite` allows
/// `output` to be an input.
///
/// Returns the dict of `wildlod report --json` (`output`, `reference`,
/// `reference_triangles`, `candidates` with `label`, `triangles`,
/// `chain_error` and `metrics`, `samples`, `seconds`) plus `warnings`.
#[pyfunction]
#[pyo3(signature = (reference, candidate, output, *, samples=100_000, overwrite=false))]
fn report<'py>(
    py: Python<'py>,
    reference: PathBuf,
    candidate: PathBuf,
    output: PathBuf,
    samples: usize,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let options = ReportOptions {
        samples,
        ..ReportOptions::default()
    };
    let (result, warnings) = py
        .detach(|| {
            wildlod_pipeline::report_files(&reference, &candidate, &output, &options, overwrite)
        })
        .map_err(|e| to_pyerr(py, e))?;
    with_warnings(py, report_dict(py, &result)?, warnings)
}

/// Adds the readers' and writers' warnings to a report dict.
fn with_warnings<'py>(
    _py: Python<'py>,
    report: Bound<'py, PyAny>,
    warnings: Vec<String>,
) -> PyResult<Bound<'py, PyAny>> {
    report.set_item("warnings", warnings)?;
    Ok(report)
}

/// The option names `**options` accepts.
#[pyfunction]
fn option_names() -> Vec<&'static str> {
    convert::OPTION_NAMES.to_vec()
}

/// The module.
#[pymodule]
fn _wildlod(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_simplify, m)?)?;
    m.add_function(wrap_pyfunction!(simplify_file, m)?)?;
    m.add_function(wrap_pyfunction!(lod_chain, m)?)?;
    m.add_function(wrap_pyfunction!(info, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(batch, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(option_names, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
