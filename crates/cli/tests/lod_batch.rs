//! `wildlod lod` and `wildlod batch` as build pipelines drive them: nested
//! levels with non-increasing counts, MSFT_lod files the Khronos validator
//! accepts, a batch over a folder with broken files (summary, exit code,
//! outputs for the good ones, resuming), and the `--json` reports.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::path::Path;

use serde_json::Value;
use support::{s, stderr, stdout, torus, validate, wildlod};

fn triangles(path: &Path) -> usize {
    wildlod_io::read(path)
        .unwrap()
        .scene
        .meshes
        .iter()
        .map(|m| m.triangle_count())
        .sum()
}

#[test]
fn lod_split_levels_are_nested_and_never_gain_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.obj"));
    let out = dir.path().join("out.obj");
    let o = wildlod(&["lod", s(&input), "-o", s(&out), "--ratios", "0.5,0.25,0.1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("lod0: 2304 triangles"), "{text}");
    assert!(text.contains("lod3: "), "{text}");
    let levels: Vec<_> = (0..4)
        .map(|k| dir.path().join(format!("out_lod{k}.obj")))
        .collect();
    let counts: Vec<usize> = levels.iter().map(|p| triangles(p)).collect();
    assert_eq!(counts[0], 2304);
    for (k, want) in [(1, 1152), (2, 576), (3, 230)] {
        assert!(counts[k].abs_diff(want) <= 1, "level {k}: {counts:?}");
    }
    assert!(counts.windows(2).all(|w| w[1] <= w[0]), "{counts:?}");
    // Nested: level 2 is exactly what simplifying level 1 gives.
    let again = dir.path().join("again.obj");
    let o = wildlod(&[
        "simplify",
        s(&levels[1]),
        "-o",
        s(&again),
        "--faces",
        &counts[2].to_string(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = wildlod_io::read(&again).unwrap().scene.meshes[0]
        .positions
        .clone();
    let b = wildlod_io::read(&levels[2]).unwrap().scene.meshes[0]
        .positions
        .clone();
    assert_eq!(a, b, "level 2 is not level 1 simplified");
}

#[test]
fn lod_errors_and_faces_lists_make_coarser_levels() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.ply"));
    let out = dir.path().join("e.ply");
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&out),
        "--errors",
        "0.002,0.01,0.05",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let levels = j["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 4);
    for w in levels.windows(2) {
        assert!(w[1]["triangles"].as_u64() <= w[0]["triangles"].as_u64());
        assert!(w[1]["error"].as_f64() >= w[0]["error"].as_f64());
    }
    for (l, limit) in levels[1..].iter().zip([0.002, 0.01, 0.05]) {
        assert!(l["error"].as_f64().unwrap() <= limit + 1e-9, "{l}");
    }
    assert!(levels[3]["triangles"].as_u64().unwrap() < 2304);

    let out = dir.path().join("f.stl");
    let o = wildlod(&["lod", s(&input), "-o", s(&out), "--faces", "1000,300", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(triangles(&dir.path().join("f_lod1.stl")).abs_diff(1000) <= 1);
    assert!(triangles(&dir.path().join("f_lod2.stl")).abs_diff(300) <= 1);
}

#[test]
fn lod_lists_that_do_not_get_coarser_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("t.obj"));
    let out = dir.path().join("o.glb");
    let o = wildlod(&["lod", s(&input), "-o", s(&out), "--ratios", "0.1,0.5"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("--ratios must decrease"),
        "{}",
        stderr(&o)
    );
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&out),
        "--ratios",
        "0.5",
        "--faces",
        "10",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!out.exists());
}

/// Checks the MSFT_lod layout of a written file: every base node lists
/// nodes outside the scene, one coverage hint per level plus the cut-off,
/// never rising, and levels that never gain triangles.
fn check_msft_lod(path: &Path, levels: usize) {
    let doc = wildlod_io::read(path).unwrap();
    let bytes = std::fs::read(path).unwrap();
    // The JSON chunk of a GLB: length at 12, JSON from 20.
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let j: Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    assert!(j["extensionsUsed"]
        .as_array()
        .unwrap()
        .contains(&Value::from("MSFT_lod")));
    let in_scene: Vec<u64> = j["scenes"][0]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let nodes = j["nodes"].as_array().unwrap();
    let mut bases = 0;
    for n in nodes {
        let Some(ids) = n["extensions"]["MSFT_lod"]["ids"].as_array() else {
            continue;
        };
        bases += 1;
        assert_eq!(ids.len(), levels);
        let cov: Vec<f64> = n["extras"]["MSFT_screencoverage"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(cov.len(), levels + 1);
        assert!(cov.windows(2).all(|w| w[1] <= w[0]), "{cov:?}");
        let mut tris =
            vec![doc.scene.meshes[n["mesh"].as_u64().unwrap() as usize].triangle_count()];
        for id in ids {
            let id = id.as_u64().unwrap();
            assert!(!in_scene.contains(&id), "level node {id} is in the scene");
            let lod = &nodes[id as usize];
            assert_eq!(lod["skin"], n["skin"]);
            tris.push(doc.scene.meshes[lod["mesh"].as_u64().unwrap() as usize].triangle_count());
        }
        assert!(tris.windows(2).all(|w| w[1] <= w[0]), "{tris:?}");
    }
    assert!(bases > 0, "no node carries MSFT_lod");
}

#[test]
fn lod_glb_holds_every_level_as_msft_lod_the_validator_accepts() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.glb"));
    let out = dir.path().join("lods.glb");
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&out),
        "--ratios",
        "0.5,0.25,0.1",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_msft_lod(&out, 3);
    if let Some(v) = validate(&out) {
        assert_eq!(v["errors"], 0, "{v}");
    }
}

#[test]
fn lod_of_textured_and_skinned_corpus_files_validates() {
    let Some(root) = wildlod_testkit::corpus("lod_of_textured_and_skinned_corpus_files_validates")
    else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // `keep` shares the input's textures at every level; the default
    // (`auto`) adds the re-baked levels' atlases and materials to the
    // same file, which must validate as well.
    for (rel, textures) in [
        ("textured/CesiumMilkTruck.glb", "keep"),
        ("textured/CesiumMilkTruck.glb", "auto"),
        ("skinned/CesiumMan.glb", "keep"),
        ("skinned/CesiumMan.glb", "auto"),
    ] {
        let input = root.join(rel);
        let out = dir.path().join("lods.glb");
        let o = wildlod(&[
            "lod",
            s(&input),
            "-o",
            s(&out),
            "--ratios",
            "0.5,0.1",
            "--textures",
            textures,
            "-q",
        ]);
        assert!(o.status.success(), "{rel}: {}", stderr(&o));
        check_msft_lod(&out, 2);
        let a = wildlod_io::read(&input).unwrap();
        let b = wildlod_io::read(&out).unwrap();
        if textures == "keep" {
            // Shared, not copied per level.
            assert_eq!(a.scene.textures.len(), b.scene.textures.len(), "{rel}");
        } else {
            assert!(a.scene.textures.len() <= b.scene.textures.len(), "{rel}");
        }
        // No error the input did not have (CesiumMan's own weights are
        // not normalized: the validator reports that on the input too).
        if let (Some(before), Some(after)) = (validate(&input), validate(&out)) {
            let codes = |v: &Value| -> Vec<String> {
                v["codes"].as_object().unwrap().keys().cloned().collect()
            };
            let new: Vec<String> = codes(&after)
                .into_iter()
                .filter(|c| !codes(&before).contains(c))
                .collect();
            assert!(
                new.is_empty(),
                "{rel} --textures {textures}: new errors {after} (input: {before})"
            );
        }
    }
}

#[test]
fn simplify_json_reports_every_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.obj"));
    let out = dir.path().join("o.obj");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.25",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j: Value = serde_json::from_str(&stdout(&o)).unwrap();
    for key in [
        "input",
        "output",
        "input_triangles",
        "output_triangles",
        "error",
        "seconds",
        "meshes",
    ] {
        assert!(j.get(key).is_some(), "missing {key}: {j}");
    }
    assert_eq!(j["input_triangles"], 2304);
    let m = &j["meshes"][0];
    assert_eq!(m["name"], "torus");
    assert_eq!(m["stop"], "target_reached");
    assert!(m["output_triangles"].as_u64().unwrap().abs_diff(576) <= 1);
    assert_eq!(
        m["output_triangles"].as_u64().unwrap() as usize,
        triangles(&out)
    );
}

