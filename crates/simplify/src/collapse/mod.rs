//! Step 4 of the simplifier: one run's collapse loop (W Alg. 1, §4, App.
//! C.1; Knodt 2024 Alg. 1 for the near-tie order of quads). It builds the
//! vertex quadrics and the initial queue from `terms`, then pops the
//! cheapest collapse, checks its guards, makes it and re-evaluates what
//! changed, until the target. `heap.rs` is the queue, `ordering.rs`
//! Knodt's near-tie order, `witness_waits.rs` the edges refused for a face
//! that would flip or flatten, `partition.rs` the parallel first phase of
//! large inputs, `history.rs` the record re-baking maps texels through
//! (W §4.3.1). It ends in a [`Collapsed`], which the refit and the assembly
//! read.

use glam::DVec3;
use rayon::prelude::*;

use crate::edges::virtual_edges::{add_virtual_edges, find_virtual_edges, VirtualEdges};
use crate::options::Metric;
use crate::options::Options;
use crate::prepare::complex::Edge;
use crate::prepare::flat_stars::FlatStars;
use crate::prepare::geometry::face_plane;
use crate::prepare::Prepared;
use crate::report::{Report, StopReason};
use crate::terms::attributes::{AttrScratch, AttributeState};
use crate::terms::collapse_terms;
use crate::terms::cost::{
    distance, median_collapse_deviation, vertex_quadric_parts, CostModel, EdgeImportance,
    Evaluation, Scratch,
};
use crate::terms::guards::{
    degraded_face, keeps_topology, pinch_prices, pinches, removed_triangles, Degrades, FaceScans,
    FaceTests, PinchPrices,
};
use crate::terms::stored::{Isotropic, StoredQuadric};
use crate::terms::symmetry::{edge_symmetry_weights, EdgeNormals, SymmetryInput, SymmetryOptions};
use crate::terms::tangent::{joint_difference, side_normals};
use heap::{CollapseQueue, Entry};
use history::{History, HistoryRecorder};
use ordering::{tie_distance, tie_tolerance, TieOrder};

pub(crate) mod heap;
pub(crate) mod history;
pub(crate) mod ordering;
mod partition;
mod refused_around;
mod slots;
mod witness_waits;

use refused_around::RefusedAround;
use witness_waits::WitnessWaits;

/// Near the target, the exact number of triangles a collapse removes is
/// computed before making it, so that the target is met to ±1 triangle.
/// Further away the prediction is skipped: no collapse removes this many.
const EXACT_COUNT_WINDOW: usize = 256;

/// What the guards say about a collapse.
enum Verdict {
    Allowed,
    /// Refused for what would become of this face: it would turn past the
    /// normal limit, or flatten to a line on a flat border. The edge waits
    /// for the face to change (see `witness_waits`).
    Waits(u32),
    /// Refused by another guard.
    Refused,
}

/// Clears edge `e`'s refusal, from whichever list holds it.
fn unrefuse(
    edge: &mut Edge,
    e: u32,
    refused_around: &mut RefusedAround,
    witness_waits: &mut WitnessWaits,
) {
    if !edge.refused() {
        return;
    }
    edge.set_refused(false);
    if witness_waits.forget(e) == Some(false) {
        // Not counted around its ends: out of retries one ring out.
        return;
    }
    refused_around.remove(edge.ends);
}

/// λ_joint · d per edge (Knodt Eq. 2–3) when the input is skinned and the
/// tangent term is on; empty otherwise. A welded vertex takes the
/// influences of its first input vertex.
fn joint_importance(p: &Prepared, options: &Options, metric: &Metric) -> Vec<f64> {
    let lambda = options.quad.joints;
    if options.data.vertex_joints.is_empty() || metric.tangent_weight <= 0.0 || lambda <= 0.0 {
        return Vec::new();
    }
    let mut rep = vec![u32::MAX; p.complex.pos.len()];
    for (v, &w) in p.weld.iter().enumerate() {
        if rep[w as usize] == u32::MAX {
            rep[w as usize] = v as u32;
        }
    }
    let none: Vec<(u32, f32)> = Vec::new();
    let of = |w: u32| {
        options
            .data
            .vertex_joints
            .get(rep[w as usize] as usize)
            .unwrap_or(&none)
    };
    p.complex
        .edges
        .iter()
        .map(|e| lambda * joint_difference(of(e.ends[0]), of(e.ends[1])))
        .collect()
}

/// λ_sym · s per edge (Knodt §3.1, Alg. 2) when the tangent term is on and
/// λ_sym > 0, and whether the work cap cut it short; empty otherwise.
fn symmetry_importance(p: &Prepared, options: &Options, metric: &Metric) -> (Vec<f64>, bool) {
    let lambda = options.quad.symmetry;
    if metric.tangent_weight <= 0.0 || lambda <= 0.0 || !p.complex.has_adjacency() {
        return (Vec::new(), false);
    }
    let c = &p.complex;
    let normals: Vec<Option<DVec3>> = (0..c.faces.len() as u32)
        .into_par_iter()
        .map(|f| {
            if c.faces[f as usize].len == 0 {
                None
            } else {
                face_plane(c, f).map(|p| p.0)
            }
        })
        .collect();
    let edge_normals: Vec<EdgeNormals> = c
        .edges
        .par_iter()
        .map_init(Vec::new, |buf, e| {
            side_normals(c, &normals, e.ends[0], e.ends[1], buf);
            EdgeNormals::from_faces(buf)
        })
        .collect();
    let edges: Vec<[u32; 2]> = c.edges.iter().map(|e| e.ends).collect();
    let result = edge_symmetry_weights(
        &SymmetryInput {
            positions: &c.pos,
            edges: &edges,
            edge_normals: &edge_normals,
        },
        &SymmetryOptions {
            delta: options.quad.symmetry_distance,
            // Below this, λ_sym · s cannot beat the floor 0.01 of Eq. 2 and
            // changes nothing: such planes may be skipped on a sample.
            min_weight: 0.01 / lambda,
            ..SymmetryOptions::default()
        },
    );
    let weights = result.weights.iter().map(|s| lambda * s).collect();
    (weights, result.truncated)
}

