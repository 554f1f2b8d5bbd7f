//! Animations written from the [`Scene`]'s keyframe tracks (glTF 2.0
//! §3.11), for documents that did not come from glTF: scenes built in
//! memory, such as generated test scenes. A document read from glTF keeps
//! its source's animations instead (see `rewrite`).

use std::collections::HashMap;

use serde_json::{json, Map, Value};
use wildlod_mesh::{Interpolation, Scene, Track, TrackPath};

use super::accessor::Component;
use super::bin::Bin;

/// Which nodes some track of the scene animates: glTF forbids `matrix` on
/// them, so they are written as translation, rotation and scale.
pub(crate) fn animated_nodes(scene: &Scene) -> Vec<bool> {
    let mut out = vec![false; scene.nodes.len()];
    for t in scene.animations.iter().flat_map(|a| &a.tracks) {
        if t.path != TrackPath::Weights {
            if let Some(a) = out.get_mut(t.node as usize) {
                *a = true;
            }
        }
    }
    out
}

/// Translation, rotation (unit quaternion x, y, z, w) and scale of a
/// column-major matrix T·R·S; a negative determinant goes into the x
/// scale. A matrix with shear has no such form: the result is the nearest
/// one this method finds, and `exact` says whether it rebuilds the matrix.
pub(crate) struct Trs {
    pub translation: [f32; 3],
    pub rotation: [f32; 4],
    pub scale: [f32; 3],
    pub exact: bool,
}

/// See [`Trs`].
pub(crate) fn decompose(m: &[f32; 16]) -> Trs {
    let col = |c: usize| [0, 1, 2].map(|r| m[c * 4 + r] as f64);
    let mut cols = [col(0), col(1), col(2)];
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let mut scale = cols.map(len);
    let det = cols[0][0] * (cols[1][1] * cols[2][2] - cols[2][1] * cols[1][2])
        - cols[1][0] * (cols[0][1] * cols[2][2] - cols[2][1] * cols[0][2])
        + cols[2][0] * (cols[0][1] * cols[1][2] - cols[1][1] * cols[0][2]);
    if det < 0.0 {
        scale[0] = -scale[0];
    }
    for (c, s) in cols.iter_mut().zip(scale) {
        if s != 0.0 {
            *c = c.map(|x| x / s);
        }
    }
    // The rotation matrix R[r][c] = cols[c][r] to a quaternion
    // (Shepperd's method: divide by the largest of the four candidates).
    let r = |row: usize, c: usize| cols[c][row];
    let trace = r(0, 0) + r(1, 1) + r(2, 2);
    let q = if scale.contains(&0.0) {
        [0.0, 0.0, 0.0, 1.0]
    } else if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            (r(2, 1) - r(1, 2)) / s,
            (r(0, 2) - r(2, 0)) / s,
            (r(1, 0) - r(0, 1)) / s,
            0.25 * s,
        ]
    } else if r(0, 0) > r(1, 1) && r(0, 0) > r(2, 2) {
        let s = (1.0 + r(0, 0) - r(1, 1) - r(2, 2)).sqrt() * 2.0;
        [
            0.25 * s,
            (r(0, 1) + r(1, 0)) / s,
            (r(0, 2) + r(2, 0)) / s,
            (r(2, 1) - r(1, 2)) / s,
        ]
    } else if r(1, 1) > r(2, 2) {
        let s = (1.0 + r(1, 1) - r(0, 0) - r(2, 2)).sqrt() * 2.0;
        [
            (r(0, 1) + r(1, 0)) / s,
            0.25 * s,
            (r(1, 2) + r(2, 1)) / s,
            (r(0, 2) - r(2, 0)) / s,
        ]
    } else {
        let s = (1.0 + r(2, 2) - r(0, 0) - r(1, 1)).sqrt() * 2.0;
        [
            (r(0, 2) + r(2, 0)) / s,
            (r(1, 2) + r(2, 1)) / s,
            0.25 * s,
            (r(1, 0) - r(0, 1)) / s,
        ]
    };
    let n = len([q[0], q[1], q[2]]).hypot(q[3]);
    let rotation = q.map(|x| (x / n) as f32);
    let translation = [m[12], m[13], m[14]];
    let scale = scale.map(|s| s as f32);
    let back = super::read::trs_matrix(translation, rotation, scale);
    let exact = back
        .iter()
        .zip(m)
        .all(|(a, b)| (a - b).abs() <= 1e-5 * b.abs().max(1.0));
    Trs {
        translation,
        rotation,
        scale,
        exact,
    }
}

/// Floats per key of a track's property (`None` for morph weights, whose
/// count is the number of targets).
fn width(path: TrackPath) -> Option<usize> {
    match path {
        TrackPath::Translation | TrackPath::Scale => Some(3),
        TrackPath::Rotation => Some(4),
        TrackPath::Weights => None,
    }
}

