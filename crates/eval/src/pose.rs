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

use glam::{Mat3, Mat4, Quat, Vec3};
use wildlod_mesh::transform::transformed;
use wildlod_mesh::{
    Interpolation, Mesh, Node, Scene, Semantic, Track, TrackPath, ABSENT, IDENTITY,
};

/// A node's local transform as translation, rotation, scale.
#[derive(Clone, Copy, Debug)]
struct Trs {
    t: Vec3,
    r: Quat,
    s: Vec3,
}

impl Trs {
    fn of(m: &[f32; 16]) -> Trs {
        let (s, r, t) = Mat4::from_cols_array(m).to_scale_rotation_translation();
        Trs { t, r, s }
    }

    fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.s, self.r, self.t)
    }
}

/// The value of a track at time `t` (`n` floats per key: 3 or 4).
fn sample(track: &Track, n: usize, t: f32) -> Option<[f32; 4]> {
    let keys = track.times.len();
    let stride = if track.interpolation == Interpolation::CubicSpline {
        3 * n
    } else {
        n
    };
    if keys == 0 || track.values.len() < keys * stride {
        return None;
    }
    // The value of key k (the middle third of a cubic key).
    let value = |k: usize| -> [f32; 4] {
        let o = k * stride + if stride == 3 * n { n } else { 0 };
        let mut v = [0.0; 4];
        v[..n].copy_from_slice(&track.values[o..o + n]);
        v
    };
    if t <= track.times[0] {
        return Some(value(0));
    }
    if t >= track.times[keys - 1] {
        return Some(value(keys - 1));
    }
    // The last key at or before t.
    let k = track.times.partition_point(|&x| x <= t).saturating_sub(1);
    let (t0, t1) = (track.times[k], track.times[k + 1]);
    let dt = t1 - t0;
    let u = if dt > 0.0 { (t - t0) / dt } else { 0.0 };
    let (a, b) = (value(k), value(k + 1));
    let mut out = [0.0; 4];
    match track.interpolation {
        Interpolation::Step => out = a,
        Interpolation::Linear if n == 4 => {
            let q = Quat::from_array(a).slerp(Quat::from_array(b), u);
            out = q.to_array();
        }
        Interpolation::Linear => {
            for x in 0..n {
                out[x] = a[x] + (b[x] - a[x]) * u;
            }
        }
        Interpolation::CubicSpline => {
            let out_tangent = k * stride + 2 * n;
            let in_tangent = (k + 1) * stride;
            let (u2, u3) = (u * u, u * u * u);
            for x in 0..n {
                out[x] = (2.0 * u3 - 3.0 * u2 + 1.0) * a[x]
                    + (u3 - 2.0 * u2 + u) * dt * track.values[out_tangent + x]
                    + (-2.0 * u3 + 3.0 * u2) * b[x]
                    + (u3 - u2) * dt * track.values[in_tangent + x];
            }
        }
    }
    if n == 4 {
        let q = Quat::from_array(out).normalize();
        out = q.to_array();
    }
    Some(out)
}

