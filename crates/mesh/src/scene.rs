//! A whole file's content: meshes, materials, textures, the node tree,
//! skins and animations.

use std::path::PathBuf;

use crate::mesh::Mesh;

/// The 4×4 identity, column-major.
pub const IDENTITY: [f32; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

/// Everything a file holds, in format-neutral form.
///
/// Formats that carry more than this (glTF extensions, animation curves,
/// samplers) keep the rest in the reader's own pass-through data so that it
/// is written back unchanged; see `wildlod-io`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Stored meshes; an instanced mesh is stored once.
    pub meshes: Vec<Mesh>,
    /// Materials referenced by [`crate::Part::material`].
    pub materials: Vec<Material>,
    /// Textures referenced by materials.
    pub textures: Vec<Texture>,
    /// Nodes of the scene graph.
    pub nodes: Vec<Node>,
    /// Root nodes of the displayed scene.
    pub roots: Vec<u32>,
    /// Skins referenced by nodes.
    pub skins: Vec<Skin>,
    /// Animations (summaries; curves stay in the format's pass-through).
    pub animations: Vec<Animation>,
}

/// A node of the scene graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Node name.
    pub name: String,
    /// Local transform, column-major 4×4.
    pub matrix: [f32; 16],
    /// Mesh instanced by this node.
    pub mesh: Option<u32>,
    /// Skin that deforms the mesh of this node.
    pub skin: Option<u32>,
    /// Child nodes.
    pub children: Vec<u32>,
}

impl Default for Node {
    fn default() -> Self {
        Node {
            name: String::new(),
            matrix: IDENTITY,
            mesh: None,
            skin: None,
            children: Vec::new(),
        }
    }
}

/// A skin: the joints (nodes) that influences refer to by index.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skin {
    /// Skin name.
    pub name: String,
    /// Joint nodes; a skinning joint index `j` means node `joints[j]`.
    pub joints: Vec<u32>,
    /// Inverse bind matrix of every joint (column-major), or empty for identity.
    pub inverse_bind_matrices: Vec<[f32; 16]>,
    /// Optional common root of the joints.
    pub skeleton: Option<u32>,
}

/// An animation: its summary and its keyframe tracks (for posing a skinned
/// mesh, e.g. to measure a level of detail at animation frames; writers
/// keep the source's own animation data).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Animation {
    /// Animation name.
    pub name: String,
    /// Number of channels (animated node properties).
    pub channels: usize,
    /// Largest keyframe time, in seconds.
    pub duration: f32,
    /// The channels' keyframes, one track per channel whose target node
    /// exists (morph weight channels included).
    pub tracks: Vec<Track>,
}

/// The node property a track animates (glTF `channel.target.path`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackPath {
    /// Translation, 3 floats per key.
    Translation,
    /// Rotation, a unit quaternion (x, y, z, w) per key.
    Rotation,
    /// Scale, 3 floats per key.
    Scale,
    /// Morph target weights, one float per target per key.
    Weights,
}

/// How values between keyframes are found (glTF `sampler.interpolation`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interpolation {
    /// Linear (spherical linear for rotations).
    #[default]
    Linear,
    /// The previous key's value.
    Step,
    /// Cubic Hermite spline; each key holds (in-tangent, value,
    /// out-tangent).
    CubicSpline,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// The animated node.
    pub node: u32,
    /// Which property.
    pub path: TrackPath,
    /// How to interpolate.
    pub interpolation: Interpolation,
    /// Key times in seconds, increasing.
    pub times: Vec<f32>,
    /// Key values, flat: per key the property's floats (three times that
    /// for cubic splines).
    pub values: Vec<f32>,
}

/// How a material's alpha is interpreted (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AlphaMode {
    /// Alpha ignored.
    #[default]
    Opaque,
    /// Alpha tested against a cutoff.
    Mask,
    /// Alpha blended.
    Blend,
}

/// A reference from a material to a texture and the UV set it uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Scene::textures`].
    pub texture: u32,
    /// UV set (`TEXCOORD_n`) used to look the texture up.
    pub tex_coord: u32,
}