/// Why a track cannot be written as a glTF channel, if it cannot.
fn track_problem(t: &Track, nodes: usize) -> Option<String> {
    let keys = t.times.len();
    let per_key = if t.interpolation == Interpolation::CubicSpline {
        3
    } else {
        1
    };
    if t.node as usize >= nodes {
        return Some(format!("it animates node {}, which does not exist", t.node));
    }
    if keys == 0 {
        return Some("it has no keys".into());
    }
    if !t.times.iter().all(|x| x.is_finite()) || t.times.windows(2).any(|w| w[0] >= w[1]) {
        return Some("its key times are not finite and increasing".into());
    }
    if !t.values.iter().all(|x| x.is_finite()) {
        return Some("it has non-finite values".into());
    }
    let fits = match width(t.path) {
        Some(w) => t.values.len() == keys * per_key * w,
        None => t.values.len() % (keys * per_key) == 0 && !t.values.is_empty(),
    };
    (!fits).then(|| {
        format!(
            "{} values do not fit {keys} keys of its property",
            t.values.len()
        )
    })
}

/// The scene's animations as glTF JSON, their keys written to `bin` (key
/// times shared between tracks that have the same ones). Tracks that glTF
/// cannot hold are left out with a warning, and so are animations left
/// without a track (glTF requires a channel).
pub(crate) fn animations(scene: &Scene, bin: &mut Bin, warnings: &mut Vec<String>) -> Vec<Value> {
    let mut inputs: HashMap<Vec<u32>, usize> = HashMap::new();
    let mut out = Vec::new();
    for (ai, a) in scene.animations.iter().enumerate() {
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        for (ti, t) in a.tracks.iter().enumerate() {
            if let Some(p) = track_problem(t, scene.nodes.len()) {
                warnings.push(format!("animation {ai} track {ti} is not written: {p}"));
                continue;
            }
            let key: Vec<u32> = t.times.iter().map(|x| x.to_bits()).collect();
            let input = *inputs.entry(key).or_insert_with(|| {
                let view = bin.view(&floats(&t.times), None, None);
                let lo = t.times[0] as f64;
                let hi = t.times[t.times.len() - 1] as f64;
                let bounds = Some((vec![lo], vec![hi]));
                bin.accessor(view, Component::F32, false, t.times.len(), "SCALAR", bounds)
            });
            let w = width(t.path).unwrap_or(1);
            let view = bin.view(&floats(&t.values), None, None);
            let kind = ["SCALAR", "SCALAR", "VEC2", "VEC3", "VEC4"][w];
            let output = bin.accessor(view, Component::F32, false, t.values.len() / w, kind, None);
            let (path, interpolation) = (
                match t.path {
                    TrackPath::Translation => "translation",
                    TrackPath::Rotation => "rotation",
                    TrackPath::Scale => "scale",
                    TrackPath::Weights => "weights",
                },
                match t.interpolation {
                    Interpolation::Linear => "LINEAR",
                    Interpolation::Step => "STEP",
                    Interpolation::CubicSpline => "CUBICSPLINE",
                },
            );
            channels.push(json!({
                "sampler": samplers.len(),
                "target": {"node": t.node, "path": path},
            }));
            samplers.push(json!({
                "input": input,
                "output": output,
                "interpolation": interpolation,
            }));
        }
        if channels.is_empty() {
            warnings.push(format!(
                "animation {ai} is not written: it has no keyframe track glTF can hold"
            ));
            continue;
        }
        let mut o = Map::new();
        if !a.name.is_empty() {
            o.insert("name".into(), json!(a.name));
        }
        o.insert("channels".into(), Value::Array(channels));
        o.insert("samplers".into(), Value::Array(samplers));
        out.push(Value::Object(o));
    }
    out
}

fn floats(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::IDENTITY;

    #[test]
    fn decompose_recovers_translation_rotation_and_scale() {
        // 90° about z (q = (0, 0, sin 45°, cos 45°)), scale (2, 1, 3),
        // translation (1, 2, 3).
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let m = super::super::read::trs_matrix([1.0, 2.0, 3.0], [0.0, 0.0, h, h], [2.0, 1.0, 3.0]);
        let t = decompose(&m);
        assert!(t.exact);
        assert_eq!(t.translation, [1.0, 2.0, 3.0]);
        for (a, b) in t.rotation.iter().zip([0.0, 0.0, h, h]) {
            assert!((a - b).abs() < 1e-6, "{:?}", t.rotation);
        }
        for (a, b) in t.scale.iter().zip([2.0, 1.0, 3.0]) {
            assert!((a - b).abs() < 1e-6, "{:?}", t.scale);
        }
    }

    #[test]
    fn decompose_of_a_translation_is_exact() {
        let mut m = IDENTITY;
        m[13] = 3.0;
        let t = decompose(&m);
        assert_eq!(t.translation, [0.0, 3.0, 0.0]);
        assert_eq!(t.rotation, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(t.scale, [1.0; 3]);
    }

    #[test]
    fn decompose_flags_a_shear() {
        let mut m = IDENTITY;
        m[4] = 0.5; // column 1 leans along x
        assert!(!decompose(&m).exact);
    }

    #[test]
    fn malformed_tracks_are_named() {
        let t = Track {
            node: 0,
            path: TrackPath::Rotation,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 1.0],
            values: vec![0.0; 7],
        };
        assert!(track_problem(&t, 1).is_some_and(|p| p.contains("7 values")));
        assert!(track_problem(&t, 0).is_some_and(|p| p.contains("node 0")));
        let ok = Track {
            values: vec![0.0; 8],
            ..t.clone()
        };
        assert_eq!(track_problem(&ok, 1), None);
        let backwards = Track {
            times: vec![1.0, 0.0],
            ..ok
        };
        assert!(track_problem(&backwards, 1).is_some_and(|p| p.contains("increasing")));
    }
}
