//! The command line, as users script against it. Names here are a contract:
//! `simplify INPUT -o OUTPUT --ratio R | --faces N | --error E`,
//! `info FILE --json`, `compare REF CAND --json`.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::flags::{TextureArgs, TuningArgs};

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
    pub texture: TextureArgs,
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
