//! `compare`: the geometric and texture metrics of W §5 and Knodt 2024 §4
//! between a reference and a candidate surface.

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;
use wildlod_geometry::TriangleSet;
use wildlod_mesh::bounds::{OutlierRule, RobustBounds};

use crate::appearance::appearance;
use crate::eval_mesh::{EvalMesh, FaceCounts};
use crate::paired::Paired;
use crate::sampling::{chunk_count, chunk_len, AreaSampler, Side, Stream, CHUNK};

/// The default seed ("wildlod" in ASCII): fixed, so that two runs of the
/// same comparison agree bit for bit.
pub const DEFAULT_SEED: u64 = 0x0077_696c_646c_6f64;

/// How to compare.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompareOptions {
    /// Area-uniform sample points per surface for the distances. Default
    /// 100 000.
    pub samples: usize,
    /// Area-uniform sample points per surface for the texture and normal
    /// Chamfer distances. Default 40 000 (W §5 uses 10 000; at 40 000 the
    /// sampling floor is about half as high, so smaller differences
    /// between levels of detail can be told apart, and the numbers match
    /// the independent reference implementation the team ranks tools
    /// with).
    pub texture_samples: usize,
    /// Seed of every random choice. Default [`DEFAULT_SEED`].
    pub seed: u64,
    /// At most this many vertices per surface are added as sample points
    /// for the Hausdorff distance (an evenly strided subset above it).
    /// Default 1 000 000.
    pub max_vertex_samples: usize,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            samples: 100_000,
            texture_samples: 40_000,
            seed: DEFAULT_SEED,
            max_vertex_samples: 1_000_000,
        }
    }
}

