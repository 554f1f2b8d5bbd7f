//! The collapse loop (W §4, App. C.1), as a pipeline of small steps over
//! flat arrays: prepare (weld, normalize, build the complex) → virtual edges
//! → vertex quadrics → initial queue → loop { pop, guard, collapse, update }
//! → assemble the output.

use glam::DVec3;
use wildlod_mesh::bounds::{robust_bounds, OutlierRule};
use wildlod_mesh::weld::weld_positions;
use wildlod_mesh::Faces;

use crate::attributes::{
    AttributeInput, AttributeState, AttributeStream, FittedSkin, FittedStream, SkinStream,
};
use crate::complex::Complex;
use crate::error::Error;
use crate::fidelity::fidelity;
use crate::history::History;
use crate::options::Options;
use crate::report::{Report, SteeringOutcome};
use crate::run::Run;

/// The simplified polygons and how they map to the input.
#[derive(Clone, Debug, Default)]
pub struct Simplified {
    /// Output positions (input units).
    pub positions: Vec<[f32; 3]>,
    /// Output faces over `positions`; every face is an input face with
    /// merged vertices.
    pub faces: Faces,
    /// For every output face, the input face it is.
    pub face_origin: Vec<u32>,
    /// For every output corner, the input corner it is (so per-corner
    /// attributes can be carried over).
    pub corner_origin: Vec<u32>,
    /// For every input vertex, the output vertex it merged into
    /// (`u32::MAX` when its faces all vanished).
    pub vertex_map: Vec<u32>,
    /// The attribute streams given to [`simplify_with_attributes`], fitted
    /// (in the order given; empty without attributes).
    pub attributes: Vec<FittedStream>,
    /// The skin influences, one set per output vertex, when given.
    pub skin: Option<FittedSkin>,
    /// What was reached, and why it stopped.
    pub report: Report,
    /// The collapse history, when [`Options::record_history`] was set.
    pub history: Option<History>,
}

