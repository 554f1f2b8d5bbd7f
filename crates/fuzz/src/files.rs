//! The file pipeline under hostile input: read → simplify every mesh →
//! write another format → read the output back, with the properties of the
//! crate docs checked at every step.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use wildlod_io::{Document, WriteOptions};
use wildlod_simplify::{simplify_mesh, Options, Partition, QuadMode, Target};

use crate::simplify_case::check_outcome;
use crate::{fnv1a, SIDECAR_MARKER};

/// The input formats, each with the sidecar its fuzz input may carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputFormat {
    /// `in.obj`, with the bytes after [`SIDECAR_MARKER`] as `m.mtl`.
    Obj,
    /// `in.ply`.
    Ply,
    /// `in.stl`.
    Stl,
    /// `in.off`.
    Off,
    /// `in.gltf`, with the bytes after [`SIDECAR_MARKER`] as `in.bin`.
    Gltf,
    /// `in.glb`.
    Glb,
}

impl InputFormat {
    /// Every input format.
    pub const ALL: [InputFormat; 6] = [
        InputFormat::Obj,
        InputFormat::Ply,
        InputFormat::Stl,
        InputFormat::Off,
        InputFormat::Gltf,
        InputFormat::Glb,
    ];

    /// The extension of the main file.
    pub fn extension(self) -> &'static str {
        match self {
            InputFormat::Obj => "obj",
            InputFormat::Ply => "ply",
            InputFormat::Stl => "stl",
            InputFormat::Off => "off",
            InputFormat::Gltf => "gltf",
            InputFormat::Glb => "glb",
        }
    }

    /// The name the sidecar is written under, for the formats that have one.
    pub fn sidecar(self) -> Option<&'static str> {
        match self {
            InputFormat::Obj => Some("m.mtl"),
            InputFormat::Gltf => Some("in.bin"),
            _ => None,
        }
    }
}

/// Output formats a run may write, picked by the input's hash.
const OUTPUTS: [&str; 6] = ["glb", "obj", "gltf", "ply", "stl", "off"];

/// Runs the whole pipeline on one fuzz input and panics on any broken
/// property. `data` is the main file, followed for OBJ and glTF by
/// [`SIDECAR_MARKER`] and the sidecar's bytes.
pub fn check_file(format: InputFormat, data: &[u8]) {
    let Ok(dir) = tempfile::tempdir() else {
        // No scratch space: nothing to test, and not the reader's fault.
        return;
    };
    let input_dir = dir.path().join("in");
    let output_dir = dir.path().join("out");
    if std::fs::create_dir(&input_dir).is_err() || std::fs::create_dir(&output_dir).is_err() {
        return;
    }
    let input = input_dir.join(format!("in.{}", format.extension()));
    let (main, sidecar) = split_sidecar(format, data);
    if std::fs::write(&input, main).is_err() {
        return;
    }
    if let (Some(name), Some(bytes)) = (format.sidecar(), sidecar) {
        if std::fs::write(input_dir.join(name), bytes).is_err() {
            return;
        }
    }
    let before = snapshot(&input_dir);
    let h = fnv1a(data);
    run(&input, &output_dir, h);
    assert_eq!(
        snapshot(&input_dir),
        before,
        "the input files changed (or a file appeared beside them)"
    );
}

/// The main file and the sidecar of a fuzz input.
pub fn split_sidecar(format: InputFormat, data: &[u8]) -> (&[u8], Option<&[u8]>) {
    if format.sidecar().is_none() {
        return (data, None);
    }
    match data
        .windows(SIDECAR_MARKER.len())
        .position(|w| w == SIDECAR_MARKER)
    {
        Some(at) => (&data[..at], Some(&data[at + SIDECAR_MARKER.len()..])),
        None => (data, None),
    }
}

