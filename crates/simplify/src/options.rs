//! Options of the simplifier: plain structs with documented defaults,
//! grouped by what a user decides (see [`Options`]); the fields marked
//! *Expert* reproduce measurements and are not meant to be tuned per file.

/// When to stop simplifying. Every set criterion applies; the simplifier
/// stops at the first one met.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Target {
    /// Keep this fraction of the input's triangles (counted on the
    /// triangulated mesh: a quad is 2, an n-gon n − 2). `0.1` keeps 10%.
    pub ratio: Option<f64>,
    /// Keep at most this many triangles (triangulated count).
    pub triangles: Option<usize>,
    /// Never make a collapse whose error exceeds this distance, relative to
    /// the bounding-box diagonal (W §6 lists error-based stopping as future
    /// work; we build it). Simplification goes on while collapses under the
    /// limit remain.
    pub error: Option<f64>,
}

impl Target {
    /// The triangle count to reach from `input` triangles: the larger of the
    /// ratio and count targets (so the first met stops the run); 0 when
    /// neither is set (an error-only target). A positive ratio keeps at least
    /// one triangle: 0.1% of a 12-triangle cube means "as few as possible",
    /// not "nothing".
    pub fn triangles_for(&self, input: usize) -> usize {
        let by_ratio = self.ratio.map(|r| {
            let t = (input as f64 * r.clamp(0.0, 1.0)).round() as usize;
            if r > 0.0 && input > 0 {
                t.max(1)
            } else {
                t
            }
        });
        match (by_ratio, self.triangles) {
            (Some(a), Some(b)) => a.max(b),
            (Some(a), None) => a,
            (None, Some(b)) => b,
            (None, None) => 0,
        }
    }
}

