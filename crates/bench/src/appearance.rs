//! The appearance evaluation behind `evaluate-appearance`: every textured
//! and skinned glTF of the corpus simplified by wildlod and by the peers a
//! technical artist would otherwise use (gltfpack, Blender's Decimate),
//! measured in one place: texture Chamfer (W Table 2), normal Chamfer,
//! Hausdorff and Chamfer at rest, and for animated files the distances
//! posed at frames of the first animation (Knodt 2024 §4).
//!
//! Peers are external programs, run as the user would run them; a peer
//! that is not installed or fails on a file is a row that says so.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use wildlod_eval::{compare, posed, CompareOptions, EvalMesh};
use wildlod_mesh::Image;

/// A simplifier run as a command line.
#[derive(Clone, Debug)]
pub struct Peer {
    /// Name in the report.
    pub name: String,
    /// The command: `{input}`, `{output}` and `{ratio}` are replaced.
    pub command: Vec<String>,
}

impl Peer {
    /// Runs the peer; returns the seconds it took or why it failed.
    fn run(&self, input: &Path, output: &Path, ratio: f64) -> Result<f64, String> {
        let args: Vec<String> = self
            .command
            .iter()
            .map(|a| {
                a.replace("{input}", &input.display().to_string())
                    .replace("{output}", &output.display().to_string())
                    .replace("{ratio}", &ratio.to_string())
            })
            .collect();
        let (exe, rest) = args.split_first().ok_or("empty command")?;
        let t0 = Instant::now();
        let o = Command::new(exe)
            .args(rest)
            .output()
            .map_err(|e| format!("{exe}: {e}"))?;
        let seconds = t0.elapsed().as_secs_f64();
        if !o.status.success() || !output.exists() {
            let err = String::from_utf8_lossy(&o.stderr);
            let last = err.lines().last().unwrap_or("").to_string();
            return Err(format!("exit {:?}: {last}", o.status.code()));
        }
        Ok(seconds)
    }
}

/// Measurements of one output.
#[derive(Clone, Debug, Default)]
pub struct Measure {
    /// Triangles, counted per instance.
    pub triangles: usize,
    /// Texture Chamfer (W Table 2), when both sides are textured.
    pub texture_chamfer: Option<f64>,
    /// Normal Chamfer in degrees.
    pub normal_chamfer: Option<f64>,
    /// Hausdorff distance at rest (relative to the diagonal).
    pub hausdorff: f64,
    /// Chamfer distance (mean) at rest.
    pub chamfer: f64,
    /// Posed at the frames: (mean Hausdorff, worst Hausdorff, mean
    /// Chamfer, worst Chamfer), for animated inputs.
    pub posed: Option<[f64; 4]>,
    /// Seconds the simplifier took (whole command, I/O included).
    pub seconds: f64,
}

/// One row of the report.
#[derive(Clone, Debug)]
pub struct Row {
    /// The input, relative to the corpus.
    pub file: String,
    /// Target ratio.
    pub ratio: f64,
    /// Simplifier.
    pub peer: String,
    /// Its measurements, or why there are none.
    pub result: Result<Measure, String>,
}

/// Evaluation settings.
#[derive(Clone, Debug)]
pub struct Config {
    /// The input files.
    pub files: Vec<(String, PathBuf)>,
    /// Target ratios.
    pub ratios: Vec<f64>,
    /// Simplifiers.
    pub peers: Vec<Peer>,
    /// Surface samples for distances.
    pub samples: usize,
    /// Texture and normal samples.
    pub texture_samples: usize,
    /// Animation frames (at 30 fps) for animated inputs; 0: none.
    pub frames: usize,
    /// Where outputs go.
    pub work: PathBuf,
}

fn images(doc: &wildlod_io::Document) -> Vec<Option<Image>> {
    doc.scene
        .textures
        .iter()
        .map(|t| wildlod_io::decode_image(&t.source).ok())
        .collect()
}

