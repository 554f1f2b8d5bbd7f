//! `wildlod report`: one self-contained HTML page with the input and its
//! level(s) of detail side by side in synchronized three.js viewers, the
//! metrics of `compare`, and the output colored by its distance to the
//! input. three.js (MIT, vendored in `assets/three/`) is inlined, so the
//! page works offline and can be mailed or archived as one file.

use std::path::Path;

use anyhow::{bail, Context};
use base64::Engine;
use rayon::prelude::*;
use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_geometry::TriangleSet;
use wildlod_io::{Document, OutputFiles};
use wildlod_mesh::{Image, Scene};

use wildlod_pipeline::{file_stem, Level};

use crate::args_assets::ReportArgs;
use crate::stdout::emit;

const TEMPLATE: &str = include_str!("../../assets/report.html");
const THREE: &str = include_str!("../../assets/three/three.module.min.js");

/// The top of the legend: this quantile of the face distances, so that a
/// few outliers do not wash the rest of the map out in blue.
const SCALE_QUANTILE: f64 = 0.99;

/// One mesh handed to the page.
#[derive(serde::Serialize)]
struct RefJson {
    label: String,
    triangles: usize,
    /// Little-endian f32 xyz, base64.
    positions: String,
    /// Little-endian u32 triangle corners, base64.
    indices: String,
}

#[derive(serde::Serialize)]
struct CandidateJson {
    label: String,
    triangles: usize,
    /// Little-endian f32 xyz, three corners per triangle (unshared), base64.
    positions: String,
    /// Little-endian f32 per triangle: distance to the reference / diagonal.
    distances: String,
    metrics: Comparison,
}

#[derive(serde::Serialize)]
struct PageJson {
    title: String,
    diagonal: f64,
    samples: usize,
    scale: f64,
    notes: Vec<String>,
    reference: RefJson,
    candidates: Vec<CandidateJson>,
}