/// How the error of a collapse is measured and accumulated (the cost terms,
/// W §4.2). They compose: every enabled term adds a quadric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metric {
    /// *Expert.* Add the Lindstrom–Turk area quadric over the boundary edges of the
    /// edge's one-ring, recomputed on the current mesh (memoryless; W §4.2).
    /// It keeps planar parts and open sheets from being eaten away. Has no
    /// effect on closed manifolds, where the metric equals classic QEM.
    /// Default: on.
    pub boundary_area: bool,
    /// *Expert.* Weight of the area term relative to the plane quadrics. Default 1
    /// (W Eq. 15 as written).
    pub boundary_area_weight: f64,
    /// *Expert.* Gluing cost of virtual edges: collapsing an edge no face uses (a
    /// virtual edge between parts) adds, for each endpoint, this weight
    /// times its area times the squared distance it travels. Plane quadrics
    /// cannot see the gap a virtual edge bridges, so without this term parts
    /// merge as soon as their planes agree, and thin parts glued early then
    /// retract into what they were glued to (a spider's legs into its body).
    /// Coincident parts still weld at no cost. 0 disables it.
    ///
    /// Default 100, by measurement on the corpus (`wild/`, `textured/`, at
    /// 10%, 1%, 0.1%): without the term virtual edges raise the mean
    /// Hausdorff distance at 10% (0.188 → 0.222); with it they never raise
    /// it and lower it at 0.1% (0.362 → 0.351), where merging parts is what
    /// keeps the shape. See `docs/design.md`.
    pub gluing_weight: f64,
    /// *Expert.* Weight of Knodt's per-edge tangent quadrics (Knodt 2024 §3.1, Eq. 2):
    /// planes through every edge orthogonal to its faces, weighted by
    /// dihedral angle and edge length, with memory. They keep sharp rims and
    /// thin parts from sliding away and space vertices evenly in flat
    /// regions. 0 disables them. Face planes here are weighted by area /
    /// arity (W Eq. 9) and tangent planes by squared edge length (see
    /// `tangent.rs` for why not Eq. 2's length), so 1/3 matches Knodt's
    /// balance on triangle meshes at every scale. Default 0: they trade
    /// distance for regularity (`manifold/armadillo` at 50%: Chamfer
    /// 0.000101 → 0.000150 at 1/3). Under a triangle target the trade is
    /// bounded as attribute steering is
    /// ([`AttributeOptions::geometry_tolerance`]): a run without them is
    /// made too, and theirs is kept only within that factor of its
    /// Hausdorff and Chamfer distances (`Report::steering`).
    pub tangent_weight: f64,
    /// *Expert.* Rank collapses by the error they introduce (Knodt 2024 Eq. 5):
    /// `(Q_i + Q_j)(v) − Q_i(p_i) − Q_j(p_j)`, instead of the error
    /// accumulated since the input. Quadrics keep their memory; the cost
    /// measures the change from the current mesh, like memoryless
    /// simplification does without forgetting the input's constraints.
    pub introduced_error: bool,
    /// *Expert.* Weight of the border constraint planes (Garland & Heckbert 1997 §6):
    /// through every border side (a face side no other face shares), the
    /// plane orthogonal to its face, weighted by this times the side's
    /// squared length, with memory. They keep open borders where they were
    /// (the area term alone lets them drift a little at every collapse);
    /// a vertex may still slide along a straight border. 0 disables them.
    /// Default 1 (a unit of border weighs like a unit of area), by
    /// measurement on the corpus: see `docs/design.md`.
    pub border_weight: f64,
    /// *Expert.* Weight of the crease constraint planes: through every sharp crease
    /// (a side shared by two faces whose normals turn by more than
    /// [`Metric::crease_angle`]), the plane through it orthogonal to each
    /// face, weighted by this times the side's squared length, as a border
    /// is held. A crease's own face planes weigh by those faces' areas, and
    /// on a CAD part the faces that keep an outline in place are often thin
    /// walls (a plate's 3 mm rim, a pocket's side): their little area let
    /// the outline slide inward and a plate flatten before the rest was
    /// done. Not on meshes whose attributes steer collapses: their hard
    /// edges are normal seams, already held by the seam planes
    /// ([`crate::AttributeOptions::seam_weight`]), and held twice they
    /// took the budget from the rest (the truck at 1%, RiggedFigure at
    /// 10%). 0 disables them.
    ///
    /// Default 0.25, by measurement on the corpus at 50/10/1% against the
    /// peers (`docs/design.md`, "Creases held like borders"):
    /// Hausdorff 1.22 → 1.20, Chamfer 1.03 → 1.01 the best peer (CAD
    /// parts' Chamfer at 50%: the tray 2.24 → 1.28, octagonal_pocket
    /// 0.55 → 0.40); weight 1 gets 1.22 and 1.01 with larger swings.
    pub crease_weight: f64,
    /// *Expert.* The turn between two faces' normals, in degrees, above which their
    /// shared side is a crease for [`Metric::crease_weight`]. Default 78
    /// (normals' cosine below 0.2): CAD edges of 90° and sharper, not the
    /// folds of a scanned surface (60° held scans' ridges too and measured
    /// worse).
    pub crease_angle: f64,
    /// *Expert.* Weight, relative to [`Metric::boundary_area_weight`], of W's
    /// memoryless area term (Eq. 15) at sharp creases: at an endpoint of a
    /// collapse that lies on a crease (a side whose two faces turn by more
    /// than [`Metric::crease_angle`]), each crease side adds the squared
    /// area the endpoint sweeps against it, as a border side does. The
    /// crease planes ([`Metric::crease_weight`]) remember where the
    /// input's creases were, weighed by their sides' squared lengths, so a
    /// crease cut into many short sides holds weakly; this term sees the
    /// current sides, which lengthen as the crease is simplified. Vertices
    /// on a crease when a run starts (and what they collapse into) carry
    /// it; finding new creases at every evaluation cost a smooth scan 44%
    /// more instructions for little. Only where [`Metric::boundary_area`]
    /// is on and attributes do not steer collapses (as for the crease
    /// planes). 0 disables it.
    ///
    /// Default 1 (the border term's weight), by measurement against the
    /// peers at 50/10/1% (`docs/design.md`, "Creases swept like
    /// borders"): corpus Hausdorff 1.15 → 1.14 and Chamfer 0.97 → 0.96
    /// the best peer, meshes made in code 1.52 → 1.49 and 1.16 → 1.15;
    /// 3.6% more instructions on a smooth scan (armadillo).
    pub crease_area_weight: f64,
    /// *Expert.* Weight of the current faces' planes in a collapse's rank
    /// (see `terms/current_faces.rs`): beside the memory quadrics' distance
    /// to the input, the area-weighted squared distance by which the
    /// collapse lifts the surviving faces around it off their present
    /// planes, at the position the memory quadrics chose. Memory weighs a
    /// vertex's planes by the input area it came with, so a vertex no
    /// collapse has touched holds its planes weakly while its faces grow
    /// around it (a plate cut by holes: the rims between top and bottom
    /// pinched into streaks at 1%); the present faces weigh by their
    /// present area. Ranking only: vertices stay where the input's planes
    /// put them. Not on inputs with quads, nor in quad mode: there Knodt's
    /// introduced error (Eq. 5) measures from the current state instead,
    /// a memoryless cost, changing over the 2-ring, would break the tie
    /// classes (Knodt §3.2), and the quad hold's plain run, which the
    /// ordered one is held to and falls back on, must rank as the ordered
    /// one does (with the term there, a symmetric quad mesh fell back to an
    /// asymmetric plain run); with the term in `--no-quads` runs alone,
    /// the quad corpus at 10% measured 11% more Chamfer with quads than
    /// without, where the ordering's own cost is under 10%. Not in
    /// [`Options::classic_qem`]. 0 disables it.
    ///
    /// Default 1: a unit of present area weighs as a unit of input area.
    /// Measured against the peers at 50/10/1% in `docs/design.md`
    /// ("The present faces rank too").
    pub current_face_weight: f64,
    /// *Expert.* Isotropic regularization (probabilistic quadric, Trettner & Kobbelt
    /// 2020): normal variance σ² relative to the unit-diagonal mesh, times
    /// each vertex's area. Keeps the optimal-point solve well conditioned in
    /// flat regions. Default 1e-4: small enough to leave the minimizer of any
    /// curved neighbourhood in place (its effect is below 1e-4 of the plane
    /// error), large enough to make A invertible in double precision.
    pub regularization: f64,
    /// *Expert.* Whether the regularization also chooses: ranks collapses (its cost,
    /// `σ² · area · travel²`, added to the planes') and places vertices
    /// along the directions the planes hold weakly. Off (default): the
    /// planes alone rank collapses and place the vertex wherever they
    /// determine a point (Garland & Heckbert 1997); the regularized solve
    /// places it only where they do not (flat and straight
    /// neighbourhoods). At fine levels a collapse's deviation from its
    /// planes is about a hundredth of its travel, so the regularization's
    /// cost outweighs it and collapses went shortest first: on a mesh with
    /// flat parts the first quarter of the collapses was not free, and
    /// CesiumMan at 50% had 2.7× the Chamfer distance of a textbook quadric
    /// simplifier. Measured on the corpus (`docs/design.md`, "Placed
    /// and ranked by the planes"): Hausdorff 1.30 → 1.26, Chamfer 1.05 →
    /// 1.03 the best peer. Quad mode keeps it on
    /// ([`QuadSettings::regularized_choice`]), and so do meshes with
    /// attributes ([`AttributeOptions::regularized_choice`]).
    pub regularized_choice: bool,
    /// *Expert.* Collapses are ranked as if their endpoints covered at least this
    /// many times the input's mean face area. Area-weighted plane quadrics
    /// (W Eq. 9–11) make a feature's error cost in proportion to its area,
    /// which is right for the average distance and wrong for features far
    /// smaller than a face: a thin strand's planes all contain its axis, its
    /// tip has almost no area, and it can be shortened by millimetres for
    /// nothing. Below the floor the ranking is by mean squared distance
    /// times the floor (as meshoptimizer's, which divides by the weight);
    /// above it, unchanged. Only the order changes, not the quadrics or the
    /// reported error. 0 disables it; 1 (a mean input face) is the value
    /// to try.
    ///
    /// Default 0, by measurement on the corpus at 50/10/1% against the
    /// peers (`docs/design.md`): at 1 the Hausdorff and Chamfer
    /// geometric means improve by about 1% overall (wild meshes at 1%:
    /// 1.04 → 0.89× the best peer) but textured meshes lose at 50%
    /// (1.66 → 1.89×) and re-baking `bob` at 10% loses 7% of its texture
    /// fidelity; appearance comes first.
    pub area_floor: f64,
    /// *Expert.* Added to the cost of a collapse that pinches or folds material
    /// (see `guards::pinches`): the first step by which a thin part (a
    /// chair leg, a blade, a scanned hair) flattens into edges no face
    /// uses, which the output cannot show, so the part vanishes at far
    /// more than the cost its planes report. In cost units of the
    /// unit-diagonal mesh (area times squared distance): 1 ranks such
    /// collapses after every ordinary one, as the link condition of
    /// Blender and meshoptimizer would, while still letting them happen,
    /// cheapest first, when nothing else is left, so targets are reached;
    /// [`Metric::pinch_distance`] caps it where ordinary collapses get
    /// costly.
    /// Not penalized: virtual edges (W's merging of parts) and closing a
    /// hole (the surface wraps air). Parts whose share of the target is
    /// below a tetrahedron's may vanish (W §1, Fig. 1), but at the price of
    /// their size, not of their planes: a target face's area times their
    /// squared diagonal, so a part goes when it is smaller than the error
    /// the rest of the mesh reaches (`guards::pinch_prices`; a truck's side
    /// mirrors stay at 10%, go at 1%). 0 lets every topology change compete
    /// at its plane cost, as W's complex does.
    ///
    /// Default 1, by measurement on the corpus at 50/10/1% against the
    /// peers (`docs/design.md`): Hausdorff geometric mean 1.75 → 1.59×
    /// the best peer (dragon at 10% 19× → 2.4×, chair_model 95× → 2.6×),
    /// Chamfer 1.23 → 1.26× (wild meshes at 1%, whose holes and parts
    /// close later).
    pub pinch_cost: f64,
    /// *Expert.* Caps [`Metric::pinch_cost`] on parts large enough for the target:
    /// a thin part (a chair's wire legs) is flattened once the ordinary
    /// collapses left would move the surface by about half this distance
    /// (relative to the bounding-box diagonal), instead of only when
    /// nothing else is left. Keeping it longer buys a thin part at any
    /// price: at 1% of `wild/chair_model` the whole seat was folded into
    /// a wedge to keep the wires. Priced like the parts too small for the
    /// target (`guards::pinch_prices`): a target face's area times this
    /// distance squared, about what an ordinary collapse at the target
    /// costs when it moves the surface by half of it. 0 keeps the full
    /// `pinch_cost` everywhere (thin parts last, whatever the rest
    /// costs); with an error limit and no triangle target there is no
    /// target face, and the full cost applies.
    ///
    /// Default 0.05, by measurement on the corpus at 50/10/1% against the
    /// peers (`docs/design.md`, "What a pinch may cost"): only 1%
    /// outputs change; Chamfer at 1% of chair_model 2.3 → 0.75× the best
    /// peer, the tray 2.75 → 2.4×; at 0.02 the spider's legs went at 10%
    /// (Hausdorff 4×), at 0.1 the gain was half.
    pub pinch_distance: f64,
    /// *Expert.* How face planes are weighted in the vertex quadrics: by area^A,
    /// scaled by the mean face area^(1−A) so the quadrics keep the scale
    /// of the other terms. 1 is W Eq. 9–11 (area-weighted: a feature costs
    /// in proportion to its area, which minimizes the mean distance); 0
    /// weighs every face alike, as Blender's Decimate does (a finely
    /// tessellated detail costs as much as a coarse one, which keeps the
    /// worst-case distance low at the price of the mean). In [0, 1].
    ///
    /// Default 1, by measurement on the corpus at 50/10/1% against the
    /// peers (`docs/design.md`, "Plane weighting"): at 0 the Hausdorff
    /// geometric mean improves from 1.58 to 1.45× the best peer (the
    /// dragon at 50% 3.2 → 1.35×, textured meshes at 10% 1.95 → 1.34×)
    /// but Chamfer worsens from 1.26 to 1.51× and one target is missed.
    pub area_exponent: f64,
    /// *Expert.* Face planes weigh at least this many mean face areas (after
    /// [`Metric::area_exponent`]). Area-weighted planes make a detail
    /// tessellated finer than the rest (a scanned hair, a fillet, engraved
    /// text) cheap to remove in proportion to its small faces, so it goes
    /// first and the worst-case distance grows; lifting small faces to a
    /// share of the mean weighs such details like the rest of the surface,
    /// as Blender's Decimate does for every face, while large faces keep
    /// their area, which is what keeps the mean distance low. Parts too
    /// small to keep a closed surface at the target (by their share of the
    /// area, as for [`Metric::pinch_cost`]) are not lifted: they still go
    /// first, where W's budget sends them (W §1, Fig. 1). 0 disables
    /// it. Not in quad mode: there Knodt's tie classes, lifted with the
    /// small faces, sweep whole chords across finely tessellated parts
    /// (`tests/quads.rs`), and the quad corpus measured no better with it.
    ///
    /// Default 0.5, by measurement on the corpus at 50/10/1% against the
    /// peers (`docs/design.md`, "Face weight floor"): Hausdorff
    /// geometric mean 1.58 → 1.46× the best peer (the dragon at 50% 3.2 →
    /// 1.5×, at 10% 2.4 → 1.1×; textured meshes at 10% 1.95 → 1.60×),
    /// Chamfer 1.26 → 1.30×; weighing every face alike (`area_exponent` 0)
    /// gets 1.45× Hausdorff for 1.51× Chamfer and misses a target.
    pub face_weight_floor: f64,
    /// *Expert.* Sweeps of the final refit (see `refit.rs`): once the collapses are
    /// done, every vertex moves to where its quadric plus the input's
    /// vertices' distances to its faces are smallest, which the collapses
    /// alone, each placing one vertex for the faces of its day, leave
    /// undone. Only positions change. 0 disables it; soft symmetry
    /// ([`QuadSettings::symmetry`]) turns it off, since it would move vertices
    /// off the mirror plane.
    /// Default 1, by measurement on the corpus against the peers
    /// (`docs/design.md`, "Refit"): Hausdorff 1.46 → 1.35× the best
    /// peer, Chamfer 1.30 → 1.13×; a second sweep gets 1.34× and 1.13× for
    /// twice the time.
    pub refit_sweeps: u32,
    /// Keep layers in front of what they lie on (see `assemble/layers.rs`):
    /// an open sheet lying a little in front of another part, facing the
    /// same way (a decal, a sticker, a road marking), moves with the
    /// simplified surface under it and keeps its offset from it, instead of
    /// sinking behind it once the surface's error exceeds the gap.
    /// Default: on (off in [`Options::classic_qem`]).
    pub keep_layers: bool,
}