/// Compares `output` with the input `doc` (whose decoded textures are
/// `input_images`).
fn measure(
    doc: &wildlod_io::Document,
    input_images: &[Option<Image>],
    output: &Path,
    cfg: &Config,
) -> Result<Measure, String> {
    let out = wildlod_io::read(output).map_err(|e| e.to_string())?;
    let out_images = images(&out);
    let options = CompareOptions {
        samples: cfg.samples,
        texture_samples: cfg.texture_samples,
        ..CompareOptions::default()
    };
    let rest_in = posed(&doc.scene, None, 0.0);
    let rest_out = posed(&out.scene, None, 0.0);
    let c = compare(
        &EvalMesh::from_scene(&rest_in, input_images),
        &EvalMesh::from_scene(&rest_out, &out_images),
        &options,
    );
    let animated = !doc.scene.skins.is_empty() && !doc.scene.animations.is_empty();
    let posed_distances =
        (animated && cfg.frames > 0 && !out.scene.animations.is_empty()).then(|| {
            let duration = doc.scene.animations[0].duration as f64;
            let mut frames = Vec::new();
            for k in 0..cfg.frames {
                let t = (k as f64 / 30.0).min(duration) as f32;
                let pc = compare(
                    &EvalMesh::from_scene(&posed(&doc.scene, Some(0), t), &[]),
                    &EvalMesh::from_scene(&posed(&out.scene, Some(0), t), &[]),
                    &CompareOptions {
                        texture_samples: 0,
                        ..options
                    },
                );
                frames.push((pc.hausdorff, pc.chamfer_mean));
            }
            let n = frames.len() as f64;
            [
                frames.iter().map(|f| f.0).sum::<f64>() / n,
                frames.iter().map(|f| f.0).fold(0.0, f64::max),
                frames.iter().map(|f| f.1).sum::<f64>() / n,
                frames.iter().map(|f| f.1).fold(0.0, f64::max),
            ]
        });
    Ok(Measure {
        triangles: c.candidate.triangulated,
        texture_chamfer: c.texture_chamfer,
        normal_chamfer: c.normal_chamfer,
        hausdorff: c.hausdorff,
        chamfer: c.chamfer_mean,
        posed: posed_distances,
        seconds: 0.0,
    })
}

/// Runs every peer on every file at every ratio; `progress` is told each
/// row as it is done.
pub fn evaluate(cfg: &Config, progress: impl Fn(&Row)) -> Vec<Row> {
    let mut rows = Vec::new();
    for (name, path) in &cfg.files {
        let doc = match wildlod_io::read(path) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("skipping {name}: {e}");
                continue;
            }
        };
        let input_images = images(&doc);
        for &ratio in &cfg.ratios {
            for (k, peer) in cfg.peers.iter().enumerate() {
                let output = cfg.work.join(format!("out_{k}.glb"));
                let _ = std::fs::remove_file(&output);
                let result = peer.run(path, &output, ratio).and_then(|seconds| {
                    let mut m = measure(&doc, &input_images, &output, cfg)?;
                    m.seconds = seconds;
                    Ok(m)
                });
                let row = Row {
                    file: name.clone(),
                    ratio,
                    peer: peer.name.clone(),
                    result,
                };
                progress(&row);
                rows.push(row);
            }
        }
    }
    rows
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("–".into(), |x| format!("{x:.digits$}"))
}

/// The rows as markdown: one table per ratio, then the summary of where
/// wildlod's texture Chamfer is at most each peer's.
pub fn markdown(rows: &[Row], cfg: &Config) -> String {
    let mut s = String::new();
    for &ratio in &cfg.ratios {
        s += &format!(
            "\n### {}%\n\n| file | simplifier | triangles | texture Chamfer | normal Chamfer (°) | Hausdorff | Chamfer | posed Hausdorff mean / worst | posed Chamfer mean / worst | seconds |\n|---|---|---|---|---|---|---|---|---|---|\n",
            ratio * 100.0
        );
        for r in rows.iter().filter(|r| r.ratio == ratio) {
            match &r.result {
                Ok(m) => {
                    let posed = m.posed.map_or(("–".into(), "–".into()), |p| {
                        (
                            format!("{:.4} / {:.4}", p[0], p[1]),
                            format!("{:.5} / {:.5}", p[2], p[3]),
                        )
                    });
                    s += &format!(
                        "| {} | {} | {} | {} | {} | {:.4} | {:.5} | {} | {} | {:.2} |\n",
                        r.file,
                        r.peer,
                        m.triangles,
                        opt(m.texture_chamfer, 4),
                        opt(m.normal_chamfer, 1),
                        m.hausdorff,
                        m.chamfer,
                        posed.0,
                        posed.1,
                        m.seconds
                    );
                }
                Err(e) => {
                    s += &format!(
                        "| {} | {} | failed: {} | | | | | | | |\n",
                        r.file, r.peer, e
                    )
                }
            }
        }
    }
    s
}
