//! Textures down a chain (`lod --textures`): every level shares the
//! input's textures until the first level that `auto` re-bakes (a keep-UV
//! texture error over the visible threshold and a re-bake that measures
//! lower, as for a single file, see [`crate::treat_textures`]); that level
//! and every coarser one are simplified from the input to the same
//! triangle counts and re-baked, each with materials of its own
//! ([`crate::LevelMaterials`]). Baking maps every texel through one
//! collapse history from the input, so a re-baked level is not nested in
//! the level above; its coarser levels are re-baked without measuring, as
//! a chain that tore at one level only tears more below it.

use std::path::Path;
use std::time::Instant;

use wildlod_io::Document;
use wildlod_mesh::Image;
use wildlod_simplify::Options;

use crate::rebake::Held;
use crate::targets::drawn_targets;
use crate::textures::{
    choose, has_base_color_texture, texture_error, texture_excess, unmeasured_reason,
    visible_excess, worth_rebaking,
};
use crate::{
    load_images, rebake_scene, Error, Level, LevelMaterials, TextureChoice, TextureMode,
    TextureSettings,
};

/// Applies `settings` to `chain`, made from `doc` (read from `input`, to
/// be written to `output`) with `options`: sets every level's
/// [`Level::textures`] and replaces the levels that are re-baked. Files
/// without a base colour texture are left alone unless `bake` is asked.
/// Returns the re-bakes' warnings.
pub fn rebake_levels(
    doc: &Document,
    chain: &mut [Level],
    input: &Path,
    output: &Path,
    options: &Options,
    settings: &TextureSettings,
    stem: &str,
) -> Result<Vec<String>, Error> {
    let mode = settings.mode;
    let mut warnings = Vec::new();
    if mode != TextureMode::Bake && !has_base_color_texture(&doc.scene) {
        return Ok(warnings);
    }
    // The input's images decoded for measuring (`f32`: four times their
    // decoded size), read when a level is measured and let go while a
    // level is re-baked, which decodes its own; `bake` measures nothing.
    let mut measured: Option<(Vec<Option<Image>>, Vec<String>)> = None;
    let instances = doc.scene.instance_counts();
    let mut baking = mode == TextureMode::Bake;
    // Why `auto` stopped trying re-bakes (one could not be made: the
    // levels below would not fit either), if it did.
    let mut gave_up: Option<String> = None;
    for level in chain.iter_mut() {
        let mut choice = TextureChoice {
            mode,
            chosen: TextureMode::Keep,
            keep_uv_excess: None,
            visible_excess: None,
            rebaked_excess: None,
            rebake_failed: None,
            unmeasured: None,
        };
        if mode == TextureMode::Keep || gave_up.is_some() {
            choice.rebake_failed = gave_up.clone();
            level.textures = Some(choice);
            continue;
        }
        if !baking {
            let kept = level.scene(&doc.scene);
            let (input_images, image_warnings) =
                measured.get_or_insert_with(|| load_images(doc, input));
            let measured = texture_error(&doc.scene, input_images, &kept, input_images);
            choice.keep_uv_excess = measured.map(|m| m.excess);
            choice.visible_excess = measured.map(|m| visible_excess(m.floor));
            if measured.is_none() {
                choice.unmeasured = Some(unmeasured_reason(image_warnings));
            }
            if !worth_rebaking(measured) {
                level.textures = Some(choice);
                continue;
            }
        }
        // The same drawn triangles per mesh as the keep-UV level, which
        // aimed for its runs' targets.
        let aimed = level.runs.iter().map(|r| r.report.target_triangles).sum();
        let targets = drawn_targets(&level.meshes, &instances, aimed);
        let hold = Held::of(&level.runs).map_or_else(Vec::new, |h| h.hold_targets(&targets));
        let t0 = Instant::now();
        measured = None;
        let mut baked = doc.clone();
        let label = format!("{stem}_lod{}", level.level);
        let (runs, more) = match rebake_scene(
            &mut baked,
            input,
            options,
            &settings.bake,
            &targets,
            &hold,
            &label,
        ) {
            Ok(r) => r,
            // `auto` keeps this level's shared texture, and says why.
            Err(e) if !baking => {
                let why = crate::error::error_chain(&e);
                choice.rebake_failed = Some(why.clone());
                gave_up = Some(why);
                level.textures = Some(choice);
                continue;
            }
            Err(e) => {
                return Err(Error::Level {
                    level: level.level,
                    source: Box::new(e),
                })
            }
        };
        warnings.extend(more);
        if !baking {
            let (baked_images, _) = load_images(&baked, output);
            let (input_images, _) = measured.get_or_insert_with(|| load_images(doc, input));
            choice.rebaked_excess =
                texture_excess(&doc.scene, input_images, &baked.scene, &baked_images);
            if choose(choice.keep_uv_excess, choice.rebaked_excess) != TextureMode::Bake {
                level.textures = Some(choice);
                continue;
            }
            baking = true;
        }
        choice.chosen = TextureMode::Bake;
        let own = LevelMaterials {
            materials: std::mem::take(&mut baked.scene.materials),
            textures: std::mem::take(&mut baked.scene.textures),
        };
        let meshes = std::mem::take(&mut baked.scene.meshes);
        let mut runs: Vec<_> = runs.into_iter().map(|r| r.run).collect();
        // A level its constraints held keeps saying so when re-baked.
        if let Some(held) = Held::of(&level.runs) {
            held.mark(&mut runs);
        }
        let seconds = t0.elapsed().as_secs_f64();
        *level = Level::from_input(&doc.scene, level.level, meshes, own, runs, seconds);
        level.textures = Some(choice);
    }
    Ok(warnings)
}
