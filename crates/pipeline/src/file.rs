//! Whole files: read → simplify (or a chain) → write, with the report.

use std::cell::OnceCell;
use std::path::Path;
use std::time::Instant;

use wildlod_io::{Document, WriteOptions};
use wildlod_simplify::{Options, SceneReport, Target};

use crate::rebake::Held;
use crate::{
    build_chain, chain_json, drawn_targets, file_stem, merge_twins_for_output, rebake_levels,
    rebake_scene, simplify_scene, simplify_whole_scene, targets_for, treat_textures, write_chain,
    ChainJson, Error, Levels, MergedTwins, MeshProgress, MeshRun, NoProgress, RunJson,
    TextureChoice, TextureSettings, Tuning,
};

/// The limits of simplifying a whole file; the first reached stops.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FileTargets {
    /// Keep this fraction of every mesh's triangles (0 to 1).
    pub ratio: Option<f64>,
    /// Keep at most this many triangles, shared among the file's meshes in
    /// proportion to their triangles.
    pub faces: Option<usize>,
    /// Allow no collapse whose error exceeds this, relative to the file's
    /// bounding-box diagonal.
    pub error: Option<f64>,
}

impl FileTargets {
    /// Checks the ranges; with no limit at all, keeps half the triangles
    /// (the CLI's default).
    pub fn checked(self) -> Result<FileTargets, Error> {
        if let Some(r) = self.ratio {
            if !(0.0..=1.0).contains(&r) {
                return Err(Error::setting("ratio", "between 0 and 1", r));
            }
        }
        if let Some(e) = self.error {
            if !(e.is_finite() && e >= 0.0) {
                return Err(Error::setting("error", "a non-negative number", e));
            }
        }
        Ok(match (self.ratio, self.faces, self.error) {
            (None, None, None) => FileTargets {
                ratio: Some(0.5),
                ..self
            },
            _ => self,
        })
    }
}

/// What simplifying a read file made: the document to write and what to
/// report about it.
#[derive(Clone, Debug)]
pub struct SimplifiedDocument {
    /// The simplified file.
    pub doc: Document,
    /// Every simplified mesh's run.
    pub runs: Vec<MeshRun>,
    /// How its textures were treated and why (files with a base colour
    /// texture, or a re-bake asked for).
    pub textures: Option<TextureChoice>,
    /// Reversed twins merged into double-sided faces (glTF outputs).
    pub twins: MergedTwins,
    /// Warnings of the re-bake (textures that could not be decoded).
    pub warnings: Vec<String>,
    /// The whole file's run report, when the written result is the one
    /// run under the file's budget (how it shared the budget, which
    /// meshes went); `None` for mesh-by-mesh runs and re-bakes.
    pub scene: Option<SceneReport>,
    /// Per run in `runs`, what was baked for it (`; baked N image(s) in
    /// SIZE² …`), empty where nothing was.
    pub notes: Vec<String>,
}

/// One way of treating the textures, made in full: the document, its runs
/// and what the summary says about them.
struct Candidate {
    doc: Document,
    runs: Vec<MeshRun>,
    scene: Option<SceneReport>,
    notes: Vec<String>,
}

impl SimplifiedDocument {
    /// The JSON report of the run, `seconds` long.
    pub fn json(&self, input: &Path, output: &Path, seconds: f64) -> RunJson {
        let mut json = RunJson::new(input, output, &self.runs, seconds);
        json.textures = self.textures.clone();
        json.double_sided_twins = self.twins.pairs;
        // The input as the file drew it, before its twins were merged.
        json.input_triangles += self.twins.triangles;
        json
    }
}

