//! Arguments of the commands for asset libraries: `lod`, `batch`,
//! `report`. Names here are a contract, like those in [`crate::args`].

use std::path::PathBuf;

use clap::Args;

use crate::flags::{TextureArgs, TuningArgs};

/// Arguments of `wildlod lod`.
#[derive(Args, Debug)]
#[command(group(
    clap::ArgGroup::new("levels")
        .args(["ratios", "errors", "faces"])
        .multiple(false)
))]
pub struct LodArgs {
    /// The mesh to make levels of detail of (.gltf, .glb, .obj, .ply, .stl).
    pub input: PathBuf,
    /// Where to write (see --help for the files of each format)
    ///
    /// A .gltf/.glb holds every level (MSFT_lod) unless --split; other formats
    /// and --split write NAME_lod0.EXT, NAME_lod1.EXT… beside it (NAME: this
    /// file's stem; level 0 is the input).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Levels as fractions of the input's triangles (default)
    ///
    /// Finest first (0.5,0.25,0.1); 0 keeps as few as possible. The default
    /// when no level list is given.
    #[arg(long, value_name = "R,R,…", value_delimiter = ',')]
    pub ratios: Vec<f64>,
    /// Levels as error limits × the bounding-box diagonal
    ///
    /// Finest first (0.001,0.005,0.02): each level adds collapses while its
    /// accumulated error (the sum over the chain) stays within its limit.
    #[arg(long, value_name = "E,E,…", value_delimiter = ',')]
    pub errors: Vec<f64>,
    /// Levels as triangle budgets for the whole file
    ///
    /// Finest first (20000,5000,1000), shared among its meshes like simplify
    /// --faces.
    #[arg(long, value_name = "N,N,…", value_delimiter = ',')]
    pub faces: Vec<usize>,
    /// With glTF output: one file per level, not MSFT_lod
    #[arg(long)]
    pub split: bool,
    /// Keep, re-bake or choose textures per level.
    #[command(flatten)]
    pub textures: TextureArgs,
    /// Also write an HTML report of the chain
    ///
    /// At PATH or, without one, at NAME_report.html beside the output (put a
    /// bare --report after INPUT, or write --report=PATH).
    #[arg(long, value_name = "PATH", num_args = 0..=1)]
    pub report: Option<Option<PathBuf>>,
    /// Print a JSON report instead of one line per level
    ///
    /// Stable keys, documented in docs/cli.md.
    #[arg(long)]
    pub json: bool,
    /// Allow an output to replace the input file.
    #[arg(long)]
    pub overwrite: bool,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
    /// How to simplify: metric, guards, attributes.
    #[command(flatten)]
    pub tuning: TuningArgs,
}

/// Arguments of `wildlod batch`.
#[derive(Args, Debug)]
pub struct BatchArgs {
    /// The folder to read: every .gltf, .glb, .obj, .ply and .stl file below
    /// it.
    pub input: PathBuf,
    /// The folder to write into, mirroring the input's tree.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Keep this fraction of each file's triangles
    ///
    /// Default 0.5 when no target and no --lod-* list is given. Not with
    /// --faces.
    #[arg(long, value_name = "R")]
    pub ratio: Option<f64>,
    /// Keep at most this many triangles per file (not with --ratio).
    #[arg(long, value_name = "N", conflicts_with = "ratio")]
    pub faces: Option<usize>,
    /// Error limit relative to each file's bounding-box diagonal.
    #[arg(long, value_name = "E")]
    pub error: Option<f64>,
    /// Make a chain of each file instead (as lod --ratios)
    #[arg(long, value_name = "R,R,…", value_delimiter = ',', conflicts_with_all = ["ratio", "faces", "error", "lod_errors", "lod_faces"])]
    pub lod_ratios: Vec<f64>,
    /// A chain by error limits (see `wildlod lod --errors`).
    #[arg(long, value_name = "E,E,…", value_delimiter = ',', conflicts_with_all = ["ratio", "faces", "error", "lod_faces"])]
    pub lod_errors: Vec<f64>,
    /// A chain by triangle budgets (see `wildlod lod --faces`).
    #[arg(long, value_name = "N,N,…", value_delimiter = ',', conflicts_with_all = ["ratio", "faces", "error"])]
    pub lod_faces: Vec<usize>,
    /// With a chain and glTF files: one file per level instead of MSFT_lod.
    #[arg(long)]
    pub split: bool,
    /// Output format for every file (default: each keeps its own)
    ///
    /// One of gltf, glb, obj, ply, stl.
    #[arg(long, value_name = "EXT")]
    pub format: Option<String>,
    /// Files simplified at once (default: the number of cores).
    #[arg(long, short = 'j', value_name = "N")]
    pub jobs: Option<usize>,
    /// Keep, re-bake or choose textures per file (per level of a chain),
    /// as simplify and lod do.
    #[command(flatten)]
    pub textures: TextureArgs,
    /// Simplify every stored mesh alone instead of each whole file
    ///
    /// As simplify --per-mesh; without it each file is simplified under one
    /// budget in world space, as simplify does.
    #[arg(long)]
    pub per_mesh: bool,
    /// Skip files whose outputs exist (resume a run)
    ///
    /// They are listed as skipped in the summary.
    #[arg(long)]
    pub skip_existing: bool,
    /// Where to write the summary (.json or .csv)
    ///
    /// Default: OUTPUT/wildlod-summary.json and .csv.
    #[arg(long, value_name = "PATH")]
    pub summary: Option<PathBuf>,
    /// Print the JSON summary to standard output as well.
    #[arg(long)]
    pub json: bool,
    /// Print nothing but errors (and no progress bar).
    #[arg(short, long)]
    pub quiet: bool,
    /// How to simplify: metric, guards, attributes.
    #[command(flatten)]
    pub tuning: TuningArgs,
}

/// Arguments of `wildlod report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// The reference mesh (usually the original).
    pub reference: PathBuf,
    /// The candidate mesh (usually a level of detail).
    pub candidate: PathBuf,
    /// The HTML file to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Area samples per surface for the metrics (as `compare --samples`).
    #[arg(long, default_value_t = 100_000)]
    pub samples: usize,
    /// Allow the output to replace an existing file given as input.
    #[arg(long)]
    pub overwrite: bool,
    /// Print what the page shows as JSON (the keys of `wildlod.report`).
    #[arg(long)]
    pub json: bool,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}
