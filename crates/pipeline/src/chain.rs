//! Chains of levels of detail, each simplified from the one before (nested,
//! and each step only works on what is left), sharing the input's
//! materials and textures (keep-UV mode). A level whose textures are
//! re-baked (`lod --textures`) is made from the input instead, as baking
//! maps every texel through one collapse history, and draws with
//! materials of its own ([`LevelMaterials`]).
//!
//! glTF output holds every level in one file (`MSFT_lod`, with
//! `MSFT_screencoverage` hints from each level's error); split output and
//! the other formats write one file per level.

use std::path::{Path, PathBuf};
use std::time::Instant;

use wildlod_io::{Document, Format, LodLevels, WriteOptions};
use wildlod_mesh::{Mesh, Scene};
use wildlod_simplify::{Options, Target};

use crate::level_materials::{append_level_materials, level_scene, LevelMaterials};
use crate::report::{ChainJson, LevelJson, MeshJson};
use crate::textures::TextureChoice;
use crate::{
    file_stem, scene_diagonal, simplify_scene, targets_for, world_diagonal, Error, MeshProgress,
    MeshRun,
};

/// The screen height, in pixels, the coverage hints are computed for (a
/// 1920 × 1080 screen, [`screen_coverage`]).
pub const SCREEN_PIXELS: f64 = 1080.0;

/// The screen width, in pixels, the coverage hints are computed for.
pub const SCREEN_WIDTH_PIXELS: f64 = 1920.0;

/// The largest deviation from the input, in pixels of that screen, a
/// level may show before the finer one above it is drawn instead.
pub const PIXEL_TOLERANCE: f64 = 1.0;

/// The screen coverage of an object whose bounding sphere just fills the
/// screen's height: a disc of diameter [`SCREEN_PIXELS`] over the screen,
/// π/4 · 1080/1920 ≈ 0.442. Level 0 is always shown from there up.
pub const FULL_VIEW_COVERAGE: f64 =
    std::f64::consts::FRAC_PI_4 * SCREEN_PIXELS / SCREEN_WIDTH_PIXELS;

/// What the levels of a chain aim for, finest first.
#[derive(Clone, Debug, PartialEq)]
pub enum Levels {
    /// Fractions of the input's triangles.
    Ratios(Vec<f64>),
    /// Accumulated error limits, relative to the file's diagonal.
    Errors(Vec<f64>),
    /// Triangle budgets for the whole file.
    Faces(Vec<usize>),
}

impl Levels {
    /// Checks level lists (`flag` prefixes their names in messages, e.g.
    /// `--` or `--lod-`): at most one given, in range, each level coarser
    /// than the one before. None given: ratios 0.5, 0.25, 0.1.
    pub fn from_lists(
        ratios: &[f64],
        errors: &[f64],
        faces: &[usize],
        flag: &str,
    ) -> Result<Levels, Error> {
        let usage = |s: String| Err(Error::Usage(s));
        let given = [!ratios.is_empty(), !errors.is_empty(), !faces.is_empty()];
        if given.iter().filter(|&&g| g).count() > 1 {
            return usage(format!(
                "give one of {flag}ratios, {flag}errors and {flag}faces"
            ));
        }
        if !errors.is_empty() {
            if let Some(e) = errors.iter().find(|e| !(e.is_finite() && **e > 0.0)) {
                return usage(format!("{flag}errors must be positive numbers, got {e}"));
            }
            if errors.windows(2).any(|w| w[1] <= w[0]) {
                return usage(format!(
                    "{flag}errors must increase (finest level first), got {errors:?}"
                ));
            }
            return Ok(Levels::Errors(errors.to_vec()));
        }
        if !faces.is_empty() {
            if faces.windows(2).any(|w| w[1] >= w[0]) {
                return usage(format!(
                    "{flag}faces must decrease (finest level first), got {faces:?}"
                ));
            }
            return Ok(Levels::Faces(faces.to_vec()));
        }
        let ratios = if ratios.is_empty() {
            vec![0.5, 0.25, 0.1]
        } else {
            ratios.to_vec()
        };
        // 0 is "as few as possible" (each mesh keeps a triangle), as with
        // `simplify --ratio 0`.
        if let Some(r) = ratios.iter().find(|r| !(**r >= 0.0 && **r <= 1.0)) {
            return usage(format!("{flag}ratios must be in [0, 1], got {r}"));
        }
        if ratios.windows(2).any(|w| w[1] >= w[0]) {
            return usage(format!(
                "{flag}ratios must decrease (finest level first), got {ratios:?}"
            ));
        }
        Ok(Levels::Ratios(ratios))
    }