fn b64_f32(v: impl Iterator<Item = f32>) -> String {
    let bytes: Vec<u8> = v.flat_map(f32::to_le_bytes).collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

fn b64_u32(v: impl Iterator<Item = u32>) -> String {
    let bytes: Vec<u8> = v.flat_map(u32::to_le_bytes).collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// Decodes the textures a scene references (for the texture metric); a
/// texture that cannot be read is left out, as `compare` does.
fn images(doc: &Document) -> Vec<Option<Image>> {
    doc.scene
        .textures
        .iter()
        .map(|t| wildlod_io::decode_image(&t.source).ok())
        .collect()
}

/// Largest distance from each candidate triangle to the reference surface
/// at its corners, edge midpoints and center (where a coarse face leaves
/// the surface most), relative to `diagonal`.
fn face_distances(reference: &TriangleSet, candidate: &EvalMesh, diagonal: f64) -> Vec<f32> {
    let scale = if diagonal > 0.0 { 1.0 / diagonal } else { 1.0 };
    (0..candidate.triangles().len())
        .into_par_iter()
        .map(|t| {
            let [a, b, c] = candidate.triangle(t);
            let points = [
                a,
                b,
                c,
                (a + b) * 0.5,
                (b + c) * 0.5,
                (c + a) * 0.5,
                (a + b + c) / 3.0,
            ];
            let d2 = points
                .iter()
                .filter_map(|&p| reference.distance2(p))
                .fold(0.0f64, f64::max);
            (d2.sqrt() * scale) as f32
        })
        .collect()
}

/// The page for `reference` and its `candidates` (label, scene, images).
pub(crate) fn build_page(
    title: &str,
    reference: (&str, &Scene, &[Option<Image>]),
    candidates: &[(String, Scene, &[Option<Image>])],
    samples: usize,
) -> anyhow::Result<String> {
    if candidates.is_empty() {
        bail!("a report needs at least one candidate");
    }
    let posed_ref = wildlod_eval::posed(reference.1, None, 0.0);
    let r = EvalMesh::from_scene(&posed_ref, reference.2);
    let ref_set = TriangleSet::new(r.positions(), r.triangles());
    let options = CompareOptions {
        samples,
        ..CompareOptions::default()
    };
    let mut notes = Vec::new();
    if r.triangles().is_empty() {
        notes.push("The input shows no triangle.".to_string());
    }
    let mut out = Vec::with_capacity(candidates.len());
    let mut all = Vec::new();
    let mut diagonal = 0.0;
    for (label, scene, imgs) in candidates {
        let posed = wildlod_eval::posed(scene, None, 0.0);
        let c = EvalMesh::from_scene(&posed, imgs);
        let metrics = compare(&r, &c, &options);
        diagonal = metrics.diagonal;
        let distances = face_distances(&ref_set, &c, metrics.diagonal);
        all.extend_from_slice(&distances);
        let positions = b64_f32(
            c.triangles()
                .iter()
                .flat_map(|t| t.iter().map(|&v| c.positions()[v as usize]))
                .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]),
        );
        out.push(CandidateJson {
            label: label.clone(),
            triangles: c.triangles().len(),
            positions,
            distances: b64_f32(distances.into_iter()),
            metrics,
        });
    }
    all.sort_by(|a, b| a.total_cmp(b));
    let scale = match all.len() {
        0 => 0.0,
        n => all[((n - 1) as f64 * SCALE_QUANTILE).round() as usize] as f64,
    };
    let page = PageJson {
        title: title.to_string(),
        diagonal,
        samples,
        scale,
        notes,
        reference: RefJson {
            label: reference.0.to_string(),
            triangles: r.triangles().len(),
            positions: b64_f32(
                r.positions()
                    .iter()
                    .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]),
            ),
            indices: b64_u32(r.triangles().iter().flatten().copied()),
        },
        candidates: out,
    };
    let json = serde_json::to_string(&page).context("serializing the report data")?;
    // Inside <script>, "</" could end the element: JSON allows "\/".
    let json = json.replace("</", "<\\/");
    let three = base64::engine::general_purpose::STANDARD.encode(THREE);
    Ok(TEMPLATE
        .replace("{{TITLE}}", &html_escape(title))
        .replace("{{THREE_BASE64}}", &three)
        .replace("{{DATA}}", &json))
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes `html` to `path` all-or-nothing, never over `inputs` unless
/// `overwrite`.
fn write_html(path: &Path, html: String, inputs: &[&Path], overwrite: bool) -> anyhow::Result<()> {
    let mut files = OutputFiles::new(None, overwrite);
    for i in inputs {
        files.protect(i);
    }
    files
        .add(path, html.into_bytes())
        .map_err(|e| wildlod_io::Error::new(path, e))?;
    files
        .commit()
        .map_err(|e| wildlod_io::Error::new(path, e))?;
    Ok(())
}

/// Runs `report`.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    if a.samples == 0 {
        bail!("--samples must be at least 1");
    }
    let reference = wildlod_io::read(&a.reference)?;
    let candidate = wildlod_io::read(&a.candidate)?;
    let ri = images(&reference);
    let ci = images(&candidate);
    let r_label = file_name(&a.reference);
    let c_label = file_name(&a.candidate);
    let html = build_page(
        &format!("wildlod report: {c_label} against {r_label}"),
        (&r_label, &reference.scene, &ri),
        &[(c_label, candidate.scene, &ci)],
        a.samples,
    )?;
    write_html(&a.output, html, &[&a.reference, &a.candidate], a.overwrite)?;
    if !a.quiet {
        emit(&format!("wrote {}\n", a.output.display()))?;
    }
    Ok(())
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

/// The report of a chain: the input against every level (`lod --report`).
pub(crate) fn write_chain_report(
    doc: &Document,
    input: &Path,
    levels: &[Level],
    path: &Path,
    overwrite: bool,
) -> anyhow::Result<()> {
    let imgs = images(doc);
    let stem = file_stem(input);
    let candidates: Vec<(String, Scene, &[Option<Image>])> = levels
        .iter()
        .map(|l| {
            let mut scene = doc.scene.clone();
            scene.meshes = l.meshes.clone();
            (format!("lod{}", l.level), scene, imgs.as_slice())
        })
        .collect();
    let html = build_page(
        &format!("wildlod report: levels of detail of {}", file_name(input)),
        (&format!("{stem} (lod0)"), &doc.scene, &imgs),
        &candidates,
        CompareOptions::default().samples,
    )?;
    write_html(path, html, &[input], overwrite)
}
