//! A scene posed at a time of one of its animations (glTF 2.0 §3.7.3
//! skins, §3.11 animations), for measuring a skinned level of detail the
//! way it is seen: Knodt 2024 §4 compares input and output at the first 50
//! frames of the first animation.
//!
//! Node transforms are animated by their translation, rotation and scale
//! tracks; a skinned mesh's vertices move with `Σ wₖ · world(jointₖ) ·
//! inverseBindₖ`, as a renderer does (the skinned node's own transform is
//! ignored, as the specification says; weights are normalized to sum 1, as
//! renderers do for files that break that rule). Morph targets apply
//! first, with the node's animated weights: positions and normals move by
//! their weighted deltas (a node with no weights track shows its rest
//! shape: default mesh weights are not modelled).

use glam::{Mat3, Mat4, Vec3};
use wildlod_mesh::pose::{morph_weights, skin_matrices, world_matrices};
use wildlod_mesh::transform::transformed;
use wildlod_mesh::{Mesh, MorphChannel, Node, Scene, Semantic, ABSENT, IDENTITY};

/// Number of morph targets of `mesh` (one past the highest target index).
fn morph_target_count(mesh: &Mesh) -> usize {
    mesh.attributes
        .iter()
        .filter_map(|a| match a.semantic {
            Semantic::Morph { target, .. } => Some(target as usize + 1),
            _ => None,
        })
        .max()
        .unwrap_or(0)
}

/// A copy of `mesh` with its morph targets applied at `weights`: each
/// position moves by the weighted deltas of its first corner; each
/// corner's normal by its own, renormalized. `None` when no weight is
/// nonzero.
fn morphed(mesh: &Mesh, weights: &[f32]) -> Option<Mesh> {
    if weights.iter().all(|&w| w == 0.0) {
        return None;
    }
    let mut out = mesh.clone();
    let mut position_done = vec![false; mesh.positions.len()];
    let normal_at = mesh
        .attributes
        .iter()
        .position(|a| a.semantic == Semantic::Normal && a.components == 3);
    // Per corner, the normal delta summed over targets.
    let mut normal_delta = vec![[0.0f32; 3]; mesh.faces.indices.len()];
    let mut any_normal = false;
    for a in &mesh.attributes {
        let Semantic::Morph { target, channel } = a.semantic else {
            continue;
        };
        let w = weights.get(target as usize).copied().unwrap_or(0.0);
        if w == 0.0 || a.components < 3 {
            continue;
        }
        match channel {
            MorphChannel::Position => {
                position_done.fill(false);
                for (c, &v) in mesh.faces.indices.iter().enumerate() {
                    if std::mem::replace(&mut position_done[v as usize], true) {
                        continue;
                    }
                    if let Some(d) = a.corner_value(c) {
                        for (p, x) in out.positions[v as usize].iter_mut().zip(d) {
                            *p += w * x;
                        }
                    }
                }
            }
            MorphChannel::Normal => {
                for (c, nd) in normal_delta.iter_mut().enumerate() {
                    if let Some(d) = a.corner_value(c) {
                        for (n, x) in nd.iter_mut().zip(d) {
                            *n += w * x;
                        }
                        any_normal = true;
                    }
                }
            }
            MorphChannel::Tangent => {}
        }
    }
    if let (Some(i), true) = (normal_at, any_normal) {
        let a = &mut out.attributes[i];
        let mut values = Vec::with_capacity(a.indices.len() * 3);
        for (corner, idx) in a.indices.iter_mut().enumerate() {
            if *idx == ABSENT {
                continue;
            }
            let at = *idx as usize * 3;
            let n = Vec3::from_slice(&a.values[at..at + 3]) + Vec3::from(normal_delta[corner]);
            *idx = (values.len() / 3) as u32;
            values.extend_from_slice(&n.normalize_or_zero().to_array());
        }
        a.values = values;
    }
    Some(out)
}

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
    posed_about(scene, animation, time, [0.0; 3])
}

/// A point to pose `scene` about ([`posed_about`]): the world position of
/// its first mesh instance's origin. Two files to compare are posed about
/// the reference's.
pub fn pose_origin(scene: &Scene) -> [f64; 3] {
    scene
        .instances()
        .first()
        .map_or([0.0; 3], |(_, m)| [m[12], m[13], m[14]].map(f64::from))
}