/// The result of [`compare`]. Serialized with exactly these field names.
///
/// Distances are divided by the [`diagonal`] of the reference's bulk (W
/// Table 1 normalizes every mesh to a unit diagonal; the bulk leaves out
/// far outliers, see below), squared distances by its square. With
/// `d(p, S)` the Euclidean distance from point `p` to the closest point of
/// surface `S` (exact point-to-triangle distance):
///
/// - `hausdorff_ref_to_cand` = max over reference samples of `d(p, cand)`,
///   and the other way round; `hausdorff` is the larger of the two.
/// - `chamfer_mean_ref_to_cand` = mean over reference samples of
///   `d(p, cand)`; `chamfer_mean` averages the two directions.
/// - `chamfer_squared_ref_to_cand` = mean over reference samples of
///   `d(p, cand)²`; `chamfer_squared` averages the two directions. This is
///   the "mean squared Chamfer distance" of W Table 1.
///
/// Means are over the area-uniform samples, so they estimate the
/// area-weighted surface integrals; maxima are over those samples and every
/// vertex, so that spikes at vertices are not missed. A surface of zero
/// area (only degenerate triangles) is represented by its vertices for the
/// means too.
///
/// Each surface is sampled with its own random numbers. The metrics that
/// pair samples with samples (texture, normal and shading-normal Chamfer)
/// are never 0 between two samplings, even of one surface: each comes with
/// its *floor*, the same metric between the reference and a second,
/// independent sampling of the reference. A candidate within the floor of
/// the reference, or two candidates whose difference is smaller than it,
/// cannot be told apart at this sample count: read it as a tie.
///
/// Outliers: reference vertices farther from the bulk of its vertices than
/// [`wildlod_mesh::bounds`]'s rule allows (a terrain with three heights at
/// −1e30) would make a plain bounding box, and every error relative to it,
/// meaningless. When the reference has such outliers, the diagonal is that
/// of the box of its other vertices; vertices of either surface beyond the
/// same limit, and triangles with such a corner, are left out of the
/// measurement; and a sample whose nearest point on the other surface lies
/// on a left-out triangle is skipped too (there the other surface is the
/// outlier's spike, which says nothing of how well the bulk fits). The
/// counts say what was left out, and `outlier_vertices` names the first
/// reference outliers. Without reference outliers nothing is left out, and
/// a candidate's far-away vertex counts in full.
///
/// Empty surfaces: the distance from a non-empty surface to an empty one is
/// `+∞`, from an empty surface to anything 0 (there is nothing to measure),
/// so an empty candidate gives `+∞` for every symmetric distance, and two
/// empty surfaces give 0. No field is ever NaN. JSON has no infinity:
/// `serde_json` writes it as `null`, and `notes` says why.
///
/// [`diagonal`]: Comparison::diagonal
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// Bounding-box diagonal of the reference's bulk, in its units: the
    /// unit of every distance below. The plain bounding box's unless the
    /// reference has outliers. When it is 0 (an empty or single-point
    /// reference) distances are left in world units.
    pub diagonal: f64,
    /// Bounding-box diagonal of the whole reference, outliers included
    /// (equal to `diagonal` when there is none).
    pub diagonal_with_outliers: f64,
    /// Area samples per surface ([`CompareOptions::samples`]).
    pub samples: usize,
    /// Texture samples per surface ([`CompareOptions::texture_samples`]).
    pub texture_samples: usize,
    /// Vertices of the reference used as extra Hausdorff samples.
    pub vertex_samples_reference: usize,
    /// Vertices of the candidate used as extra Hausdorff samples.
    pub vertex_samples_candidate: usize,
    /// Seed of the sampling.
    pub seed: u64,
    /// Symmetric Hausdorff distance: the larger directed one.
    pub hausdorff: f64,
    /// Largest distance from the reference to the candidate.
    pub hausdorff_ref_to_cand: f64,
    /// Largest distance from the candidate to the reference.
    pub hausdorff_cand_to_ref: f64,
    /// Chamfer distance as a mean distance, averaged over both directions.
    pub chamfer_mean: f64,
    /// Mean distance from the reference to the candidate.
    pub chamfer_mean_ref_to_cand: f64,
    /// Mean distance from the candidate to the reference.
    pub chamfer_mean_cand_to_ref: f64,
    /// Chamfer distance as a mean squared distance, averaged over both
    /// directions (W Table 1's "Chamfer").
    pub chamfer_squared: f64,
    /// Mean squared distance from the reference to the candidate.
    pub chamfer_squared_ref_to_cand: f64,
    /// Mean squared distance from the candidate to the reference.
    pub chamfer_squared_cand_to_ref: f64,
    /// Quad ratio (Knodt 2024 §4): `(cand.quads / cand.triangulated) /
    /// (ref.quads / ref.triangulated)`; 1 when the candidate keeps the
    /// reference's share of quads. `None` when the reference has no quad or
    /// the candidate no face.
    pub quad_ratio: Option<f64>,
    /// Texture Chamfer distance (W §5, Table 2, after Yuan et al. 2018):
    /// the mean L2 norm (not squared) of the RGB difference, colors in
    /// [0, 1], between each texture sample and the spatially closest
    /// texture sample of the other surface, averaged over both directions.
    /// `None` unless both surfaces have a base color texture and area.
    pub texture_chamfer: Option<f64>,
    /// Texture Chamfer from the reference's samples to the candidate's.
    pub texture_chamfer_ref_to_cand: Option<f64>,
    /// Texture Chamfer from the candidate's samples to the reference's.
    pub texture_chamfer_cand_to_ref: Option<f64>,
    /// The texture Chamfer distance's sampling floor: the reference
    /// against a second sampling of itself.
    pub texture_chamfer_floor: Option<f64>,
    /// Normal Chamfer distance: the texture Chamfer scheme on vertex
    /// normals — the mean angle in degrees (0 to 90: orientation is
    /// ignored, so the two sides of a thin shell do not count as flipped)
    /// between each sample's normal (the mesh's normals interpolated, or
    /// the face's own where it has none) and that of the spatially closest
    /// sample of the other surface, averaged over both directions. `None`
    /// when either surface has no area (uses `texture_samples` samples).
    pub normal_chamfer: Option<f64>,
    /// Normal Chamfer from the reference's samples to the candidate's.
    pub normal_chamfer_ref_to_cand: Option<f64>,
    /// Normal Chamfer from the candidate's samples to the reference's.
    pub normal_chamfer_cand_to_ref: Option<f64>,
    /// The normal Chamfer distance's sampling floor.
    pub normal_chamfer_floor: Option<f64>,
    /// Shading-normal Chamfer distance: the normal Chamfer distance on the
    /// normals a glTF renderer lights with, normal maps applied in the
    /// MikkTSpace tangent frame on both sides
    /// ([`EvalMesh::shading_normal_at`]). Equal to `normal_chamfer` when
    /// neither side has a normal map.
    pub shading_normal_chamfer: Option<f64>,
    /// Shading-normal Chamfer from the reference's samples.
    pub shading_normal_chamfer_ref_to_cand: Option<f64>,
    /// Shading-normal Chamfer from the candidate's samples.
    pub shading_normal_chamfer_cand_to_ref: Option<f64>,
    /// The shading-normal Chamfer distance's sampling floor.
    pub shading_normal_chamfer_floor: Option<f64>,
    /// The fraction of the reference's alpha-tested (`MASK`) surface that
    /// an alpha test draws: its base color alpha (image times factor,
    /// bilinear) at least the material's cutoff, over the texture
    /// samples. `None` when it has no alpha-tested material. A LOD whose
    /// re-baked atlas averaged thin strokes under the cutoff draws less
    /// (a fence loses its wires), which no colour distance shows.
    pub alpha_coverage_reference: Option<f64>,
    /// The same on the candidate.
    pub alpha_coverage_candidate: Option<f64>,
    /// Reference vertices that are outliers (see above).
    pub outliers_reference: usize,
    /// Candidate vertices beyond the reference's outlier limit (0 when
    /// the reference has no outlier: the limit is then not applied).
    pub outliers_candidate: usize,
    /// Reference triangles left out for having an outlier corner.
    pub outlier_triangles_reference: usize,
    /// Candidate triangles left out for having a corner beyond the limit.
    pub outlier_triangles_candidate: usize,
    /// The first reference outliers ([`MAX_NAMED_OUTLIERS`] at most), by
    /// mesh and vertex.
    pub outlier_vertices: Vec<OutlierVertex>,
    /// Face counts of the reference.
    pub reference: FaceCounts,
    /// Face counts of the candidate.
    pub candidate: FaceCounts,
    /// Human-readable remarks on anything unusual (an empty surface, a
    /// missing texture, outliers).
    pub notes: Vec<String>,
}

