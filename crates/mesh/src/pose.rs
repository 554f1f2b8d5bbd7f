//! A scene's nodes and skins at a time of one of its animations (glTF 2.0
//! §3.7.3 skins, §3.11 animations): what the evaluation poses a skinned
//! level of detail with, and what the simplifier measures a skin's
//! collapses in.
//!
//! Node transforms are animated by their translation, rotation and scale
//! tracks; a skinned vertex moves with `Σ wₖ · world(jointₖ) ·
//! inverseBindₖ`, as a renderer does (the skinned node's own transform is
//! ignored, as the specification says).

use glam::{Mat4, Quat, Vec3};

use crate::{Interpolation, Scene, Track, TrackPath};

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

/// The value of a track at time `t` (`n` floats per key: 3 or 4), as
/// glTF 2.0 §3.11 interpolates it; `None` when the track holds too few
/// values.
pub fn sample(track: &Track, n: usize, t: f32) -> Option<[f32; 4]> {
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

/// The value of a morph weight track at time `t`, `n` weights per key
/// (glTF 2.0 §3.11: weights interpolate component by component, cubic
/// splines included); `None` when the track holds too few values.
pub fn sample_weights(track: &Track, n: usize, t: f32) -> Option<Vec<f32>> {
    let keys = track.times.len();
    let cubic = track.interpolation == Interpolation::CubicSpline;
    let stride = if cubic { 3 * n } else { n };
    if keys == 0 || n == 0 || track.values.len() < keys * stride {
        return None;
    }
    let value = |k: usize| -> &[f32] {
        let o = k * stride + if cubic { n } else { 0 };
        &track.values[o..o + n]
    };
    if t <= track.times[0] {
        return Some(value(0).to_vec());
    }
    if t >= track.times[keys - 1] {
        return Some(value(keys - 1).to_vec());
    }
    let k = track.times.partition_point(|&x| x <= t).saturating_sub(1);
    let (t0, t1) = (track.times[k], track.times[k + 1]);
    let dt = t1 - t0;
    let u = if dt > 0.0 { (t - t0) / dt } else { 0.0 };
    let (a, b) = (value(k), value(k + 1));
    Some(match track.interpolation {
        Interpolation::Step => a.to_vec(),
        Interpolation::Linear => (0..n).map(|x| a[x] + (b[x] - a[x]) * u).collect(),
        Interpolation::CubicSpline => {
            let out_tangent = k * stride + 2 * n;
            let in_tangent = (k + 1) * stride;
            let (u2, u3) = (u * u, u * u * u);
            (0..n)
                .map(|x| {
                    (2.0 * u3 - 3.0 * u2 + 1.0) * a[x]
                        + (u3 - 2.0 * u2 + u) * dt * track.values[out_tangent + x]
                        + (-2.0 * u3 + 3.0 * u2) * b[x]
                        + (u3 - u2) * dt * track.values[in_tangent + x]
                })
                .collect()
        }
    })
}

/// The morph target weights of node `node` (whose mesh has `targets`
/// targets) at `time` of `animation`: its weights track there, else
/// zeros (the rest pose; the mesh's default weights, which the model does
/// not hold, are not applied).
pub fn morph_weights(
    scene: &Scene,
    animation: Option<usize>,
    time: f32,
    node: u32,
    targets: usize,
) -> Vec<f32> {
    animation
        .and_then(|a| scene.animations.get(a))
        .and_then(|anim| {
            anim.tracks
                .iter()
                .find(|t| t.node == node && t.path == TrackPath::Weights)
        })
        .and_then(|track| sample_weights(track, targets, time))
        .unwrap_or_else(|| vec![0.0; targets])
}

/// World matrix of every node at time `time` of `animation` (the rest pose
/// when `None`). Nodes no root reaches keep their local transform.
pub fn world_matrices(scene: &Scene, animation: Option<usize>, time: f32) -> Vec<Mat4> {
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
    compose(scene, &local)
}

/// World matrices of every node with the rest pose's local transforms,
/// except that each node of `bent` turns by `angle` radians about `axis`
/// of its own frame: a pose bending every joint of a skin at once, for
/// measuring a skin that no animation moves.
pub fn bent_world_matrices(scene: &Scene, bent: &[u32], axis: Vec3, angle: f32) -> Vec<Mat4> {
    let mut local: Vec<Trs> = scene.nodes.iter().map(|n| Trs::of(&n.matrix)).collect();
    let turn = Quat::from_axis_angle(axis.normalize_or_zero(), angle);
    for &n in bent {
        if let Some(l) = local.get_mut(n as usize) {
            l.r = (l.r * turn).normalize();
        }
    }
    compose(scene, &local)
}

/// World matrices from local transforms, down the node forest.
fn compose(scene: &Scene, local: &[Trs]) -> Vec<Mat4> {
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
        .zip(local)
        .map(|(w, l)| w.unwrap_or_else(|| l.matrix()))
        .collect()
}

/// Every joint's skinning matrix of `skin` given the nodes' world
/// matrices (see [`world_matrices`]): the joint's world matrix times its
/// inverse bind matrix (identity where the file gives none or the joint is
/// no node). A skinned position moves by the weighted sum of these.
pub fn skin_matrices(scene: &Scene, skin: u32, world: &[Mat4]) -> Vec<Mat4> {
    let Some(skin) = scene.skins.get(skin as usize) else {
        return Vec::new();
    };
    skin.joints
        .iter()
        .enumerate()
        .map(|(k, &j)| {
            let ibm = skin
                .inverse_bind_matrices
                .get(k)
                .map_or(Mat4::IDENTITY, Mat4::from_cols_array);
            world.get(j as usize).copied().unwrap_or(Mat4::IDENTITY) * ibm
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn morph_weights_interpolate_component_by_component() {
        // Three targets, keys at 0 and 2 s.
        let mut track = Track {
            node: 0,
            path: TrackPath::Weights,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 2.0],
            values: vec![0.0, 1.0, 0.5, 1.0, 0.0, 0.5],
        };
        assert_eq!(sample_weights(&track, 3, 0.5), Some(vec![0.25, 0.75, 0.5]));
        assert_eq!(sample_weights(&track, 3, 9.0), Some(vec![1.0, 0.0, 0.5]));
        track.interpolation = Interpolation::Step;
        assert_eq!(sample_weights(&track, 3, 1.9), Some(vec![0.0, 1.0, 0.5]));
        // Cubic with zero tangents: the value eases by 3u² − 2u³
        // (u = 0.5: halfway).
        track.interpolation = Interpolation::CubicSpline;
        track.values = vec![
            0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.0, 0.0, 0.0, // key 0: in, value, out
            0.0, 0.0, 0.0, 1.0, 0.0, 0.5, 0.0, 0.0, 0.0, // key 1
        ];
        assert_eq!(sample_weights(&track, 3, 1.0), Some(vec![0.5, 0.5, 0.5]));
        // Too few values for three weights a key.
        assert_eq!(sample_weights(&track, 4, 1.0), None);
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

    #[test]
    fn a_bent_joint_turns_its_subtree_about_its_own_frame() {
        // Root at the origin, a child one unit along x: bending the root
        // by 90° about z carries the child to (0, 1, 0); bending the child
        // turns it in place.
        let mut scene = Scene::default();
        let mut child = crate::IDENTITY;
        child[12] = 1.0;
        scene.nodes.push(crate::Node {
            children: vec![1],
            ..crate::Node::default()
        });
        scene.nodes.push(crate::Node {
            matrix: child,
            ..crate::Node::default()
        });
        scene.roots.push(0);
        let quarter = std::f32::consts::FRAC_PI_2;
        let w = bent_world_matrices(&scene, &[0], Vec3::Z, quarter);
        let p = w[1].transform_point3(Vec3::ZERO);
        assert!((p - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6, "{p}");
        let w = bent_world_matrices(&scene, &[1], Vec3::Z, quarter);
        let p = w[1].transform_point3(Vec3::ZERO);
        assert!((p - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-6, "{p}");
        let x = w[1].transform_point3(Vec3::X);
        assert!((x - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6, "{x}");
    }
}
