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