    /// Number of levels below the input.
    pub fn len(&self) -> usize {
        match self {
            Levels::Ratios(v) | Levels::Errors(v) => v.len(),
            Levels::Faces(v) => v.len(),
        }
    }

    /// Whether there is no level below the input.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One level below the input.
#[derive(Clone, Debug)]
pub struct Level {
    /// 1 for the first level below the input.
    pub level: usize,
    /// One mesh per scene mesh.
    pub meshes: Vec<Mesh>,
    /// The simplifier's runs that made it from the level above.
    pub runs: Vec<MeshRun>,
    /// Triangles the level draws (each mesh once per node that shows it).
    pub triangles: usize,
    /// Accumulated error (the sum of the steps' errors: a bound on the
    /// distance to the input, as each step's is to its own input),
    /// relative to the file's diagonal; the largest over the meshes.
    pub error: f64,
    /// The same per mesh, relative to the mesh's own diagonal.
    pub mesh_errors: Vec<f64>,
    /// Wall time of this level.
    pub seconds: f64,
    /// The level's own materials and textures when its textures were
    /// re-baked; `None`: it shares the input's.
    pub own_materials: Option<LevelMaterials>,
    /// How the level's textures were treated and why, for a file with
    /// textures (set by the caller that chose: `lod --textures`).
    pub textures: Option<TextureChoice>,
}

impl Level {
    /// A level simplified straight from `scene` (a re-baked one): `meshes`
    /// drawn with `own` materials, made by `runs`, whose errors are
    /// relative to each input mesh's own diagonal.
    pub fn from_input(
        scene: &Scene,
        level: usize,
        meshes: Vec<Mesh>,
        own: LevelMaterials,
        runs: Vec<MeshRun>,
        seconds: f64,
    ) -> Level {
        let to_file = to_file_scale(scene);
        let mut mesh_errors = vec![0.0; scene.meshes.len()];
        for r in &runs {
            if let Some(e) = mesh_errors.get_mut(r.mesh) {
                *e = r.report.error;
            }
        }
        let error = mesh_errors
            .iter()
            .zip(&to_file)
            .map(|(e, f)| e * f)
            .fold(0.0, f64::max);
        let triangles = drawn_triangles(&level_scene(scene, &meshes, None));
        Level {
            level,
            meshes,
            runs,
            triangles,
            error,
            mesh_errors,
            seconds,
            own_materials: Some(own),
            textures: None,
        }
    }

