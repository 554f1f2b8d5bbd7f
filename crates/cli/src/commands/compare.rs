//! `wildlod compare`: the metrics of both papers between two files.

use anyhow::{bail, Context};
use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_mesh::Image;

use crate::args::CompareArgs;
use crate::stdout::emit;

/// Decodes the textures a scene references; a texture that cannot be read
/// is left out with a warning (the texture metric then says why).
fn images(doc: &wildlod_io::Document, file: &std::path::Path) -> Vec<Option<Image>> {
    doc.scene
        .textures
        .iter()
        .map(|t| match wildlod_io::decode_image(&t.source) {
            Ok(img) => Some(img),
            Err(e) => {
                eprintln!("warning: {}: texture {:?}: {e}", file.display(), t.name);
                None
            }
        })
        .collect()
}

/// Runs `compare`.
pub fn run(a: &CompareArgs) -> anyhow::Result<()> {
    if a.samples == 0 {
        bail!("--samples must be at least 1");
    }
    let reference = wildlod_io::read(&a.reference)?;
    let candidate = wildlod_io::read(&a.candidate)?;
    let ri = images(&reference, &a.reference);
    let ci = images(&candidate, &a.candidate);
    let r = EvalMesh::from_scene(&reference.scene, &ri);
    let c = EvalMesh::from_scene(&candidate.scene, &ci);
    let options = CompareOptions {
        samples: a.samples,
        texture_samples: a.texture_samples,
        seed: a.seed,
        ..CompareOptions::default()
    };
    let result = compare(&r, &c, &options);
    if a.json {
        let json = serde_json::to_string_pretty(&result).context("serializing the comparison")?;
        emit(&(json + "\n"))
    } else {
        emit(&text(&result))
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
