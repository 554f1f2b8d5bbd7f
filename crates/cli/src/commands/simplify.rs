//! `wildlod simplify`: read → simplify every mesh → write.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use wildlod_io::{Document, ErrorKind, WriteOptions};
use wildlod_mesh::Scene;
use wildlod_simplify::{
    simplify_mesh_with_progress, AttributeOptions, Guards, NormalMode, Options, QuadMode, Report,
    SeamPolicy, StopReason, Target,
};

use crate::args::{NormalArg, SeamArg, SimplifyArgs, TuningArgs};
use crate::progress::Progress;
use crate::stdout::emit;

/// Validated settings of one `simplify` run.
#[derive(Debug)]
pub struct Config {
    pub input: PathBuf,
    pub output: PathBuf,
    /// Base options; targets are set per mesh.
    pub options: Options,
    pub ratio: Option<f64>,
    pub faces: Option<usize>,
    pub error: Option<f64>,
    pub overwrite: bool,
    pub quiet: bool,
    /// Re-bake textures (`--bake`), with these settings.
    pub bake: Option<super::bake::BakeConfig>,
    /// Print the JSON report instead of lines.
    pub json: bool,
}

impl Config {
    /// Checks the arguments' ranges and combinations.
    pub fn from_args(a: SimplifyArgs) -> anyhow::Result<Config> {
        if let Some(r) = a.ratio {
            if !(0.0..=1.0).contains(&r) {
                bail!("--ratio must be between 0 and 1, got {r}");
            }
        }
        if let Some(e) = a.error {
            if !(e.is_finite() && e >= 0.0) {
                bail!("--error must be a non-negative number, got {e}");
            }
        }
        let options = tuning_options(&a.tuning)?;
        check_output(&a.input, &a.output, a.overwrite)?;
        if let Some(n) = a.texture_size {
            if !(16..=16384).contains(&n) {
                bail!("--texture-size must be between 16 and 16384, got {n}");
            }
        }
        if !(1..=100).contains(&a.jpeg_quality) {
            bail!(
                "--jpeg-quality must be between 1 and 100, got {}",
                a.jpeg_quality
            );
        }
        let bake = a.bake.then_some(super::bake::BakeConfig {
            texture_size: a.texture_size,
            merge_materials: a.merge_materials,
            jpeg_quality: a.jpeg_quality,
        });
        let ratio = match (a.ratio, a.faces, a.error) {
            (None, None, None) => Some(0.5),
            (r, _, _) => r,
        };
        Ok(Config {
            json: a.json,
            bake,
            input: a.input,
            output: a.output,
            options,
            ratio,
            faces: a.faces,
            error: a.error,
            overwrite: a.overwrite,
            quiet: a.quiet,
        })
    }
}

/// What can be known about the output before any work: its format, its
/// folder, and whether it would replace the input. (The writer checks all
/// of this again; checking here saves the user the wait, which on a large
/// mesh is seconds, and names the problem in the user's terms.)
fn check_output(input: &Path, output: &Path, overwrite: bool) -> anyhow::Result<()> {
    wildlod_io::Format::from_path(output).map_err(|kind| wildlod_io::Error::new(output, kind))?;
    let folder = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match std::fs::metadata(folder) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => bail!(
            "{}: cannot write there: {} is not a folder",
            output.display(),
            folder.display()
        ),
        Err(e) => bail!(
            "{}: cannot write there: the folder {} {}",
            output.display(),
            folder.display(),
            if e.kind() == std::io::ErrorKind::NotFound {
                "does not exist".to_string()
            } else {
                format!("cannot be read ({e})")
            }
        ),
    }
    if !overwrite && same_file(input, output) {
        bail!(
            "{}: refusing to overwrite the input file; pass --overwrite to allow it",
            output.display()
        );
    }
    Ok(())
}

