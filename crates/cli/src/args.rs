//! The command line, as users script against it. Names here are a contract:
//! `simplify INPUT -o OUTPUT --ratio R | --faces N | --error E`,
//! `info FILE --json`, `compare REF CAND --json`.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Levels of detail for real-world meshes: non-manifold, many-component,
/// triangle soups, textured, quad-dominant, skinned.
///
/// Formats: glTF 2.0 (.gltf, .glb), OBJ (+MTL), PLY, STL, OFF. The output format
/// follows the output file's extension.
#[derive(Parser, Debug)]
#[command(name = "wildlod", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Simplify a mesh file to a target triangle count, ratio or error.
    ///
    /// The whole file is simplified under one budget, in world space:
    /// --ratio and --faces count the triangles the file draws (a
    /// mesh shown by several nodes once per node), --error is relative to
    /// the whole file's size, and the
    /// triangles go where the error is smallest. A mesh whose every
    /// triangle goes is removed (nodes no longer show it; the summary names
    /// it). A mesh instanced several times is simplified once, as large as
    /// its largest instance. --per-mesh simplifies every stored mesh alone
    /// instead (each keeps a triangle). Polygons of more than 32 corners are
    /// simplified (and written) as pieces of at most 32. Materials, nodes,
    /// skins and animations are written back unchanged.
    // The examples go in `after_help`: clap rewraps doc-comment paragraphs,
    // which ran the three of them into one line.
    #[command(after_help = SIMPLIFY_EXAMPLES, allow_negative_numbers = true)]
    Simplify(SimplifyArgs),
    /// Describe a mesh file: faces by arity, topology, UVs, materials, skins.
    ///
    /// Topology (components, boundary and non-manifold edges) is computed
    /// after welding equal positions. Counts are totals over the file with
    /// each stored mesh counted once; `drawn` (JSON: `instanced` and
    /// `drawn_triangles`) counts each mesh once per node that shows it, the
    /// count simplify, lod and batch use.
    Info(InfoArgs),
    /// Measure how far a candidate (a level of detail) is from a reference.
    ///
    /// Both are normalized by the reference's bounding-box diagonal and
    /// sampled uniformly by area; distances are exact point-to-triangle
    /// distances. Reports Hausdorff (both directions and their maximum),
    /// Chamfer as mean distance and as mean squared distance, the quad ratio
    /// (Knodt 2024) and, when both have a base color texture, the texture
    /// Chamfer distance (Liu et al. 2025). Deterministic for a given seed.
    #[command(after_help = COMPARE_EXAMPLES, allow_negative_numbers = true)]
    Compare(CompareArgs),
    /// Run the main job on a built-in example: write a wild mesh generated
    /// in code and its level of detail, and describe both.
    #[command(allow_negative_numbers = true)]
    Demo(DemoArgs),
    /// Make a chain of levels of detail, each from the one before.
    ///
    /// Each level is simplified from the one before and shares the input's
    /// materials and textures.
    ///
    /// glTF output holds every level in one file as MSFT_lod (nodes listing
    /// their lower levels, with MSFT_screencoverage hints from each level's
    /// error); --split, OBJ, PLY and STL write NAME_lod0…NAME_lodN, level 0
    /// being the input.
    #[command(after_help = LOD_EXAMPLES)]
    Lod(crate::args_assets::LodArgs),
    /// Simplify every mesh file below a folder into another folder, in
    /// parallel, and write a summary.
    ///
    /// The output mirrors the input's tree. A file that fails is listed in
    /// the summary (OUTPUT/wildlod-summary.json and .csv) and the run goes
    /// on; the exit code is 1 if any failed.
    #[command(after_help = BATCH_EXAMPLES)]
    Batch(crate::args_assets::BatchArgs),
    /// Write one self-contained HTML page comparing two meshes: both in
    /// synchronized 3D views, the candidate colored by its distance to the
    /// reference, and the metrics of `compare`.
    ///
    /// Example:
    ///   wildlod report bunny.obj bunny_lod.obj -o report.html
    Report(crate::args_assets::ReportArgs),
}

