//! Mesh simplification for meshes in the wild.
//!
//! The core of wildlod, with no I/O:
//!
//! - vertex-pair collapse on a simplicial 2-complex with virtual edges and
//!   an area-aware quadric (Liu, Zhang & Yuksel 2025, "W": §4.1, §4.2,
//!   App. A–C), for non-manifold, many-component meshes and triangle soups;
//! - polygon faces kept through collapses (Knodt 2024, "Q": output faces are
//!   input faces with merged vertices).
//!
//! Entry points: [`simplify_polygons`] and [`simplify_triangles`] on plain
//! arrays, [`simplify_mesh`] on a [`wildlod_mesh::Mesh`] with its attributes.
//! Options are a plain struct with documented defaults ([`Options`]); every
//! run returns a [`Report`] of what it reached and why it stopped.
//!
//! ```
//! use wildlod_simplify::{simplify_mesh, Options, Target};
//! let mesh = wildlod_mesh::shapes::torus(24, 12, 1.0, 0.3);
//! let options = Options {
//!     target: Target { ratio: Some(0.25), ..Target::default() },
//!     ..Options::default()
//! };
//! let (lod, report) = simplify_mesh(&mesh, &options)?;
//! assert!(report.output_triangles.abs_diff(report.target_triangles) <= 1);
//! assert_eq!(lod.triangle_count(), report.output_triangles);
//! # Ok::<(), wildlod_simplify::Error>(())
//! ```

// The simplifier's steps, in the order they run; each imports only the
// ones before it (and the contracts: `input`, `options`, `report`,
// `error`), checked by `crates/testkit/tests/no_import_cycles.rs`.
// 1. check, weld, normalize, build the complex (W §4.1)
mod prepare;
// 2. the edges a collapse may take, virtual ones included (W §4.1.1)
mod edges;
// 3. the quadrics, every cost term and the guards (W §4.2, Knodt §3)
mod terms;
// 4. the collapse loop (W Alg. 1, Knodt Alg. 1)
mod collapse;
// 5. the output refit to the input
mod refit;
// 6. the output faces, positions and attributes, mapped to the input
mod assemble;

// The contracts every step reads.
mod error;
mod input;
mod options;
mod report;

// 7. the quad ordering held to the measured output, around whole runs
mod quad_hold;

// 8. quad mode's leftover triangle pairs joined into quads (`simplify_mesh`)
mod quad_pairs;

// The entry points, from plain arrays up to whole scenes.
mod mesh;
mod scene;
mod simplify;

pub use assemble::Simplified;
pub use collapse::history::{CollapseRecord, History, RingFace, RingInput};
pub use error::Error;
pub use input::{
    AttributeInput, AttributeStream, FittedSkin, FittedStream, MorphStream, SeamPolicy, SkinStream,
    StreamKind,
};
pub use mesh::{
    morph_targets, simplify_mesh, simplify_mesh_with_progress, vertex_joints, MAX_MORPH_POSES,
};
pub use options::{
    AttributeOptions, Guards, InputData, Metric, NormalMode, Options, Partition, QuadMode,
    QuadSettings, Record, Target,
};
pub use prepare::large_polygons::MAX_POLYGON_CORNERS;
pub use report::{QuadTies, Rejections, Report, SteeringOutcome, StopReason};
pub use scene::{
    enclosures_hide, material_uv_sets, see_through_materials, simplify_scene,
    simplify_scene_with_progress, skin_poses, GroupReport, GroupSpace, MeshOutcome, SceneReport,
};
pub use simplify::{
    simplify_polygons, simplify_polygons_with_progress, simplify_triangles,
    simplify_with_attributes, simplify_with_attributes_and_progress,
};
pub use terms::quadric::{place, place_by_planes, place_exact, Placement, Quadric, FREE_DIRECTION};