/// World matrix of every node at time `time` of `animation` (the rest pose
/// when `None`). Nodes no root reaches keep their local transform.
fn world_matrices(scene: &Scene, animation: Option<usize>, time: f32) -> Vec<Mat4> {
    let mut local: Vec<Trs> = scene.nodes.iter().map(|n| Trs::of(&n.matrix)).collect();
    if let Some(anim) = animation.and_then(|a| scene.animations.get(a)) {
        for track in &anim.tracks {
            let Some(l) = local.get_mut(track.node as usize) else {
                continue;
            };
            match track.path {
                TrackPath::Translation => {
                    if let Some(v) = sample(track, 3, time) {
                        l.t = Vec3::new(v[0], v[1], v[2]);
                    }
                }
                TrackPath::Scale => {
                    if let Some(v) = sample(track, 3, time) {
                        l.s = Vec3::new(v[0], v[1], v[2]);
                    }
                }
                TrackPath::Rotation => {
                    if let Some(v) = sample(track, 4, time) {
                        l.r = Quat::from_array(v);
                    }
                }
                TrackPath::Weights => {}
            }
        }
    }
    let mut world: Vec<Option<Mat4>> = vec![None; scene.nodes.len()];
    let mut stack: Vec<(u32, Mat4)> = scene.roots.iter().map(|&r| (r, Mat4::IDENTITY)).collect();
    while let Some((n, parent)) = stack.pop() {
        let Some(node) = scene.nodes.get(n as usize) else {
            continue;
        };
        if world[n as usize].is_some() {
            continue; // a node reached twice: the graph is not a forest
        }
        let w = parent * local[n as usize].matrix();
        world[n as usize] = Some(w);
        for &c in &node.children {
            stack.push((c, w));
        }
    }
    world
        .into_iter()
        .zip(&local)
        .map(|(w, l)| w.unwrap_or_else(|| l.matrix()))
        .collect()
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
        let skin = node.skin.and_then(|s| scene.skins.get(s as usize));
        let posed_mesh = match skin {
            Some(skin) if mesh.skinning.is_some() => {
                let joints: Vec<Mat4> = skin
                    .joints
                    .iter()
                    .enumerate()
                    .map(|(k, &j)| {
                        let ibm = skin
                            .inverse_bind_matrices
                            .get(k)
                            .map_or(Mat4::IDENTITY, Mat4::from_cols_array);
                        world.get(j as usize).copied().unwrap_or(Mat4::IDENTITY) * ibm
                    })
                    .collect();
                skinned(mesh, &joints)
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
    use wildlod_mesh::{Animation, ComponentFormat, Skin, Skinning};

    fn track(
        path: TrackPath,
        interpolation: Interpolation,
        times: &[f32],
        values: &[f32],
    ) -> Track {
        Track {
            node: 1,
            path,
            interpolation,
            times: times.to_vec(),
            values: values.to_vec(),
        }
    }

    #[test]
    fn tracks_interpolate_as_gltf_says() {
        let t = track(
            TrackPath::Translation,
            Interpolation::Linear,
            &[0.0, 2.0],
            &[0.0, 0.0, 0.0, 4.0, 2.0, 0.0],
        );
        assert_eq!(sample(&t, 3, 0.5).unwrap()[..3], [1.0, 0.5, 0.0]);
        // Clamped before the first and after the last key.
        assert_eq!(sample(&t, 3, -1.0).unwrap()[..3], [0.0, 0.0, 0.0]);
        assert_eq!(sample(&t, 3, 9.0).unwrap()[..3], [4.0, 2.0, 0.0]);
        let step = Track {
            interpolation: Interpolation::Step,
            ..t.clone()
        };
        assert_eq!(sample(&step, 3, 1.9).unwrap()[..3], [0.0, 0.0, 0.0]);
        // Rotation halfway from identity to 90° about z is 45° about z.
        let q90 = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let r = track(
            TrackPath::Rotation,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 1.0, q90.x, q90.y, q90.z, q90.w],
        );
        let half = Quat::from_array(sample(&r, 4, 0.5).unwrap());
        assert!(half.angle_between(Quat::from_rotation_z(std::f32::consts::FRAC_PI_4)) < 1e-5);
        // A cubic spline with zero tangents: Hermite at u = 1/2 is the mean.
        let c = track(
            TrackPath::Translation,
            Interpolation::CubicSpline,
            &[0.0, 1.0],
            &[
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, // key 0: in, value, out
                0.0, 0.0, 0.0, 2.0, 4.0, 6.0, 0.0, 0.0, 0.0, // key 1
            ],
        );
        let v = sample(&c, 3, 0.5).unwrap();
        assert!((v[0] - 1.0).abs() < 1e-6 && (v[2] - 3.0).abs() < 1e-6);
    }

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
            tracks: vec![track(
                TrackPath::Translation,
                Interpolation::Linear,
                &[0.0, 1.0],
                &[0.0, 0.0, 0.0, 0.0, 0.0, 2.0],
            )],
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
