//! The defaults on files nobody tuned them for (issue 31): generated
//! scenes unlike the corpus (architecture, CAD, a city block), each
//! simplified with the default options and with attributes that fit but do
//! not steer ("geometry only": every attribute weight 0).
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_mesh::{Scene, Semantic};
use wildlod_simplify::{simplify_scene, NormalMode, Options, SceneReport, Target};
use wildlod_testkit::scenes;

mod common;
use common::assert_within_geometry_bound;

fn at_ratio(ratio: f64) -> Options {
    Options {
        target: Target {
            ratio: Some(ratio),
            ..Target::default()
        },
        ..Options::default()
    }
}

/// Every attribute weight 0: attributes are fitted, nothing they say
/// steers a collapse.
fn geometry_only(mut o: Options) -> Options {
    o.attributes.tex_coord_weight = 0.0;
    o.attributes.normal_weight = 0.0;
    o.attributes.color_weight = 0.0;
    o.attributes.skin_weight = 0.0;
    o
}

fn measure(input: &Scene, output: &Scene) -> Comparison {
    let images = vec![None; input.textures.len()];
    let out_images = vec![None; output.textures.len()];
    compare(
        &EvalMesh::from_scene(input, &images),
        &EvalMesh::from_scene(output, &out_images),
        &CompareOptions {
            samples: 100_000,
            ..CompareOptions::default()
        },
    )
}

/// The default and geometry-only outputs and their distances to the input.
fn both(scene: &Scene, options: &Options) -> [(Scene, SceneReport, Comparison); 2] {
    [options.clone(), geometry_only(options.clone())].map(|o| {
        let (out, report) = simplify_scene(scene, &o).unwrap();
        assert!(
            report.output_triangles <= report.target_triangles + 1,
            "{report:?}"
        );
        let c = measure(scene, &out);
        (out, report, c)
    })
}

/// Area of the faces of material `m` in a scene's meshes (stored once).
fn material_area(scene: &Scene, m: u32) -> f64 {
    let mut area = 0.0;
    for mesh in &scene.meshes {
        for (f, face) in mesh.faces.iter().enumerate() {
            let part = &mesh.parts[mesh.face_parts[f] as usize];
            if part.material != Some(m) {
                continue;
            }
            let p = |k: usize| glam::DVec3::from(mesh.positions[face[k] as usize].map(f64::from));
            for k in 1..face.len() - 1 {
                area += 0.5 * (p(k) - p(0)).cross(p(k + 1) - p(0)).length();
            }
        }
    }
    area
}

#[test]
fn an_untextured_house_keeps_its_ground_and_its_shape() {
    // UVs everywhere, no texture reads them: they steer nothing, and the
    // 2-triangle ground plane, the largest part, stays whole.
    let house = scenes::house(false);
    let [(out, _, d), (_, _, g)] = both(&house, &at_ratio(0.1));
    assert_within_geometry_bound("house", &d, &g);
    let ground = material_area(&out, 0);
    assert!(
        (ground - 3600.0).abs() < 1.0,
        "the ground's area is {ground} m², not 3600"
    );
}

#[test]
fn a_house_with_textured_walls_steers_there_and_keeps_its_ground() {
    let house = scenes::house(true);
    let [(out, report, d), (_, _, g)] = both(&house, &at_ratio(0.1));
    assert_within_geometry_bound("textured house", &d, &g);
    // The wall texture's UVs steered (the run measured its steering).
    assert!(
        report.groups.iter().any(|r| r.report.steering.is_some()),
        "{report:?}"
    );
    let ground = material_area(&out, 0);
    assert!(
        (ground - 3600.0).abs() < 1.0,
        "the ground's area is {ground} m², not 3600"
    );
}

#[test]
fn a_filleted_cad_part_with_per_face_normals_keeps_its_shape() {
    // Every B-rep face its own normals: normal seams at every crease. At
    // half its triangles, its distance stays that of geometry alone.
    let block = scenes::filleted_block();
    let [(_, _, d), (_, _, g)] = both(&block, &at_ratio(0.5));
    assert_within_geometry_bound("filleted block", &d, &g);
}