fn run(input: &Path, output_dir: &Path, h: u64) {
    let mut doc = match wildlod_io::read(input) {
        Ok(doc) => doc,
        Err(e) => {
            assert_names_a_file(&e, input);
            return;
        }
    };
    if let Err(e) = doc.scene.validate() {
        panic!("the reader returned an invalid scene: {e}");
    }
    let options = options_for(h);
    for m in 0..doc.scene.meshes.len() {
        let mesh = &doc.scene.meshes[m];
        if mesh.faces.is_empty() {
            continue;
        }
        let outcome = simplify_mesh(mesh, &options);
        let (lod, report) = match outcome {
            Ok(r) => r,
            Err(e) => panic!("simplify_mesh refused a mesh the reader accepted: {e}"),
        };
        check_outcome(mesh, &options, &lod, &report);
        doc.scene.meshes[m] = lod;
    }
    let ext = OUTPUTS[(h >> 40) as usize % OUTPUTS.len()];
    write_and_read_back(&doc, &output_dir.join(format!("out.{ext}")));
}

/// The options of one run, drawn from the input's hash so that a crash
/// reproduces from the input alone.
fn options_for(h: u64) -> Options {
    let mut o = if (h >> 8) % 8 == 0 {
        Options::classic_qem()
    } else {
        Options::default()
    };
    let ratio = [0.5, 0.1, 0.01, 1.0, 0.0][(h >> 12) as usize % 5];
    o.target = Target {
        ratio: Some(ratio),
        triangles: ((h >> 16) % 4 == 0).then_some(((h >> 18) % 16) as usize),
        error: ((h >> 22) % 4 == 0).then_some(0.01),
    };
    o.quad.mode = [QuadMode::Auto, QuadMode::Never, QuadMode::Always][(h >> 24) as usize % 3];
    o.guards.keep_topology = (h >> 26) % 4 == 0;
    o.guards.lock_borders = (h >> 28) % 8 == 0;
    if (h >> 31) % 4 == 0 {
        // The parallel first phase, on meshes small enough to fuzz.
        o.partition = Partition {
            min_triangles: 8,
            chunk_faces: 16,
            ..Partition::default()
        };
    }
    if (h >> 33) % 8 == 0 {
        o.quad.symmetry = 1.0;
        o.quad.tangent_weight = 1.0 / 3.0;
    }
    o
}

fn write_and_read_back(doc: &Document, output: &Path) {
    let dir = output.parent().map(Path::to_path_buf).unwrap_or_default();
    match wildlod_io::write(doc, output, &WriteOptions::default()) {
        Err(e) => {
            assert_names_a_file(&e, output);
            let left: Vec<PathBuf> = list(&dir);
            assert!(
                left.is_empty(),
                "a failed write ({e}) left files behind: {left:?}"
            );
        }
        Ok(_) => {
            assert!(
                output.is_file(),
                "write succeeded but {output:?} is missing"
            );
            let left: Vec<PathBuf> = list(&dir)
                .into_iter()
                .filter(|p| p.extension().is_some_and(|e| e == "tmp"))
                .collect();
            assert!(left.is_empty(), "temporary files left behind: {left:?}");
            match wildlod_io::read(output) {
                Ok(back) => {
                    if let Err(e) = back.scene.validate() {
                        panic!("the written file reads back invalid: {e}");
                    }
                }
                Err(e) => panic!("wildlod cannot read back what it wrote: {e}"),
            }
        }
    }
}

/// An error must name a file of the run, and say so in its message.
fn assert_names_a_file(e: &wildlod_io::Error, expected_near: &Path) {
    let dir = expected_near.parent().unwrap_or(Path::new(""));
    let root = dir.parent().unwrap_or(dir);
    assert!(
        e.path.starts_with(root),
        "the error names {:?}, not a file of the run ({e})",
        e.path
    );
    let shown = e.to_string();
    let name = e
        .path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    assert!(
        shown.contains(&name),
        "the error message does not name the file: {shown}"
    );
}

fn list(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| rd.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

/// Every file of a folder with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    list(dir)
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap_or_default();
            (p, bytes)
        })
        .collect()
}
