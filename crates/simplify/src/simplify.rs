//! The simplifier's entry points on plain arrays: the six steps in order,
//! each a module that imports only the ones before it — `prepare` (check,
//! weld, normalize, build the complex; W §4.1) → `edges` (virtual edges;
//! W §4.1) → `terms` (the quadrics and every cost term; W §4.2, Knodt §3)
//! → `collapse` (the loop; W Alg. 1, Knodt Alg. 1) → `refit` → `assemble`
//! (the output and its maps back to the input). The steering check (two
//! runs, appearance within a geometric budget) is decided here.

use wildlod_mesh::Faces;

use crate::assemble::fidelity::{diagonal, Reference};
use crate::assemble::layers::keep_layers;
use crate::assemble::{assemble, Simplified};
use crate::collapse::Run;
use crate::error::Error;
use crate::input::{AttributeInput, AttributeStream, SeamPolicy, SkinStream, StreamKind};
use crate::options::{
    AttributeOptions, Guards, Metric, Options, Partition, QuadSettings, Record, Target,
};
use crate::prepare::large_polygons::split_large;
use crate::prepare::{check_input, prepare};
use crate::quad_hold::hold_quad_ties;
use crate::refit::refit_run;
use crate::report::{SteeringOutcome, StopReason};
use crate::terms::attributes::AttributeState;

/// Simplifies polygon faces over `positions` (W §4): vertex-pair collapse on
/// the simplicial complex with virtual edges and the area-aware quadric.
///
/// Faces may be triangles, quads or n-gons, non-manifold, duplicated or
/// degenerate, in any number of components. Polygons of more than
/// [`crate::MAX_POLYGON_CORNERS`] corners are split into pieces of at most
/// that many first, so time stays near-linear in corners; the pieces are
/// output faces of the same input face ([`crate::Report::split_polygons`] counts
/// the polygons split). Equal positions are welded
/// first. The result reaches the target within one triangle whenever the
/// complex has enough collapsible edges; otherwise the report says why not.
/// Deterministic: the same input and options give the same output on any
/// number of threads.
pub fn simplify_polygons(
    positions: &[[f32; 3]],
    faces: &Faces,
    options: &Options,
) -> Result<Simplified, Error> {
    simplify_polygons_with_progress(positions, faces, options, &|_| {})
}

/// [`simplify_polygons`], calling `progress` with the fraction of the work
/// done (0 to 1) about a hundred times during the run, from the calling
/// thread. For progress bars; the result is the same.
pub fn simplify_polygons_with_progress(
    positions: &[[f32; 3]],
    faces: &Faces,
    options: &Options,
    progress: &dyn Fn(f64),
) -> Result<Simplified, Error> {
    simplify_with_attributes_and_progress(
        positions,
        faces,
        &AttributeInput::default(),
        options,
        progress,
    )
}

/// [`simplify_polygons`] with attributes (UV sets, normals, colors, morph
/// deltas, skin weights; like meshoptimizer's `simplifyWithAttributes`,
/// as plain arrays): they steer the collapses through Hoppe's attribute
/// quadrics (weights per stream), keep their seams (see
/// [`crate::SeamPolicy`]), and come back fitted at the output positions in
/// [`Simplified::attributes`] and [`Simplified::skin`].
///
/// ```
/// use wildlod_simplify::{simplify_with_attributes, AttributeInput, AttributeStream, Options, StreamKind, Target};
/// use wildlod_mesh::shapes;
/// // A grid whose UV is its (x, y): a linear field survives exactly.
/// let grid = shapes::quad_grid(8, 8);
/// let uv: Vec<f32> = grid.positions.iter().flat_map(|p| [p[0], p[1]]).collect();
/// let indices = grid.faces.indices.clone();
/// let input = AttributeInput {
///     streams: vec![AttributeStream {
///         components: 2,
///         values: &uv,
///         indices: &indices,
///         weight: 1.0,
///         seams: true,
///         kind: StreamKind::TexCoord,
///     }],
///     ..AttributeInput::default()
/// };
/// let options = Options { target: Target { ratio: Some(0.1), ..Target::default() }, ..Options::default() };
/// let out = simplify_with_attributes(&grid.positions, &grid.faces, &input, &options)?;
/// let fitted = &out.attributes[0];
/// for (corner, &v) in out.faces.indices.iter().enumerate() {
///     let p = out.positions[v as usize];
///     let i = fitted.indices[corner] as usize;
///     assert!((fitted.values[2 * i] - p[0]).abs() < 1e-5);
///     assert!((fitted.values[2 * i + 1] - p[1]).abs() < 1e-5);
/// }
/// # Ok::<(), wildlod_simplify::Error>(())
/// ```
pub fn simplify_with_attributes(
    positions: &[[f32; 3]],
    faces: &Faces,
    attributes: &AttributeInput<'_>,
    options: &Options,
) -> Result<Simplified, Error> {
    simplify_with_attributes_and_progress(positions, faces, attributes, options, &|_| {})
}