#[test]
fn tangent_quadrics_move_the_surface_no_farther_than_attributes_may() {
    // Knodt's tangent quadrics trade distance for regular spacing; like an
    // attribute they may cost at most the geometric bound against a run
    // without them (and without steering).
    for (name, scene, ratio) in [
        ("house", scenes::house(false), 0.1),
        ("filleted block", scenes::filleted_block(), 0.5),
        ("city block", scenes::city_block(), 0.1),
    ] {
        let mut tangent = at_ratio(ratio);
        tangent.metric.tangent_weight = 1.0 / 3.0;
        let (out, _) = simplify_scene(&scene, &tangent).unwrap();
        let (plain, _) = simplify_scene(&scene, &geometry_only(at_ratio(ratio))).unwrap();
        assert_within_geometry_bound(name, &measure(&scene, &out), &measure(&scene, &plain));
    }
}

/// Output normal values farther than 75° from every face they shade.
fn stray_normals(scene: &Scene) -> usize {
    let cos = 75f64.to_radians().cos();
    let mut stray = 0;
    for mesh in &scene.meshes {
        let Some(normals) = mesh
            .attributes
            .iter()
            .find(|a| a.semantic == Semantic::Normal && a.components == 3)
        else {
            continue;
        };
        let mut agrees = vec![false; normals.value_count()];
        let mut used = vec![false; normals.value_count()];
        let mut corner = 0;
        for face in mesh.faces.iter() {
            let p = |k: usize| glam::DVec3::from(mesh.positions[face[k] as usize].map(f64::from));
            let mut n = glam::DVec3::ZERO;
            for k in 0..face.len() {
                n += p(k).cross(p((k + 1) % face.len()));
            }
            for _ in face {
                let i = normals.indices[corner];
                corner += 1;
                if i == wildlod_mesh::ABSENT {
                    continue;
                }
                used[i as usize] = true;
                let v = normals.value(i);
                let v = glam::DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
                if n.length() > 0.0 && v.dot(n) >= cos * n.length() * v.length() {
                    agrees[i as usize] = true;
                }
            }
        }
        stray += (0..agrees.len()).filter(|&i| used[i] && !agrees[i]).count();
    }
    stray
}

#[test]
fn a_city_blocks_normals_face_their_faces_fitted_or_recomputed() {
    // Recessed windows flattened into a facade merge their normals into
    // the facade's: a fitted normal can then point along the wall.
    let city = scenes::city_block();
    for mode in [NormalMode::Fit, NormalMode::Recompute] {
        let mut o = at_ratio(0.1);
        o.attributes.normals = mode;
        let (out, report) = simplify_scene(&city, &o).unwrap();
        assert!(report.output_triangles <= report.target_triangles + 1);
        assert_eq!(stray_normals(&out), 0, "{mode:?}");
    }
}

#[test]
fn one_far_vertex_does_not_make_the_rest_of_the_error_vanish() {
    // A terrain with three heights at -1e30, as broken exporters write
    // them, against the same terrain without them: the error reported is
    // that of the terrain, and the far vertices are named.
    let with = scenes::outlier_terrain(100, 3);
    let without = scenes::outlier_terrain(100, 0);
    let (_, r_with) = simplify_scene(&with, &at_ratio(0.1)).unwrap();
    let (_, r_without) = simplify_scene(&without, &at_ratio(0.1)).unwrap();
    assert!(r_without.error > 0.0, "{r_without:?}");
    let ratio = r_with.error / r_without.error;
    assert!(
        (0.5..=2.0).contains(&ratio),
        "error {:e} with the outliers, {:e} without",
        r_with.error,
        r_without.error
    );
    assert!((0.5..=2.0).contains(&(r_with.world_error / r_without.world_error)));
    let named: Vec<u32> = r_with
        .groups
        .iter()
        .flat_map(|g| g.report.outliers.iter().copied())
        .collect();
    let mut expected = scenes::terrain_outliers(100, 3);
    expected.sort_unstable();
    assert_eq!(named, expected);
    assert!(r_without
        .groups
        .iter()
        .all(|g| g.report.outliers.is_empty()));
}

