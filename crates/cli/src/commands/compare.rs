//! `wildlod compare`: the metrics of both papers between two files.

use anyhow::Context;
use wildlod_eval::Comparison;
use wildlod_pipeline::{compare_files, CompareFilesOptions};

use super::with_flag_names;
use crate::args::CompareArgs;
use crate::stdout::emit;

/// Runs `compare`.
pub fn run(a: &CompareArgs) -> anyhow::Result<()> {
    let options = CompareFilesOptions {
        samples: a.samples,
        texture_samples: a.texture_samples,
        seed: a.seed,
        animation: a.animation,
        frames: a.frames,
        fps: a.fps,
    };
    let result = compare_files(&a.reference, &a.candidate, &options).map_err(with_flag_names)?;
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    if a.json {
        let json = result.to_json().context("serializing the comparison")?;
        let json = serde_json::to_string_pretty(&json).context("serializing the comparison")?;
        emit(&(json + "\n"))
    } else {
        let mut s = text(&result.comparison);
        if let Some(anim) = &result.animation {
            s += &anim.text();
        }
        emit(&s)
    }
}

/// The human-readable form.
pub fn text(c: &Comparison) -> String {
    let opt = |v: Option<f64>| v.map_or("n/a".to_string(), |x| format!("{x:.4}"));
    let mut s = String::new();
    s += &format!(
        "distances relative to the reference diagonal ({:.6}), {} samples per surface\n",
        c.diagonal, c.samples
    );
    s += &format!(
        "  Hausdorff      {:.6}  (reference→candidate {:.6}, candidate→reference {:.6})\n",
        c.hausdorff, c.hausdorff_ref_to_cand, c.hausdorff_cand_to_ref
    );
    s += &format!("  Chamfer mean   {:.6}\n", c.chamfer_mean);
    s += &format!(
        "  Chamfer²       {:.3e}  (mean squared distance)\n",
        c.chamfer_squared
    );
    s += &format!("  quad ratio     {}\n", opt(c.quad_ratio));
    s += &format!("  texture Chamfer {}\n", opt(c.texture_chamfer));
    s += &format!("  normal Chamfer  {} degrees\n", opt(c.normal_chamfer));
    s += &format!(
        "  reference      {} faces ({} triangles, {} quads, {} n-gons), {} components\n",
        c.reference.faces,
        c.reference.triangles,
        c.reference.quads,
        c.reference.ngons,
        c.reference.components
    );
    s += &format!(
        "  candidate      {} faces ({} triangles, {} quads, {} n-gons), {} components\n",
        c.candidate.faces,
        c.candidate.triangles,
        c.candidate.quads,
        c.candidate.ngons,
        c.candidate.components
    );
    for n in &c.notes {
        s += &format!("  note: {n}\n");
    }
    s
}
