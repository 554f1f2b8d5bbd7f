//! `wildlod simplify`: read → simplify every mesh → write.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use wildlod_io::{Document, ErrorKind, WriteOptions};
use wildlod_pipeline::{
    file_stem, simplify_document, BakeSettings, FileTargets, NormalSetting, SeamSetting,
    TextureChoice, TextureMode, TextureSettings, Tuning,
};
use wildlod_simplify::{Options, Report, SceneReport, StopReason};

use super::with_flag_names;
use crate::args::SimplifyArgs;
use crate::flags::{NormalArg, SeamArg, TextureArg, TextureArgs, TuningArgs};
use crate::progress::Progress;
use crate::stdout::emit;

/// Validated settings of one `simplify` run.
#[derive(Clone, Debug)]
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
    /// Every stored mesh alone (`--per-mesh`) instead of one scene budget.
    pub per_mesh: bool,
    /// Keep the UVs, re-bake, or choose (`--textures`, `--bake`).
    pub textures: TextureMode,
    /// How to re-bake where that is done.
    pub bake: BakeSettings,
    /// Print the JSON report instead of lines.
    pub json: bool,
}

impl Config {
    /// Checks the arguments' ranges and combinations.
    pub fn from_args(a: SimplifyArgs) -> anyhow::Result<Config> {
        let targets = FileTargets {
            ratio: a.ratio,
            faces: a.faces,
            error: a.error,
        }
        .checked()
        .map_err(with_flag_names)?;
        let options = tuning_options(&a.tuning)?;
        check_output(&a.input, &a.output, a.overwrite)?;
        let textures = match (a.bake, a.texture.textures) {
            (true, TextureArg::Keep) => bail!("--bake contradicts --textures keep"),
            (true, _) => TextureMode::Bake,
            (false, t) => texture_mode(t),
        };
        let t = &a.texture;
        let bake = bake_config(
            textures,
            t.texture_size,
            t.merge_materials,
            t.jpeg_quality,
            !t.no_normal_bake,
        )?;
        Ok(Config {
            json: a.json,
            textures,
            bake,
            input: a.input,
            output: a.output,
            options,
            ratio: targets.ratio,
            faces: targets.faces,
            error: targets.error,
            overwrite: a.overwrite,
            quiet: a.quiet,
            per_mesh: a.per_mesh,
        })
    }
}

/// `--textures` and the re-baking settings of `lod` and `batch`, checked.
pub(crate) fn texture_settings(
    t: &TextureArgs,
) -> anyhow::Result<wildlod_pipeline::TextureSettings> {
    let mode = texture_mode(t.textures);
    Ok(wildlod_pipeline::TextureSettings {
        mode,
        bake: bake_config(
            mode,
            t.texture_size,
            t.merge_materials,
            t.jpeg_quality,
            !t.no_normal_bake,
        )?,
    })
}

/// `--textures` as the pipeline names it.
pub(crate) fn texture_mode(t: TextureArg) -> TextureMode {
    match t {
        TextureArg::Auto => TextureMode::Auto,
        TextureArg::Keep => TextureMode::Keep,
        TextureArg::Bake => TextureMode::Bake,
    }
}

/// The re-baking settings, checked: in range, and not given where nothing
/// is re-baked.
pub(crate) fn bake_config(
    textures: TextureMode,
    texture_size: Option<u32>,
    merge_materials: bool,
    jpeg_quality: u8,
    normal_maps: bool,
) -> anyhow::Result<BakeSettings> {
    if let Some(n) = texture_size {
        if !(16..=16384).contains(&n) {
            bail!("--texture-size must be between 16 and 16384, got {n}");
        }
    }
    if !(1..=100).contains(&jpeg_quality) {
        bail!("--jpeg-quality must be between 1 and 100, got {jpeg_quality}");
    }
    if textures == TextureMode::Keep && (texture_size.is_some() || merge_materials || !normal_maps)
    {
        bail!("--texture-size, --merge-materials and --no-normal-bake apply only when re-baking, not with --textures keep");
    }
    Ok(BakeSettings {
        texture_size,
        merge_materials,
        jpeg_quality,
        normal_maps,
    })
}

