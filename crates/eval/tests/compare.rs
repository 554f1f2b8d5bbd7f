//! `compare` against hand-computed values on generated meshes.

use std::f64::consts::SQRT_2;

use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_mesh::{shapes, Faces, Image, ImageSource, Material, Mesh, Scene, Texture, TextureRef};

fn moved(mut m: Mesh, f: impl Fn([f32; 3]) -> [f32; 3]) -> Mesh {
    for p in &mut m.positions {
        *p = f(*p);
    }
    m
}

fn run(a: &Mesh, b: &Mesh, options: &CompareOptions) -> Comparison {
    compare(&EvalMesh::from_mesh(a), &EvalMesh::from_mesh(b), options)
}

fn close(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs().max(1e-300)
}

/// Every float of the result, for checks that none is NaN.
fn floats(c: &Comparison) -> Vec<f64> {
    let mut v = vec![
        c.diagonal,
        c.hausdorff,
        c.hausdorff_ref_to_cand,
        c.hausdorff_cand_to_ref,
        c.chamfer_mean,
        c.chamfer_mean_ref_to_cand,
        c.chamfer_mean_cand_to_ref,
        c.chamfer_squared,
        c.chamfer_squared_ref_to_cand,
        c.chamfer_squared_cand_to_ref,
    ];
    v.extend(c.quad_ratio);
    v.extend(c.texture_chamfer);
    v.extend(c.texture_chamfer_ref_to_cand);
    v.extend(c.texture_chamfer_cand_to_ref);
    v
}

#[test]
fn identical_meshes_are_zero_apart() {
    let t = shapes::torus(24, 12, 2.0, 0.5);
    let c = run(&t, &t, &CompareOptions::default());
    for x in floats(&c).iter().take(10).skip(1) {
        assert!(*x < 1e-12, "{c:?}");
    }
    assert_eq!(c.quad_ratio, Some(1.0));
    assert_eq!(c.reference, c.candidate);
    assert_eq!(c.vertex_samples_reference, 24 * 12);
}

#[test]
fn plane_shifted_along_its_normal_is_d_apart_everywhere() {
    // The unit square's diagonal is √2, so d = 0.125 reads d / √2.
    let d = 0.125f32;
    let grid = shapes::quad_grid(4, 4);
    let lifted = moved(grid.clone(), |p| [p[0], p[1], p[2] + d]);
    let c = run(&grid, &lifted, &CompareOptions::default());
    let dn = f64::from(d) / SQRT_2;
    assert!(close(c.diagonal, SQRT_2, 1e-12));
    for x in [
        c.hausdorff,
        c.hausdorff_ref_to_cand,
        c.hausdorff_cand_to_ref,
    ] {
        assert!(close(x, dn, 1e-12), "{c:?}");
    }
    for x in [
        c.chamfer_mean,
        c.chamfer_mean_ref_to_cand,
        c.chamfer_mean_cand_to_ref,
    ] {
        assert!(close(x, dn, 1e-12), "{c:?}");
    }
    for x in [
        c.chamfer_squared,
        c.chamfer_squared_ref_to_cand,
        c.chamfer_squared_cand_to_ref,
    ] {
        assert!(close(x, dn * dn, 1e-12), "{c:?}");
    }
}

#[test]
fn small_square_inside_large_square_differs_by_direction() {
    // Reference [0, 1]², candidate [−1, 2]², same plane. Every reference
    // point lies on the candidate. From the candidate: 0 on the middle
    // square, |x| on the four edge strips, √(x² + y²) on the four corner
    // squares; the farthest point is a corner, √2 away.
    let small = shapes::quad_grid(1, 1);
    let large = moved(shapes::quad_grid(3, 3), |p| {
        [3.0 * p[0] - 1.0, 3.0 * p[1] - 1.0, 0.0]
    });
    let c = run(&small, &large, &CompareOptions::default());
    assert!(c.hausdorff_ref_to_cand < 1e-12);
    assert!(c.chamfer_mean_ref_to_cand < 1e-12);
    // Normalized by the reference's diagonal √2.
    assert!(close(c.hausdorff_cand_to_ref, 1.0, 1e-12), "{c:?}");
    assert!(close(c.hausdorff, 1.0, 1e-12));
    // Mean over the corner square of √(x² + y²) is (√2 + ln(1 + √2)) / 3.
    let corner = (SQRT_2 + (1.0 + SQRT_2).ln()) / 3.0;
    let mean = (4.0 * 0.5 + 4.0 * corner) / 9.0;
    assert!(
        close(c.chamfer_mean_cand_to_ref, mean / SQRT_2, 0.01),
        "{c:?}"
    );
    assert!(close(c.chamfer_mean, 0.5 * mean / SQRT_2, 0.01));
    // Mean of x² on a strip is 1/3, of x² + y² on a corner 2/3: 4/9 in all.
    let mean2 = (4.0 / 3.0 + 8.0 / 3.0) / 9.0;
    assert!(
        close(c.chamfer_squared_cand_to_ref, mean2 / 2.0, 0.01),
        "{c:?}"
    );
    assert!(close(c.chamfer_squared, mean2 / 4.0, 0.01));
}

