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
    // As a renderer shows them at rest: skinned meshes through their
    // joints' rest transforms (an exporter may place a skinned mesh's node
    // anywhere, since renderers ignore it).
    let r = EvalMesh::from_scene(&wildlod_eval::posed(&reference.scene, None, 0.0), &ri);
    let c = EvalMesh::from_scene(&wildlod_eval::posed(&candidate.scene, None, 0.0), &ci);
    let options = CompareOptions {
        samples: a.samples,
        texture_samples: a.texture_samples,
        seed: a.seed,
        ..CompareOptions::default()
    };
    let result = compare(&r, &c, &options);
    let animated = match a.animation {
        Some(index) => Some(animated(
            &reference,
            &candidate,
            (&ri, &ci),
            index,
            a,
            &options,
        )?),
        None => None,
    };
    if a.json {
        let mut json = serde_json::to_value(&result).context("serializing the comparison")?;
        if let (Some(anim), Some(obj)) = (&animated, json.as_object_mut()) {
            obj.insert(
                "animation".into(),
                serde_json::to_value(anim).context("serializing the animation comparison")?,
            );
        }
        let json = serde_json::to_string_pretty(&json).context("serializing the comparison")?;
        emit(&(json + "\n"))
    } else {
        let mut s = text(&result);
        if let Some(anim) = &animated {
            s += &anim.text();
        }
        emit(&s)
    }
}

/// Distances between the two files posed at one frame.
#[derive(serde::Serialize)]
struct Frame {
    time: f64,
    hausdorff: f64,
    chamfer_mean: f64,
    chamfer_squared: f64,
}

/// Distances at animation frames (the `animation` key of the JSON).
#[derive(serde::Serialize)]
struct Animated {
    index: usize,
    name: String,
    fps: f64,
    hausdorff_mean: f64,
    hausdorff_max: f64,
    chamfer_mean_mean: f64,
    chamfer_mean_max: f64,
    frames: Vec<Frame>,
}

impl Animated {
    fn text(&self) -> String {
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

/// Compares both files posed at `a.frames` frames of animation `index`.
fn animated(
    reference: &wildlod_io::Document,
    candidate: &wildlod_io::Document,
    images: (&[Option<Image>], &[Option<Image>]),
    index: usize,
    a: &CompareArgs,
    options: &CompareOptions,
) -> anyhow::Result<Animated> {
    let Some(anim) = reference.scene.animations.get(index) else {
        bail!(
            "{}: has {} animations, so --animation {index} does not exist",
            a.reference.display(),
            reference.scene.animations.len()
        );
    };
    if candidate.scene.animations.len() <= index {
        bail!(
            "{}: has {} animations, so --animation {index} does not exist",
            a.candidate.display(),
            candidate.scene.animations.len()
        );
    }
    if a.frames == 0 || !(a.fps.is_finite() && a.fps > 0.0) {
        bail!("--frames must be at least 1 and --fps positive");
    }
    let mut frames = Vec::with_capacity(a.frames);
    for k in 0..a.frames {
        // Past the animation's end the last pose holds.
        let time = (k as f64 / a.fps).min(anim.duration as f64);
        let pr = wildlod_eval::posed(&reference.scene, Some(index), time as f32);
        let pc = wildlod_eval::posed(&candidate.scene, Some(index), time as f32);
        let c = compare(
            &EvalMesh::from_scene(&pr, images.0),
            &EvalMesh::from_scene(&pc, images.1),
            &CompareOptions {
                texture_samples: 0,
                ..*options
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
        fps: a.fps,
        hausdorff_mean: mean(|f| f.hausdorff),
        hausdorff_max: max(|f| f.hausdorff),
        chamfer_mean_mean: mean(|f| f.chamfer_mean),
        chamfer_mean_max: max(|f| f.chamfer_mean),
        frames,
    })
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
