//! The single-mesh bake: [`bake_mesh`], a mesh's simplification and its
//! own atlases, as a bake of one mesh through `scene_bake.rs` (W §4.3,
//! Fig. 18).

use crate::input::BakeInput;
use crate::interface::{BakeError, BakeOptions, Baked};
use crate::scene_bake::{bake_meshes, SceneMesh};

/// Simplifies `input.mesh` with collapses free to cross UV seams, and
/// re-bakes every texture channel of its materials onto a new atlas by
/// successive mapping (W §4.3, App. B, App. C.2).
///
/// A mesh whose materials have no texture and which has no vertex colors
/// gets only a normal map ([`BakeOptions::bake_normals`]; its materials
/// keep their factors), or with that off is only simplified (no atlas, no
/// image). Several meshes baked into shared atlases: [`crate::bake_meshes`].
///
/// # Errors
/// [`BakeError::Simplify`] when the mesh or options are invalid,
/// [`BakeError::AtlasFull`] when its charts fit no atlas allowed.
pub fn bake_mesh(input: &BakeInput, options: &BakeOptions) -> Result<Baked, BakeError> {
    let one = SceneMesh {
        input: *input,
        simplify: options.simplify.clone(),
        world_scale: 1.0,
    };
    let mut scene = bake_meshes(std::slice::from_ref(&one), options).map_err(|e| e.source)?;
    let Some(baked) = scene.meshes.pop() else {
        unreachable!("one mesh in, one out");
    };
    let materials = if baked.keeps_input_materials {
        // Its parts name the input's materials.
        input.materials.to_vec()
    } else {
        scene.materials
    };
    Ok(Baked {
        mesh: baked.mesh,
        materials,
        images: scene.images,
        report: baked.report,
    })
}