/// Whether two paths name the same existing file (through links, `.` and
/// `..`).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// The simplifier's options from the tuning flags shared by `simplify`,
/// `lod` and `batch`, with their ranges checked; targets are set per mesh.
pub(crate) fn tuning_options(t: &TuningArgs) -> anyhow::Result<Options> {
    if !(t.virtual_radius.is_finite() && t.virtual_radius >= 0.0) {
        bail!(
            "--virtual-radius must be a non-negative number, got {}",
            t.virtual_radius
        );
    }
    if !(t.quad_epsilon.is_finite() && t.quad_epsilon >= 0.0) {
        bail!(
            "--quad-epsilon must be a non-negative number, got {}",
            t.quad_epsilon
        );
    }
    for (flag, value) in [
        ("--tangent-weight", t.tangent_weight),
        ("--symmetry", t.symmetry),
        ("--uv-weight", t.uv_weight),
        ("--normal-weight", t.normal_weight),
        ("--color-weight", t.color_weight),
        ("--skin-weight", t.skin_weight),
        ("--seam-weight", t.seam_weight),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            bail!("{flag} must be a non-negative number, got {value}");
        }
    }
    if !(t.max_normal_turn > 0.0 && t.max_normal_turn <= 180.0) {
        bail!(
            "--max-normal-turn must be in (0, 180], got {}",
            t.max_normal_turn
        );
    }
    let mut options = if t.classic {
        Options::classic_qem()
    } else {
        Options {
            virtual_edge_radius: t.virtual_radius,
            ..Options::default()
        }
    };
    if t.no_quads {
        options.quad_mode = QuadMode::Never;
    }
    options.quad.epsilon = t.quad_epsilon;
    // Knodt's balance of tangent planes against face planes, when only
    // the symmetry term asks for them.
    let tangent = if t.tangent_weight == 0.0 && t.symmetry > 0.0 {
        1.0 / 3.0
    } else {
        t.tangent_weight
    };
    options.metric.tangent_weight = tangent;
    options.quad.tangent_weight = tangent;
    options.quad.symmetry = t.symmetry;
    options.attributes = AttributeOptions {
        tex_coord_weight: t.uv_weight,
        normal_weight: t.normal_weight,
        color_weight: t.color_weight,
        skin_weight: t.skin_weight,
        seams: match t.seams {
            SeamArg::Keep => SeamPolicy::Keep,
            SeamArg::Penalize => SeamPolicy::Penalize,
            SeamArg::Ignore => SeamPolicy::Ignore,
        },
        normals: match t.normals {
            NormalArg::Fit => NormalMode::Fit,
            NormalArg::Recompute => NormalMode::Recompute,
        },
        seam_weight: t.seam_weight,
    };
    options.guards = Guards {
        max_normal_turn_degrees: (t.max_normal_turn < 180.0).then_some(t.max_normal_turn),
        keep_topology: t.keep_topology,
        lock_borders: t.lock_borders,
    };
    Ok(options)
}

/// One simplified mesh of a file: what the per-mesh line and the JSON
/// report say.
#[derive(Clone, Debug)]
pub(crate) struct MeshRun {
    /// Index of the mesh in the scene.
    pub mesh: usize,
    /// Its name for messages (the file stem for a lone unnamed mesh).
    pub name: String,
    /// What the simplifier reached.
    pub report: Report,
    /// Wall time of this mesh.
    pub seconds: f64,
}

/// How a mesh is named in messages: its own name, the file's stem when it
/// is the file's only mesh, else `mesh N`.
pub(crate) fn mesh_name(scene: &Scene, m: usize, stem: &str) -> String {
    match (
        scene.meshes.get(m).map_or("", |x| x.name.as_str()),
        scene.meshes.len(),
    ) {
        ("", 1) => stem.to_string(),
        ("", _) => format!("mesh {m}"),
        (n, _) => n.to_string(),
    }
}