/// Shown after `wildlod simplify --help`, one example per line.
const SIMPLIFY_EXAMPLES: &str = "\
Examples:
  wildlod simplify bunny.obj -o bunny_lod.obj --ratio 0.1
  wildlod simplify truck.glb -o truck_lod.glb --faces 2000
  wildlod simplify scan.ply -o scan_lod.stl --error 0.001";

/// Shown after `wildlod lod --help`, one example per line.
const LOD_EXAMPLES: &str = "\
Examples:
  wildlod lod chair.glb -o chair_lods.glb --ratios 0.5,0.25,0.1
  wildlod lod scan.obj -o out/scan.obj --errors 0.001,0.005,0.02
  wildlod lod truck.glb -o truck.glb --faces 20000,5000,1000 --split";

/// Shown after `wildlod batch --help`, one example per line.
const BATCH_EXAMPLES: &str = "\
Examples:
  wildlod batch assets/ -o lods/ --ratio 0.25
  wildlod batch assets/ -o lods/ --lod-ratios 0.5,0.25,0.1 --jobs 4
  wildlod batch assets/ -o lods/ --ratio 0.25 --skip-existing";

/// Shown after `wildlod compare --help`.
const COMPARE_EXAMPLES: &str = "\
Example:
  wildlod compare bunny.obj bunny_lod.obj --json";

/// Arguments of `wildlod simplify`.
#[derive(Args, Debug)]
pub struct SimplifyArgs {
    /// The mesh to simplify (.gltf, .glb, .obj, .ply, .stl, .off)
    pub input: PathBuf,
    /// Where to write the result; its extension picks the format
    ///
    /// Its folder must exist.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Keep this fraction of the triangles, 0 to 1 (default 0.5)
    ///
    /// A quad counts as two triangles. 0 keeps as few as possible: one triangle
    /// in the file (one per mesh with --per-mesh), or what the guards leave.
    /// Not with --faces.
    #[arg(long, value_name = "R")]
    pub ratio: Option<f64>,
    /// Keep at most this many triangles in the file
    ///
    /// A quad counts as two. Not with --ratio.
    #[arg(long, value_name = "N", conflicts_with = "ratio")]
    pub faces: Option<usize>,
    /// Stop before the error exceeds E × the bounding-box diagonal
    ///
    /// 0.001 is 0.1% of the diagonal. Combines with --ratio/--faces: the first
    /// limit reached stops.
    #[arg(long, value_name = "E")]
    pub error: Option<f64>,
    /// Keep, re-bake or choose textures, and how to re-bake.
    #[command(flatten)]
    pub texture: crate::args_assets::TextureArgs,
    /// Re-bake textures onto a new atlas (same as --textures bake)
    ///
    /// Collapses cross UV seams freely, the simplified mesh gets a new atlas,
    /// and every texel of it is mapped back to the input through the collapse
    /// history to bake every channel of its material (base color with vertex
    /// colors, metallic-roughness, normal, occlusion, emissive) with no
    /// bleeding.
    #[arg(long)]
    pub bake: bool,
    /// Simplify every stored mesh alone instead of the whole file
    ///
    /// Each mesh goes to --ratio, --faces is shared in proportion to the
    /// triangles each mesh draws, --error is converted to each mesh's size;
    /// every mesh keeps a triangle. Without it the whole file is simplified
    /// under one budget in world space, so the triangles go where the error is
    /// smallest and a part too small to matter may disappear. --bake always
    /// works per mesh.
    #[arg(long)]
    pub per_mesh: bool,
    /// Allow the output to replace the input file
    #[arg(long)]
    pub overwrite: bool,
    /// Print nothing but errors
    #[arg(short, long)]
    pub quiet: bool,
    /// Print a JSON report instead of one line per mesh
    ///
    /// Stable keys, documented in docs/cli.md.
    #[arg(long)]
    pub json: bool,
    /// How to simplify: metric, guards, attributes.
    #[command(flatten)]
    pub tuning: TuningArgs,
}

