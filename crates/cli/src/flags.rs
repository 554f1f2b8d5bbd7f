//! Flag groups several commands share (`simplify`, `lod`, `batch`): how to
//! simplify, what to do with textures, and the value enums of their flags.
//! Names here are a contract, like those in [`crate::args`].

use clap::{Args, ValueEnum};

/// How to simplify, shared by `simplify`, `lod` and `batch`.
#[derive(Args, Debug, Clone)]
pub struct TuningArgs {
    /// Merge distance for separate parts (0: never merge)
    ///
    /// Radius r of virtual edges, relative to the bounding-box diagonal: parts
    /// of different components closer than 2r may merge. 0 disables.
    #[arg(long, value_name = "R", default_value_t = wildlod_simplify::Options::default().guards.virtual_edge_radius)]
    pub virtual_radius: f64,
    /// Keep topology: no merging of parts, no closing of holes
    ///
    /// A manifold stays a manifold of the same genus. The target may be out of
    /// reach.
    #[arg(long)]
    pub keep_topology: bool,
    /// Never move or remove vertices on open borders
    #[arg(long)]
    pub lock_borders: bool,
    /// Largest turn of a face in one collapse, in degrees
    ///
    /// 180 turns the flip guard off.
    #[arg(long, value_name = "DEG", default_value_t = 90.0)]
    pub max_normal_turn: f64,
    /// Do not try to keep quads
    ///
    /// Plain cost order even when the input has quads. By default a mesh with
    /// quads is reduced by an ordering that removes whole quad chords and keeps
    /// edge loops.
    #[arg(long)]
    pub no_quads: bool,
    /// Quad keeping tolerance (larger: more quads)
    ///
    /// Tolerance under which collapse costs count as equal and are ordered to
    /// keep quads, as a distance relative to the diagonal at the input's
    /// resolution; it grows with the reduction (twice as wide once half the
    /// vertices are gone, up to ten times). It is the widest the tolerance
    /// gets: on a finely tessellated mesh, whose collapses deviate less, it is
    /// twice the median initial collapse's deviation where that is smaller.
    #[arg(long, value_name = "E", default_value_t = wildlod_simplify::QuadSettings::default().epsilon)]
    pub quad_epsilon: f64,
    /// Quad tie width vs the mesh's detail (0: off)
    ///
    /// Width of the quad ties as a multiple of the input's median initial
    /// collapse deviation, at most --quad-epsilon: a finely tessellated or
    /// finely curved mesh, whose collapses deviate less, gets narrower ties and
    /// keeps closer to its input. 0 uses --quad-epsilon alone.
    #[arg(long, value_name = "F", default_value_t = wildlod_simplify::QuadSettings::default().tie_factor)]
    pub quad_tie_factor: f64,
    /// Mean distance the quad ordering may add (inf: any)
    ///
    /// How much farther from the input, in mean distance, a quad-ordered
    /// output may be than the same run without the ordering: where the
    /// ties would cost more, they narrow (three runs more at most, down to a
    /// sixteenth of their width) to a width within, else the run without
    /// the ordering is kept. The summary and --json say how wide the ties were.
    /// inf keeps the ties as --quad-epsilon and --quad-tie-factor set them.
    #[arg(long, value_name = "T", default_value_t = wildlod_simplify::QuadSettings::default().distance_tolerance)]
    pub quad_tolerance: f64,
    /// Hold edges along creases and keep edge flow (0: off)
    ///
    /// Weight of tangent edge quadrics against the face planes (0.33 balances
    /// them). They hold edges in place along creases and keep edge flow and
    /// thin parts; off by default because they trade distance for regularity
    /// and, on the quad corpus, kept fewer quads than the ordering alone.
    #[arg(long, value_name = "W", default_value_t = 0.0)]
    pub tangent_weight: f64,
    /// Keep mirror symmetry lines (0: off; try 0.33)
    ///
    /// Edges on planes that mirror the model onto itself weigh more, so
    /// symmetry lines survive. Works through the tangent quadrics: turns them
    /// on at 0.33 unless --tangent-weight is given. Costs time on large meshes
    /// (capped at about ten seconds).
    #[arg(long, value_name = "L", default_value_t = 0.0)]
    pub symmetry: f64,
    /// Keep sub-face features longer (try 1; 0: off)
    ///
    /// Rank collapses as if they covered at least this many mean input faces:
    /// features far smaller than a face (hair-thin spurs, tiny parts) are then
    /// ranked by distance rather than by their area, and are kept longer. Off
    /// by default, because on the corpus it costs textured meshes more than it
    /// gains elsewhere.
    #[arg(long, value_name = "K", default_value_t = wildlod_simplify::Metric::default().area_floor)]
    pub area_floor: f64,
    /// Keep thin parts longer (0: off, 1: last)
    ///
    /// Added to the cost of a collapse that pinches or folds material: thin
    /// legs, blades and hair-thin strands stay until nothing cheaper is left,
    /// instead of flattening into edges the output cannot show. 1 ranks such
    /// collapses after every ordinary one (up to --pinch-distance); 0 lets them
    /// compete at their plane cost. Merging parts, closing holes and dropping
    /// parts too small for the target are never penalized.
    #[arg(long, value_name = "C", default_value_t = wildlod_simplify::Metric::default().pinch_cost)]
    pub pinch_cost: f64,
    /// Error at which thin parts may flatten (0: never)
    ///
    /// Caps the pinch cost: a thin part of a part large enough for the target
    /// is flattened once the ordinary collapses left would move the surface by
    /// about half this distance (relative to the bounding-box diagonal), so an
    /// extreme target does not fold the rest of a model to keep thin wires. 0
    /// keeps thin parts until nothing else is left. With --error alone there is
    /// no cap.
    #[arg(long, value_name = "D", default_value_t = wildlod_simplify::Metric::default().pinch_distance)]
    pub pinch_distance: f64,
    /// Weigh faces by area^A (0: all alike)
    ///
    /// How face planes weigh in the error, from 0 to 1. 1 (area-weighted
    /// quadrics) gives the lowest mean distance; 0 weighs every face alike, as
    /// Blender's Decimate does, which keeps finely tessellated details and
    /// lowers the worst-case (Hausdorff) distance at some cost in the mean.
    /// 0.5 suits machined parts whose features are cut in faces much
    /// smaller than the faces beside them: a generated gear at 10% keeps
    /// its teeth, at half the worst-case distance.
    #[arg(long, value_name = "A", default_value_t = wildlod_simplify::Metric::default().area_exponent)]
    pub area_exponent: f64,
    /// Small faces weigh at least K mean faces (0: off)
    ///
    /// Details tessellated finer than the rest (a scanned hair, a fillet,
    /// engraved text) then cost like the rest of the surface instead of going
    /// first, which lowers the worst-case distance. Parts too small for the
    /// target still go first. 0 is plain area weighting. Quad mode always uses
    /// plain area weighting.
    #[arg(long, value_name = "K", default_value_t = wildlod_simplify::Metric::default().face_weight_floor)]
    pub face_weight_floor: f64,
    /// Hold sharp creases (CAD edges) in place (0: off)
    ///
    /// Through every side whose two faces turn by more than --crease-angle, the
    /// plane through it orthogonal to each face is weighted by this times the
    /// side's squared length, as a border is held. Raise it when a part's
    /// outlines slide inward. Not where attributes steer collapses (their hard
    /// edges are seams, held by --seam-weight).
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::Metric::default().crease_weight)]
    pub crease_weight: f64,
    /// Turn between faces, in degrees, that makes a crease
    ///
    /// Between 0 and 180: above it, the shared side of two faces is a crease
    /// for --crease-weight and --crease-area-weight. The default holds CAD
    /// edges of about 90 degrees and sharper, not the folds of a scan.
    #[arg(long, value_name = "DEG", default_value_t = wildlod_simplify::Metric::default().crease_angle)]
    pub crease_angle: f64,
    /// Keep finely cut creases straight (0: off)
    ///
    /// Weight of the area a collapse sweeps against a crease, relative to the
    /// same term at open borders: it sees the crease as simplified so far, so
    /// an edge cut into many short sides holds as well as one long side.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::Metric::default().crease_area_weight)]
    pub crease_area_weight: f64,
    /// Rank collapses by the surface as it is now too (0: off)
    ///
    /// Weight of the present faces' planes beside the input's: a collapse
    /// also costs how far it lifts the faces around it off their current
    /// planes, weighed by their current area, so a vertex that anchors
    /// large triangles holds them like one that carries their input area.
    /// Ranking only (vertices are placed by the input's planes); not with
    /// quads kept, nor with --classic.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::Metric::default().current_face_weight)]
    pub current_faces: f64,
    /// Sweeps of the final vertex refit (0: off)
    ///
    /// Once the collapses are done, every vertex moves to where its error
    /// quadric plus the input's distances to its faces are smallest, which
    /// lowers the distance between input and output. A vertex never moves
    /// farther from the input than the input points it fits, nor folds a face.
    /// --classic and --symmetry do not refit (it would move vertices off the
    /// mirror plane).
    #[arg(long, value_name = "N", default_value_t = wildlod_simplify::Options::default().metric.refit_sweeps)]
    pub refit_sweeps: u32,
    /// Keep back-to-back duplicate faces that cannot be seen
    ///
    /// Exporters make surfaces double-sided by writing every face twice, once
    /// each way; on a closed part one copy looks into the solid, and elsewhere
    /// a copy from which no ray escapes the mesh and no line of sight reaches
    /// an opening is enclosed too. By default such copies are dropped before
    /// simplifying and their share of the budget buys visible detail. Open
    /// sheets and blended (see-through) materials keep both sides.
    #[arg(long)]
    pub keep_hidden_twins: bool,
    /// Keep parts that are wholly inside another, closed part
    ///
    /// A part inside another part that is closed, faces outward and is
    /// drawn opaque and one-sided (the shaft in a sealed CAD housing, the
    /// engine under a closed body), touching it nowhere, cannot be seen: by
    /// default it is dropped before simplifying and its share of the budget
    /// buys visible detail. Parts that show through an opening, poke out or
    /// rest on the inner wall stay, and so does every part of a file with
    /// animations, skins, morph targets, or a double-sided, alpha-tested or
    /// blended material.
    #[arg(long)]
    pub keep_enclosed_parts: bool,
    /// Let decals sink into the simplified surface under them
    ///
    /// An open sheet lying a little in front of another part and facing the
    /// same way (a decal, a sticker, a road marking) is a layer: by default
    /// it moves with the simplified surface under it and keeps its offset
    /// from it, instead of sinking behind it once the surface's error
    /// exceeds the gap. --classic turns this off too.
    #[arg(long)]
    pub no_layers: bool,
    /// Classic quadric error simplification, for comparisons
    ///
    /// No virtual edges, no area term.
    #[arg(long)]
    pub classic: bool,
    /// How much UVs steer collapses (raise if smeared)
    ///
    /// Every attribute is fitted at the new positions whatever its weight; a
    /// weight says how much a change of it costs: 1 makes a change across the
    /// stream's whole range cost as much as moving the surface by the whole
    /// bounding-box diagonal. 0 lets geometry alone decide.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().tex_coord_weight)]
    pub uv_weight: f64,
    /// How much normals steer collapses
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().normal_weight)]
    pub normal_weight: f64,
    /// How much vertex colors steer collapses
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().color_weight)]
    pub color_weight: f64,
    /// How much skin weights steer collapses
    ///
    /// Joints are fitted per position and written as the input's number of
    /// influences, summing to 1. At any weight, 0 included, a skinned mesh
    /// is simplified as it is drawn: each face's plane counts in the rest
    /// pose and in poses spread over the file's animations (without
    /// animations, each joint bent both ways), so the rings a pose bends
    /// stay, at some cost in distance at rest.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().skin_weight)]
    pub skin_weight: f64,
    /// Seams: penalize, keep or ignore (see --help)
    ///
    /// `penalize` crosses a seam only where that costs less than what else is
    /// left (moving a seam costs its distance, merging two sides costs the
    /// difference of their values: UV charts apart stay apart); `keep` never
    /// crosses them (the target may be missed); `ignore` lets them move and
    /// close like any edge (for re-baked textures).
    #[arg(long, value_enum, default_value_t = SeamArg::Penalize, hide_possible_values = true)]
    pub seams: SeamArg,
    /// How firmly seams hold their path (0: may bend)
    ///
    /// Weight of the planes that hold seam vertices on their seam when a
    /// collapse slides them along it, per squared edge length; 0: seams may
    /// bend within their charts.
    #[arg(long, value_name = "W", default_value_t = wildlod_simplify::AttributeOptions::default().seam_weight)]
    pub seam_weight: f64,
    /// Output normals: fitted or recomputed
    ///
    /// `fit` carries the input's normals through every collapse (smooth shading
    /// survives); `recompute` derives them from the simplified faces, keeping
    /// the input's hard edges.
    #[arg(long, value_enum, default_value_t = NormalArg::Fit, hide_possible_values = true)]
    pub normals: NormalArg,
}