/// Simplifies polygon faces over `positions` (W §4): vertex-pair collapse on
/// the simplicial complex with virtual edges and the area-aware quadric.
///
/// Faces may be triangles, quads or n-gons, non-manifold, duplicated or
/// degenerate, in any number of components. Polygons of more than
/// [`crate::MAX_POLYGON_CORNERS`] corners are split into pieces of at most
/// that many first, so time stays near-linear in corners; the pieces are
/// output faces of the same input face ([`Report::split_polygons`] counts
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
pub fn simplify_with_attributes_and_progress(
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
    if !steers(attributes) || tolerance.is_infinite() || !counted || options.record_error_curve {
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
    let plain = AttributeInput {
        streams: attributes
            .streams
            .iter()
            .map(|s| AttributeStream { weight: 0.0, ..*s })
            .collect(),
        skin: attributes.skin.map(|s| SkinStream { weight: 0.0, ..s }),
        face_groups: attributes.face_groups,
    };
    let geometry = simplify_once(positions, faces, &plain, options, f64::INFINITY, &|f| {
        progress(0.4 * f)
    })?;
    let budget = tolerance.powi(2) * geometry.report.cost_level;
    let steered = simplify_once(positions, faces, attributes, options, budget, &|f| {
        progress(0.4 + 0.6 * f)
    })?;
    let input = (positions, faces);
    let g = fidelity(input, (&geometry.positions, &geometry.faces));
    let s = fidelity(input, (&steered.positions, &steered.faces));
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

/// Whether any attribute steers collapses.
fn steers(attributes: &AttributeInput<'_>) -> bool {
    attributes
        .streams
        .iter()
        .any(|s| s.weight > 0.0 && s.kind != crate::StreamKind::Carried)
        || attributes.skin.is_some_and(|s| s.weight > 0.0)
}

/// The diagonal of the bounding box of the positions faces use (1 when
/// there is none).
fn diagonal(positions: &[[f32; 3]], faces: &Faces) -> f64 {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &v in &faces.indices {
        let p = DVec3::from(positions[v as usize].map(f64::from));
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let d = (hi - lo).length();
    if d > 0.0 && d.is_finite() {
        d
    } else {
        1.0
    }
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
    let split = crate::large_polygons::split_large(positions, faces, attributes);
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
    let see = &options.see_through_faces;
    let see_through = |f: u32| {
        let input = split.as_ref().map_or(f, |s| s.input_face(f));
        see.get(input as usize).copied().unwrap_or(false)
    };
    // So does `face_instances`.
    let instances: Vec<u32> = if options.face_instances.is_empty() {
        Vec::new()
    } else {
        (0..faces.len() as u32)
            .map(|f| {
                let input = split.as_ref().map_or(f, |s| s.input_face(f));
                options.face_instances[input as usize].max(1)
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
    let kept: Vec<bool> = if options.refit_sweeps > 0 {
        prepared.complex.faces.iter().map(|f| f.len > 0).collect()
    } else {
        Vec::new()
    };
    let mut prepared = prepared;
    prepared.appearance_budget = appearance_budget;
    let mut run = Run::new(prepared, options, attrs);
    run.start(progress);
    run.collapse_loop(progress);
    run.refit(positions, faces, &kept);
    progress(1.0);
    let mut out = run.assemble(positions, attributes);
    if let Some(s) = &split {
        s.map_back(&mut out);
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

fn check_input(positions: &[[f32; 3]], faces: &Faces, options: &Options) -> Result<(), Error> {
    let n = positions.len();
    if faces.offsets.first() != Some(&0)
        || faces.offsets.last().map(|&o| o as usize) != Some(faces.indices.len())
        || faces.offsets.windows(2).any(|w| w[1] < w[0])
    {
        return Err(Error::MalformedFaces);
    }
    for f in 0..faces.len() {
        let face = faces.face(f);
        if face.len() < 3 {
            return Err(Error::FaceTooSmall { face: f });
        }
        if let Some(&v) = face.iter().find(|&&v| v as usize >= n) {
            return Err(Error::IndexOutOfRange {
                face: f,
                index: v,
                vertices: n,
            });
        }
    }
    for f in faces.iter() {
        for &v in f {
            if !positions[v as usize].iter().all(|c| c.is_finite()) {
                return Err(Error::NonFinitePosition { vertex: v as usize });
            }
        }
    }
    let o = options;
    let bad = |name: &'static str, value: f64| Err(Error::BadOption { name, value });
    if let Some(r) = o.target.ratio {
        if !(0.0..=1.0).contains(&r) {
            return bad("ratio", r);
        }
    }
    if let Some(e) = o.target.error {
        if !(e >= 0.0 && e.is_finite()) {
            return bad("error", e);
        }
    }
    if !(o.virtual_edge_radius >= 0.0 && o.virtual_edge_radius.is_finite()) {
        return bad("virtual_edge_radius", o.virtual_edge_radius);
    }
    if !(o.metric.regularization >= 0.0 && o.metric.regularization.is_finite()) {
        return bad("regularization", o.metric.regularization);
    }
    let non_negative = [
        ("boundary_area_weight", o.metric.boundary_area_weight),
        ("border_weight", o.metric.border_weight),
        ("gluing_weight", o.metric.gluing_weight),
        ("pinch_distance", o.metric.pinch_distance),
        ("tangent_weight", o.metric.tangent_weight),
        ("quad.epsilon", o.quad.epsilon),
        ("quad.relative_epsilon", o.quad.relative_epsilon),
        ("quad.tangent_weight", o.quad.tangent_weight),
        ("quad.symmetry", o.quad.symmetry),
        ("quad.joints", o.quad.joints),
        ("quad.attribute_weight", o.quad.attribute_weight),
        ("partition.handoff", o.partition.handoff),
    ];
    for (name, value) in non_negative {
        if !(value >= 0.0 && value.is_finite()) {
            return bad(name, value);
        }
    }
    if !(o.quad.symmetry_distance > 0.0 && o.quad.symmetry_distance.is_finite()) {
        return bad("quad.symmetry_distance", o.quad.symmetry_distance);
    }
    if !o.see_through_faces.is_empty() && o.see_through_faces.len() != faces.len() {
        return Err(Error::SeeThroughCount {
            flags: o.see_through_faces.len(),
            faces: faces.len(),
        });
    }
    if !o.face_instances.is_empty() && o.face_instances.len() != faces.len() {
        return Err(Error::InstanceCount {
            counts: o.face_instances.len(),
            faces: faces.len(),
        });
    }
    if !o.vertex_weights.is_empty() {
        if o.vertex_weights.len() != n {
            return Err(Error::WeightCount {
                weights: o.vertex_weights.len(),
                vertices: n,
            });
        }
        if let Some((v, &w)) = o
            .vertex_weights
            .iter()
            .enumerate()
            .find(|(_, w)| !(w.is_finite() && **w >= 0.0))
        {
            return Err(Error::BadWeight {
                vertex: v,
                weight: w,
            });
        }
    }
    Ok(())
}

/// The input, welded, normalized to a unit-diagonal box centered at the
/// origin, and built into a complex.
pub(crate) struct Prepared {
    pub complex: Complex,
    pub cleaned: usize,
    /// Twins dropped as hidden (see `twins.rs`).
    pub hidden_twins: usize,
    /// Triangles a ratio is of: the cleaned surface with every twin.
    pub ratio_base: usize,
    /// Input vertex → welded vertex.
    pub weld: Vec<u32>,
    pub center: DVec3,
    pub scale: f64,
    pub input_triangles: usize,
    /// Per welded vertex importance (empty: all 1).
    pub weights: Vec<f64>,
    /// The first input vertex of each welded vertex, whose position bits
    /// an untouched vertex keeps (the input's positions are the caller's:
    /// not copied).
    pub rep: Vec<u32>,
    /// Welded vertices far from the bulk of the others (see
    /// [`wildlod_mesh::bounds`]; empty: none): they neither move nor
    /// vanish, and the faces they touch weigh nothing in the quadrics.
    pub outliers: Vec<bool>,
    /// The input vertex of each outlier, ascending.
    pub outlier_inputs: Vec<u32>,
    /// The geometric error budget within which appearance steers (see
    /// `CostModel::appearance_budget`); infinite by default.
    pub appearance_budget: f64,
}

pub(crate) fn prepare(
    positions: &[[f32; 3]],
    faces: &Faces,
    options: &Options,
    with_attributes: bool,
    see_through: &dyn Fn(u32) -> bool,
    instances: Vec<u32>,
) -> Prepared {
    let (weld, nw) = weld_positions(positions);
    let mut rep = vec![u32::MAX; nw];
    for (v, &w) in weld.iter().enumerate() {
        if rep[w as usize] == u32::MAX {
            rep[w as usize] = v as u32;
        }
    }
    // Normalize by the bounds of the bulk of the vertices faces use: a
    // vertex far from all the others (a height of -1e30 an exporter wrote)
    // would otherwise set the unit, and every real error would vanish
    // beside it. Such outliers stay where they are (see `Prepared::outliers`).
    let mut used = vec![false; nw];
    for &v in &faces.indices {
        used[weld[v as usize] as usize] = true;
    }
    let used_ids: Vec<u32> = (0..nw as u32).filter(|&w| used[w as usize]).collect();
    let bounds = robust_bounds(
        used_ids
            .iter()
            .map(|&w| positions[rep[w as usize] as usize].map(f64::from)),
        &OutlierRule::default(),
    );
    let mut outliers = vec![false; if bounds.outliers.is_empty() { 0 } else { nw }];
    for &k in &bounds.outliers {
        outliers[used_ids[k] as usize] = true;
    }
    let (lo, hi) = (DVec3::from(bounds.min), DVec3::from(bounds.max));
    let (center, diag) = if bounds.is_empty() {
        (DVec3::ZERO, 1.0)
    } else {
        (0.5 * (lo + hi), (hi - lo).length())
    };
    let scale = if diag > 0.0 { diag } else { 1.0 };
    let pos: Vec<DVec3> = rep
        .iter()
        .map(|&v| (DVec3::from(positions[v as usize].map(f64::from)) - center) / scale)
        .collect();
    let indices: Vec<u32> = faces.indices.iter().map(|&v| weld[v as usize]).collect();
    // The partitioned path works on faces alone until its last pass: the
    // star lists would be built for nothing.
    // Attribute wedges live on the global complex: no partitioned phase.
    // Drawn triangles: each face as many times as it is drawn.
    let input_triangles = if instances.is_empty() {
        faces.triangulated_count()
    } else {
        faces
            .iter()
            .zip(&instances)
            .map(|(f, &k)| f.len().saturating_sub(2) * k as usize)
            .sum()
    };
    let (mut complex, cleaned) = Complex::faces_only(pos, &faces.offsets, &indices);
    complex.set_instances(instances);
    // The ratio is of the surface before hidden twins go: they cost
    // nothing to drop, and the budget then buys visible detail.
    let ratio_base = complex.triangles;
    let hidden_twins = if options.drop_hidden_twins {
        crate::twins::drop_hidden_twins(&mut complex, see_through)
    } else {
        0
    };
    if with_attributes || !crate::run::may_partition(faces, options) {
        complex.build_adjacency();
    }
    let mut weights = Vec::new();
    if !options.vertex_weights.is_empty() {
        // A welded vertex is as important as its most important copy.
        weights = vec![0.0f64; nw];
        for (v, &w) in weld.iter().enumerate() {
            let x = &mut weights[w as usize];
            *x = x.max(options.vertex_weights[v] as f64);
        }
    }
    Prepared {
        appearance_budget: f64::INFINITY,
        outlier_inputs: bounds
            .outliers
            .iter()
            .map(|&k| rep[used_ids[k] as usize])
            .collect(),
        outliers,
        rep,
        complex,
        cleaned: cleaned.degenerate + cleaned.duplicate,
        hidden_twins,
        ratio_base,
        weld,
        center,
        scale,
        input_triangles,
        weights,
    }
}
