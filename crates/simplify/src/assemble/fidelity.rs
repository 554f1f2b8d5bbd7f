//! How far a result is from its input, measured on the surfaces: the check
//! behind [`crate::AttributeOptions::geometry_tolerance`].
//!
//! Attributes steer collapses by their own errors, which no quadric bound
//! ties to the distance a viewer sees: a different order of equally cheap
//! collapses can move the worst spot of a surface by more than any bound on
//! their ranks promises. So the promise is checked where it is made, on the
//! results: both directions of the distance between the input and a result,
//! measured at the vertices and face centres of each surface (dense on the
//! input; on a coarse result its vertices, where errors concentrate, and
//! the middles of its faces, where a cut-off feature shows).

use glam::DVec3;
use rayon::prelude::*;
use wildlod_geometry::TriangleSet;
use wildlod_mesh::Faces;

/// The diagonal of the bounding box of the positions faces use (1 when
/// there is none).
pub(crate) fn diagonal(positions: &[[f32; 3]], faces: &Faces) -> f64 {
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

/// Distances between two surfaces, in the units of their positions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Fidelity {
    /// The largest distance from a sample of either surface to the other
    /// (Hausdorff, as sampled).
    pub hausdorff: f64,
    /// The mean of the two directions' area-weighted mean distances
    /// (Chamfer, as sampled).
    pub chamfer: f64,
}

/// A surface as triangles (the fans polygons are drawn with) and its
/// samples: every vertex a face uses, weighted by a third of its faces'
/// areas, and every triangle's centre, weighted by the rest. A grid-sampled
/// surface also has points along its edges, weighing nothing: a coarse
/// result's largest distance to its input is often at the middle of an
/// edge (a chord across a curved or creased region, farthest from the
/// input where both of its faces leave it), which no grid cell's centre
/// reaches (on `bob` at 10% the centres read a fifth less than the edges
/// did).
struct Surface {
    set: TriangleSet,
    /// Face samples first (`..face_samples`), then vertex samples
    /// (`..vertex_end`), then edge samples.
    samples: Vec<(DVec3, f64)>,
    face_samples: usize,
    vertex_end: usize,
    /// Total area.
    area: f64,
}

/// Grid steps a side at most (4096 samples on a triangle): only a
/// triangle far larger than the rest meets it, the budget below bounds
/// the sum.
const MAX_GRID: usize = 64;

/// A result is sampled at most this many times as often as its input (at
/// the input's own density a result of about the input's area has about
/// as many samples as the input; the grid's spacing widens beyond it), so
/// the check's time stays bounded by the input's size.
const SAMPLE_BUDGET: f64 = 2.0;

