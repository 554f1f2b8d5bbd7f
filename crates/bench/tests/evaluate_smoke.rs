//! The evaluation command in a reduced form (two small generated meshes,
//! one ratio), so that it cannot rot.
#![allow(clippy::unwrap_used)] // test code

use wildlod_bench::evaluation::{evaluate, markdown, Config};
use wildlod_bench::methods::Method;
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Scene};

#[test]
fn evaluation_runs_every_method_and_writes_the_report() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("manifold")).unwrap();
    std::fs::create_dir_all(dir.path().join("wild")).unwrap();
    let write = |m: wildlod_mesh::Mesh, p: &str| {
        wildlod_io::write(
            &Document::from_scene(Scene::from_mesh(m)),
            dir.path().join(p),
            &WriteOptions::default(),
        )
        .unwrap();
    };
    write(
        shapes::triangulate(&shapes::quad_sphere(8)),
        "manifold/sphere.obj",
    );
    write(
        shapes::merge(&[
            shapes::box_grid([0.0; 3], [1.0; 3], 4),
            shapes::box_grid([1.0, 0.2, 0.2], [1.5, 0.8, 0.8], 3),
        ]),
        "wild/boxes.ply",
    );
    let cfg = Config {
        corpus: dir.path().to_path_buf(),
        ratios: vec![0.5],
        samples: 2000,
        ..Config::default()
    };
    let rows = evaluate(&cfg, |_| {}).unwrap();
    let of = |file: &str| -> Vec<_> { rows.iter().filter(|r| r.file.ends_with(file)).collect() };
    assert_eq!(of("sphere.obj").len(), Method::ALL.len());
    assert_eq!(of("boxes.ply").len(), Method::ALL.len());
    // Without quads there is no quad ratio, and "quads off" is the default.
    let sphere = |m| {
        of("sphere.obj")
            .into_iter()
            .find(|r| r.method == m)
            .unwrap()
    };
    assert_eq!(sphere(Method::Wildlod).quad_ratio, None);
    assert_eq!(
        sphere(Method::Wildlod).hausdorff,
        sphere(Method::WildlodNoQuads).hausdorff
    );
    let quads = |m| {
        of("boxes.ply")
            .into_iter()
            .find(|r| r.method == m)
            .unwrap()
            .quad_ratio
    };
    // Quad ordering keeps more quads than the same run with it off, and
    // meshoptimizer (triangles only) keeps none.
    assert!(quads(Method::Wildlod).unwrap() > quads(Method::WildlodNoQuads).unwrap());
    assert_eq!(quads(Method::Meshopt), Some(0.0));
    // The equal-budget row asks for exactly what meshoptimizer reached.
    for file in ["sphere.obj", "boxes.ply"] {
        let sel = of(file);
        let m = sel.iter().find(|r| r.method == Method::Meshopt).unwrap();
        let w = sel
            .iter()
            .find(|r| r.method == Method::WildlodAtMeshoptCount)
            .unwrap();
        assert_eq!(w.target, m.triangles);
        assert!(w.triangles.abs_diff(m.triangles) <= 1, "{w:?} vs {m:?}");
    }
    for r in &rows {
        assert!(r.failure.is_none(), "{r:?}");
        assert!(r.hausdorff.is_finite() && r.hausdorff >= 0.0, "{r:?}");
        assert!(r.chamfer_mean <= r.hausdorff, "{r:?}");
    }
    // wildlod reaches the target on both.
    for r in rows.iter().filter(|r| r.method == Method::Wildlod) {
        assert!(r.reached(), "{r:?}");
    }
    let md = markdown(&cfg, &rows, "test");
    assert!(
        md.contains("| manifold | 50% | wildlod | 1/1 | 0 |"),
        "{md}"
    );
    assert!(md.contains("| wild | 50% | meshopt simplify |"), "{md}");
    assert!(md.contains("### wild/boxes.ply"), "{md}");
}

#[test]
fn evaluate_binary_parses_its_arguments_and_writes_markdown() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("manifold")).unwrap();
    wildlod_io::write(
        &Document::from_scene(Scene::from_mesh(shapes::triangulate(&shapes::quad_sphere(
            4,
        )))),
        dir.path().join("manifold/s.obj"),
        &WriteOptions::default(),
    )
    .unwrap();
    let out = dir.path().join("report.md");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_evaluate"))
        .arg(dir.path())
        .args(["--ratios", "0.5", "--samples", "1000", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(&out).unwrap();
    assert!(md.starts_with("# wildlod evaluation"));
    assert!(md.contains("manifold/s.obj"));
}
