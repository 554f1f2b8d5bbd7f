//! Morph targets are poses the mesh is drawn in: a LOD is judged, and
//! simplified, in them as well as at rest (`terms/posed.rs`).
#![allow(clippy::unwrap_used)] // test code

mod common;

use common::ratio;
use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::{shapes, Attribute, ComponentFormat, Mesh, MorphChannel, Semantic};
use wildlod_simplify::simplify_mesh;

/// A sphere with one morph target that raises a nose: a bump of height
/// 0.4 within 20° of +x, nothing elsewhere. Deltas per position, the
/// way glTF stores them (one value per vertex).
fn sphere_with_a_nose(n: usize) -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_sphere(n));
    let deltas: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|&p| {
            let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let angle = (p[0] / len).clamp(-1.0, 1.0).acos().to_degrees();
            let h = if angle < 20.0 {
                0.4 * (1.0 - angle / 20.0).powi(2)
            } else {
                0.0
            };
            p.map(|c| c / len * h)
        })
        .collect();
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::Morph {
            target: 0,
            channel: MorphChannel::Position,
        },
        components: 3,
        values: deltas,
        indices,
        format: ComponentFormat::F32,
    });
    m
}

/// The mesh with its first morph target at `weight`.
fn posed(m: &Mesh, weight: f32) -> Mesh {
    let mut out = m.clone();
    out.attributes.clear();
    let morph = m
        .attributes
        .iter()
        .find(|a| matches!(a.semantic, Semantic::Morph { .. }))
        .unwrap();
    let mut done = vec![false; m.positions.len()];
    for (c, &v) in m.faces.indices.iter().enumerate() {
        if std::mem::replace(&mut done[v as usize], true) {
            continue;
        }
        let d = morph.corner_value(c).unwrap();
        for (p, x) in out.positions[v as usize].iter_mut().zip(d) {
            *p += weight * x;
        }
    }
    out
}

fn hausdorff(a: &Mesh, b: &Mesh) -> f64 {
    let options = CompareOptions {
        samples: 40_000,
        texture_samples: 0,
        ..CompareOptions::default()
    };
    compare(&EvalMesh::from_mesh(a), &EvalMesh::from_mesh(b), &options).hausdorff
}

#[test]
fn a_morph_target_is_simplified_as_a_pose() {
    let input = sphere_with_a_nose(24);
    let (out, report) = simplify_mesh(&input, &ratio(0.1)).unwrap();
    assert!(report.output_triangles.abs_diff(report.target_triangles) <= 1);
    // Rest pose only: the deltas carried along but not looked at.
    let mut rest_only = ratio(0.1);
    rest_only.attributes.morph_poses = false;
    let (plain, _) = simplify_mesh(&input, &rest_only).unwrap();
    let (rest, nose) = (
        hausdorff(&input, &out),
        hausdorff(&posed(&input, 1.0), &posed(&out, 1.0)),
    );
    let (plain_rest, plain_nose) = (
        hausdorff(&input, &plain),
        hausdorff(&posed(&input, 1.0), &posed(&plain, 1.0)),
    );
    // Measured: the nose at 0.0029 against 0.0221 (a tenth of the
    // sphere's vertices spread evenly flatten it), the rest pose at 0.0024
    // both ways: the nose's vertices come from where the rest pose needs
    // them least.
    assert!(
        nose <= 0.5 * plain_nose,
        "posed {nose} against {plain_nose} with the rest pose alone"
    );
    assert!(
        rest <= 1.15 * plain_rest,
        "rest {rest} against {plain_rest} with the rest pose alone"
    );
}

#[test]
fn targets_that_move_nothing_are_not_poses() {
    let mut input = sphere_with_a_nose(8);
    assert_eq!(wildlod_simplify::morph_targets(&input).len(), 1);
    for a in &mut input.attributes {
        a.values.fill(0.0);
    }
    assert!(wildlod_simplify::morph_targets(&input).is_empty());
    // And a mesh with only still targets simplifies as with the rest
    // pose alone.
    let (out, _) = simplify_mesh(&input, &ratio(0.1)).unwrap();
    let mut rest_only = ratio(0.1);
    rest_only.attributes.morph_poses = false;
    let (plain, _) = simplify_mesh(&input, &rest_only).unwrap();
    assert_eq!(out.positions, plain.positions);
}
