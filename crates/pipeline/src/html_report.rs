//! The HTML report of `wildlod report`, `wildlod lod --report` and
//! `wildlod.report`: one self-contained page with the input and its
//! level(s) of detail side by side in synchronized three.js viewers, each
//! drawn textured as the file shows it, as an error heat map, or as a
//! wireframe; the metrics of `compare`; and for a chain, a slider through
//! the levels. three.js (MIT, vendored in `assets/three/`) and the base
//! color images (scaled to at most [`ReportOptions::max_texture_size`]
//! texels) are inlined, so the page works offline and can be mailed or
//! archived as one file.

use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

use base64::Engine;
use glam::DVec3;
use rayon::prelude::*;
use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_geometry::TriangleSet;
use wildlod_io::{Document, ImageEncoding, OutputFiles};
use wildlod_mesh::shapes::triangulate;
use wildlod_mesh::transform::transformed;
use wildlod_mesh::{AlphaMode, Attribute, Image, Rgba8Image, Scene, Semantic, Wrap, ABSENT};

use crate::{file_stem, load_images, Error, Level};

const TEMPLATE: &str = include_str!("../assets/report.html");
const THREE: &str = include_str!("../assets/three/three.module.min.js");

/// The top of the heat map's legend: this quantile of the face distances,
/// so that a few outliers do not wash the rest of the map out in blue.
const SCALE_QUANTILE: f64 = 0.99;

/// How a report is made.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportOptions {
    /// Area samples per surface for the metrics (as `compare --samples`;
    /// at least 1). Default: `compare`'s, 100 000.
    pub samples: usize,
    /// Largest side, in texels, of an image embedded in the page: larger
    /// ones are scaled down by a whole factor (box filter), which keeps the
    /// page small and is plenty for a viewer a few hundred pixels wide.
    /// Default: 1024.
    pub max_texture_size: u32,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            samples: CompareOptions::default().samples,
            max_texture_size: 1024,
        }
    }
}

/// One model of a report: a scene and its decoded images.
#[derive(Clone, Copy, Debug)]
pub struct ReportModel<'a> {
    /// Its name on the page.
    pub label: &'a str,
    /// The scene.
    pub scene: &'a Scene,
    /// The decoded image of every texture of `scene` (`None`: not drawn).
    pub images: &'a [Option<Image>],
    /// Which file the scene's textures come from: models with the same
    /// `source` share their images on the page (the levels of a chain).
    pub source: usize,
    /// A chain level's accumulated error (relative to the diagonal), shown
    /// beside the measured distances.
    pub chain_error: Option<f64>,
}

/// What the report page shows of one candidate, as `report --json`
/// prints it (keys documented in docs/cli.md).
#[derive(Clone, Debug, serde::Serialize)]
pub struct CandidateReport {
    /// Its name on the page.
    pub label: String,
    /// Triangles drawn (each mesh once per node that shows it).
    pub triangles: usize,
    /// A chain level's accumulated error, relative to the diagonal.
    pub chain_error: Option<f64>,
    /// The metrics of `compare` against the reference.
    pub metrics: Comparison,
}

/// `report --json`: what the page holds.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ReportJson {
    /// The HTML file written.
    pub output: String,
    /// The reference's name on the page.
    pub reference: String,
    /// Triangles the reference draws.
    pub reference_triangles: usize,
    /// Every candidate, in the page's order.
    pub candidates: Vec<CandidateReport>,
    /// Area samples per surface of the metrics.
    pub samples: usize,
    /// Wall time (read, measure, write).
    pub seconds: f64,
}

fn b64<T: Copy, const N: usize>(v: impl Iterator<Item = T>, bytes: fn(T) -> [u8; N]) -> String {
    let raw: Vec<u8> = v.flat_map(bytes).collect();
    base64::engine::general_purpose::STANDARD.encode(raw)
}

fn b64_f32(v: impl Iterator<Item = f32>) -> String {
    b64(v, f32::to_le_bytes)
}

fn b64_u32(v: impl Iterator<Item = u32>) -> String {
    b64(v, u32::to_le_bytes)
}

/// A material of a model on the page.
#[derive(serde::Serialize)]
struct MaterialJson {
    /// Base color factor, linear RGBA.
    color: [f32; 4],
    /// Index into the page's textures.
    texture: Option<usize>,
    /// `opaque`, `mask` or `blend`.
    alpha: &'static str,
    cutoff: f32,
}