/// [`simplify_with_attributes`] with a progress callback (see
/// [`simplify_polygons_with_progress`]).
///
/// Constraints cost triangles, not distance: where locked borders, kept
/// topology or kept seams keep a run from its triangle target, the run
/// does not go on to its floor, making the collapses left whatever they
/// cost (a sofa with its cushions' borders locked lost its whole body at
/// 10%). It stops where its error reaches what a run without those
/// constraints reaches at as many triangles as they leave (its floor).
/// And any constrained run, whether it reached its target or not, stops
/// lower where its output, measured against the input (Hausdorff and
/// Chamfer), would be farther from it than a run without the constraints
/// at the target ([`crate::Guards::hold_target`] when set), beyond
/// [`crate::AttributeOptions::geometry_tolerance`];
/// [`crate::Report::held_by_constraints`] says so.
pub fn simplify_with_attributes_and_progress(
    positions: &[[f32; 3]],
    faces: &Faces,
    attributes: &AttributeInput<'_>,
    options: &Options,
    progress: &dyn Fn(f64),
) -> Result<Simplified, Error> {
    // The quad ordering's ties as wide as the surface allows; what follows
    // works with the width chosen.
    let (out, options) = hold_quad_ties(
        positions,
        faces,
        options,
        &|o, p| simplify_steered(positions, faces, attributes, o, p),
        progress,
    )?;
    let options = &options;
    let t = &options.target;
    let counted = t.ratio.is_some() || t.triangles.is_some();
    if !constrained(options) || !counted || t.error.is_some() || options.record.error_curve {
        return Ok(out);
    }
    let r = &out.report;
    let out_of_reach = r.stop == Some(StopReason::NoCollapsibleEdges)
        && r.output_triangles > r.target_triangles + 1;
    let unconstrained = Options {
        guards: Guards {
            lock_borders: false,
            keep_topology: false,
            ..options.guards
        },
        attributes: AttributeOptions {
            seams: if options.attributes.seams == SeamPolicy::Keep {
                SeamPolicy::default()
            } else {
                options.attributes.seams
            },
            ..options.attributes
        },
        record: Record::default(),
        ..options.clone()
    };
    // The constrained output is measured against the input (Hausdorff and
    // Chamfer) and compared with a run without the constraints at the
    // target, geometry only (what attributes are held to as well: the
    // user's output without the constraints is within their tolerance of
    // it). The quadrics' error cannot stand in for the measurement: where
    // locked rims or kept topology pin a part, its vertices collapse
    // toward the pinned ones, most of their planes stay near, a few go
    // far, and the area-weighted mean stays small (a sofa's legs vanished
    // and its arms became flaps at 3.6× the free run's Hausdorff, the
    // spider with its borders locked reached 10% at 3.9×).
    let geometry = simplify_once(
        positions,
        faces,
        &unsteered(attributes),
        &Options {
            target: match options.guards.hold_target {
                Some(triangles) => Target {
                    triangles: Some(triangles),
                    ..Target::default()
                },
                None => options.target,
            },
            metric: Metric {
                tangent_weight: 0.0,
                ..unconstrained.metric
            },
            quad: QuadSettings {
                tangent_weight: 0.0,
                ..unconstrained.quad
            },
            ..unconstrained.clone()
        },
        f64::INFINITY,
        &|_| {},
    )?;
    let reference = Reference::new((positions, faces));
    let bound = reference.fidelity((&geometry.positions, &geometry.faces));
    let diagonal = diagonal(positions, faces);
    let a = &options.attributes;
    let close = |o: &Simplified| {
        let d = reference.fidelity((&o.positions, &o.faces));
        let within = |held: f64, free: f64, invisible: f64| {
            held <= (a.geometry_tolerance * free).max(free + invisible * diagonal)
        };
        within(d.hausdorff, bound.hausdorff, a.invisible_distance)
            && within(d.chamfer, bound.chamfer, a.invisible_distance / 10.0)
    };
    let mut level = out.report.error;
    if out_of_reach {
        // A run that went on to its floor made every collapse left,
        // whatever it cost: it stops instead where its error reaches what
        // a run without the constraints has at as many triangles as they
        // leave, no worse than the free run at the same size.
        let curve = Options {
            // The whole error curve: every collapse in the one loop; no
            // history, as only the curve is read.
            record: Record {
                error_curve: true,
                history: false,
            },
            partition: Partition {
                min_triangles: usize::MAX,
                ..options.partition
            },
            ..unconstrained
        };
        let floor = out.report.output_triangles;
        let free = simplify_steered(positions, faces, attributes, &curve, &|_| {})?.report;
        let at_floor = free
            .error_curve
            .iter()
            .find(|&&(t, _)| t <= floor)
            .map_or(free.error, |&(_, e)| e);
        if at_floor.is_finite() && at_floor < level {
            level = at_floor;
        }
    }
    let held = |level: f64| {
        let held = Options {
            target: Target {
                error: Some(level),
                ..options.target
            },
            ..options.clone()
        };
        simplify_steered(positions, faces, attributes, &held, &|_| {})
    };
    let first = out.report.error;
    let mut out = if level < first { held(level)? } else { out };
    // (A level of zero has nothing to halve: its output is the input's
    // surface, as close as any.)
    if level > 0.0 && level.is_finite() && !close(&out) {
        // Halve the level until the output is close enough, then narrow
        // between the last level that was not and the first that was.
        let mut far = level;
        let mut found = false;
        for _ in 0..HELD_HALVINGS {
            level *= 0.5;
            out = held(level)?;
            if close(&out) {
                found = true;
                break;
            }
            far = level;
        }
        if found {
            for _ in 0..HELD_REFINEMENTS {
                let mid = (level * far).sqrt();
                let candidate = held(mid)?;
                if close(&candidate) {
                    (out, level) = (candidate, mid);
                } else {
                    far = mid;
                }
            }
        }
    }
    if level < first {
        out.report.held_by_constraints = Some(level);
    }
    Ok(out)
}

