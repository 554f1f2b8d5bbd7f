//! What a bake is asked and what it gives back: [`BakeOptions`], the baked
//! mesh, materials and images, the atlases' reports and [`BakeError`]
//! (W §4.3). Their own module so that the single-mesh entry (`bake.rs`)
//! and the scene's multi-mesh bake (`scene_bake.rs`) share them without
//! importing each other.

use wildlod_mesh::{Material, Mesh, Rgba8Image};
use wildlod_simplify::{Options, Report};

use crate::atlas::{AtlasOptions, AtlasStats};
use crate::channels::Channel;

/// Options of a bake ([`crate::bake_mesh`], [`crate::bake_meshes`]).
#[derive(Clone, Debug)]
pub struct BakeOptions {
    /// The simplification (target, metric, guards). History recording is
    /// turned on by the baker. Not read by [`crate::bake_meshes`], whose
    /// meshes each bring their own.
    pub simplify: Options,
    /// Atlas width and height in texels; `None`: the input's texel
    /// density, scaled by the level when [`BakeOptions::density_follows_level`]
    /// (see [`BakeOptions::max_texture_size`]).
    pub texture_size: Option<u32>,
    /// Largest atlas side chosen from the input's texel density. Default
    /// 4096.
    pub max_texture_size: u32,
    /// Without a `texture_size`: texel density = the input's × √(output
    /// triangles / input triangles), at least 256 texels a side (never
    /// above the input's density). A level is shown where its error is
    /// about a pixel; its edges are about 1/√ratio times longer than the
    /// input's, so it is drawn about √ratio times as large on screen, and
    /// the input's density would spend texels no screen samples (a 1% LOD
    /// of a 4k-textured asset got a 4k atlas). But never coarser than the
    /// input's base colour images can be averaged without a visible change
    /// (`texture_detail.rs`): a face or printed text keeps its texels at
    /// any level. Default on; off keeps the input's density at every
    /// ratio.
    pub density_follows_level: bool,
    /// Empty texels between charts (and along the border). Default 4.
    pub padding: u32,
    /// Bake all materials with the same alpha mode and sidedness into one
    /// atlas and material. Off: one atlas per output material.
    pub merge_materials: bool,
    /// Chart cone angle in degrees ([`AtlasOptions::max_chart_angle`]).
    pub max_chart_angle: f64,
    /// Bake a tangent-space normal map for every output material from the
    /// input's shading normals: its normal map applied where it has one,
    /// else its interpolated vertex normals (its face normals without a
    /// normal stream), at each texel's mapped input point, in the LOD's
    /// MikkTSpace frame. The successive mapping gives every texel its
    /// input point exactly, so unlike ray casting (Simplygon, InstaLOD) it
    /// never misses on thin or overlapping parts. Default on: a LOD keeps
    /// the small-scale shape its collapses removed under lighting. Off:
    /// normal maps are baked only where the input has one.
    pub bake_normals: bool,
}

impl Default for BakeOptions {
    fn default() -> Self {
        BakeOptions {
            simplify: Options::default(),
            texture_size: None,
            max_texture_size: 4096,
            density_follows_level: true,
            padding: AtlasOptions::default().padding,
            merge_materials: false,
            max_chart_angle: AtlasOptions::default().max_chart_angle,
            bake_normals: true,
        }
    }
}

/// One re-baked image.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedImage {
    /// Which channel it holds.
    pub channel: Channel,
    /// Which output material it belongs to.
    pub material: usize,
    /// The pixels (sRGB for base color and emissive, linear otherwise).
    pub image: Rgba8Image,
    /// Texels that hold their own surface point (the rest are gutter fill).
    pub mapped: Vec<bool>,
}

/// One atlas: its layout quality and work.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasReport {
    /// Width and height in texels.
    pub size: u32,
    /// Layout statistics.
    pub stats: AtlasStats,
    /// Seconds spent laying out the atlas (charts, parametrization,
    /// packing).
    pub layout_seconds: f64,
    /// Texels mapped to the input through the history.
    pub texels_mapped: usize,
    /// Seconds spent mapping texels and evaluating channels.
    pub seconds: f64,
}

/// What a bake did for one mesh.
#[derive(Clone, Debug)]
pub struct BakeReport {
    /// The simplification's report.
    pub simplify: Report,
    /// One entry per atlas (output material).
    pub atlases: Vec<AtlasReport>,
}

/// The result: the simplified mesh with new UVs, its materials, and the
/// images they refer to.
#[derive(Clone, Debug)]
pub struct Baked {
    /// The simplified, triangulated mesh: one part per output material,
    /// `TEXCOORD_0` in the new atlas, normals (and tangents when a normal
    /// map was baked), the input's skin influences and other per-corner
    /// streams carried along; vertex colors are baked into base color and
    /// dropped.
    pub mesh: Mesh,
    /// Output materials, indexed by the mesh's parts. Their texture
    /// references are indices into `images`; factors of baked channels
    /// are 1.
    pub materials: Vec<Material>,
    /// The baked images.
    pub images: Vec<BakedImage>,
    /// What was reached.
    pub report: BakeReport,
}

/// Why a bake failed.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    /// The simplifier refused the input or options.
    #[error(transparent)]
    Simplify(#[from] wildlod_simplify::Error),
    /// The LOD's charts do not fit the largest atlas allowed (each takes a
    /// texel and its padding at least): a surface split into tens of
    /// thousands of charts (a noisy scan's), or a `texture_size` too small.
    #[error("{charts} atlas charts do not fit a {size}² atlas")]
    AtlasFull {
        /// Charts of the layout.
        charts: usize,
        /// The largest atlas side tried.
        size: u32,
    },
}
