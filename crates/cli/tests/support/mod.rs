//! Helpers shared by the CLI tests of the asset-library commands: running
//! the binary, generated inputs, and the external checkers (the Khronos
//! glTF validator, headless Chromium), each installed from the npm
//! registry on first use and skipped with a loud message where they
//! cannot run, except under `CI=true`, where that is a failure.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)] // test code

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Scene};

pub fn wildlod(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wildlod"))
        .args(args)
        .output()
        .expect("run wildlod")
}

/// Runs wildlod and fails the test, with its stderr, unless it succeeds.
pub fn wildlod_ok(args: &[&str]) -> Output {
    let o = wildlod(args);
    assert!(o.status.success(), "wildlod {args:?}: {}", stderr(&o));
    o
}

/// `wildlod simplify INPUT -o OUTPUT ARGS… --json` (which must succeed)
/// and the report it prints.
pub fn simplify_json(input: &Path, output: &Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["simplify", s(input), "-o", s(output), "--json"];
    all.extend_from_slice(args);
    let o = wildlod_ok(&all);
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", stdout(&o)))
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Posed Hausdorff distance of `candidate` to `reference` at each frame
/// `wildlod compare --animation 0` measures, with `extra` arguments
/// (`--frames`, `--fps`, `--samples`).
pub fn posed_hausdorff(reference: &Path, candidate: &Path, extra: &[&str]) -> Vec<f64> {
    let mut args = vec![
        "compare",
        s(reference),
        s(candidate),
        "--animation",
        "0",
        "--json",
    ];
    args.extend(extra);
    let o = wildlod(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    j["animation"]["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["hausdorff"].as_f64().unwrap())
        .collect()
}

/// A bumpy torus of quads (2304 triangles) written to `path` (any format).
pub fn torus(path: &Path) -> PathBuf {
    let mut m = shapes::torus(48, 24, 1.0, 0.35);
    for (k, p) in m.positions.iter_mut().enumerate() {
        p[2] *= 1.0 + 0.1 * ((k % 7) as f32 / 7.0);
    }
    m.name = "torus".into();
    wildlod_io::write(
        &Document::from_scene(Scene::from_mesh(m)),
        path,
        &WriteOptions::default(),
    )
    .unwrap();
    path.to_path_buf()
}

/// Installs the npm packages of `tools/<tool>` once; `None` (with a loud
/// message) where node or the registry is missing, a panic under CI.
///
/// Tests run in parallel threads and several need the same tool, so the
/// install holds a file lock and leaves a marker only once npm succeeded:
/// two concurrent `npm install`s into one folder fail with ENOTEMPTY, and a
/// half-installed `node_modules` must not pass for a finished one.
pub fn npm_tool(tool: &str, module: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tools")
        .join(tool);
    if Command::new("node").arg("--version").output().is_err() {
        assert!(!in_ci(), "node is not installed: {tool} cannot run");
        wildlod_testkit::skipped(&format!("node is not installed, so {tool} cannot run"));
        return None;
    }
    let marker = dir.join("node_modules").join(".wildlod-installed");
    if marker.exists() {
        return Some(dir);
    }
    // `cargo test` runs one test binary at a time, so a lock within the
    // process is enough (`File::lock` is newer than the MSRV).
    static INSTALL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _held = INSTALL.lock().unwrap_or_else(|e| e.into_inner());
    if !marker.exists() {
        let o = Command::new("npm")
            .args(["install", "--no-audit", "--no-fund", "--prefix"])
            .arg(&dir)
            .output();
        let ok = o.as_ref().is_ok_and(|o| o.status.success())
            && dir.join("node_modules").join(module).exists();
        if !ok {
            assert!(!in_ci(), "npm install of {tool} failed: {o:?}");
            wildlod_testkit::skipped(&format!("could not install {tool} from npm: {o:?}"));
            return None;
        }
        std::fs::write(&marker, b"").unwrap();
    }
    Some(dir)
}

/// The Khronos validator's error count and codes for a glTF file, or
/// `None` where it cannot run.
pub fn validate(file: &Path) -> Option<serde_json::Value> {
    let dir = npm_tool("gltf-validator", "gltf-validator")?;
    let o = Command::new("node")
        .arg(dir.join("validate.js"))
        .arg(file)
        .output()
        .unwrap();
    Some(
        serde_json::from_slice(&o.stdout)
            .unwrap_or_else(|e| panic!("validator output for {}: {e}", file.display())),
    )
}

/// Headless Chromium (Debian's package): whether it is installed, else a
/// loud skip (a failure under CI, where `.ci/run` installs it).
pub fn chromium() -> Option<PathBuf> {
    let path =
        PathBuf::from(std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into()));
    if path.exists() {
        return Some(path);
    }
    assert!(
        !in_ci(),
        "Chromium is not installed at {} (apt-get install chromium): the report test cannot run",
        path.display()
    );
    wildlod_testkit::skipped(&format!(
        "Chromium is not installed at {} (apt-get install chromium); nothing is checked in a browser",
        path.display()
    ));
    None
}

/// Opens an HTML report in headless Chromium, saves a screenshot of its
/// two views to `shot`, and returns `{ready, errors}`; `None` where the
/// browser cannot run.
pub fn open_in_chromium(report: &Path, shot: &Path) -> Option<serde_json::Value> {
    let browser = chromium()?;
    let dir = npm_tool("report-check", "playwright-core")?;
    let o = Command::new("node")
        .arg(dir.join("check.js"))
        .arg(report)
        .arg(shot)
        .env("CHROMIUM", browser)
        .output()
        .unwrap();
    Some(serde_json::from_slice(&o.stdout).unwrap_or_else(|e| {
        panic!(
            "report check output: {e}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        )
    }))
}