/// SplitMix64's finalizer: a fixed, well-spread hash of a sample's index.
fn mix(mut x: u64) -> u64 {
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// Samples a side [`Reference::chamfer`] reads at most (about): the mean
/// of this many distances, spread by a hash over each class, is within a
/// fraction of a percent of all of them, far inside the bounds it is
/// compared with.
const CHAMFER_SAMPLES: usize = 65_536;

impl Surface {
    /// `spacing`: on triangles larger than a square of this side, samples
    /// on a barycentric grid of about this spacing (up to
    /// [`MAX_GRID`] steps a side) instead of the centre alone, widened
    /// where the grids would hold more than `budget` samples in all.
    fn new(positions: &[[f32; 3]], faces: &Faces, spacing: f64, budget: f64) -> Surface {
        let p: Vec<DVec3> = positions
            .iter()
            .map(|x| DVec3::from(x.map(f64::from)))
            .collect();
        let mut triangles: Vec<[u32; 3]> = Vec::new();
        for face in faces.iter() {
            for k in 1..face.len().saturating_sub(1) {
                triangles.push([face[0], face[k], face[k + 1]]);
            }
        }
        let area_of = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|v| p[v as usize]);
            0.5 * (b - a).cross(c - a).length()
        };
        let spacing = if spacing > 0.0 {
            let cells: f64 = triangles
                .iter()
                .map(area_of)
                .filter(|a| a.is_finite())
                .sum::<f64>()
                / (spacing * spacing);
            if cells > budget {
                spacing * (cells / budget).sqrt()
            } else {
                spacing
            }
        } else {
            spacing
        };
        let mut vertex_area = vec![0.0f64; p.len()];
        let mut samples = Vec::with_capacity(triangles.len());
        let mut total = 0.0;
        for t in &triangles {
            let [a, b, c] = t.map(|v| p[v as usize]);
            let area = 0.5 * (b - a).cross(c - a).length();
            if !area.is_finite() {
                continue;
            }
            total += area;
            for &v in t {
                vertex_area[v as usize] += area / 6.0;
            }
            let steps = if spacing > 0.0 {
                ((area / (spacing * spacing)).sqrt().ceil() as usize).clamp(1, MAX_GRID)
            } else {
                1
            };
            if steps == 1 {
                samples.push(((a + b + c) / 3.0, area / 2.0));
                continue;
            }
            // The centres of the n² sub-triangles of an n-step grid.
            let n = steps as f64;
            let w = area / 2.0 / n / n;
            for i in 0..steps {
                for j in 0..steps - i {
                    let (u, v) = ((i as f64 + 1.0 / 3.0) / n, (j as f64 + 1.0 / 3.0) / n);
                    samples.push((a + (b - a) * u + (c - a) * v, w));
                    if i + j + 1 < steps {
                        let (u, v) = ((i as f64 + 2.0 / 3.0) / n, (j as f64 + 2.0 / 3.0) / n);
                        samples.push((a + (b - a) * u + (c - a) * v, w));
                    }
                }
            }
        }
        let face_samples = samples.len();
        samples.extend(
            vertex_area
                .iter()
                .enumerate()
                .filter(|(_, &w)| w > 0.0)
                .map(|(v, &w)| (p[v], w)),
        );
        let vertex_end = samples.len();
        if spacing > 0.0 {
            let mut edges: Vec<(u32, u32)> = triangles
                .iter()
                .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                .map(|(a, b)| (a.min(b), a.max(b)))
                .filter(|(a, b)| a != b)
                .collect();
            edges.sort_unstable();
            edges.dedup();
            for (a, b) in edges {
                let (a, b) = (p[a as usize], p[b as usize]);
                let length = (b - a).length();
                if !length.is_finite() {
                    continue;
                }
                // At least the middle; as finely as the grid otherwise.
                let steps = ((length / spacing).ceil() as usize).clamp(2, MAX_GRID);
                samples.extend((1..steps).map(|k| (a + (b - a) * (k as f64 / steps as f64), 0.0)));
            }
        }
        Surface {
            set: TriangleSet::new(&p, &triangles),
            samples,
            face_samples,
            vertex_end,
            area: total,
        }
    }

    /// The side of a square of the mean triangle's area.
    fn mean_triangle_side(&self) -> f64 {
        let (area, count) = (self.area, self.set.len().max(1));
        (area / count as f64).sqrt()
    }

    /// The largest and the weighted mean distance from this surface's
    /// samples to `other`: every sample (`cap` = `usize::MAX`), or about
    /// `cap` of them, half among the face samples and half among the
    /// vertex samples, and none of the edge samples (which count in the
    /// largest distance only).
    ///
    /// A class larger than its half keeps about one sample in `k`, picked
    /// by a hash of its index (a fixed stride aliases with a regular
    /// tessellation's rows), and each class keeps its total weight: on a
    /// coarse result a few vertex samples weigh as much as all the face
    /// samples, and a plain subset moved the result-to-input mean of the
    /// test below by up to 44%.
    fn to(&self, other: &Surface, cap: usize) -> (f64, f64) {
        let classes = [0..self.face_samples, self.face_samples..self.vertex_end];
        let half = (cap / 2).max(1);
        let strides = classes
            .clone()
            .map(|r| r.len().div_ceil(half).max(1) as u64);
        let kept = |c: usize, i: usize| strides[c] == 1 || mix(i as u64) % strides[c] == 0;
        let picked: Vec<(usize, DVec3, f64)> = classes
            .iter()
            .enumerate()
            .flat_map(|(c, r)| {
                r.clone()
                    .filter(move |&i| kept(c, i))
                    .map(move |i| (c, self.samples[i].0, self.samples[i].1))
            })
            .collect();
        // Distances in parallel, summed in sample order: a parallel float
        // reduction associates differently from run to run, and the
        // steering decision must be the same on every run.
        let d: Vec<f64> = picked
            .par_iter()
            .map(|&(_, x, _)| other.set.distance2(x).map_or(0.0, f64::sqrt))
            .collect();
        let mut max = 0.0f64;
        let (mut sum, mut weight) = ([0.0f64; 2], [0.0f64; 2]);
        for (&d, &(c, _, w)) in d.iter().zip(&picked) {
            max = max.max(d);
            sum[c] += d * w;
            weight[c] += w;
        }
        // The edge samples count in the largest distance only, so each
        // needs measuring only where it is farther than the largest so far
        // (most are not: a bounded search). A capped measurement is read
        // for its mean alone (see `Reference::chamfer`) and skips them.
        if cap == usize::MAX {
            let bound = max * max;
            let edges = self.samples[self.vertex_end..]
                .par_iter()
                .map(|&(x, _)| match other.set.distance2_within(x, bound) {
                    Some(_) => 0.0,
                    None => other.set.distance2(x).map_or(0.0, f64::sqrt),
                })
                .reduce(|| 0.0, f64::max);
            max = max.max(edges);
        }
        if strides == [1, 1] {
            let w = weight[0] + weight[1];
            return (max, if w > 0.0 { (sum[0] + sum[1]) / w } else { 0.0 });
        }
        // Each class's mean, weighed by the class's whole weight.
        let (mut mean, mut total) = (0.0, 0.0);
        for (c, r) in classes.iter().enumerate() {
            let all: f64 = self.samples[r.clone()].iter().map(|s| s.1).sum();
            if weight[c] > 0.0 {
                mean += all * sum[c] / weight[c];
                total += all;
            }
        }
        (max, if total > 0.0 { mean / total } else { 0.0 })
    }
}

