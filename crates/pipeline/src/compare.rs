//! What `wildlod compare --json` prints about two files.

use std::path::Path;

use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_io::Document;
use wildlod_mesh::Image;

use crate::Error;

/// How to compare two files: the sampling of `compare`, and optionally the
/// frames of an animation.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareFilesOptions {
    /// Area samples per surface for the distances (at least 1).
    pub samples: usize,
    /// Samples per surface for the texture and normal Chamfer distances.
    pub texture_samples: usize,
    /// Seed of the sampling.
    pub seed: u64,
    /// Also compare both files posed at frames of this animation (index
    /// into the reference's animations; the candidate's of the same index).
    pub animation: Option<usize>,
    /// Frames to compare with `animation`, from time 0 (at least 1).
    pub frames: usize,
    /// Frame rate of those frames (positive).
    pub fps: f64,
}

impl Default for CompareFilesOptions {
    fn default() -> Self {
        CompareFilesOptions {
            samples: 100_000,
            texture_samples: 40_000,
            seed: wildlod_eval::DEFAULT_SEED,
            animation: None,
            // Knodt 2024 §4 uses the first 50 frames of animation 0.
            frames: 50,
            fps: 30.0,
        }
    }
}

/// Decodes the textures a document references; a texture that cannot be
/// read is left out (`None`, and the texture metric then says why), with a
/// warning naming `file` in the second list.
pub fn load_images(doc: &Document, file: &Path) -> (Vec<Option<Image>>, Vec<String>) {
    let mut warnings = Vec::new();
    let images = doc
        .scene
        .textures
        .iter()
        .map(|t| match wildlod_io::decode_image(&t.source) {
            Ok(img) => Some(img),
            Err(e) => {
                warnings.push(format!("{}: texture {:?}: {e}", file.display(), t.name));
                None
            }
        })
        .collect();
    (images, warnings)
}

/// Distances between the two files posed at one frame.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Frame {
    /// Time of the frame, in seconds.
    pub time: f64,
    /// Symmetric Hausdorff distance.
    pub hausdorff: f64,
    /// Chamfer distance as a mean distance.
    pub chamfer_mean: f64,
    /// Chamfer distance as a mean squared distance.
    pub chamfer_squared: f64,
}

/// Distances at animation frames (the `animation` key of the JSON).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Animated {
    /// Index of the animation.
    pub index: usize,
    /// Its name.
    pub name: String,
    /// Frame rate of the frames.
    pub fps: f64,
    /// Mean of the frames' Hausdorff distances.
    pub hausdorff_mean: f64,
    /// Worst of them.
    pub hausdorff_max: f64,
    /// Mean of the frames' mean Chamfer distances.
    pub chamfer_mean_mean: f64,
    /// Worst of them.
    pub chamfer_mean_max: f64,
    /// Every frame.
    pub frames: Vec<Frame>,
}

impl Animated {
    /// The human-readable form.
    pub fn text(&self) -> String {
        format!(
            "animation {} {:?}, {} frames at {} fps:\n  Hausdorff      mean {:.6}, worst {:.6}\n  Chamfer mean   mean {:.6}, worst {:.6}\n",
            self.index,
            self.name,
            self.frames.len(),
            self.fps,
            self.hausdorff_mean,
            self.hausdorff_max,
            self.chamfer_mean_mean,
            self.chamfer_mean_max
        )
    }
}

/// Two files compared.
#[derive(Clone, Debug)]
pub struct FileComparison {
    /// The metrics at rest.
    pub comparison: Comparison,
    /// The metrics over animation frames, when asked for.
    pub animation: Option<Animated>,
    /// Problems met (textures that could not be decoded), naming the file.
    pub warnings: Vec<String>,
}

impl FileComparison {
    /// What `compare --json` prints: the keys of [`Comparison`], plus
    /// `animation` when it was asked for.
    pub fn to_json(&self) -> Result<serde_json::Value, Error> {
        let mut json = serde_json::to_value(&self.comparison)?;
        if let (Some(anim), Some(obj)) = (&self.animation, json.as_object_mut()) {
            obj.insert("animation".into(), serde_json::to_value(anim)?);
        }
        Ok(json)
    }
}