/// How to simplify, shared by `simplify`, `lod` and `batch`.
#[derive(Args, Debug, Clone)]
pub struct TuningArgs {
    /// Merge distance for separate parts (0: never merge)
    ///
    /// Radius r of virtual edges, relative to the bounding-box diagonal: parts
    /// of different components closer than 2r may merge. 0 disables.
    #[arg(long, value_name = "R", default_value_t = wildlod_simplify::Options::default().virtual_edge_radius)]
    pub virtual_radius: f64,
    /// Keep topology: no merging of parts, no closing of holes
    ///
    /// A manifold stays a manifold of the same genus. The target may be out of
    /// reach.
    #[arg(long)]
    pub keep_topology: bool,
    /// Never move or remove vertices on open borders
    #[arg(long)]
    pub lock_borders: bool,
    /// Largest turn of a face in one collapse, in degrees
    ///
    /// 180 turns the flip guard off.
    #[arg(long, value_name = "DEG", default_value_t = 90.0)]
    pub max_normal_turn: f64,
    /// Do not try to keep quads
    ///
    /// Plain cost order even when the input has quads. By default a mesh with
    /// quads is reduced by an ordering that removes whole quad chords and keeps
    /// edge loops.
    #[arg(long)]
    pub no_quads: bool,
    /// Quad keeping tolerance (larger: more quads)
    ///
    /// Tolerance under which collapse costs count as equal and are ordered to
    /// keep quads, as a distance relative to the diagonal at the input's
    /// resolution; it grows with the reduction (twice as wide once half the
    /// vertices are gone, up to ten times). It is the widest the tolerance
    /// gets: on a finely tessellated mesh, whose collapses deviate less, it is
    /// twice the median initial collapse's deviation where that is smaller.
    #[arg(long, value_name = "E", default_value_t = wildlod_simplify::QuadSettings::default().epsilon)]
    pub quad_epsilon: f64,
    /// Quad tie width vs the mesh's detail (0: off)
    ///
    /// Width of the quad ties as a multiple of the input's median initial
    /// collapse deviation, at most --quad-epsilon: a finely tessellated or
    /// finely curved mesh, whose collapses deviate less, gets narrower ties and
    /// keeps closer to its input. 0 uses --quad-epsilon alone.
    #[arg(long, value_name = "F", default_value_t = wildlod_simplify::QuadSettings::default().tie_factor)]
    pub quad_tie_factor: f64,
    /// Hold edges along creases and keep edge flow (0: off)
    ///
    /// Weight of tangent edge quadrics against the face planes (0.33 balances
    /// them). They hold edges in place along creases and keep edge flow and
    /// thin parts; off by default because they trade distance for regularity
    /// and, on the quad corpus, kept fewer quads than the ordering alone.
    #[arg(long, value_name = "W", default_value_t = 0.0)]
    pub tangent_weight: f64,
    /// Keep mirror symmetry lines (0: off; try 0.33)
    ///
    /// Edges on planes that mirror the model onto itself weigh more, so
    /// symmetry lines survive. Works through the tangent quadrics: turns them
    /// on at 0.33 unless --tangent-weight is given. Costs time on large meshes
    /// (capped at about ten seconds).
    #[arg(long, value_name = "L", default_value_t = 0.0)]
    pub symmetry: f64,
    /// Keep sub-face features longer (try 1; 0: off)
    ///
    /// Rank collapses as if they covered at least this many mean input faces:
    /// features far smaller than a face (hair-thin spurs, tiny parts) are then
    /// ranked by distance rather than by their area, and are kept longer. Off
    /// by default, because on the corpus it costs textured meshes more than it
    /// gains elsewhere.
    #[arg(long, value_name = "K", default_value_t = wildlod_simplify::Metric::default().area_floor)]
    pub area_floor: f64,
    /// Keep thin parts longer (0: off, 1: last)
    ///
    /// Added to the cost of a collapse that pinches or folds material: thin
    /// legs, blades and hair-thin strands stay until nothing cheaper is left,
    /// instead of flattening into edges the output cannot show. 1 ranks such
    /// collapses after every ordinary one (up to --pinch-distance); 0 lets them
    /// compete at their plane cost. Merging parts, closing holes and dropping
    /// parts too small for the target are never penalized.
    #[arg(long, value_name = "C", default_value_t = wildlod_simplify::Metric::default().pinch_cost)]
    pub pinch_cost: f64,
    /// Error at which thin parts may flatten (0: never)
    ///
    /// Caps the pinch cost: a thin part of a part large enough for the target
    /// is flattened once the ordinary collapses left would move the surface by
    /// about half this distance (relative to the bounding-box diagonal), so an
    /// extreme target does not fold the rest of a model to keep thin wires. 0
    /// keeps thin parts until nothing else is left. With --error alone there is
    /// no cap.
    #[arg(long, value_name = "D", default_value_t = wildlod_simplify::Metric::default().pinch_distance)]
    pub pinch_distance: f64,
    /// Weigh faces by area^A (0: all alike)
    ///
    /// How face planes weigh in the error, from 0 to 1. 1 (area-weighted
    /// quadrics) gives the lowest mean distance; 0 weighs every face alike, as
    /// Blender's Decimate does, which keeps finely tessellated details and
    /// lowers the worst-case (Hausdorff) distance at some cost in the mean.
    #[arg(long, value_name = "A", default_value_t = wildlod_simplify::Metric::default().area_exponent)]
    pub area_exponent: f64,
    /// Small faces weigh at least K mean faces (0: off)
    ///
    /// Details tessellated finer than the rest (a scanned hair, a fillet,
    /// engraved text) then cost like the rest of the surface instead of going
    /// first, which lowers the worst-case distance. Parts too small for the
    /// target still go first. 0 is plain area weighting. Quad mode always uses
    /// plain area weighting.
    #[arg(long, value_name = "K", default_value_t = wildlod_simplify::Metric::default().face_weight_floor)]
    pub face_weight_floor: f64,
    /// Hold sharp creases (CAD edges) in place (0: off)
    ///
    /// Through every side whose two faces turn by more than --crease-angle, the
    /// plane through it orthogonal to each face is weighted by this times the
    /// side's squared length, as a border is held. Raise it when a part's
    /// outlines slide inward. Not where attributes steer collapses (their hard
    /// edges are seams, held by --seam-weight).
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::Metric::default().crease_weight)]
    pub crease_weight: f64,
    /// Turn between faces, in degrees, that makes a crease
    ///
    /// Between 0 and 180: above it, the shared side of two faces is a crease
    /// for --crease-weight and --crease-area-weight. The default holds CAD
    /// edges of about 90 degrees and sharper, not the folds of a scan.
    #[arg(long, value_name = "DEG", default_value_t = wildlod_simplify::Metric::default().crease_angle)]
    pub crease_angle: f64,
    /// Keep finely cut creases straight (0: off)
    ///
    /// Weight of the area a collapse sweeps against a crease, relative to the
    /// same term at open borders: it sees the crease as simplified so far, so
    /// an edge cut into many short sides holds as well as one long side.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::Metric::default().crease_area_weight)]
    pub crease_area_weight: f64,
    /// Sweeps of the final vertex refit (0: off)
    ///
    /// Once the collapses are done, every vertex moves to where its error
    /// quadric plus the input's distances to its faces are smallest, which
    /// lowers the distance between input and output. A vertex never moves
    /// farther from the input than the input points it fits, nor folds a face.
    /// --classic and --symmetry do not refit (it would move vertices off the
    /// mirror plane).
    #[arg(long, value_name = "N", default_value_t = wildlod_simplify::Options::default().refit_sweeps)]
    pub refit_sweeps: u32,
    /// Keep back-to-back duplicate faces that cannot be seen
    ///
    /// Exporters make surfaces double-sided by writing every face twice, once
    /// each way; on a closed part one copy looks into the solid, and elsewhere
    /// a copy from which no ray escapes the mesh and no line of sight reaches
    /// an opening is enclosed too. By default such copies are dropped before
    /// simplifying and their share of the budget buys visible detail. Open
    /// sheets and blended (see-through) materials keep both sides.
    #[arg(long)]
    pub keep_hidden_twins: bool,
    /// Classic quadric error simplification, for comparisons
    ///
    /// No virtual edges, no area term.
    #[arg(long)]
    pub classic: bool,
    /// How much UVs steer collapses (raise if smeared)
    ///
    /// Every attribute is fitted at the new positions whatever its weight; a
    /// weight says how much a change of it costs: 1 makes a change across the
    /// stream's whole range cost as much as moving the surface by the whole
    /// bounding-box diagonal. 0 lets geometry alone decide.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().tex_coord_weight)]
    pub uv_weight: f64,
    /// How much normals steer collapses
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().normal_weight)]
    pub normal_weight: f64,
    /// How much vertex colors steer collapses
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().color_weight)]
    pub color_weight: f64,
    /// How much skin weights steer collapses
    ///
    /// Joints are fitted per position and written as the input's number of
    /// influences, summing to 1.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().skin_weight)]
    pub skin_weight: f64,
    /// Seams: penalize, keep or ignore (see --help)
    ///
    /// `penalize` crosses a seam only where that costs less than what else is
    /// left (moving a seam costs its distance, merging two sides costs the
    /// difference of their values: UV charts apart stay apart); `keep` never
    /// crosses them (the target may be missed); `ignore` lets them move and
    /// close like any edge (for re-baked textures).
    #[arg(long, value_enum, default_value_t = SeamArg::Penalize, hide_possible_values = true)]
    pub seams: SeamArg,
    /// How firmly seams hold their path (0: may bend)
    ///
    /// Weight of the planes that hold seam vertices on their seam when a
    /// collapse slides them along it, per squared edge length; 0: seams may
    /// bend within their charts.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().seam_weight)]
    pub seam_weight: f64,
    /// Output normals: fitted or recomputed
    ///
    /// `fit` carries the input's normals through every collapse (smooth shading
    /// survives); `recompute` derives them from the simplified faces, keeping
    /// the input's hard edges.
    #[arg(long, value_enum, default_value_t = NormalArg::Fit, hide_possible_values = true)]
    pub normals: NormalArg,
}