/// The rank below which 99% of a run's collapses were made: the level a
/// greedy run ends at, robust to the few collapses a pinch price or a
/// forced last step put far above it.
fn cost_level(made: &mut [f32]) -> f64 {
    if made.is_empty() {
        return 0.0;
    }
    let k = (made.len() * 99 / 100).min(made.len() - 1);
    let (_, x, _) = made.select_nth_unstable_by(k, f32::total_cmp);
    f64::from(*x)
}

/// How many vertices carry area (a positive quadric weight): the vertices
/// the reduction factor of the tie tolerance counts from.
fn area_vertices(q: &[StoredQuadric]) -> usize {
    q.iter().filter(|q| q.weight() > 0.0).count()
}

/// Per-vertex values of a run: its own, or, in a chunk of the partitioned
/// path, its range of the pass's array, which holds every chunk's values
/// in the memory of the global ones (moved there, not copied).
#[derive(Debug)]
pub(crate) enum PerVertex<'a, T> {
    /// A whole run's array.
    Owned(Vec<T>),
    /// A chunk's range of the pass's array (see `partition::Slots`).
    Borrowed(&'a mut [T]),
}

impl<T> Default for PerVertex<'_, T> {
    fn default() -> Self {
        PerVertex::Owned(Vec::new())
    }
}

impl<T> std::ops::Deref for PerVertex<'_, T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        match self {
            PerVertex::Owned(v) => v,
            PerVertex::Borrowed(s) => s,
        }
    }
}

impl<T> std::ops::DerefMut for PerVertex<'_, T> {
    fn deref_mut(&mut self) -> &mut [T] {
        match self {
            PerVertex::Owned(v) => v,
            PerVertex::Borrowed(s) => s,
        }
    }
}

impl<T: Clone> PerVertex<'_, T> {
    /// The values as an owned array (a copy only when borrowed).
    pub fn into_vec(self) -> Vec<T> {
        match self {
            PerVertex::Owned(v) => v,
            PerVertex::Borrowed(s) => s.to_vec(),
        }
    }
}

/// What the loop takes next.
enum Next {
    /// An edge, with its cost, its evaluation when just computed, and its
    /// recency.
    Edge(u32, f64, Option<Evaluation>, u32),
    /// The cheapest collapse left costs more than the cap.
    AboveCap,
    /// Nothing is left.
    None,
}

/// State of one simplification run.
pub(crate) struct Run<'o> {
    p: Prepared,
    options: &'o Options,
    model: CostModel,
    quadrics: PerVertex<'o, StoredQuadric>,
    /// The regularization part of each quadric (in `quadrics` too), kept
    /// apart so that placement can solve without it.
    reg: PerVertex<'o, Isotropic>,
    /// Candidate collapses by cost, at most one entry per edge; an entry is
    /// stale when its generation differs from the edge's.
    queue: CollapseQueue,
    /// Knodt's near-tie ordering, when quad mode is active.
    ties: Option<TieOrder>,
    quads_active: bool,
    /// The vertices carrying area at the start (for Knodt's ε as a cost
    /// difference, see `Run::tie_tolerance`).
    area_vertices: usize,
    /// Knodt's ε as a distance on this input (see
    /// `ordering::tie_distance`).
    tie_epsilon: f64,
    /// The virtual edges added, as vertex pairs (the partitioned path adds
    /// them back after rebuilding the complex).
    virtual_pairs: Vec<(u32, u32)>,
    /// Cost of the last collapse popped: the key under which an edge that
    /// left the queue is put back to be evaluated again soon.
    last_cost: f64,
    /// Refused edges around each vertex, so that finding them near a
    /// collapse costs nothing in the usual case of none (see
    /// `refused_around`). Edges refused for a face are counted only while
    /// they have retries one ring out left: they wait in `witness_waits`.
    refused_around: RefusedAround,
    /// Edges refused for a face that would flip or flatten, each waiting on
    /// that face (see `witness_waits`).
    witness_waits: WitnessWaits,
    /// Where in each vertex's face list the face tests start, and the
    /// faces they read (see `guards::first_moved_failing`).
    face_scans: FaceScans,
    /// Vertices on a boundary edge (kept only when a term needs them).
    border: Vec<bool>,
    /// Which vertices are at a sharp crease (see `init_queue`).
    crease: Vec<bool>,
    /// Vertices that must not move or vanish (empty: none): a chunk's
    /// vertices shared with other chunks, in the partitioned path.
    locked: Vec<bool>,
    /// Which vertices' faces are flat, for the flat-border rule (empty
    /// while the rule does not apply).
    flat: FlatStars,
    track_border: bool,
    /// What a pinch costs at each vertex (see `guards::pinch_prices`).
    pinch_price: PinchPrices,
    moved: Vec<bool>,
    /// The vertex each vertex was merged into (itself while alive).
    merged_into: Vec<u32>,
    target: usize,
    /// Triangles when the run started (progress is measured from there).
    progress_start: usize,
    /// A collapse was refused for exceeding the error limit.
    error_limited: bool,
    report: Report,
    history: Option<HistoryRecorder>,
    /// Attributes fitted through the collapses (Hoppe 1999), when given.
    attrs: Option<AttributeState<'o>>,
    attr_scratch: AttrScratch,
    scratch: Scratch,
    star: Vec<u32>,
    star_verts: Vec<u32>,
    changed: Vec<u32>,
    /// The rank of every collapse the loop made, for
    /// [`Report::cost_level`].
    made: Vec<f32>,
}