/// A model on the page: indexed triangles, the streams the textured view
/// needs, and one group of triangles per material.
#[derive(serde::Serialize)]
struct ModelJson {
    label: String,
    triangles: usize,
    /// Little-endian f32 xyz per vertex, base64.
    positions: String,
    /// Little-endian f32 xyz per vertex; absent: flat shading.
    normals: Option<String>,
    /// Little-endian f32 uv per vertex (the base color texture's set).
    uvs: Option<String>,
    /// Little-endian f32 rgb per vertex (`COLOR_0`, white where absent).
    colors: Option<String>,
    /// Little-endian u32 triangle corners, base64.
    indices: String,
    /// (first index, index count, material) of each run of triangles.
    groups: Vec<[usize; 3]>,
    materials: Vec<MaterialJson>,
    /// Candidates: little-endian f32 per triangle, distance to the
    /// reference / diagonal, in the order of `indices`.
    #[serde(skip_serializing_if = "Option::is_none")]
    distances: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    metrics: Option<Comparison>,
    #[serde(skip_serializing_if = "Option::is_none")]
    chain_error: Option<f64>,
}

#[derive(serde::Serialize)]
struct TextureJson {
    /// A `data:` URI of the image.
    uri: String,
    /// `repeat`, `mirror` or `clamp` along u and v.
    wrap: [&'static str; 2],
}

#[derive(serde::Serialize)]
struct PageJson {
    title: String,
    diagonal: f64,
    samples: usize,
    scale: f64,
    notes: Vec<String>,
    /// `textured` when a model has a texture or vertex colors, else `heat`.
    default_mode: &'static str,
    textures: Vec<TextureJson>,
    reference: ModelJson,
    candidates: Vec<ModelJson>,
}

fn wrap_name(w: Wrap) -> &'static str {
    match w {
        Wrap::Repeat => "repeat",
        Wrap::MirroredRepeat => "mirror",
        Wrap::ClampToEdge => "clamp",
    }
}

/// An image as 8-bit RGBA at most `max` texels on a side: whole-factor
/// box filtering, so every output texel averages the same number of
/// input texels.
fn page_image(img: &Image, max: u32) -> Rgba8Image {
    let f = img.width.max(img.height).div_ceil(max.max(1)).max(1);
    let (w, h) = ((img.width / f).max(1), (img.height / f).max(1));
    let mut pixels = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0f32; 4];
            let mut n = 0f32;
            for yy in y * f..((y + 1) * f).min(img.height) {
                for xx in x * f..((x + 1) * f).min(img.width) {
                    let p = img.texel(xx as i64, yy as i64);
                    for k in 0..4 {
                        sum[k] += p[k];
                    }
                    n += 1.0;
                }
            }
            pixels.push(sum.map(|s| (s / n.max(1.0) * 255.0).round().clamp(0.0, 255.0) as u8));
        }
    }
    Rgba8Image {
        width: w,
        height: h,
        pixels,
    }
}

/// The page's images: each texture of each source once, as a data URI
/// (JPEG when opaque, PNG with alpha).
struct Textures {
    list: Vec<TextureJson>,
    index: HashMap<(usize, u32), Option<usize>>,
    max: u32,
}

impl Textures {
    fn get(&mut self, model: &ReportModel, texture: u32) -> Option<usize> {
        if let Some(&i) = self.index.get(&(model.source, texture)) {
            return i;
        }
        let made = (|| {
            let img = model.images.get(texture as usize)?.as_ref()?;
            let t = model.scene.textures.get(texture as usize)?;
            let small = page_image(img, self.max);
            let opaque = small.pixels.iter().all(|p| p[3] == 255);
            let encoding = if opaque {
                ImageEncoding::Jpeg { quality: 85 }
            } else {
                ImageEncoding::Png
            };
            let bytes = wildlod_io::encode_image(&small, encoding, &t.name).ok()?;
            self.list.push(TextureJson {
                uri: format!(
                    "data:{};base64,{}",
                    encoding.mime_type(),
                    base64::engine::general_purpose::STANDARD.encode(bytes)
                ),
                wrap: [wrap_name(t.sampler.wrap_u), wrap_name(t.sampler.wrap_v)],
            });
            Some(self.list.len() - 1)
        })();
        self.index.insert((model.source, texture), made);
        made
    }
}