/// At most this many outliers are named in [`Comparison::outlier_vertices`].
pub const MAX_NAMED_OUTLIERS: usize = 10;

/// A reference vertex left out as an outlier.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OutlierVertex {
    /// Index of the stored mesh ([`wildlod_mesh::Scene::meshes`]).
    pub mesh: u32,
    /// Index of the mesh instance, in [`wildlod_mesh::Scene::instances`]
    /// order.
    pub instance: usize,
    /// Index of the vertex in the stored mesh's positions.
    pub vertex: u32,
    /// Its world-space position.
    pub position: [f64; 3],
}

/// Running statistics of distances from sample points, in world units.
#[derive(Clone, Copy, Debug, Default)]
struct Partial {
    max: f64,
    sum: f64,
    sum2: f64,
    count: usize,
    /// Samples not measured (see [`Target::distance2`]).
    skipped: usize,
}

impl Partial {
    fn push(&mut self, d2: Option<f64>) {
        let Some(d2) = d2 else {
            self.skipped += 1;
            return;
        };
        let d = d2.sqrt();
        self.max = self.max.max(d);
        self.sum += d;
        self.sum2 += d2;
        self.count += 1;
    }

    /// Folds partials in their order, so sums do not depend on which thread
    /// computed which chunk.
    fn fold(parts: Vec<Partial>) -> Partial {
        parts.into_iter().fold(Partial::default(), |a, b| Partial {
            max: a.max.max(b.max),
            sum: a.sum + b.sum,
            sum2: a.sum2 + b.sum2,
            count: a.count + b.count,
            skipped: a.skipped + b.skipped,
        })
    }
}

/// One direction, in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Directed {
    max: f64,
    mean: f64,
    mean2: f64,
    /// Samples skipped for being nearest to the other surface's left-out
    /// triangles.
    shadowed: usize,
}

/// The surface distances are measured to: the triangles kept, and those
/// left out for an outlier corner (`None` when nothing is left out).
struct Target {
    kept: TriangleSet,
    left_out: Option<TriangleSet>,
}