/// Arguments of `wildlod info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The mesh file to describe.
    pub file: PathBuf,
    /// Print JSON (stable keys, documented in docs/cli.md) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `wildlod compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The reference mesh (usually the original).
    pub reference: PathBuf,
    /// The candidate mesh (usually a level of detail).
    pub candidate: PathBuf,
    /// Print JSON (stable keys, documented in docs/cli.md) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Area samples per surface for the distances.
    #[arg(long, default_value_t = 100_000)]
    pub samples: usize,
    /// Samples per surface for the texture and normal Chamfer distances.
    #[arg(long, default_value_t = 40_000)]
    pub texture_samples: usize,
    /// Seed of the sampling.
    #[arg(long, default_value_t = wildlod_eval::DEFAULT_SEED)]
    pub seed: u64,
    /// Also compare both files posed at frames of this animation (index
    /// into the reference's animations; the candidate's animation of the
    /// same index is used): how a skinned level of detail looks when it
    /// moves (Knodt 2024 §4 uses the first 50 frames of animation 0).
    #[arg(long, value_name = "INDEX")]
    pub animation: Option<usize>,
    /// Frames to compare with --animation, from time 0.
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub frames: usize,
    /// Frame rate of those frames (glTF animations have times, not frames).
    #[arg(long, value_name = "FPS", default_value_t = 30.0)]
    pub fps: f64,
}

/// Arguments of `wildlod demo`.
#[derive(Args, Debug)]
pub struct DemoArgs {
    /// Folder to write `demo_input.obj` and `demo_lod.obj` into.
    #[arg(short, long, default_value = "wildlod-demo")]
    pub out: PathBuf,
    /// Ratio of triangles the level of detail keeps.
    #[arg(long, default_value_t = 0.1)]
    pub ratio: f64,
}

/// `--textures`: keep the UVs, re-bake, or choose by measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TextureArg {
    /// Keep the UVs; re-bake where that shows the texture visibly worse
    /// and the re-bake measures better.
    Auto,
    /// Keep the input's UVs and atlas.
    Keep,
    /// Re-bake onto a new atlas.
    Bake,
}

/// `--seams`: what happens to attribute seams.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SeamArg {
    /// Cross seams only where that costs less than what else is left.
    Penalize,
    /// Never cross seams; the target may be missed.
    Keep,
    /// Let seams move and close like any edge.
    Ignore,
}

/// `--normals`: how output normals are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalArg {
    /// Fitted through every collapse, then normalized.
    Fit,
    /// Recomputed from the simplified faces, input hard edges kept.
    Recompute,
}