/// The stem of a file name, for messages and output names.
pub(crate) fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Simplifies every mesh of `scene` in place to its target (keep-UV mode:
/// every stream fitted, textures shared), one after the other; `progress`
/// makes the display for a mesh's name. Errors name `input` and the mesh.
pub(crate) fn simplify_scene(
    scene: &mut Scene,
    input: &Path,
    options: &Options,
    targets: &[Target],
    stem: &str,
    progress: &dyn Fn(&str) -> Progress,
) -> anyhow::Result<Vec<MeshRun>> {
    let mut runs = Vec::new();
    for (m, target) in targets.iter().enumerate() {
        let Some(mesh) = scene.meshes.get(m) else {
            continue;
        };
        if mesh.faces.is_empty() {
            continue;
        }
        let name = mesh_name(scene, m, stem);
        let options = Options {
            target: *target,
            ..options.clone()
        };
        let bar = progress(&name);
        let t0 = Instant::now();
        let (lod, report) = simplify_mesh_with_progress(mesh, &options, &|f| bar.set(f))
            .with_context(|| format!("{}: simplifying {name}", input.display()))?;
        bar.finish();
        runs.push(MeshRun {
            mesh: m,
            name,
            report,
            seconds: t0.elapsed().as_secs_f64(),
        });
        scene.meshes[m] = lod;
    }
    Ok(runs)
}

/// Runs `simplify`.
pub fn run(cfg: &Config) -> anyhow::Result<()> {
    let t0 = Instant::now();
    let mut doc = wildlod_io::read(&cfg.input)?;
    if !cfg.quiet {
        for w in &doc.warnings {
            eprintln!("warning: {}: {w}", cfg.input.display());
        }
    }
    let targets = mesh_targets(&doc.scene, cfg);
    let stem = file_stem(&cfg.input);
    if let Some(b) = &cfg.bake {
        super::bake::bake_scene(&mut doc, cfg, b, &targets, &stem)?;
        return write(&doc, cfg);
    }
    let show = !cfg.quiet && !cfg.json;
    let runs = simplify_scene(
        &mut doc.scene,
        &cfg.input,
        &cfg.options,
        &targets,
        &stem,
        &|name| Progress::new(name, show),
    )?;
    if show {
        for r in &runs {
            emit(&(summary(&r.name, &r.report, r.seconds) + "\n"))?;
        }
    }
    write(&doc, cfg)?;
    if cfg.json {
        let json = RunJson::new(&cfg.input, &cfg.output, &runs, t0.elapsed().as_secs_f64());
        let text = serde_json::to_string_pretty(&json).context("serializing the report")?;
        emit(&(text + "\n"))?;
    }
    Ok(())
}

/// One mesh in the JSON report (`meshes` of `simplify --json`, of each
/// level of `lod --json`, of each file of `batch`'s summary).
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct MeshJson {
    pub name: String,
    pub mesh: usize,
    pub input_triangles: usize,
    pub target_triangles: usize,
    pub output_triangles: usize,
    pub error: f64,
    pub stop: Option<String>,
    pub collapses: usize,
    pub seconds: f64,
}

impl MeshJson {
    pub(crate) fn new(r: &MeshRun) -> Self {
        MeshJson {
            name: r.name.clone(),
            mesh: r.mesh,
            input_triangles: r.report.input_triangles,
            target_triangles: r.report.target_triangles,
            output_triangles: r.report.output_triangles,
            error: r.report.error,
            stop: r.report.stop.map(|s| stop_key(s).to_string()),
            collapses: r.report.collapses,
            seconds: r.seconds,
        }
    }
}

/// The stable JSON name of a stop reason.
pub(crate) fn stop_key(s: StopReason) -> &'static str {
    match s {
        StopReason::TargetReached => "target_reached",
        StopReason::ErrorLimit => "error_limit",
        StopReason::NoCollapsibleEdges => "no_collapsible_edges",
        StopReason::NothingToDo => "nothing_to_do",
    }
}

/// `simplify --json`.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct RunJson {
    pub input: String,
    pub output: String,
    pub input_triangles: usize,
    pub output_triangles: usize,
    /// Largest error over the meshes (each relative to its own diagonal).
    pub error: f64,
    pub seconds: f64,
    pub meshes: Vec<MeshJson>,
}

impl RunJson {
    pub(crate) fn new(input: &Path, output: &Path, runs: &[MeshRun], seconds: f64) -> Self {
        RunJson {
            input: input.display().to_string(),
            output: output.display().to_string(),
            input_triangles: runs.iter().map(|r| r.report.input_triangles).sum(),
            output_triangles: runs.iter().map(|r| r.report.output_triangles).sum(),
            error: runs.iter().map(|r| r.report.error).fold(0.0, f64::max),
            seconds,
            meshes: runs.iter().map(MeshJson::new).collect(),
        }
    }
}

pub(super) fn write(doc: &Document, cfg: &Config) -> anyhow::Result<()> {
    let warnings = wildlod_io::write(
        doc,
        &cfg.output,
        &WriteOptions {
            allow_overwrite_input: cfg.overwrite,
        },
    )
    .map_err(|e| match &e.kind {
        // The library names its option; the user knows the flag.
        ErrorKind::WouldOverwriteInput(p) => anyhow::anyhow!(
            "{}: refusing to overwrite the input file {}; pass --overwrite to allow it",
            cfg.output.display(),
            p.display()
        ),
        _ => e.into(),
    })?;
    if !cfg.quiet {
        for w in warnings {
            eprintln!("warning: {}: {w}", cfg.output.display());
        }
    }
    Ok(())
}

/// One line per mesh: `bunny: 6598 → 660 triangles, error 0.0021, 38 ms`,
/// and why it stopped short when it did.
pub fn summary(name: &str, r: &Report, seconds: f64) -> String {
    let mut s = format!(
        "{name}: {} → {} triangles, error {:.4}, {:.0} ms",
        r.input_triangles,
        r.output_triangles,
        r.error,
        seconds * 1000.0
    );
    let short = r.output_triangles > r.target_triangles + 1;
    if short && r.stop == Some(StopReason::NoCollapsibleEdges) {
        let j = &r.rejected;
        s.push_str(&format!(
            " (target {} not reached: no collapsible edge left; refused by normal flip {}, topology {}, locked border {}, overshoot {})",
            r.target_triangles, j.normal_flip, j.topology, j.locked_border, j.overshoot
        ));
    } else if short && r.stop == Some(StopReason::ErrorLimit) {
        s.push_str(" (stopped at the error limit)");
    }
    if r.split_polygons > 0 {
        s.push_str(&format!(
            "; {} polygon{} of more than {} corners simplified and written as pieces",
            r.split_polygons,
            if r.split_polygons == 1 { "" } else { "s" },
            wildlod_simplify::MAX_POLYGON_CORNERS
        ));
    }
    s
}

