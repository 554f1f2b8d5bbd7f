//! `compare`: the geometric and texture metrics of W §5 and Knodt 2024 §4
//! between a reference and a candidate surface.

use rayon::prelude::*;
use serde::Serialize;
use wildlod_geometry::TriangleSet;

use crate::eval_mesh::{EvalMesh, FaceCounts};
use crate::sampling::{chunk_count, chunk_len, AreaSampler, Stream, CHUNK};
use crate::shading::normal_chamfer;
use crate::texture::texture_chamfer;

/// The default seed ("wildlod" in ASCII): fixed, so that two runs of the
/// same comparison agree bit for bit.
pub const DEFAULT_SEED: u64 = 0x0077_696c_646c_6f64;

/// How to compare.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompareOptions {
    /// Area-uniform sample points per surface for the distances. Default
    /// 100 000.
    pub samples: usize,
    /// Area-uniform sample points per surface for the texture Chamfer
    /// distance. Default 10 000, as W §5 uses.
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
            texture_samples: 10_000,
            seed: DEFAULT_SEED,
            max_vertex_samples: 1_000_000,
        }
    }
}

/// The result of [`compare`]. Serialized with exactly these field names.
///
/// Distances are divided by the reference's bounding-box [`diagonal`]
/// (squared distances by its square), as W Table 1 normalizes every mesh to
/// a unit diagonal. With `d(p, S)` the Euclidean distance from point `p`
/// to the closest point of surface `S` (exact point-to-triangle distance):
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
/// Empty surfaces: the distance from a non-empty surface to an empty one is
/// `+∞`, from an empty surface to anything 0 (there is nothing to measure),
/// so an empty candidate gives `+∞` for every symmetric distance, and two
/// empty surfaces give 0. No field is ever NaN. JSON has no infinity:
/// `serde_json` writes it as `null`, and `notes` says why.
///
/// [`diagonal`]: Comparison::diagonal
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// Bounding-box diagonal of the reference, in its units: the unit of
    /// every distance below. When it is 0 (an empty or single-point
    /// reference) distances are left in world units.
    pub diagonal: f64,
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
    /// Normal Chamfer distance: the texture Chamfer scheme on shading
    /// normals — the mean angle in degrees (0 to 90: orientation is
    /// ignored, so the two sides of a thin shell do not count as flipped)
    /// between each sample's shading normal (the mesh's normals
    /// interpolated, or the face's own where it has none) and that of the
    /// spatially closest sample of the other surface, averaged over both
    /// directions. What lighting shows of the
    /// difference. `None` when either surface has no area (uses
    /// `texture_samples` samples).
    pub normal_chamfer: Option<f64>,
    /// Normal Chamfer from the reference's samples to the candidate's.
    pub normal_chamfer_ref_to_cand: Option<f64>,
    /// Normal Chamfer from the candidate's samples to the reference's.
    pub normal_chamfer_cand_to_ref: Option<f64>,
    /// Face counts of the reference.
    pub reference: FaceCounts,
    /// Face counts of the candidate.
    pub candidate: FaceCounts,
    /// Human-readable remarks on anything unusual (an empty surface, a
    /// missing texture).
    pub notes: Vec<String>,
}

/// Running statistics of distances from sample points, in world units.
#[derive(Clone, Copy, Debug, Default)]
struct Partial {
    max: f64,
    sum: f64,
    sum2: f64,
    count: usize,
}

impl Partial {
    fn push(&mut self, d2: f64) {
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
        })
    }
}

/// One direction, in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Directed {
    max: f64,
    mean: f64,
    mean2: f64,
}

/// Distances from the samples of `from` to the surface `to`.
fn directed(
    from: &EvalMesh,
    sampler: &AreaSampler,
    vertices: &[u32],
    to: &TriangleSet,
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
        };
    }
    if to.bvh().bounds().is_empty() {
        return Directed {
            max: f64::INFINITY,
            mean: f64::INFINITY,
            mean2: f64::INFINITY,
        };
    }
    // Every sample is finite and `to` has a finite triangle, so a hit
    // always exists; the fallback only keeps this total.
    let dist2 = |p| to.distance2(p).unwrap_or(f64::INFINITY);
    let area = Partial::fold(
        (0..chunk_count(area_samples))
            .into_par_iter()
            .map(|c| {
                let mut part = Partial::default();
                let pts = sampler.chunk(
                    from,
                    options.seed,
                    Stream::Surface,
                    c,
                    chunk_len(area_samples, c),
                );
                for s in pts {
                    part.push(dist2(s.point));
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
                    part.push(dist2(positions[v as usize]));
                }
                part
            })
            .collect(),
    );
    let means = if area.count > 0 { area } else { verts };
    Directed {
        max: area.max.max(verts.max),
        mean: means.sum / means.count as f64,
        mean2: means.sum2 / means.count as f64,
    }
}

