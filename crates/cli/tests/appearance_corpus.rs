//! Appearance on the corpus's textured and skinned glTF files at 50%, 10%
//! and 1%: no new UV islands (as `wildlod info` counts them), one influence
//! set per position in every skinned output, and the Khronos glTF validator
//! finds no error in an output whose input had none, nor a new kind of
//! error in the others.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use wildlod_testkit::{corpus, mesh_files, short};

const RATIOS: [f64; 3] = [0.5, 0.1, 0.01];

fn wildlod(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_wildlod"))
        .args(args)
        .output()
        .expect("run wildlod")
}

fn gltf_files(root: &Path) -> Vec<PathBuf> {
    ["textured", "skinned"]
        .iter()
        .flat_map(|c| mesh_files(root, c))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("gltf" | "glb")))
        .collect()
}

fn islands(path: &Path) -> Option<u64> {
    let o = wildlod(&["info", path.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    v["uv_islands"].as_u64()
}

fn simplify(input: &Path, out: &Path, r: f64) {
    simplify_with(input, out, r, &[]);
}

fn simplify_with(input: &Path, out: &Path, r: f64, extra: &[&str]) {
    let ratio = r.to_string();
    let mut args = vec![
        "simplify",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--ratio",
        &ratio,
        "-q",
    ];
    args.extend_from_slice(extra);
    let o = wildlod(&args);
    assert!(
        o.status.success(),
        "{}: {}",
        input.display(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Keeping the UVs keeps the input's islands: no new seam is cut (a
/// re-baked LOD, which the default writes where it measures better, gets
/// an atlas of its own by design).
#[test]
fn levels_of_detail_add_no_uv_island() {
    let Some(root) = corpus("levels_of_detail_add_no_uv_island") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for input in gltf_files(&root) {
        let Some(before) = islands(&input) else {
            continue;
        };
        for r in RATIOS {
            let out = dir.path().join(format!("lod_{r}.glb"));
            simplify_with(&input, &out, r, &["--textures", "keep"]);
            let after = islands(&out).unwrap_or(0);
            assert!(
                after <= before,
                "{} at {r}: {before} UV islands became {after}",
                short(&root, &input)
            );
            checked += 1;
        }
    }
    assert!(
        checked >= 18,
        "only {checked} runs: is the corpus complete?"
    );
}

#[test]
fn skinned_levels_of_detail_keep_one_influence_set_per_position() {
    let Some(root) = corpus("skinned_levels_of_detail_keep_one_influence_set_per_position") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut skinned = 0;
    for input in gltf_files(&root) {
        for r in RATIOS {
            let out = dir.path().join(format!("lod_{r}.glb"));
            simplify(&input, &out, r);
            let doc = wildlod_io::read(&out).unwrap();
            for mesh in &doc.scene.meshes {
                let Some(s) = &mesh.skinning else {
                    continue;
                };
                skinned += 1;
                let mut sets: BTreeMap<[u32; 3], Vec<(u16, u32)>> = BTreeMap::new();
                for (corner, &v) in mesh.faces.indices.iter().enumerate() {
                    let (js, ws) = s.entry(s.indices[corner]);
                    let mut set: Vec<(u16, u32)> = js
                        .iter()
                        .zip(ws)
                        .filter(|(_, &w)| w > 0.0)
                        .map(|(&j, &w)| (j, w.to_bits()))
                        .collect();
                    set.sort_unstable();
                    let key = mesh.positions[v as usize].map(f32::to_bits);
                    let seen = sets.entry(key).or_insert_with(|| set.clone());
                    assert_eq!(
                        *seen,
                        set,
                        "{} at {r}: copies of one position carry different influences",
                        short(&root, &input)
                    );
                }
            }
        }
    }
    assert!(skinned >= 12, "only {skinned} skinned outputs checked");
}

/// `node tools/gltf-validator/validate.js`, installing the validator from
/// the npm registry the first time; `None` (with a message) where Node.js
/// is absent, a failure under `CI=true`.
fn validator() -> Option<PathBuf> {
    support::npm_tool("gltf-validator", "gltf-validator").map(|dir| dir.join("validate.js"))
}

/// The error codes the validator reports for a file, with counts.
fn validation_errors(script: &Path, file: &Path) -> BTreeMap<String, u64> {
    let o = Command::new("node").arg(script).arg(file).output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("validator output for {}: {e}", file.display()));
    v["codes"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, n)| (k.clone(), n.as_u64().unwrap()))
        .collect()
}

#[test]
fn the_khronos_validator_finds_no_new_error_in_levels_of_detail() {
    let Some(root) = corpus("the_khronos_validator_finds_no_new_error_in_levels_of_detail") else {
        return;
    };
    let Some(script) = validator() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for input in gltf_files(&root) {
        let before = validation_errors(&script, &input);
        for r in RATIOS {
            let out = dir.path().join(format!("lod_{r}.glb"));
            simplify(&input, &out, r);
            let after = validation_errors(&script, &out);
            let new: Vec<&String> = after.keys().filter(|k| !before.contains_key(*k)).collect();
            assert!(
                new.is_empty(),
                "{} at {r}: new kinds of error {new:?} (input had {before:?})",
                short(&root, &input)
            );
            assert!(
                !before.is_empty() || after.is_empty(),
                "{} at {r}: {after:?} in the output of a valid input",
                short(&root, &input)
            );
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} runs");
}