/// What can be known about the output before any work: its format, its
/// folder, and whether it would replace the input. (The writer checks all
/// of this again; checking here saves the user the wait, which on a large
/// mesh is seconds, and names the problem in the user's terms.)
pub(crate) fn check_output(input: &Path, output: &Path, overwrite: bool) -> anyhow::Result<()> {
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
/// `lod` and `batch`, with their ranges checked (by the library, so the
/// Python package checks the same); targets are set per mesh.
pub(crate) fn tuning_options(t: &TuningArgs) -> anyhow::Result<Options> {
    tuning(t).options().map_err(with_flag_names)
}

/// The library's settings from the flags.
pub(crate) fn tuning(t: &TuningArgs) -> Tuning {
    Tuning {
        virtual_radius: t.virtual_radius,
        keep_topology: t.keep_topology,
        lock_borders: t.lock_borders,
        max_normal_turn: t.max_normal_turn,
        no_quads: t.no_quads,
        quad_epsilon: t.quad_epsilon,
        quad_tie_factor: t.quad_tie_factor,
        quad_tolerance: t.quad_tolerance,
        tangent_weight: t.tangent_weight,
        symmetry: t.symmetry,
        area_floor: t.area_floor,
        pinch_cost: t.pinch_cost,
        pinch_distance: t.pinch_distance,
        area_exponent: t.area_exponent,
        face_weight_floor: t.face_weight_floor,
        crease_weight: t.crease_weight,
        crease_angle: t.crease_angle,
        crease_area_weight: t.crease_area_weight,
        current_faces: t.current_faces,
        refit_sweeps: t.refit_sweeps,
        keep_hidden_twins: t.keep_hidden_twins,
        keep_enclosed_parts: t.keep_enclosed_parts,
        no_layers: t.no_layers,
        classic: t.classic,
        uv_weight: t.uv_weight,
        normal_weight: t.normal_weight,
        color_weight: t.color_weight,
        skin_weight: t.skin_weight,
        seams: match t.seams {
            SeamArg::Keep => SeamSetting::Keep,
            SeamArg::Penalize => SeamSetting::Penalize,
            SeamArg::Ignore => SeamSetting::Ignore,
        },
        seam_weight: t.seam_weight,
        normals: match t.normals {
            NormalArg::Fit => NormalSetting::Fit,
            NormalArg::Recompute => NormalSetting::Recompute,
        },
    }
}

/// Runs `simplify`.
pub fn run(cfg: &Config) -> anyhow::Result<()> {
    let t0 = Instant::now();
    let doc = wildlod_io::read(&cfg.input)?;
    if !cfg.quiet {
        for w in &doc.warnings {
            eprintln!("warning: {}: {w}", cfg.input.display());
        }
    }
    let stem = file_stem(&cfg.input);
    let names: Vec<String> = doc
        .scene
        .meshes
        .iter()
        .enumerate()
        .map(|(m, mesh)| match mesh.name.as_str() {
            "" => format!("mesh {m}"),
            n => n.to_string(),
        })
        .collect();
    let show = !cfg.quiet && !cfg.json;
    let targets = FileTargets {
        ratio: cfg.ratio,
        faces: cfg.faces,
        error: cfg.error,
    };
    let done = simplify_document(
        doc,
        &cfg.input,
        &cfg.output,
        &targets,
        cfg.per_mesh,
        &cfg.options,
        &TextureSettings {
            mode: cfg.textures,
            bake: cfg.bake,
        },
        &|name| Progress::new(name, show),
    )?;
    if !cfg.quiet {
        for w in &done.warnings {
            eprintln!("warning: {w}");
        }
    }
    if show {
        let lines: Vec<String> = match &done.scene {
            Some(report) => done
                .runs
                .iter()
                .map(|run| scene_summary(&stem, report, &names, run.seconds))
                .collect(),
            None => done
                .runs
                .iter()
                .zip(&done.notes)
                .map(|(r, note)| summary(&r.name, &r.report, r.seconds) + note)
                .collect(),
        };
        for line in lines {
            emit(&(line + "\n"))?;
        }
        if let Some(c) = &done.textures {
            emit(&(texture_line(c) + "\n"))?;
        }
        if done.twins.pairs > 0 {
            emit(&format!(
                "twins: {} reversed face pairs written once with a double-sided material ({} triangles the input drew twice)\n",
                done.twins.pairs, done.twins.triangles
            ))?;
        }
    }
    write(&done.doc, cfg)?;
    if cfg.json {
        let json = done.json(&cfg.input, &cfg.output, t0.elapsed().as_secs_f64());
        let text = serde_json::to_string_pretty(&json).context("serializing the report")?;
        emit(&(text + "\n"))?;
    }
    Ok(())
}

/// The line saying which texture treatment the output has and why.
fn texture_line(c: &TextureChoice) -> String {
    let excess = |e: Option<f64>| e.map_or("not measured".to_string(), |e| format!("{e:.4}"));
    match (c.mode, c.chosen) {
        (TextureMode::Auto, TextureMode::Bake) => format!(
            "textures: re-baked (texture error over the input's own: keeping the UVs {}, re-baked {})",
            excess(c.keep_uv_excess),
            excess(c.rebaked_excess)
        ),
        (TextureMode::Auto, _) => match (c.rebaked_excess, &c.rebake_failed) {
            (_, Some(why)) => format!(
                "textures: UVs kept (texture error over the input's own {}; the re-bake could not be made: {why})",
                excess(c.keep_uv_excess)
            ),
            (Some(_), None) => format!(
                "textures: UVs kept (texture error over the input's own: keeping the UVs {}, re-baked {})",
                excess(c.keep_uv_excess),
                excess(c.rebaked_excess)
            ),
            (None, None) => match (&c.keep_uv_excess, &c.unmeasured) {
                (None, Some(why)) => {
                    format!("textures: UVs kept (their texture error was not measured: {why})")
                }
                _ => format!(
                    "textures: UVs kept (texture error over the input's own {}, below the visible {})",
                    excess(c.keep_uv_excess),
                    excess(c.visible_excess)
                ),
            },
        },
        (_, TextureMode::Bake) => "textures: re-baked (--textures bake)".to_string(),
        _ => "textures: UVs kept (--textures keep)".to_string(),
    }
}

/// The scene run's line: the file's triangles and achieved error (relative
/// to the file's diagonal, and in its units), how the budget was shared,
/// and the meshes that disappeared.
pub fn scene_summary(name: &str, r: &SceneReport, names: &[String], seconds: f64) -> String {
    let whole = wildlod_pipeline::whole_report(r);
    let mut s = summary(name, &whole, seconds);
    let shown = r.meshes.iter().filter(|m| m.input_triangles > 0).count();
    s.push_str(&format!(
        "; {shown} mesh{} under one budget, world error {:.3e} in file units",
        if shown == 1 { "" } else { "es" },
        r.world_error
    ));
    if r.common_threshold {
        s.push_str(&format!(
            " ({} groups that cannot share a complex, budget shared at one world error)",
            r.groups.len()
        ));
    }
    let removed = r.removed();
    if !removed.is_empty() {
        const LISTED: usize = 8;
        let mut list: Vec<&str> = removed
            .iter()
            .take(LISTED)
            .filter_map(|&m| names.get(m as usize).map(String::as_str))
            .collect();
        let more = removed.len().saturating_sub(LISTED);
        let tail = format!("and {more} more");
        if more > 0 {
            list.push(&tail);
        }
        s.push_str(&format!(
            "; {} mesh{} removed (every triangle went): {}",
            removed.len(),
            if removed.len() == 1 { "" } else { "es" },
            list.join(", ")
        ));
    }
    s
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

/// One line per mesh: `bunny: 6598 → 660 triangles, error 0.0021 of the
/// diagonal, 38 ms`,
/// and why it stopped short when it did.
pub fn summary(name: &str, r: &Report, seconds: f64) -> String {
    let mut s = format!(
        // Which error is which: this one is relative to the bounding-box
        // diagonal, the scene line's "world error" is in the file's units.
        "{name}: {} → {} triangles, error {:.4} of the diagonal, {:.0} ms",
        r.input_triangles,
        r.output_triangles,
        r.error,
        seconds * 1000.0
    );
    let short = r.output_triangles > r.target_triangles + 1;
    if let (true, Some(level)) = (short, r.held_by_constraints) {
        s.push_str(&format!(
            " (target {} held by the constraints: stopped at error {level:.4}, no farther from the input than the target without them)",
            r.target_triangles
        ));
    } else if short && r.stop == Some(StopReason::NoCollapsibleEdges) {
        let j = &r.rejected;
        s.push_str(&format!(
            " (target {} not reached: no collapsible edge left; refused by normal flip {}, topology {}, locked border {}, overshoot {}, flat border {})",
            r.target_triangles, j.normal_flip, j.topology, j.locked_border, j.overshoot, j.flat_border
        ));
    } else if short && r.stop == Some(StopReason::ErrorLimit) {
        s.push_str(" (stopped at the error limit)");
    }
    if r.twin_slack && r.output_triangles + 1 < r.target_triangles {
        s.push_str(&format!(
            " (target {}: the last faces carry twins, which go with their face)",
            r.target_triangles
        ));
    }
    if r.split_polygons > 0 {
        s.push_str(&format!(
            "; {} polygon{} of more than {} corners simplified and written as pieces",
            r.split_polygons,
            if r.split_polygons == 1 { "" } else { "s" },
            wildlod_simplify::MAX_POLYGON_CORNERS
        ));
    }
    if r.hidden_twins > 0 {
        s.push_str(&format!(
            "; {} hidden twin face{} dropped (reversed copies that cannot be seen; --keep-hidden-twins keeps them)",
            r.hidden_twins,
            if r.hidden_twins == 1 { "" } else { "s" },
        ));
    }
    if r.enclosed_parts > 0 {
        s.push_str(&format!(
            "; {} part{} inside a closed, opaque part dropped (they cannot be seen; --keep-enclosed-parts keeps them)",
            r.enclosed_parts,
            if r.enclosed_parts == 1 { "" } else { "s" },
        ));
    }
    if r.layer_vertices > 0 {
        s.push_str(&format!(
            "; {} vert{} of decals and other layers kept at their offset from the surface under them",
            r.layer_vertices,
            if r.layer_vertices == 1 { "ex" } else { "ices" },
        ));
    }
    if !r.outliers.is_empty() {
        s.push_str(&format!(
            "; {} outlier vert{} far from the rest left in place (errors are relative to the rest)",
            r.outliers.len(),
            if r.outliers.len() == 1 { "ex" } else { "ices" },
        ));
    }
    if let Some(radius) = r.virtual_radius_reduced {
        s.push_str(&format!(
            "; parts bridged only across gaps under {:.2e} of the diagonal (many small parts: \
             the requested --virtual-radius would have made more virtual edges than the budget)",
            2.0 * radius,
        ));
    }
    if let Some(q) = r.quad_ties.filter(|q| q.scale < 1.0) {
        if q.scale > 0.0 {
            s.push_str(&format!(
                "; quad ties narrowed to {:.2} of their width (wider ones left the surface farther \
                 than --quad-tolerance allows)",
                q.scale
            ));
        } else {
            s.push_str(
                "; the quad ordering would have left the surface farther than --quad-tolerance \
                 allows: the run without it is kept",
            );
        }
    }
    if r.steering.is_some_and(|s| !s.kept) {
        s.push_str(
            "; attributes would have cost geometry beyond the tolerance: the result of a run \
             where they did not steer is kept",
        );
    }
    s
}
