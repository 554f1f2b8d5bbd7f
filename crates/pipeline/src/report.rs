//! The machine-readable reports of `simplify --json` and `lod --json`
//! (keys documented in docs/cli.md; add keys, never rename or remove
//! them). The Python package returns the same keys as dicts.

use std::path::Path;

use wildlod_simplify::StopReason;

use crate::MeshRun;

/// One mesh in a report (`meshes` of `simplify --json`, of each level of
/// `lod --json`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct MeshJson {
    /// The mesh's name ([`crate::mesh_name`]).
    pub name: String,
    /// Its index in the file.
    pub mesh: usize,
    /// Triangles before (a quad counts as two).
    pub input_triangles: usize,
    /// Triangles aimed for.
    pub target_triangles: usize,
    /// Triangles reached.
    pub output_triangles: usize,
    /// Error reached, relative to the mesh's diagonal.
    pub error: f64,
    /// Why it stopped ([`stop_key`]), or null when it never started.
    pub stop: Option<String>,
    /// Collapses done.
    pub collapses: usize,
    /// Collapse costs evaluated: the loop's work, which grows with the
    /// input's size (see `wildlod_simplify::Report::evaluations`).
    pub evaluations: usize,
    /// Faces the flip and flatten tests read (see
    /// `wildlod_simplify::Report::faces_tested`).
    pub faces_tested: usize,
    /// Collapses the guards refused, by guard: why a target may be missed
    /// or a run slow.
    pub rejected: RejectedJson,
    /// Polygons of more than `wildlod_simplify::MAX_POLYGON_CORNERS`
    /// corners simplified and written as pieces.
    pub split_polygons: usize,
    /// Reversed copies of faces that cannot be seen (inside a closed or
    /// almost closed surface), dropped before simplifying
    /// (`--keep-hidden-twins` keeps them).
    pub hidden_twins: usize,
    /// Parts wholly inside a closed, opaque part, dropped before
    /// simplifying (`--keep-enclosed-parts` keeps them).
    pub enclosed_parts: usize,
    /// Went below the target by more than one triangle because the last
    /// collapse took faces with their twins, which go together.
    pub twin_slack: bool,
    /// The share (0 to 1) of the textured surface whose kept UVs fold or
    /// stretch beyond 4× the input's texel density; null without textured
    /// UVs.
    pub uv_damage: Option<f64>,
    /// With attributes that steer: whether their steering was kept (the
    /// result was within the geometric tolerance of a run where they did
    /// not steer) and the distances both runs measured; null otherwise.
    pub steering: Option<SteeringJson>,
    /// With the quad ordering held to the surface: how wide its ties were
    /// and the mean distances that chose the width; null when the
    /// ordering was off or not held.
    pub quad_ties: Option<QuadTiesJson>,
    /// Vertices far from the bulk of the others (a height of -1e30 an
    /// exporter wrote): left where they were; errors are relative to the
    /// rest's diagonal.
    pub outliers: usize,
    /// Vertices of decals and other layers (open sheets lying on another
    /// part) placed at their input offset from the simplified surface
    /// under them (`--no-layers` lets them sink).
    pub layer_vertices: usize,
    /// The virtual-edge radius (relative to the diagonal) that separate
    /// parts were bridged at when the requested `--virtual-radius` would
    /// have made more virtual edges than the search's budget, which is
    /// linear in the input (many parts much smaller than the radius); null
    /// when the requested radius was used.
    pub virtual_radius_reduced: Option<f64>,
    /// Where `--lock-borders`, `--keep-topology` or `--seams keep` kept the
    /// run from its target: the error (relative to the diagonal of its
    /// mesh group, the largest over groups) a run without them has at as
    /// many triangles as they leave, where this run stopped instead of
    /// making every collapse left; null otherwise.
    pub held_by_constraints: Option<f64>,
    /// Wall time.
    pub seconds: f64,
}

impl MeshJson {
    /// The report of one run.
    pub fn new(r: &MeshRun) -> Self {
        MeshJson {
            name: r.name.clone(),
            mesh: r.mesh,
            input_triangles: r.report.input_triangles,
            target_triangles: r.report.target_triangles,
            output_triangles: r.report.output_triangles,
            error: r.report.error,
            stop: r.report.stop.map(|s| stop_key(s).to_string()),
            collapses: r.report.collapses,
            evaluations: r.report.evaluations,
            faces_tested: r.report.faces_tested,
            rejected: RejectedJson::new(&r.report.rejected),
            split_polygons: r.report.split_polygons,
            hidden_twins: r.report.hidden_twins,
            enclosed_parts: r.report.enclosed_parts,
            twin_slack: r.report.twin_slack,
            uv_damage: r.report.uv_damage,
            outliers: r.report.outliers.len(),
            layer_vertices: r.report.layer_vertices,
            virtual_radius_reduced: r.report.virtual_radius_reduced,
            held_by_constraints: r.report.held_by_constraints,
            steering: r.report.steering.map(|s| SteeringJson {
                kept: s.kept,
                hausdorff: s.hausdorff,
                chamfer: s.chamfer,
                geometry_hausdorff: s.geometry_hausdorff,
                geometry_chamfer: s.geometry_chamfer,
            }),
            quad_ties: r.report.quad_ties.map(|q| QuadTiesJson {
                scale: q.scale,
                chamfer: q.chamfer,
                plain_chamfer: q.plain_chamfer,
            }),
            seconds: r.seconds,
        }
    }
}