#[test]
fn far_triangle_counts_in_one_direction_by_its_area() {
    // Candidate = reference square + a triangle of area 1/2 floating 5
    // above it: a third of the candidate's area is 5 away.
    let square = shapes::quad_grid(2, 2);
    let mut extra = square.clone();
    let base = extra.positions.len() as u32;
    extra
        .positions
        .extend([[0.0, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 1.0, 5.0]]);
    extra.faces.push(&[base, base + 1, base + 2]);
    extra.face_parts.push(0);
    extra.attributes.clear();
    let c = run(&square, &extra, &CompareOptions::default());
    assert!(c.hausdorff_ref_to_cand < 1e-12);
    assert!(close(c.hausdorff_cand_to_ref, 5.0 / SQRT_2, 1e-12));
    assert!(
        close(c.chamfer_mean_cand_to_ref, 5.0 / 3.0 / SQRT_2, 0.02),
        "{c:?}"
    );
    assert!(
        close(c.chamfer_squared_cand_to_ref, 25.0 / 3.0 / 2.0, 0.02),
        "{c:?}"
    );
    assert_eq!(c.candidate.components, 2);
    assert_eq!((c.candidate.quads, c.candidate.triangles), (4, 1));
}

fn octahedron() -> Mesh {
    let p = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut idx = Vec::new();
    for x in [0u32, 1] {
        for y in [2u32, 3] {
            for z in [4u32, 5] {
                idx.extend([x, y, z]);
            }
        }
    }
    Mesh::from_triangles(p, &idx)
}

#[test]
fn sphere_against_inscribed_octahedron_has_the_known_gap() {
    // The sphere points (±1, ±1, ±1)/√3 are 1 − 1/√3 from the octahedron's
    // faces; they are vertices of the quad sphere, which lies inside the
    // unit sphere, so no tessellated point is farther. The sphere's
    // diagonal is 2√3 (an even n puts vertices on the axes).
    let sphere = shapes::quad_sphere(32);
    let c = run(&sphere, &octahedron(), &CompareOptions::default());
    let s3 = 3f64.sqrt();
    let gap = (1.0 - 1.0 / s3) / (2.0 * s3);
    assert!(close(c.diagonal, 2.0 * s3, 1e-6));
    assert!(close(c.hausdorff_ref_to_cand, gap, 1e-6), "{c:?}");
    assert!(close(c.hausdorff, gap, 1e-6));
    // The octahedron's face centers are 1 − 1/√3 from the true sphere; the
    // tessellation and the sampling may only bring that down a little.
    assert!(c.hausdorff_cand_to_ref <= gap * (1.0 + 1e-6));
    assert!(c.hausdorff_cand_to_ref > 0.99 * gap, "{c:?}");
    assert_eq!(c.quad_ratio, Some(0.0), "the octahedron has no quad");
}

#[test]
fn vertex_samples_catch_a_spike_that_area_samples_miss() {
    let grid = shapes::quad_grid(8, 8);
    let mut spiked = grid.clone();
    // Raise the middle vertex (4, 4) by 2: a thin spike of small area.
    spiked.positions[4 * 9 + 4][2] = 2.0;
    let options = CompareOptions {
        samples: 50,
        ..CompareOptions::default()
    };
    let c = run(&grid, &spiked, &options);
    assert!(close(c.hausdorff_cand_to_ref, 2.0 / SQRT_2, 1e-12), "{c:?}");
    assert_eq!(c.vertex_samples_candidate, 81);
}