/// An input sampled and indexed once, to measure any number of its
/// results against.
pub(crate) struct Reference {
    surface: Surface,
    /// The result's larger triangles are sampled on a grid this fine.
    spacing: f64,
}

impl Reference {
    /// The input as faces over positions, sampled at its own density.
    pub(crate) fn new(input: (&[[f32; 3]], &Faces)) -> Reference {
        let surface = Surface::new(input.0, input.1, 0.0, f64::INFINITY);
        let spacing = surface.mean_triangle_side();
        Reference { surface, spacing }
    }

    /// The sampled distances between the input and `output`, a result of
    /// simplifying it.
    pub(crate) fn fidelity(&self, output: (&[[f32; 3]], &Faces)) -> Fidelity {
        self.measure(output, usize::MAX)
    }

    /// The Chamfer distance of [`Reference::fidelity`] from at most about
    /// [`CHAMFER_SAMPLES`] samples a side (the same ones on every call):
    /// a mean, unlike the largest distance, is read as well from a
    /// regular subset, and on a large input most of the check's time is
    /// these queries.
    pub(crate) fn chamfer(&self, output: (&[[f32; 3]], &Faces)) -> f64 {
        self.measure(output, CHAMFER_SAMPLES).chamfer
    }

    /// The distances, from at most about `cap` samples a side.
    fn measure(&self, output: (&[[f32; 3]], &Faces), cap: usize) -> Fidelity {
        // The result's larger triangles are sampled on a grid as fine as
        // the input's mean triangle, so a feature cut off inside one is
        // seen.
        let a = &self.surface;
        let budget = SAMPLE_BUDGET * a.samples.len() as f64;
        let b = Surface::new(output.0, output.1, self.spacing, budget);
        if b.samples.is_empty() || a.samples.is_empty() {
            return Fidelity::default();
        }
        let (h1, c1) = a.to(&b, cap);
        let (h2, c2) = b.to(a, cap);
        Fidelity {
            hausdorff: h1.max(h2),
            chamfer: 0.5 * (c1 + c2),
        }
    }
}