    /// The scene this level draws: `scene` with its meshes, and its own
    /// materials when it has them.
    pub fn scene(&self, scene: &Scene) -> Scene {
        level_scene(scene, &self.meshes, self.own_materials.as_ref())
    }
}

/// How each mesh's own relative error reads against the file's diagonal.
fn to_file_scale(scene: &Scene) -> Vec<f64> {
    let file_diag = scene_diagonal(scene);
    (0..scene.meshes.len())
        .map(|m| {
            let d = world_diagonal(scene, m);
            if file_diag > 0.0 && d > 0.0 {
                d / file_diag
            } else {
                1.0
            }
        })
        .collect()
}

/// Triangles `scene` draws: each mesh's once per node that shows it (the
/// count budgets are of, and every command reports).
pub fn drawn_triangles(scene: &Scene) -> usize {
    scene
        .meshes
        .iter()
        .zip(scene.instance_counts())
        .map(|(m, k)| m.triangle_count() * k)
        .sum()
}

/// Diagonal of all of a mesh's positions, in its own frame.
fn local_diagonal(mesh: &Mesh) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k] as f64);
            hi[k] = hi[k].max(p[k] as f64);
        }
    }
    if lo[0] > hi[0] {
        return 0.0;
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// Simplifies `scene` level after level, each from the one before.
pub fn build_chain<P: MeshProgress>(
    scene: &Scene,
    input: &Path,
    options: &Options,
    levels: &Levels,
    stem: &str,
    progress: &dyn Fn(&str) -> P,
) -> Result<Vec<Level>, Error> {
    // Counts of drawn triangles, as targets are (see `simplify_scene`).
    let instances = scene.instance_counts();
    let input_tris: Vec<usize> = scene
        .meshes
        .iter()
        .zip(&instances)
        .map(|(m, k)| m.triangle_count() * k)
        .collect();
    let input_diag: Vec<f64> = scene.meshes.iter().map(local_diagonal).collect();
    let to_file = to_file_scale(scene);
    let mut current = scene.clone();
    let mut accumulated = vec![0.0f64; scene.meshes.len()];
    let mut out = Vec::with_capacity(levels.len());
    for k in 0..levels.len() {
        let file_targets = match levels {
            Levels::Ratios(r) => targets_for(scene, Some(r[k]), None, None),
            Levels::Faces(n) => targets_for(scene, None, Some(n[k]), None),
            Levels::Errors(e) => targets_for(scene, None, None, Some(e[k])),
        };
        let targets: Vec<Target> = file_targets
            .iter()
            .enumerate()
            .map(|(m, t)| match levels {
                // A ratio of the input, as a count: the level above has
                // fewer triangles than the input.
                Levels::Ratios(_) => Target {
                    triangles: Some(t.triangles_for(input_tris[m])),
                    ..Target::default()
                },
                Levels::Faces(_) => *t,
                // What the levels above used of the error budget is spent.
                Levels::Errors(_) => {
                    let left = t.error.unwrap_or(0.0) - accumulated[m];
                    // `left` is relative to the input mesh's diagonal; the
                    // simplifier reads a limit against the current level's,
                    // which optimal placement may have grown.
                    let current_diag = local_diagonal(&current.meshes[m]);
                    let scale = if current_diag > 0.0 {
                        input_diag[m] / current_diag
                    } else {
                        1.0
                    };
                    if left > 0.0 {
                        Target {
                            error: Some(left * scale),
                            ..Target::default()
                        }
                    } else {
                        Target {
                            triangles: Some(current.meshes[m].triangle_count() * instances[m]),
                            ..Target::default()
                        }
                    }
                }
            })
            .collect();
        let before: Vec<f64> = current.meshes.iter().map(local_diagonal).collect();
        let t0 = Instant::now();
        let label = format!("{stem} lod{}", k + 1);
        let runs = simplify_scene(&mut current, input, options, &targets, &label, progress)
            .map_err(|e| Error::Level {
                level: k + 1,
                source: Box::new(e),
            })?;
        for r in &runs {
            if input_diag[r.mesh] > 0.0 {
                accumulated[r.mesh] += r.report.error * before[r.mesh] / input_diag[r.mesh];
            }
        }
        out.push(Level {
            level: k + 1,
            meshes: current.meshes.clone(),
            triangles: drawn_triangles(&current),
            error: accumulated
                .iter()
                .zip(&to_file)
                .map(|(e, f)| e * f)
                .fold(0.0, f64::max),
            mesh_errors: accumulated.clone(),
            runs,
            seconds: t0.elapsed().as_secs_f64(),
            own_materials: None,
            textures: None,
        });
    }
    Ok(out)
}

/// The screen coverage up to which a level whose error is `error`
/// (relative to the diagonal of the object's bounding box) deviates from
/// the input by at most [`PIXEL_TOLERANCE`] pixels on a 1920 × 1080 screen.
///
/// Screen coverage is the area of the object's bounding sphere on screen
/// over the screen's area, as Babylon.js measures it for `MSFT_lod`. The
/// sphere's diameter is the box's diagonal, so an object drawn `D` pixels
/// across shows the error as `error · D` pixels, at most the tolerance
/// while `D ≤ tolerance / error`; its coverage is then
/// `π (D/2)² / (1920 · 1080)`. Infinite for an exact level.
pub fn coverage_for_error(error: f64) -> f64 {
    if error > 0.0 {
        let d = PIXEL_TOLERANCE / error;
        std::f64::consts::PI * (d / 2.0).powi(2) / (SCREEN_WIDTH_PIXELS * SCREEN_PIXELS)
    } else {
        f64::INFINITY
    }
}

/// Four significant digits: hints read better short, and rounding to a
/// fixed number of decimals would turn small coverages into 0.
fn round_hint(x: f64) -> f64 {
    if x <= 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(3 - x.log10().floor() as i32);
    (x * scale).round() / scale
}

/// `MSFT_screencoverage` of mesh `m`, one value per level starting with
/// the input: level `k` is drawn while the object's screen coverage is
/// above value `k` (and below value `k - 1`).
///
/// Value `k` is where level `k + 1` takes over: [`coverage_for_error`] of
/// its accumulated error (relative to the mesh's own diagonal, as each
/// node's bounding sphere is its mesh's), never rising down the chain. The
/// input's value is at most [`FULL_VIEW_COVERAGE`]: an object that fills
/// the screen's height is drawn at full detail even where the next level
/// would stay under the tolerance. The last value is 0: wildlod does not
/// decide when an object may vanish.
pub fn screen_coverage(levels: &[Level], m: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(levels.len() + 1);
    let mut last = FULL_VIEW_COVERAGE;
    for l in levels {
        let e = l.mesh_errors.get(m).copied().unwrap_or(0.0);
        last = last.min(coverage_for_error(e));
        out.push(round_hint(last));
    }
    out.push(0.0);
    out
}

/// Entries of `weights` (`per_entry` influences each) whose weights do
/// not sum to one are scaled to, as the simplifier leaves the levels it
/// makes: the input of a chain is written as its level 0, and a glTF
/// validator refuses weights that do not sum to one within 2·10⁻⁷ per
/// influence. Entries within 10⁻⁷ already, and entries of weight 0 (no
/// influence to scale), stay bit for bit; nothing else changes. Returns
/// the number of entries scaled.
pub fn normalize_weights(weights: &mut [f32], per_entry: usize) -> usize {
    if per_entry == 0 {
        return 0;
    }
    let mut scaled = 0;
    for entry in weights.chunks_mut(per_entry) {
        let sum: f64 = entry.iter().map(|&w| w as f64).sum();
        if !(sum > 0.0 && sum.is_finite()) || (sum - 1.0).abs() <= 1e-7 {
            continue;
        }
        for w in entry.iter_mut() {
            *w = (*w as f64 / sum) as f32;
        }
        // Rounding to f32 may leave the sum a unit in the last place off:
        // the largest weight takes the rest, as glTF's encoders do.
        let big = (0..entry.len()).fold(0, |b, i| if entry[i] > entry[b] { i } else { b });
        let rest: f64 = entry
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != big)
            .map(|(_, &w)| w as f64)
            .sum();
        entry[big] = (1.0 - rest).max(0.0) as f32;
        scaled += 1;
    }
    scaled
}