/// A metallic-roughness PBR material (the glTF model; OBJ/MTL maps onto it).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Material name.
    pub name: String,
    /// Base color factor, linear RGBA.
    pub base_color: [f32; 4],
    /// Base color texture.
    pub base_color_texture: Option<TextureRef>,
    /// Metallic factor.
    pub metallic: f32,
    /// Roughness factor.
    pub roughness: f32,
    /// Metallic (B) / roughness (G) texture.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map.
    pub normal_texture: Option<TextureRef>,
    /// Ambient occlusion (R) texture.
    pub occlusion_texture: Option<TextureRef>,
    /// Emissive factor, linear RGB.
    pub emissive: [f32; 3],
    /// Emissive texture.
    pub emissive_texture: Option<TextureRef>,
    /// Alpha interpretation.
    pub alpha_mode: AlphaMode,
    /// Alpha cutoff for [`AlphaMode::Mask`].
    pub alpha_cutoff: f32,
    /// Whether back faces are rendered.
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: String::new(),
            base_color: [1.0; 4],
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive: [0.0; 3],
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            alpha_cutoff: 0.5,
            double_sided: false,
        }
    }
}

impl Material {
    /// Every texture reference of the material, in a fixed order: base
    /// color, metallic-roughness, normal, occlusion, emissive.
    pub fn texture_refs(&self) -> impl Iterator<Item = TextureRef> + '_ {
        [
            self.base_color_texture,
            self.metallic_roughness_texture,
            self.normal_texture,
            self.occlusion_texture,
            self.emissive_texture,
        ]
        .into_iter()
        .flatten()
    }
}

/// Where a texture's image bytes are.
#[derive(Clone, Debug, PartialEq)]
pub enum ImageSource {
    /// A file; relative paths are relative to the file that referenced them
    /// and readers resolve them to absolute paths.
    Path(PathBuf),
    /// Bytes held in memory (a glTF buffer view or data URI), with MIME type.
    Embedded {
        /// The encoded image (PNG, JPEG…), kept byte for byte.
        bytes: Vec<u8>,
        /// MIME type such as `image/png`.
        mime_type: String,
    },
}

/// How texture coordinates outside [0, 1] are folded back (glTF sampler
/// `wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles (glTF's default).
    #[default]
    Repeat,
    /// The image tiles, every other copy mirrored.
    MirroredRepeat,
    /// Coordinates clamp to the edge texels.
    ClampToEdge,
}

/// How a texture is sampled: its wrap modes along u and v.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sampler {
    /// Wrapping along u.
    pub wrap_u: Wrap,
    /// Wrapping along v.
    pub wrap_v: Wrap,
}

/// A texture: an image, its name and how it is sampled.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Texture or image name.
    pub name: String,
    /// Where the image is.
    pub source: ImageSource,
    /// Wrap modes (glTF sampler; OBJ textures repeat).
    pub sampler: Sampler,
}

impl Scene {
    /// A scene with one mesh instanced once by one root node.
    pub fn from_mesh(mesh: Mesh) -> Self {
        Scene {
            nodes: vec![Node {
                name: mesh.name.clone(),
                mesh: Some(0),
                ..Node::default()
            }],
            roots: vec![0],
            meshes: vec![mesh],
            ..Scene::default()
        }
    }

    /// How many times each mesh is instanced by the node tree reachable from
    /// the roots (a mesh no node reaches counts once: it is still stored).
    pub fn instance_counts(&self) -> Vec<usize> {
        let mut counts = vec![0usize; self.meshes.len()];
        let mut stack: Vec<u32> = self.roots.clone();
        // Bounded walk: a malformed cyclic graph must not loop forever.
        let mut budget = self.nodes.len().saturating_mul(self.nodes.len().max(1)) + 1;
        while let Some(n) = stack.pop() {
            if budget == 0 {
                break;
            }
            budget -= 1;
            let Some(node) = self.nodes.get(n as usize) else {
                continue;
            };
            if let Some(c) = node.mesh.and_then(|m| counts.get_mut(m as usize)) {
                *c += 1;
            }
            stack.extend_from_slice(&node.children);
        }
        for c in &mut counts {
            if *c == 0 {
                *c = 1;
            }
        }
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instanced_mesh_counts_once_per_reaching_node() {
        let mut s = Scene::from_mesh(Mesh::default());
        s.meshes.push(Mesh::default());
        // root 0 (mesh 0) has children 1 and 2, both instancing mesh 1.
        s.nodes[0].children = vec![1, 2];
        for _ in 0..2 {
            s.nodes.push(Node {
                mesh: Some(1),
                ..Node::default()
            });
        }
        assert_eq!(s.instance_counts(), vec![1, 2]);
    }
}
