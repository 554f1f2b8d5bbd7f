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

/// Width of the label column of [`text`]: the longest label and a gap.
const LABEL: usize = "shading-normal Chamfer".len() + 2;

/// The human-readable form.
pub fn text(c: &Comparison) -> String {
    let opt = |v: Option<f64>| v.map_or("n/a".to_string(), |x| format!("{x:.4}"));
    // A paired metric with its sampling floor: a difference below the
    // floor is a tie.
    let floored = |v: Option<f64>, floor: Option<f64>| match (v, floor) {
        (Some(v), Some(f)) => format!("{v:.4}  (sampling floor {f:.4})"),
        _ => opt(v),
    };
    // One label column wide enough for the longest label, so the values
    // line up.
    let row = |label: &str, value: String| format!("  {label:<LABEL$}{value}\n");
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let faces = |f: &wildlod_eval::FaceCounts| {
        format!(
            "{} ({}, {}, {}), {}",
            plural(f.faces, "face", "faces"),
            plural(f.triangles, "triangle", "triangles"),
            plural(f.quads, "quad", "quads"),
            plural(f.ngons, "n-gon", "n-gons"),
            plural(f.components, "component", "components")
        )
    };
    let mut s = String::new();
    s += &format!(
        "distances relative to the reference diagonal ({:.6}), {} samples per surface\n",
        c.diagonal, c.samples
    );
    if c.outliers_reference > 0 {
        s += &row(
            "outliers",
            format!(
                "{} reference vertices left out (diagonal with them {:.6e})",
                c.outliers_reference, c.diagonal_with_outliers
            ),
        );
    }
    s += &row(
        "Hausdorff",
        format!(
            "{:.6}  (reference→candidate {:.6}, candidate→reference {:.6})",
            c.hausdorff, c.hausdorff_ref_to_cand, c.hausdorff_cand_to_ref
        ),
    );
    s += &row("Chamfer mean", format!("{:.6}", c.chamfer_mean));
    s += &row(
        "Chamfer²",
        format!("{:.3e}  (mean squared distance)", c.chamfer_squared),
    );
    s += &row("quad ratio", opt(c.quad_ratio));
    s += &row(
        "texture Chamfer",
        floored(c.texture_chamfer, c.texture_chamfer_floor),
    );
    s += &row(
        "normal Chamfer",
        format!(
            "{} degrees",
            floored(c.normal_chamfer, c.normal_chamfer_floor)
        ),
    );
    s += &row(
        "shading-normal Chamfer",
        format!(
            "{} degrees (normal maps applied)",
            floored(c.shading_normal_chamfer, c.shading_normal_chamfer_floor)
        ),
    );
    if c.alpha_coverage_reference.is_some() || c.alpha_coverage_candidate.is_some() {
        s += &row(
            "alpha-tested coverage",
            format!(
                "reference {}, candidate {} (fraction of the alpha-tested surface drawn)",
                opt(c.alpha_coverage_reference),
                opt(c.alpha_coverage_candidate)
            ),
        );
    }
    s += &row("reference", faces(&c.reference));
    s += &row("candidate", faces(&c.candidate));
    for n in &c.notes {
        s += &format!("  note: {n}\n");
    }
    s
}
