//! Morph targets are poses the mesh is drawn in: a LOD is judged, and
//! simplified, in them as well as at rest (`terms/posed.rs`).
#![allow(clippy::unwrap_used)] // test code

mod common;

use common::ratio;
use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::{shapes, Attribute, ComponentFormat, Mesh, MorphChannel, Semantic};
use wildlod_simplify::simplify_mesh;

/// Adds position morph target `target` with one delta per position
/// (`values`, three floats each), indexed like the positions, as glTF
/// stores targets.
fn push_target(m: &mut Mesh, target: u32, values: Vec<f32>) {
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::Morph {
            target,
            channel: MorphChannel::Position,
        },
        components: 3,
        values,
        indices,
        format: ComponentFormat::F32,
    });
}

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
    push_target(&mut m, 0, deltas);
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

/// A linear delta field: what any fit must give back exactly.
fn field(p: [f32; 3]) -> [f32; 3] {
    [0.2 * p[0] - 0.1 * p[1] + 0.05, 0.3 * p[1], 0.1 * p[0] + 0.2]
}

/// An `n × n` triangle grid on [0, 1]² with two targets: target 0 the
/// linear `field` everywhere, target 1 zero but on a small corner, and a
/// UV seam down the middle (the positions on it are stored twice, as a
/// glTF writer stores them, each copy with the same deltas).
fn grid_with_targets(n: usize) -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_grid(n, n));
    m.attributes.clear();
    let mut uvs = Vec::new();
    let mut uv_indices = Vec::new();
    for (c, &v) in m.faces.indices.iter().enumerate() {
        let p = m.positions[v as usize];
        let face = c / 3;
        let fc = m.faces.face(face);
        let cx = fc.iter().map(|&x| m.positions[x as usize][0]).sum::<f32>() / 3.0;
        // Left and right halves in separate charts.
        let shift = if cx < 0.5 { 0.0 } else { 2.0 };
        uv_indices.push((uvs.len() / 2) as u32);
        uvs.extend([p[0] + shift, p[1]]);
    }
    let target0: Vec<f32> = m.positions.iter().flat_map(|&p| field(p)).collect();
    let target1: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|&p| {
            let h = (0.2 - p[0] - p[1]).max(0.0);
            [0.0, 0.0, h]
        })
        .collect();
    for (target, values) in [(0u32, target0), (1, target1)] {
        push_target(&mut m, target, values);
    }
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uvs,
        indices: uv_indices,
        format: ComponentFormat::F32,
    });
    m
}

fn delta(m: &Mesh, target: u32, corner: usize) -> [f32; 3] {
    let a = m
        .attribute(&Semantic::Morph {
            target,
            channel: MorphChannel::Position,
        })
        .unwrap();
    let d = a.corner_value(corner).unwrap();
    [d[0], d[1], d[2]]
}

#[test]
fn a_linear_delta_field_survives_simplification_exactly_with_and_without_chunks() {
    let input = grid_with_targets(48);
    let mut chunked = ratio(0.05);
    chunked.partition = wildlod_simplify::Partition {
        min_triangles: 0,
        chunk_faces: 1024,
        handoff: 0.02,
    };
    for options in [ratio(0.05), chunked] {
        let (out, report) = simplify_mesh(&input, &options).unwrap();
        assert!(
            options.partition.min_triangles > 0 || report.parallel_collapses > 0,
            "{report:?}"
        );
        out.validate().unwrap();
        // Vertices moved, so the deltas were fitted, not copied.
        assert!(out.positions.iter().any(|p| !input.positions.contains(p)));
        for (corner, &v) in out.faces.indices.iter().enumerate() {
            let p = out.positions[v as usize];
            let (got, want) = (delta(&out, 0, corner), field(p));
            for k in 0..3 {
                assert!(
                    (got[k] - want[k]).abs() <= 1e-5,
                    "corner {corner} at {p:?}: {got:?} against the field's {want:?}"
                );
            }
            // Target 1 stays zero away from its corner of the grid (where
            // it is zero on every face a vertex could have merged).
            if p[0] + p[1] > 0.6 {
                assert_eq!(delta(&out, 1, corner), [0.0; 3], "at {p:?}");
            }
        }
    }
}

#[test]
fn copies_of_a_position_share_one_delta() {
    let input = grid_with_targets(48);
    let (out, _) = simplify_mesh(&input, &ratio(0.1)).unwrap();
    // The UV seam survives, so positions on it have corners in two charts.
    let uv = out.attribute(&Semantic::TexCoord(0)).unwrap();
    let mut charts_at = vec![Vec::new(); out.positions.len()];
    for (c, &v) in out.faces.indices.iter().enumerate() {
        let u = uv.corner_value(c).unwrap()[0];
        charts_at[v as usize].push((u >= 1.5, c));
    }
    let mut seam_positions = 0;
    for corners in &charts_at {
        if corners.iter().any(|x| x.0) && corners.iter().any(|x| !x.0) {
            seam_positions += 1;
        }
        for &(_, c) in corners {
            for target in [0, 1] {
                assert_eq!(delta(&out, target, c), delta(&out, target, corners[0].1));
            }
        }
    }
    assert!(seam_positions > 0);
}