/// The target of every stored mesh: the same ratio for all; a `--faces`
/// budget shared in proportion to triangle counts (largest remainders, so
/// the shares sum to the budget); `--error` converted from the file's
/// diagonal to each mesh's own.
///
/// Every mesh keeps at least one triangle, whatever the targets: a mesh
/// simplified to nothing would leave its nodes, skins and instances
/// pointing at an empty mesh, and `--ratio 0` would write a file with no
/// geometry and exit 0. "As small as possible" is what a user asking for 0
/// wants; one triangle per mesh is the smallest valid result.
pub(super) fn mesh_targets(scene: &Scene, cfg: &Config) -> Vec<Target> {
    targets_for(scene, cfg.ratio, cfg.faces, cfg.error)
}

/// [`mesh_targets`] from the three limits.
pub(crate) fn targets_for(
    scene: &Scene,
    ratio: Option<f64>,
    faces: Option<usize>,
    error: Option<f64>,
) -> Vec<Target> {
    let tris: Vec<usize> = scene.meshes.iter().map(|m| m.triangle_count()).collect();
    let shares = faces.map(|n| share_budget(n, &tris));
    let file_diag = scene_diagonal(scene);
    tris.iter()
        .enumerate()
        .map(|(m, _)| Target {
            ratio,
            triangles: Some(
                shares
                    .as_ref()
                    .map_or(MIN_TRIANGLES, |s| s[m].max(MIN_TRIANGLES)),
            ),
            error: error.map(|e| {
                let d = world_diagonal(scene, m);
                if d > 0.0 && file_diag > 0.0 {
                    e * file_diag / d
                } else {
                    e
                }
            }),
        })
        .collect()
}

/// Triangles every mesh keeps (see [`mesh_targets`]).
const MIN_TRIANGLES: usize = 1;

/// Splits `n` among items in proportion to `weights`, summing to `n`
/// (or less when the weights sum to less).
pub(crate) fn share_budget(n: usize, weights: &[usize]) -> Vec<usize> {
    let total: usize = weights.iter().sum();
    if total == 0 {
        return vec![0; weights.len()];
    }
    let n = n.min(total);
    let exact: Vec<f64> = weights
        .iter()
        .map(|&w| n as f64 * w as f64 / total as f64)
        .collect();
    let mut out: Vec<usize> = exact.iter().map(|x| x.floor() as usize).collect();
    let mut rest = n - out.iter().sum::<usize>();
    let mut order: Vec<usize> = (0..weights.len()).collect();
    order.sort_by(|&a, &b| {
        (exact[b] - exact[b].floor())
            .total_cmp(&(exact[a] - exact[a].floor()))
            .then(a.cmp(&b))
    });
    for i in order {
        if rest == 0 {
            break;
        }
        out[i] += 1;
        rest -= 1;
    }
    out
}

/// Bounding-box diagonal of everything the scene shows, in world space.
pub(crate) fn scene_diagonal(scene: &Scene) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (m, world) in scene.instances() {
        for p in &scene.meshes[m as usize].positions {
            let q = wildlod_mesh::transform::apply_point(&world, *p);
            for k in 0..3 {
                lo[k] = lo[k].min(q[k] as f64);
                hi[k] = hi[k].max(q[k] as f64);
            }
        }
    }
    diag(lo, hi)
}

/// Diagonal of mesh `m` as its first instance shows it.
pub(crate) fn world_diagonal(scene: &Scene, m: usize) -> f64 {
    let world = scene
        .instances()
        .into_iter()
        .find(|(i, _)| *i as usize == m)
        .map(|(_, w)| w)
        .unwrap_or(wildlod_mesh::IDENTITY);
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &scene.meshes[m].positions {
        let q = wildlod_mesh::transform::apply_point(&world, *p);
        for k in 0..3 {
            lo[k] = lo[k].min(q[k] as f64);
            hi[k] = hi[k].max(q[k] as f64);
        }
    }
    diag(lo, hi)
}

fn diag(lo: [f64; 3], hi: [f64; 3]) -> f64 {
    if lo[0] > hi[0] {
        return 0.0;
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budget_shares_sum_to_the_budget_in_proportion() {
        assert_eq!(share_budget(10, &[50, 30, 20]), vec![5, 3, 2]);
        assert_eq!(share_budget(10, &[10, 10, 10]), vec![4, 3, 3]);
        // A budget above the total keeps every triangle.
        assert_eq!(share_budget(10, &[1, 1, 1]), vec![1, 1, 1]);
        assert_eq!(share_budget(100, &[3, 4]), vec![3, 4]);
        assert_eq!(share_budget(5, &[0, 0]), vec![0, 0]);
    }
}
