//! Issue 3, on real meshes: every corpus mesh reaches its target within one
//! triangle at 50%, 10%, 1% and 0.1%, or the report says why not; the result
//! is valid (indices in range, finite positions, `validate()` passes).
#![allow(clippy::unwrap_used)] // test code

use wildlod_simplify::{simplify_mesh, Guards, Options, StopReason, Target};
use wildlod_testkit::{corpus, mesh_files, short};

#[test]
fn every_corpus_mesh_reaches_every_ratio_within_one_triangle() {
    let Some(root) = corpus("every_corpus_mesh_reaches_every_ratio_within_one_triangle") else {
        return;
    };
    let mut failures = Vec::new();
    let mut checked = 0;
    for path in mesh_files(&root, "") {
        let name = short(&root, &path);
        let doc = wildlod_io::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        // The large scan is covered at two ratios to keep the suite fast.
        let ratios: &[f64] = if name.starts_with("large/") {
            &[0.1, 0.01]
        } else {
            &[0.5, 0.1, 0.01, 0.001]
        };
        for (m, mesh) in doc.scene.meshes.iter().enumerate() {
            if mesh.faces.is_empty() {
                continue;
            }
            for &r in ratios {
                let options = Options {
                    target: Target {
                        ratio: Some(r),
                        ..Target::default()
                    },
                    ..Options::default()
                };
                let (out, rep) = simplify_mesh(mesh, &options).unwrap();
                checked += 1;
                if let Err(e) = out.validate() {
                    failures.push(format!("{name} mesh {m} at {r}: invalid output: {e}"));
                }
                assert_eq!(out.triangle_count(), rep.output_triangles);
                let reached = rep.output_triangles.abs_diff(rep.target_triangles) <= 1;
                // Stopped above the target with nothing left to collapse, or
                // below it because the faces left all carry twins, which go
                // with their face (the report says which).
                let explained = (rep.stop == Some(StopReason::NoCollapsibleEdges)
                    && rep.output_triangles > rep.target_triangles)
                    || (rep.twin_slack && rep.output_triangles < rep.target_triangles);
                if !reached && !explained {
                    failures.push(format!(
                        "{name} mesh {m} at {r}: {} -> {} for target {} ({:?})",
                        rep.input_triangles, rep.output_triangles, rep.target_triangles, rep.stop
                    ));
                }
                if !reached {
                    eprintln!(
                        "{name} mesh {m} at {r}: stopped at {} for target {}: {:?}, refused {:?}",
                        rep.output_triangles, rep.target_triangles, rep.stop, rep.rejected
                    );
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} runs: corpus incomplete?");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn info_json_face_counts_match_the_corpus_readme() {
    let Some(root) = corpus("info_json_face_counts_match_the_corpus_readme") else {
        return;
    };
    let expected = wildlod_testkit::readme_face_counts(&root);
    let mut checked = 0;
    for path in mesh_files(&root, "") {
        let rel = path.strip_prefix(&root).unwrap().to_path_buf();
        let Some(&(t, q, n)) = expected.get(&rel) else {
            continue;
        };
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_wildlod"))
            .args(["info", "--json"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{}: {}",
            rel.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        // The README counts a glTF mesh once per instance.
        let inst = &v["instanced"];
        let got = (
            inst["triangles"].as_u64().unwrap() as usize,
            inst["quads"].as_u64().unwrap() as usize,
            inst["ngons"].as_u64().unwrap() as usize,
        );
        assert_eq!(got, (t, q, n), "{}", rel.display());
        checked += 1;
    }
    assert!(checked >= 35, "only {checked} README rows matched files");
}

#[test]
fn spider_keeps_its_legs_at_ten_percent() {
    // Regression guard for the gluing term (`Metric::gluing_weight`): with
    // virtual edges but without it, the spider's legs retracted into its
    // body at 10% (Hausdorff 0.35 against 0.08 without virtual edges when
    // this was written; 0.11 against 0.047 now, geometry-only).
    // Measured with attributes fitted but not steering (every weight 0):
    // the gluing term acts on the geometry, and a steered run's order
    // depends on the appearance budget its geometry-only run sets, so two
    // steered runs differ by chance at this level (0.054 with virtual
    // edges, 0.037 without, each within 1.15x of its own geometry-only
    // run's 0.047).
    let Some(root) = corpus("spider_keeps_its_legs_at_ten_percent") else {
        return;
    };
    let doc = wildlod_io::read(root.join("wild/spider/spider.obj")).unwrap();
    let reference = wildlod_eval::EvalMesh::from_scene(&doc.scene, &[]);
    let run = |options: Options| {
        let mut s = doc.scene.clone();
        s.meshes[0] = simplify_mesh(&s.meshes[0], &options).unwrap().0;
        let c = wildlod_eval::compare(
            &reference,
            &wildlod_eval::EvalMesh::from_scene(&s, &[]),
            &wildlod_eval::CompareOptions {
                samples: 20_000,
                ..Default::default()
            },
        );
        c.hausdorff
    };
    let mut geometry = Options {
        target: Target {
            ratio: Some(0.1),
            ..Target::default()
        },
        ..Options::default()
    };
    geometry.attributes.tex_coord_weight = 0.0;
    geometry.attributes.normal_weight = 0.0;
    geometry.attributes.color_weight = 0.0;
    geometry.attributes.skin_weight = 0.0;
    let wild = run(geometry.clone());
    let apart = run(Options {
        guards: Guards {
            virtual_edge_radius: 0.0,
            ..Guards::default()
        },
        ..geometry.clone()
    });
    let unglued = {
        let mut o = geometry.clone();
        o.metric.gluing_weight = 0.0;
        run(o)
    };
    eprintln!("virtual edges {wild:.4}, none {apart:.4}, without gluing {unglued:.4}");
    assert!(
        wild <= 1.25 * apart,
        "default {wild:.4} vs no virtual edges {apart:.4}"
    );
}
