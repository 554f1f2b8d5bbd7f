//! Keep the input's UVs or re-bake the textures: chosen per file by what
//! the level of detail shows (`simplify --textures auto`, the default).
//!
//! Keeping UVs (Hoppe 1999's attribute quadrics, seams kept) is fast and
//! keeps the artist's atlas, and at moderate ratios it shows the texture
//! as well as a re-bake does. Past some ratio, different for every file,
//! the collapses must cross UV charts and the texture tears (smears, black
//! wedges); re-baking (W §4.3) onto a new atlas does not, but costs
//! seconds and replaces the atlas. Neither wins everywhere: on the corpus
//! a re-bake is clearly better at 1% on most files and ties at 50%, and on
//! a 149-island sofa at 1% keeping the UVs is better.
//!
//! So the choice is measured on the result, as the steering of the
//! attribute terms is (W §5's texture Chamfer distance: the colour each
//! surface sample shows against the colour of the other surface's closest
//! sample, both ways, minus the reference's own sampling floor): the
//! keep-UV result is kept when its texture error over the floor is below
//! [`visible_excess`], a difference nobody sees; otherwise the file is
//! also re-baked and the lower of the two measured errors wins. The
//! threshold only decides when a re-bake is worth its time: the choice
//! between two results is always by measurement.

use std::path::Path;

use serde::Serialize;
use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_io::Document;
use wildlod_mesh::{Image, Scene};

use crate::{load_images, BakeSettings, Error};

/// Mean colour difference (RGB in 0..1, Euclidean, as the texture Chamfer
/// distance measures it) below which a keep-UV result is kept without
/// trying a re-bake, on a busy texture: 0.01 is 2.5 of 255 levels spread
/// over the channels, about one just-noticeable difference for a uniform
/// patch (and a mean: the local differences that make it up are where
/// texels moved, not a tint). On a plainer texture less is seen: see
/// [`visible_excess`].
pub const VISIBLE_TEXTURE_EXCESS: f64 = 0.01;

/// The share of the input's own texture variation (the sampling floor) a
/// keep-UV result may add before a re-bake is tried: see
/// [`visible_excess`].
pub const VISIBLE_SHARE_OF_FLOOR: f64 = 0.25;

/// The least excess that counts as visible: half of one 8-bit level, below
/// which no 8-bit texture shows a difference.
const LEAST_VISIBLE_EXCESS: f64 = 0.5 / 255.0;

/// The texture error over the floor below which a keep-UV result is kept
/// without trying a re-bake, for an input whose own texture Chamfer
/// distance (the floor: how much the colours of neighbouring samples of
/// the input differ) is `floor`.
///
/// A texture's own detail masks errors in it (contrast masking): on a
/// busy texture a shifted texel is lost among its neighbours, on flat
/// colours with sharp borders (a low-poly character's palette) a border
/// that moves shows. So the threshold is a share of the floor,
/// [`VISIBLE_SHARE_OF_FLOOR`], between half an 8-bit level and
/// [`VISIBLE_TEXTURE_EXCESS`]. On the corpus the keep-UV results at 50%
/// and 10% are either within 13% of their floor or beyond 33% of it
/// (the Fox at 50%, Avocado and CesiumMan at 10%), and there the re-bake
/// measures 19–27% lower (`texchamfer.py`); the fixed 0.01 alone kept the
/// Fox and Avocado.
pub fn visible_excess(floor: f64) -> f64 {
    (VISIBLE_SHARE_OF_FLOOR * floor).clamp(LEAST_VISIBLE_EXCESS, VISIBLE_TEXTURE_EXCESS)
}

/// Texture samples per surface: W §5 uses 10 000; 40 000 halves the
/// sampling floor, so the two candidates are told apart where they differ
/// by the threshold.
const TEXTURE_SAMPLES: usize = 40_000;

/// How `simplify` treats textured materials.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TextureMode {
    /// Keep the UVs, and re-bake when that shows the texture visibly worse
    /// and the re-bake measures better (see the module documentation).
    #[default]
    Auto,
    /// Keep the input's UVs and atlas.
    Keep,
    /// Re-bake every textured mesh onto a new atlas (W §4.3).
    Bake,
}

/// What was chosen for a file and why: its `textures` key in
/// `simplify --json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TextureChoice {
    /// What was asked.
    pub mode: TextureMode,
    /// What the output holds: [`TextureMode::Keep`] or [`TextureMode::Bake`].
    pub chosen: TextureMode,
    /// The keep-UV result's texture Chamfer distance over the input's
    /// sampling floor, when measured.
    pub keep_uv_excess: Option<f64>,
    /// The excess below which the keep-UV result is kept without trying a
    /// re-bake ([`visible_excess`] of the input's floor), when measured.
    pub visible_excess: Option<f64>,
    /// The re-baked result's, when measured.
    pub rebaked_excess: Option<f64>,
    /// Why a re-bake that `auto` tried could not be made (the UVs were
    /// kept); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rebake_failed: Option<String>,
    /// Why `auto` could not measure the keep-UV result (its images do not
    /// decode, say), so kept the UVs unmeasured; absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unmeasured: Option<String>,
}