impl Default for Metric {
    fn default() -> Self {
        Metric {
            boundary_area: true,
            boundary_area_weight: 1.0,
            border_weight: 1.0,
            crease_weight: 0.25,
            crease_angle: 78.0,
            crease_area_weight: 1.0,
            current_face_weight: 1.0,
            gluing_weight: 100.0,
            tangent_weight: 0.0,
            introduced_error: false,
            regularization: 1e-4,
            regularized_choice: false,
            area_floor: 0.0,
            pinch_cost: 1.0,
            pinch_distance: 0.05,
            area_exponent: 1.0,
            face_weight_floor: 0.5,
            refit_sweeps: 1,
            keep_layers: true,
        }
    }
}

/// Topology: which separate parts may merge, which hidden twin faces go,
/// and the collapses the user may forbid. Defaults chosen by measurement on
/// the corpus (see `docs/design.md`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guards {
    /// Virtual edges (W §4.1.1): pairs of triangles of different connected
    /// components closer than `2 r` get an edge between their closest vertex
    /// pair. `r` is relative to the bounding-box diagonal; 0 disables them.
    /// Default 0.0025 (so parts within 0.5% of the diagonal may merge),
    /// chosen by measurement on the corpus: see `docs/design.md`.
    ///
    /// The search keeps its work and edge count linear in the input: where
    /// many parts much smaller than `r` sit within reach of hundreds of
    /// others (a long row of pickets, gravel), bridging every gap under
    /// `2 r` would grow with the square of the part count, and the radius
    /// halves until it fits; [`crate::Report::virtual_radius_reduced`] says
    /// so.
    pub virtual_edge_radius: f64,
    /// Drop the twins that cannot be seen before simplifying. A twin is a
    /// face's reversed copy, how exporters make a sheet double-sided. On a
    /// closed part one copy of each face looks into the solid and is never
    /// seen with an opaque material; elsewhere a copy goes when no ray from
    /// its middle escapes the mesh and no line of sight reaches an opening
    /// of its part (the inside of an almost closed shell, away from its
    /// openings). The copy that can be seen is
    /// kept; open sheets keep both. The ratio of [`Target`] still counts the
    /// dropped twins, so their share of the budget buys visible detail
    /// (Blender drops such copies when it imports a file). Default true.
    pub drop_hidden_twins: bool,
    /// Drop the parts no one can see before simplifying: a part (faces
    /// joined by shared vertices) wholly inside another part that is closed
    /// (every side shared by two of its faces), faces outward and is drawn
    /// opaque and one-sided (no face seen through, no twin), touching it
    /// nowhere. The shaft inside a closed CAD housing, the engine under a
    /// sealed body: behind an opaque enclosure they never show, and the
    /// budget they would take buys visible detail (the ratio of [`Target`]
    /// still counts them). A part showing through an opening, poking out
    /// or resting on the inner wall stays; skinned and morphed meshes keep
    /// every part, since a pose may open the enclosure. An enclosure that
    /// is seen through in ways a mesh cannot tell (a double-sided or
    /// alpha-tested material, an animated node) is the caller's to rule
    /// out: the file pipeline turns this off for such files. Default true.
    pub drop_enclosed_parts: bool,
    /// *Expert.* Reject a collapse that turns any surviving face's normal by more than
    /// this angle (degrees). Default 90: a face that turns past 90° has
    /// flipped over its neighbours. `None` disables the test.
    pub max_normal_turn_degrees: Option<f64>,
    /// Keep topology: the link condition (Dey et al. 1999; W App. B) and no
    /// virtual edges. A manifold input stays a manifold of the same genus and
    /// component count; the target may then be out of reach. Default off.
    pub keep_topology: bool,
    /// Never move or remove vertices on boundary edges. Default off.
    pub lock_borders: bool,
    /// *Expert.* The triangle target of the run without constraints that
    /// a constrained run (locked borders, kept topology, kept seams) is held
    /// to: it stops where its output, measured against the input, would be
    /// farther from it than that run's (see
    /// [`crate::simplify_with_attributes_and_progress`]). Default `None`:
    /// the run's own target. A run aiming at the counts another, held run
    /// reached (a re-bake following the run over the whole file) gives that
    /// run's target: held against a free run at the counts its
    /// constraints cost, it would pay for them twice (a sofa with locked
    /// borders at 1% kept 1,925 triangles where its held run kept 1,034).
    pub hold_target: Option<usize>,
}