/// Decision 3: flat stays flat. A flat open tiling of triangles and quads
/// (z = 0 exactly, a ragged border and a hole) at 10% and 1%, quads kept
/// and not: every output vertex in the plane and every output border
/// vertex on the input's border, to 1e-9 of the diagonal (the output may
/// not cover area the input does not), no face folded over, and without
/// quads every output vertex an input one (every point of the plane costs
/// the same, so a vertex stays at an endpoint). The same with the
/// collapse history recorded, as re-baking records it.
#[test]
fn a_flat_tiling_stays_in_its_plane_and_inside_its_border() {
    use wildlod_simplify::QuadMode;
    let scene = scenes::flat_tiling(7);
    let input = &scene.meshes[0];
    let border = scenes::border_segments(input);
    let diagonal = {
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for p in &input.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(f64::from(p[k]));
                hi[k] = hi[k].max(f64::from(p[k]));
            }
        }
        (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
    };
    let mut failures = Vec::new();
    for (quad_mode, history) in [
        (QuadMode::default(), false),
        (QuadMode::Never, false),
        (QuadMode::default(), true),
        (QuadMode::Never, true),
    ] {
        for ratio in [0.1, 0.01] {
            let mut o = at_ratio(ratio);
            o.quad.mode = quad_mode;
            // Re-baking records the history (mesh by mesh) and maps
            // texels through it.
            o.record.history = history;
            let out = if history {
                wildlod_simplify::simplify_mesh(input, &o).unwrap().0
            } else {
                simplify_scene(&scene, &o).unwrap().0.meshes.remove(0)
            };
            let mesh = &out;
            let off_plane = mesh
                .positions
                .iter()
                .map(|p| f64::from(p[2]).abs())
                .fold(0.0, f64::max);
            let off_border = scenes::border_segments(mesh)
                .iter()
                .flatten()
                .map(|p| scenes::distance_to_segments(p.map(f64::from), &border))
                .fold(0.0, f64::max);
            // No face folded over: every face with area winds like the
            // input's (the tiling's faces all face +z).
            let signed = |m: &wildlod_mesh::Mesh, f: usize| {
                let c = m.faces.face(f);
                (0..c.len())
                    .map(|k| {
                        let (a, b) = (
                            m.positions[c[k] as usize],
                            m.positions[c[(k + 1) % c.len()] as usize],
                        );
                        f64::from(a[0]) * f64::from(b[1]) - f64::from(b[0]) * f64::from(a[1])
                    })
                    .sum::<f64>()
            };
            let up = signed(input, 0).signum();
            let folded = (0..mesh.faces.len())
                .filter(|&f| signed(mesh, f) * up < -1e-12)
                .count();
            if folded > 0 {
                failures.push(format!(
                    "{quad_mode:?}, history {history}, at {ratio}: {folded} faces folded over"
                ));
            }
            let input_at: std::collections::HashSet<[u32; 3]> = input
                .positions
                .iter()
                .map(|p| p.map(f32::to_bits))
                .collect();
            let moved = mesh
                .positions
                .iter()
                .filter(|p| !input_at.contains(&p.map(f32::to_bits)))
                .count();
            eprintln!("{quad_mode:?}, history {history}, at {ratio}: off the plane {off_plane:e}, off the border {off_border:e}, {moved} of {} vertices not the input's", mesh.positions.len());
            // Every point of the plane costs the same, so without quads
            // (whose regularization places vertices) a vertex stays at an
            // endpoint: the output's vertices are the input's.
            if quad_mode == QuadMode::Never && moved > 0 {
                failures.push(format!(
                    "{quad_mode:?}, history {history}, at {ratio}: {moved} vertices not the input's"
                ));
            }
            if off_plane > 1e-9 * diagonal || off_border > 1e-9 * diagonal {
                failures.push(format!(
                    "{quad_mode:?}, history {history}, at {ratio}: off the plane {off_plane:e}, off the border {off_border:e} (diagonal {diagonal})"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Decision 3, whatever steers: a box of flat panels whose smooth normals
/// turn across every ramp and edge, at 50% and 10%. The normals' joint
/// placement may slide a vertex within its planes but not off them: every
/// output vertex lies on the input's surface to the rounding of its
/// coordinates (positions are f32: a point of a ramp's slanted plane is
/// one unit in the last place off it; 1e-9 holds on axis-aligned planes,
/// as the flat tiling's test checks).
/// Before the joint placement lost its invisible allowance, a change of
/// order elsewhere (the current-face term) let it lift vertices by up to
/// 4e-5 of the diagonal on the holdout's panel crate.
#[test]
fn a_box_of_flat_panels_with_smooth_normals_stays_on_its_planes() {
    use glam::DVec3;
    use wildlod_geometry::point_triangle_distance2;
    let scene = scenes::panel_box(24);
    let input = &scene.meshes[0];
    let p = |m: &wildlod_mesh::Mesh, v: u32| DVec3::from(m.positions[v as usize].map(f64::from));
    let triangles: Vec<[DVec3; 3]> = input
        .faces
        .iter()
        .map(|f| [p(input, f[0]), p(input, f[1]), p(input, f[2])])
        .collect();
    // Four units in the last place of the largest coordinate (1.04).
    let rounding = 4.0 * f64::from(f32::EPSILON) * 1.04;
    let mut failures = Vec::new();
    for ratio in [0.5, 0.1] {
        let (out, report) = simplify_scene(&scene, &at_ratio(ratio)).unwrap();
        assert!(report.output_triangles <= report.target_triangles + 1);
        let mesh = &out.meshes[0];
        let off = (0..mesh.positions.len() as u32)
            .map(|v| {
                let q = p(mesh, v);
                triangles
                    .iter()
                    .map(|t| point_triangle_distance2(q, t[0], t[1], t[2]))
                    .fold(f64::INFINITY, f64::min)
                    .sqrt()
            })
            .fold(0.0, f64::max);
        eprintln!("at {ratio}: farthest vertex {off:e} off the input");
        if off > rounding {
            failures.push(format!("at {ratio}: a vertex {off:e} off the input"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Flat stays flat where every edge is a crease: a voxel torus (every face
/// axis-aligned, staircase outlines) at 50% loses only coplanar faces, as
/// meshoptimizer, Blender and MeshLab do, so its output lies on its input
/// to rounding, whatever the order of its faces. A straight run collapsed
/// onto a line leaves faces without area, which the flip guard cannot
/// judge; given area again across a step's corner they cut it (6 of these
/// 24 orders at 1.6e-3 to 6.7e-3 of the diagonal before collapses were
/// refused to flatten faces).
#[test]
fn a_voxel_shape_at_half_loses_only_coplanar_faces() {
    let mut failures = Vec::new();
    for seed in 0..24 {
        let scene = scenes::voxel_torus(seed);
        let (out, report) = simplify_scene(&scene, &at_ratio(0.5)).unwrap();
        assert!(
            report.output_triangles <= report.target_triangles + 1,
            "{report:?}"
        );
        let d = measure(&scene, &out);
        eprintln!("voxel torus, order {seed}: Hausdorff {:e}", d.hausdorff);
        if d.hausdorff > 1e-6 {
            failures.push(format!(
                "order {seed}: Hausdorff {:e} of the diagonal",
                d.hausdorff
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Attributes that steer nothing leave the surface as it is without them:
/// a geometry-only run (every weight 0) of a scan-like sphere with smooth
/// normals gives the surface the same run gives on its positions alone,
/// to the last digit of its distances.
/// Before Hoppe's joint placement was kept to attributes that steer, the
/// zero appearance quadric still placed vertices by the regularized solve,
/// allowed 1e-4 of the diagonal off the planes' point: CesiumMan at 50%
/// had 1.4× the Hausdorff and 1.6× the Chamfer distance of its own
/// positions, and the steering check measured defaults against that (this
/// sphere: Chamfer 2% above, Hausdorff 3% below).
#[test]
fn normals_that_steer_nothing_leave_the_surface_as_without_them() {
    let with = scenes::smooth_bumpy_sphere(24);
    let mut without = with.clone();
    without.meshes[0].attributes.clear();
    let mut failures = Vec::new();
    for ratio in [0.5, 0.1] {
        let o = geometry_only(at_ratio(ratio));
        let [a, b] = [&with, &without].map(|s| {
            let (out, report) = simplify_scene(s, &o).unwrap();
            assert!(report.output_triangles <= report.target_triangles + 1);
            measure(s, &out)
        });
        eprintln!(
            "at {ratio}: with normals H {:e} C {:e}, positions alone H {:e} C {:e}",
            a.hausdorff, a.chamfer_mean, b.hausdorff, b.chamfer_mean
        );
        if a.hausdorff != b.hausdorff || a.chamfer_mean != b.chamfer_mean {
            failures.push(format!(
                "at {ratio}: H {:e} C {:e} against H {:e} C {:e}",
                a.hausdorff, a.chamfer_mean, b.hausdorff, b.chamfer_mean
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