/// [`posed`] with every position relative to `origin`, placed in f64: a
/// georeferenced file's meshes sit millions of units from the world
/// origin, where f32 positions step by a quarter of a unit, so posing in
/// world coordinates would swamp every distance measured on them.
pub fn posed_about(scene: &Scene, animation: Option<usize>, time: f32, origin: [f64; 3]) -> Scene {
    let world = world_matrices(scene, animation, time);
    let about = |m: &Mat4| shifted(m, origin);
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
        let targets = morph_target_count(mesh);
        let with_morphs = (targets > 0)
            .then(|| {
                morphed(
                    mesh,
                    &morph_weights(scene, animation, time, n as u32, targets),
                )
            })
            .flatten();
        let mesh = with_morphs.as_ref().unwrap_or(mesh);
        let posed_mesh = match node.skin {
            Some(skin) if mesh.skinning.is_some() && (skin as usize) < scene.skins.len() => {
                // Weights sum to one: shifting every joint shifts the blend.
                let joints: Vec<Mat4> = skin_matrices(scene, skin, &world)
                    .iter()
                    .map(about)
                    .collect();
                skinned(mesh, &joints)
            }
            _ => transformed(mesh, &about(&world[n]).to_cols_array()),
        };
        push_instance(&mut out, posed_mesh);
    }
    for (m, r) in reached.iter().enumerate() {
        if !r {
            let mesh = &scene.meshes[m];
            let moved = if origin == [0.0; 3] {
                mesh.clone()
            } else {
                transformed(mesh, &about(&Mat4::IDENTITY).to_cols_array())
            };
            push_instance(&mut out, moved);
        }
    }
    out
}

/// `m` followed by a translation by `-origin`, computed in f64.
fn shifted(m: &Mat4, origin: [f64; 3]) -> Mat4 {
    if origin == [0.0; 3] {
        return *m;
    }
    let mut c = m.to_cols_array().map(f64::from);
    for col in 0..4 {
        let w = c[4 * col + 3];
        for k in 0..3 {
            c[4 * col + k] -= origin[k] * w;
        }
    }
    Mat4::from_cols_array(&c.map(|x| x as f32))
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

    /// A tilted 10 × 10 square as an `n × n` grid of triangle pairs, shown
    /// by one node moved by `t`.
    fn tilted_square(n: usize, t: [f32; 3]) -> Scene {
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, z) = (10.0 * i as f32 / n as f32, 10.0 * j as f32 / n as f32);
                pos.push([x, 0.37 * x, z]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut idx = Vec::new();
        for j in 0..n {
            for i in 0..n {
                idx.extend_from_slice(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                idx.extend_from_slice(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let mut matrix = IDENTITY;
        matrix[12..15].copy_from_slice(&t);
        Scene {
            meshes: vec![Mesh::from_triangles(pos, &idx)],
            nodes: vec![Node {
                mesh: Some(0),
                matrix,
                ..Node::default()
            }],
            roots: vec![0],
            ..Scene::default()
        }
    }

    #[test]
    fn far_from_the_origin_one_plane_in_two_tessellations_measures_zero() {
        // Four million units away f32 steps by a quarter of a unit: placed
        // in world coordinates, the tessellations rounded apart (0.1
        // units); posed about the reference's point, they coincide.
        let at = [2.0e6, 4.0e6, 1.0e3];
        let (fine, coarse) = (tilted_square(8, at), tilted_square(1, at));
        let origin = pose_origin(&fine);
        assert_eq!(origin, [2.0e6, 4.0e6, 1.0e3]);
        let measure = |o: [f64; 3]| {
            let images: Vec<Option<wildlod_mesh::Image>> = Vec::new();
            let r = crate::EvalMesh::from_scene(&posed_about(&fine, None, 0.0, o), &images);
            let c = crate::EvalMesh::from_scene(&posed_about(&coarse, None, 0.0, o), &images);
            crate::compare(&r, &c, &crate::CompareOptions::default()).hausdorff
        };
        assert!(measure(origin) < 1e-6, "{}", measure(origin));
        assert!(measure([0.0; 3]) > 1e-3, "the case tests nothing");
    }

    #[test]
    fn morph_targets_apply_with_the_animated_weights() {
        // A unit triangle whose target 1 lifts vertex 2 by 2 (target 0
        // moves nothing); the node's weights go from (0, 0) to (0, 1).
        let mut m = Mesh::from_triangles(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2],
        );
        for (target, lift) in [(0u32, 0.0f32), (1, 2.0)] {
            m.attributes.push(wildlod_mesh::Attribute {
                semantic: Semantic::Morph {
                    target,
                    channel: MorphChannel::Position,
                },
                components: 3,
                values: vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, lift],
                indices: vec![0, 1, 2],
                format: ComponentFormat::F32,
            });
        }
        let mut s = Scene::from_mesh(m);
        s.animations.push(Animation {
            name: "open".into(),
            channels: 1,
            duration: 1.0,
            tracks: vec![Track {
                node: 0,
                path: TrackPath::Weights,
                interpolation: Interpolation::Linear,
                times: vec![0.0, 1.0],
                values: vec![0.0, 0.0, 0.0, 1.0],
            }],
        });
        let z2 = |t: f32| posed(&s, Some(0), t).meshes[0].positions[2][2];
        assert_eq!(z2(0.0), 0.0);
        assert_eq!(z2(0.25), 0.5);
        assert_eq!(z2(1.0), 2.0);
        // The rest pose, and an animation without weights, show the rest
        // shape.
        assert_eq!(posed(&s, None, 0.5).meshes[0].positions[2][2], 0.0);
        let still = posed(&s, Some(7), 0.5);
        assert_eq!(still.meshes[0].positions, s.meshes[0].positions);
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