impl Default for Guards {
    fn default() -> Self {
        Guards {
            virtual_edge_radius: 0.0025,
            drop_hidden_twins: true,
            drop_enclosed_parts: true,
            max_normal_turn_degrees: Some(90.0),
            keep_topology: false,
            lock_borders: false,
            hold_target: None,
        }
    }
}

/// When the quad-preserving ordering of Knodt 2024 applies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum QuadMode {
    /// When the input has at least one quad (the default): artists' quad
    /// meshes keep their edge flow, triangle meshes behave as before.
    #[default]
    Auto,
    /// Always, even on triangle meshes.
    Always,
    /// Never: plain greedy order on the metric.
    Never,
}

/// Quad-dominant reduction (Knodt 2024 §3): when it applies ([`QuadSettings::mode`])
/// and its settings, which apply only then (all but `mode` are expert).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadSettings {
    /// When the quad-preserving ordering applies. Default [`QuadMode::Auto`]:
    /// on inputs with at least one quad.
    pub mode: QuadMode,
    /// *Expert.* ε_abs of Knodt Eq. 4, as the largest distance relative to the
    /// bounding-box diagonal at the input's resolution (narrowed on fine
    /// meshes by [`QuadSettings::tie_factor`]): a collapse whose cost differs
    /// from the first of its class by less than the cost of moving its own
    /// vertex by ε·min(n₀/n, 10) (n₀ vertices at the start, n now) is treated as
    /// equal and ordered by recency. Knodt gives ε_abs in raw cost units
    /// (5e-6 on his meshes); wildlod's costs are area-weighted and grow as
    /// vertices take over their neighbours' area, and the deviation of a
    /// typical collapse grows as n₀/n, so a raw or fixed tolerance would
    /// mean a different share of the error on every mesh, in every part of
    /// it, and at every stage (too wide at 50% and on finely tessellated
    /// parts, too narrow at 10%).
    ///
    /// Default 1.5e-3 (so 3e-3 once half the vertices are gone, 1.5e-2
    /// from a tenth on), by measurement on `corpus/quad` (see
    /// `docs/evaluation-quads.md`): median quad ratio 0.98 / 0.96 / 0.83
    /// at 50% / 25% / 10% against 0.70 / 0.46 / 0.10 without the ordering,
    /// for 5–8% more mean Chamfer distance. 1.25e-3 keeps fewer quads at
    /// 10% (0.55 on the median mesh); 2e-3 keeps more (0.96) for 10% more
    /// Chamfer distance.
    pub epsilon: f64,
    /// *Expert.* Ties are narrower on meshes whose collapses are finer: the tie
    /// distance is this many times the input's median initial collapse
    /// deviation, where that is below [`QuadSettings::epsilon`] (which then
    /// caps it). 0 leaves `epsilon` alone.
    ///
    /// Default 2: the median deviation of the corpus's mid-size quad
    /// meshes, on which `epsilon` was measured, is about half of it
    /// (`spot_quadrangulated` 8.1e-4, `mixedFaring` 7.8e-4), so they keep
    /// their ties. On `corpus/quad` (`docs/design.md`, "Warped polygons"
    /// and the quads section) the Chamfer distance at 50% / 10%
    /// / 1% went from 1.55 / 1.20 / 1.04 to 1.33 / 1.03 / 0.83× the best
    /// peer, most of it on the dense sword: 3.2 / 2.8 / 2.8 to 1.6 / 1.2 /
    /// 1.0× (quad ratio 1.00 / 0.98 / 0.95 to 0.97 / 0.74 / 0.16). Factor
    /// 1 is where a smooth surface's ties stop buying quads (the generated
    /// spheres of `collapse::ordering`) but it kept half the quads of the
    /// corpus at 10%.
    pub tie_factor: f64,
    /// *Expert.* ε_rel: costs within this fraction of the larger one are also ties
    /// (Dawson's relative comparison, which Knodt cites and ablates beside
    /// ε_abs). Costs grow by orders of magnitude as a mesh coarsens, so a
    /// relative tolerance keeps classes meaningful at every ratio.
    pub relative_epsilon: f64,
    /// *Expert.* Within a class, collapse the edge of highest recency first; a
    /// collapse raises the recency of the opposite edges of its quads, so
    /// quad chords collapse together (Alg. 1). Default on.
    pub recency: bool,
    /// *Expert.* Tangent edge quadric weight used in quad mode (see
    /// [`Metric::tangent_weight`]). Default 0: on `corpus/quad`, 1/3
    /// (Knodt's balance) left the Chamfer distance within −5%…+4% of the
    /// ordering alone but kept far fewer quads (median quad ratio 0.85 /
    /// 0.58 / 0.22 against 0.98 / 0.96 / 0.83 at 50% / 25% / 10%). Bounded
    /// against a run without them as [`Metric::tangent_weight`] is.
    pub tangent_weight: f64,
    /// *Expert.* Rank by introduced error (Knodt Eq. 5) in quad mode. Default off:
    /// with the ordering it raised the Chamfer distance at 50% by 17% (and
    /// the Hausdorff distance by 57%), though at 25% and 10% it kept a few
    /// more quads (0.96 / 0.88) at about the same distance.
    pub introduced_error: bool,
    /// *Expert.* [`Metric::regularized_choice`] in quad mode. Default on: Knodt's
    /// tie classes rank collapses whose costs are close, and without the
    /// regularization's share the quad corpus measured worse (Hausdorff
    /// at 1% 1.19 → 1.60–1.72 the best peer, `docs/design.md`).
    pub regularized_choice: bool,
    /// *Expert.* λ_sym of Eq. 2: weight of the soft symmetry term (Knodt §3.1,
    /// Alg. 2): edges whose plane mirrors much of the model onto itself
    /// weigh more in the tangent quadrics, so symmetry lines and their
    /// mirrored edge loops are kept. Acts through the tangent quadrics
    /// only, so it needs a positive tangent weight. Default 0 (off): the
    /// weights cost O(|V|) per distinct edge plane, capped at about ten
    /// seconds (see [`Report::symmetry_truncated`](crate::Report)).
    pub symmetry: f64,
    /// *Expert.* δ of Alg. 2: how close a vertex's mirror image must come to another
    /// vertex to count as its partner, relative to the bounding-box
    /// diagonal. Default 1e-3.
    pub symmetry_distance: f64,
    /// *Expert.* λ_joint of Eq. 2: weight of the joint-influence difference of an
    /// edge's endpoints, on skinned meshes. Default 1 (Knodt §4).
    pub joints: f64,
    /// *Expert.* Factor on every attribute weight ([`AttributeOptions`]) in quad mode.
    /// The ordering keeps quads by treating near-equal costs as ties; the
    /// attribute error of a collapse (a UV field's curvature, say) varies
    /// far more along a quad chord than its distance does and breaks the
    /// ties. Default 0.1, by measurement on `quad/spot_quadrangulated` (13
    /// UV islands, all kept): quad ratio 0.98 / 0.94 / 0.93 at 50% / 25% /
    /// 10% against 0.87 / 0.84 / 0.85 at full weight (which has 10–20% less
    /// Chamfer distance there).
    pub attribute_weight: f64,
    /// *Expert.* How much farther from the input, in mean distance
    /// (Chamfer, both ways), a quad-ordered output may be than the output
    /// of the same run with the ordering off ([`QuadMode::Never`]).
    /// Where the ordering's ties cost more, they narrow ([`QuadSettings::epsilon`],
    /// [`QuadSettings::tie_factor`] and [`QuadSettings::relative_epsilon`]
    /// scaled together, at most three runs more, down to a sixteenth) to a
    /// width whose output is within it, else the output is that of the run
    /// without the ordering; [`crate::Report::quad_ties`] says which.
    /// Differences below a tenth of
    /// [`AttributeOptions::invisible_distance`] count as within. ≥ 1;
    /// `f64::INFINITY` leaves the ties as set (Knodt 2024 as written).
    ///
    /// Default 1.15, the bound attributes are held to
    /// ([`AttributeOptions::geometry_tolerance`]): quads are kept where a
    /// chord costs about what the cheapest collapse would, and not where
    /// a chord sweeps across a curved surface. On `corpus/quad` at 25%
    /// and 10% the full ties cost `spot_quadrangulated` 1.6× and 1.9× the
    /// mean distance of the ordering off, more than Knodt's own
    /// simplifier's, for quads it keeps at a quarter of the ties
    /// (`docs/evaluation-quads.md`). The largest distance is not held:
    /// a chord that moves a few points is what the ordering is for (the
    /// dense sword's at 50% is 4× the ordering off's, at a third of the
    /// mean distance of Knodt's).
    pub distance_tolerance: f64,
}