impl Target {
    /// Squared distance from `p` to the kept triangles, or `None` when the
    /// nearest point is on a left-out triangle: the point faces the
    /// outlier's spike.
    ///
    /// Ties count as left out. They are the rule, not the exception: a
    /// spike's triangles share their top edge with kept ones, and a point
    /// above that edge is nearest to it on both. The two distances are
    /// computed on different triangles and may differ in the last bits, so
    /// "at most as far" allows a relative 1e-9 (squared).
    fn distance2(&self, p: DVec3) -> Option<f64> {
        // Every sample is finite and the kept set has a finite triangle
        // (checked by the caller), so a hit exists; the fallback only keeps
        // this total.
        let d = self.kept.distance2(p).unwrap_or(f64::INFINITY);
        match &self.left_out {
            Some(out) if out.distance2(p).is_some_and(|o| o <= d * (1.0 + 1e-9)) => None,
            _ => Some(d),
        }
    }
}

/// Distances from the samples of `from` to the surface `to`.
fn directed(
    (from, sampler, side): (&EvalMesh, &AreaSampler, Side),
    vertices: &[u32],
    to: &Target,
    options: &CompareOptions,
) -> Directed {
    let area_samples = if sampler.can_sample() {
        options.samples
    } else {
        0
    };
    if area_samples == 0 && vertices.is_empty() {
        return Directed {
            max: 0.0,
            mean: 0.0,
            mean2: 0.0,
            shadowed: 0,
        };
    }
    if to.kept.bvh().bounds().is_empty() {
        return Directed {
            max: f64::INFINITY,
            mean: f64::INFINITY,
            mean2: f64::INFINITY,
            shadowed: 0,
        };
    }
    let area = Partial::fold(
        (0..chunk_count(area_samples))
            .into_par_iter()
            .map(|c| {
                let mut part = Partial::default();
                let pts = sampler.chunk(
                    from,
                    options.seed,
                    (Stream::Surface, side),
                    c,
                    chunk_len(area_samples, c),
                );
                for s in pts {
                    part.push(to.distance2(s.point));
                }
                part
            })
            .collect(),
    );
    let positions = from.positions();
    let verts = Partial::fold(
        vertices
            .par_chunks(CHUNK)
            .map(|vs| {
                let mut part = Partial::default();
                for &v in vs {
                    part.push(to.distance2(positions[v as usize]));
                }
                part
            })
            .collect(),
    );
    let means = if area.count > 0 { area } else { verts };
    let per = |sum: f64| {
        if means.count > 0 {
            sum / means.count as f64
        } else {
            0.0
        }
    };
    Directed {
        max: area.max.max(verts.max),
        mean: per(means.sum),
        mean2: per(means.sum2),
        shadowed: area.skipped + verts.skipped,
    }
}

/// At most `cap` of the mesh's vertex samples, evenly strided, without
/// those `left_out` rejects.
fn capped_vertices(mesh: &EvalMesh, cap: usize, left_out: &dyn Fn(DVec3) -> bool) -> Vec<u32> {
    let positions = mesh.positions();
    let all: Vec<u32> = mesh
        .vertex_samples()
        .iter()
        .copied()
        .filter(|&v| !left_out(positions[v as usize]))
        .collect();
    if all.len() <= cap {
        return all;
    }
    (0..cap).map(|i| all[i * all.len() / cap]).collect()
}

/// Which triangles of `mesh` are kept (no corner `left_out`), and the
/// number left out.
fn kept_triangles(
    mesh: &EvalMesh,
    left_out: &(dyn Fn(DVec3) -> bool + Sync),
) -> (Vec<bool>, usize) {
    let positions = mesh.positions();
    let keep: Vec<bool> = mesh
        .triangles()
        .par_iter()
        .map(|t| !t.iter().any(|&v| left_out(positions[v as usize])))
        .collect();
    let dropped = keep.iter().filter(|&&k| !k).count();
    (keep, dropped)
}

/// The target surface of `mesh`: its kept triangles, and the left-out ones
/// when there are any.
fn target(mesh: &EvalMesh, keep: &[bool], dropped: usize) -> Target {
    let split = |want: bool| -> Vec<[u32; 3]> {
        mesh.triangles()
            .iter()
            .zip(keep)
            .filter(|(_, &k)| k == want)
            .map(|(t, _)| *t)
            .collect()
    };
    if dropped == 0 {
        return Target {
            kept: TriangleSet::new(mesh.positions(), mesh.triangles()),
            left_out: None,
        };
    }
    let (kept, out) = rayon::join(
        || TriangleSet::new(mesh.positions(), &split(true)),
        || TriangleSet::new(mesh.positions(), &split(false)),
    );
    Target {
        kept,
        left_out: Some(out),
    }
}

