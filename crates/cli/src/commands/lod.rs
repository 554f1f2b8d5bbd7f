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
use wildlod_pipeline::{
    build_chain, chain_json, chain_paths, drawn_triangles, file_stem, rebake_levels, write_chain,
    Level, Levels, TextureMode,
};

use super::simplify::{check_output, texture_settings, tuning_options};
use super::with_flag_names;
use crate::args_assets::LodArgs;
use crate::progress::Progress;
use crate::stdout::emit;

/// The line of one level: `lod1: 1152 triangles (50.0% of the input), error
/// 0.0012 of the diagonal, 35 ms`, and why it stopped short when its
/// constraints held it.
fn level_line(l: &Level, input_tris: usize) -> String {
    let pct = if input_tris == 0 {
        100.0
    } else {
        100.0 * l.triangles as f64 / input_tris as f64
    };
    let textures = match l.textures.as_ref().map(|t| t.chosen) {
        Some(TextureMode::Bake) => ", textures re-baked",
        Some(_) => ", textures shared",
        None => "",
    };
    // As `simplify` says it: a level its constraints held above its
    // target.
    let target: usize = l.runs.iter().map(|r| r.report.target_triangles).sum();
    let held = l
        .runs
        .iter()
        .filter_map(|r| r.report.held_by_constraints)
        .reduce(f64::max)
        .filter(|_| l.triangles > target + 1)
        .map(|level| {
            format!(
                " (target {target} held by the constraints: stopped at error {level:.4}, no farther from the input than the target without them)"
            )
        })
        .unwrap_or_default();
    format!(
        "lod{}: {} triangles ({pct:.1}% of the input), error {:.4} of the diagonal, {:.0} ms{textures}{held}",
        l.level,
        l.triangles,
        l.error,
        l.seconds * 1000.0
    )
}

/// Runs `lod`.
pub fn run(a: LodArgs) -> anyhow::Result<()> {
    let levels =
        Levels::from_lists(&a.ratios, &a.errors, &a.faces, "--").map_err(with_flag_names)?;
    let options = tuning_options(&a.tuning)?;
    let textures = texture_settings(&a.textures)?;
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
    let rebake_warnings = rebake_levels(
        &doc, &mut chain, &a.input, &a.output, &options, &textures, &stem,
    )?;
    if !a.quiet {
        for w in rebake_warnings {
            eprintln!("warning: {w}");
        }
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