#[test]
fn quad_ratio_of_a_partially_triangulated_copy() {
    // 2 × 2 quads (8 triangles after triangulation). The copy splits quad 0
    // into two triangles: (3 / 8) / (4 / 8) = 3/4.
    let grid = shapes::quad_grid(2, 2);
    let mut faces = Faces::new();
    for (f, face) in grid.faces.iter().enumerate() {
        if f == 0 {
            faces.push(&[face[0], face[1], face[2]]);
            faces.push(&[face[0], face[2], face[3]]);
        } else {
            faces.push(face);
        }
    }
    let split = Mesh::from_polygons(grid.positions.clone(), faces);
    let c = run(&grid, &split, &CompareOptions::default());
    assert_eq!(c.quad_ratio, Some(0.75));
    assert!(c.hausdorff < 1e-12);
    assert_eq!(c.candidate.triangulated, 8);
    // A reduced copy: one quad and one triangle, 3 triangles in all:
    // (1 / 3) / (4 / 8) = 2/3.
    let mut faces = Faces::new();
    faces.push(&[0, 2, 8, 6]);
    faces.push(&[0, 2, 4]);
    let reduced = Mesh::from_polygons(grid.positions.clone(), faces);
    let q = run(&grid, &reduced, &CompareOptions::default()).quad_ratio;
    assert!(close(q.expect("a ratio"), 2.0 / 3.0, 1e-15));
    // No quad in the reference: no ratio.
    assert_eq!(
        run(&octahedron(), &grid, &CompareOptions::default()).quad_ratio,
        None
    );
}

/// A 4 × 4 grid whose single material uses texture 0 through UV set 0.
fn textured_grid(factor: [f32; 4]) -> Scene {
    let mut mesh = shapes::quad_grid(4, 4);
    mesh.parts[0].material = Some(0);
    let mut s = Scene::from_mesh(mesh);
    s.materials.push(Material {
        base_color: factor,
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    });
    s.textures.push(Texture {
        name: "color".into(),
        source: ImageSource::Path("color.png".into()),
        sampler: Default::default(),
    });
    s
}

#[test]
fn texture_chamfer_of_constant_colors_is_their_distance() {
    let scene = textured_grid([1.0; 4]);
    let a = [Some(Image::filled(4, 4, [0.2, 0.4, 0.6, 1.0]))];
    let b = [Some(Image::filled(4, 4, [0.5, 0.4, 0.2, 1.0]))];
    let (ea, eb) = (
        EvalMesh::from_scene(&scene, &a),
        EvalMesh::from_scene(&scene, &b),
    );
    assert!(ea.has_texture());
    let options = CompareOptions::default();
    // √(0.3² + 0² + 0.4²) = 0.5.
    let c = compare(&ea, &eb, &options);
    for t in [
        c.texture_chamfer,
        c.texture_chamfer_ref_to_cand,
        c.texture_chamfer_cand_to_ref,
    ] {
        assert!(close(t.expect("textured"), 0.5, 1e-6), "{c:?}");
    }
    assert_eq!(compare(&ea, &ea, &options).texture_chamfer, Some(0.0));
    // The base color factor (linear, glTF) multiplies the image (sRGB): a
    // white image times the second color, linearized, gives the same
    // answer. sRGB 0.5 is linear 0.214041, 0.4 is 0.133209, 0.2 is 0.033105.
    let tinted = textured_grid([0.214_041, 0.133_209, 0.033_105, 1.0]);
    let white = [Some(Image::filled(4, 4, [1.0; 4]))];
    let et = EvalMesh::from_scene(&tinted, &white);
    let t = compare(&ea, &et, &options)
        .texture_chamfer
        .expect("textured");
    assert!(close(t, 0.5, 1e-5), "{t}");
}

