//! The error metric of W §4.2, as composable terms:
//!
//! - plane quadrics of the faces, area-weighted per vertex (W Eq. 9–11),
//!   summed per edge with *memory* (W Eq. 13, App. A.2);
//! - a probabilistic (isotropic) regularization term (Trettner & Kobbelt
//!   2020) that keeps the solve well conditioned;
//! - the Lindstrom–Turk area quadric over the boundary edges of the edge's
//!   one-ring (W Eq. 15), recomputed on the current mesh: *memoryless*.
//!
//! Per-vertex importance weights scale a vertex's quadrics (W Fig. 20).
//! Later terms (tangent quadrics, attributes) add to the same sums.

use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

use crate::options::Metric;
use crate::prepare::complex::{Complex, NONE};
use crate::prepare::flat_stars::FlatStars;
use crate::prepare::geometry::face_plane;
use crate::terms::attributes::{AttrScratch, AttributeState};
use crate::terms::current_faces::current_face_cost;
use crate::terms::guards::too_small_for_budget;
use crate::terms::quadric::{place, place_by_planes, place_exact, Quadric};
use crate::terms::stored::{Isotropic, StoredQuadric};
use crate::terms::tangent::tangent_quadrics;
pub(crate) use crate::terms::tangent::EdgeImportance;
use crate::terms::term::{Candidate, CollapseTerm, FAR};

/// How far from an edge's midpoint, in edge lengths, the optimal point may
/// land before the solve is distrusted. Generous: sharp corners can lie a
/// couple of edge lengths beyond a bevel being collapsed.
const REACH: f64 = 4.0;

/// Corner `v`'s share of face `f`'s plane quadric and of its (weighed)
/// area `a`: the barycentric share of W Eq. 9.
///
/// A triangle has one plane, a third of which each corner takes. A warped
/// polygon has no plane: it is drawn as the fan of triangles from its first
/// corner (by wildlod's writers, which cut only flat polygons whose fan
/// folds, by OBJ readers, renderers and the error metrics), so each corner
/// takes a third of the planes of the fan triangles it belongs to, scaled
/// so that the polygon weighs `a` in all.
/// Every corner then lies on every plane it holds, as on a triangle mesh,
/// where the average (Newell) plane lies on none of them: a curved blade's
/// quads lost their curvature to it, and their vertices their place. For a
/// planar polygon the planes are its one plane.
fn face_share(c: &Complex, f: u32, v: u32, (n, a, p): (DVec3, f64, DVec3)) -> (Quadric, f64) {
    let face = c.face(f);
    let k = face.len();
    if k == 3 {
        let share = a / 3.0;
        return (Quadric::plane(n, p, share), share);
    }
    let at = |i: usize| c.pos[face[i] as usize];
    let mut mine = Quadric::ZERO;
    let mut fan_area = 0.0;
    for i in 1..k - 1 {
        let (p0, p1, p2) = (at(0), at(i), at(i + 1));
        let n2 = (p1 - p0).cross(p2 - p0);
        let len = n2.length();
        if len.is_finite() && len > 0.0 {
            fan_area += 0.5 * len;
            if face[0] == v || face[i] == v || face[i + 1] == v {
                mine += Quadric::plane(n2 / len, p0, 0.5 * len / 3.0);
            }
        }
    }
    if fan_area > 0.0 && fan_area.is_finite() {
        let q = mine.scaled(a / fan_area);
        let share = q.weight;
        (q, share)
    } else {
        let share = a / k as f64;
        (Quadric::plane(n, p, share), share)
    }
}