impl Default for QuadSettings {
    fn default() -> Self {
        QuadSettings {
            mode: QuadMode::Auto,
            epsilon: 1.5e-3,
            tie_factor: 2.0,
            relative_epsilon: 0.0,
            recency: true,
            tangent_weight: 0.0,
            introduced_error: false,
            regularized_choice: true,
            symmetry: 0.0,
            symmetry_distance: 1e-3,
            joints: 1.0,
            attribute_weight: 0.1,
            distance_tolerance: 1.15,
        }
    }
}

/// The parallel first phase for large inputs. Not in the papers: a speed
/// measure that keeps their greedy order where it matters.
///
/// An input of at least `min_triangles` triangles is cut into spatially
/// compact chunks of about `chunk_faces` faces (consecutive along a Morton
/// curve of face centroids). Each chunk is simplified on its own, in
/// parallel, with the vertices near the cuts locked, in rounds of a rising
/// cost cap, so that every chunk makes the collapses the global order would
/// make first, the triangles going wherever collapses are cheapest (a chunk
/// is not held at its share of the target). A pass stops once its chunks'
/// interiors are reduced as far as the whole mesh should be; the next one
/// cuts elsewhere, so the faces along the last cuts catch up; the passes
/// stop once the whole mesh is within `handoff` of the target (as a
/// fraction of the triangles still to remove). The usual global loop then
/// finishes, cuts included. Small chunks also fit in the
/// processor's caches, which is most of the gain on any number of cores.
/// The result is deterministic and does not depend on the thread count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Partition {
    /// *Expert.* Inputs with fewer triangles go straight to the global loop.
    /// Default 100 000; `usize::MAX` turns the phase off.
    pub min_triangles: usize,
    /// *Expert.* Faces per chunk. Default 16 384: a chunk's complex and queue stay in
    /// a core's cache.
    pub chunk_faces: usize,
    /// *Expert.* The global loop starts when the triangles left to remove are at most
    /// this fraction of those the run removes in all. Default 0.02.
    pub handoff: f64,
}

