//! `validate()`: every invariant of the model, checked, with the offending
//! element named. Problems are collected (up to a cap) instead of stopping at
//! the first, so a broken file reports all it can in one go.

use std::fmt;

use crate::attribute::ABSENT;
use crate::mesh::Mesh;
use crate::scene::Scene;

/// At most this many problems are collected; a file broken everywhere would
/// otherwise produce millions of lines.
const MAX_PROBLEMS: usize = 64;

/// One broken invariant, naming the element.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Invalid {
    /// `faces.offsets` is not `[0, …, indices.len()]` increasing.
    #[error("face offsets are malformed at face {face}")]
    FaceOffsets {
        /// First face whose offsets are wrong.
        face: usize,
    },
    /// A face with fewer than three corners.
    #[error("face {face} has {arity} corners (at least 3 needed)")]
    FaceTooSmall {
        /// Face index.
        face: usize,
        /// Its corner count.
        arity: usize,
    },
    /// A corner refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but there are {vertices} vertices")]
    VertexOutOfRange {
        /// Face index.
        face: usize,
        /// The bad vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A position with a NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite position {position:?}")]
    NonFinitePosition {
        /// Vertex index.
        vertex: usize,
        /// The position.
        position: [f32; 3],
    },
    /// `face_parts` length differs from the face count.
    #[error("{found} face parts for {faces} faces")]
    FacePartsLength {
        /// Face count.
        faces: usize,
        /// Length of `face_parts`.
        found: usize,
    },
    /// A face refers to a part that does not exist.
    #[error("face {face} is in part {part}, but there are {parts} parts")]
    PartOutOfRange {
        /// Face index.
        face: usize,
        /// Bad part index.
        part: u32,
        /// Number of parts.
        parts: usize,
    },
    /// A part refers to a material that does not exist.
    #[error("part {part} uses material {material}, but there are {materials} materials")]
    MaterialOutOfRange {
        /// Part index.
        part: usize,
        /// Bad material index.
        material: u32,
        /// Number of materials.
        materials: usize,
    },
    /// An attribute stream with 0 or more than 4 components, or a value pool
    /// that is not a multiple of the component count.
    #[error("attribute {attribute} has {components} components and {values} floats")]
    AttributeShape {
        /// Stream index.
        attribute: usize,
        /// Component count.
        components: u8,
        /// Length of the value pool.
        values: usize,
    },
    /// A per-corner index list whose length is not the corner count.
    #[error("attribute {attribute} has {found} corner indices for {corners} corners")]
    AttributeIndicesLength {
        /// Stream index (`usize::MAX` for the skinning stream).
        attribute: usize,
        /// Corner count.
        corners: usize,
        /// Length of the index list.
        found: usize,
    },
    /// A corner refers to an attribute value that does not exist.
    #[error("corner {corner} of attribute {attribute} refers to value {index}, but there are {values} values")]
    AttributeIndexOutOfRange {
        /// Stream index (`usize::MAX` for the skinning stream).
        attribute: usize,
        /// Corner index.
        corner: usize,
        /// Bad value index.
        index: u32,
        /// Number of values.
        values: usize,
    },
    /// A NaN or infinite attribute value.
    #[error("value {value} of attribute {attribute} is not finite")]
    NonFiniteAttribute {
        /// Stream index.
        attribute: usize,
        /// Value index.
        value: usize,
    },
    /// Skinning joints and weights of different lengths, or zero influences.
    #[error("skinning has {influences} influences, {joints} joints and {weights} weights")]
    SkinningShape {
        /// Influences per entry.
        influences: u8,
        /// Length of the joint list.
        joints: usize,
        /// Length of the weight list.
        weights: usize,
    },
    /// A skin weight that is negative or not finite.
    #[error("skin entry {entry} has an invalid weight {weight}")]
    BadWeight {
        /// Entry index.
        entry: usize,
        /// The weight.
        weight: f32,
    },
    /// A node refers to a mesh that does not exist.
    #[error("node {node} instances mesh {mesh}, but there are {meshes} meshes")]
    NodeMeshOutOfRange {
        /// Node index.
        node: usize,
        /// Bad mesh index.
        mesh: u32,
        /// Number of meshes.
        meshes: usize,
    },
    /// A node refers to a skin that does not exist.
    #[error("node {node} uses skin {skin}, but there are {skins} skins")]
    NodeSkinOutOfRange {
        /// Node index.
        node: usize,
        /// Bad skin index.
        skin: u32,
        /// Number of skins.
        skins: usize,
    },
    /// A node child, root, skin joint or skeleton refers to a missing node.
    #[error("{what} refers to node {index}, but there are {nodes} nodes")]
    NodeOutOfRange {
        /// What refers to it ("node 3 child", "root", "skin 0 joint 4"…).
        what: String,
        /// Bad node index.
        index: u32,
        /// Number of nodes.
        nodes: usize,
    },
    /// A node is reached twice from the roots (a cycle or shared child).
    #[error("node {node} has more than one parent or is part of a cycle")]
    NodeGraph {
        /// Node index.
        node: usize,
    },
    /// A material refers to a texture that does not exist.
    #[error("material {material} uses texture {texture}, but there are {textures} textures")]
    TextureOutOfRange {
        /// Material index.
        material: usize,
        /// Bad texture index.
        texture: u32,
        /// Number of textures.
        textures: usize,
    },
    /// A skin with a number of inverse bind matrices other than its joints.
    #[error("skin {skin} has {matrices} inverse bind matrices for {joints} joints")]
    InverseBindMatrices {
        /// Skin index.
        skin: usize,
        /// Joint count.
        joints: usize,
        /// Matrix count.
        matrices: usize,
    },
}