/// The median, over the sides of the faces, of the distance a collapse of
/// that side would move the surface: √(error / mean weight) of the two
/// endpoints' quadrics at their optimal point. Faces are sampled evenly, at
/// most 65,536 sides, and every side counts once per face it bounds; faces
/// only are read, so it works before the complex has edges (the
/// partitioned path). 0 when no side has area.
///
/// The scale of the errors this mesh's collapses make at the start, which
/// Knodt's tie tolerance is a share of (see
/// [`crate::collapse::ordering::tie_distance`]).
pub(crate) fn median_collapse_deviation(c: &Complex, q: &[StoredQuadric]) -> f64 {
    const SAMPLES: usize = 1 << 16;
    let live: Vec<u32> = (0..c.faces.len() as u32)
        .filter(|&f| c.faces[f as usize].len > 0)
        .collect();
    let sides: usize = live.iter().map(|&f| c.faces[f as usize].len as usize).sum();
    let stride = sides.div_ceil(SAMPLES).max(1);
    let mut deviations: Vec<f64> = live
        .iter()
        .step_by(stride)
        .flat_map(|&f| {
            let face = c.face(f);
            (0..face.len()).map(move |k| (face[k], face[(k + 1) % face.len()]))
        })
        .filter_map(|(a, b)| {
            let (pa, pb) = (c.pos[a as usize], c.pos[b as usize]);
            let sum = q[a as usize].quadric(pa) + q[b as usize].quadric(pb);
            let placed = place(&sum, pa, pb, REACH);
            // Per mean endpoint weight, as the tie tolerance is applied
            // (`ordering::tie_tolerance`).
            let d2 = placed.error / (0.5 * sum.weight);
            (sum.weight > 0.0 && d2.is_finite()).then(|| d2.max(0.0).sqrt())
        })
        .collect();
    if deviations.is_empty() {
        return 0.0;
    }
    let mid = deviations.len() / 2;
    *deviations.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The quadrics of [`vertex_quadric_parts`] as plain quadrics, for any
/// budget.
#[cfg(test)]
pub(crate) fn vertex_quadrics(
    c: &Complex,
    metric: &Metric,
    weights: &[f64],
    importance: EdgeImportance<'_>,
) -> Vec<Quadric> {
    // A budget no part is too small for.
    vertex_quadric_terms(c, metric, weights, importance, usize::MAX, &[], |_, q| q).0
}

/// The initial quadric of every vertex: Σ over its faces of its share of
/// their planes (the barycentric share of W Eq. 9, polygons as the fans
/// they are drawn with, see [`face_share`]), plus the regularization
/// term, times the vertex's weight; summed per vertex in face order, so
/// the result does not depend on thread count. As a run stores them
/// (each about its vertex, see [`StoredQuadric`]), and the regularization
/// part of each (already in the first), which the placement takes back
/// out to solve exactly (see
/// [`crate::terms::quadric::place_exact`]). `budget` is the run's target in
/// triangles (see [`Metric::face_weight_floor`]).
pub(crate) fn vertex_quadric_parts(
    c: &Complex,
    metric: &Metric,
    weights: &[f64],
    importance: EdgeImportance<'_>,
    budget: usize,
    outliers: &[bool],
) -> (Vec<StoredQuadric>, Vec<Isotropic>) {
    vertex_quadric_terms(c, metric, weights, importance, budget, outliers, |v, q| {
        StoredQuadric::new(&q, c.pos[v])
    })
}

/// The vertex quadrics, each handed to `store` with its vertex, and the
/// regularization parts.
fn vertex_quadric_terms<T: Send>(
    c: &Complex,
    metric: &Metric,
    weights: &[f64],
    importance: EdgeImportance<'_>,
    budget: usize,
    outliers: &[bool],
    store: impl Fn(usize, Quadric) -> T + Sync,
) -> (Vec<T>, Vec<Isotropic>) {
    let planes = weighed_planes(c, metric, budget, outliers);
    let tangent = if metric.tangent_weight > 0.0 {
        let normals: Vec<Option<DVec3>> = planes.iter().map(|p| p.map(|p| p.0)).collect();
        tangent_quadrics(c, &normals, importance, metric.tangent_weight)
    } else {
        Vec::new()
    };
    let border = if metric.border_weight > 0.0 || metric.crease_weight > 0.0 {
        border_planes(
            c,
            &planes,
            metric.border_weight,
            metric.crease_weight,
            metric.crease_angle.to_radians().cos(),
        )
    } else {
        SidePlanes::none()
    };
    let finish = |v: usize, mut q: Quadric, area: f64| {
        let mut reg = Quadric::ZERO;
        if metric.regularization > 0.0 && area > 0.0 {
            reg = Quadric::point(c.pos[v], metric.regularization * area);
            q += reg;
        }
        if let Some(t) = tangent.get(v) {
            // Tangent planes carry no area: keep the weight (which turns
            // errors into distances) the faces' own.
            q += Quadric { weight: 0.0, ..*t };
        }
        if let Some(b) = border.get(v) {
            q += *b;
        }
        match weights.get(v) {
            Some(&w) if w != 1.0 => (store(v, q.scaled(w)), Isotropic::of(&reg.scaled(w))),
            _ => (store(v, q), Isotropic::of(&reg)),
        }
    };
    if !c.has_adjacency() {
        // No star lists (the partitioned path defers them): a compact
        // vertex → faces index, filled in face order like the star lists,
        // so the sums are the same to the bit.
        let (start, list) = c.vertex_face_index();
        return (0..c.pos.len())
            .into_par_iter()
            .map(|v| {
                let mut q = Quadric::ZERO;
                let mut area = 0.0;
                for &f in &list[start[v] as usize..start[v + 1] as usize] {
                    if let Some(plane) = planes[f as usize] {
                        let (fq, share) = face_share(c, f, v as u32, plane);
                        q += fq;
                        area += share;
                    }
                }
                finish(v, q, area)
            })
            .unzip();
    }
    (0..c.pos.len())
        .into_par_iter()
        .map(|v| {
            let mut q = Quadric::ZERO;
            let mut area = 0.0;
            for &f in &c.vert_faces[v] {
                if let Some(plane) = planes[f as usize] {
                    let (fq, share) = face_share(c, f, v as u32, plane);
                    q += fq;
                    area += share;
                }
            }
            finish(v, q, area)
        })
        .unzip()
}

/// Every live face's plane (unit normal, weight, centroid) as the vertex
/// quadrics take it: weighed by the metric (see [`weigh_planes`]), none
/// for a face that reaches an outlier vertex (see `Prepared::outliers`),
/// which is no surface to keep: its plane would outweigh every other by
/// orders of magnitude.
fn weighed_planes(
    c: &Complex,
    metric: &Metric,
    budget: usize,
    outliers: &[bool],
) -> Vec<Option<(DVec3, f64, DVec3)>> {
    let reaches_outlier =
        |f: u32| !outliers.is_empty() && c.face(f).iter().any(|&v| outliers[v as usize]);
    let planes: Vec<Option<(DVec3, f64, DVec3)>> = (0..c.faces.len() as u32)
        .into_par_iter()
        .map(|f| {
            if c.faces[f as usize].len == 0 || reaches_outlier(f) {
                None
            } else {
                face_plane(c, f)
            }
        })
        .collect();
    weigh_planes(
        c,
        planes,
        metric.area_exponent,
        metric.face_weight_floor,
        budget,
    )
}

/// What the vertex quadrics weigh each face's plane by, per unit of its
/// area: 1 under W's area weighting, other values under
/// [`Metric::area_exponent`] and [`Metric::face_weight_floor`], 0 for a
/// face they leave out (dead, degenerate, reaching an outlier).
pub(crate) fn plane_weight_factors(
    c: &Complex,
    metric: &Metric,
    budget: usize,
    outliers: &[bool],
) -> Vec<f64> {
    weighed_planes(c, metric, budget, outliers)
        .into_par_iter()
        .enumerate()
        .map(|(f, weighed)| match (weighed, face_plane(c, f as u32)) {
            (Some((_, w, _)), Some((_, a, _))) if a > 0.0 => w / a,
            _ => 0.0,
        })
        .collect()
}

/// The weight each face plane carries, in place of its area (see
/// [`plane_weight`]), `mean` being the mean area of all faces: the floor
/// lifts faces below it except in parts too small to keep a closed
/// surface at `budget` triangles (`guards::too_small_for_budget`), which
/// stay as cheap as W's budget makes them, so they still go first (W §1,
/// Fig. 1). Exponent 1 and floor 0 leave the areas as they are.
fn weigh_planes(
    c: &Complex,
    planes: Vec<Option<(DVec3, f64, DVec3)>>,
    exponent: f64,
    floor: f64,
    budget: usize,
) -> Vec<Option<(DVec3, f64, DVec3)>> {
    if exponent == 1.0 && floor <= 0.0 {
        return planes;
    }
    let (count, sum) = planes
        .iter()
        .flatten()
        .fold((0usize, 0.0), |(n, s), p| (n + 1, s + p.1));
    if count == 0 || sum.is_nan() || sum <= 0.0 {
        return planes;
    }
    let mean = sum / count as f64;
    let small = if floor > 0.0 {
        small_part_faces(c, &planes, sum, budget)
    } else {
        Vec::new()
    };
    // In place: the planes are the largest array of this phase.
    let mut planes = planes;
    planes.par_iter_mut().enumerate().for_each(|(f, p)| {
        if let Some((_, a, _)) = p {
            let lift = if small.get(f).copied().unwrap_or(false) {
                0.0
            } else {
                floor * mean
            };
            *a = plane_weight(*a, mean, exponent, lift);
        }
    });
    planes
}

/// Whether each face lies in a connected part too small, by its share of
/// the area `total`, to keep a closed surface at `budget` triangles.
fn small_part_faces(
    c: &Complex,
    planes: &[Option<(DVec3, f64, DVec3)>],
    total: f64,
    budget: usize,
) -> Vec<bool> {
    let (label, parts) = c.part_labels();
    let part = |f: usize| {
        c.face(f as u32)
            .first()
            .map(|&v| label[v as usize] as usize)
    };
    let mut area = vec![0.0f64; parts];
    for (f, p) in planes.iter().enumerate() {
        if let (Some(k), Some(p)) = (part(f), p) {
            area[k] += p.1;
        }
    }
    (0..planes.len())
        .map(|f| part(f).is_some_and(|k| too_small_for_budget(area[k], total, budget)))
        .collect()
}

/// `max(mean · (area / mean)^exponent, lift)`: the plane weight of a face
/// of `area` on a mesh whose mean face area is `mean`, at least `lift`
/// (see [`Metric::area_exponent`] and [`Metric::face_weight_floor`]).
#[inline]
pub(crate) fn plane_weight(area: f64, mean: f64, exponent: f64, lift: f64) -> f64 {
    // Exponent 1 is the area itself, to the bit: a floor that lifts no
    // face must leave the quadrics exactly as W's weighting makes them.
    let weighted = if exponent == 1.0 {
        area
    } else {
        mean * (area / mean).powf(exponent)
    };
    weighted.max(lift)
}

/// The plane through `side` orthogonal to a face of `normal`, weighted by
/// `weight · |side|²` and carrying no area (see [`border_planes`]); none
/// for a side along the normal or of no length.
fn side_plane((pa, pb): (DVec3, DVec3), normal: DVec3, weight: f64) -> Option<Quadric> {
    let side = pb - pa;
    let n = side.cross(normal);
    let len = n.length();
    (len > 0.0 && len.is_finite()).then(|| Quadric {
        weight: 0.0,
        ..Quadric::plane(n / len, pa, weight * side.length_squared())
    })
}

/// Garland & Heckbert's boundary constraints (1997 §6; Blender's Decimate
/// and meshoptimizer keep borders the same way): for every side of a face
/// that no other face shares, the plane through that side orthogonal to
/// the face, weighted by `weight · |side|²`, added to both its ends, with
/// memory. The memoryless area term (W Eq. 15) charges a collapse for the
/// area its border edges sweep on the current mesh only, so a border can
/// drift away a little at every step; these planes remember where the
/// input's border was. A vertex on a straight border may still slide along
/// it for free, a border corner sits at the meeting point of two planes and
/// stays. Squared length keeps the planes on the scale of the area-weighted
/// face quadrics (weight 1: a unit of border side weighs like a unit of
/// area), so the balance is the same at every resolution. They carry no
/// area (`weight` 0): reported distances stay per unit of surface.
///
/// Sharp creases (two faces whose normals' cosine is below `crease_cos`)
/// are held the same way from both faces with `crease_weight` (see
/// [`Metric::crease_weight`]); 0 holds none.
pub(crate) fn border_planes(
    c: &Complex,
    planes: &[Option<(DVec3, f64, DVec3)>],
    weight: f64,
    crease_weight: f64,
    crease_cos: f64,
) -> SidePlanes {
    // Every side of every live face, keyed by its ends; a key seen once is
    // a border side.
    let mut sides: Vec<(u64, u32, u32)> = Vec::new();
    for f in c.live_faces() {
        let face = c.face(f);
        let n = face.len();
        for k in 0..n {
            let (a, b) = (face[k], face[(k + 1) % n]);
            sides.push((((a.min(b) as u64) << 32) | a.max(b) as u64, f, k as u32));
        }
    }
    sides.par_sort_unstable();
    let mut out = SidePlanes {
        slot: vec![NONE; c.pos.len()],
        quadric: Vec::new(),
    };
    let mut g = 0;
    while g < sides.len() {
        let mut h = g + 1;
        while h < sides.len() && sides[h].0 == sides[g].0 {
            h += 1;
        }
        if h - g == 2 && crease_weight > 0.0 {
            let (_, f0, k0) = sides[g];
            let (_, f1, k1) = sides[g + 1];
            if let (Some((n0, _, _)), Some((n1, _, _))) = (planes[f0 as usize], planes[f1 as usize])
            {
                let face = c.face(f0);
                let (a, b) = (face[k0 as usize], face[(k0 as usize + 1) % face.len()]);
                // Faces wound against each other (a wild mesh's flipped
                // face) walk their side the same way: the turn between
                // them is measured with one normal reversed, or a flat
                // sheet with a flipped face would be all creases.
                let other = c.face(f1);
                let n1 = if other[k1 as usize] == a { -n1 } else { n1 };
                if n0.dot(n1) < crease_cos {
                    let side = (c.pos[a as usize], c.pos[b as usize]);
                    for normal in [n0, n1] {
                        if let Some(q) = side_plane(side, normal, crease_weight) {
                            out.add(a, q);
                            out.add(b, q);
                        }
                    }
                }
            }
        }
        if h - g == 1 && weight > 0.0 {
            let (_, f, k) = sides[g];
            if let Some((normal, _, _)) = planes[f as usize] {
                let face = c.face(f);
                let (a, b) = (face[k as usize], face[(k as usize + 1) % face.len()]);
                let side = (c.pos[a as usize], c.pos[b as usize]);
                if let Some(q) = side_plane(side, normal, weight) {
                    out.add(a, q);
                    out.add(b, q);
                }
            }
        }
        g = h;
    }
    out
}

/// The border and crease planes of the vertices that have any (most
/// vertices of most meshes have none: a dense array of quadrics would
/// double the memory of the phase that builds the vertex quadrics).
pub(crate) struct SidePlanes {
    /// Each vertex's index into `quadric`, or `NONE`.
    slot: Vec<u32>,
    quadric: Vec<Quadric>,
}

impl SidePlanes {
    /// No planes at any vertex.
    pub fn none() -> SidePlanes {
        SidePlanes {
            slot: Vec::new(),
            quadric: Vec::new(),
        }
    }

    fn add(&mut self, v: u32, q: Quadric) {
        let s = &mut self.slot[v as usize];
        if *s == NONE {
            *s = self.quadric.len() as u32;
            self.quadric.push(Quadric::ZERO);
        }
        self.quadric[*s as usize] += q;
    }

    /// The planes of vertex `v`, if it has any.
    pub fn get(&self, v: usize) -> Option<&Quadric> {
        match self.slot.get(v) {
            Some(&s) if s != NONE => self.quadric.get(s as usize),
            _ => None,
        }
    }

    /// The planes of vertex `v` (zero if none).
    #[cfg(test)]
    pub fn at(&self, v: usize) -> Quadric {
        self.get(v).copied().unwrap_or(Quadric::ZERO)
    }
}

/// The result of evaluating a collapse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Evaluation {
    /// Queue priority: the total quadric error at the new position.
    pub cost: f64,
    /// Where the new vertex goes.
    pub position: DVec3,
}