#[test]
fn texture_chamfer_follows_uvs_across_the_image() {
    // Left half black, right half white, mapped by u = x. The copy mirrors
    // the image: colors differ by 1 except at the center column.
    let scene = textured_grid([1.0; 4]);
    let mut img = Image::filled(2, 1, [0.0, 0.0, 0.0, 1.0]);
    img.pixels[1] = [1.0; 4];
    let mut mirrored = img.clone();
    mirrored.pixels.reverse();
    let (a, b) = ([Some(img)], [Some(mirrored)]);
    let c = compare(
        &EvalMesh::from_scene(&scene, &a),
        &EvalMesh::from_scene(&scene, &b),
        &CompareOptions::default(),
    );
    // Texel centers sit at u = 1/4 (black) and 3/4 (white); bilinear
    // filtering with repeat wrapping makes each channel a triangle wave
    // c(u) between them, and the mirror shows 1 − c(u). Nearest samples lie
    // at (almost) the same u, so each differs by √3 |2 c(u) − 1| over RGB,
    // a triangle wave in [0, √3] whose mean is √3 / 2.
    let want = 3f64.sqrt() / 2.0;
    let t = c.texture_chamfer.expect("textured");
    assert!(close(t, want, 0.03), "{t} vs {want}");
}

#[test]
fn untextured_meshes_have_no_texture_chamfer() {
    let scene = textured_grid([1.0; 4]);
    let undecoded: [Option<Image>; 1] = [None];
    let e = EvalMesh::from_scene(&scene, &undecoded);
    assert!(!e.has_texture());
    let c = compare(&e, &e, &CompareOptions::default());
    assert_eq!(c.texture_chamfer, None);
    assert!(!c.notes.is_empty());
}

#[test]
fn same_seed_gives_bit_identical_results_on_one_and_two_threads() {
    let scene = textured_grid([1.0; 4]);
    let mut img = Image::filled(8, 8, [0.1, 0.2, 0.3, 1.0]);
    for (i, p) in img.pixels.iter_mut().enumerate() {
        *p = [(i % 8) as f32 / 8.0, (i / 8) as f32 / 8.0, 0.5, 1.0];
    }
    let images = [Some(img)];
    let reference = EvalMesh::from_scene(&scene, &images);
    let bumpy = moved(shapes::quad_grid(7, 5), |p| {
        [p[0], p[1], 0.05 * (7.0 * p[0]).sin()]
    });
    let mut bumpy_scene = textured_grid([0.9, 0.8, 1.0, 1.0]);
    bumpy_scene.meshes[0] = Mesh {
        parts: bumpy_scene.meshes[0].parts.clone(),
        ..bumpy
    };
    let candidate = EvalMesh::from_scene(&bumpy_scene, &images);
    let options = CompareOptions {
        samples: 30_000,
        texture_samples: 5_000,
        ..CompareOptions::default()
    };
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(|| compare(&reference, &candidate, &options))
    };
    let (one, two) = (on(1), on(2));
    assert_eq!(format!("{one:?}"), format!("{two:?}"));
    assert!(one.hausdorff > 0.0 && one.texture_chamfer.expect("textured") > 0.0);
    let other = compare(
        &reference,
        &candidate,
        &CompareOptions {
            seed: 1,
            ..options.clone()
        },
    );
    assert_ne!(other.chamfer_mean, one.chamfer_mean, "the seed matters");
}

/// A bumpy 24 × 24 grid textured with a 64 × 64 image of smooth color
/// waves plus a fine checker: detail at several scales, like a real
/// texture.
fn detailed_texture_scene() -> (Scene, [Option<Image>; 1]) {
    let mut scene = textured_grid([1.0; 4]);
    let parts = scene.meshes[0].parts.clone();
    let bumpy = moved(shapes::quad_grid(24, 24), |p| {
        [p[0], p[1], 0.05 * (9.0 * p[0]).sin() * (7.0 * p[1]).cos()]
    });
    scene.meshes[0] = Mesh { parts, ..bumpy };
    let mut img = Image::filled(64, 64, [0.0; 4]);
    for (i, px) in img.pixels.iter_mut().enumerate() {
        let (x, y) = ((i % 64) as f32 / 64.0, (i / 64) as f32 / 64.0);
        let checker = ((i % 64) / 4 + (i / 64) / 4) % 2;
        *px = [
            0.5 + 0.4 * (12.0 * x).sin(),
            0.5 + 0.4 * (9.0 * y).cos(),
            0.2 + 0.6 * checker as f32,
            1.0,
        ];
    }
    (scene, [Some(img)])
}