/// The remark on the reference's outliers.
fn outlier_note(bounds: &RobustBounds, named: &[OutlierVertex], full: f64) -> String {
    let first = named.first().map_or(String::new(), |o| {
        format!(
            ", the first vertex {} of mesh {} at ({:.6e}, {:.6e}, {:.6e})",
            o.vertex, o.mesh, o.position[0], o.position[1], o.position[2]
        )
    });
    format!(
        "{} reference vertices lie more than {:.6e} from the median of its vertices \
         ({} times the extent of their central half){first}: they are outliers, \
         left out with their triangles; distances are relative to the diagonal of \
         the rest ({:.6e}; with the outliers {:.6e})",
        bounds.outliers.len(),
        bounds.limit,
        OutlierRule::default().factor,
        bounds.diagonal(),
        full
    )
}

/// Compares `candidate` with `reference` as W §5 and Knodt 2024 §4 measure
/// simplified meshes; see [`Comparison`] for every number's definition.
///
/// Runs on the rayon pool; the result is bit-identical for a given seed
/// whatever the thread count: samples come in fixed-size chunks seeded from
/// (seed, purpose, side, chunk index), and partial sums are added in chunk
/// order. The two surfaces (and the reference's second sampling for the
/// floors) draw independent random numbers, so a surface compared with
/// itself is 0 apart in the geometric distances (each sample lies on the
/// other surface) but at the floor in the paired ones.
pub fn compare(reference: &EvalMesh, candidate: &EvalMesh, options: &CompareOptions) -> Comparison {
    let mut notes = Vec::new();
    let full_diagonal = reference.bounds().diagonal();
    let bounds = reference.robust_bounds(&OutlierRule::default());
    let has_outliers = !bounds.outliers.is_empty();
    let diagonal = if has_outliers {
        bounds.diagonal()
    } else {
        full_diagonal
    };
    let unit = if diagonal > 0.0 && diagonal.is_finite() {
        diagonal
    } else {
        notes.push(
            "the reference's bounding-box diagonal is 0: distances are in world units".into(),
        );
        1.0
    };
    // The reference's outlier limit applies to both surfaces, and only
    // when the reference has outliers: a candidate's own far-away vertex
    // is a defect to measure, not to leave out.
    let left_out = |p: DVec3| has_outliers && bounds.is_outlier(p.to_array());
    let ((ref_keep, ref_dropped), (cand_keep, cand_dropped)) = rayon::join(
        || kept_triangles(reference, &left_out),
        || kept_triangles(candidate, &left_out),
    );
    let (ref_set, cand_set) = rayon::join(
        || target(reference, &ref_keep, ref_dropped),
        || target(candidate, &cand_keep, cand_dropped),
    );
    let keep = |dropped: usize, k: &[bool]| (dropped > 0).then_some(k.to_vec());
    let (ref_mask, cand_mask) = (keep(ref_dropped, &ref_keep), keep(cand_dropped, &cand_keep));
    let (ref_sampler, cand_sampler) = rayon::join(
        || AreaSampler::new(reference, ref_mask.as_deref()),
        || AreaSampler::new(candidate, cand_mask.as_deref()),
    );
    for (name, m) in [("reference", reference), ("candidate", candidate)] {
        if m.triangles().is_empty() {
            notes.push(format!(
                "the {name} has no triangle: distances to it are infinite"
            ));
        }
    }
    let ref_vertices = capped_vertices(reference, options.max_vertex_samples, &left_out);
    let cand_vertices = capped_vertices(candidate, options.max_vertex_samples, &left_out);
    let r2c = directed(
        (reference, &ref_sampler, Side::Reference),
        &ref_vertices,
        &cand_set,
        options,
    );
    let c2r = directed(
        (candidate, &cand_sampler, Side::Candidate),
        &cand_vertices,
        &ref_set,
        options,
    );
    let looks = appearance(
        (reference, &ref_sampler),
        (candidate, &cand_sampler),
        options.texture_samples,
        options.seed,
    );
    let texture = looks.texture;
    if texture.is_none() && options.texture_samples > 0 {
        for (name, m) in [("reference", reference), ("candidate", candidate)] {
            if !m.has_texture() {
                notes.push(format!(
                    "the {name} has no base color texture: no texture Chamfer distance"
                ));
            }
        }
    }
    let positions = reference.positions();
    let samples = reference.vertex_samples();
    let outlier_vertices: Vec<OutlierVertex> = bounds
        .outliers
        .iter()
        .take(MAX_NAMED_OUTLIERS)
        .filter_map(|&i| {
            let p = samples[i];
            let (instance, mesh, vertex) = reference.locate(p)?;
            Some(OutlierVertex {
                mesh,
                instance,
                vertex,
                position: positions[p as usize].to_array(),
            })
        })
        .collect();
    let cand_outliers = if has_outliers {
        let cp = candidate.positions();
        candidate
            .vertex_samples()
            .iter()
            .filter(|&&v| bounds.is_outlier(cp[v as usize].to_array()))
            .count()
    } else {
        0
    };
    if has_outliers {
        notes.push(outlier_note(&bounds, &outlier_vertices, full_diagonal));
        if cand_outliers > 0 {
            notes.push(format!(
                "{cand_outliers} candidate vertices lie beyond the same limit: left out with their {cand_dropped} triangles"
            ));
        }
        let shadowed = r2c.shadowed + c2r.shadowed;
        if shadowed > 0 {
            notes.push(format!(
                "{shadowed} samples nearest to the other surface's left-out triangles were skipped"
            ));
        }
    }
    let (rc, cc) = (reference.counts(), candidate.counts());
    let quad_ratio = (rc.quads > 0 && cc.triangulated > 0).then(|| {
        (cc.quads as f64 / cc.triangulated as f64) / (rc.quads as f64 / rc.triangulated as f64)
    });
    let u2 = unit * unit;
    let mean = |p: Option<Paired>| p.map(|p| p.mean());
    let (normal, shading) = (looks.normal, looks.shading);
    Comparison {
        diagonal,
        diagonal_with_outliers: full_diagonal,
        samples: options.samples,
        texture_samples: options.texture_samples,
        vertex_samples_reference: ref_vertices.len(),
        vertex_samples_candidate: cand_vertices.len(),
        seed: options.seed,
        hausdorff: r2c.max.max(c2r.max) / unit,
        hausdorff_ref_to_cand: r2c.max / unit,
        hausdorff_cand_to_ref: c2r.max / unit,
        chamfer_mean: 0.5 * (r2c.mean + c2r.mean) / unit,
        chamfer_mean_ref_to_cand: r2c.mean / unit,
        chamfer_mean_cand_to_ref: c2r.mean / unit,
        chamfer_squared: 0.5 * (r2c.mean2 + c2r.mean2) / u2,
        chamfer_squared_ref_to_cand: r2c.mean2 / u2,
        chamfer_squared_cand_to_ref: c2r.mean2 / u2,
        quad_ratio,
        texture_chamfer: mean(texture),
        texture_chamfer_ref_to_cand: texture.map(|t| t.ref_to_cand),
        texture_chamfer_cand_to_ref: texture.map(|t| t.cand_to_ref),
        texture_chamfer_floor: texture.map(|t| t.floor),
        normal_chamfer: mean(normal),
        normal_chamfer_ref_to_cand: normal.map(|t| t.ref_to_cand),
        normal_chamfer_cand_to_ref: normal.map(|t| t.cand_to_ref),
        normal_chamfer_floor: normal.map(|t| t.floor),
        shading_normal_chamfer: mean(shading),
        shading_normal_chamfer_ref_to_cand: shading.map(|t| t.ref_to_cand),
        shading_normal_chamfer_cand_to_ref: shading.map(|t| t.cand_to_ref),
        shading_normal_chamfer_floor: shading.map(|t| t.floor),
        alpha_coverage_reference: looks.coverage[0],
        alpha_coverage_candidate: looks.coverage[1],
        outliers_reference: bounds.outliers.len(),
        outliers_candidate: cand_outliers,
        outlier_triangles_reference: ref_dropped,
        outlier_triangles_candidate: cand_dropped,
        outlier_vertices,
        reference: rc,
        candidate: cc,
        notes,
    }
}
