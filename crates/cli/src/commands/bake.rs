//! Re-baking for `simplify`: the pipeline's re-bake
//! ([`wildlod_pipeline::rebake_scene`]) with its warnings printed and one
//! summary line per mesh, saying what was baked.

use wildlod_io::Document;
use wildlod_pipeline::{rebake_scene, MeshRun};
use wildlod_simplify::Target;

use super::simplify::{summary, Config};

/// Re-bakes every mesh of the document in place; returns every simplified
/// mesh's run and summary line.
pub fn bake_scene(
    doc: &mut Document,
    cfg: &Config,
    targets: &[Target],
    stem: &str,
) -> anyhow::Result<(Vec<MeshRun>, Vec<String>)> {
    let (baked, warnings) = rebake_scene(doc, &cfg.input, &cfg.options, &cfg.bake, targets, stem)?;
    if !cfg.quiet {
        for w in warnings {
            eprintln!("warning: {w}");
        }
    }
    let lines = baked
        .iter()
        .map(|b| summary(&b.run.name, &b.run.report, b.run.seconds) + &b.atlases)
        .collect();
    Ok((baked.into_iter().map(|b| b.run).collect(), lines))
}
