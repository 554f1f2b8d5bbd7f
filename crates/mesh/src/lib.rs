//! The wildlod mesh model.
//!
//! One representation that can hold what real assets carry, so that readers
//! and writers never lose anything the simplifier did not change:
//!
//! - [`Mesh`]: positions, polygon faces stored flat (offsets + indices, quads
//!   and n-gons are first-class), per-corner attribute streams (UV sets,
//!   normals, tangents, colors, morph targets), per-corner skin influences,
//!   and a part (material group, glTF primitive, OBJ group) per face.
//! - [`Scene`]: meshes plus materials, textures, nodes with transforms,
//!   skins and animations.
//!
//! Every attribute stream is indexed per *corner* (a face's use of a vertex),
//! like OBJ's `v/vt/vn` triplets or Blender's loops. Positions are therefore
//! independent of attribute seams: the simplifier welds equal positions
//! ([`weld`]) and the attributes stay split wherever the input split them.
//!
//! The model holds no I/O; `wildlod-io` fills it and writes it back.

mod attribute;
pub mod bounds;
pub mod disjoint_sets;
mod faces;
mod image;
mod mesh;
pub mod polygon;
pub mod pose;
mod scene;
pub mod shapes;
pub mod stats;
pub mod tangents;
pub mod transform;
mod validate;
pub mod weld;

pub use attribute::{Attribute, ComponentFormat, MorphChannel, Semantic, Skinning, ABSENT};
pub use faces::{FaceIter, Faces};
pub use image::{Image, Rgba8Image};
pub use mesh::{Mesh, Part};
pub use scene::{
    AlphaMode, Animation, ImageSource, Interpolation, Material, Node, Sampler, Scene, Skin,
    Texture, TextureRef, Track, TrackPath, Wrap, IDENTITY,
};
pub use validate::{Invalid, ValidationErrors};
