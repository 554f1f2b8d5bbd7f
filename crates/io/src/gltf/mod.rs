//! glTF 2.0 (`.gltf` with external or data-URI buffers, and `.glb`).
//!
//! Reading decodes every accessor with bounds-checked code of our own and
//! fills the mesh model; everything the model does not hold is kept in a
//! [`Passthrough`] (the original JSON and buffers) so that writing puts it
//! back unchanged, rebuilding only the meshes and the binary data they use.

mod accessor;
mod animation_json;
mod attribute_keys;
mod bin;
mod encode;
mod glb;
mod image_levels;
mod images;
mod load;
mod lod;
mod meshopt_decode;
mod passthrough;
mod read;
mod rewrite;
mod scene_json;
mod texture_transform;
mod trs;
mod uri;
mod write;

pub(crate) use passthrough::Passthrough;
pub(crate) use read::read;
pub(crate) use write::{write, write_with_lods};