/// Root-mean-square distance from `x` to the planes vertices `i` and `j`
/// accumulated (relative to the unit diagonal): the error users see, and the
/// one `--error` limits. Computed only for collapses actually considered.
pub(crate) fn distance(c: &Complex, q: &[StoredQuadric], i: u32, j: u32, x: DVec3) -> f64 {
    let at = |v: u32| q[v as usize].quadric(c.pos[v as usize]);
    let m = at(i) + at(j);
    (m.eval(x).max(0.0) / m.weight.max(f64::MIN_POSITIVE)).sqrt()
}

/// `cost` of a collapse whose endpoints carry `weight` of area, ranked as
/// if they carried at least `floor` (see [`Metric::area_floor`]): the mean
/// squared distance `cost / weight` times the floor when the weight is
/// below it. A weightless collapse (tangent or attribute terms alone) is
/// left as it is.
#[inline]
pub(crate) fn floored(cost: f64, weight: f64, floor: f64) -> f64 {
    if weight > 0.0 && weight < floor {
        cost * (floor / weight)
    } else {
        cost
    }
}

/// Evaluation settings derived from the options.
#[derive(Clone, Debug)]
pub(crate) struct CostModel {
    pub metric: Metric,
    /// The memoryless terms, in the order they add (see
    /// [`crate::terms::collapse_terms`]).
    pub terms: Arc<[Box<dyn CollapseTerm>]>,
    pub lock_borders: bool,
    /// [`Metric::area_floor`] in the complex's area units (times the mean
    /// face area of the whole input, so chunks rank alike).
    pub area_floor: f64,
    /// [`crate::AttributeOptions::attributes_move_vertices`].
    pub attributes_move_vertices: bool,
    /// How much more a collapse's geometric cost may be where attributes
    /// place its vertex (Hoppe's joint placement) than where the surface
    /// alone would: `tolerance² − 1` for
    /// [`crate::AttributeOptions::geometry_tolerance`] (costs are squared
    /// distances times area).
    pub attribute_slack: f64,
    /// Squared [`crate::AttributeOptions::invisible_distance`]: appearance
    /// may always reorder collapses below it, whatever the budget, and
    /// move a vertex by it where its planes do not hold it already.
    pub invisible_distance2: f64,
    /// Whether a border vertex of a planar region moves only onto a border
    /// vertex (see `evaluate`). On in every run, re-baking's included
    /// (issue 31, decision 3); unit tests turn it off to compare with the
    /// free placement.
    pub exact_flat_borders: bool,
    /// The file's geometric error budget, in cost units (area times
    /// squared distance): appearance may lift a collapse's rank up to it,
    /// never higher, and never lowers a rank. The budget is
    /// `geometry_tolerance²` times the level a run on the positions alone
    /// ends at for the same target ([`crate::Report::cost_level`]): the
    /// greedy order of the attributes' run then makes every collapse of
    /// the surface cheaper than that before it lets appearance hold one.
    /// A collapse whose seam or texture would suffer waits, at most until
    /// every collapse of the surface within the budget is made; the
    /// output's distance to the input then stays within about the
    /// tolerance of a geometry-only run's, whatever the attributes say.
    /// Infinite: appearance steers without bound (Hoppe 1999 as written).
    pub appearance_budget: f64,
    /// Whether the regularization's travel cost counts as appearance (with
    /// steering attributes, [`crate::AttributeOptions::regularized_choice`]).
    pub regularization_looks: bool,
}

/// Reusable buffers of one evaluating thread.
#[derive(Default)]
pub(crate) struct Scratch {
    pub a: Vec<u32>,
    pub b: Vec<u32>,
    pub crease: Vec<u32>,
    pub attributes: AttrScratch,
}

impl CostModel {
    /// Whether the crease area term applies (see
    /// [`Metric::crease_area_weight`]): with the border's area term, and
    /// not where attributes steer (their hard edges are seams).
    pub fn crease_area_applies(&self) -> bool {
        self.metric.boundary_area && self.metric.crease_area_weight > 0.0
    }

    /// What moving the surface by the invisible distance costs over `area`.
    #[inline]
    fn invisible_cost(&self, area: f64) -> f64 {
        self.invisible_distance2 * area.max(0.0)
    }

    /// Whether evaluation needs to know which vertices are on a border.
    pub fn needs_border(&self) -> bool {
        self.metric.boundary_area || self.lock_borders
    }