/// How many times a held run's error level may halve before its output is
/// as close to the input as the free run's (each halving is a run; a
/// thousandth of the first level keeps nearly every input triangle).
const HELD_HALVINGS: usize = 10;

/// Runs spent narrowing the held level once one is close enough: each
/// halves the ratio between the closest level too far and the level kept.
const HELD_REFINEMENTS: usize = 2;

/// Whether `options` hold the surface with constraints that can keep a
/// run from its target: locked borders, kept topology, kept seams.
fn constrained(options: &Options) -> bool {
    options.guards.lock_borders
        || options.guards.keep_topology
        || options.attributes.seams == SeamPolicy::Keep
}

/// [`simplify_with_attributes_and_progress`] without the constraints'
/// limit: the steering check (two runs, appearance within a geometric
/// budget) around [`simplify_once`].
fn simplify_steered(
    positions: &[[f32; 3]],
    faces: &Faces,
    attributes: &AttributeInput<'_>,
    options: &Options,
    progress: &dyn Fn(f64),
) -> Result<Simplified, Error> {
    check_input(positions, faces, options)?;
    let tolerance = options.attributes.geometry_tolerance;
    if tolerance.is_nan() || tolerance < 1.0 {
        return Err(Error::BadOption {
            name: "attributes.geometry_tolerance",
            value: tolerance,
        });
    }
    let t = &options.target;
    let counted = t.ratio.is_some() || t.triangles.is_some();
    let regularizes = options.metric.tangent_weight > 0.0 || options.quad.tangent_weight > 0.0;
    if !(steers(attributes) || regularizes)
        || tolerance.is_infinite()
        || !counted
        || options.record.error_curve
    {
        // Nothing steers, the user lets it steer without bound, an error
        // target bounds every collapse's distance already, or the run only
        // measures how far it could go (a scene's first pass).
        return simplify_once(
            positions,
            faces,
            attributes,
            options,
            f64::INFINITY,
            progress,
        );
    }
    // Attributes steer within the geometric error of a run that lets
    // them fit but not steer, and keep that run's result unless theirs is
    // as close to the input (see `AttributeOptions::geometry_tolerance`).
    // Knodt's tangent quadrics (and the symmetry that weighs them) trade
    // distance for regular spacing: they are held to the same bound, the
    // plain run made without them.
    let plain_options = Options {
        metric: Metric {
            tangent_weight: 0.0,
            ..options.metric
        },
        quad: QuadSettings {
            tangent_weight: 0.0,
            ..options.quad
        },
        ..options.clone()
    };
    let geometry = simplify_once(
        positions,
        faces,
        &unsteered(attributes),
        &plain_options,
        f64::INFINITY,
        &|f| progress(0.4 * f),
    )?;
    let budget = tolerance.powi(2) * geometry.report.cost_level;
    let steered = simplify_once(positions, faces, attributes, options, budget, &|f| {
        progress(0.4 + 0.6 * f)
    })?;
    // The input is sampled and indexed once for both results.
    let (g, s) = {
        let reference = Reference::new((positions, faces));
        (
            reference.fidelity((&geometry.positions, &geometry.faces)),
            reference.fidelity((&steered.positions, &steered.faces)),
        )
    };
    let diagonal = diagonal(positions, faces);
    let a = &options.attributes;
    let within = |steered: f64, plain: f64, invisible: f64| {
        steered <= (tolerance * plain).max(plain + invisible * diagonal)
    };
    let kept = within(s.hausdorff, g.hausdorff, a.invisible_distance)
        && within(s.chamfer, g.chamfer, a.invisible_distance / 10.0);
    let mut out = if kept { steered } else { geometry };
    out.report.steering = Some(SteeringOutcome {
        kept,
        hausdorff: s.hausdorff / diagonal,
        chamfer: s.chamfer / diagonal,
        geometry_hausdorff: g.hausdorff / diagonal,
        geometry_chamfer: g.chamfer / diagonal,
    });
    Ok(out)
}