impl<'o> Run<'o> {
    /// Virtual edges, vertex quadrics, initial costs (in parallel; the
    /// results do not depend on the thread count).
    ///
    /// Without star lists (see
    /// [`crate::prepare::complex::Complex::faces_only`]) the virtual edges are
    /// found but added only once the complex gets its adjacency, in
    /// [`Run::start`].
    pub fn new(mut p: Prepared, options: &'o Options, attrs: Option<AttributeState<'o>>) -> Self {
        let quads = p.complex.faces.iter().filter(|f| f.len == 4).count();
        let quads_active = options.quads_active(quads);
        let metric = options.effective_metric(quads);
        if metric.tangent_weight > 0.0 && !p.complex.has_adjacency() {
            // Tangent quadrics are per edge.
            p.complex.build_adjacency();
        }
        let radius = options.guards.virtual_edge_radius;
        let found = if radius > 0.0 && !options.guards.keep_topology {
            let threshold = 2.0 * radius;
            if p.complex.has_adjacency() {
                add_virtual_edges(&mut p.complex, threshold)
            } else {
                find_virtual_edges(&p.complex, threshold)
            }
        } else {
            VirtualEdges::default()
        };
        let virtual_radius_reduced =
            (radius > 0.0 && found.threshold < 2.0 * radius).then_some(0.5 * found.threshold);
        let virtual_pairs = found.edges;
        let joints = joint_importance(&p, options, &metric);
        let (symmetry, symmetry_truncated) = symmetry_importance(&p, options, &metric);
        let importance = EdgeImportance {
            symmetry: &symmetry,
            joints: &joints,
        };
        // A ratio is of the triangles that are surface: degenerate faces and
        // exact repeats are cleaned away first (as Blender validates a mesh
        // before decimating), twins count, even those dropped as hidden
        // (their share of the budget goes to what can be seen).
        let target = options.target.triangles_for(p.ratio_base);
        // An error-only target has no budget to share: every part counts
        // as large enough to keep.
        let budget = if target > 0 {
            target
        } else {
            p.complex.triangles
        };
        // A crease is a geometric feature first: its planes hold it whatever
        // the attributes. Seams are held by their own planes too: they keep
        // a seam's vertices on the seam's curve, where the layout needs
        // them (see `AttributeState::seam_planes`).
        let steering = attrs.as_ref().is_some_and(AttributeState::steers);
        let (mut quadrics, reg) = vertex_quadric_parts(
            &p.complex,
            &metric,
            &p.weights,
            importance,
            budget,
            &p.outliers,
        );
        crate::terms::posed::add_pose_terms(&mut quadrics, &p, options, &metric, budget);
        if let Some(a) = &attrs {
            let planes = a.seam_planes(&p.complex, options.attributes.seam_weight);
            for (v, (q, plane)) in quadrics.iter_mut().zip(planes).enumerate() {
                let at = p.complex.pos[v];
                *q = StoredQuadric::new(&(q.quadric(at) + plane), at);
            }
        }
        let faces = p.complex.faces.iter().filter(|f| f.len > 0).count();
        let area: f64 = quadrics.iter().map(StoredQuadric::weight).sum();
        // Attributes keep the regularization choosing (see
        // `AttributeOptions::regularized_choice`).
        let model = CostModel {
            metric,
            terms: collapse_terms(&metric),
            lock_borders: options.guards.lock_borders,
            // Hoppe's joint placement is for attributes that steer: with
            // none (geometry-only, every weight 0), the solve over the
            // zero appearance quadric is only the regularized one, and its
            // allowance would move vertices off the planes' point for
            // nothing.
            attributes_move_vertices: options.attributes.attributes_move_vertices && steering,
            area_floor: metric.area_floor.max(0.0) * area / faces.max(1) as f64,
            attribute_slack: options.attributes.geometry_tolerance.powi(2) - 1.0,
            invisible_distance2: options.attributes.invisible_distance.powi(2),
            // Decision 3 holds under re-baking too (`tests/defaults.rs`:
            // the flat tiling with the history recorded; the bake crate's
            // flat plane maps every texel to its input point with it).
            exact_flat_borders: true,
            appearance_budget: p.appearance_budget,
            regularization_looks: steering
                && options.attributes.regularized_choice
                && !metric.regularized_choice,
        };
        let report = Report {
            input_triangles: p.input_triangles,
            target_triangles: target,
            cleaned_faces: p.cleaned,
            hidden_twins: p.hidden_twins,
            enclosed_parts: p.enclosed_parts,
            virtual_edges: virtual_pairs.len(),
            virtual_radius_reduced,
            outliers: p.outlier_inputs.clone(),
            symmetry_truncated,
            ..Report::default()
        };
        let nv = p.complex.pos.len();
        let locked = p.outliers.clone();
        let (track_border, pinch_base) = (model.needs_border(), model.metric.pinch_cost);
        let mut run = Run {
            history: options
                .record
                .history
                .then(|| HistoryRecorder::new(p.center, p.scale)),
            p,
            options,
            model,
            quadrics: PerVertex::Owned(quadrics),
            reg: PerVertex::Owned(reg),
            queue: CollapseQueue::default(),
            ties: None,
            quads_active,
            area_vertices: 0,
            tie_epsilon: 0.0,
            virtual_pairs,
            last_cost: 0.0,
            refused_around: RefusedAround::new(nv),
            witness_waits: WitnessWaits::default(),
            face_scans: FaceScans::new(nv),
            border: Vec::new(),
            crease: Vec::new(),
            locked,
            flat: FlatStars::default(),
            track_border,
            pinch_price: PinchPrices {
                base: pinch_base,
                per_vertex: Vec::new(),
            },
            moved: vec![false; nv],
            merged_into: (0..nv as u32).collect(),
            target,
            progress_start: 0,
            error_limited: false,
            report,
            attrs,
            attr_scratch: AttrScratch::default(),
            scratch: Scratch::default(),
            star: Vec::new(),
            star_verts: Vec::new(),
            changed: Vec::new(),
            made: Vec::new(),
        };
        run.progress_start = run.p.complex.triangles;
        run.area_vertices = area_vertices(&run.quadrics);
        run.tie_epsilon = options.quad.epsilon;
        if run.quads_active && options.quad.tie_factor > 0.0 {
            let deviation = median_collapse_deviation(&run.p.complex, &run.quadrics);
            run.tie_epsilon =
                tie_distance(options.quad.epsilon, options.quad.tie_factor, deviation);
        }
        if run.model.metric.pinch_cost > 0.0 {
            let area: Vec<f64> = run.quadrics.iter().map(StoredQuadric::weight).collect();
            let pinch = run.model.metric.pinch_cost;
            let distance = (target > 0).then_some(run.model.metric.pinch_distance);
            let scale = 1.0 + run.model.metric.current_face_weight.max(0.0);
            run.pinch_price = pinch_prices(&run.p.complex, &area, budget, pinch, distance, scale);
        }
        run
    }

