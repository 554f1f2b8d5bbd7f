//! A scene posed at a time of one of its animations (glTF 2.0 §3.7.3
//! skins, §3.11 animations), for measuring a skinned level of detail the
//! way it is seen: Knodt 2024 §4 compares input and output at the first 50
//! frames of the first animation.
//!
//! Node transforms are animated by their translation, rotation and scale
//! tracks; a skinned mesh's vertices move with `Σ wₖ · world(jointₖ) ·
//! inverseBindₖ`, as a renderer does (the skinned node's own transform is
//! ignored, as the specification says; weights are normalized to sum 1, as
//! renderers do for files that break that rule). Morph target weights are
//! not applied.

use glam::{Mat3, Mat4, Vec3};
use wildlod_mesh::pose::{skin_matrices, world_matrices};
use wildlod_mesh::transform::transformed;
use wildlod_mesh::{Mesh, Node, Scene, Semantic, ABSENT, IDENTITY};

/// A copy of `mesh` skinned by `joints` (one matrix per skin joint): each
/// position moves with the influences of its first skinned corner; normals
/// turn with the same blend. Positions without influences stay.
fn skinned(mesh: &Mesh, joints: &[Mat4]) -> Mesh {
    let mut out = mesh.clone();
    let Some(s) = &mesh.skinning else {
        return out;
    };
    let mut blend: Vec<Option<Mat4>> = vec![None; mesh.positions.len()];
    for (corner, &v) in mesh.faces.indices.iter().enumerate() {
        let e = s.indices[corner];
        if e == ABSENT || blend[v as usize].is_some() {
            continue;
        }
        let (js, ws) = s.entry(e);
        // Renderers normalize weights that do not sum to 1 (three.js's
        // glTF loader does; the specification requires the sum to be 1).
        let sum: f32 = ws.iter().sum();
        if sum <= 0.0 {
            continue;
        }
        let mut m = Mat4::ZERO;
        for (&j, &w) in js.iter().zip(ws) {
            if let Some(jm) = joints.get(j as usize) {
                m += *jm * (w / sum);
            }
        }
        blend[v as usize] = Some(m);
    }
    for (p, b) in out.positions.iter_mut().zip(&blend) {
        if let Some(m) = b {
            *p = m.transform_point3(Vec3::from_array(*p)).to_array();
        }
    }
    // Normals turn with the blend of their corner's vertex.
    let corner_blend: Vec<Option<Mat3>> = mesh
        .faces
        .indices
        .iter()
        .map(|&v| blend[v as usize].map(|m| Mat3::from_mat4(m).inverse().transpose()))
        .collect();
    for a in out.attributes.iter_mut() {
        if a.semantic != Semantic::Normal || a.components != 3 {
            continue;
        }
        // A value may be shared by corners of different blends: give every
        // corner its own value.
        let mut values = Vec::with_capacity(a.indices.len() * 3);
        for (corner, i) in a.indices.iter_mut().enumerate() {
            if *i == ABSENT {
                continue;
            }
            let n = Vec3::from_slice(&a.values[*i as usize * 3..*i as usize * 3 + 3]);
            let n = match corner_blend[corner] {
                Some(m) => (m * n).normalize_or_zero(),
                None => n,
            };
            *i = (values.len() / 3) as u32;
            values.extend_from_slice(&n.to_array());
        }
        a.values = values;
    }
    out.skinning = None;
    out
}

/// `scene` posed at `time` seconds of animation `animation` (the rest pose
/// for `None`, or an animation that does not exist): every mesh instance
/// becomes its own mesh in world space under one identity node, skinned
/// meshes deformed by their joints; materials and textures are kept, so
/// every metric (texture and normal Chamfer included) applies.
pub fn posed(scene: &Scene, animation: Option<usize>, time: f32) -> Scene {
    let world = world_matrices(scene, animation, time);
    let mut out = Scene {
        materials: scene.materials.clone(),
        textures: scene.textures.clone(),
        ..Scene::default()
    };
    let mut reached = vec![false; scene.meshes.len()];
    for (n, node) in scene.nodes.iter().enumerate() {
        let Some(mi) = node.mesh.filter(|&m| (m as usize) < scene.meshes.len()) else {
            continue;
        };
        reached[mi as usize] = true;
        let mesh = &scene.meshes[mi as usize];
        let posed_mesh = match node.skin {
            Some(skin) if mesh.skinning.is_some() && (skin as usize) < scene.skins.len() => {
                skinned(mesh, &skin_matrices(scene, skin, &world))
            }
            _ => transformed(mesh, &world[n].to_cols_array()),
        };
        push_instance(&mut out, posed_mesh);
    }
    for (m, r) in reached.iter().enumerate() {
        if !r {
            push_instance(&mut out, scene.meshes[m].clone());
        }
    }
    out
}

fn push_instance(out: &mut Scene, mut mesh: Mesh) {
    mesh.skinning = None;
    let m = out.meshes.len() as u32;
    out.meshes.push(mesh);
    out.roots.push(out.nodes.len() as u32);
    out.nodes.push(Node {
        matrix: IDENTITY,
        mesh: Some(m),
        ..Node::default()
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::{
        Animation, ComponentFormat, Interpolation, Skin, Skinning, Track, TrackPath,
    };

    /// A unit triangle skinned half to a fixed root (joint 0) and half to a
    /// child joint (joint 1, node 1) whose translation animates from 0 to
    /// (0, 0, 2) over one second.
    fn rig() -> Scene {
        let mut m = Mesh::from_triangles(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2],
        );
        m.skinning = Some(Skinning {
            influences: 2,
            // Vertex 0 on joint 0; vertex 1 on joint 1; vertex 2 half each.
            joints: vec![0, 1, 1, 0, 0, 1],
            weights: vec![1.0, 0.0, 1.0, 0.0, 0.5, 0.5],
            indices: vec![0, 1, 2],
            weight_format: ComponentFormat::F32,
            joint_format: ComponentFormat::U8,
        });
        let mut s = Scene::from_mesh(m);
        s.nodes[0].skin = Some(0);
        s.nodes[0].children = vec![1];
        s.nodes.push(Node::default());
        s.skins.push(Skin {
            joints: vec![0, 1],
            ..Skin::default()
        });
        s.animations.push(Animation {
            name: "lift".into(),
            channels: 1,
            duration: 1.0,
            tracks: vec![Track {
                node: 1,
                path: TrackPath::Translation,
                interpolation: Interpolation::Linear,
                times: vec![0.0, 1.0],
                values: vec![0.0, 0.0, 0.0, 0.0, 0.0, 2.0],
            }],
        });
        s
    }

    #[test]
    fn skinned_vertices_follow_their_joints() {
        let s = rig();
        let rest = posed(&s, None, 0.0);
        assert_eq!(rest.meshes[0].positions, s.meshes[0].positions);
        let p = posed(&s, Some(0), 0.5).meshes[0].positions.clone();
        // Joint 1 has moved by (0, 0, 1): vertex 1 fully, vertex 2 by half.
        assert_eq!(p[0], [0.0, 0.0, 0.0]);
        assert_eq!(p[1], [1.0, 0.0, 1.0]);
        assert_eq!(p[2], [0.0, 1.0, 0.5]);
        assert!(posed(&s, Some(0), 0.5).meshes[0].skinning.is_none());
    }
}
