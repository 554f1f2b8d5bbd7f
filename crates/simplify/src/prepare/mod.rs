//! Step 1 of the simplifier: the input checked, welded, normalized and built
//! into a simplicial complex (W §4.1: a mesh in the wild is a 2-complex of
//! faces, edges and vertices, however non-manifold). Polygons of many
//! corners are split first (`large_polygons.rs`), hidden twin faces folded
//! away (`twins.rs`); `geometry.rs` measures the complex's faces for every
//! later step, `flat_stars.rs` remembers which vertices' faces are flat.
//!
//! The steps after it, each a module that imports only the ones before:
//! `edges` (virtual edges, W §4.1) → `terms` (the error metric, W §4.2,
//! Knodt §3) → `collapse` (the loop, W Alg. 1, Knodt Alg. 1) → `refit` →
//! `assemble` (the output and its maps back to the input).

pub(crate) mod complex;
pub(crate) mod enclosed_parts;
pub(crate) mod flat_stars;
pub(crate) mod geometry;
pub(crate) mod large_polygons;
pub(crate) mod neighbour_moments;
pub(crate) mod star_lists;
pub(crate) mod twins;

use glam::DVec3;
use wildlod_mesh::bounds::{robust_bounds, OutlierRule};
use wildlod_mesh::weld::{merge_within, weld_positions};
use wildlod_mesh::Faces;

use crate::error::Error;
use crate::options::Options;
use crate::prepare::complex::Complex;

/// Whether the partitioned first phase (`collapse/partition.rs`) may apply to `faces` (decided before building the
/// complex, which then skips its star lists): large enough, not in quad mode,
/// no per-edge terms, no history.
pub(crate) fn may_partition(faces: &Faces, o: &Options) -> bool {
    let (_, quads, _) = faces.arity_counts();
    let quads_active = o.quads_active(quads);
    !o.record.history
        && !quads_active
        && o.effective_metric(quads).tangent_weight <= 0.0
        && faces.triangulated_count() >= o.partition.min_triangles
}