    /// A run over one chunk of the partitioned path: its own small complex
    /// (local ids), the quadrics of its vertices (moved out of the global
    /// arrays), its attribute state (local ids too), the vertices it shares
    /// with other chunks locked, and its share of the target.
    pub fn chunk(
        parent: &Run<'o>,
        p: Prepared,
        (quadrics, reg): (&'o mut [StoredQuadric], &'o mut [Isotropic]),
        attrs: Option<AttributeState<'o>>,
        locked: Vec<bool>,
        target: usize,
    ) -> Self {
        let nv = p.complex.pos.len();
        let mut run = Run {
            history: None,
            p,
            options: parent.options,
            model: parent.model.clone(),
            quadrics: PerVertex::Borrowed(quadrics),
            reg: PerVertex::Borrowed(reg),
            queue: CollapseQueue::default(),
            ties: None,
            quads_active: parent.quads_active,
            area_vertices: parent.area_vertices,
            tie_epsilon: parent.tie_epsilon,
            virtual_pairs: Vec::new(),
            last_cost: 0.0,
            refused_around: RefusedAround::new(nv),
            witness_waits: WitnessWaits::default(),
            face_scans: FaceScans::new(nv),
            border: Vec::new(),
            crease: Vec::new(),
            locked,
            flat: FlatStars::default(),
            track_border: parent.model.needs_border(),
            pinch_price: PinchPrices {
                base: parent.pinch_price.base,
                per_vertex: Vec::new(),
            },
            moved: vec![false; nv],
            merged_into: (0..nv as u32).collect(),
            target,
            progress_start: 0,
            error_limited: false,
            report: Report {
                target_triangles: target,
                ..Report::default()
            },
            attrs,
            attr_scratch: AttrScratch::default(),
            scratch: Scratch::default(),
            star: Vec::new(),
            star_verts: Vec::new(),
            changed: Vec::new(),
            made: Vec::new(),
        };
        run.init_queue();
        run
    }

    /// A chunk's share of its parent's pinch prices (see `pinch_price`),
    /// `vertex` mapping its vertices to the parent's.
    pub fn inherit_pinch_prices(&mut self, parent: &Run<'o>, vertex: &[u32]) {
        let parent = &parent.pinch_price.per_vertex;
        if !parent.is_empty() {
            self.pinch_price.per_vertex = vertex.iter().map(|&v| parent[v as usize]).collect();
        }
    }

    /// Everything before the global loop: the partitioned phase when it
    /// applies (see [`crate::Partition`]), then the queue.
    pub fn start(&mut self, progress: &dyn Fn(f64)) {
        if partition::applies(self) {
            partition::presimplify(self, progress);
        }
        self.ensure_adjacency();
        self.init_queue();
    }

    /// Builds the star lists and edges if the complex has none (deferred by
    /// the partitioned path, or stale after it), with the virtual edges
    /// between the vertices their ends became.
    fn ensure_adjacency(&mut self) {
        let c = &mut self.p.complex;
        if c.has_adjacency() {
            return;
        }
        c.build_adjacency();
        let root = |mut v: u32| {
            while self.merged_into[v as usize] != v {
                v = self.merged_into[v as usize];
            }
            v
        };
        for &(a, b) in &self.virtual_pairs {
            c.add_edge(root(a), root(b));
        }
    }

    /// Border flags, the cost of every edge, the queues.
    pub fn init_queue(&mut self) {
        if self.model.crease_area_applies() {
            let cos = self.model.metric.crease_angle.to_radians().cos();
            self.p.complex.keep_crease_lists(cos);
        }
        let c = &self.p.complex;
        let locked = &self.locked;
        // A locked vertex's border status does not matter: it stays where it
        // is, where its boundary edges sweep no area, and it is not on the
        // border it seems to be on (a cut) anyway. Leaving it unflagged keeps
        // collapses next to a cut on the fast path.
        self.border = if self.track_border {
            (0..c.pos.len() as u32)
                .into_par_iter()
                .map(|v| !locked.get(v as usize).copied().unwrap_or(false) && c.on_boundary(v))
                .collect()
        } else {
            Vec::new()
        };
        // Vertices at a sharp crease now, for the crease area term (see
        // `Metric::crease_area_weight`); a collapse passes its endpoints'
        // flags on. Vertices a collapse puts on a new crease are not
        // flagged: finding creases at every evaluation cost a smooth scan
        // 44% more.
        self.crease = if self.model.crease_area_applies() {
            let cos = self.model.metric.crease_angle.to_radians().cos();
            (0..c.pos.len() as u32)
                .into_par_iter()
                .map_init(Vec::new, |out, v| {
                    out.clear();
                    c.crease_neighbors(v, cos, out);
                    !out.is_empty()
                })
                .collect()
        } else {
            Vec::new()
        };
        if self.model.exact_flat_borders && self.model.needs_border() {
            self.flat = FlatStars::measure(c);
        }
        let (model, quadrics, reg, border, crease, locked, flat, attrs) = (
            &self.model,
            &self.quadrics,
            &self.reg,
            &self.border,
            &self.crease,
            &self.locked,
            &self.flat,
            self.attrs.as_ref(),
        );
        let entries: Vec<Entry> = (0..c.edges.len() as u32)
            .into_par_iter()
            .map_init(Scratch::default, |s, e| {
                if !c.edges[e as usize].alive() {
                    return None;
                }
                model
                    .evaluate(c, quadrics, reg, border, crease, locked, flat, attrs, e, s)
                    .map(|ev| Entry {
                        cost: ev.cost,
                        edge: e,
                        gen: c.edges[e as usize].gen(),
                    })
            })
            .flatten_iter()
            .collect();
        self.report.evaluations += c.edges.iter().filter(|e| e.alive()).count();
        for en in &entries {
            self.p.complex.edges[en.edge as usize].set_queued(true);
        }
        self.queue = CollapseQueue::from_entries(entries);
        let options = self.options;
        self.ties = self.quads_active.then(|| {
            TieOrder::new(
                self.p.complex.edges.len(),
                options.quad.relative_epsilon,
                options.quad.recency,
            )
        });
    }