    /// Evaluates collapsing edge `e`: the summed quadric with memory, plus
    /// the memoryless boundary-area term, plus the attribute error (Hoppe
    /// 1999) when `attributes` are given, minimized (W Eq. 14) with the
    /// documented fallback. `None` when the collapse is not allowed (both
    /// endpoints locked, or a seam forbids it) or its error is not finite.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &self,
        c: &Complex,
        q: &[StoredQuadric],
        reg: &[Isotropic],
        border: &[bool],
        crease: &[bool],
        locked: &[bool],
        flat: &FlatStars,
        attributes: Option<&AttributeState>,
        e: u32,
        s: &mut Scratch,
    ) -> Option<Evaluation> {
        let [i, j] = c.edges[e as usize].ends;
        let (pi, pj) = (c.pos[i as usize], c.pos[j as usize]);
        // NaN (a non-finite position) counts as far.
        let d2 = pi.distance_squared(pj);
        if d2.is_nan() || d2 > FAR * FAR {
            return None;
        }
        let (qi, qj) = (q[i as usize].quadric(pi), q[j as usize].quadric(pj));
        let mut total = qi + qj;
        // `border` says which vertices have boundary edges at all; most
        // evaluations (interior edges) skip the scan.
        let (mut bi, mut bj) = (false, false);
        s.a.clear();
        s.b.clear();
        if self.needs_border() {
            if border.get(i as usize).copied().unwrap_or(true) {
                c.boundary_neighbors(i, &mut s.a);
                bi = !s.a.is_empty();
            }
            if border.get(j as usize).copied().unwrap_or(true) {
                c.boundary_neighbors(j, &mut s.b);
                bj = !s.b.is_empty();
            }
        }
        // The memoryless terms (see `terms::collapse_terms`).
        let candidate = Candidate {
            c,
            e,
            i,
            j,
            pi,
            pj,
            qi: &qi,
            qj: &qj,
            border_i: &s.a,
            border_j: &s.b,
            crease,
        };
        for term in self.terms.iter() {
            term.evaluate(&candidate, &mut s.crease, &mut total);
        }
        // A fixed vertex (a locked border, a chunk's edge in the partitioned
        // path, a seam the collapse must not move) does not move: the other
        // one comes to it.
        let mut fixed_i =
            (self.lock_borders && bi) || locked.get(i as usize).copied().unwrap_or(false);
        let mut fixed_j =
            (self.lock_borders && bj) || locked.get(j as usize).copied().unwrap_or(false);
        // The surface's own quadric: what the collapse does to the geometry.
        // Attributes add an appearance quadric that steers, within bounds
        // (see `CostModel::attribute_slack`).
        let geometry = total;
        let appearance = match attributes {
            Some(a) => {
                let t = a.terms(c, i, j, &mut s.attributes)?;
                fixed_i |= t.fixed_i;
                fixed_j |= t.fixed_j;
                Some(t.quadric)
            }
            None => None,
        };
        if fixed_i && fixed_j {
            return None;
        }
        let r = match (reg.get(i as usize), reg.get(j as usize)) {
            (Some(ri), Some(rj)) => Some(ri.quadric() + rj.quadric()),
            _ => None,
        };
        // What ranks a collapse geometrically: the planes and area terms,
        // with the regularization only where it is asked to choose.
        let ranked = match &r {
            Some(r) if !self.metric.regularized_choice => geometry.minus(r),
            _ => geometry,
        };
        let position = if fixed_i {
            pi
        } else if fixed_j {
            pj
        } else {
            // Solved without the regularization, which only steadies the
            // free directions (see `place_exact`); with no record of it,
            // the regularized solve.
            let by_geometry = |q: &Quadric| match &r {
                Some(r) if self.metric.regularized_choice => place_exact(q, r, pi, pj, REACH),
                Some(r) => place_by_planes(q, r, pi, pj, REACH),
                None => place(q, pi, pj, REACH),
            };
            let at = endpoint_if_as_good(
                &ranked,
                by_geometry(&geometry).position,
                pi,
                pj,
                qi.weight + qj.weight,
            );
            match &appearance {
                // Hoppe's joint placement over position and attributes, kept
                // only where it costs the surface no more than the slack.
                Some(app) if self.attributes_move_vertices => {
                    let joint = match &r {
                        Some(r) => place_exact(&(geometry + *app), r, pi, pj, REACH),
                        None => place(&(geometry + *app), pi, pj, REACH),
                    }
                    .position;
                    // The invisible allowance only where the planes do not
                    // hold `at` already: where they do (a flat region, a
                    // straight crease, to the precision of f32 input), the
                    // joint point must be as exact, so flat stays flat
                    // whatever steers (issue 31, decision 3); elsewhere the
                    // attributes may move the vertex by an invisible
                    // distance, which keeps a UV seam's texture whole.
                    let weight = qi.weight + qj.weight;
                    let planes = match &r {
                        Some(r) => geometry.minus(r),
                        None => geometry,
                    };
                    let held = planes.eval(at) <= weight * HELD * HELD;
                    let allowance = if held {
                        0.0
                    } else {
                        self.invisible_cost(weight)
                    };
                    let bound = ranked.eval(at).max(0.0) * (1.0 + self.attribute_slack) + allowance;
                    if ranked.eval(joint) <= bound {
                        joint
                    } else {
                        at
                    }
                }
                _ => at,
            }
        };
        // Flat stays flat (issue 31, decision 3): on the border of a planar
        // region a vertex moves only onto a border vertex. The border
        // planes hold it only in a least-squares sense: two corners of a
        // ragged border joined meet between them, and a vertex on a
        // straight run slides past the run's end, so the output would
        // cover area the input does not. Endpoints keep every output
        // border vertex an input one (as meshoptimizer keeps all borders);
        // along a straight run that costs nothing. Curved or folded
        // borders keep the optimal placement, which serves them.
        let position = if (bi || bj)
            && !fixed_i
            && !fixed_j
            && position != pi
            && position != pj
            && self.exact_flat_borders
            // A virtual edge joins separate parts (W §4.1): no region's
            // border to keep between them.
            && !c.edges[e as usize].is_virtual()
            && flat.flat_pair(c, i, j)
            // A collapse that only deletes faces (a lone triangle going
            // to an edge) keeps no border: where its leftover edge lies
            // matters only to the merges after it.
            && c
                .star_faces_iter(i, j)
                .any(|f| !crate::terms::guards::vanishes(c.face(f), i, j))
        {
            match (bi, bj) {
                (true, false) => pi,
                (false, true) => pj,
                // Two border vertices join only along their border (as
                // meshoptimizer's border vertices do): a chord across the
                // region would fold or cover its faces twice.
                _ if !s.a.contains(&j) => return None,
                _ if ranked.eval(pi) <= ranked.eval(pj) => pi,
                _ => pj,
            }
        } else {
            position
        };
        // A fixed endpoint's collapse is ranked by the whole quadric, as
        // the solve cannot set the regularization aside there.
        let mut cost = if fixed_i || fixed_j {
            geometry.eval(position)
        } else {
            ranked.eval(position)
        }
        .max(0.0);
        // The present faces rank the collapse too, at the position the
        // memory chose (see `terms/current_faces.rs`).
        if self.metric.current_face_weight > 0.0 {
            cost += current_face_cost(c, i, j, position, self.metric.current_face_weight);
        }
        // Knodt Eq. 5: what the collapse adds to the error the endpoints
        // already carry. Never negative: the quadric sum at the optimum is
        // at least each part's own minimum (up to rounding).
        if self.metric.introduced_error {
            // What the endpoints carry, measured as the cost is: without
            // the regularization unless it ranks.
            let carried = |v: u32, qv: &Quadric, p: DVec3| match reg.get(v as usize) {
                Some(rv) if !self.metric.regularized_choice => qv.minus(&rv.quadric()).eval(p),
                _ => qv.eval(p),
            };
            cost = (cost - carried(i, &qi, pi) - carried(j, &qj, pj)).max(0.0);
        }
        if let Some(app) = &appearance {
            // Appearance steers within the file's geometric error budget:
            // it may lift a collapse's rank up to the budget, never beyond
            // (see `CostModel::appearance_budget`).
            let mut looks = app.eval(position).max(0.0);
            if let (Some(r), true) = (&r, self.regularization_looks) {
                looks += r.eval(position).max(0.0);
            }
            let ceiling = self
                .appearance_budget
                .max(self.invisible_cost(qi.weight + qj.weight));
            cost = (cost + looks).min(cost.max(ceiling));
        }
        let cost = floored(cost, qi.weight + qj.weight, self.area_floor);
        if !cost.is_finite() {
            return None;
        }
        Some(Evaluation { cost, position })
    }
}

/// A mean distance to its planes, relative to the unit diagonal, below
/// which the planes hold a vertex exactly for the joint placement: ten
/// times the rounding of f32 coordinates (about 1e-7 of the diagonal), so
/// planes computed from f32 input count as exact where they agree.
const HELD: f64 = 1e-6;

