//! Whole files: read → simplify (or a chain) → write, with the report.

use std::path::Path;
use std::time::Instant;

use wildlod_io::WriteOptions;

use crate::{
    build_chain, chain_json, file_stem, simplify_scene, targets_for, write_chain, ChainJson, Error,
    Levels, NoProgress, RunJson, Tuning,
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

/// Simplifies every mesh of the file `input` and writes `output` (its
/// extension picks the format): what `wildlod simplify` does without
/// `--bake`. Refuses to replace `input` unless `overwrite`. Returns the
/// report and the warnings of the reader and the writer, each naming its
/// file.
pub fn simplify_file(
    input: &Path,
    output: &Path,
    targets: &FileTargets,
    tuning: &Tuning,
    overwrite: bool,
) -> Result<(RunJson, Vec<String>), Error> {
    let t0 = Instant::now();
    let targets = targets.checked()?;
    let options = tuning.options()?;
    // Refuse an output format that does not exist before the work.
    wildlod_io::Format::from_path(output).map_err(|k| wildlod_io::Error::new(output, k))?;
    let mut doc = wildlod_io::read(input)?;
    let mut warnings: Vec<String> = doc
        .warnings
        .iter()
        .map(|w| format!("{}: {w}", input.display()))
        .collect();
    let per_mesh = targets_for(&doc.scene, targets.ratio, targets.faces, targets.error);
    let runs = simplify_scene(
        &mut doc.scene,
        input,
        &options,
        &per_mesh,
        &file_stem(input),
        &|_| NoProgress,
    )?;
    for w in wildlod_io::write(
        &doc,
        output,
        &WriteOptions {
            allow_overwrite_input: overwrite,
        },
    )? {
        warnings.push(format!("{}: {w}", output.display()));
    }
    Ok((
        RunJson::new(input, output, &runs, t0.elapsed().as_secs_f64()),
        warnings,
    ))
}

/// Makes a chain of levels of detail of `input` and writes it to `output`
/// (one glTF file with `MSFT_lod` unless `split`; other formats and split
/// glTF write `NAME_lod0…NAME_lodN` beside `output`): what `wildlod lod`
/// does without `--report`. Returns the report and the warnings.
pub fn lod_file(
    input: &Path,
    output: &Path,
    levels: &Levels,
    tuning: &Tuning,
    split: bool,
    overwrite: bool,
) -> Result<(ChainJson, Vec<String>), Error> {
    let t0 = Instant::now();
    let options = tuning.options()?;
    // Refuse a bad output name before the work.
    crate::chain_paths(output, levels.len(), split)?;
    let doc = wildlod_io::read(input)?;
    let mut warnings: Vec<String> = doc
        .warnings
        .iter()
        .map(|w| format!("{}: {w}", input.display()))
        .collect();
    let chain = build_chain(
        &doc.scene,
        input,
        &options,
        levels,
        &file_stem(input),
        &|_| NoProgress,
    )?;
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
        let (report, _) = simplify_file(&input, &output, &targets, &Tuning::default(), false)
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
            &Tuning::default(),
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