impl Default for Partition {
    fn default() -> Self {
        Partition {
            min_triangles: 100_000,
            chunk_faces: 16_384,
            handoff: 0.02,
        }
    }
}

impl Partition {
    /// The phase off: one global greedy loop, whatever the input size.
    pub const OFF: Partition = Partition {
        min_triangles: usize::MAX,
        chunk_faces: 16_384,
        handoff: 0.125,
    };
}

/// How normals are produced for the output of [`crate::simplify_mesh`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalMode {
    /// Fitted through every collapse like any attribute (Hoppe 1999), then
    /// normalized: a coarse level of detail keeps the input's shading.
    #[default]
    Fit,
    /// Recomputed from the simplified faces (area-weighted face normals),
    /// smoothed only among corners that kept one normal wedge: the input's
    /// hard edges stay hard, flat-shaded meshes stay flat.
    Recompute,
}

/// How attributes steer and survive simplification (Hoppe 1999; Knodt 2024
/// §3, Eq. 6–7). Every stream is fitted through every collapse whatever its
/// weight; the weight only decides how much it steers the collapses. Each
/// kind is measured on the scale of positions (relative to the bounding-box
/// diagonal), so one weight means the same on every asset: a UV error as
/// the distance the texture slides on the surface, normals, colors and
/// skin weights as they are (see [`crate::StreamKind`]). Weight 1 makes an
/// error of `d` cost as much as moving the surface by `d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttributeOptions {
    /// Weight of every UV set: 1 makes a texture that slides by `d` on the
    /// surface cost as much as moving the surface by `d`. Default 0.25.
    /// Measured on the textured and skinned corpus at 10% (geometric means
    /// of 7 files; `docs/evaluation-appearance.md`): texture Chamfer 0.0615
    /// at 0 (which also drops UV seams), 0.0563 at 0.25, 0.0557 at 1 for 5%
    /// more Chamfer distance and worse normals.
    pub tex_coord_weight: f64,
    /// Weight of normals: 1 makes a normal that turns by `θ` radians cost as
    /// much as moving the surface by `θ` times the input's mean edge length.
    /// Default 0.25: normal Chamfer 9.9° at 0, 8.8° at 0.25 (+8% Chamfer
    /// distance), 8.1° at 0.5 (+18%), same set as above.
    pub normal_weight: f64,
    /// Weight of vertex colors, on the scale of normals (a change of `d`
    /// costs like moving the surface `d` mean edge lengths). Default 0.25,
    /// like normals (the corpus has no vertex-colored asset to measure).
    pub color_weight: f64,
    /// Weight of skin (joint) weights: a weight error of `d` costs like
    /// moving the surface by `d` diagonals. Fitting alone already keeps
    /// skins right; the weight barely matters. Default 0.01: on the skinned
    /// corpus posed at 50 frames of its first animation (`wildlod compare
    /// --animation 0`, geometric means of 4 files), mean Chamfer 0.00055 /
    /// 0.00639 at 50% / 10% against 0.00062 / 0.00636 at 0 and 0.00056 /
    /// 0.00717 at 0.03 (Hausdorff 0.0085 / 0.0498 against 0.0080 / 0.0469
    /// at 0). The posed planes ([`InputData::skin_poses`]) apply at any
    /// weight, 0 included: they are how the surface is measured, not an
    /// attribute.
    pub skin_weight: f64,
    /// Whether attribute seams (UV seams, hard normal edges, color and
    /// material borders) are kept. Default: crossed only where that costs
    /// less than what else is left.
    pub seams: crate::SeamPolicy,
    /// *Expert.* Weight of the planes that hold seam vertices on their seam's curve
    /// when a collapse moves them along it, per squared edge length.
    /// Default 0.05: texture Chamfer 0.0622 at 0, 0.0563 at 0.05, 0.0546
    /// at 0.2 for 8% more Chamfer distance (what keeps seams in place keeps
    /// textures in place).
    pub seam_weight: f64,
    /// How output normals are produced. Default: fitted (normal Chamfer
    /// 8.8° against 9.6° recomputed at 10%, 25.5° against 26.6° at 1%).
    pub normals: NormalMode,
    /// *Expert.* Whether attributes may move a collapse's vertex (Hoppe 1999's joint
    /// minimization over position and attributes) instead of only ranking
    /// collapses and being fitted where the surface's quadric puts the
    /// vertex. Jointly minimized, a vertex leaves the surface to make an
    /// attribute field fit better: the surface moves for the sake of
    /// texture coordinates and normals the viewer never sees as positions.
    /// Only where some attribute steers (a weight above 0): attributes
    /// that steer nothing leave the surface exactly as it is without them.
    ///
    /// Default true (Hoppe's joint placement): false measured better on the
    /// keep-UV path (`docs/design.md`, "Joint
    /// placement") but re-baking `bob` at 10% then loses to keep-UV
    /// (0.0454 against 0.0439), which `tests/bake.rs` forbids; until that
    /// is understood the default stays. With false, on the textured and
    /// skinned corpus the texture
    /// and normal Chamfer stay the same or improve (CesiumMilkTruck at 10%
    /// 0.0663 → 0.0646, Fox 0.0584 → 0.0537, tea_set at 50% 0.0390 →
    /// 0.0396), CesiumMan's posed Hausdorff at 50% halves (0.0056 →
    /// 0.0028), and the corpus scoreboard against the peers improves
    /// (Hausdorff 1.58 → 1.55×, Chamfer 1.26 → 1.25×).
    pub attributes_move_vertices: bool,
    /// *Expert.* With attributes that steer collapses (any stream of nonzero weight,
    /// or skin weights), the regularization ranks collapses and places
    /// vertices as well ([`Metric::regularized_choice`] on). Attribute
    /// fields are sampled at the input's vertices, and a vertex that
    /// travels far drags the samples its faces interpolate; the
    /// regularization's travel cost keeps them where they were measured.
    /// Default true: without it the texture Chamfer of CesiumMilkTruck at
    /// 50% rose from 0.0338 to 0.0412 and CesiumMan's posed Hausdorff from
    /// 0.0014 to 0.0020 (`docs/design.md`, "Placed and ranked by the
    /// planes").
    pub regularized_choice: bool,
    /// *Expert.* How much farther from the input than a geometry-only run the
    /// surface may end because attributes steered it: a collapse's cost
    /// is its geometric cost plus its appearance cost (attribute quadrics,
    /// seam planes, the regularization's travel), the latter capped at
    /// `tolerance² − 1` times the former (costs are squared distances), and
    /// Hoppe's joint placement is kept only where it costs the surface no
    /// more than that. Attributes then reorder only collapses whose
    /// distances lie within this factor of each other: where keeping a
    /// seam or a shading detail would cost more, geometry wins. A UV set
    /// that no texture reads, a hard normal edge on a crease, never outbids
    /// the surface. ≥ 1; `f64::INFINITY` lets attributes steer without
    /// bound (Hoppe 1999 as written).
    ///
    /// Default 1.15 (issue 31's bound: a default output's Hausdorff and
    /// Chamfer distances within 1.15× of the geometry-only output's).
    pub geometry_tolerance: f64,
    /// *Expert.* A distance, relative to the bounding-box diagonal, below which
    /// attributes steer the order freely: appearance may always add what
    /// moving the surface by this much over the collapse's area costs to a
    /// collapse's rank. Flat regions, where every geometric cost is 0,
    /// would otherwise give attributes no say at all. Hoppe's joint
    /// placement may move a vertex by it too, except where the planes hold
    /// the vertex already (a flat panel, a straight crease, to 1e-6 of the
    /// diagonal): there it stays on them (decision 3 of issue 31).
    /// Default 1e-4 (issue 31: Hausdorff differences below 1e-4 of the
    /// diagonal are not visible on any screen).
    pub invisible_distance: f64,
    /// Whether morph targets (blend shapes) count as poses the mesh is
    /// drawn in: each target at full weight is a pose, and every vertex's
    /// face planes are their mean over the rest pose and these poses, as
    /// a skin's are (`terms/posed.rs`). A target's deltas are positions: a
    /// nose or an open mouth that a LOD flattens shows as much as a
    /// flattened rest pose does, and a region no target moves keeps its
    /// rest planes. Default true: on a generated sphere whose one target
    /// raises a nose, at 10%, the posed Hausdorff distance dropped by more
    /// than half for the same rest distance (`tests/morph.rs`). False:
    /// deltas are only fitted at the new positions (the rest pose alone
    /// steers). At most [`crate::MAX_MORPH_POSES`] targets are poses, those
    /// that move the surface most.
    pub morph_poses: bool,
}