/// The document written as level 0 of a chain: the input with its skin
/// weights normalized ([`normalize_weights`]).
fn level_zero(doc: &Document) -> Document {
    let mut doc = doc.clone();
    for mesh in &mut doc.scene.meshes {
        if let Some(s) = &mut mesh.skinning {
            normalize_weights(&mut s.weights, s.influences as usize);
        }
    }
    doc
}

/// `NAME_lodK.EXT` beside `output`.
pub fn level_path(output: &Path, k: usize) -> PathBuf {
    let stem = file_stem(output);
    let ext = output
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    output.with_file_name(format!("{stem}_lod{k}.{ext}"))
}

/// The files a chain of `levels` levels below the input is written to:
/// `output` itself for glTF unless `split`, else `NAME_lod0…NAME_lodN`.
pub fn chain_paths(output: &Path, levels: usize, split: bool) -> Result<Vec<PathBuf>, Error> {
    let format = Format::from_path(output).map_err(|k| wildlod_io::Error::new(output, k))?;
    if matches!(format, Format::Gltf | Format::Glb) && !split {
        Ok(vec![output.to_path_buf()])
    } else {
        Ok((0..=levels).map(|k| level_path(output, k)).collect())
    }
}

/// Writes the chain: one glTF file with `MSFT_lod`, or one file per level
/// (level 0 is the input as read, its skin weights normalized), each
/// all-or-nothing. Returns the files
/// written and the writers' warnings.
pub fn write_chain(
    doc: &Document,
    levels: &[Level],
    output: &Path,
    split: bool,
    overwrite: bool,
) -> Result<(Vec<PathBuf>, Vec<String>), Error> {
    let paths = chain_paths(output, levels.len(), split)?;
    let options = WriteOptions {
        allow_overwrite_input: overwrite,
    };
    let doc = &level_zero(doc);
    let mut warnings = Vec::new();
    if paths.len() == 1 {
        // One file: the input's materials, then each re-baked level's.
        let mut one = doc.clone();
        let meshes: Vec<Vec<Mesh>> = levels
            .iter()
            .map(|l| match &l.own_materials {
                Some(own) => append_level_materials(&mut one.scene, &l.meshes, own),
                None => l.meshes.clone(),
            })
            .collect();
        let coverage: Vec<Vec<f64>> = (0..doc.scene.meshes.len())
            .map(|m| screen_coverage(levels, m))
            .collect();
        warnings = wildlod_io::write_lods(
            &one,
            &LodLevels {
                levels: &meshes,
                screen_coverage: &coverage,
            },
            output,
            &options,
        )?;
        return Ok((paths, warnings));
    }
    for (k, path) in paths.iter().enumerate() {
        let mut level_doc = doc.clone();
        if let Some(l) = k.checked_sub(1).and_then(|k| levels.get(k)) {
            level_doc.scene = l.scene(&doc.scene);
        }
        for w in wildlod_io::write(&level_doc, path, &options)? {
            warnings.push(format!("{}: {w}", path.display()));
        }
    }
    Ok((paths, warnings))
}