/// At most `cap` of the mesh's vertex samples, evenly strided.
fn capped_vertices(mesh: &EvalMesh, cap: usize) -> Vec<u32> {
    let all = mesh.vertex_samples();
    if all.len() <= cap {
        return all.to_vec();
    }
    (0..cap).map(|i| all[i * all.len() / cap]).collect()
}

/// Compares `candidate` with `reference` as W §5 and Knodt 2024 §4 measure
/// simplified meshes; see [`Comparison`] for every number's definition.
///
/// Runs on the rayon pool; the result is bit-identical for a given seed
/// whatever the thread count: samples come in fixed-size chunks seeded from
/// (seed, purpose, chunk index), and partial sums are added in chunk order.
/// Both surfaces are sampled with the same random numbers, so a surface
/// compared with itself gives exactly 0 on every metric, texture included.
pub fn compare(reference: &EvalMesh, candidate: &EvalMesh, options: &CompareOptions) -> Comparison {
    let mut notes = Vec::new();
    let diagonal = reference.bounds().diagonal();
    let unit = if diagonal > 0.0 && diagonal.is_finite() {
        diagonal
    } else {
        notes.push(
            "the reference's bounding-box diagonal is 0: distances are in world units".into(),
        );
        1.0
    };
    let (ref_set, cand_set) = rayon::join(
        || TriangleSet::new(reference.positions(), reference.triangles()),
        || TriangleSet::new(candidate.positions(), candidate.triangles()),
    );
    let (ref_sampler, cand_sampler) = rayon::join(
        || AreaSampler::new(reference),
        || AreaSampler::new(candidate),
    );
    for (name, m) in [("reference", reference), ("candidate", candidate)] {
        if m.triangles().is_empty() {
            notes.push(format!(
                "the {name} has no triangle: distances to it are infinite"
            ));
        }
    }
    let ref_vertices = capped_vertices(reference, options.max_vertex_samples);
    let cand_vertices = capped_vertices(candidate, options.max_vertex_samples);
    let r2c = directed(reference, &ref_sampler, &ref_vertices, &cand_set, options);
    let c2r = directed(candidate, &cand_sampler, &cand_vertices, &ref_set, options);
    let texture = texture_chamfer(
        (reference, &ref_sampler),
        (candidate, &cand_sampler),
        options.texture_samples,
        options.seed,
    );
    let normals = normal_chamfer(
        (reference, &ref_sampler),
        (candidate, &cand_sampler),
        options.texture_samples,
        options.seed,
    );
    if texture.is_none() && options.texture_samples > 0 {
        for (name, m) in [("reference", reference), ("candidate", candidate)] {
            if !m.has_texture() {
                notes.push(format!(
                    "the {name} has no base color texture: no texture Chamfer distance"
                ));
            }
        }
    }
    let (rc, cc) = (reference.counts(), candidate.counts());
    let quad_ratio = (rc.quads > 0 && cc.triangulated > 0).then(|| {
        (cc.quads as f64 / cc.triangulated as f64) / (rc.quads as f64 / rc.triangulated as f64)
    });
    let u2 = unit * unit;
    Comparison {
        diagonal,
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
        texture_chamfer: texture.map(|(a, b)| 0.5 * (a + b)),
        texture_chamfer_ref_to_cand: texture.map(|t| t.0),
        texture_chamfer_cand_to_ref: texture.map(|t| t.1),
        normal_chamfer: normals.map(|(a, b)| 0.5 * (a + b)),
        normal_chamfer_ref_to_cand: normals.map(|t| t.0),
        normal_chamfer_cand_to_ref: normals.map(|t| t.1),
        reference: rc,
        candidate: cc,
        notes,
    }
}
