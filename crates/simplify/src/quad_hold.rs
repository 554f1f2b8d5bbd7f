//! The quad ordering held to the surface (Knodt 2024 §3.2, Eq. 4; issue 31,
//! decision 6: "let the tie tolerance give way when keeping a quad costs
//! more than the chord is worth").
//!
//! Knodt's ties treat collapses whose costs differ by less than ε as
//! equal and collapse whole quad chords among them. One ε does not fit
//! every mesh: where collapses are cheap next to it (a dense blade, a flat
//! panel) chords cost nothing and the mesh keeps its edge flow, but where
//! every collapse bends a curved surface (an organic model at 25% and
//! less) a chord is a sweep of collapses each up to ε dearer than the best
//! one, and the mean distance doubles for quads Knodt's own simplifier
//! does not keep either (`docs/evaluation-quads.md`).
//!
//! So the ordered run is measured against the input, beside the same run
//! with the ordering off, as attributes are ([`crate::AttributeOptions::geometry_tolerance`]):
//! where the ordered output's mean distance (Chamfer) is beyond
//! [`crate::QuadSettings::distance_tolerance`] times the plain run's,
//! three runs more at most look for the widest ties within: one at the
//! width a square law of the excess puts just inside the bound, one
//! corrected by what that run measured, and where both fall short the
//! narrowest ties; if none is within, the plain output is kept.
//! The largest distance is not held: a chord that moves a
//! few points farther is the trade the ordering makes.

use wildlod_mesh::Faces;

use crate::assemble::fidelity::Reference;
use crate::assemble::Simplified;
use crate::error::Error;
use crate::options::{Options, QuadMode};
use crate::report::QuadTies;

/// The narrowest tie width tried, as a share of the one set: narrower ties
/// keep about the quads of exact ties alone, which the plain run keeps too.
const MIN_SCALE: f64 = 1.0 / 16.0;

/// One run of the pipeline with `options`, reporting progress as a share
/// of its own work (0 to 1).
pub(crate) type RunWith<'a> =
    dyn Fn(&Options, &dyn Fn(f64)) -> Result<Simplified, Error> + Sync + 'a;

/// `options` with the quad ties scaled by `scale` (the tie distance, its
/// factor on the mesh's own deviation and the relative tolerance alike).
fn with_ties(options: &Options, scale: f64) -> Options {
    let mut o = options.clone();
    o.quad.epsilon *= scale;
    o.quad.tie_factor *= scale;
    o.quad.relative_epsilon *= scale;
    o
}

/// Whether the ordering is held on this run: it applies (an input with
/// quads, or [`QuadMode::Always`]), the target counts triangles (an error
/// target bounds every collapse already), the run is not a scene's first
/// pass, which only measures, and the tolerance is finite.
fn held(faces: &Faces, options: &Options) -> bool {
    let t = &options.target;
    let counted = t.ratio.is_some() || t.triangles.is_some();
    let tolerance = options.quad.distance_tolerance;
    options.quads_active(faces.arity_counts().1)
        && counted
        && t.error.is_none()
        && !options.record.error_curve
        && tolerance.is_finite()
}