/// A model flattened for the page, with its world-space triangles in the
/// page's order (for the distances).
struct Flat {
    json: ModelJson,
    corners: Vec<[DVec3; 3]>,
    /// Whether anything is drawn from a texture or vertex colors.
    appearance: bool,
}

/// Value `i` of an optional stream (`None` for [`ABSENT`]).
fn value(a: Option<&Attribute>, i: u32) -> Option<&[f32]> {
    a.filter(|_| i != ABSENT).map(|a| a.value(i))
}

/// Value index of a corner in an optional stream, or [`ABSENT`].
fn value_index(a: Option<&Attribute>, corner: usize) -> u32 {
    a.and_then(|a| a.indices.get(corner).copied())
        .filter(|&i| i != ABSENT && (i as usize) < a.map_or(0, Attribute::value_count))
        .unwrap_or(ABSENT)
}

/// Flattens every mesh instance of `model.scene` (posed as `compare`
/// measures it, about `origin`: see `wildlod_eval::posed_about`) into
/// indexed triangles grouped by material. A vertex is a
/// distinct (position, UV, normal, color, part) of a mesh instance, so UV
/// seams and hard edges stay as the file has them.
fn flatten(model: &ReportModel, textures: &mut Textures, origin: [f64; 3]) -> Flat {
    let scene = wildlod_eval::posed_about(model.scene, None, 0.0, origin);
    let mut materials: Vec<MaterialJson> = scene
        .materials
        .iter()
        .map(|m| MaterialJson {
            color: m.base_color,
            texture: m
                .base_color_texture
                .and_then(|t| textures.get(model, t.texture)),
            alpha: match m.alpha_mode {
                AlphaMode::Opaque => "opaque",
                AlphaMode::Mask => "mask",
                AlphaMode::Blend => "blend",
            },
            cutoff: m.alpha_cutoff,
        })
        .collect();
    // Faces without a material: glTF's default, white.
    let default_material = materials.len();
    materials.push(MaterialJson {
        color: [1.0; 4],
        texture: None,
        alpha: "opaque",
        cutoff: 0.5,
    });
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut normals: Vec<Option<[f32; 3]>> = Vec::new();
    let mut uvs: Vec<[f32; 2]> = Vec::new();
    let mut colors: Vec<Option<[f32; 3]>> = Vec::new();
    // Triangles and their world corners, per material.
    let mut buckets: Vec<Vec<([u32; 3], [DVec3; 3])>> = Vec::new();
    buckets.resize_with(materials.len(), Vec::new);
    for (mi, matrix) in scene.instances() {
        let Some(mesh) = scene.meshes.get(mi as usize) else {
            continue;
        };
        let tri = triangulate(&transformed(mesh, &matrix));
        let normal_stream = tri
            .attribute(&Semantic::Normal)
            .filter(|a| a.components == 3);
        let color_stream = tri
            .attribute(&Semantic::Color(0))
            .filter(|a| a.components >= 3);
        let parts: Vec<(usize, Option<&Attribute>)> = tri
            .parts
            .iter()
            .map(|p| {
                let m = p
                    .material
                    .map(|m| m as usize)
                    .filter(|&m| m < default_material);
                let set = m
                    .and_then(|m| scene.materials[m].base_color_texture)
                    .map(|t| t.tex_coord);
                let uv = set
                    .and_then(|s| tri.attribute(&Semantic::TexCoord(s)))
                    .filter(|a| a.components >= 2);
                (m.unwrap_or(default_material), uv)
            })
            .collect();
        let np = tri.positions.len();
        let finite =
            |v: u32| (v as usize) < np && tri.positions[v as usize].iter().all(|x| x.is_finite());
        let mut vertex: HashMap<[u32; 5], u32> = HashMap::new();
        for f in 0..tri.faces.len() {
            let face = tri.faces.face(f);
            if face.len() != 3 || !face.iter().all(|&v| finite(v)) {
                continue;
            }
            let part = tri.face_parts.get(f).copied().unwrap_or(0);
            let (material, uv) = parts
                .get(part as usize)
                .copied()
                .unwrap_or((default_material, None));
            let mut ids = [0u32; 3];
            for (k, c) in tri.faces.corner_range(f).enumerate() {
                let p = face[k];
                let key = [
                    p,
                    value_index(uv, c),
                    value_index(normal_stream, c),
                    value_index(color_stream, c),
                    part,
                ];
                ids[k] = *vertex.entry(key).or_insert_with(|| {
                    positions.push(tri.positions[p as usize]);
                    uvs.push(value(uv, key[1]).map_or([0.0; 2], |v| [v[0], v[1]]));
                    normals.push(value(normal_stream, key[2]).map(|v| [v[0], v[1], v[2]]));
                    colors.push(value(color_stream, key[3]).map(|v| [v[0], v[1], v[2]]));
                    positions.len() as u32 - 1
                });
            }
            let corners =
                [0, 1, 2].map(|k| DVec3::from(tri.positions[face[k] as usize].map(f64::from)));
            buckets[material].push((ids, corners));
        }
    }
    let textured_material = |m: &MaterialJson| m.texture.is_some();
    let used_textured = buckets
        .iter()
        .zip(&materials)
        .any(|(b, m)| !b.is_empty() && textured_material(m));
    let has_colors = colors.iter().any(Option::is_some);
    let has_normals = !normals.is_empty() && normals.iter().all(Option::is_some);
    let mut indices = Vec::new();
    let mut corners = Vec::new();
    let mut groups = Vec::new();
    for (m, bucket) in buckets.into_iter().enumerate() {
        if bucket.is_empty() {
            continue;
        }
        groups.push([indices.len(), 3 * bucket.len(), m]);
        for (ids, c) in bucket {
            indices.extend_from_slice(&ids);
            corners.push(c);
        }
    }
    Flat {
        json: ModelJson {
            label: model.label.to_string(),
            triangles: corners.len(),
            positions: b64_f32(positions.iter().flatten().copied()),
            normals: has_normals.then(|| b64_f32(normals.iter().flatten().flatten().copied())),
            uvs: used_textured.then(|| b64_f32(uvs.iter().flatten().copied())),
            colors: has_colors.then(|| b64_f32(colors.iter().flat_map(|c| c.unwrap_or([1.0; 3])))),
            indices: b64_u32(indices.into_iter()),
            groups,
            materials,
            distances: None,
            metrics: None,
            chain_error: model.chain_error,
        },
        corners,
        appearance: used_textured || has_colors,
    }
}