/// A folder with good files in a tree and broken ones.
fn library(root: &Path) {
    std::fs::create_dir_all(root.join("props/small")).unwrap();
    torus(&root.join("ring.obj"));
    torus(&root.join("props/ring.glb"));
    torus(&root.join("props/small/ring.ply"));
    std::fs::write(root.join("props/broken.obj"), "v 1 2 oops\nf 1 2 3\n").unwrap();
    std::fs::write(root.join("props/small/empty.stl"), "").unwrap();
    std::fs::write(root.join("notes.txt"), "not a mesh").unwrap();
}

fn summary(out: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(out.join("wildlod-summary.json")).unwrap()).unwrap()
}

fn status_of<'a>(j: &'a Value, file: &str) -> &'a str {
    j["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["file"] == file)
        .unwrap_or_else(|| panic!("{file} not in the summary: {j}"))["status"]
        .as_str()
        .unwrap()
}

#[test]
fn batch_goes_past_broken_files_lists_them_and_fails() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("assets");
    let out = dir.path().join("lods");
    library(&input);
    let o = wildlod(&[
        "batch",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.25",
        "-j",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("2 of 5 files failed"), "{}", stderr(&o));
    assert!(stderr(&o).contains("broken.obj"), "{}", stderr(&o));
    let j = summary(&out);
    assert_eq!(
        (j["files"].as_u64(), j["ok"].as_u64(), j["failed"].as_u64()),
        (Some(5), Some(3), Some(2))
    );
    for good in ["ring.obj", "props/ring.glb", "props/small/ring.ply"] {
        assert_eq!(status_of(&j, good), "ok");
        assert!(triangles(&out.join(good)).abs_diff(576) <= 1, "{good}");
    }
    for bad in ["props/broken.obj", "props/small/empty.stl"] {
        assert_eq!(status_of(&j, bad), "failed");
        assert!(!out.join(bad).exists(), "{bad} has an output");
    }
    let broken = j["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["file"] == "props/broken.obj")
        .unwrap();
    assert!(
        broken["message"].as_str().unwrap().contains("line 1"),
        "{broken}"
    );
    let ok = j["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["file"] == "ring.obj")
        .unwrap();
    assert_eq!(ok["triangles_in"], 2304);
    assert!(ok["error"].as_f64().unwrap() > 0.0);
    let csv = std::fs::read_to_string(out.join("wildlod-summary.csv")).unwrap();
    assert!(
        csv.starts_with("file,status,triangles_in,triangles_out,error,seconds"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 6, "{csv}");
    assert!(
        csv.lines()
            .any(|l| l.starts_with("props/small/empty.stl,failed,")),
        "{csv}"
    );
}

#[test]
fn batch_resumes_with_skip_existing() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("assets");
    let out = dir.path().join("lods");
    library(&input);
    std::fs::remove_file(input.join("props/broken.obj")).unwrap();
    std::fs::remove_file(input.join("props/small/empty.stl")).unwrap();
    let o = wildlod(&["batch", s(&input), "-o", s(&out), "--ratio", "0.25", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // An interrupted run: one output missing.
    std::fs::remove_file(out.join("props/ring.glb")).unwrap();
    let before = std::fs::metadata(out.join("ring.obj"))
        .unwrap()
        .modified()
        .unwrap();
    let o = wildlod(&[
        "batch",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.25",
        "--skip-existing",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(status_of(&j, "props/ring.glb"), "ok");
    assert_eq!(status_of(&j, "ring.obj"), "skipped");
    assert_eq!(status_of(&j, "props/small/ring.ply"), "skipped");
    assert!(out.join("props/ring.glb").exists());
    let after = std::fs::metadata(out.join("ring.obj"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after, "a skipped output was rewritten");
}

#[test]
fn batch_makes_lod_chains_in_another_format() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("assets");
    let out = dir.path().join("lods");
    std::fs::create_dir_all(&input).unwrap();
    torus(&input.join("a.obj"));
    torus(&input.join("b.ply"));
    let o = wildlod(&[
        "batch",
        s(&input),
        "-o",
        s(&out),
        "--lod-ratios",
        "0.5,0.1",
        "--format",
        "glb",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["a.glb", "b.glb"] {
        check_msft_lod(&out.join(f), 2);
    }
    let j = summary(&out);
    let r = &j["results"][0];
    assert!(
        r["triangles_out"].as_u64().unwrap().abs_diff(230) <= 1,
        "{r}"
    );
}