/// Compares two files (see [`FileComparison::to_json`] for the report).
pub fn compare_files(
    reference: &Path,
    candidate: &Path,
    options: &CompareFilesOptions,
) -> Result<FileComparison, Error> {
    if options.samples == 0 {
        return Err(Error::Setting {
            name: "samples",
            expected: "at least 1",
            value: "0".into(),
        });
    }
    let ref_doc = wildlod_io::read(reference)?;
    let cand_doc = wildlod_io::read(candidate)?;
    let (ri, mut warnings) = load_images(&ref_doc, reference);
    let (ci, more) = load_images(&cand_doc, candidate);
    warnings.extend(more);
    // As a renderer shows them at rest: skinned meshes through their
    // joints' rest transforms (an exporter may place a skinned mesh's node
    // anywhere, since renderers ignore it).
    // Both about the reference's first instance (see `posed_about`).
    let origin = wildlod_eval::pose_origin(&ref_doc.scene);
    let r = EvalMesh::from_scene(
        &wildlod_eval::posed_about(&ref_doc.scene, None, 0.0, origin),
        &ri,
    );
    let c = EvalMesh::from_scene(
        &wildlod_eval::posed_about(&cand_doc.scene, None, 0.0, origin),
        &ci,
    );
    let compare_options = CompareOptions {
        samples: options.samples,
        texture_samples: options.texture_samples,
        seed: options.seed,
        ..CompareOptions::default()
    };
    let comparison = compare(&r, &c, &compare_options);
    let animation = match options.animation {
        Some(index) => Some(animated(
            (&ref_doc, reference),
            (&cand_doc, candidate),
            (&ri, &ci),
            index,
            options,
            &compare_options,
        )?),
        None => None,
    };
    Ok(FileComparison {
        comparison,
        animation,
        warnings,
    })
}

/// Compares both files posed at `options.frames` frames of animation
/// `index`.
fn animated(
    reference: (&Document, &Path),
    candidate: (&Document, &Path),
    images: (&[Option<Image>], &[Option<Image>]),
    index: usize,
    options: &CompareFilesOptions,
    compare_options: &CompareOptions,
) -> Result<Animated, Error> {
    let missing = |(doc, path): (&Document, &Path)| {
        Error::Usage(format!(
            "{}: has {} animations, so animation {index} does not exist",
            path.display(),
            doc.scene.animations.len()
        ))
    };
    let Some(anim) = reference.0.scene.animations.get(index) else {
        return Err(missing(reference));
    };
    if candidate.0.scene.animations.len() <= index {
        return Err(missing(candidate));
    }
    if options.frames == 0 {
        return Err(Error::Setting {
            name: "frames",
            expected: "at least 1",
            value: "0".into(),
        });
    }
    if !(options.fps.is_finite() && options.fps > 0.0) {
        return Err(Error::setting("fps", "a positive number", options.fps));
    }
    let mut frames = Vec::with_capacity(options.frames);
    for k in 0..options.frames {
        // Past the animation's end the last pose holds.
        let time = (k as f64 / options.fps).min(anim.duration as f64);
        let origin = wildlod_eval::pose_origin(&reference.0.scene);
        let pr = wildlod_eval::posed_about(&reference.0.scene, Some(index), time as f32, origin);
        let pc = wildlod_eval::posed_about(&candidate.0.scene, Some(index), time as f32, origin);
        let c = compare(
            &EvalMesh::from_scene(&pr, images.0),
            &EvalMesh::from_scene(&pc, images.1),
            &CompareOptions {
                texture_samples: 0,
                ..*compare_options
            },
        );
        frames.push(Frame {
            time,
            hausdorff: c.hausdorff,
            chamfer_mean: c.chamfer_mean,
            chamfer_squared: c.chamfer_squared,
        });
    }
    let n = frames.len() as f64;
    let mean = |f: fn(&Frame) -> f64| frames.iter().map(f).sum::<f64>() / n;
    let max = |f: fn(&Frame) -> f64| frames.iter().map(f).fold(0.0, f64::max);
    Ok(Animated {
        index,
        name: anim.name.clone(),
        fps: options.fps,
        hausdorff_mean: mean(|f| f.hausdorff),
        hausdorff_max: max(|f| f.hausdorff),
        chamfer_mean_mean: mean(|f| f.chamfer_mean),
        chamfer_mean_max: max(|f| f.chamfer_mean),
        frames,
    })
}