pub(crate) fn check_input(
    positions: &[[f32; 3]],
    faces: &Faces,
    options: &Options,
) -> Result<(), Error> {
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
    if !(o.guards.virtual_edge_radius >= 0.0 && o.guards.virtual_edge_radius.is_finite()) {
        return bad("virtual_edge_radius", o.guards.virtual_edge_radius);
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
    if !o.data.see_through_faces.is_empty() && o.data.see_through_faces.len() != faces.len() {
        return Err(Error::SeeThroughCount {
            flags: o.data.see_through_faces.len(),
            faces: faces.len(),
        });
    }
    if !o.data.face_instances.is_empty() && o.data.face_instances.len() != faces.len() {
        return Err(Error::InstanceCount {
            counts: o.data.face_instances.len(),
            faces: faces.len(),
        });
    }
    if !o.data.vertex_weights.is_empty() {
        if o.data.vertex_weights.len() != n {
            return Err(Error::WeightCount {
                weights: o.data.vertex_weights.len(),
                vertices: n,
            });
        }
        if let Some((v, &w)) = o
            .data
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
    /// Parts dropped as enclosed by others (see `enclosed_parts.rs`).
    pub enclosed_parts: usize,
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

/// The first input vertex of each of the `n` welded vertices.
fn first_copies(weld: &[u32], n: usize) -> Vec<u32> {
    let mut rep = vec![u32::MAX; n];
    for (v, &w) in weld.iter().enumerate() {
        if rep[w as usize] == u32::MAX {
            rep[w as usize] = v as u32;
        }
    }
    rep
}

pub(crate) fn prepare(
    positions: &[[f32; 3]],
    faces: &Faces,
    options: &Options,
    with_attributes: bool,
    see_through: &dyn Fn(u32) -> bool,
    instances: Vec<u32>,
) -> Prepared {
    let (mut weld, mut nw) = weld_positions(positions);
    let mut rep = first_copies(&weld, nw);
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
    let mut outlier_ids: Vec<u32> = bounds.outliers.iter().map(|&k| used_ids[k]).collect();
    // Positions equal to the precision of the file's numbers but not bit
    // for bit are one point: a generator's `sin(π)` leaves 1e-17 on one
    // side of a grid line and -1e-17 on the other, and the surface is slit
    // along it (no virtual edge bridges a part to itself), a crack the
    // simplified level opens. The tolerance is a quarter of the `f32`
    // spacing at the bulk's largest coordinate: below any difference a
    // point there can hold, so no two vertices an author could place apart
    // anywhere in the model's extent merge.
    let largest = bounds
        .min
        .iter()
        .chain(&bounds.max)
        .fold(0.0f64, |m, c| m.max(c.abs()));
    outlier_ids.sort_unstable();
    let is_outlier = |w: u32| outlier_ids.binary_search(&w).is_ok();
    let bulk: Vec<(u32, [f64; 3])> = used_ids
        .iter()
        .filter(|&&w| !is_outlier(w))
        .map(|&w| (w, positions[rep[w as usize] as usize].map(f64::from)))
        .collect();
    if let Some((remap, n)) = merge_within(&bulk, nw, largest * 2f64.powi(-25)) {
        for w in &mut weld {
            *w = remap[*w as usize];
        }
        for w in &mut outlier_ids {
            *w = remap[*w as usize];
        }
        nw = n;
        rep = first_copies(&weld, nw);
    }
    let mut outliers = vec![false; if outlier_ids.is_empty() { 0 } else { nw }];
    for &w in &outlier_ids {
        outliers[w as usize] = true;
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
    // So is it of the parts no one sees. Poses could open an enclosure or
    // move a part out of it: skinned and morphed meshes keep theirs.
    let posed = !options.data.vertex_joints.is_empty()
        || !options.data.skin_poses.is_empty()
        || !options.data.morph_targets.is_empty();
    let enclosed_parts = if options.guards.drop_enclosed_parts && !posed {
        crate::prepare::enclosed_parts::drop_enclosed_parts(&mut complex, see_through)
    } else {
        0
    };
    let hidden_twins = if options.guards.drop_hidden_twins {
        crate::prepare::twins::drop_hidden_twins(&mut complex, see_through)
    } else {
        0
    };
    if with_attributes || !may_partition(faces, options) {
        complex.build_adjacency();
    }
    let mut weights = Vec::new();
    if !options.data.vertex_weights.is_empty() {
        // A welded vertex is as important as its most important copy.
        weights = vec![0.0f64; nw];
        for (v, &w) in weld.iter().enumerate() {
            let x = &mut weights[w as usize];
            *x = x.max(options.data.vertex_weights[v] as f64);
        }
    }
    Prepared {
        appearance_budget: f64::INFINITY,
        outlier_inputs: {
            let mut inputs: Vec<u32> = outlier_ids.iter().map(|&w| rep[w as usize]).collect();
            inputs.sort_unstable();
            inputs
        },
        outliers,
        rep,
        complex,
        cleaned: cleaned.degenerate + cleaned.duplicate,
        hidden_twins,
        enclosed_parts,
        ratio_base,
        weld,
        center,
        scale,
        input_triangles,
        weights,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn welded(positions: &[[f32; 3]], triangles: &[u32]) -> Vec<u32> {
        let faces = Faces::from_triangles(triangles);
        prepare(
            positions,
            &faces,
            &Options::default(),
            false,
            &|_| false,
            Vec::new(),
        )
        .weld
    }

    #[test]
    fn rounding_noise_welds_and_one_float_step_at_the_largest_coordinate_does_not() {
        // Two triangles over the edge (4.4, 1.5)–(4.4, 3): the lower one's
        // copies of its ends sit at z = ±1e-17, the upper one's at 0, as a
        // generator's sin(π) leaves them. One point to anything a float
        // can hold at a coordinate of 10.
        let noisy = [
            [4.4, 1.5, 1e-17],
            [4.4, 3.0, -1e-17],
            [0.0, 2.0, 0.0],
            [4.4, 1.5, 0.0],
            [4.4, 3.0, 0.0],
            [10.0, 2.0, 0.0],
        ];
        let w = welded(&noisy, &[0, 1, 2, 3, 5, 4]);
        assert_eq!((w[0], w[1]), (w[3], w[4]), "{w:?}");
        assert_eq!(w.iter().max(), Some(&3));
        // One f32 step apart at x = 10, the largest coordinate: two points
        // an author can place apart, so two vertices.
        let step = f32::from_bits(10f32.to_bits() + 1);
        let apart = [
            [10.0, 0.0, 0.0],
            [10.0, 1.0, 0.0],
            [0.0, 0.5, 0.0],
            [step, 0.0, 0.0],
            [step, 1.0, 0.0],
            [5.0, 0.5, 0.0],
        ];
        let w = welded(&apart, &[0, 1, 2, 3, 5, 4]);
        assert_eq!(w, vec![0, 1, 2, 3, 4, 5]);
    }
}