#[test]
fn a_textured_surface_against_itself_is_at_the_floor_not_zero() {
    // Each side draws its own samples, so nearest samples carry different
    // colors even on one surface: the self-comparison is the floor (both
    // are estimates: 5% covers their sampling error at 40k samples, see
    // below), and the floor is in the result.
    let (scene, images) = detailed_texture_scene();
    let e = EvalMesh::from_scene(&scene, &images);
    let options = CompareOptions {
        samples: 2_000,
        ..CompareOptions::default()
    };
    assert_eq!(options.texture_samples, 40_000);
    let c = compare(&e, &e, &options);
    let (t, floor) = (
        c.texture_chamfer.expect("textured"),
        c.texture_chamfer_floor.expect("textured"),
    );
    assert!(floor > 0.01, "{c:?}");
    assert!(
        (t - floor).abs() <= 0.05 * floor,
        "{t} against the floor {floor}"
    );
    // The geometric distances of a surface to itself stay 0: every sample
    // lies on the other surface.
    assert!(c.hausdorff < 1e-12 && c.chamfer_mean < 1e-12);
    // The floor is stable: over five seeds it varies by less than 5%, and
    // so does the self-comparison about it.
    let runs: Vec<(f64, f64)> = (1..=5)
        .map(|seed| {
            let c = compare(
                &e,
                &e,
                &CompareOptions {
                    seed,
                    ..options.clone()
                },
            );
            (
                c.texture_chamfer.expect("textured"),
                c.texture_chamfer_floor.expect("textured"),
            )
        })
        .collect();
    let floors: Vec<f64> = runs.iter().map(|r| r.1).collect();
    let (lo, hi) = floors
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &f| (a.min(f), b.max(f)));
    assert!(hi / lo < 1.05, "{floors:?}");
    for (t, f) in runs {
        assert!((t - f).abs() <= 0.05 * f, "{t} against {f}");
    }
}

#[test]
fn fewer_texture_samples_raise_the_floor() {
    // The floor is the spacing of the samples made visible: with a quarter
    // of the samples, nearest samples are about twice as far apart, and
    // the colors they compare about twice as different on a smooth
    // texture.
    let (scene, images) = detailed_texture_scene();
    let e = EvalMesh::from_scene(&scene, &images);
    let floor = |n: usize| {
        compare(
            &e,
            &e,
            &CompareOptions {
                samples: 1_000,
                texture_samples: n,
                ..CompareOptions::default()
            },
        )
        .texture_chamfer_floor
        .expect("textured")
    };
    let ratio = floor(10_000) / floor(40_000);
    assert!((1.4..2.2).contains(&ratio), "{ratio}");
}

#[test]
fn empty_candidate_is_infinitely_far_without_nan() {
    let t = shapes::torus(12, 6, 2.0, 0.5);
    let empty = Mesh::default();
    let c = run(&t, &empty, &CompareOptions::default());
    assert!(floats(&c).iter().all(|x| !x.is_nan()), "{c:?}");
    assert_eq!(c.hausdorff, f64::INFINITY);
    assert_eq!(c.hausdorff_ref_to_cand, f64::INFINITY);
    assert_eq!(c.hausdorff_cand_to_ref, 0.0);
    assert_eq!(c.chamfer_mean, f64::INFINITY);
    assert_eq!(c.chamfer_squared, f64::INFINITY);
    assert_eq!(c.quad_ratio, None);
    assert!(c
        .notes
        .iter()
        .any(|n| n.contains("candidate has no triangle")));
    // Empty reference: the diagonal is 0, distances stay in world units.
    let c = run(&empty, &t, &CompareOptions::default());
    assert_eq!(c.diagonal, 0.0);
    assert_eq!(c.hausdorff_cand_to_ref, f64::INFINITY);
    assert!(floats(&c).iter().all(|x| !x.is_nan()));
    // Nothing against nothing: identical.
    let c = run(&empty, &empty, &CompareOptions::default());
    assert!(floats(&c).iter().all(|&x| x == 0.0), "{c:?}");
}

