//! Texture re-baking for levels of detail (Liu, Zhang & Yuksel 2025, "W",
//! §4.3, App. B, App. C.2).
//!
//! A simplifier that must keep every UV seam cannot reduce meshes with
//! thousands of UV islands. W lets collapses cross seams freely, records the
//! collapse history, and afterwards re-bakes the textures onto a new
//! parametrization of the simplified mesh, mapping every texel back to the
//! input surface through the history. This crate does that, with no I/O
//! (images arrive decoded):
//!
//! - [`SuccessiveMap`] (`mapping.rs`): a point of the simplified mesh → the
//!   input face and barycentrics it came from (W §4.3.1). Public, so engines
//!   can bake their own channels.
//! - [`build_atlas`] (`atlas/`): a new injective UV layout, charts packed
//!   with gutters, and [`atlas_stats`] to measure one.
//! - `density.rs`: the input's texel density over each output triangle,
//!   through the mapping, so that charts get texels where the input has
//!   its detail ([`build_atlas_weighted`]).
//! - [`rasterize`] and [`Rasterizer`] (`raster.rs`): which texels a bake
//!   computes (charts plus the bilinear margin) and where each one is on
//!   the surface, a band of rows at a time.
//! - `channels.rs`: every PBR channel at an input point, normals re-expressed
//!   in the output's MikkTSpace frame.
//! - `texture_detail.rs`: how far an input texture may be downsampled
//!   before its content visibly changes (the floor under a level's
//!   smaller atlas).
//! - [`gutter`]: the rest of the atlas filled from the nearest texel, so
//!   that no mip level shows background (W App. B).
//! - `prepare.rs`: one mesh simplified with its history, triangulated, its
//!   faces grouped by output material.
//! - `shared_layout.rs`: one atlas per output material across every mesh
//!   baked together, texel densities comparable in world units.
//! - [`bake_meshes`] (`scene_bake.rs`): the driver, from several meshes
//!   with their materials and decoded images to simplified meshes sharing
//!   one material and one set of images per material group.
//! - [`bake_mesh`] (`bake.rs`): the same for one mesh; `interface.rs`
//!   holds the options and results both share.

mod alpha_coverage;
mod atlas;
mod bake;
mod channels;
mod density;
pub mod gutter;
mod input;
mod interface;
mod mapping;
mod prepare;
mod raster;
mod ring_block;
mod ring_triangle;
mod scene_bake;
mod shared_layout;
mod texture_detail;

pub use atlas::{
    atlas_stats, build_atlas, build_atlas_weighted, Atlas, AtlasOptions, AtlasStats,
    MAX_DENSITY_RATIO,
};
pub use bake::bake_mesh;
pub use channels::Channel;
pub use input::BakeInput;
pub use interface::{AtlasReport, BakeError, BakeOptions, BakeReport, Baked, BakedImage};
pub use mapping::{SuccessiveMap, SurfacePoint};
pub use raster::{closest_on_triangle_2d, rasterize, Coverage, Rasterizer, NO_TRIANGLE};
pub use scene_bake::{bake_meshes, BakedMesh, SceneBakeError, SceneBaked, SceneMesh};
pub use texture_detail::VISIBLE_BLUR;