/// Why a keep-UV result's texture error is `None`, from the warnings of
/// loading the input's images.
pub(crate) fn unmeasured_reason(image_warnings: &[String]) -> String {
    if image_warnings.is_empty() {
        "nothing textured to compare".to_string()
    } else {
        // One line per distinct problem (an image many textures share
        // fails once).
        let mut distinct: Vec<&str> = Vec::new();
        for w in image_warnings {
            if !distinct.contains(&w.as_str()) {
                distinct.push(w);
            }
        }
        format!(
            "the input's textures do not decode ({})",
            distinct.join("; ")
        )
    }
}

/// How a file's textures are treated: the mode (`--textures`) and how to
/// re-bake where that is done. Default: `auto`, [`BakeSettings::default`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TextureSettings {
    /// Keep the UVs, re-bake, or choose by measurement.
    pub mode: TextureMode,
    /// How to re-bake.
    pub bake: BakeSettings,
}

impl TextureSettings {
    /// Checks the ranges, and that re-baking settings are not given where
    /// nothing is re-baked.
    pub fn checked(self) -> Result<TextureSettings, Error> {
        let bake = self.bake.checked()?;
        if self.mode == TextureMode::Keep && (bake.texture_size.is_some() || bake.merge_materials) {
            return Err(Error::Usage(
                "texture_size and merge_materials apply only when re-baking, not with textures keep"
                    .into(),
            ));
        }
        Ok(self)
    }
}

/// A file's result under `mode`: `keep` makes the keep-UV candidate and
/// `rebake` the re-baked one (each whatever the caller reports with its
/// document, which `doc_of` gives); `doc` is the input, read from `input`,
/// and re-baked images are named as if beside `output`. `auto` makes the
/// keep-UV candidate, measures it, and only where it is visibly off makes
/// and measures the re-bake and keeps the lower (see the module
/// documentation). Returns the chosen candidate and, for a file with a
/// base colour texture (or a re-bake asked for), what was chosen and why.
pub fn treat_textures<T>(
    doc: &Document,
    input: &Path,
    output: &Path,
    mode: TextureMode,
    keep: impl FnOnce() -> Result<T, Error>,
    rebake: impl FnOnce() -> Result<T, Error>,
    doc_of: impl Fn(&T) -> &Document,
) -> Result<(T, Option<TextureChoice>), Error> {
    let textured = has_base_color_texture(&doc.scene);
    let fixed = |mode| TextureChoice {
        mode,
        chosen: mode,
        keep_uv_excess: None,
        visible_excess: None,
        rebaked_excess: None,
        rebake_failed: None,
        unmeasured: None,
    };
    match mode {
        TextureMode::Bake => Ok((rebake()?, textured.then(|| fixed(TextureMode::Bake)))),
        TextureMode::Keep => Ok((keep()?, textured.then(|| fixed(TextureMode::Keep)))),
        TextureMode::Auto if !textured => Ok((keep()?, None)),
        TextureMode::Auto => {
            let (input_images, image_warnings) = load_images(doc, input);
            let kept = keep()?;
            let measured = texture_error(
                &doc.scene,
                &input_images,
                &doc_of(&kept).scene,
                &input_images,
            );
            let keep_uv_excess = measured.map(|m| m.excess);
            let mut choice = TextureChoice {
                mode,
                chosen: TextureMode::Keep,
                keep_uv_excess,
                visible_excess: measured.map(|m| visible_excess(m.floor)),
                rebaked_excess: None,
                rebake_failed: None,
                unmeasured: keep_uv_excess
                    .is_none()
                    .then(|| unmeasured_reason(&image_warnings)),
            };
            if !worth_rebaking(measured) {
                return Ok((kept, Some(choice)));
            }
            // The measured images (`f32`, four times the decoded size) are
            // let go while the bake decodes its own, and read again to
            // measure its result: a 4096² texture's auto run peaked at
            // 632 MB holding them, 367 MB without.
            drop(input_images);
            // A re-bake that cannot be made leaves the keep-UV result,
            // which is a valid LOD, and says why.
            let baked = match rebake() {
                Ok(b) => b,
                Err(e) => {
                    choice.rebake_failed = Some(with_causes(&e));
                    return Ok((kept, Some(choice)));
                }
            };
            let (input_images, _) = load_images(doc, input);
            let (baked_images, _) = load_images(doc_of(&baked), output);
            choice.rebaked_excess = texture_excess(
                &doc.scene,
                &input_images,
                &doc_of(&baked).scene,
                &baked_images,
            );
            choice.chosen = choose(keep_uv_excess, choice.rebaked_excess);
            let result = if choice.chosen == TextureMode::Bake {
                baked
            } else {
                kept
            };
            Ok((result, Some(choice)))
        }
    }
}