/// The problems `validate()` found, each with the mesh it is in (if any).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ValidationErrors {
    /// (mesh index, problem); mesh is `None` for scene-level problems.
    pub problems: Vec<(Option<usize>, Invalid)>,
    /// True when more problems existed than were collected.
    pub truncated: bool,
}

impl ValidationErrors {
    fn push(&mut self, mesh: Option<usize>, p: Invalid) {
        if self.problems.len() < MAX_PROBLEMS {
            self.problems.push((mesh, p));
        } else {
            self.truncated = true;
        }
    }

    fn full(&self) -> bool {
        self.problems.len() >= MAX_PROBLEMS
    }

    fn into_result(self) -> Result<(), ValidationErrors> {
        if self.problems.is_empty() {
            Ok(())
        } else {
            Err(self)
        }
    }
}

impl fmt::Display for ValidationErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (mesh, p)) in self.problems.iter().enumerate() {
            if i > 0 {
                f.write_str("; ")?;
            }
            match mesh {
                Some(m) => write!(f, "mesh {m}: {p}")?,
                None => write!(f, "{p}")?,
            }
        }
        if self.truncated {
            f.write_str("; and more")?;
        }
        Ok(())
    }
}

impl std::error::Error for ValidationErrors {}

impl Mesh {
    /// Checks every invariant of the mesh: face offsets, arity ≥ 3, vertex
    /// indices in range, finite positions, parts and their materials (when
    /// `materials` is given), attribute and skinning streams.
    ///
    /// Degenerate faces (a repeated vertex) and duplicate faces are *valid*:
    /// wild meshes have them and the simplifier removes them.
    pub fn validate(&self) -> Result<(), ValidationErrors> {
        let mut errs = ValidationErrors::default();
        self.validate_into(None, None, &mut errs);
        errs.into_result()
    }