/// Simplifies `doc` (read from `input`, to be written to `output`, whose
/// extension decides what a glTF can say) to `targets` (checked): the
/// whole file under one budget in world space, as `wildlod simplify` does
/// ([`simplify_whole_scene`]), or with `per_mesh` every mesh to its share
/// ([`targets_for`]); reversed twins of a glTF output become one
/// double-sided face (see [`crate::merge_twins_double_sided`]; a ratio is
/// then of what the input drew), and textures are kept, re-baked or chosen
/// per `textures` (see [`treat_textures`]). A re-bake maps texels through
/// one mesh's history, so it simplifies mesh by mesh, but under the file's
/// one budget: each mesh to the triangles the whole-file run gives it
/// ([`drawn_targets`]; a mesh that run removes goes).
#[allow(clippy::too_many_arguments)]
pub fn simplify_document<P: MeshProgress>(
    mut doc: Document,
    input: &Path,
    output: &Path,
    targets: &FileTargets,
    per_mesh: bool,
    options: &Options,
    textures: &TextureSettings,
    progress: &dyn Fn(&str) -> P,
) -> Result<SimplifiedDocument, Error> {
    let stem = file_stem(input);
    let (twins, t) = merge_twins_for_output(&mut doc.scene, output, targets);
    let mesh_targets = targets_for(&doc.scene, t.ratio, t.faces, t.error);
    let mut warnings = Vec::new();
    // Under one budget for the file (the default), a re-bake reaches mesh
    // by mesh what the run over the whole file spent where: the keep-UV
    // candidate's counts when it was made, else its own run's.
    let instances = doc.scene.instance_counts();
    let whole_file: OnceCell<(Vec<Target>, Option<Held>)> = OnceCell::new();
    let keep = || -> Result<Candidate, Error> {
        let mut out = doc.clone();
        let (runs, scene) = if per_mesh {
            let runs = simplify_scene(
                &mut out.scene,
                input,
                options,
                &mesh_targets,
                &stem,
                progress,
            )?;
            (runs, None)
        } else {
            let (run, report) =
                simplify_whole_scene(&mut out.scene, input, options, &t, &stem, progress)?;
            let _ = whole_file.set((
                drawn_targets(&out.scene.meshes, &instances, report.target_triangles),
                Held::of(std::slice::from_ref(&run)),
            ));
            (vec![run], Some(report))
        };
        let notes = vec![String::new(); runs.len()];
        Ok(Candidate {
            doc: out,
            runs,
            scene,
            notes,
        })
    };
    let rebake = || -> Result<Candidate, Error> {
        let (rebake_targets, held) = if per_mesh {
            (mesh_targets.clone(), None)
        } else if let Some(t) = whole_file.get() {
            t.clone()
        } else {
            let mut scene = doc.scene.clone();
            let (run, report) =
                simplify_whole_scene(&mut scene, input, options, &t, &stem, progress)?;
            (
                drawn_targets(&scene.meshes, &instances, report.target_triangles),
                Held::of(std::slice::from_ref(&run)),
            )
        };
        let hold = held.map_or_else(Vec::new, |h| h.hold_targets(&rebake_targets));
        let mut out = doc.clone();
        let (runs, more) = rebake_scene(
            &mut out,
            input,
            options,
            &textures.bake,
            &rebake_targets,
            &hold,
            &stem,
        )?;
        warnings.extend(more);
        let (mut runs, notes): (Vec<MeshRun>, _) =
            runs.into_iter().map(|r| (r.run, r.atlases)).unzip();
        if let Some(held) = held {
            held.mark(&mut runs);
        }
        Ok(Candidate {
            doc: out,
            runs,
            scene: None,
            notes,
        })
    };
    let (done, choice) =
        treat_textures(&doc, input, output, textures.mode, keep, rebake, |c| &c.doc)?;
    Ok(SimplifiedDocument {
        doc: done.doc,
        runs: done.runs,
        textures: choice,
        twins,
        warnings,
        scene: done.scene,
        notes: done.notes,
    })
}

/// Simplifies the file `input` and writes `output` (its extension picks
/// the format): what `wildlod simplify` does, with `per_mesh` what
/// `--per-mesh` does (see [`simplify_document`]). Refuses to replace
/// `input` unless `overwrite`. Returns the report and the warnings of the
/// reader, the re-bake and the writer, each naming its file.
pub fn simplify_file(
    input: &Path,
    output: &Path,
    targets: &FileTargets,
    per_mesh: bool,
    tuning: &Tuning,
    textures: &TextureSettings,
    overwrite: bool,
) -> Result<(RunJson, Vec<String>), Error> {
    let t0 = Instant::now();
    let targets = targets.checked()?;
    let options = tuning.options()?;
    let textures = textures.checked()?;
    // Refuse an output format that does not exist before the work.
    wildlod_io::Format::from_path(output).map_err(|k| wildlod_io::Error::new(output, k))?;
    let doc = wildlod_io::read(input)?;
    let mut warnings: Vec<String> = doc
        .warnings
        .iter()
        .map(|w| format!("{}: {w}", input.display()))
        .collect();
    let done = simplify_document(
        doc,
        input,
        output,
        &targets,
        per_mesh,
        &options,
        &textures,
        &|_| NoProgress,
    )?;
    warnings.extend(done.warnings.iter().cloned());
    for w in wildlod_io::write(
        &done.doc,
        output,
        &WriteOptions {
            allow_overwrite_input: overwrite,
        },
    )? {
        warnings.push(format!("{}: {w}", output.display()));
    }
    Ok((
        done.json(input, output, t0.elapsed().as_secs_f64()),
        warnings,
    ))
}