/// `quad_ties` of a mesh in a report: see [`wildlod_simplify::QuadTies`]
/// (distances relative to the diagonal).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct QuadTiesJson {
    /// The tie distance the output was made with, as a share of the one
    /// set (1: as set; 0: the run without the ordering is the output).
    pub scale: f64,
    /// The output's mean distance to the input.
    pub chamfer: f64,
    /// The mean distance to the input of the run without the ordering.
    pub plain_chamfer: f64,
}

/// `rejected` of a mesh in a report: see
/// [`wildlod_simplify::Rejections`].
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct RejectedJson {
    /// A surviving face would have turned past the normal limit.
    pub normal_flip: usize,
    /// A surviving face would have flattened to a line.
    pub flat_border: usize,
    /// The link condition failed (`--keep-topology`).
    pub topology: usize,
    /// A border vertex would have moved (`--lock-borders`).
    pub locked_border: usize,
    /// The collapse would have gone past the target.
    pub overshoot: usize,
    /// The collapse's error exceeded `--error`.
    pub error_limit: usize,
}

impl RejectedJson {
    /// The counts of `r`.
    pub fn new(r: &wildlod_simplify::Rejections) -> Self {
        RejectedJson {
            normal_flip: r.normal_flip,
            flat_border: r.flat_border,
            topology: r.topology,
            locked_border: r.locked_border,
            overshoot: r.overshoot,
            error_limit: r.error_limit,
        }
    }
}

/// `steering` of a mesh in a report: see
/// [`wildlod_simplify::SteeringOutcome`] (distances relative to the
/// diagonal).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct SteeringJson {
    /// The steered result is the output.
    pub kept: bool,
    /// The steered result's largest distance to the input.
    pub hausdorff: f64,
    /// The steered result's mean distance to the input.
    pub chamfer: f64,
    /// The unsteered result's largest distance to the input.
    pub geometry_hausdorff: f64,
    /// The unsteered result's mean distance to the input.
    pub geometry_chamfer: f64,
}

/// The stable JSON name of a stop reason.
pub fn stop_key(s: StopReason) -> &'static str {
    match s {
        StopReason::TargetReached => "target_reached",
        StopReason::ErrorLimit => "error_limit",
        StopReason::NoCollapsibleEdges => "no_collapsible_edges",
        StopReason::NothingToDo => "nothing_to_do",
    }
}

/// `simplify --json`: one file simplified.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunJson {
    /// The input file.
    pub input: String,
    /// The output file.
    pub output: String,
    /// Triangles of the simplified meshes before.
    pub input_triangles: usize,
    /// Triangles of the simplified meshes after.
    pub output_triangles: usize,
    /// Largest error over the meshes (each relative to its own diagonal).
    pub error: f64,
    /// Wall time of the whole run (read, simplify, write).
    pub seconds: f64,
    /// Every simplified mesh.
    pub meshes: Vec<MeshJson>,
    /// Keep-UV or re-bake, and the measurements that chose it (files with
    /// a base colour texture).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub textures: Option<crate::TextureChoice>,
    /// Reversed twin face pairs written once with a double-sided material
    /// (glTF outputs; see [`crate::merge_twins_double_sided`]).
    pub double_sided_twins: usize,
}

impl RunJson {
    /// The report of a file's runs.
    pub fn new(input: &Path, output: &Path, runs: &[MeshRun], seconds: f64) -> Self {
        RunJson {
            input: input.display().to_string(),
            output: output.display().to_string(),
            input_triangles: runs.iter().map(|r| r.report.input_triangles).sum(),
            output_triangles: runs.iter().map(|r| r.report.output_triangles).sum(),
            error: runs.iter().map(|r| r.report.error).fold(0.0, f64::max),
            seconds,
            meshes: runs.iter().map(MeshJson::new).collect(),
            textures: None,
            double_sided_twins: 0,
        }
    }
}

/// One level in `lod --json` (level 0 is the input).
#[derive(Clone, Debug, serde::Serialize)]
pub struct LevelJson {
    /// 0 for the input, 1 for the first level below it.
    pub level: usize,
    /// Triangles the level draws (each mesh once per node that shows it).
    pub triangles: usize,
    /// Triangles as a fraction of the input's.
    pub ratio: f64,
    /// Accumulated error relative to the file's diagonal.
    pub error: f64,
    /// Wall time of this level.
    pub seconds: f64,
    /// The file holding this level.
    pub file: Option<String>,
    /// The `MSFT_screencoverage` hint of a file's only mesh; null for files
    /// of several meshes (each base node has its own).
    pub screen_coverage: Option<f64>,
    /// The simplifier's runs that made it from the level above (from the
    /// input, for a re-baked level).
    pub meshes: Vec<MeshJson>,
    /// How the level's textures were treated and why (as `simplify
    /// --json`'s `textures`); null for the input and for files without
    /// textures.
    pub textures: Option<crate::TextureChoice>,
}

/// `lod --json`: a chain of levels.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ChainJson {
    /// The input file.
    pub input: String,
    /// Every file written.
    pub files: Vec<String>,
    /// The HTML report, when one was written.
    pub report: Option<String>,
    /// Wall time of the whole run.
    pub seconds: f64,
    /// Level 0 (the input) and every level below it.
    pub levels: Vec<LevelJson>,
}