/// The sampled distances between an input and a result of simplifying it.
#[cfg(test)]
fn fidelity(input: (&[[f32; 3]], &Faces), output: (&[[f32; 3]], &Faces)) -> Fidelity {
    Reference::new(input).fidelity(output)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An `n × n` grid of the unit square, two triangles a cell, lifted to
    /// `z = height(x, y)`.
    pub(super) fn height_field(
        n: usize,
        height: impl Fn(f32, f32) -> f32,
    ) -> (Vec<[f32; 3]>, Faces) {
        let grid = wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::quad_grid(n, n));
        let p = grid
            .positions
            .iter()
            .map(|&[x, y, _]| [x, y, height(x, y)])
            .collect();
        (p, grid.faces)
    }

    fn square(z: f32) -> (Vec<[f32; 3]>, Faces) {
        (
            vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
            Faces::from_triangles(&[0, 1, 2, 0, 2, 3]),
        )
    }

    #[test]
    fn a_surface_is_at_distance_zero_from_itself() {
        let (p, f) = square(0.0);
        assert_eq!(fidelity((&p, &f), (&p, &f)), Fidelity::default());
    }

    #[test]
    fn a_parallel_copy_is_at_its_offset_both_ways() {
        let (p, f) = square(0.0);
        let (q, g) = square(0.25);
        let d = fidelity((&p, &f), (&q, &g));
        assert!((d.hausdorff - 0.25).abs() < 1e-7, "{d:?}");
        assert!((d.chamfer - 0.25).abs() < 1e-7, "{d:?}");
    }

    #[test]
    fn a_cut_off_spike_counts_in_the_hausdorff_distance_and_by_area_in_the_mean() {
        // A square with a tent of height 1 over its middle, against the flat
        // square: the tent's apex is 1 away.
        let p = vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [1.0, 1.0, 1.0],
        ];
        let f = Faces::from_triangles(&[0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4]);
        let (q, g) = (
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 2.0, 0.0],
                [0.0, 2.0, 0.0],
            ],
            Faces::from_triangles(&[0, 1, 2, 0, 2, 3]),
        );
        // The tent as the result (its triangles are smaller than the flat
        // input's: sampled at their centres alone).
        let d = fidelity((&q, &g), (&p, &f));
        assert!((d.hausdorff - 1.0).abs() < 1e-7, "{d:?}");
        // Tent → flat: four centroids at height 1/3 weighing half their
        // triangle's area √2 each, the apex at 1 weighing 4·√2/6, corners
        // at 0: mean 1/3. Flat → tent: the two centroids lie √2/3 below
        // the tent (weight 1 each of 4), the corners on it: mean √2/6.
        let expected = 0.5 * (1.0 / 3.0 + 2f64.sqrt() / 6.0);
        assert!((d.chamfer - expected).abs() < 1e-7, "{d:?} {expected}");
    }

    #[test]
    fn a_result_covering_a_small_hole_is_seen_inside_its_large_triangles() {
        // The input: a 40 × 40 grid of the unit square with a 2 × 2 cell
        // hole (0.05 wide); the result: the square's two triangles, 800
        // times the input's mean triangle, covering the hole. The hole's
        // middle is 0.025 from the input; the result's grid samples it
        // as finely as the input's triangles (about 0.018 apart), where 36
        // samples a triangle saw none of it.
        let n = 40;
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                p.push([i as f32 / n as f32, j as f32 / n as f32, 0.0]);
            }
        }
        let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut idx = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if (27..29).contains(&i) && (9..11).contains(&j) {
                    continue;
                }
                idx.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                idx.extend([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let input = (p, Faces::from_triangles(&idx));
        let (q, g) = square(0.0);
        let d = fidelity((&input.0, &input.1), (&q, &g));
        assert!(d.hausdorff > 0.015 && d.hausdorff <= 0.025 + 1e-6, "{d:?}");
    }

    #[test]
    fn the_sample_budget_widens_the_grid() {
        // A spacing of 0.001 asks a million cells of the unit square; the
        // budget of 1000 widens it to about 0.032: two triangles of 23
        // steps a side (the ceiling of 0.707 / 0.032), 529 samples each,
        // the four corners, and 31 points inside each side (32 steps of
        // 1 / 0.032) and 44 inside the diagonal (45 steps of 1.414 / 0.032).
        let (q, g) = square(0.0);
        let s = Surface::new(&q, &g, 0.001, 1000.0);
        assert_eq!(s.samples.len(), 2 * 23 * 23 + 4 + 4 * 31 + 44);
        // At 0.02 the diagonal's 71 steps stop at the grid's 64.
        let unbounded = Surface::new(&q, &g, 0.02, f64::INFINITY);
        assert_eq!(unbounded.samples.len(), 2 * 36 * 36 + 4 + 4 * 49 + 63);
    }

    #[test]
    fn chamfer_from_a_regular_subset_is_the_chamfer_of_all_samples() {
        // A 60 × 60 grid over a smooth bump, against the flat square:
        // 10,800 triangles' and 3,721 vertices' samples on the input side.
        let (p, faces) = height_field(60, |x, y| 0.2 * (3.0 * x).sin() * (2.0 * y).cos());
        let (q, g) = square(0.0);
        let reference = Reference::new((&p, &faces));
        let all = reference.fidelity((&q, &g));
        // Every face and vertex sample when the cap is above their count:
        // the same mean.
        assert_eq!(reference.measure((&q, &g), 1 << 20).chamfer, all.chamfer);
        // About a thousand samples a side (one in 22 of the input's face
        // samples, one in 8 of its vertices', one in 15 of the result's
        // face samples and its four corners): the mean within 1%.
        let some = reference.measure((&q, &g), 1000).chamfer;
        assert!((some / all.chamfer - 1.0).abs() < 0.01, "{some} {all:?}");
    }
}