    pub(crate) fn validate_into(
        &self,
        mesh: Option<usize>,
        materials: Option<usize>,
        errs: &mut ValidationErrors,
    ) {
        let faces = &self.faces;
        let nv = self.positions.len();
        let corners = faces.indices.len();
        // Offsets first: everything else indexes through them.
        if faces.offsets.first() != Some(&0)
            || faces.offsets.last().map(|&o| o as usize) != Some(corners)
        {
            errs.push(mesh, Invalid::FaceOffsets { face: 0 });
            return;
        }
        for f in 0..faces.len() {
            let (a, b) = (faces.offsets[f], faces.offsets[f + 1]);
            if b < a {
                errs.push(mesh, Invalid::FaceOffsets { face: f });
                return;
            }
            if b - a < 3 {
                errs.push(
                    mesh,
                    Invalid::FaceTooSmall {
                        face: f,
                        arity: (b - a) as usize,
                    },
                );
            }
            for &v in faces.face(f) {
                if v as usize >= nv {
                    errs.push(
                        mesh,
                        Invalid::VertexOutOfRange {
                            face: f,
                            index: v,
                            vertices: nv,
                        },
                    );
                }
            }
            if errs.full() {
                errs.truncated = true;
                return;
            }
        }
        for (v, p) in self.positions.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                errs.push(
                    mesh,
                    Invalid::NonFinitePosition {
                        vertex: v,
                        position: *p,
                    },
                );
            }
        }
        if self.face_parts.len() != faces.len() {
            errs.push(
                mesh,
                Invalid::FacePartsLength {
                    faces: faces.len(),
                    found: self.face_parts.len(),
                },
            );
        } else {
            for (f, &p) in self.face_parts.iter().enumerate() {
                if p as usize >= self.parts.len() {
                    errs.push(
                        mesh,
                        Invalid::PartOutOfRange {
                            face: f,
                            part: p,
                            parts: self.parts.len(),
                        },
                    );
                }
            }
        }
        if let Some(nm) = materials {
            for (i, part) in self.parts.iter().enumerate() {
                if let Some(m) = part.material.filter(|&m| m as usize >= nm) {
                    errs.push(
                        mesh,
                        Invalid::MaterialOutOfRange {
                            part: i,
                            material: m,
                            materials: nm,
                        },
                    );
                }
            }
        }
        for (ai, a) in self.attributes.iter().enumerate() {
            if a.components == 0 || a.components > 4 || a.values.len() % a.components as usize != 0
            {
                errs.push(
                    mesh,
                    Invalid::AttributeShape {
                        attribute: ai,
                        components: a.components,
                        values: a.values.len(),
                    },
                );
                continue;
            }
            check_corner_indices(mesh, ai, &a.indices, corners, a.value_count(), errs);
            let c = a.components as usize;
            for (i, chunk) in a.values.chunks(c).enumerate() {
                if !chunk.iter().all(|x| x.is_finite()) {
                    errs.push(
                        mesh,
                        Invalid::NonFiniteAttribute {
                            attribute: ai,
                            value: i,
                        },
                    );
                }
            }
        }
        if let Some(s) = &self.skinning {
            let k = s.influences as usize;
            if k == 0 || s.joints.len() != s.weights.len() || s.weights.len() % k != 0 {
                errs.push(
                    mesh,
                    Invalid::SkinningShape {
                        influences: s.influences,
                        joints: s.joints.len(),
                        weights: s.weights.len(),
                    },
                );
            } else {
                check_corner_indices(mesh, usize::MAX, &s.indices, corners, s.entry_count(), errs);
                for (i, &w) in s.weights.iter().enumerate() {
                    if !(w.is_finite() && w >= 0.0) {
                        errs.push(
                            mesh,
                            Invalid::BadWeight {
                                entry: i / k,
                                weight: w,
                            },
                        );
                    }
                }
            }
        }
    }
}

fn check_corner_indices(
    mesh: Option<usize>,
    attribute: usize,
    indices: &[u32],
    corners: usize,
    values: usize,
    errs: &mut ValidationErrors,
) {
    if indices.len() != corners {
        errs.push(
            mesh,
            Invalid::AttributeIndicesLength {
                attribute,
                corners,
                found: indices.len(),
            },
        );
        return;
    }
    for (corner, &i) in indices.iter().enumerate() {
        if i != ABSENT && i as usize >= values {
            errs.push(
                mesh,
                Invalid::AttributeIndexOutOfRange {
                    attribute,
                    corner,
                    index: i,
                    values,
                },
            );
            if errs.full() {
                return;
            }
        }
    }
}