impl Default for AttributeOptions {
    fn default() -> Self {
        AttributeOptions {
            tex_coord_weight: 0.25,
            normal_weight: 0.25,
            color_weight: 0.25,
            skin_weight: 0.01,
            seams: crate::SeamPolicy::Penalize,
            seam_weight: 0.05,
            normals: NormalMode::Fit,
            attributes_move_vertices: true,
            regularized_choice: true,
            geometry_tolerance: 1.15,
            invisible_distance: 1e-4,
            morph_poses: true,
        }
    }
}

/// What the run records for its caller, beside the output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Record {
    /// Record every collapse (edge one-ring before, vertex one-ring after)
    /// for successive mapping (W §4.3). Default off: it costs memory.
    pub history: bool,
    /// Record, after every collapse, the triangles left and the error
    /// reached so far ([`crate::Report::error_curve`]), so that a caller
    /// simplifying several meshes under one budget can pick a common error
    /// threshold (see [`crate::simplify_scene`], W §1 Fig. 1). Collapses of
    /// the parallel first phase are not recorded: turn it off
    /// ([`Partition::min_triangles`] = `usize::MAX`) for the whole curve.
    /// Default off: 16 bytes per collapse.
    pub error_curve: bool,
}

/// Data that comes with the faces, per input vertex or face, or per scene
/// material: importance, skinning, how faces are drawn. Not decisions: the
/// mesh and scene entry points ([`crate::simplify_mesh`],
/// [`crate::simplify_scene`]) fill it from the file; callers of the plain
/// arrays may set it. Empty (default): none.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InputData {
    /// Per-vertex importance (≥ 0, one per input vertex): the quadrics of a
    /// vertex are multiplied by its weight, so heavier vertices survive
    /// longer (visibility-driven simplification, W Fig. 20). Empty: all 1.
    pub vertex_weights: Vec<f32>,
    /// Joint influences of every input vertex, as sparse (joint, weight)
    /// lists (empty: not skinned). They feed Knodt Eq. 2's λ_joint·d term
    /// (d = ½ ℓ1 between an edge's endpoints, Eq. 3), which makes the
    /// tangent quadrics of edges between differently skinned vertices
    /// heavier, so joints keep their edges. `simplify_mesh` fills this from
    /// the mesh's skinning.
    pub vertex_joints: Vec<Vec<(u32, f32)>>,
    /// Poses the skin takes when drawn, for [`InputData::vertex_joints`]:
    /// per pose, every joint's skinning matrix (the joint's world matrix in
    /// that pose times its inverse bind matrix; column-major, input units),
    /// indexed by the joint ids of `vertex_joints`. A skinned mesh is never
    /// seen at rest: each vertex's face planes become their mean over the
    /// rest pose and these poses (see `posed.rs`), so collapses cost what
    /// they cost as the mesh moves (an elbow keeps the rings it bends with).
    /// Empty (default): the rest pose alone. [`crate::simplify_scene`]
    /// fills it from the file's animations (frames spread over each), or,
    /// without animations, from poses bending every joint.
    pub skin_poses: Vec<Vec<[f32; 16]>>,
    /// Morph targets as poses ([`AttributeOptions::morph_poses`]): per
    /// target, the position delta of every input vertex (input units; a
    /// shorter list leaves the rest still). Empty (default): none.
    /// [`crate::simplify_mesh`] fills it from the mesh's position morph
    /// targets when `morph_poses` is on.
    pub morph_targets: Vec<Vec<[f32; 3]>>,
    /// Input faces that are seen through (a blended material), one flag per
    /// input face: their twins stay even on closed surfaces, since the
    /// inside shows. Empty: none. [`crate::simplify_mesh`] fills it from
    /// [`InputData::see_through_materials`].
    pub see_through_faces: Vec<bool>,
    /// Materials (ids into the scene's materials) that are seen through:
    /// [`crate::simplify_mesh`] marks their faces in
    /// [`InputData::see_through_faces`]. Empty: none. The pipeline fills it
    /// from the file's materials (alpha mode blend).
    pub see_through_materials: Vec<u32>,
    /// Which UV sets each material's textures sample, per material (ids
    /// into the scene's materials), as a bitmask (bit `k`: `TEXCOORD_k`).
    /// A UV set steers collapses ([`AttributeOptions::tex_coord_weight`])
    /// only on faces whose material samples a texture through it: UVs no
    /// texture reads show nothing, and an architectural export's box-mapped
    /// UVs under plain colors would otherwise decide which walls survive.
    /// Faces without a material sample nothing. They are still fitted.
    /// `None` (default): not known, every UV set steers everywhere (plain
    /// arrays, a mesh without its scene). [`crate::simplify_scene`] fills
    /// it from the scene's materials.
    pub material_uv_sets: Option<Vec<u32>>,
    /// How many times a renderer draws each input face (one count per input
    /// face): a mesh shown by several nodes is stored once and drawn once
    /// per node. Each face counts that many times in the triangle budget
    /// ([`Target::ratio`] and [`Target::triangles`]) and in the reported
    /// counts, so a budget is one of drawn triangles, as gltfpack's ratio
    /// and `wildlod info`'s instanced counts are. Empty: once each.
    /// [`crate::simplify_scene`] fills it from the node graph.
    pub face_instances: Vec<u32>,
}