/// Largest distance from each triangle to the reference surface at its
/// corners, edge midpoints and center (where a coarse face leaves the
/// surface most), relative to `diagonal`.
fn face_distances(reference: &TriangleSet, triangles: &[[DVec3; 3]], diagonal: f64) -> Vec<f32> {
    let scale = if diagonal > 0.0 { 1.0 / diagonal } else { 1.0 };
    triangles
        .par_iter()
        .map(|&[a, b, c]| {
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

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The page for `reference` and its `candidates` (at least one), and what
/// it shows as [`ReportJson`] (with `output` and `seconds` left empty).
pub fn report_page(
    title: &str,
    reference: &ReportModel,
    candidates: &[ReportModel],
    options: &ReportOptions,
) -> Result<(String, ReportJson), Error> {
    if candidates.is_empty() {
        return Err(Error::Usage("a report needs at least one candidate".into()));
    }
    if options.samples == 0 {
        return Err(Error::setting("samples", "at least 1", 0.0));
    }
    let compare_options = CompareOptions {
        samples: options.samples,
        ..CompareOptions::default()
    };
    let mut textures = Textures {
        list: Vec::new(),
        index: HashMap::new(),
        max: options.max_texture_size,
    };
    // Every model about the reference's first instance (see
    // `wildlod_eval::posed_about`).
    let origin = wildlod_eval::pose_origin(reference.scene);
    let posed_ref = wildlod_eval::posed_about(reference.scene, None, 0.0, origin);
    let r = EvalMesh::from_scene(&posed_ref, reference.images);
    let ref_flat = flatten(reference, &mut textures, origin);
    let ref_set = TriangleSet::new(r.positions(), r.triangles());
    let mut notes = Vec::new();
    if r.triangles().is_empty() {
        notes.push("The input shows no triangle.".to_string());
    }
    let mut appearance = ref_flat.appearance;
    let mut out = Vec::with_capacity(candidates.len());
    let mut all = Vec::new();
    let mut diagonal = 0.0;
    for c in candidates {
        let posed = wildlod_eval::posed_about(c.scene, None, 0.0, origin);
        let metrics = compare(
            &r,
            &EvalMesh::from_scene(&posed, c.images),
            &compare_options,
        );
        diagonal = metrics.diagonal;
        let mut flat = flatten(c, &mut textures, origin);
        appearance |= flat.appearance;
        let distances = face_distances(&ref_set, &flat.corners, metrics.diagonal);
        all.extend_from_slice(&distances);
        flat.json.distances = Some(b64_f32(distances.into_iter()));
        flat.json.metrics = Some(metrics);
        out.push(flat.json);
    }
    all.sort_by(|a, b| a.total_cmp(b));
    let scale = match all.len() {
        0 => 0.0,
        n => all[((n - 1) as f64 * SCALE_QUANTILE).round() as usize] as f64,
    };
    let report = ReportJson {
        output: String::new(),
        reference: ref_flat.json.label.clone(),
        reference_triangles: ref_flat.json.triangles,
        candidates: out
            .iter()
            .filter_map(|c| {
                Some(CandidateReport {
                    label: c.label.clone(),
                    triangles: c.triangles,
                    chain_error: c.chain_error,
                    metrics: c.metrics.clone()?,
                })
            })
            .collect(),
        samples: options.samples,
        seconds: 0.0,
    };
    let page = PageJson {
        title: title.to_string(),
        diagonal,
        samples: options.samples,
        scale,
        notes,
        default_mode: if appearance { "textured" } else { "heat" },
        textures: textures.list,
        reference: ref_flat.json,
        candidates: out,
    };
    let json = serde_json::to_string(&page)?;
    // Inside <script>, "</" could end the element: JSON allows "\/".
    let json = json.replace("</", "<\\/");
    let three = base64::engine::general_purpose::STANDARD.encode(THREE);
    let html = TEMPLATE
        .replace("{{TITLE}}", &html_escape(title))
        .replace("{{THREE_BASE64}}", &three)
        .replace("{{DATA}}", &json);
    Ok((html, report))
}

/// Writes `html` to `path` all-or-nothing, never over `inputs` unless
/// `overwrite`.
fn write_html(path: &Path, html: String, inputs: &[&Path], overwrite: bool) -> Result<(), Error> {
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

/// The name of a file on the page.
fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

/// `wildlod report REFERENCE CANDIDATE -o OUTPUT`: reads both files, writes
/// the page (never over an input unless `overwrite`), and returns what it
/// shows and the readers' warnings (textures that could not be decoded
/// are drawn untextured and named there).
pub fn report_files(
    reference: &Path,
    candidate: &Path,
    output: &Path,
    options: &ReportOptions,
    overwrite: bool,
) -> Result<(ReportJson, Vec<String>), Error> {
    let t0 = Instant::now();
    if options.samples == 0 {
        return Err(Error::setting("samples", "at least 1", 0.0));
    }
    let r = wildlod_io::read(reference)?;
    let c = wildlod_io::read(candidate)?;
    let (ri, mut warnings) = load_images(&r, reference);
    let (ci, more) = load_images(&c, candidate);
    warnings.extend(more);
    let (r_label, c_label) = (file_name(reference), file_name(candidate));
    let (html, mut report) = report_page(
        &format!("wildlod report: {c_label} against {r_label}"),
        &ReportModel {
            label: &r_label,
            scene: &r.scene,
            images: &ri,
            source: 0,
            chain_error: None,
        },
        &[ReportModel {
            label: &c_label,
            scene: &c.scene,
            images: &ci,
            source: 1,
            chain_error: None,
        }],
        options,
    )?;
    write_html(output, html, &[reference, candidate], overwrite)?;
    report.output = output.display().to_string();
    report.seconds = t0.elapsed().as_secs_f64();
    Ok((report, warnings))
}

/// A level as the chain's report shows it: label, scene, accumulated
/// error, and its own images when it was re-baked.
type LevelView = (String, Scene, f64, Option<Vec<Option<Image>>>);

/// The report of a chain (`lod --report`): the input (`doc`, read from
/// `input`) against every level, with a slider through the levels.
pub fn write_chain_report(
    doc: &Document,
    input: &Path,
    levels: &[Level],
    path: &Path,
    overwrite: bool,
) -> Result<ReportJson, Error> {
    let t0 = Instant::now();
    let (images, _) = load_images(doc, input);
    let stem = file_stem(input);
    // A re-baked level shows its own atlas (embedded, so the path is
    // only a name for warnings).
    let scenes: Vec<LevelView> = levels
        .iter()
        .map(|l| {
            let scene = l.scene(&doc.scene);
            let own_images = l.own_materials.as_ref().map(|_| {
                let mut level_doc = doc.clone();
                level_doc.scene = scene.clone();
                load_images(&level_doc, input).0
            });
            (format!("lod{}", l.level), scene, l.error, own_images)
        })
        .collect();
    let candidates: Vec<ReportModel> = scenes
        .iter()
        .map(|(label, scene, error, own_images)| ReportModel {
            label,
            scene,
            images: own_images.as_ref().unwrap_or(&images),
            source: 0,
            chain_error: Some(*error),
        })
        .collect();
    let ref_label = format!("{stem} (lod0)");
    let (html, mut report) = report_page(
        &format!("wildlod report: levels of detail of {}", file_name(input)),
        &ReportModel {
            label: &ref_label,
            scene: &doc.scene,
            images: &images,
            source: 0,
            chain_error: None,
        },
        &candidates,
        &ReportOptions::default(),
    )?;
    write_html(path, html, &[input], overwrite)?;
    report.output = path.display().to_string();
    report.seconds = t0.elapsed().as_secs_f64();
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_images_shrink_by_a_whole_factor_averaging_their_texels() {
        // 5 × 3 texels, at most 2 a side: factor 3, one output texel of
        // the top-left 3 × 3 block (texels 0.0 and 0.9 alternating).
        let mut img = Image::filled(5, 3, [0.0; 4]);
        for (k, p) in img.pixels.iter_mut().enumerate() {
            *p = if k % 2 == 0 {
                [0.0, 0.0, 0.0, 1.0]
            } else {
                [0.9, 0.9, 0.9, 1.0]
            };
        }
        let small = page_image(&img, 2);
        assert_eq!((small.width, small.height), (1, 1));
        // Row-major, 5 wide: the block holds k = 0,1,2,5,6,7,10,11,12, of
        // which 1, 5, 7, 11 are odd: 4 × 0.9 / 9 = 0.4 → 102.
        assert_eq!(small.pixels[0], [102, 102, 102, 255]);
        // Small enough already: copied, rounded to 8 bits.
        let same = page_image(&img, 8);
        assert_eq!((same.width, same.height), (5, 3));
        assert_eq!(same.pixels[1], [230, 230, 230, 255]);
    }

    #[test]
    fn a_uv_seam_splits_a_vertex_and_materials_group_the_triangles() {
        use wildlod_mesh::{Material, Part, TextureRef};
        // Two triangles sharing an edge, the shared corners with different
        // UVs on each side, each triangle its own material.
        let mut mesh = wildlod_mesh::shapes::quad_grid(1, 1);
        let corners = mesh.faces.indices.len();
        mesh.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: (0..corners).flat_map(|c| [c as f32 / 10.0, 0.5]).collect(),
            indices: (0..corners as u32).collect(),
            format: wildlod_mesh::ComponentFormat::F32,
        });
        let tri = triangulate(&mesh);
        let mut scene = Scene::from_mesh(tri);
        scene.materials = vec![
            Material {
                base_color_texture: Some(TextureRef {
                    texture: 0,
                    tex_coord: 0,
                }),
                ..Material::default()
            },
            Material::default(),
        ];
        let m = &mut scene.meshes[0];
        m.parts = vec![
            Part {
                material: Some(1),
                ..Part::default()
            },
            Part {
                material: Some(0),
                ..Part::default()
            },
        ];
        m.face_parts = vec![0, 1];
        let images = vec![None];
        let mut textures = Textures {
            list: Vec::new(),
            index: HashMap::new(),
            max: 64,
        };
        let flat = flatten(
            &ReportModel {
                label: "q",
                scene: &scene,
                images: &images,
                source: 0,
                chain_error: None,
            },
            &mut textures,
            [0.0; 3],
        );
        assert_eq!(flat.json.triangles, 2);
        // Six corners, all different (UV per corner, parts differ).
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(&flat.json.positions)
            .unwrap_or_default();
        assert_eq!(bytes.len(), 6 * 12);
        // Material 0 first, then material 1: one group each.
        assert_eq!(flat.json.groups, vec![[0, 3, 0], [3, 3, 1]]);
        // No image decoded: nothing textured, no UVs sent.
        assert!(flat.json.uvs.is_none() && !flat.appearance);
    }
}