impl Scene {
    /// Checks every mesh ([`Mesh::validate`]) and every reference between
    /// scene elements: node meshes, skins and children, roots, skin joints,
    /// material textures, part materials; and that the node graph is a forest.
    pub fn validate(&self) -> Result<(), ValidationErrors> {
        let mut errs = ValidationErrors::default();
        let nodes = self.nodes.len();
        for (i, m) in self.meshes.iter().enumerate() {
            m.validate_into(Some(i), Some(self.materials.len()), &mut errs);
        }
        let node_ref = |errs: &mut ValidationErrors, what: String, index: u32| {
            if index as usize >= nodes {
                errs.push(None, Invalid::NodeOutOfRange { what, index, nodes });
            }
        };
        for (i, n) in self.nodes.iter().enumerate() {
            if let Some(m) = n.mesh.filter(|&m| m as usize >= self.meshes.len()) {
                errs.push(
                    None,
                    Invalid::NodeMeshOutOfRange {
                        node: i,
                        mesh: m,
                        meshes: self.meshes.len(),
                    },
                );
            }
            if let Some(s) = n.skin.filter(|&s| s as usize >= self.skins.len()) {
                errs.push(
                    None,
                    Invalid::NodeSkinOutOfRange {
                        node: i,
                        skin: s,
                        skins: self.skins.len(),
                    },
                );
            }
            for &c in &n.children {
                node_ref(&mut errs, format!("node {i} child"), c);
            }
        }
        for &r in &self.roots {
            node_ref(&mut errs, "root".to_string(), r);
        }
        for (si, s) in self.skins.iter().enumerate() {
            for (j, &n) in s.joints.iter().enumerate() {
                node_ref(&mut errs, format!("skin {si} joint {j}"), n);
            }
            if let Some(k) = s.skeleton {
                node_ref(&mut errs, format!("skin {si} skeleton"), k);
            }
            if !s.inverse_bind_matrices.is_empty()
                && s.inverse_bind_matrices.len() != s.joints.len()
            {
                errs.push(
                    None,
                    Invalid::InverseBindMatrices {
                        skin: si,
                        joints: s.joints.len(),
                        matrices: s.inverse_bind_matrices.len(),
                    },
                );
            }
        }
        for (mi, m) in self.materials.iter().enumerate() {
            for t in m.texture_refs() {
                if t.texture as usize >= self.textures.len() {
                    errs.push(
                        None,
                        Invalid::TextureOutOfRange {
                            material: mi,
                            texture: t.texture,
                            textures: self.textures.len(),
                        },
                    );
                }
            }
        }
        // A node may have at most one parent; this also rules out cycles
        // except a cycle with no entry from outside, caught by the walk below.
        let mut parents = vec![0u32; nodes];
        for n in &self.nodes {
            for &c in &n.children {
                if let Some(p) = parents.get_mut(c as usize) {
                    *p += 1;
                }
            }
        }
        for (i, &p) in parents.iter().enumerate() {
            if p > 1 {
                errs.push(None, Invalid::NodeGraph { node: i });
            }
        }
        let mut seen = vec![false; nodes];
        let mut stack: Vec<u32> = self.roots.clone();
        while let Some(n) = stack.pop() {
            let Some(s) = seen.get_mut(n as usize) else {
                continue;
            };
            if *s {
                errs.push(None, Invalid::NodeGraph { node: n as usize });
                break;
            }
            *s = true;
            stack.extend_from_slice(&self.nodes[n as usize].children);
        }
        errs.into_result()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Attribute, ComponentFormat, Faces, Node, Semantic};

    fn tri() -> Mesh {
        Mesh::from_triangles(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2])
    }

    #[test]
    fn valid_triangle_passes() {
        assert_eq!(tri().validate(), Ok(()));
    }

    #[test]
    fn out_of_range_index_names_face_and_index() {
        let mut m = tri();
        m.faces.indices[2] = 7;
        let e = m.validate().unwrap_err();
        assert_eq!(
            e.problems,
            vec![(
                None,
                Invalid::VertexOutOfRange {
                    face: 0,
                    index: 7,
                    vertices: 3
                }
            )]
        );
        assert!(e.to_string().contains("face 0 refers to vertex 7"));
    }

    #[test]
    fn nan_position_and_two_corner_face_are_both_reported() {
        let mut m = tri();
        m.positions[1][2] = f32::NAN;
        m.faces.push(&[0, 1]);
        m.face_parts.push(0);
        let e = m.validate().unwrap_err();
        assert!(e
            .problems
            .iter()
            .any(|(_, p)| matches!(p, Invalid::FaceTooSmall { face: 1, arity: 2 })));
        assert!(e
            .problems
            .iter()
            .any(|(_, p)| matches!(p, Invalid::NonFinitePosition { vertex: 1, .. })));
    }

    #[test]
    fn bad_offsets_are_reported_not_panicking() {
        let mut m = tri();
        m.faces = Faces {
            offsets: vec![0, 5],
            indices: vec![0, 1, 2],
        };
        assert!(m.validate().is_err());
    }

    #[test]
    fn attribute_index_out_of_range_is_reported() {
        let mut m = tri();
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: vec![0.0; 4],
            indices: vec![0, 1, 2],
            format: ComponentFormat::F32,
        });
        let e = m.validate().unwrap_err();
        assert!(matches!(
            e.problems[0].1,
            Invalid::AttributeIndexOutOfRange {
                corner: 2,
                index: 2,
                values: 2,
                ..
            }
        ));
    }

    #[test]
    fn scene_cycle_and_missing_mesh_are_reported() {
        let mut s = Scene::from_mesh(tri());
        s.nodes.push(Node {
            mesh: Some(4),
            children: vec![0],
            ..Node::default()
        });
        s.nodes[0].children = vec![1];
        let e = s.validate().unwrap_err();
        assert!(e.problems.iter().any(|(_, p)| matches!(
            p,
            Invalid::NodeMeshOutOfRange {
                node: 1,
                mesh: 4,
                ..
            }
        )));
        assert!(e
            .problems
            .iter()
            .any(|(_, p)| matches!(p, Invalid::NodeGraph { .. })));
    }
}