/// The report of a chain (level 0 is the input).
pub fn chain_json(
    input: &Path,
    scene: &Scene,
    levels: &[Level],
    files: &[PathBuf],
    report: Option<&Path>,
    seconds: f64,
) -> ChainJson {
    let input_tris = drawn_triangles(scene);
    let ratio = |t: usize| {
        if input_tris == 0 {
            1.0
        } else {
            t as f64 / input_tris as f64
        }
    };
    let split = files.len() > 1;
    let file = |k: usize| {
        let f = if split { files.get(k) } else { files.first() };
        f.map(|p| p.display().to_string())
    };
    // Single-mesh files get the coverage hint of their one mesh.
    let coverage = |k: usize| {
        (scene.meshes.len() == 1)
            .then(|| screen_coverage(levels, 0).get(k).copied())
            .flatten()
    };
    let mut out = vec![LevelJson {
        level: 0,
        triangles: input_tris,
        ratio: 1.0,
        error: 0.0,
        seconds: 0.0,
        file: file(0),
        screen_coverage: coverage(0),
        meshes: Vec::new(),
        textures: None,
    }];
    for l in levels {
        out.push(LevelJson {
            level: l.level,
            triangles: l.triangles,
            ratio: ratio(l.triangles),
            error: l.error,
            seconds: l.seconds,
            file: file(l.level),
            screen_coverage: coverage(l.level),
            meshes: l.runs.iter().map(MeshJson::new).collect(),
            textures: l.textures.clone(),
        });
    }
    ChainJson {
        input: input.display().to_string(),
        files: files.iter().map(|p| p.display().to_string()).collect(),
        report: report.map(|p| p.display().to_string()),
        seconds,
        levels: out,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_lists_must_get_coarser() {
        assert!(Levels::from_lists(&[0.5, 0.25], &[], &[], "--").is_ok());
        assert!(Levels::from_lists(&[0.25, 0.5], &[], &[], "--").is_err());
        assert!(Levels::from_lists(&[0.5, 0.5], &[], &[], "--").is_err());
        assert!(Levels::from_lists(&[1.5], &[], &[], "--").is_err());
        // 0 is the smallest valid level, as `simplify --ratio 0`.
        assert!(Levels::from_lists(&[0.5, 0.0], &[], &[], "--").is_ok());
        assert!(Levels::from_lists(&[0.5, -0.1], &[], &[], "--").is_err());
        assert!(Levels::from_lists(&[f64::NAN], &[], &[], "--").is_err());
        assert!(Levels::from_lists(&[], &[0.01, 0.001], &[], "--").is_err());
        assert!(Levels::from_lists(&[], &[], &[100, 1000], "--").is_err());
        assert!(Levels::from_lists(&[0.5], &[0.01], &[], "--").is_err());
        assert_eq!(
            Levels::from_lists(&[], &[], &[], "--").ok(),
            Some(Levels::Ratios(vec![0.5, 0.25, 0.1]))
        );
    }

    fn level(e: f64) -> Level {
        Level {
            level: 1,
            meshes: Vec::new(),
            runs: Vec::new(),
            triangles: 0,
            error: e,
            mesh_errors: vec![e],
            seconds: 0.0,
            own_materials: None,
            textures: None,
        }
    }

    #[test]
    fn coverage_is_where_the_error_reaches_a_pixel_at_1080p() {
        // An error of 1/100 of the diagonal is one pixel when the object
        // is 100 pixels across: a disc of radius 50 over 1920 × 1080.
        let c = coverage_for_error(0.01);
        assert!((c - std::f64::consts::PI * 2500.0 / 2_073_600.0).abs() < 1e-15);
        assert!((c - 0.003_787_6).abs() < 1e-7, "{c}");
        // Half the error, twice the size, four times the area.
        assert!((coverage_for_error(0.005) / c - 4.0).abs() < 1e-12);
        assert_eq!(coverage_for_error(0.0), f64::INFINITY);
        // Filling the screen's height: π/4 · 1080/1920.
        assert!((FULL_VIEW_COVERAGE - 0.441_786_5).abs() < 1e-7);
    }

    #[test]
    fn screen_coverage_falls_with_the_error_and_ends_at_zero() {
        // Level 1 is exact and level 2 under a pixel until the object is
        // 10 000 pixels across: both would take over at any size, but the
        // input holds the full view. Level 3 (1/100: 100 pixels) takes
        // over from 0.003788; level 4 is finer than level 3, which does
        // not let the hint rise.
        let c = screen_coverage(&[level(0.0), level(1e-4), level(1e-2), level(5e-3)], 0);
        assert_eq!(c, vec![0.4418, 0.4418, 0.003788, 0.003788, 0.0]);
        // The input is shown above a coverage below 1 whatever the chain.
        assert!(c[0] < 1.0);
        // A coarse first level: the input is drawn down to its coverage.
        let c = screen_coverage(&[level(0.02), level(0.04)], 0);
        assert_eq!(c, vec![0.000_946_9, 0.000_236_7, 0.0]);
    }

    #[test]
    fn hints_keep_four_significant_digits() {
        assert_eq!(round_hint(0.123_456), 0.1235);
        assert_eq!(round_hint(0.000_012_345_6), 0.000_012_35);
        assert_eq!(round_hint(0.0), 0.0);
    }

    #[test]
    fn weights_are_scaled_to_sum_one_and_normalized_ones_kept() {
        let mut w = vec![
            0.5, 0.3, 0.1, 0.0, // sums to 0.9: scaled
            0.7, 0.2, 0.1, 0.0, // sums to one (within 1e-7): kept
            0.0, 0.0, 0.0, 0.0, // no influence: kept
        ];
        let kept = w[4..].to_vec();
        assert_eq!(normalize_weights(&mut w, 4), 1);
        assert_eq!(&w[4..], &kept[..]);
        let sum: f64 = w[..4].iter().map(|&x| x as f64).sum();
        assert!((sum - 1.0).abs() <= 1e-7, "{sum}");
        // The ratios stay: 5 : 3 : 1.
        assert!((w[0] / w[2] - 5.0).abs() < 1e-5 && (w[1] / w[2] - 3.0).abs() < 1e-5);
        assert_eq!(w[3], 0.0);
        // A second pass changes nothing.
        let once = w.clone();
        assert_eq!(normalize_weights(&mut w, 4), 0);
        assert_eq!(w, once);
    }

    #[test]
    fn split_levels_are_named_after_the_output() {
        let p = level_path(Path::new("out/chair.glb"), 2);
        assert_eq!(p, Path::new("out/chair_lod2.glb"));
    }
}