#[test]
fn of_many_targets_those_that_move_the_surface_most_are_poses() {
    // 70 targets on a small sphere, target k lifting every position by
    // (k + 1)·1e-3 along z, but targets 3, 10 and 20 by less than any
    // other: past the cap, the smallest go.
    let mut m = shapes::triangulate(&shapes::quad_sphere(4));
    m.attributes.clear();
    let count = wildlod_simplify::MAX_MORPH_POSES + 6;
    let small = [3usize, 10, 20, 30, 40, 50];
    for k in 0..count {
        let h = if small.contains(&k) {
            1e-5 * (k + 1) as f32
        } else {
            1e-3 * (k + 1) as f32
        };
        let values = m.positions.iter().flat_map(|_| [0.0, 0.0, h]).collect();
        push_target(&mut m, k as u32, values);
    }
    let poses = wildlod_simplify::morph_targets(&m);
    assert_eq!(poses.len(), wildlod_simplify::MAX_MORPH_POSES);
    // In target order, the small ones left out.
    let lifts: Vec<f32> = poses.iter().map(|p| p[0][2]).collect();
    let want: Vec<f32> = (0..count)
        .filter(|k| !small.contains(k))
        .map(|k| 1e-3 * (k + 1) as f32)
        .collect();
    assert_eq!(lifts, want);
    // And the mesh simplifies with all 70 targets fitted.
    let (out, _) = simplify_mesh(&m, &ratio(0.5)).unwrap();
    let targets = out
        .attributes
        .iter()
        .filter(|a| matches!(a.semantic, Semantic::Morph { .. }))
        .count();
    assert_eq!(targets, count);
}

#[test]
fn a_skinned_mesh_with_blend_shapes_keeps_both() {
    // The bent tube (skinned, animated) with a target that swells a band
    // below its elbow: the scene path poses it by its skin and its target
    // together, and fits both.
    let mut scene = wildlod_testkit::scenes::bent_tube();
    let m = &mut scene.meshes[0];
    let values: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|p| {
            let band = (1.0 - ((p[1] - 1.5) / 0.5).powi(2)).max(0.0);
            let r = (p[0] * p[0] + p[2] * p[2]).sqrt().max(1e-6);
            [0.3 * band * p[0] / r, 0.0, 0.3 * band * p[2] / r]
        })
        .collect();
    push_target(m, 0, values);
    let run = |morph_poses: bool| {
        let mut o = ratio(0.1);
        o.attributes.morph_poses = morph_poses;
        let (out, report) = wildlod_simplify::simplify_scene(&scene, &o).unwrap();
        assert_eq!(report.groups.len(), 1, "{report:?}");
        let mut mesh = out.meshes[0].clone();
        mesh.validate().unwrap();
        assert!(mesh.skinning.is_some());
        // Measured unskinned (the skin's rest is its bind pose here).
        mesh.skinning = None;
        mesh
    };
    let mut input = scene.meshes[0].clone();
    input.skinning = None;
    let (with, without) = (run(true), run(false));
    let measure = |m: &Mesh| {
        (
            hausdorff(&input, m),
            hausdorff(&posed(&input, 1.0), &posed(m, 1.0)),
        )
    };
    let ((rest, swollen), (plain_rest, plain_swollen)) = (measure(&with), measure(&without));
    // Judged over the shapes it is drawn in: the worst of rest and full
    // weight. Measured: rest 0.0034, swollen 0.0046 with the pose; rest
    // 0 (a straight tube loses its rings for free), swollen 0.033 without:
    // the rest pose pays for the band it now keeps.
    let (worst, plain_worst) = (rest.max(swollen), plain_rest.max(plain_swollen));
    assert!(
        worst <= 0.5 * plain_worst,
        "rest {rest}, swollen {swollen}; without the target's pose: rest {plain_rest}, swollen {plain_swollen}"
    );
}

#[test]
fn poses_weigh_faces_no_more_than_the_rest_pose_does() {
    // A wavy grid whose columns crowd towards x = 0 (the faces' areas span
    // three orders of magnitude) and a target that bends it (z += 0.3xy).
    // Weighing every face alike (area exponent 0), the large faces weigh
    // less than their area at rest; a pose that took their rest planes
    // back out by area would leave a negative share of them, and the
    // collapses would pay for leaving the surface. Measured: 6.5× the
    // Hausdorff distance of area weighting that way, 1.07× now.
    let mut m = shapes::triangulate(&shapes::quad_grid(30, 30));
    m.attributes.clear();
    for p in &mut m.positions {
        p[0] = p[0].powi(3);
        p[2] = 0.05 * (4.0 * p[0]).sin() * (4.0 * p[1]).cos();
    }
    let bend: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|p| [0.0, 0.0, 0.3 * p[0] * p[1]])
        .collect();
    push_target(&mut m, 0, bend);
    let by_area = ratio(0.5);
    let mut alike = ratio(0.5);
    alike.metric.area_exponent = 0.0;
    let (a, _) = simplify_mesh(&m, &by_area).unwrap();
    let (b, _) = simplify_mesh(&m, &alike).unwrap();
    let (area, same) = (hausdorff(&m, &a), hausdorff(&m, &b));
    assert!(
        same <= 1.5 * area,
        "faces alike {same} against {area} weighed by area"
    );
    let (area, same) = (
        hausdorff(&posed(&m, 1.0), &posed(&a, 1.0)),
        hausdorff(&posed(&m, 1.0), &posed(&b, 1.0)),
    );
    assert!(
        same <= 1.5 * area,
        "posed: faces alike {same} against {area} weighed by area"
    );
}
