//! One scene, one budget (W §1, Fig. 1): `simplify_scene` against
//! simplifying every mesh alone.

mod common;

use common::bumpy_sphere;
use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::{Mesh, Node, Scene, Skinning, IDENTITY};
use wildlod_simplify::{simplify_mesh, simplify_scene, GroupSpace, Options, Target};

fn translate_scale(t: [f32; 3], s: f32) -> [f32; 16] {
    let mut m = IDENTITY;
    for k in 0..3 {
        m[5 * k] = s;
        m[12 + k] = t[k];
    }
    m
}

/// A scene whose node `i` shows mesh `mesh` through `matrix`.
fn scene(meshes: Vec<Mesh>, nodes: &[(u32, [f32; 16])]) -> Scene {
    Scene {
        meshes,
        nodes: nodes
            .iter()
            .map(|&(m, matrix)| Node {
                mesh: Some(m),
                matrix,
                ..Node::default()
            })
            .collect(),
        roots: (0..nodes.len() as u32).collect(),
        ..Scene::default()
    }
}

fn target(t: Target) -> Options {
    Options {
        target: t,
        ..Options::default()
    }
}

fn ratio(r: f64) -> Options {
    target(Target {
        ratio: Some(r),
        ..Target::default()
    })
}

/// Two-sided Hausdorff distance of `candidate` to `reference`, relative
/// to the reference's diagonal.
fn hausdorff(reference: &Mesh, candidate: &Mesh) -> f64 {
    compare(
        &EvalMesh::from_mesh(reference),
        &EvalMesh::from_mesh(candidate),
        &CompareOptions {
            samples: 20_000,
            ..CompareOptions::default()
        },
    )
    .hausdorff
}

#[test]
fn tiny_far_part_disappears_before_the_big_one_loses_detail() {
    // A big sphere, a box touching it, and a tiny sphere far away: at 20%
    // of the scene, the tiny sphere's triangles are worth nothing and go
    // first; the big sphere keeps more than 20% of its own.
    let big = bumpy_sphere(12);
    let mut plate = common::grid_box([1.0, -0.5, -0.5], [1.5, 0.5, 0.5], 6);
    plate = wildlod_mesh::shapes::triangulate(&plate);
    let tiny = bumpy_sphere(8);
    let s = scene(
        vec![big.clone(), plate, tiny],
        &[
            (0, IDENTITY),
            (1, IDENTITY),
            (2, translate_scale([20.0, 0.0, 0.0], 0.002)),
        ],
    );
    let input: usize = s.meshes.iter().map(Mesh::triangle_count).sum();
    let (lod, report) = simplify_scene(&s, &ratio(0.2)).unwrap();
    let target = (input as f64 * 0.2).round() as usize;
    assert_eq!(report.target_triangles, target);
    assert!(
        report.output_triangles.abs_diff(target) <= 1,
        "{} triangles for a target of {target}",
        report.output_triangles
    );
    let total: usize = lod.meshes.iter().map(Mesh::triangle_count).sum();
    assert_eq!(total, report.output_triangles);
    assert_eq!(report.groups.len(), 1, "one complex for the whole scene");
    assert!(
        report.meshes[2].removed,
        "the tiny part should go: {report:?}"
    );
    assert_eq!(report.removed(), vec![2]);
    assert!(lod.meshes[2].faces.is_empty());
    // The big sphere against the same sphere simplified alone to 20%.
    let (alone, _) = simplify_mesh(&big, &ratio(0.2)).unwrap();
    assert!(
        lod.meshes[0].triangle_count() > alone.triangle_count(),
        "scene {} vs alone {}",
        lod.meshes[0].triangle_count(),
        alone.triangle_count()
    );
    let in_scene = hausdorff(&big, &lod.meshes[0]);
    let by_itself = hausdorff(&big, &alone);
    assert!(
        in_scene < by_itself,
        "big sphere error {in_scene} in the scene vs {by_itself} alone"
    );
    // The reported world error bounds what happened to every part.
    assert!(report.world_error > 0.0 && report.world_error.is_finite());
    assert!((report.error - report.world_error / report.diagonal).abs() < 1e-12);
}

#[test]
fn meshes_come_back_in_their_own_space() {
    // A sphere moved, scaled and mirrored by its node: at ratio 1 nothing
    // collapses and every position must come back bit for bit, in the
    // mesh's own space (not the world space the scene was simplified in).
    let sphere = bumpy_sphere(6);
    let mut m = translate_scale([3.0, -2.0, 7.0], 2.5);
    m[0] = -2.5;
    let s = scene(vec![sphere.clone()], &[(0, m)]);
    let (lod, report) = simplify_scene(&s, &ratio(1.0)).unwrap();
    assert_eq!(report.output_triangles, report.input_triangles);
    let mut a = sphere.positions.clone();
    let mut b = lod.meshes[0].positions.clone();
    let key = |p: &[f32; 3]| p.map(f32::to_bits);
    a.sort_by_key(key);
    b.sort_by_key(key);
    assert_eq!(a, b);
    // Simplified, the output stays near the input in mesh space.
    let (lod, _) = simplify_scene(&s, &ratio(0.3)).unwrap();
    let d = hausdorff(&sphere, &lod.meshes[0]);
    assert!(d < 0.05, "output is {d} away from the input in mesh space");
}

