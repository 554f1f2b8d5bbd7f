//! What a simplification run reached and why it stopped.

/// Why the collapse loop ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The triangle target was reached.
    TargetReached,
    /// Every remaining collapse exceeds the error limit.
    ErrorLimit,
    /// No collapsible edge is left: the guards rejected the rest, or each
    /// remaining collapse would overshoot the target by more than one
    /// triangle. [`Report::rejected`] says which.
    NoCollapsibleEdges,
    /// The input was already at or below the target.
    NothingToDo,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StopReason::TargetReached => "target reached",
            StopReason::ErrorLimit => "error limit reached",
            StopReason::NoCollapsibleEdges => "no collapsible edge left",
            StopReason::NothingToDo => "already at target",
        })
    }
}

/// Collapses the guards refused, by guard.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rejections {
    /// A surviving face would have turned past the normal limit.
    pub normal_flip: usize,
    /// The link condition failed (topology would change).
    pub topology: usize,
    /// A border vertex would have moved.
    pub locked_border: usize,
    /// The collapse would remove more triangles than left to the target.
    pub overshoot: usize,
    /// The collapse's error exceeded the error limit.
    pub error_limit: usize,
    /// A surviving face would have flattened to a line (its corners on
    /// one straight run), where the flip guard could no longer judge it.
    pub flat_border: usize,
}

/// Whether the attributes' steering was kept (see
/// [`crate::AttributeOptions::geometry_tolerance`]), with the distances
/// both runs measured, relative to the input's bounding-box diagonal
/// (sampled at vertices and face centres, both directions).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SteeringOutcome {
    /// The steered result was as close to the input as the tolerance
    /// asks, and is the output; otherwise the result of the run in which
    /// attributes were fitted but did not steer is.
    pub kept: bool,
    /// The steered result's largest distance to the input.
    pub hausdorff: f64,
    /// The steered result's mean distance to the input.
    pub chamfer: f64,
    /// The unsteered result's largest distance to the input.
    pub geometry_hausdorff: f64,
    /// The unsteered result's mean distance to the input.
    pub geometry_chamfer: f64,
}

/// How wide the quad ordering's ties were in the output (see
/// [`crate::QuadSettings::distance_tolerance`]), with the mean distances
/// (Chamfer, both ways) of the output and of the run with the ordering
/// off, relative to the input's bounding-box diagonal.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadTies {
    /// The tie distance the output was made with, as a share of the one
    /// set: 1 as set, 0.5 after one halving, and so on; 0 when the output
    /// is the run without the ordering.
    pub scale: f64,
    /// The output's mean distance to the input.
    pub chamfer: f64,
    /// The mean distance to the input of the run without the ordering.
    pub plain_chamfer: f64,
}

