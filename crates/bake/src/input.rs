//! What a bake reads: a mesh with its materials, textures and decoded
//! images (W §4.3: the input the LOD's texels are mapped back to). Its own
//! module so that the driver (`bake.rs`) and the density estimate
//! (`density.rs`) both read it without importing each other.

use wildlod_mesh::{Material, Mesh, Rgba8Image, Texture};

/// What a bake reads: a mesh, the scene's materials and textures, and the
/// textures' decoded images (`None` where an image could not be read: its
/// channel then uses the material's factor, and the caller warns).
#[derive(Clone, Copy, Debug)]
pub struct BakeInput<'a> {
    /// The mesh to simplify and bake.
    pub mesh: &'a Mesh,
    /// Materials its parts refer to.
    pub materials: &'a [Material],
    /// Textures the materials refer to (for their samplers).
    pub textures: &'a [Texture],
    /// Decoded image of every texture, same order.
    pub images: &'a [Option<Rgba8Image>],
}