#[test]
fn a_georeferenced_scene_simplifies_as_it_would_at_the_origin() {
    // Two spheres placed four million units from the origin (a survey
    // grid's coordinates), where f32 steps by a quarter of a unit: merged
    // in world space they were rounded to that grid. About their own
    // point, each comes out bit for bit as the same pair near the origin.
    let sphere = bumpy_sphere(12);
    let far = 4.0e6;
    let at = |t: [f32; 3]| translate_scale(t, 1.0);
    for r in [0.5, 0.1] {
        let near = scene(
            vec![sphere.clone(), sphere.clone()],
            &[(0, at([0.0, 0.0, 0.0])), (1, at([3.0, 0.0, 0.0]))],
        );
        let away = scene(
            vec![sphere.clone(), sphere.clone()],
            &[(0, at([0.0, far, 0.0])), (1, at([3.0, far, 0.0]))],
        );
        let (a, ra) = simplify_scene(&near, &ratio(r)).unwrap();
        let (b, rb) = simplify_scene(&away, &ratio(r)).unwrap();
        assert_eq!(ra.output_triangles, rb.output_triangles);
        for (x, y) in a.meshes.iter().zip(&b.meshes) {
            assert_eq!(x.positions, y.positions, "ratio {r}");
            assert_eq!(x.faces, y.faces, "ratio {r}");
        }
    }
}

#[test]
fn a_budget_counts_the_triangles_the_scene_draws() {
    // A sphere shown by four nodes beside another shown once, both the
    // same size: the scene draws five spheres. A budget of 1000 triangles
    // is met by what a renderer draws, not by what the file stores (which
    // let it draw 2.5 times the budget).
    let sphere = bumpy_sphere(10);
    let s = scene(
        vec![sphere.clone(), sphere.clone()],
        &[
            (0, translate_scale([0.0, 0.0, 0.0], 1.0)),
            (0, translate_scale([10.0, 0.0, 0.0], 1.0)),
            (0, translate_scale([20.0, 0.0, 0.0], 1.0)),
            (0, translate_scale([30.0, 0.0, 0.0], 1.0)),
            (1, translate_scale([0.0, 10.0, 0.0], 1.0)),
        ],
    );
    let options = Options {
        target: Target {
            ratio: None,
            triangles: Some(1000),
            error: None,
        },
        ..Options::default()
    };
    let (lod, report) = simplify_scene(&s, &options).unwrap();
    assert_eq!(report.input_triangles, 5 * sphere.triangle_count());
    let (a, b) = (
        lod.meshes[0].triangle_count(),
        lod.meshes[1].triangle_count(),
    );
    let drawn = 4 * a + b;
    assert_eq!(report.output_triangles, drawn);
    assert!(
        (990..=1000).contains(&drawn),
        "draws {drawn} triangles ({a} × 4 + {b}) for a budget of 1000"
    );
    // Per stored mesh, the counts stay the file's.
    assert_eq!(report.meshes[0].output_triangles, a);
    assert_eq!(report.meshes[0].input_triangles, sphere.triangle_count());
}

#[test]
fn instanced_mesh_is_simplified_once_and_weighted_by_its_largest_instance() {
    // Mesh 0 is shown twice, mesh 1 (the same shape) once at scale 3, far
    // apart. With mesh 0's instances at scales 1 and 10, its largest
    // instance is the largest object: it keeps more triangles than mesh 1.
    // With instances at 1 and 2, it is smaller and keeps fewer. (Summing
    // or averaging the instances would order the two cases the same way.)
    let sphere = bumpy_sphere(10);
    let run = |small: f32, large: f32| {
        let s = scene(
            vec![sphere.clone(), sphere.clone()],
            &[
                (0, translate_scale([0.0, 0.0, 0.0], small)),
                (0, translate_scale([100.0, 0.0, 0.0], large)),
                (1, translate_scale([0.0, 100.0, 0.0], 3.0)),
            ],
        );
        let (lod, report) = simplify_scene(&s, &ratio(0.2)).unwrap();
        assert_eq!(lod.meshes.len(), 2, "the instanced mesh is stored once");
        assert_eq!(lod.nodes[0].mesh, Some(0));
        assert_eq!(lod.nodes[1].mesh, Some(0));
        // Drawn triangles: mesh 0 twice, mesh 1 once.
        assert_eq!(report.input_triangles, 3 * sphere.triangle_count());
        let (a, b) = (
            lod.meshes[0].triangle_count(),
            lod.meshes[1].triangle_count(),
        );
        assert_eq!(report.output_triangles, 2 * a + b);
        assert!(report.output_triangles <= report.target_triangles + 2);
        (a, b)
    };
    let (a, b) = run(1.0, 10.0);
    assert!(a > b, "largest instance 10 vs 3: {a} vs {b} triangles");
    let (a, b) = run(1.0, 2.0);
    assert!(a < b, "largest instance 2 vs 3: {a} vs {b} triangles");
}

