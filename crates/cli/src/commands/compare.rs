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
    // A paired metric with its sampling floor: a difference below the
    // floor is a tie.
    let floored = |v: Option<f64>, floor: Option<f64>| match (v, floor) {
        (Some(v), Some(f)) => format!("{v:.4}  (sampling floor {f:.4})"),
        _ => opt(v),
    };
    let mut s = String::new();
    s += &format!(
        "distances relative to the reference diagonal ({:.6}), {} samples per surface\n",
        c.diagonal, c.samples
    );
    if c.outliers_reference > 0 {
        s += &format!(
            "  outliers       {} reference vertices left out (diagonal with them {:.6e})\n",
            c.outliers_reference, c.diagonal_with_outliers
        );
    }
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
    s += &format!(
        "  texture Chamfer {}\n",
        floored(c.texture_chamfer, c.texture_chamfer_floor)
    );
    s += &format!(
        "  normal Chamfer  {} degrees\n",
        floored(c.normal_chamfer, c.normal_chamfer_floor)
    );
    s += &format!(
        "  shading-normal Chamfer {} degrees (normal maps applied)\n",
        floored(c.shading_normal_chamfer, c.shading_normal_chamfer_floor)
    );
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