/// Where the planes cannot tell placements apart (around a flat region or
/// along a straight crease every point of a plane or a line costs the
/// same), the endpoint that costs no more than `at` to rounding (a mean
/// squared distance of 1e-18 of the unit diagonal per unit of `weight`),
/// else `at`. An output vertex left where an input vertex was keeps every
/// later collapse there exact; a point the solve picked inside the free
/// directions is on the planes but not necessarily where the next
/// collapse's planes meet.
fn endpoint_if_as_good(q: &Quadric, at: DVec3, pi: DVec3, pj: DVec3, weight: f64) -> DVec3 {
    const EXACT: f64 = 1e-9;
    let (ei, ej) = (q.eval(pi), q.eval(pj));
    let (end, e) = if ei <= ej { (pi, ei) } else { (pj, ej) };
    if e <= q.eval(at).max(0.0) + weight * EXACT * EXACT {
        end
    } else {
        at
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cost model of `metric` alone: no area floor, borders free,
    /// attributes not moving vertices.
    fn model_of(metric: Metric) -> CostModel {
        CostModel {
            terms: crate::terms::collapse_terms(&metric),
            area_floor: 0.0,
            attributes_move_vertices: false,
            attribute_slack: f64::INFINITY,
            invisible_distance2: 0.0,
            exact_flat_borders: true,
            appearance_budget: f64::INFINITY,
            regularization_looks: false,
            metric,
            lock_borders: false,
        }
    }

    /// `q` as a run stores it, each about its vertex.
    fn stored(c: &Complex, q: &[Quadric]) -> Vec<StoredQuadric> {
        q.iter()
            .zip(&c.pos)
            .map(|(q, &p)| StoredQuadric::new(q, p))
            .collect()
    }

    #[test]
    fn an_endpoint_as_cheap_as_the_solve_is_kept() {
        // One plane, z = 0, weight 2: every point of it costs 0, so the
        // solve's point (here (0.5, 0.3, 0)) and the endpoints tie, and
        // the cheaper endpoint, i, stays where it was.
        let flat = Quadric::plane(DVec3::Z, DVec3::ZERO, 2.0);
        let (pi, pj) = (DVec3::ZERO, DVec3::new(1.0, 0.0, 0.0));
        let free = DVec3::new(0.5, 0.3, 0.0);
        assert_eq!(endpoint_if_as_good(&flat, free, pi, pj, 2.0), pi);
        // Off the plane by 1e-6 the endpoint costs 2·1e-12, far above the
        // tolerance (2·1e-18): the solve's point is kept.
        let lifted = DVec3::new(0.0, 0.0, 1e-6);
        assert_eq!(
            endpoint_if_as_good(&flat, free, lifted, pj + lifted, 2.0),
            free
        );
        // Planes x = 0.5 and z = 0 meet on a line through the edge's
        // middle: both endpoints cost 2·0.25 = 0.5 more than the solve.
        let crease = flat + Quadric::plane(DVec3::X, DVec3::new(0.5, 0.0, 0.0), 2.0);
        assert_eq!(endpoint_if_as_good(&crease, free, pi, pj, 4.0), free);
        // j cheaper than i: j is the endpoint taken.
        let near_j = Quadric::plane(DVec3::X, DVec3::new(1.0, 0.0, 0.0), 1.0);
        let at = DVec3::new(1.0, 5.0, 0.0);
        assert_eq!(endpoint_if_as_good(&near_j, at, pi, pj, 1.0), pj);
    }

    #[test]
    fn area_floor_ranks_small_collapses_by_mean_squared_distance() {
        // Cost 2e-6 on weight 0.5 (mean squared distance 4e-6) under a
        // floor of 2: ranked as if the weight were 2, so 8e-6.
        assert_eq!(floored(2e-6, 0.5, 2.0), 8e-6);
        // At or above the floor, and for weightless terms, unchanged.
        assert_eq!(floored(2e-6, 2.0, 2.0), 2e-6);
        assert_eq!(floored(2e-6, 3.0, 2.0), 2e-6);
        assert_eq!(floored(2e-6, 0.0, 2.0), 2e-6);
        assert_eq!(floored(2e-6, 0.5, 0.0), 2e-6);
    }

    /// A fan of six triangles around vertex 0 (near the origin) with its
    /// rim at height `rim`, vertex 0 on the bowl z = `rim` · r², and per
    /// corner a scalar attribute that is far from linear (4x³).
    fn fan_with_cubic_attribute(rim: f64) -> (Complex, Vec<u32>, Vec<f32>) {
        let mut pos = vec![DVec3::new(0.05, 0.02, 0.0)];
        for k in 0..6 {
            let a = k as f64 * std::f64::consts::PI / 3.0;
            pos.push(DVec3::new(a.cos(), a.sin(), rim));
        }
        pos[0].z = rim * (pos[0].x * pos[0].x + pos[0].y * pos[0].y);
        let mut idx = Vec::new();
        for k in 0..6u32 {
            idx.extend_from_slice(&[0, 1 + k, 1 + (k + 1) % 6]);
        }
        let offsets: Vec<u32> = (0..=6).map(|f| 3 * f).collect();
        let (c, _) = Complex::new(pos.clone(), &offsets, &idx);
        let values: Vec<f32> = idx
            .iter()
            .map(|&v| (pos[v as usize].x.powi(3) * 4.0) as f32)
            .collect();
        (c, idx, values)
    }

    /// Collapsing edge 0–1 of [`fan_with_cubic_attribute`] under
    /// `slack` and `invisible` (a distance), evaluated three ways: by the
    /// surface alone, with the attribute stream steering but the vertex
    /// placed by the surface, and with joint placement.
    fn on_fan(rim: f64, slack: f64, invisible: f64) -> [Evaluation; 3] {
        let (c, idx, values) = fan_with_cubic_attribute(rim);
        let corners: Vec<u32> = (0..idx.len() as u32).collect();
        let input = crate::AttributeInput {
            streams: vec![crate::AttributeStream {
                components: 1,
                values: &values,
                indices: &corners,
                weight: 1.0,
                seams: false,
                kind: crate::StreamKind::Generic,
            }],
            ..Default::default()
        };
        let attrs =
            AttributeState::new(&input, &idx, &c, &[], crate::SeamPolicy::Penalize, 1.0).unwrap();
        let metric = Metric {
            regularization: 0.0,
            ..Metric::default()
        };
        let q = vertex_quadrics(&c, &metric, &[], EdgeImportance::default());
        let border = vec![true; c.pos.len()];
        let e = (0..c.edges.len() as u32)
            .find(|&e| {
                c.edges[e as usize].ends.contains(&0) && c.edges[e as usize].ends.contains(&1)
            })
            .unwrap();
        let eval = |joint, a: Option<&AttributeState>| {
            CostModel {
                attributes_move_vertices: joint,
                attribute_slack: slack,
                invisible_distance2: invisible * invisible,
                ..model_of(metric)
            }
            .evaluate(
                &c,
                &stored(&c, &q),
                &[],
                &border,
                &[],
                &[],
                &FlatStars::default(),
                a,
                e,
                &mut Scratch::default(),
            )
            .unwrap()
        };
        [
            eval(false, None),
            eval(false, Some(&attrs)),
            eval(true, Some(&attrs)),
        ]
    }

    #[test]
    fn off_flat_ground_the_invisible_allowance_lets_attributes_move_the_vertex() {
        // On the bowl the planes do not hold the collapse's point: with no
        // slack, the allowance alone lets the attribute pull the vertex
        // off the surface's own point; without it the vertex stays. (Where
        // the planes do hold it, `tests/defaults.rs`'s box of flat panels
        // checks that it stays on them: on a single flat fan the joint
        // point never leaves the plane, allowance or not.)
        let [surface, _, joint] = on_fan(1.0, 0.0, 0.1);
        assert!(
            joint.position.distance(surface.position) > 1e-6,
            "{joint:?}"
        );
        let [surface, _, joint] = on_fan(1.0, 0.0, 0.0);
        assert_eq!(joint.position, surface.position);
    }

    #[test]
    fn attributes_rank_collapses_but_do_not_move_the_vertex_unless_asked() {
        // A fan of six triangles around vertex 0 on a bowl (z = r²), with
        // a scalar attribute that is far from linear (x³): the joint
        // minimum trades surface for attribute fit and leaves the
        // geometric one. No slack bound and no allowance: Hoppe's joint
        // placement as written.
        let [surface, fitted, joint] = on_fan(1.0, f64::INFINITY, 0.0);
        // By default the vertex goes where the surface alone puts it, and
        // the attribute error it causes there is added to the cost.
        assert_eq!(fitted.position, surface.position);
        assert!(fitted.cost > surface.cost, "{fitted:?} {surface:?}");
        // Jointly minimized, the attribute pulls it elsewhere, for a lower
        // total cost.
        assert!(
            joint.position.distance(surface.position) > 1e-6,
            "{joint:?}"
        );
        assert!(joint.cost <= fitted.cost, "{joint:?} {fitted:?}");
    }

    #[test]
    fn plane_weight_interpolates_between_area_and_uniform() {
        // A face of area 4 on a mesh of mean face area 1.
        assert_eq!(plane_weight(4.0, 1.0, 1.0, 0.0), 4.0);
        assert_eq!(plane_weight(4.0, 1.0, 0.5, 0.0), 2.0);
        assert_eq!(plane_weight(4.0, 1.0, 0.0, 0.0), 1.0);
        // The mean face keeps its weight whatever the exponent.
        assert_eq!(plane_weight(3.0, 3.0, 0.25, 0.0), 3.0);
        // The lift raises small faces only: with a lift of 1, a face of
        // area 0.2 weighs 1, one of area 4 keeps its area.
        assert_eq!(plane_weight(0.2, 2.0, 1.0, 1.0), 1.0);
        assert_eq!(plane_weight(4.0, 2.0, 1.0, 1.0), 4.0);
    }

    #[test]
    fn uniform_plane_weights_give_every_face_the_mean_area() {
        // Two triangles sharing vertex 0: areas 1/2 and 2 (mean 5/4). With
        // exponent 0 each plane weighs 5/4, shared by 3 corners: vertex 0
        // carries 2 · 5/12 of weight; with exponent 1, (1/2 + 2) / 3.
        let pos = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(-2.0, 0.0, 0.0),
            DVec3::new(0.0, -2.0, 0.0),
        ];
        let c = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 0, 3, 4]).0;
        let weigh = |exponent, floor| {
            let metric = Metric {
                regularization: 0.0,
                border_weight: 0.0,
                area_exponent: exponent,
                face_weight_floor: floor,
                ..Metric::default()
            };
            vertex_quadrics(&c, &metric, &[], EdgeImportance::default())[0].weight
        };
        let w = weigh(1.0, 0.0);
        assert!((w - 2.5 / 3.0).abs() < 1e-9, "{w}");
        let w = weigh(0.0, 0.0);
        assert!((w - 2.0 * 1.25 / 3.0).abs() < 1e-9, "{w}");
        // A floor of the mean lifts the small face (1/2) to 5/4 and leaves
        // the large one (2): (5/4 + 2) / 3.
        let w = weigh(1.0, 1.0);
        assert!((w - 3.25 / 3.0).abs() < 1e-9, "{w}");
        // Apart, each triangle is a part too small for a budget of two
        // triangles (a closed part needs four): nothing is lifted, so small
        // parts still go first.
        let pos = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(5.0, -2.0, 0.0),
        ];
        let apart = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 3, 4, 5]).0;
        let metric = Metric {
            regularization: 0.0,
            border_weight: 0.0,
            face_weight_floor: 1.0,
            ..Metric::default()
        };
        let weights = |budget| {
            let keep = |_, q| q;
            vertex_quadric_terms(
                &apart,
                &metric,
                &[],
                EdgeImportance::default(),
                budget,
                &[],
                keep,
            )
            .0
        };
        let q = weights(2);
        assert!((q[0].weight - 0.5 / 3.0).abs() < 1e-12, "{}", q[0].weight);
        assert!((q[3].weight - 2.0 / 3.0).abs() < 1e-12, "{}", q[3].weight);
        // With room for both (a budget of 40: the small one gets 8), the
        // small triangle is lifted to the mean, 5/4.
        let q = weights(40);
        assert!((q[0].weight - 1.25 / 3.0).abs() < 1e-12, "{}", q[0].weight);
        assert!((q[3].weight - 2.0 / 3.0).abs() < 1e-12, "{}", q[3].weight);
    }
    /// Two triangles folded along the x axis (a "hinge"):
    /// ```text
    ///   2 (0,1,0)
    ///   |\
    ///   0--1   (0,0,0)–(1,0,0)
    ///   |/
    ///   3 (0,0,1)  -- in the xz plane
    /// ```
    fn hinge() -> Complex {
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 0, 3]).0
    }

    #[test]
    fn vertex_quadric_is_area_share_of_face_planes() {
        let c = hinge();
        // Face planes alone: the hinge's fold is also a crease.
        let m = Metric {
            regularization: 0.0,
            border_weight: 0.0,
            crease_weight: 0.0,
            ..Metric::default()
        };
        let q = vertex_quadrics(&c, &m, &[], EdgeImportance::default());
        // Vertex 2 is only in face 0 (plane z = 0, area 1/2): share 1/6.
        // At (0,0,3): 1/6 · 9 = 1.5.
        assert!((q[2].eval(DVec3::new(0.0, 0.0, 3.0)) - 1.5).abs() < 1e-12);
        // Vertex 0 is in both: at (0, 2, 3): 1/6 · 9 + 1/6 · 4.
        assert!((q[0].eval(DVec3::new(0.0, 2.0, 3.0)) - 13.0 / 6.0).abs() < 1e-12);
        assert!((q[0].weight - 1.0 / 3.0).abs() < 1e-15);
        // Weights scale the quadric.
        let qw = vertex_quadrics(&c, &m, &[2.0, 1.0, 1.0, 1.0], EdgeImportance::default());
        assert!((qw[0].eval(DVec3::new(0.0, 2.0, 3.0)) - 13.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn polygon_planes_are_those_of_the_fan_it_is_drawn_with() {
        let m = Metric {
            regularization: 0.0,
            border_weight: 0.0,
            crease_weight: 0.0,
            ..Metric::default()
        };
        // The unit square, drawn as (0,1,2) and (0,2,3), area 1/2 each:
        // the corners on the diagonal take a third of both, the others a
        // third of one (1/3, 1/6, 1/3, 1/6), all of the plane z = 0.
        let square = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let (c, _) = Complex::new(square, &[0, 4], &[0, 1, 2, 3]);
        let q = vertex_quadrics(&c, &m, &[], EdgeImportance::default());
        for (v, share) in [1.0 / 3.0, 1.0 / 6.0, 1.0 / 3.0, 1.0 / 6.0]
            .into_iter()
            .enumerate()
        {
            assert!((q[v].weight - share).abs() < 1e-15, "corner {v}");
            assert!((q[v].eval(DVec3::new(0.3, 0.7, 2.0)) - 4.0 * share).abs() < 1e-12);
        }
        // Warped: corner 2 lifted to (1,1,1). Drawn as (0,1,2), normal
        // (0,-1,1)/√2, and (0,2,3), normal (-1,0,1)/√2, both through the
        // origin, each of area √2/2; the face weighs its Newell area
        // |(-1,-1,2)|/2 = √6/2, so the fan (area √2) is scaled by √3/2.
        let warped = vec![DVec3::ZERO, DVec3::X, DVec3::ONE, DVec3::Y];
        let (c, _) = Complex::new(warped.clone(), &[0, 4], &[0, 1, 2, 3]);
        let q = vertex_quadrics(&c, &m, &[], EdgeImportance::default());
        // Every corner lies on every plane it holds: no error where it is
        // (on the Newell plane, normal (-1,-1,2)/√6 through the centroid,
        // every corner was 1/(2√6) away).
        for (v, p) in warped.iter().enumerate() {
            assert!(q[v].eval(*p).abs() < 1e-15, "corner {v}: {}", q[v].eval(*p));
        }
        // Corner 1 holds only the plane of (0,1,2), a third of
        // (√2/2)·(√3/2) = √6/4: weight √6/12. At corner 3, (0,1,0), that
        // plane is 1/√2 away: √6/24.
        let r6 = 6f64.sqrt();
        assert!((q[1].weight - r6 / 12.0).abs() < 1e-15);
        assert!((q[1].eval(DVec3::Y) - r6 / 24.0).abs() < 1e-15);
        // The shares add up to the face's area.
        let total: f64 = q.iter().map(|q| q.weight).sum();
        assert!((total - r6 / 2.0).abs() < 1e-15);
        // Listed from corner 1, the quad is drawn across the other
        // diagonal, (1,2,3) and (1,3,0): corner 0 now holds only z = 0.
        let (turned, _) = Complex::new(warped, &[0, 4], &[1, 2, 3, 0]);
        let t = vertex_quadrics(&turned, &m, &[], EdgeImportance::default());
        let w0 = t[0].weight;
        assert!((t[0].eval(DVec3::new(0.4, -3.0, 2.0)) - 4.0 * w0).abs() < 1e-12);
    }

    #[test]
    fn median_collapse_deviation_is_a_distance_that_shrinks_as_h_squared() {
        // The planes alone (the regularization's travel cost would count
        // on a flat grid too).
        let m = Metric {
            regularization: 0.0,
            ..Metric::default()
        };
        let deviation = |mesh: &wildlod_mesh::Mesh, scale: f64| {
            let pos: Vec<DVec3> = mesh
                .positions
                .iter()
                .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) * scale)
                .collect();
            let (c, _) = Complex::new(pos, &mesh.faces.offsets, &mesh.faces.indices);
            let q = vertex_quadrics(&c, &m, &[], EdgeImportance::default());
            median_collapse_deviation(&c, &stored(&c, &q))
        };
        // A flat grid: every side collapses onto its plane.
        let flat = wildlod_mesh::shapes::quad_grid(8, 8);
        assert!(deviation(&flat, 1.0) < 1e-9, "{}", deviation(&flat, 1.0));
        // On a sphere, a distance: twice the size, twice the deviation.
        let coarse = wildlod_mesh::shapes::quad_sphere(8);
        let d = deviation(&coarse, 1.0);
        assert!(d > 0.0);
        assert!((deviation(&coarse, 2.0) / d - 2.0).abs() < 1e-6);
        // Twice as fine (h halved): about a quarter (κh²/8).
        let fine = wildlod_mesh::shapes::quad_sphere(16);
        let ratio = deviation(&fine, 1.0) / d;
        assert!((0.2..0.3).contains(&ratio), "{ratio}");
    }

    #[test]
    fn quadrics_without_star_lists_are_the_same_to_the_bit() {
        // A fan of five triangles and a quad around vertex 0, bumpy.
        let mut pos = vec![DVec3::ZERO];
        for k in 0..7 {
            let a = k as f64;
            pos.push(DVec3::new(a.cos(), a.sin(), 0.1 * (a * 3.0).sin()));
        }
        let idx = [0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 7, 1];
        let offsets = [0, 3, 6, 9, 12, 15, 19];
        let (with, _) = Complex::new(pos.clone(), &offsets, &idx);
        let (without, _) = Complex::faces_only(pos, &offsets, &idx);
        assert!(with.has_adjacency() && !without.has_adjacency());
        let m = Metric::default();
        let a = vertex_quadrics(&with, &m, &[], EdgeImportance::default());
        let b = vertex_quadrics(&without, &m, &[], EdgeImportance::default());
        assert_eq!(a, b);
        assert!(a[0].weight > 0.0);
    }

    #[test]
    fn boundary_area_term_is_absent_without_boundary_edges() {
        // A closed tetrahedron: the metric is the plain quadric sum.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let (c, _) = Complex::new(
            pos,
            &[0, 3, 6, 9, 12],
            &[0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
        );
        let metric = Metric::default();
        let q = vertex_quadrics(&c, &metric, &[], EdgeImportance::default());
        let with = model_of(metric);
        let without = model_of(Metric {
            boundary_area: false,
            ..metric
        });
        let mut s = Scratch::default();
        for e in 0..c.edges.len() as u32 {
            assert_eq!(
                with.evaluate(
                    &c,
                    &stored(&c, &q),
                    &[],
                    &[],
                    &[],
                    &[],
                    &FlatStars::default(),
                    None,
                    e,
                    &mut s
                ),
                without.evaluate(
                    &c,
                    &stored(&c, &q),
                    &[],
                    &[],
                    &[],
                    &[],
                    &FlatStars::default(),
                    None,
                    e,
                    &mut s
                )
            );
        }
    }

    #[test]
    fn boundary_area_term_penalizes_moving_a_border_vertex_off_its_line() {
        // Hinge edge (0, 2) is a boundary edge; so are 1-2, 0-3, 1-3.
        let c = hinge();
        let metric = Metric {
            regularization: 0.0,
            ..Metric::default()
        };
        let q = vertex_quadrics(&c, &metric, &[], EdgeImportance::default());
        let m = model_of(metric);
        let mut s = Scratch::default();
        let e = c.edge_between(0, 2).unwrap();
        let ev = m
            .evaluate(
                &c,
                &stored(&c, &q),
                &[],
                &[],
                &[],
                &[],
                &FlatStars::default(),
                None,
                e,
                &mut s,
            )
            .unwrap();
        let plain = model_of(Metric {
            boundary_area: false,
            ..metric
        })
        .evaluate(
            &c,
            &stored(&c, &q),
            &[],
            &[],
            &[],
            &[],
            &FlatStars::default(),
            None,
            e,
            &mut s,
        )
        .unwrap();
        assert!(ev.cost > plain.cost, "{ev:?} vs {plain:?}");
    }

    #[test]
    fn introduced_error_subtracts_what_the_endpoints_already_carry() {
        // Knodt Eq. 5 on the two-quad hinge: quads (0,1,2,3) in z = 0 and
        // (1,0,5,4) in y = 0, sharing the x axis from 0 to 1.
        let c = crate::terms::tangent::tests::hinge();
        let base = Metric {
            regularization: 0.0,
            boundary_area: false,
            ..Metric::default()
        };
        let mut q = vertex_quadrics(&c, &base, &[], EdgeImportance::default());
        // Give vertex 2 a history: as if an earlier collapse had left it
        // 0.5 above its plane, Q2(p2) = (1/4)·0.25 with the z = 0 plane at
        // weight 1/4 (quad area 1 over 4 corners).
        let p2 = c.pos[2];
        assert!((q[2].eval(p2)).abs() < 1e-15);
        q[2] += Quadric::plane(DVec3::Z, p2 + DVec3::new(0.0, 0.0, 0.5), 0.25);
        let carried = q[2].eval(p2);
        assert!((carried - 0.0625).abs() < 1e-15);
        let e = c.edge_between(1, 2).unwrap();
        let sq = stored(&c, &q);
        let eval = |metric: Metric| {
            model_of(metric)
                .evaluate(
                    &c,
                    &sq,
                    &[],
                    &[],
                    &[],
                    &[],
                    &FlatStars::default(),
                    None,
                    e,
                    &mut Scratch::default(),
                )
                .unwrap()
        };
        let plain = eval(base);
        let eq5 = eval(Metric {
            introduced_error: true,
            ..base
        });
        // Same placement; the cost drops by exactly Q1(p1) + Q2(p2) = 0 + 1/16.
        assert_eq!(plain.position, eq5.position);
        assert!(
            (plain.cost - eq5.cost - carried).abs() < 1e-12,
            "{} {}",
            plain.cost,
            eq5.cost
        );
    }

    #[test]
    fn gluing_charges_area_times_squared_travel_across_a_virtual_edge() {
        // Two right triangles of area 3/2 in the plane z = 0, apart along
        // x; a virtual edge joins vertex 1 (1,0,0) and vertex 3 (3,0,0).
        let pos = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.0, 3.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(3.0, 3.0, 0.0),
        ];
        let (mut c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 3, 4, 5]);
        c.add_edge(1, 3);
        let e = c.edge_between(1, 3).unwrap();
        let metric = Metric {
            regularization: 0.0,
            boundary_area: false,
            border_weight: 0.0,
            gluing_weight: 2.0,
            ..Metric::default()
        };
        let q = stored(
            &c,
            &vertex_quadrics(&c, &metric, &[], EdgeImportance::default()),
        );
        let m = model_of(metric);
        let mut s = Scratch::default();
        let ev = m
            .evaluate(
                &c,
                &q,
                &[],
                &[],
                &[],
                &[],
                &FlatStars::default(),
                None,
                e,
                &mut s,
            )
            .unwrap();
        // Each vertex has area share 1/2 and lies in z = 0: the planes are
        // indifferent within the plane, the gluing term 2·(1/2)·|x−p|² per
        // endpoint is least at the midpoint (2, 0, 0): 2·(1/2)·(1 + 1).
        assert!(ev.position.distance(DVec3::new(2.0, 0.0, 0.0)) < 1e-9);
        assert!((ev.cost - 2.0).abs() < 1e-9, "{}", ev.cost);
        // Without the term the collapse is free.
        let free = model_of(Metric {
            gluing_weight: 0.0,
            ..metric
        });
        let ev = free
            .evaluate(
                &c,
                &q,
                &[],
                &[],
                &[],
                &[],
                &FlatStars::default(),
                None,
                e,
                &mut s,
            )
            .unwrap();
        assert!(ev.cost < 1e-12);
    }

    #[test]
    fn flat_borders_are_kept_for_faces_that_stay_not_for_a_vanishing_triangle() {
        let place = |pos: Vec<DVec3>, offsets: &[u32], indices: &[u32], exact: bool| {
            let (c, _) = Complex::new(pos, offsets, indices);
            let metric = Metric::default();
            let q = stored(
                &c,
                &vertex_quadrics(&c, &metric, &[], EdgeImportance::default()),
            );
            let m = CostModel {
                exact_flat_borders: exact,
                ..model_of(metric)
            };
            let e = c.edge_between(0, 1).unwrap();
            m.evaluate(
                &c,
                &q,
                &[],
                &[],
                &[],
                &[],
                &FlatStars::default(),
                None,
                e,
                &mut Scratch::default(),
            )
            .map(|ev| ev.position)
        };
        let (p0, p1) = (DVec3::ZERO, DVec3::X);
        // A lone triangle: collapsing its side 0–1 deletes it, no face of
        // the region is left to keep inside a border, and the placement is
        // the free one, strictly between the endpoints (the border planes
        // of the three sides pull it inward).
        let lone = vec![p0, p1, DVec3::Y];
        let free = place(lone.clone(), &[0, 3], &[0, 1, 2], false).unwrap();
        assert!(
            free.distance(p0) > 1e-3 && free.distance(p1) > 1e-3,
            "{free}"
        );
        let ruled = place(lone, &[0, 3], &[0, 1, 2], true).unwrap();
        assert!(ruled.distance(free) < 1e-12, "{ruled} {free}");
        // A square of two: the triangle (1, 3, 2) stays, so the border
        // vertices 0 and 1 join at one of them, never between.
        let square = vec![p0, p1, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        let at = place(square, &[0, 3, 6], &[0, 1, 2, 1, 3, 2], true).unwrap();
        assert!(at == p0 || at == p1, "{at}");
    }

    #[test]
    fn locked_borders_refuse_border_to_border_collapses() {
        let c = hinge();
        let q = vertex_quadrics(&c, &Metric::default(), &[], EdgeImportance::default());
        let m = CostModel {
            terms: crate::terms::collapse_terms(&Metric::default()),
            area_floor: 0.0,
            attributes_move_vertices: false,
            attribute_slack: f64::INFINITY,
            invisible_distance2: 0.0,
            exact_flat_borders: true,
            appearance_budget: f64::INFINITY,
            regularization_looks: false,
            metric: Metric::default(),
            lock_borders: true,
        };
        let mut s = Scratch::default();
        // Every vertex of the hinge is on the border.
        for e in 0..c.edges.len() as u32 {
            assert_eq!(
                m.evaluate(
                    &c,
                    &stored(&c, &q),
                    &[],
                    &[],
                    &[],
                    &[],
                    &FlatStars::default(),
                    None,
                    e,
                    &mut s
                ),
                None
            );
        }
    }

    #[test]
    fn crease_planes_hold_a_sharp_side_from_both_faces() {
        // Two triangles sharing the side 0–1 along x, one in z = 0 (normal
        // +z), one in y = 0 folded down (normal −y): a 90° crease.
        // ```text
        //   2 (0,1,0)        3 (0,0,-1)
        //   |  \             |  \
        //   0 -- 1 (1,0,0)   0 -- 1
        // ```
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, -1.0)];
        let (c, _) = Complex::new(pos.clone(), &[0, 3, 6], &[0, 1, 2, 1, 0, 3]);
        let planes: Vec<_> = (0..2).map(|f| face_plane(&c, f)).collect();
        // Crease planes only (no border weight): through the side,
        // orthogonal to each face, so y = 0 and z = 0, each weighing
        // 3 · |side|² = 3 at both ends. At (0.5, 0.5, 0.3) from vertex 0:
        // 3 · 0.25 + 3 · 0.09 = 1.02.
        let b = border_planes(&c, &planes, 0.0, 3.0, 0.2);
        let p = DVec3::new(0.5, 0.5, 0.3);
        assert!(
            (b.at(0).eval(p) - 1.02).abs() < 1e-12,
            "{}",
            b.at(0).eval(p)
        );
        assert!((b.at(1).eval(p) - 1.02).abs() < 1e-12);
        // Sliding along the crease is free; the far corners get nothing.
        assert!(b.at(0).eval(DVec3::new(7.0, 0.0, 0.0)).abs() < 1e-12);
        assert_eq!(b.at(2).eval(p), 0.0);
        assert_eq!(b.at(0).weight, 0.0);
        // Below the angle (90° is not above 95°) there is no crease.
        let blunt = border_planes(&c, &planes, 0.0, 3.0, 95f64.to_radians().cos());
        assert_eq!(blunt.at(0).eval(p), 0.0);
        // A flat pair is no crease, even with one face wound the other
        // way (a wild mesh's flipped face): its normal turns by 180°, the
        // surface by nothing.
        let mut flat = pos;
        flat[3] = DVec3::new(0.0, -1.0, 0.0);
        for idx in [[0, 1, 2, 1, 0, 3], [0, 1, 2, 0, 1, 3]] {
            let (c, _) = Complex::new(flat.clone(), &[0, 3, 6], &idx);
            let planes: Vec<_> = (0..2).map(|f| face_plane(&c, f)).collect();
            let b = border_planes(&c, &planes, 0.0, 3.0, 0.2);
            assert_eq!(b.at(0).eval(p), 0.0, "{idx:?}");
        }
    }

    #[test]
    fn crease_neighbors_are_the_sharp_sides_of_the_current_mesh() {
        // The 90° fold of the test above: side 0–1 is a crease, seen from
        // both its ends; the other sides have one face each.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, -1.0)];
        let at = |pos: &[DVec3], idx: &[u32], v: u32, cos: f64| {
            let (c, _) = Complex::new(pos.to_vec(), &[0, 3, 6], idx);
            let mut out = Vec::new();
            c.crease_neighbors(v, cos, &mut out);
            out
        };
        let fold = [0, 1, 2, 1, 0, 3];
        assert_eq!(at(&pos, &fold, 0, 0.2), vec![1]);
        assert_eq!(at(&pos, &fold, 1, 0.2), vec![0]);
        assert!(at(&pos, &fold, 2, 0.2).is_empty());
        // Below the angle (90° is not above 95°): none.
        assert!(at(&pos, &fold, 0, 95f64.to_radians().cos()).is_empty());
        // Folded by 60° only: none at 78°.
        let mut blunt = pos.clone();
        blunt[3] = DVec3::new(0.0, -0.5, -0.75f64.sqrt());
        assert!(at(&blunt, &fold, 0, 0.2).is_empty());
        // Flat, wound either way: none (a flipped face's normal turns by
        // 180°, the surface by nothing).
        let mut flat = pos;
        flat[3] = DVec3::new(0.0, -1.0, 0.0);
        assert!(at(&flat, &fold, 0, 0.2).is_empty());
        assert!(at(&flat, &[0, 1, 2, 0, 1, 3], 0, 0.2).is_empty());
        // The flipped face on the fold: still the 90° crease.
        let mut flipped_fold = flat.clone();
        flipped_fold[3] = DVec3::new(0.0, 0.0, -1.0);
        assert_eq!(at(&flipped_fold, &[0, 1, 2, 0, 1, 3], 0, 0.2), vec![1]);
    }

    #[test]
    fn crease_area_term_charges_the_area_swept_against_a_crease_side() {
        // The 90° fold again, vertex 2 locked: collapsing 0–2 puts the
        // vertex at 2 = (0, 1, 0). Vertex 0 is on the crease 0–1 (along
        // x), so the term adds ½·|(p − p0) × (p1 − p0)|² = ½·|Y × X|² = ½
        // (twice the squared area of the triangle it sweeps), times the
        // border term's weight 1 and the crease weight 1.
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, -1.0)];
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 1, 0, 3]);
        let metric = Metric::default();
        let q = stored(
            &c,
            &vertex_quadrics(&c, &metric, &[], EdgeImportance::default()),
        );
        let m = model_of(metric);
        let e = c.edge_between(0, 2).unwrap();
        let locked = [false, false, true, false];
        let mut s = Scratch::default();
        let mut eval = |crease: &[bool]| {
            m.evaluate(
                &c,
                &q,
                &[],
                &[],
                crease,
                &locked,
                &FlatStars::default(),
                None,
                e,
                &mut s,
            )
            .unwrap()
        };
        let without = eval(&[false; 4]);
        let with = eval(&[true, false, false, false]);
        assert_eq!(with.position, DVec3::Y);
        assert!(
            (with.cost - without.cost - 0.5).abs() < 1e-12,
            "{with:?} {without:?}"
        );
        // Weight 0: no term, whatever the flags.
        let off_metric = Metric {
            crease_area_weight: 0.0,
            ..metric
        };
        let off = CostModel {
            terms: crate::terms::collapse_terms(&off_metric),
            metric: off_metric,
            ..m
        };
        let flagged = [true, false, false, false];
        let ev = off
            .evaluate(
                &c,
                &q,
                &[],
                &[],
                &flagged,
                &locked,
                &FlatStars::default(),
                None,
                e,
                &mut s,
            )
            .unwrap();
        assert_eq!(ev.cost, without.cost);
    }

    #[test]
    fn border_planes_stand_on_border_sides_orthogonal_to_their_face() {
        // Two triangles of the unit square in z = 0, sharing the diagonal
        // 0–2; the four sides of the square are border sides:
        // ```text
        //   3 (0,1) -- 2 (1,1)
        //   |       /  |
        //   0 (0,0) -- 1 (1,0)
        // ```
        let pos = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let (c, _) = Complex::new(pos, &[0, 3, 6], &[0, 1, 2, 0, 2, 3]);
        let planes: Vec<_> = (0..2).map(|f| face_plane(&c, f)).collect();
        let b = border_planes(&c, &planes, 2.0, 0.0, -1.0);
        // Vertex 0 is on sides 0–1 (plane y = 0) and 3–0 (plane x = 0),
        // each of length 1, weight 2 · 1²: at (0.5, 3, 7),
        // 2 · 3² + 2 · 0.5² = 18.5; the face's own direction (z) is free.
        assert!((b.at(0).eval(DVec3::new(0.5, 3.0, 7.0)) - 18.5).abs() < 1e-12);
        // Vertex 1: sides 0–1 (y = 0) and 1–2 (x = 1): at (0.5, 3, 0),
        // 2 · 9 + 2 · 0.25.
        assert!((b.at(1).eval(DVec3::new(0.5, 3.0, 0.0)) - 18.5).abs() < 1e-12);
        // The shared diagonal adds nothing: on the square's corners the
        // planes vanish, and they carry no area.
        for (v, p) in c.pos.iter().enumerate() {
            assert!(b.at(v).eval(*p).abs() < 1e-12);
            assert_eq!(b.at(v).weight, 0.0);
        }
        // Anywhere on the diagonal line beyond the square, only the two
        // border planes of vertex 0 see it: at (2, 2, 0), 2·4 + 2·4.
        assert!((b.at(0).eval(DVec3::new(2.0, 2.0, 0.0)) - 16.0).abs() < 1e-12);
    }
}