#[test]
fn groups_that_cannot_merge_stop_at_one_world_error() {
    // A skinned mesh (bind space) and a static one cannot share a complex:
    // the budget is split so both stop near the same world-space error,
    // and the total is the scene's target.
    let mut skinned = bumpy_sphere(10);
    let corners = skinned.faces.corner_count();
    skinned.skinning = Some(Skinning {
        influences: 4,
        joints: vec![0, 0, 0, 0],
        weights: vec![1.0, 0.0, 0.0, 0.0],
        indices: vec![0; corners],
        weight_format: Default::default(),
        joint_format: wildlod_mesh::ComponentFormat::U8,
    });
    // The static sphere is 4 times larger: it deserves more triangles.
    let big = bumpy_sphere(10);
    let s = scene(
        vec![skinned, big],
        &[(0, IDENTITY), (1, translate_scale([10.0, 0.0, 0.0], 4.0))],
    );
    let (lod, report) = simplify_scene(&s, &ratio(0.25)).unwrap();
    assert_eq!(report.groups.len(), 2);
    assert!(report.common_threshold);
    assert!(matches!(report.groups[0].space, GroupSpace::Skinned { .. }));
    assert_eq!(report.groups[1].space, GroupSpace::World);
    assert!(
        report.output_triangles.abs_diff(report.target_triangles) <= 2,
        "{} for {}",
        report.output_triangles,
        report.target_triangles
    );
    assert!(lod.meshes[0].skinning.is_some());
    assert!(lod.meshes[1].triangle_count() > lod.meshes[0].triangle_count());
    // Same world error: within a factor of two of each other (one collapse
    // is the granularity).
    let (e0, e1) = (report.groups[0].world_error, report.groups[1].world_error);
    assert!(e0 > 0.0 && e1 > 0.0);
    assert!(
        e0 / e1 < 2.0 && e1 / e0 < 2.0,
        "world errors {e0} and {e1} should be close"
    );
}

#[test]
fn error_target_is_relative_to_the_whole_scene() {
    // --error on a scene of a big and a small sphere: every group keeps its
    // world error under the limit times the scene diagonal.
    let s = scene(
        vec![bumpy_sphere(10), bumpy_sphere(10)],
        &[(0, IDENTITY), (1, translate_scale([5.0, 0.0, 0.0], 0.1))],
    );
    let limit = 0.002;
    let (_, report) = simplify_scene(
        &s,
        &target(Target {
            error: Some(limit),
            ..Target::default()
        }),
    )
    .unwrap();
    assert!(report.output_triangles < report.input_triangles);
    assert!(
        report.error <= limit * (1.0 + 1e-9),
        "error {} over the limit {limit}",
        report.error
    );
}

#[test]
fn twins_of_a_blended_material_stay_those_of_an_opaque_one_go() {
    // A closed sphere written with every face twice, once each way, with
    // its material opaque or alpha-blended (its inside shows through).
    let single = bumpy_sphere(4);
    let n = single.faces.len();
    let mut faces = single.faces.clone();
    for f in single.faces.iter() {
        let back: Vec<u32> = f.iter().rev().copied().collect();
        faces.push(&back);
    }
    let mut double = Mesh::from_polygons(single.positions.clone(), faces);
    double.parts[0].material = Some(0);
    for (mode, dropped) in [
        (wildlod_mesh::AlphaMode::Opaque, n),
        (wildlod_mesh::AlphaMode::Blend, 0),
    ] {
        let mut s = Scene::from_mesh(double.clone());
        s.materials = vec![wildlod_mesh::Material {
            alpha_mode: mode,
            ..wildlod_mesh::Material::default()
        }];
        let (_, report) = simplify_scene(&s, &Options::default()).unwrap();
        let hidden: usize = report.groups.iter().map(|g| g.report.hidden_twins).sum();
        assert_eq!(hidden, dropped, "{mode:?}");
    }
}

#[test]
fn instance_counts_must_name_every_face() {
    // A caller's per-face counts that do not match the faces are refused
    // by name, not read past the end or ignored.
    let sphere = bumpy_sphere(4);
    let mut options = Options::default();
    options.data.face_instances = vec![2; 3];
    let err = simplify_mesh(&sphere, &options).unwrap_err();
    assert!(
        matches!(err, wildlod_simplify::Error::InstanceCount { counts: 3, faces } if faces == sphere.faces.len()),
        "{err}"
    );
    // One count per face is accepted and counts in the report.
    let mut options = Options::default();
    options.data.face_instances = vec![2; sphere.faces.len()];
    let (_, report) = simplify_mesh(&sphere, &options).unwrap();
    assert_eq!(report.input_triangles, 2 * sphere.triangle_count());
}