#[cfg(test)]
mod dense {
    use super::tests::height_field;
    use super::*;
    use crate::{simplify_polygons, Options, Target};

    /// The largest distance from points of `from` on a barycentric grid of
    /// `n` steps (corners, edges and inside) to `to`.
    fn dense_one_way(from: (&[[f32; 3]], &Faces), to: &TriangleSet, n: usize) -> f64 {
        let p = |v: u32| DVec3::from(from.0[v as usize].map(f64::from));
        let mut max = 0.0f64;
        for face in from.1.iter() {
            for k in 1..face.len() - 1 {
                let [a, b, c] = [face[0], face[k], face[k + 1]].map(p);
                for i in 0..=n {
                    for j in 0..=n - i {
                        let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                        let x = a + (b - a) * u + (c - a) * v;
                        max = max.max(to.distance2(x).map_or(0.0, f64::sqrt));
                    }
                }
            }
        }
        max
    }

    fn set(positions: &[[f32; 3]], faces: &Faces) -> TriangleSet {
        let p: Vec<DVec3> = positions
            .iter()
            .map(|x| DVec3::from(x.map(f64::from)))
            .collect();
        let t: Vec<[u32; 3]> = faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
        TriangleSet::new(&p, &t)
    }

    #[test]
    fn the_largest_distance_of_a_coarse_result_is_read_where_it_is() {
        // A creased, rippled height field (valleys where |sin| turns)
        // simplified to 3%: the result's chords bridge the creases,
        // farthest from the input along their edges. The sampled Hausdorff
        // is within 3% of one read on a grid of 24 steps a triangle (325
        // points, its edges included) in both directions; sampled at grid
        // centres and vertices alone it read 8% short.
        let (p, faces) = height_field(60, |x, y| {
            0.12 * (7.0 * x).sin().abs() * (1.0 + 0.5 * (5.0 * y).cos())
        });
        let options = Options {
            target: Target {
                ratio: Some(0.03),
                ..Target::default()
            },
            ..Options::default()
        };
        let lod = simplify_polygons(&p, &faces, &options).expect("simplifies");
        let sampled = Reference::new((&p, &faces)).fidelity((&lod.positions, &lod.faces));
        let dense = dense_one_way((&lod.positions, &lod.faces), &set(&p, &faces), 24).max(
            dense_one_way((&p, &faces), &set(&lod.positions, &lod.faces), 24),
        );
        assert!(
            sampled.hausdorff <= dense * (1.0 + 1e-9) && sampled.hausdorff >= 0.97 * dense,
            "sampled {} dense {dense}",
            sampled.hausdorff
        );
    }
}