/// Whether anything of `scene` shows a base colour texture (what the
/// texture Chamfer distance measures), so that the choice matters.
pub fn has_base_color_texture(scene: &Scene) -> bool {
    scene
        .materials
        .iter()
        .any(|m| m.base_color_texture.is_some())
}

/// A texture error as [`texture_error`] measures it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureError {
    /// The texture Chamfer distance over the floor (0 when within it).
    pub excess: f64,
    /// The input against a second sampling of itself: its sampling floor.
    pub floor: f64,
}

/// The texture Chamfer distance of `output` against `input` (both with
/// their decoded textures) over the input's own sampling floor; `None`
/// when it cannot be measured (no texture on either side, no area).
pub fn texture_excess(
    input: &Scene,
    input_images: &[Option<Image>],
    output: &Scene,
    output_images: &[Option<Image>],
) -> Option<f64> {
    texture_error(input, input_images, output, output_images).map(|e| e.excess)
}

/// [`texture_excess`] with the floor it is over.
pub fn texture_error(
    input: &Scene,
    input_images: &[Option<Image>],
    output: &Scene,
    output_images: &[Option<Image>],
) -> Option<TextureError> {
    let reference = EvalMesh::from_scene(input, input_images);
    let candidate = EvalMesh::from_scene(output, output_images);
    let c = compare(
        &reference,
        &candidate,
        &CompareOptions {
            // Only the texture distance is used: the geometric ones at
            // their cheapest.
            samples: 1_000,
            texture_samples: TEXTURE_SAMPLES,
            max_vertex_samples: 1_000,
            ..CompareOptions::default()
        },
    );
    let floor = c.texture_chamfer_floor?;
    Some(TextureError {
        excess: (c.texture_chamfer? - floor).max(0.0),
        floor,
    })
}

/// Whether a keep-UV result with this measured error is worth trying a
/// re-bake for: its excess is above [`visible_excess`] of its floor.
pub fn worth_rebaking(keep_uv: Option<TextureError>) -> bool {
    keep_uv.is_some_and(|e| e.excess > visible_excess(e.floor))
}

/// The choice between the two measured results: the re-bake only where it
/// measures lower.
pub fn choose(keep_uv_excess: Option<f64>, rebaked_excess: Option<f64>) -> TextureMode {
    match (keep_uv_excess, rebaked_excess) {
        (Some(k), Some(b)) if b < k => TextureMode::Bake,
        (None, Some(_)) => TextureMode::Bake,
        _ => TextureMode::Keep,
    }
}

/// An error's message followed by each of its causes, `: `-separated (what
/// `anyhow` prints with `{:#}`): the summary says why, not only where.
fn with_causes(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(excess: f64, floor: f64) -> Option<TextureError> {
        Some(TextureError { excess, floor })
    }

    #[test]
    fn a_rebake_is_tried_only_past_the_visible_threshold() {
        assert!(!worth_rebaking(None));
        // A busy texture (floor 0.2): the fixed threshold, 0.01.
        assert!(!worth_rebaking(error(0.0, 0.2)));
        assert!(!worth_rebaking(error(VISIBLE_TEXTURE_EXCESS, 0.2)));
        assert!(worth_rebaking(error(VISIBLE_TEXTURE_EXCESS * 1.01, 0.2)));
        // A plain one (floor 0.012): a quarter of it, 0.003.
        assert_eq!(visible_excess(0.012), 0.003);
        assert!(!worth_rebaking(error(0.003, 0.012)));
        assert!(worth_rebaking(error(0.0031, 0.012)));
        // Flat colour (floor 0): half an 8-bit level, 0.00196.
        assert_eq!(visible_excess(0.0), 0.5 / 255.0);
        assert!(!worth_rebaking(error(0.0019, 0.0)));
        assert!(worth_rebaking(error(0.0020, 0.0)));
    }

    #[test]
    fn the_lower_measured_error_wins_and_ties_keep_the_uvs() {
        assert_eq!(choose(Some(0.05), Some(0.02)), TextureMode::Bake);
        assert_eq!(choose(Some(0.02), Some(0.05)), TextureMode::Keep);
        assert_eq!(choose(Some(0.02), Some(0.02)), TextureMode::Keep);
        assert_eq!(choose(Some(0.02), None), TextureMode::Keep);
        assert_eq!(choose(None, Some(0.02)), TextureMode::Bake);
        assert_eq!(choose(None, None), TextureMode::Keep);
    }
}
