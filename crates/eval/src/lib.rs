//! Mesh comparison as the papers measure it, for `wildlod compare`:
//!
//! - Hausdorff and Chamfer distances between surfaces, normalized by the
//!   reference's bounding-box diagonal (W §5, Table 1);
//! - the quad ratio of a quad-dominant reduction (Knodt 2024 §4);
//! - the texture Chamfer distance (W §5, Table 2, after Yuan et al. 2018),
//!   and the same scheme on shading normals (the normal Chamfer distance);
//! - any of these at the frames of an animation ([`posed`]), as Knodt 2024
//!   §4 measures skinned meshes.
//!
//! Build an [`EvalMesh`] for each side ([`EvalMesh::from_scene`] flattens a
//! file's instances to world space), then call [`compare()`]:
//!
//! ```
//! use wildlod_eval::{compare, CompareOptions, EvalMesh};
//! use wildlod_mesh::shapes;
//!
//! let sphere = shapes::quad_sphere(8);
//! let coarse = shapes::quad_sphere(2);
//! let options = CompareOptions { samples: 5_000, ..CompareOptions::default() };
//! let c = compare(&EvalMesh::from_mesh(&sphere), &EvalMesh::from_mesh(&coarse), &options);
//! assert!(c.hausdorff > 0.0 && c.hausdorff < 0.1);
//! assert!(c.chamfer_squared < c.chamfer_mean * c.hausdorff + 1e-12);
//! assert_eq!(c.quad_ratio, Some(1.0)); // all quads on both sides
//! ```
//!
//! W = Liu, Zhang, Yuksel 2025, *Simplifying Textured Triangle Meshes in the
//! Wild*; Knodt 2024, *Single Edge Collapse Quad-Dominant Mesh Reduction*.

mod appearance;
mod compare;
mod eval_mesh;
mod paired;
mod pose;
mod sampling;

pub use compare::{
    compare, CompareOptions, Comparison, OutlierVertex, DEFAULT_SEED, MAX_NAMED_OUTLIERS,
};
pub use eval_mesh::{EvalMesh, FaceCounts, InstanceCounts};
pub use pose::{pose_origin, posed, posed_about};