#[test]
fn zero_area_candidate_is_measured_by_its_vertices() {
    // A degenerate triangle: the segment from (0, 0, 1) to (1, 0, 1).
    let seg = Mesh::from_triangles(
        vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.5, 0.0, 1.0]],
        &[0, 1, 2],
    );
    let grid = shapes::quad_grid(2, 2);
    let c = run(&grid, &seg, &CompareOptions::default());
    assert!(floats(&c).iter().all(|x| x.is_finite()), "{c:?}");
    // Each of the three vertices is 1 above the grid.
    assert!(close(c.chamfer_mean_cand_to_ref, 1.0 / SQRT_2, 1e-12));
    assert!(close(c.hausdorff_cand_to_ref, 1.0 / SQRT_2, 1e-12));
}

#[test]
fn comparison_serializes_with_the_documented_keys() {
    let c = run(&shapes::cube(), &octahedron(), &CompareOptions::default());
    let json = serde_json::to_value(&c).expect("serializable");
    for key in [
        "hausdorff",
        "hausdorff_ref_to_cand",
        "hausdorff_cand_to_ref",
        "chamfer_mean",
        "chamfer_squared",
        "quad_ratio",
        "texture_chamfer",
        "texture_chamfer_floor",
        "normal_chamfer",
        "normal_chamfer_floor",
        "shading_normal_chamfer",
        "shading_normal_chamfer_ref_to_cand",
        "shading_normal_chamfer_cand_to_ref",
        "shading_normal_chamfer_floor",
        "diagonal",
        "diagonal_with_outliers",
        "outliers_reference",
        "outliers_candidate",
        "outlier_triangles_reference",
        "outlier_triangles_candidate",
        "outlier_vertices",
        "samples",
        "seed",
        "reference",
        "candidate",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert!(json["texture_chamfer"].is_null());
    assert!(json["texture_chamfer_floor"].is_null());
    assert!(json["normal_chamfer_floor"].as_f64().is_some());
    assert_eq!(json["outliers_reference"], 0);
    assert_eq!(json["outlier_vertices"], serde_json::json!([]));
    assert_eq!(json["quad_ratio"], serde_json::json!(0.0));
    for key in [
        "faces",
        "triangles",
        "quads",
        "ngons",
        "triangulated",
        "components",
    ] {
        assert!(
            json["reference"].get(key).is_some(),
            "missing reference.{key}"
        );
    }
    assert_eq!(json["reference"]["quads"], 6);
    assert_eq!(json["candidate"]["triangulated"], 8);
}

#[test]
fn alpha_tested_coverage_is_the_fraction_of_the_surface_the_test_draws() {
    // Opaque for u < 0.3 (a 100-texel row: the bilinear alpha crosses
    // 0.5 at u = 0.30), transparent beyond, over a grid mapped by u = x.
    let mut scene = textured_grid([1.0; 4]);
    scene.materials[0].alpha_mode = wildlod_mesh::AlphaMode::Mask;
    scene.materials[0].alpha_cutoff = 0.5;
    let mut img = Image::filled(100, 1, [0.5, 0.5, 0.5, 0.0]);
    for p in &mut img.pixels[..30] {
        p[3] = 1.0;
    }
    let images = [Some(img)];
    let masked = EvalMesh::from_scene(&scene, &images);
    assert!(masked.alpha_tested());
    let c = compare(&masked, &masked, &CompareOptions::default());
    for v in [c.alpha_coverage_reference, c.alpha_coverage_candidate] {
        // 40k samples: a standard error of 0.0023.
        assert!((v.expect("alpha-tested") - 0.3).abs() < 0.01, "{c:?}");
    }
    // A factor that takes every alpha under the cutoff draws nothing.
    let mut faded = scene.clone();
    faded.materials[0].base_color[3] = 0.4;
    let faded = EvalMesh::from_scene(&faded, &images);
    let c = compare(&masked, &faded, &CompareOptions::default());
    assert_eq!(c.alpha_coverage_candidate, Some(0.0));
    // An opaque material is not alpha-tested: no coverage on that side,
    // and none at all when neither side tests.
    let opaque = textured_grid([1.0; 4]);
    let opaque = EvalMesh::from_scene(&opaque, &images);
    let c = compare(&masked, &opaque, &CompareOptions::default());
    assert!(c.alpha_coverage_reference.is_some());
    assert_eq!(c.alpha_coverage_candidate, None);
    let c = compare(&opaque, &opaque, &CompareOptions::default());
    assert_eq!(
        (c.alpha_coverage_reference, c.alpha_coverage_candidate),
        (None, None)
    );
}
