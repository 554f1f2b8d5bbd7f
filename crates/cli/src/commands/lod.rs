//! `wildlod lod`: a chain of levels of detail, each simplified from the one
//! before (nested, and each step only works on what is left), sharing the
//! input's materials and textures (keep-UV mode) down to the level where
//! `--textures auto` finds a re-bake better; that level and the coarser
//! ones are made from the input with atlases of their own.
//!
//! glTF output holds every level in one file (`MSFT_lod`, with
//! `MSFT_screencoverage` hints from each level's error); `--split` and the
//! other formats write one file per level. The chain itself is
//! `wildlod_pipeline`'s, shared with the Python package.

use std::time::Instant;

use anyhow::Context;
use wildlod_io::Document;
use wildlod_pipeline::{
    build_chain, chain_json, chain_paths, choose_textures, drawn_triangles, file_stem,
    has_base_color_texture, load_images, texture_excess, worth_rebaking, write_chain, Level,
    LevelMaterials, Levels, TextureChoice, TextureMode,
};
use wildlod_simplify::Target;

use super::bake::{bake_scene, BakeConfig};
use super::simplify::{bake_config, check_output, texture_mode, tuning_options, Config};
use super::with_flag_names;
use crate::args_assets::LodArgs;
use crate::progress::Progress;
use crate::stdout::emit;

/// The line of one level: `lod1: 1152 triangles (50.0% of the input), error
/// 0.0012 of the diagonal, 35 ms`.
fn level_line(l: &Level, input_tris: usize) -> String {
    let pct = if input_tris == 0 {
        100.0
    } else {
        100.0 * l.triangles as f64 / input_tris as f64
    };
    let textures = match l.textures.map(|t| t.chosen) {
        Some(TextureMode::Bake) => ", textures re-baked",
        Some(_) => ", textures shared",
        None => "",
    };
    format!(
        "lod{}: {} triangles ({pct:.1}% of the input), error {:.4} of the diagonal, {:.0} ms{textures}",
        l.level,
        l.triangles,
        l.error,
        l.seconds * 1000.0
    )
}

/// `--textures` over a chain: every level shares the input's textures
/// until the first level that `auto` re-bakes (a keep-UV texture error
/// over the visible threshold and a re-bake that measures lower, as
/// `simplify` decides); that level and every coarser one are simplified
/// from the input to the same triangle counts and re-baked. `bake`
/// re-bakes every level, `keep` none.
fn chain_textures(
    doc: &Document,
    chain: &mut [Level],
    mode: TextureMode,
    cfg: &Config,
    stem: &str,
) -> anyhow::Result<()> {
    let (input_images, _) = load_images(doc, &cfg.input);
    let instances = doc.scene.instance_counts();
    let mut baking = mode == TextureMode::Bake;
    for level in chain.iter_mut() {
        let mut choice = TextureChoice {
            mode,
            chosen: TextureMode::Keep,
            keep_uv_excess: None,
            rebaked_excess: None,
        };
        if mode == TextureMode::Keep {
            level.textures = Some(choice);
            continue;
        }
        if !baking {
            let kept = level.scene(&doc.scene);
            choice.keep_uv_excess = texture_excess(&doc.scene, &input_images, &kept, &input_images);
            if !worth_rebaking(choice.keep_uv_excess) {
                level.textures = Some(choice);
                continue;
            }
        }
        // The same drawn triangles per mesh as the keep-UV level.
        let targets: Vec<Target> = level
            .meshes
            .iter()
            .zip(&instances)
            .map(|(m, &k)| Target {
                triangles: Some(m.triangle_count() * k),
                ..Target::default()
            })
            .collect();
        let t0 = Instant::now();
        let mut baked = doc.clone();
        let label = format!("{stem}_lod{}", level.level);
        let (runs, _) = bake_scene(&mut baked, cfg, &cfg.bake, &targets, &label)
            .with_context(|| format!("re-baking level {}", level.level))?;
        if !baking {
            let (baked_images, _) = load_images(&baked, &cfg.output);
            choice.rebaked_excess =
                texture_excess(&doc.scene, &input_images, &baked.scene, &baked_images);
            if choose_textures(choice.keep_uv_excess, choice.rebaked_excess) != TextureMode::Bake {
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
        let seconds = t0.elapsed().as_secs_f64();
        *level = Level::from_input(&doc.scene, level.level, meshes, own, runs, seconds);
        level.textures = Some(choice);
    }
    Ok(())
}

/// Runs `lod`.
pub fn run(a: LodArgs) -> anyhow::Result<()> {
    let levels =
        Levels::from_lists(&a.ratios, &a.errors, &a.faces, "--").map_err(with_flag_names)?;
    let options = tuning_options(&a.tuning)?;
    let textures = texture_mode(a.textures);
    let bake: BakeConfig =
        bake_config(textures, a.texture_size, a.merge_materials, a.jpeg_quality)?;
    // Refuse a bad output name or folder before the work.
    for path in chain_paths(&a.output, levels.len(), a.split)? {
        check_output(&a.input, &path, a.overwrite)?;
    }
    let t0 = Instant::now();
    let doc = wildlod_io::read(&a.input)?;
    if !a.quiet {
        for w in &doc.warnings {
            eprintln!("warning: {}: {w}", a.input.display());
        }
    }
    let stem = file_stem(&a.input);
    let show = !a.quiet && !a.json;
    let mut chain = build_chain(&doc.scene, &a.input, &options, &levels, &stem, &|name| {
        Progress::new(name, show)
    })?;
    if textures == TextureMode::Bake || has_base_color_texture(&doc.scene) {
        let cfg = Config {
            input: a.input.clone(),
            output: a.output.clone(),
            options: options.clone(),
            ratio: None,
            faces: None,
            error: None,
            overwrite: a.overwrite,
            quiet: a.quiet,
            per_mesh: true,
            textures,
            bake,
            json: a.json,
        };
        chain_textures(&doc, &mut chain, textures, &cfg, &stem)?;
    }
    let (files, warnings) = write_chain(&doc, &chain, &a.output, a.split, a.overwrite)?;
    if !a.quiet {
        for w in warnings {
            eprintln!("warning: {w}");
        }
    }
    let report = match &a.report {
        None => None,
        Some(p) => {
            let path = p.clone().unwrap_or_else(|| {
                a.output
                    .with_file_name(format!("{}_report.html", file_stem(&a.output)))
            });
            super::report::write_chain_report(&doc, &a.input, &chain, &path, a.overwrite)?;
            Some(path)
        }
    };
    // Drawn triangles (a mesh shown by two nodes counts twice), as the
    // levels and `--json` count them.
    let input_tris = drawn_triangles(&doc.scene);
    if a.json {
        let j = chain_json(
            &a.input,
            &doc.scene,
            &chain,
            &files,
            report.as_deref(),
            t0.elapsed().as_secs_f64(),
        );
        let text = serde_json::to_string_pretty(&j).context("serializing the report")?;
        emit(&(text + "\n"))?;
    } else if !a.quiet {
        let mut s = format!("lod0: {input_tris} triangles (the input)\n");
        for l in &chain {
            s += &level_line(l, input_tris);
            s.push('\n');
        }
        for f in &files {
            s += &format!("wrote {}\n", f.display());
        }
        if let Some(r) = &report {
            s += &format!("wrote {}\n", r.display());
        }
        emit(&s)?;
    }
    Ok(())
}
