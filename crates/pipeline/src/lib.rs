//! File-level pipelines of wildlod: what a command of the `wildlod` binary
//! does to a file, as library functions that the CLI and the Python
//! package both call, so both give the same results and the same reports.
//!
//! - [`Tuning`]: how to simplify, as named settings with their ranges
//!   checked, turned into [`wildlod_simplify::Options`];
//! - [`simplify_scene`] and [`simplify_file`]: every mesh of a file to its
//!   share of a target ([`targets_for`]), reported as [`RunJson`];
//! - [`build_chain`], [`write_chain`] and [`lod_file`]: nested levels of
//!   detail, glTF `MSFT_lod` with `MSFT_screencoverage` hints or one file
//!   per level, reported as [`ChainJson`]; re-baked levels carry their own
//!   materials ([`LevelMaterials`]);
//! - [`run_batch`]: every file of a folder, with the summary of
//!   `batch` ([`BatchSummary`]);
//! - [`describe`]: what `info --json` prints ([`FileInfo`]);
//! - [`compare_files`]: what `compare --json` prints;
//! - [`report_files`] and [`write_chain_report`]: the HTML report of
//!   `report` and `lod --report` ([`ReportJson`]).
//!
//! Data flows one way: io → mesh → simplify → mesh → io. Nothing here
//! prints; progress goes to a [`MeshProgress`] the caller chooses.

mod batch;
mod chain;
mod chain_textures;
mod compare;
mod double_sided;
mod error;
mod file;
mod html_report;
mod info;
mod level_materials;
mod progress;
mod rebake;
mod report;
mod scene;
mod targets;
mod textures;
mod tuning;

pub use batch::{
    batch_file, mesh_files, run_batch, summary_csv, summary_paths, write_summary, BatchJob,
    BatchSettings, BatchSummary, FileResult,
};
pub use chain::{
    build_chain, chain_json, chain_paths, coverage_for_error, drawn_triangles, level_path,
    normalize_weights, screen_coverage, write_chain, Level, Levels, FULL_VIEW_COVERAGE,
    PIXEL_TOLERANCE, SCREEN_PIXELS, SCREEN_WIDTH_PIXELS,
};
pub use chain_textures::rebake_levels;
pub use compare::{
    compare_files, load_images, Animated, CompareFilesOptions, FileComparison, Frame,
};
pub use double_sided::{merge_twins_double_sided, merge_twins_for_output, MergedTwins};
pub use error::Error;
pub use file::{lod_file, simplify_document, simplify_file, FileTargets, SimplifiedDocument};
pub use html_report::{
    report_files, report_page, write_chain_report, CandidateReport, ReportJson, ReportModel,
    ReportOptions,
};
pub use info::{describe, FaceCounts, FileInfo, MeshInfo};
pub use level_materials::{append_level_materials, level_scene, LevelMaterials};
pub use progress::{MeshProgress, NoProgress};
pub use rebake::{rebake_scene, BakeSettings, RebakedRun};
pub use report::{stop_key, ChainJson, LevelJson, MeshJson, RunJson};
pub use scene::{
    clear_unused_joint_slots, file_stem, mesh_name, simplify_scene, simplify_whole_scene,
    whole_report, MeshRun,
};
pub use targets::{
    drawn_targets, scene_diagonal, share_budget, targets_for, world_diagonal, MIN_TRIANGLES,
};
pub use textures::{
    choose as choose_textures, has_base_color_texture, texture_error, texture_excess,
    treat_textures, visible_excess, worth_rebaking, TextureChoice, TextureError, TextureMode,
    TextureSettings, VISIBLE_SHARE_OF_FLOOR, VISIBLE_TEXTURE_EXCESS,
};
pub use tuning::{NormalSetting, SeamSetting, Tuning};
