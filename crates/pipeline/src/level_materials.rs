//! Levels of a chain that carry their own materials: a level whose
//! textures were re-baked (`lod --textures auto|bake`) draws with a new
//! atlas, so its meshes index materials and textures of its own instead of
//! the input's shared ones.
//!
//! A file per level writes each level with its own set; one glTF file of
//! every level (`MSFT_lod`) holds the input's materials followed by each
//! re-baked level's, its meshes' material indices shifted to match.

use wildlod_mesh::{Material, Mesh, Scene, Texture, TextureRef};

/// The materials and textures a re-baked level draws with; its meshes'
/// parts index `materials`, whose texture references index `textures`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LevelMaterials {
    /// The level's materials.
    pub materials: Vec<Material>,
    /// The level's textures (the baked atlases, embedded).
    pub textures: Vec<Texture>,
}

/// `scene` as a level draws it: its meshes, with its own materials and
/// textures when it has them, else the input's.
pub fn level_scene(scene: &Scene, meshes: &[Mesh], own: Option<&LevelMaterials>) -> Scene {
    let mut s = scene.clone();
    s.meshes = meshes.to_vec();
    if let Some(own) = own {
        s.materials = own.materials.clone();
        s.textures = own.textures.clone();
    }
    s
}

/// Appends `own`'s materials and textures to `scene`'s and returns
/// `meshes` with their material indices shifted onto the appended ones,
/// so that one file holds levels with different materials.
pub fn append_level_materials(
    scene: &mut Scene,
    meshes: &[Mesh],
    own: &LevelMaterials,
) -> Vec<Mesh> {
    let (mat0, tex0) = (scene.materials.len() as u32, scene.textures.len() as u32);
    let shift = |r: Option<TextureRef>| {
        r.map(|r| TextureRef {
            texture: r.texture + tex0,
            tex_coord: r.tex_coord,
        })
    };
    scene.textures.extend(own.textures.iter().cloned());
    scene
        .materials
        .extend(own.materials.iter().map(|m| Material {
            base_color_texture: shift(m.base_color_texture),
            metallic_roughness_texture: shift(m.metallic_roughness_texture),
            normal_texture: shift(m.normal_texture),
            occlusion_texture: shift(m.occlusion_texture),
            emissive_texture: shift(m.emissive_texture),
            ..m.clone()
        }));
    meshes
        .iter()
        .map(|mesh| {
            let mut mesh = mesh.clone();
            for p in &mut mesh.parts {
                p.material = p.material.map(|i| i + mat0);
            }
            mesh
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::{ImageSource, Part};

    fn texture(name: &str) -> Texture {
        Texture {
            name: name.into(),
            source: ImageSource::Path(format!("{name}.png").into()),
            sampler: Default::default(),
        }
    }

    #[test]
    fn appended_levels_index_their_own_materials_and_textures() {
        let mut scene = Scene {
            textures: vec![texture("input0"), texture("input1")],
            materials: vec![Material {
                name: "input".into(),
                base_color_texture: Some(TextureRef {
                    texture: 1,
                    tex_coord: 0,
                }),
                ..Material::default()
            }],
            ..Scene::default()
        };
        let own = LevelMaterials {
            materials: vec![
                Material {
                    name: "plain".into(),
                    ..Material::default()
                },
                Material {
                    name: "baked".into(),
                    base_color_texture: Some(TextureRef {
                        texture: 0,
                        tex_coord: 0,
                    }),
                    normal_texture: Some(TextureRef {
                        texture: 1,
                        tex_coord: 0,
                    }),
                    ..Material::default()
                },
            ],
            textures: vec![texture("atlas"), texture("atlas_normal")],
        };
        let mesh = Mesh {
            parts: vec![
                Part {
                    material: Some(1),
                    ..Part::default()
                },
                Part {
                    material: None,
                    ..Part::default()
                },
            ],
            ..Mesh::default()
        };
        let shifted = append_level_materials(&mut scene, &[mesh], &own);
        // Two input textures before the level's: its 0 and 1 become 2, 3;
        // one input material before its: its 1 becomes 2.
        assert_eq!(shifted[0].parts[0].material, Some(2));
        assert_eq!(shifted[0].parts[1].material, None);
        let baked = &scene.materials[2];
        assert_eq!(baked.name, "baked");
        assert_eq!(baked.base_color_texture.map(|r| r.texture), Some(2));
        assert_eq!(baked.normal_texture.map(|r| r.texture), Some(3));
        assert_eq!(scene.textures[3].name, "atlas_normal");
        // The input's stay as they were.
        assert_eq!(
            scene.materials[0].base_color_texture.map(|r| r.texture),
            Some(1)
        );
        // Drawn on its own, the level uses its set unshifted.
        let alone = level_scene(&scene, &shifted, Some(&own));
        assert_eq!(alone.materials.len(), 2);
        assert_eq!(alone.textures[0].name, "atlas");
    }
}