/// The outcome of a simplification run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// Triangles of the triangulated input (a quad counts 2), each face as
    /// many times as it is drawn ([`crate::InputData::face_instances`]).
    pub input_triangles: usize,
    /// Triangles the run aimed for.
    pub target_triangles: usize,
    /// Triangles of the triangulated output, counted as the input's.
    pub output_triangles: usize,
    /// Faces removed before simplifying because they were degenerate (fewer
    /// than three distinct vertices) or duplicates of another face.
    pub cleaned_faces: usize,
    /// Reversed copies of faces that cannot be seen (inside a closed or
    /// almost closed surface), dropped before simplifying (see
    /// [`crate::Guards::drop_hidden_twins`]).
    pub hidden_twins: usize,
    /// Parts wholly inside another part that is closed, faces outward and
    /// is drawn opaque, dropped before simplifying (see
    /// [`crate::Guards::drop_enclosed_parts`]).
    pub enclosed_parts: usize,
    /// Collapses made.
    pub collapses: usize,
    /// Of those, the ones the parallel first phase made (see
    /// [`crate::Partition`]); 0 when it did not run.
    pub parallel_collapses: usize,
    /// Passes of the parallel first phase.
    pub parallel_passes: usize,
    /// Input vertices far from the bulk of the others (by
    /// [`wildlod_mesh::bounds::robust_bounds`]'s rule), ascending: errors
    /// are relative to the bulk's diagonal, and these vertices stayed where
    /// they were, their faces weighing nothing in the error.
    pub outliers: Vec<u32>,
    /// Virtual edges added between separate components (W §4.1.1).
    pub virtual_edges: usize,
    /// The virtual-edge radius (relative to the diagonal) parts were
    /// bridged at, when bridging every gap under the requested
    /// `virtual_edge_radius` would have exceeded the search's budget, which
    /// is linear in the input (many parts much smaller than the radius:
    /// see [`crate::Guards::virtual_edge_radius`]); `None` when the
    /// requested radius was used.
    pub virtual_radius_reduced: Option<f64>,
    /// The rank (the loop's cost units: area times squared distance on the
    /// unit-diagonal mesh, with every term) below which 99% of the loop's
    /// collapses were made: the level the run ended at. Collapses of the
    /// parallel first phase are not counted (they are cheaper).
    pub cost_level: f64,
    /// Largest error of a collapse made, as a distance relative to the
    /// bounding-box diagonal (root mean square distance to the planes the
    /// collapsed vertex accumulated).
    pub error: f64,
    /// The soft symmetry weights ran into their work cap: edges past it
    /// got no symmetry weight (see [`crate::QuadSettings::symmetry`]).
    pub symmetry_truncated: bool,
    /// Why the run stopped.
    pub stop: Option<StopReason>,
    /// A collapse near the target removed faces with their twins, which go
    /// together, and went past the target by more than one triangle (by at
    /// most one face's copies).
    pub twin_slack: bool,
    /// Collapses refused, by guard.
    pub rejected: Rejections,
    /// Collapse costs the loop evaluated (the queue's first ones, and every
    /// one again of an edge whose cost changed or whose refusal may have
    /// lifted), the parallel first phase's included: the loop's work, which
    /// must grow with the input's size and not faster (a loop that takes
    /// the same refused collapses again and again shows here first).
    pub evaluations: usize,
    /// Faces read by the flip and flatten tests, the guards' share of the
    /// loop's work, which must grow with the input's size like
    /// `evaluations` (a vertex of high valence refused again and again
    /// shows here).
    pub faces_tested: usize,
    /// Input polygons of more than [`crate::MAX_POLYGON_CORNERS`] corners,
    /// split into smaller pieces before simplifying (their pieces are
    /// output faces of the same input face).
    pub split_polygons: usize,
    /// Triangle pairs joined into quads after a quad-dominant run
    /// (`quad_pairs.rs`; [`crate::simplify_mesh`] only).
    pub joined_quads: usize,
    /// Output normal values that pointed more than 75° away from every face
    /// they shade and were replaced by their faces' normal (see
    /// [`crate::simplify_mesh`]).
    pub stray_normals: usize,
    /// Output vertices of layers (decals and other sheets lying on another
    /// part, see [`crate::Metric::keep_layers`]) placed at their input
    /// offset from the simplified surface under them.
    pub layer_vertices: usize,
    /// The share (0 to 1) of the output's textured surface whose kept UVs
    /// fold over or stretch beyond 4× the input's texel density (see
    /// [`crate::simplify_mesh`]): where the input's textures no longer show
    /// as they did, and re-baking would. `None` without textured UVs.
    pub uv_damage: Option<f64>,
    /// With attributes that steer a triangle-count target: whether their
    /// steering was kept, and why (see
    /// [`crate::AttributeOptions::geometry_tolerance`]). `None` when
    /// nothing steered.
    pub steering: Option<SteeringOutcome>,
    /// With the quad ordering on and a triangle-count target: the tie
    /// width the output was made with and the mean distances that chose
    /// it (see [`crate::QuadSettings::distance_tolerance`]). `None` when
    /// the ordering was off or not held.
    pub quad_ties: Option<QuadTies>,
    /// Where constraints (locked borders, kept topology, kept seams) held
    /// the run above its triangle target: the error level, relative to
    /// the diagonal, where it stopped: what a run without them has at as
    /// many triangles as they leave (the constrained run's floor) where
    /// they put the target out of reach, or lower where the output
    /// measured farther from the input than a run without them at the
    /// target (see [`crate::simplify_with_attributes_and_progress`]).
    /// `None` otherwise.
    pub held_by_constraints: Option<f64>,
    /// With [`crate::Record::error_curve`]: after every collapse of
    /// the global loop, the triangles left and [`Report::error`] so far, in
    /// order (so both columns are monotone). Empty otherwise.
    pub error_curve: Vec<(usize, f64)>,
}