/// Texture arguments of `simplify`, `lod` and `batch`.
#[derive(Args, Debug)]
pub struct TextureArgs {
    /// Textures: auto, keep or bake (see --help)
    ///
    /// `auto` keeps the input's UVs and textures while the result shows the
    /// texture as the input does (texture Chamfer distance over the input's
    /// own by at most a quarter of it, and at most 0.01), else also re-bakes
    /// and keeps whichever measures better. Down a chain (lod), levels share the input's textures until
    /// the first level that auto re-bakes; that level and every coarser one
    /// are made from the input with a re-baked atlas of their own. `keep`
    /// always keeps the input's textures; `bake` always re-bakes.
    #[arg(long, value_enum, default_value_t = TextureArg::Auto, hide_possible_values = true)]
    pub textures: TextureArg,
    /// When re-baking: atlas size in texels
    ///
    /// Default: the input's texel density × √(triangles kept), at least 256
    /// a side and never coarser than the input's textures can be averaged
    /// without a visible change, rounded to a power of two, at most 4096.
    #[arg(long, value_name = "N")]
    pub texture_size: Option<u32>,
    /// When re-baking: one atlas per alpha mode and sidedness
    ///
    /// Bakes every material with the same alpha mode and sidedness into one
    /// atlas and one material (fewer draw calls).
    #[arg(long)]
    pub merge_materials: bool,
    /// When re-baking: JPEG quality for JPEG inputs
    ///
    /// Used when the input's textures were all JPEG; otherwise PNG is written.
    #[arg(long, value_name = "Q", default_value_t = 90)]
    pub jpeg_quality: u8,
    /// When re-baking: no normal map from geometry
    ///
    /// By default every re-baked material gets a tangent-space normal map of
    /// the input's shading normals (its normal map applied where it has one,
    /// else its vertex normals), so the LOD is lit with the detail its
    /// collapses removed. With this flag normal maps are baked only where the
    /// input has one.
    #[arg(long)]
    pub no_normal_bake: bool,
}

/// `--textures`: keep the UVs, re-bake, or choose by measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TextureArg {
    /// Keep the UVs; re-bake where that shows the texture visibly worse
    /// and the re-bake measures better.
    Auto,
    /// Keep the input's UVs and atlas.
    Keep,
    /// Re-bake onto a new atlas.
    Bake,
}

/// `--seams`: what happens to attribute seams.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SeamArg {
    /// Cross seams only where that costs less than what else is left.
    Penalize,
    /// Never cross seams; the target may be missed.
    Keep,
    /// Let seams move and close like any edge.
    Ignore,
}

/// `--normals`: how output normals are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalArg {
    /// Fitted through every collapse, then normalized.
    Fit,
    /// Recomputed from the simplified faces, input hard edges kept.
    Recompute,
}