    /// Greedy: always the cheapest valid collapse (W §4, App. C.1).
    ///
    /// Re-evaluation is lazy: a collapse only bumps the generation of the
    /// edges whose cost it changed; a stale edge is evaluated again when it
    /// reaches the top and re-keyed in place. Plane quadrics only accumulate
    /// (memory), so a cost can only grow: the stale key is a lower bound and
    /// the order is exactly greedy, while edges that never come near the top
    /// are never re-evaluated.
    pub fn collapse_loop(&mut self, progress: &dyn Fn(f64)) {
        if self.p.complex.triangles <= self.target && self.options.target.error.is_none() {
            self.report.stop = Some(StopReason::NothingToDo);
            return;
        }
        self.collapse_until(f64::INFINITY, progress);
        self.report.cost_level = cost_level(&mut self.made);
    }

    /// The greedy loop, paused before the first collapse that costs more
    /// than `cap` (the partitioned path's rounds). Returns whether it paused
    /// there, with collapses left to make under a higher cap; otherwise
    /// `report.stop` says why it ended.
    pub fn collapse_until(&mut self, cap: f64, progress: &dyn Fn(f64)) -> bool {
        let min_cos = self
            .options
            .guards
            .max_normal_turn_degrees
            .map(|d| d.to_radians().cos());
        let max_error = self.options.target.error;
        let start = self.progress_start;
        let span = start.saturating_sub(self.target).max(1);
        let step = (span / 100).max(1);
        let mut next_report = self.p.complex.triangles.saturating_sub(step);
        loop {
            if self.p.complex.triangles <= next_report {
                progress(start.saturating_sub(self.p.complex.triangles) as f64 / span as f64);
                next_report = self.p.complex.triangles.saturating_sub(step);
            }
            if self.p.complex.triangles <= self.target {
                self.report.stop = Some(StopReason::TargetReached);
                // Past it by more than one triangle only where the last
                // collapse took faces with their twins (see `allowed`).
                self.report.twin_slack = self.p.complex.triangles + 1 < self.target;
                break;
            }
            let (e, cost, known, recency) = match self.next_candidate(cap) {
                Next::Edge(e, cost, known, recency) => (e, cost, known, recency),
                Next::AboveCap => {
                    self.report.output_triangles = self.p.complex.triangles;
                    return true;
                }
                Next::None => {
                    self.report.stop = Some(if self.error_limited {
                        StopReason::ErrorLimit
                    } else {
                        StopReason::NoCollapsibleEdges
                    });
                    break;
                }
            };
            // A pinching collapse (see `Metric::pinch_cost`) goes back
            // with its penalty the first time it reaches the top: checked
            // here, once per pop, not at every evaluation.
            let [a, b] = self.p.complex.edges[e as usize].ends;
            let pinch = self.pinch_price.at(a);
            if pinch > 0.0 && cost < pinch && pinches(&self.p.complex, a, b) {
                let edge = &mut self.p.complex.edges[e as usize];
                edge.set_queued(true);
                self.queue.push(Entry {
                    cost: cost + pinch,
                    edge: e,
                    gen: edge.gen(),
                });
                continue;
            }
            // Neighbours of this collapse are put back under this key to
            // be evaluated soon: without the penalty of a pinch.
            self.last_cost = if pinch > 0.0 && cost >= pinch {
                cost - pinch
            } else {
                cost
            };
            // The entry is current, so evaluating again gives its cost back,
            // now with the position (cheaper than storing one per edge),
            // unless it was just evaluated on its way to the top.
            if known.is_none() {
                self.refresh_flat(e);
                self.report.evaluations += 1;
            }
            let c = &self.p.complex;
            let Some(ev) = known.or_else(|| {
                self.model.evaluate(
                    c,
                    &self.quadrics,
                    &self.reg,
                    &self.border,
                    &self.crease,
                    &self.locked,
                    &self.flat,
                    self.attrs.as_ref(),
                    e,
                    &mut self.scratch,
                )
            }) else {
                continue;
            };
            let [a, b] = c.edges[e as usize].ends;
            let dist = distance(c, &self.quadrics, a, b, ev.position);
            if let Some(limit) = max_error {
                if dist > limit {
                    self.report.rejected.error_limit += 1;
                    self.error_limited = true;
                    continue;
                }
            }
            // Keep the endpoint with the larger star: fewer lists to move;
            // but a locked vertex (which does not move) always stays, since
            // other chunks refer to it.
            let (fa, fb) = (
                c.vert_faces[a as usize].len(),
                c.vert_faces[b as usize].len(),
            );
            let is_locked = |v: u32| self.locked.get(v as usize).copied().unwrap_or(false);
            let keep_a = if is_locked(a) != is_locked(b) {
                is_locked(a)
            } else {
                fa > fb || (fa == fb && a < b)
            };
            let (i, j) = if keep_a { (a, b) } else { (b, a) };
            // Quads this edge is a side of: their opposite sides get
            // recency once the collapse is made (Alg. 1 line 22).
            let opposite = if self.ties.is_some() {
                self.opposite_sides(a, b)
            } else {
                Default::default()
            };
            match self.allowed(i, j, &ev, min_cos) {
                Verdict::Allowed => {}
                Verdict::Waits(face) => {
                    // Tried again when that face changes or the edge's
                    // cost does, and only a few times at collapses nearby
                    // before that: see `witness_waits`.
                    let edge = &mut self.p.complex.edges[e as usize];
                    if !edge.refused() {
                        edge.set_refused(true);
                        if self.witness_waits.wait(e, face) {
                            self.refused_around.add(e, [a, b]);
                        }
                    }
                    continue;
                }
                Verdict::Refused => {
                    let edge = &mut self.p.complex.edges[e as usize];
                    if !edge.refused() {
                        edge.set_refused(true);
                        self.refused_around.add(e, [a, b]);
                    }
                    continue;
                }
            }
            self.made.push(cost as f32);
            self.collapse(e, i, j, ev);
            self.report.error = self.report.error.max(dist);
            if self.options.record.error_curve {
                let t = self.p.complex.triangles;
                self.report.error_curve.push((t, self.report.error));
            }
            if self.ties.is_some() {
                self.after_tie_collapse(&opposite, recency);
            }
        }
        self.report.output_triangles = self.p.complex.triangles;
        false
    }