/// All options of [`crate::simplify_polygons`] and the other entry points,
/// grouped by what a user decides (issue 35). Most users set only
/// `target`; the fields marked *Expert* in each group were measured on the
/// corpus and are there to reproduce the measurements, not to be tuned per
/// file.
///
/// | group | decides | fields a user sets |
/// |---|---|---|
/// | [`target`](Options::target) | when to stop | ratio, triangles, error |
/// | [`metric`](Options::metric) | quality: how error is measured, the refit | all expert |
/// | [`guards`](Options::guards) | topology: parts merging, twins, forbidden collapses | `virtual_edge_radius`, `keep_topology`, `lock_borders` |
/// | [`quad`](Options::quad) | quads: Knodt's ordering | `mode` |
/// | [`attributes`](Options::attributes) | UVs, normals, colors, skins | weights, `seams`, `normals` |
/// | [`partition`](Options::partition) | performance on large inputs | all expert |
/// | [`record`](Options::record) | what the run records | `history`, `error_curve` |
/// | [`data`](Options::data) | per-vertex and per-face data | filled by the mesh and scene layers |
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// When to stop.
    pub target: Target,
    /// Quality: the error metric and the final refit.
    pub metric: Metric,
    /// Topology: parts, twins, and the collapses the user forbids.
    pub guards: Guards,
    /// Quads: when Knodt's ordering applies, and its settings.
    pub quad: QuadSettings,
    /// Attributes: their weights in the error, seams, normals.
    pub attributes: AttributeOptions,
    /// Performance: the parallel first phase for large inputs (off while
    /// recording the history, which must see the global order, and with
    /// attributes).
    pub partition: Partition,
    /// What the run records beside the output.
    pub record: Record,
    /// Data that comes with the faces.
    pub data: InputData,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            target: Target {
                ratio: Some(0.5),
                ..Target::default()
            },
            metric: Metric::default(),
            guards: Guards::default(),
            quad: QuadSettings::default(),
            attributes: AttributeOptions::default(),
            partition: Partition::default(),
            record: Record::default(),
            data: InputData::default(),
        }
    }
}

impl Options {
    /// Classic quadric error simplification (Garland & Heckbert 1997) in the
    /// same engine: physical edges only, no area term. The baseline the
    /// papers compare with.
    pub fn classic_qem() -> Self {
        Options {
            metric: Metric {
                boundary_area: false,
                current_face_weight: 0.0,
                gluing_weight: 0.0,
                pinch_cost: 0.0,
                face_weight_floor: 0.0,
                refit_sweeps: 0,
                keep_layers: false,
                ..Metric::default()
            },
            guards: Guards {
                virtual_edge_radius: 0.0,
                ..Guards::default()
            },
            quad: QuadSettings {
                mode: QuadMode::Never,
                ..QuadSettings::default()
            },
            ..Options::default()
        }
    }

    /// Whether the quad ordering applies to an input with `quads` quad faces.
    pub fn quads_active(&self, quads: usize) -> bool {
        match self.quad.mode {
            QuadMode::Auto => quads > 0,
            QuadMode::Always => true,
            QuadMode::Never => false,
        }
    }

    /// The metric in effect for an input with `quads` quad faces: in quad
    /// mode, with its tangent quadrics and introduced-error ranking and
    /// planes weighted by area alone (see [`Metric::face_weight_floor`]);
    /// without the current-face term wherever the input has quads or quad
    /// mode is on (see [`Metric::current_face_weight`]).
    pub fn effective_metric(&self, quads: usize) -> Metric {
        let mut metric = if self.quads_active(quads) {
            Metric {
                tangent_weight: self.quad.tangent_weight,
                introduced_error: self.quad.introduced_error,
                regularized_choice: self.quad.regularized_choice,
                face_weight_floor: 0.0,
                current_face_weight: 0.0,
                ..self.metric
            }
        } else {
            self.metric
        };
        if quads > 0 {
            metric.current_face_weight = 0.0;
        }
        metric
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_target_met_wins() {
        let t = Target {
            ratio: Some(0.1),
            triangles: Some(500),
            error: None,
        };
        assert_eq!(t.triangles_for(1000), 500);
        assert_eq!(t.triangles_for(10_000), 1000);
        assert_eq!(Target::default().triangles_for(10), 0);
        // 0.1% of 6598 rounds to 7.
        let t = Target {
            ratio: Some(0.001),
            ..Target::default()
        };
        assert_eq!(t.triangles_for(6598), 7);
        // A positive ratio of a tiny mesh keeps one triangle; ratio 0 none.
        assert_eq!(t.triangles_for(12), 1);
        let zero = Target {
            ratio: Some(0.0),
            ..Target::default()
        };
        assert_eq!(zero.triangles_for(12), 0);
    }
}