/// Makes a chain of levels of detail of `input` and writes it to `output`
/// (one glTF file with `MSFT_lod` unless `split`; other formats and split
/// glTF write `NAME_lod0…NAME_lodN` beside `output`), with textures
/// shared or re-baked per `textures` (see [`rebake_levels`]): what
/// `wildlod lod` does without `--report`. Returns the report and the
/// warnings.
pub fn lod_file(
    input: &Path,
    output: &Path,
    levels: &Levels,
    tuning: &Tuning,
    textures: &TextureSettings,
    split: bool,
    overwrite: bool,
) -> Result<(ChainJson, Vec<String>), Error> {
    let t0 = Instant::now();
    let options = tuning.options()?;
    let textures = textures.checked()?;
    // Refuse a bad output name before the work.
    crate::chain_paths(output, levels.len(), split)?;
    let doc = wildlod_io::read(input)?;
    let mut warnings: Vec<String> = doc
        .warnings
        .iter()
        .map(|w| format!("{}: {w}", input.display()))
        .collect();
    let stem = file_stem(input);
    let mut chain = build_chain(&doc.scene, input, &options, levels, &stem, &|_| NoProgress)?;
    warnings.extend(rebake_levels(
        &doc, &mut chain, input, output, &options, &textures, &stem,
    )?);
    let (files, more) = write_chain(&doc, &chain, output, split, overwrite)?;
    warnings.extend(more);
    Ok((
        chain_json(
            input,
            &doc.scene,
            &chain,
            &files,
            None,
            t0.elapsed().as_secs_f64(),
        ),
        warnings,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_io::Document;
    use wildlod_mesh::{shapes, Scene};

    fn torus(path: &Path) {
        let doc = Document::from_scene(Scene::from_mesh(shapes::torus(24, 12, 1.0, 0.3)));
        wildlod_io::write(&doc, path, &WriteOptions::default()).expect("write the torus");
    }

    #[test]
    fn a_file_is_simplified_to_its_ratio_and_reported() {
        let dir = tempfile::tempdir().expect("temp dir");
        let (input, output) = (dir.path().join("t.obj"), dir.path().join("t_lod.ply"));
        torus(&input);
        let targets = FileTargets {
            ratio: Some(0.25),
            ..FileTargets::default()
        };
        let (report, _) = simplify_file(
            &input,
            &output,
            &targets,
            false,
            &Tuning::default(),
            &TextureSettings::default(),
            false,
        )
        .expect("simplified");
        assert_eq!(report.input_triangles, 576);
        assert!(report.output_triangles.abs_diff(144) <= 1, "{report:?}");
        let back = wildlod_io::read(&output).expect("read back");
        assert_eq!(
            back.scene.meshes[0].triangle_count(),
            report.output_triangles
        );
    }

    #[test]
    fn an_input_is_never_replaced_without_overwrite() {
        let dir = tempfile::tempdir().expect("temp dir");
        let input = dir.path().join("t.obj");
        torus(&input);
        let before = std::fs::read(&input).expect("read");
        let r = simplify_file(
            &input,
            &input,
            &FileTargets::default(),
            false,
            &Tuning::default(),
            &TextureSettings::default(),
            false,
        );
        assert!(matches!(r, Err(Error::Io(_))), "{r:?}");
        assert_eq!(std::fs::read(&input).expect("read"), before);
    }

    #[test]
    fn bad_targets_are_named() {
        let bad = FileTargets {
            ratio: Some(1.5),
            ..FileTargets::default()
        };
        assert!(matches!(
            bad.checked(),
            Err(Error::Setting { name: "ratio", .. })
        ));
        assert_eq!(
            FileTargets::default().checked().ok().and_then(|t| t.ratio),
            Some(0.5)
        );
    }
}