/// `attributes` fitted and carried but steering nothing (weights 0).
fn unsteered<'a>(attributes: &AttributeInput<'a>) -> AttributeInput<'a> {
    AttributeInput {
        streams: attributes
            .streams
            .iter()
            .map(|s| AttributeStream { weight: 0.0, ..*s })
            .collect(),
        skin: attributes.skin.map(|s| SkinStream { weight: 0.0, ..s }),
        morphs: attributes.morphs.clone(),
        face_groups: attributes.face_groups,
    }
}

/// Whether any attribute steers collapses.
fn steers(attributes: &AttributeInput<'_>) -> bool {
    attributes
        .streams
        .iter()
        .any(|s| s.weight > 0.0 && s.kind != StreamKind::Carried)
        || attributes.skin.is_some_and(|s| s.weight > 0.0)
}

/// One run of the pipeline, appearance within `appearance_budget` (see
/// `CostModel::appearance_budget`).
fn simplify_once(
    positions: &[[f32; 3]],
    faces: &Faces,
    attributes: &AttributeInput<'_>,
    options: &Options,
    appearance_budget: f64,
    progress: &dyn Fn(f64),
) -> Result<Simplified, Error> {
    // Polygons above a few dozen corners are worked on in pieces (see
    // `large_polygons.rs`): otherwise their collapses cost O(k²) each. The
    // per-corner streams and per-face groups follow the pieces.
    let split = split_large(positions, faces, attributes);
    let split_attributes = split.as_ref().map(|s| s.attributes(attributes));
    let attributes = match &split_attributes {
        Some(a) => a.input(attributes),
        None => attributes.clone(),
    };
    let attributes = &attributes;
    let faces = split.as_ref().map_or(faces, |s| &s.faces);
    if !(options.attributes.seam_weight >= 0.0 && options.attributes.seam_weight.is_finite()) {
        return Err(Error::BadOption {
            name: "attributes.seam_weight",
            value: options.attributes.seam_weight,
        });
    }
    let with_attributes = !attributes.is_empty();
    // `see_through_faces` names input faces; the complex sees the pieces.
    let see = &options.data.see_through_faces;
    let see_through = |f: u32| {
        let input = split.as_ref().map_or(f, |s| s.input_face(f));
        see.get(input as usize).copied().unwrap_or(false)
    };
    // So does `face_instances`.
    let instances: Vec<u32> = if options.data.face_instances.is_empty() {
        Vec::new()
    } else {
        (0..faces.len() as u32)
            .map(|f| {
                let input = split.as_ref().map_or(f, |s| s.input_face(f));
                options.data.face_instances[input as usize].max(1)
            })
            .collect()
    };
    let prepared = prepare(
        positions,
        faces,
        options,
        with_attributes,
        &see_through,
        instances,
    );
    let attrs = if with_attributes {
        let corner_vertex: Vec<u32> = faces
            .indices
            .iter()
            .map(|&v| prepared.weld[v as usize])
            .collect();
        let quads = faces.arity_counts().1;
        let factor = if options.quads_active(quads) {
            options.quad.attribute_weight
        } else {
            1.0
        };
        Some(AttributeState::new(
            attributes,
            &corner_vertex,
            &prepared.complex,
            &prepared.weights,
            options.attributes.seams,
            factor,
        )?)
    } else {
        None
    };
    // The input faces the complex keeps (duplicates and twins folded
    // away), for the refit to see the surface the quadrics saw.
    let kept: Vec<bool> = if options.metric.refit_sweeps > 0 {
        prepared.complex.faces.iter().map(|f| f.len > 0).collect()
    } else {
        Vec::new()
    };
    let mut prepared = prepared;
    prepared.appearance_budget = appearance_budget;
    let mut run = Run::new(prepared, options, attrs);
    run.start(progress);
    run.collapse_loop(progress);
    let mut collapsed = run.finish();
    refit_run(&mut collapsed, positions, faces, &kept);
    progress(1.0);
    let mut out = assemble(collapsed, positions, attributes);
    if options.metric.keep_layers {
        out.report.layer_vertices = keep_layers(positions, faces, &mut out);
    }
    if let Some(s) = &split {
        out.map_back(s);
    }
    Ok(out)
}

/// Simplifies a triangle list (three indices per triangle); see
/// [`simplify_polygons`].
pub fn simplify_triangles(
    positions: &[[f32; 3]],
    indices: &[u32],
    options: &Options,
) -> Result<Simplified, Error> {
    if indices.len() % 3 != 0 {
        return Err(Error::IndexCount(indices.len()));
    }
    simplify_polygons(positions, &Faces::from_triangles(indices), options)
}