    /// The cost of the cheapest collapse left, if any (current, so exact).
    /// A paused run's tie queue is empty: pauses happen between classes.
    pub fn next_cost(&mut self) -> Option<f64> {
        self.settle().map(|(_, cost, _)| cost)
    }

    /// The next collapse to try, with its cost, its evaluation when just
    /// computed, and its recency: from the tie queue while the current class
    /// lasts, else the cheapest current edge of the main queue, which starts
    /// a new class.
    fn next_candidate(&mut self, cap: f64) -> Next {
        if let Some(ties) = &mut self.ties {
            while let Some(t) = ties.pop() {
                let edge = &mut self.p.complex.edges[t.edge as usize];
                if !edge.alive() {
                    edge.set_queued(false);
                    continue;
                }
                if t.gen != edge.gen() {
                    // Its cost changed since it joined: it leaves the class
                    // (Alg. 1 line 24) and waits, stale, in the main queue.
                    self.queue.push(Entry {
                        cost: t.cost,
                        edge: t.edge,
                        gen: t.gen,
                    });
                    continue;
                }
                edge.set_queued(false);
                return Next::Edge(t.edge, t.cost, None, t.recency);
            }
        }
        let Some((e, cost, known)) = self.settle() else {
            return Next::None;
        };
        if cost > cap {
            return Next::AboveCap;
        }
        self.queue.pop();
        self.p.complex.edges[e as usize].set_queued(false);
        if let Some(ties) = &mut self.ties {
            ties.new_class(cost);
        }
        Next::Edge(e, cost, known, 0)
    }

    /// Knodt's ε_abs in cost units for collapsing `e` at this point of the
    /// run (see [`tie_tolerance`]): the area is its endpoints' mean.
    fn tie_tolerance(&self, e: u32) -> f64 {
        let [a, b] = self.p.complex.edges[e as usize].ends;
        let area = 0.5 * (self.quadrics[a as usize].weight() + self.quadrics[b as usize].weight());
        let left = self.area_vertices.saturating_sub(self.report.collapses);
        tie_tolerance(self.tie_epsilon, area, self.area_vertices, left)
    }

    /// Brings a current entry to the top of the main queue and returns it
    /// without popping it, with its evaluation when just computed. Entries
    /// of dead edges are dropped; a stale entry is evaluated again and
    /// re-keyed in place (one sift-down instead of a pop and a push).
    fn settle(&mut self) -> Option<(u32, f64, Option<Evaluation>)> {
        let mut last: Option<(u32, u32, Evaluation)> = None;
        loop {
            let top = self.queue.peek()?;
            let e = top.edge as usize;
            let edge = self.p.complex.edges[e];
            if !edge.alive() {
                self.queue.pop();
                self.p.complex.edges[e].set_queued(false);
                continue;
            }
            if top.gen == edge.gen() {
                let known = last
                    .filter(|&(le, lg, _)| le == top.edge && lg == edge.gen())
                    .map(|l| l.2);
                return Some((top.edge, top.cost, known));
            }
            self.refresh_flat(top.edge);
            let c = &self.p.complex;
            self.report.evaluations += 1;
            let ev = self.model.evaluate(
                c,
                &self.quadrics,
                &self.reg,
                &self.border,
                &self.crease,
                &self.locked,
                &self.flat,
                self.attrs.as_ref(),
                top.edge,
                &mut self.scratch,
            );
            match ev {
                Some(ev) => {
                    last = Some((top.edge, edge.gen(), ev));
                    self.queue.replace_top(Entry {
                        cost: ev.cost,
                        edge: top.edge,
                        gen: edge.gen(),
                    })
                }
                None => {
                    self.queue.pop();
                    self.p.complex.edges[e].set_queued(false);
                }
            }
        }
    }

    /// Measures again the planes of `e`'s ends where their counts went
    /// stale or were not kept (see `FlatStars`), so that every edge
    /// evaluated there reads the counts instead of scanning the stars.
    fn refresh_flat(&mut self, e: u32) {
        let c = &self.p.complex;
        let [a, b] = c.edges[e as usize].ends;
        // The rule asks only about edges with an end on a border.
        if c.on_boundary(a) || c.on_boundary(b) {
            self.flat.refresh(c, a);
            self.flat.refresh(c, b);
        }
    }

    /// The sides opposite `a`–`b` in the quads it is a side of.
    fn opposite_sides(&self, a: u32, b: u32) -> smallvec::SmallVec<[u32; 4]> {
        let c = &self.p.complex;
        let mut out = smallvec::SmallVec::new();
        for &f in &c.vert_faces[a as usize] {
            let face = c.face(f);
            if face.len() != 4 {
                continue;
            }
            let Some(k) = face.iter().position(|&v| v == a) else {
                continue;
            };
            let (next, prev) = (face[(k + 1) % 4], face[(k + 3) % 4]);
            let (c0, c1) = if next == b {
                (face[(k + 2) % 4], face[(k + 3) % 4])
            } else if prev == b {
                (face[(k + 1) % 4], face[(k + 2) % 4])
            } else {
                continue;
            };
            if let Some(o) = c.edge_between(c0, c1) {
                out.push(o);
            }
        }
        out
    }