/// Runs `run` with the quad ties as wide as
/// [`crate::QuadSettings::distance_tolerance`] allows (see the module
/// documentation), and returns its output with the options it was made
/// with ([`crate::Report::quad_ties`] set when the ordering was held).
pub(crate) fn hold_quad_ties(
    positions: &[[f32; 3]],
    faces: &Faces,
    options: &Options,
    run: &RunWith<'_>,
    progress: &dyn Fn(f64),
) -> Result<(Simplified, Options), Error> {
    let tolerance = options.quad.distance_tolerance;
    if tolerance.is_nan() || tolerance < 1.0 {
        return Err(Error::BadOption {
            name: "quad.distance_tolerance",
            value: tolerance,
        });
    }
    if !held(faces, options) {
        let out = run(options, progress)?;
        return Ok((out, options.clone()));
    }
    let plain_options = Options {
        quad: crate::options::QuadSettings {
            mode: QuadMode::Never,
            ..options.quad
        },
        ..options.clone()
    };
    // Both runs at once (each is mostly one thread's loop); progress
    // follows the ordered one, on the calling thread.
    let mut plain = None;
    let ordered = rayon::in_place_scope(|s| {
        s.spawn(|_| plain = Some(run(&plain_options, &|_| {})));
        run(options, &|f| progress(0.6 * f))
    })?;
    let plain = plain.unwrap_or_else(|| run(&plain_options, &|_| {}))?;
    let diagonal = crate::assemble::fidelity::diagonal(positions, faces);
    // A run whose attributes steered was measured by its steering check,
    // against the same samples of the input: its kept output's distance is
    // read from the report. Others are measured here (the input sampled
    // once, when first needed).
    let reference = std::cell::OnceCell::new();
    let chamfer = |o: &Simplified| match o.report.steering {
        Some(st) => {
            diagonal
                * if st.kept {
                    st.chamfer
                } else {
                    st.geometry_chamfer
                }
        }
        None => reference
            .get_or_init(|| Reference::new((positions, faces)))
            .chamfer((&o.positions, &o.faces)),
    };
    let plain_chamfer = chamfer(&plain);
    let invisible = options.attributes.invisible_distance / 10.0 * diagonal;
    let bound = (tolerance * plain_chamfer).max(plain_chamfer + invisible);
    let finish = |mut out: Simplified, scale: f64, c: f64, o: Options| {
        out.report.quad_ties = Some(QuadTies {
            scale,
            chamfer: c / diagonal,
            plain_chamfer: plain_chamfer / diagonal,
        });
        progress(1.0);
        Ok((out, o))
    };
    let c = chamfer(&ordered);
    if c <= bound {
        return finish(ordered, 1.0, c, options.clone());
    }
    // The ordering's excess over the plain run's mean distance grows
    // faster than the square of the tie width (spot_quadrangulated at 10%:
    // 0.91 of it at the full width, 0.13 at half). Two runs more, and a
    // third at the narrowest width where both fall short:
    // the width that a square law puts just inside the bound, then one
    // corrected by what that run measured: wider if it was within (at most
    // half way, in ratio, to the full width, which was not), narrower if
    // not. The widest within is kept, else the plain run. (A search of up
    // to six halvings and bisections kept more quads on one more corpus case,
    // at three times the time on a 180k-triangle quad mesh.)
    let aim = 0.9 * (bound - plain_chamfer);
    let towards = |scale: f64, c: f64| {
        let excess = c - plain_chamfer;
        if excess > 0.0 {
            scale * (aim / excess).sqrt()
        } else {
            2.0 * scale
        }
    };
    let mut at = 0.6;
    let mut attempt = |scale: f64| -> Result<(Simplified, f64, Options), Error> {
        let o = with_ties(options, scale);
        let start = at;
        at += 0.4 / 3.0;
        let out = run(&o, &|f| progress(start + 0.4 / 3.0 * f))?;
        let c = chamfer(&out);
        Ok((out, c, o))
    };
    let first = towards(1.0, c).clamp(MIN_SCALE, 0.5);
    if !(first.is_finite() && bound.is_finite()) {
        // A distance that is not a number (an output with nothing to
        // measure): nothing to search by.
        return finish(plain, 0.0, plain_chamfer, plain_options);
    }
    let (out, c1, o) = attempt(first)?;
    if c1 <= bound {
        let wider = towards(first, c1).clamp(first, first.sqrt());
        if wider > 1.05 * first {
            let (out2, c2, o2) = attempt(wider)?;
            if c2 <= bound {
                return finish(out2, wider, c2, o2);
            }
        }
        return finish(out, first, c1, o);
    }
    // (`max` after `min`: at the narrowest width there is none narrower.)
    let narrower = towards(first, c1).min(0.7 * first).max(MIN_SCALE);
    if narrower < first {
        let (out2, c2, o2) = attempt(narrower)?;
        if c2 <= bound {
            return finish(out2, narrower, c2, o2);
        }
        // Where the excess does not fall with the width (a smooth sphere
        // of quads at 25%: 1.38x the plain distance at full and half width,
        // 1.2x at a sixteenth), the narrowest ties are tried last: they
        // still keep most chords whose costs are equal.
        if narrower > MIN_SCALE {
            let (out3, c3, o3) = attempt(MIN_SCALE)?;
            if c3 <= bound {
                return finish(out3, MIN_SCALE, c3, o3);
            }
        }
    }
    finish(plain, 0.0, plain_chamfer, plain_options)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_the_ties_scales_every_tolerance_and_nothing_else() {
        let o = Options::default();
        let h = with_ties(&o, 0.25);
        assert_eq!(h.quad.epsilon, 0.25 * o.quad.epsilon);
        assert_eq!(h.quad.tie_factor, 0.25 * o.quad.tie_factor);
        assert_eq!(h.quad.relative_epsilon, 0.25 * o.quad.relative_epsilon);
        assert_eq!(
            Options {
                quad: o.quad,
                ..h.clone()
            },
            o
        );
    }

    #[test]
    fn only_counted_targets_with_quads_are_held() {
        let mut quads = Faces::new();
        quads.push(&[0, 1, 2, 3]);
        let tris = Faces::from_triangles(&[0, 1, 2]);
        let mut o = Options::default();
        o.target.ratio = Some(0.5);
        assert!(held(&quads, &o));
        assert!(!held(&tris, &o));
        o.quad.distance_tolerance = f64::INFINITY;
        assert!(!held(&quads, &o));
        o.quad.distance_tolerance = 1.15;
        o.target.error = Some(1e-3);
        assert!(!held(&quads, &o));
    }
}