    /// After a collapse in quad mode: the opposite sides of its quads gain
    /// recency (Alg. 1 line 23), and every edge the main queue now offers
    /// within ε of the class joins the tie queue (lines 25–27).
    fn after_tie_collapse(&mut self, opposite: &[u32], recency: u32) {
        if let Some(ties) = &mut self.ties {
            for &o in opposite {
                let edge = &self.p.complex.edges[o as usize];
                if edge.alive() {
                    ties.bump(o, recency + 1, edge.gen());
                }
            }
        }
        while let Some((e, cost, _)) = self.settle() {
            let tolerance = self.tie_tolerance(e);
            let Some(ties) = &mut self.ties else {
                return;
            };
            if !ties.same_class(cost, tolerance) {
                break;
            }
            self.queue.pop();
            let gen = self.p.complex.edges[e as usize].gen();
            // Still `queued`: it waits in the tie queue now.
            let [a, b] = self.p.complex.edges[e as usize].ends;
            let bare = self.p.complex.collapse_leaves_a_bare_vertex(a, b);
            ties.push(e, cost, gen, bare);
        }
    }

    /// The guards, cheapest first.
    fn allowed(&mut self, i: u32, j: u32, ev: &Evaluation, min_cos: Option<f64>) -> Verdict {
        let x = ev.position;
        // No guard reads the whole star unless it must: a refused collapse
        // at a vertex with a hundred thousand faces costs no more than at
        // any other (see `guards`).
        let c = &self.p.complex;
        let left = c.triangles - self.target;
        if left <= EXACT_COUNT_WINDOW {
            c.star_faces(i, j, &mut self.star);
            let removed = removed_triangles(c, &self.star, i, j);
            // Within one triangle of the target (one face's worth where
            // faces have twins, which go together: a doubled mesh then
            // simplifies exactly like its single copy), and never empty a
            // mesh that was asked to keep something.
            let slack = self.star.iter().map(|&f| c.copies(f)).max().unwrap_or(1);
            let floor = if self.target > 0 { 1 } else { 0 };
            if removed > left + slack || c.triangles - removed.min(c.triangles) < floor {
                self.report.rejected.overshoot += 1;
                return Verdict::Refused;
            }
        }
        if self.options.guards.keep_topology && !keeps_topology(c, i, j) {
            self.report.rejected.topology += 1;
            return Verdict::Refused;
        }
        // Nor may a surviving face flatten to a line (three corners on a
        // straight run): the flip guard cannot judge a face without area,
        // so a later collapse could give it area again across a step's
        // corner or over a flat region's border.
        let tests = FaceTests {
            flatten: true,
            min_cos,
        };
        let degraded = degraded_face(c, i, j, x, tests, &mut self.face_scans);
        self.report.faces_tested = self.face_scans.tested;
        if let Some((face, why)) = degraded {
            match why {
                Degrades::Flattens => self.report.rejected.flat_border += 1,
                Degrades::Flips => self.report.rejected.normal_flip += 1,
            }
            return Verdict::Waits(face);
        }
        Verdict::Allowed
    }

    fn collapse(&mut self, e: u32, i: u32, j: u32, ev: Evaluation) {
        // Which vertices' faces change: those of the star. Only when one of
        // them is on a border can border flags change (see below), so the
        // usual interior collapse just scans the flags.
        self.p.complex.star_faces(i, j, &mut self.star);
        let mut star_had_border = false;
        if self.track_border {
            let c = &self.p.complex;
            star_had_border = self
                .star
                .iter()
                .any(|&f| c.face(f).iter().any(|&v| self.border[v as usize]));
            self.star_verts.clear();
            if star_had_border {
                for &f in &self.star {
                    self.star_verts.extend_from_slice(c.face(f));
                }
            }
        }
        // The star's faces change: out of their corners' plane counts
        // now, back in once changed.
        self.flat.before_collapse(&self.p.complex, &self.star);
        let c = &mut self.p.complex;
        let (pi, pj) = (c.pos[i as usize], c.pos[j as usize]);
        if let Some(h) = &mut self.history {
            h.before(c, &self.star, i, j);
        }
        let plan = self
            .attrs
            .as_ref()
            .map(|a| a.plan(c, i, j, &mut self.attr_scratch));
        let prefer_removed = pj.distance_squared(ev.position) < pi.distance_squared(ev.position);
        let outcome = c.collapse(e, i, ev.position, prefer_removed, &mut self.changed);
        self.flat.after_collapse(c, &self.star);
        if let Some(&at_crease) = self.crease.get(j as usize) {
            self.crease[i as usize] |= at_crease;
        }
        // j's edges are i's now: so are their refusals. The counts are
        // hints for finding refused edges near a collapse; an edge whose
        // ends moved under it may be counted at the old end, so they never
        // go below zero (a debug build caught the wrap).
        self.refused_around.merge(i, j);
        for &k in &c.killed {
            unrefuse(
                &mut c.edges[k as usize],
                k,
                &mut self.refused_around,
                &mut self.witness_waits,
            );
            self.witness_waits.cost_changed(k);
        }
        self.moved[i as usize] = true;
        self.merged_into[j as usize] = i;
        // Each endpoint's quadric expanded about where it was stored (its
        // position before the collapse), summed in double precision, and
        // stored about where the vertex went.
        let merged = self.quadrics[i as usize].quadric(pi) + self.quadrics[j as usize].quadric(pj);
        self.quadrics[i as usize] = StoredQuadric::new(&merged, c.pos[i as usize]);
        if !self.reg.is_empty() {
            self.reg[i as usize] = self.reg[i as usize] + self.reg[j as usize];
        }
        if let (Some(a), Some(plan)) = (&mut self.attrs, plan) {
            a.commit(c, i, j, plan, pi, pj);
        }
        if let Some(h) = &mut self.history {
            h.after(c, i, j);
        }
        self.report.collapses += 1;
        // A collapse inside a closed region keeps it closed unless something
        // irregular happened (see `CollapseOutcome::irregular`), so border
        // flags need no update there: the common case on most meshes.
        let border_changes = star_had_border || outcome.irregular;
        if border_changes && self.star_verts.is_empty() {
            // Irregular collapse in a border-free region: the star's vertices
            // are the new vertex's ring now.
            let c = &self.p.complex;
            self.star_verts.push(i);
            for &f in &c.vert_faces[i as usize] {
                self.star_verts.extend_from_slice(c.face(f));
            }
        }
        self.star_verts.sort_unstable();
        self.star_verts.dedup();
        self.invalidate_around(i, j, border_changes);
    }

    /// Marks stale the edges whose cost or validity the collapse changed:
    /// those of the new vertex; with the memoryless area term, those of
    /// vertices whose boundary edges moved or whose border status changed;
    /// and refused edges one ring out, whose guards may now pass.
    fn invalidate_around(&mut self, i: u32, j: u32, border_changes: bool) {
        let c = &self.p.complex;
        let mut todo = std::mem::take(&mut self.changed);
        if self.track_border && border_changes {
            for &v in &self.star_verts {
                if v == j || self.locked.get(v as usize).copied().unwrap_or(false) {
                    continue;
                }
                let now = c.on_boundary(v);
                // i moved: its border neighbours' area terms changed too.
                let touches_i = v != i && now && c.edge_face_count(v, i) == 1;
                if now != self.border[v as usize] || touches_i || (v == i && now) {
                    todo.extend_from_slice(&c.vert_edges[v as usize]);
                }
                self.border[v as usize] = now;
            }
            self.border[j as usize] = false;
        }
        // Those whose cost changed: their retries one ring out start over.
        todo.sort_unstable();
        todo.dedup();
        if !self.witness_waits.is_empty() {
            for &ed in &todo {
                self.witness_waits.cost_changed(ed);
            }
        }
        let changed_cost = todo.len();
        for &ei in &c.vert_edges[i as usize] {
            let k = c.other(ei, i);
            let waits = &self.witness_waits;
            self.refused_around
                .collect(c, k, |ek| waits.near_retry(ek), &mut todo);
        }
        // (An edge between two neighbours of `i` is found from both.)
        todo[changed_cost..].sort_unstable();
        for t in changed_cost..todo.len() {
            let ed = todo[t];
            if (t == 0 || todo[t - 1] != ed) && todo[..changed_cost].binary_search(&ed).is_err() {
                self.witness_waits.retried_near(ed);
            }
        }
        // Edges refused for a face, when that witness was in the star:
        // every such face lost a corner or has `i` moved now.
        if !self.witness_waits.is_empty() {
            for &f in &self.star {
                self.witness_waits.wake(f, &mut todo);
            }
        }
        todo.sort_unstable();
        todo.dedup();
        let c = &mut self.p.complex;
        for &ed in &todo {
            let k = ed as usize;
            if !c.edges[k].alive() {
                continue;
            }
            let edge = &mut c.edges[k];
            edge.bump_gen();
            unrefuse(edge, ed, &mut self.refused_around, &mut self.witness_waits);
            if !edge.queued() {
                // Not in the queue (refused, or not collapsible before): put
                // it back, stale, under the cost of the last collapse so
                // that it is evaluated again right away.
                edge.set_queued(true);
                self.queue.push(Entry {
                    cost: self.last_cost,
                    edge: ed,
                    gen: edge.gen().wrapping_sub(1) & crate::prepare::complex::GEN_MASK,
                });
            }
        }
        todo.clear();
        self.changed = todo;
    }

    /// Frees what only collapsing reads — the queue, the star lists and
    /// edges (most of a run's memory) — so that what follows a run (the
    /// refit, assembling, a chunk's write-back) fits under its peak.
    pub(crate) fn release_adjacency(&mut self) {
        self.queue = CollapseQueue::default();
        self.refused_around = RefusedAround::default();
        self.witness_waits = WitnessWaits::default();
        self.p.complex.clear_adjacency();
    }

    /// Ends the run: what the steps after the loop (refit, assemble) read,
    /// with the queue and the loop's bookkeeping freed.
    pub fn finish(self) -> Collapsed<'o> {
        Collapsed {
            p: self.p,
            options: self.options,
            quadrics: self.quadrics,
            reg: self.reg,
            moved: self.moved,
            merged_into: self.merged_into,
            report: self.report,
            history: self.history.map(HistoryRecorder::finish),
            attrs: self.attrs,
            exact_flat_borders: self.model.exact_flat_borders,
        }
    }
}

/// A finished run, as the steps after the loop read it: the complex at its
/// target, the quadrics the refit fits against, which vertices moved and
/// where each went.
pub(crate) struct Collapsed<'o> {
    /// The complex, collapsed (its star lists until the refit frees them).
    pub p: Prepared,
    pub options: &'o Options,
    /// The vertex quadrics, summed through the collapses.
    pub quadrics: PerVertex<'o, StoredQuadric>,
    /// The regularization part of each quadric (see `Run::reg`).
    pub reg: PerVertex<'o, Isotropic>,
    /// Vertices whose position the run changed.
    pub moved: Vec<bool>,
    /// The vertex each vertex was merged into (itself while alive).
    pub merged_into: Vec<u32>,
    pub report: Report,
    /// The collapse history, when recorded.
    pub history: Option<History>,
    /// The attributes fitted through the collapses, when given.
    pub attrs: Option<AttributeState<'o>>,
    /// Whether flat borders were held exactly (see
    /// `CostModel::exact_flat_borders`): the refit holds them too.
    pub exact_flat_borders: bool,
}

impl Collapsed<'_> {
    /// Where each welded vertex went: the collapse forest followed to its
    /// roots. It only points from removed to kept vertices, so it has no
    /// cycle.
    pub fn roots(&self) -> Vec<u32> {
        let mut root = self.merged_into.clone();
        for v in 0..root.len() {
            let mut r = v as u32;
            while root[r as usize] != r {
                r = root[r as usize];
            }
            root[v] = r;
        }
        root
    }
}
