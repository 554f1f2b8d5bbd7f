//! Seeded, area-uniform surface sampling in fixed-size chunks.
//!
//! Determinism whatever the thread count: sample `i` of a stream is always
//! produced by chunk `i / CHUNK`, whose generator is seeded from (seed,
//! stream, chunk) alone, so which thread runs a chunk changes nothing.

use glam::DVec3;

use crate::eval_mesh::EvalMesh;

/// Samples per chunk: the unit of parallel work and of seeding.
pub(crate) const CHUNK: usize = 2048;

/// Independent sample streams of one comparison, so that drawing the
/// samples of the paired metrics does not move the geometric ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stream {
    /// Points measured against the other surface (Hausdorff, Chamfer).
    Surface = 1,
    /// Points paired with the other surface's (texture, normal and
    /// shading-normal Chamfer).
    Paired = 2,
}

/// Which sample set of a comparison a stream feeds. Each surface draws its
/// own random numbers: with one sequence for both, a candidate that keeps
/// input triangles unchanged (in the input's order) would get the very same
/// sample points on them, and the metrics that pair samples with samples
/// (texture and normal Chamfer) would fall below their own sampling floor,
/// flattering exactly such candidates (issue 31, decision 10). `Floor` is a
/// second, independent set on the reference: the reference against itself
/// with another seed, the noise any candidate is measured under.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    Reference = 0,
    Candidate = 1,
    Floor = 2,
}

/// SplitMix64 (Steele, Lea and Flood 2014): small, fast, and good enough
/// for Monte Carlo sampling; the same sequence on every platform.
#[derive(Clone, Debug)]
pub(crate) struct SplitMix64(u64);

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix64(self.0)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// SplitMix64's finalizer: a bijection that spreads every input bit.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The generator of one chunk of one stream of one side. The reference
/// side's sequence does not depend on the side tag (it is 0), so reference
/// samples are the same as before sides existed.
pub(crate) fn chunk_rng(seed: u64, stream: Stream, side: Side, chunk: usize) -> SplitMix64 {
    let tag = (stream as u64) << 56 ^ (side as u64) << 48 ^ chunk as u64;
    let s = mix64(seed ^ mix64(tag));
    SplitMix64::new(s)
}

/// A point on a surface: triangle, barycentrics, position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SurfacePoint {
    pub(crate) triangle: u32,
    pub(crate) bary: [f64; 3],
    pub(crate) point: DVec3,
}

/// Picks triangles with probability proportional to their area.
pub(crate) struct AreaSampler {
    /// Running sum of areas: `cdf[t]` is the area of triangles `0..=t`.
    cdf: Vec<f64>,
}

impl AreaSampler {
    /// Samples every triangle of `mesh` for which `keep` holds (all when
    /// `keep` is `None`).
    pub(crate) fn new(mesh: &EvalMesh, keep: Option<&[bool]>) -> Self {
        let mut acc = 0.0;
        let cdf = (0..mesh.triangles().len())
            .map(|t| {
                let a = mesh.triangle_area(t);
                // Non-finite areas (overflowing coordinates) get no samples,
                // nor do triangles left out (they get no interval).
                if a.is_finite() && keep.map_or(true, |k| k[t]) {
                    acc += a;
                }
                acc
            })
            .collect();
        AreaSampler { cdf }
    }

    /// Total area.
    pub(crate) fn total(&self) -> f64 {
        self.cdf.last().copied().unwrap_or(0.0)
    }

    /// True when there is an area to sample.
    pub(crate) fn can_sample(&self) -> bool {
        self.total() > 0.0
    }

    /// Samples `count` points of `stream` for `side` starting at sample `first` (a
    /// multiple of [`CHUNK`]): the whole of one chunk, or its first part.
    /// The caller guarantees [`AreaSampler::can_sample`].
    pub(crate) fn chunk(
        &self,
        mesh: &EvalMesh,
        seed: u64,
        (stream, side): (Stream, Side),
        chunk: usize,
        count: usize,
    ) -> Vec<SurfacePoint> {
        let mut rng = chunk_rng(seed, stream, side, chunk);
        let total = self.total();
        let last = self.cdf.len().saturating_sub(1);
        (0..count)
            .map(|_| {
                let x = rng.unit() * total;
                // First triangle whose running sum exceeds x: zero-area
                // triangles have no interval and are never chosen.
                let t = self.cdf.partition_point(|&c| c <= x).min(last);
                // Uniform on the triangle: √u folds the unit square onto
                // it with constant density (Osada et al. 2002, Eq. 1).
                let (r1, r2) = (rng.unit().sqrt(), rng.unit());
                let bary = [1.0 - r1, r1 * (1.0 - r2), r1 * r2];
                let [a, b, c] = mesh.triangle(t);
                SurfacePoint {
                    triangle: t as u32,
                    bary,
                    point: a * bary[0] + b * bary[1] + c * bary[2],
                }
            })
            .collect()
    }
}

/// Number of chunks for `n` samples.
pub(crate) fn chunk_count(n: usize) -> usize {
    n.div_ceil(CHUNK)
}

/// Number of samples in chunk `c` of `n`.
pub(crate) fn chunk_len(n: usize, c: usize) -> usize {
    CHUNK.min(n - c * CHUNK)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunk_streams_differ_and_repeat() {
        let r = Side::Reference;
        let a: Vec<u64> = (0..4)
            .map(|_| chunk_rng(1, Stream::Surface, r, 0).next_u64())
            .collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        let x = chunk_rng(1, Stream::Surface, r, 0).next_u64();
        let y = chunk_rng(1, Stream::Surface, r, 1).next_u64();
        let z = chunk_rng(1, Stream::Paired, r, 0).next_u64();
        let w = chunk_rng(2, Stream::Surface, r, 0).next_u64();
        let c = chunk_rng(1, Stream::Surface, Side::Candidate, 0).next_u64();
        let f = chunk_rng(1, Stream::Surface, Side::Floor, 0).next_u64();
        let all = [x, y, z, w, c, f];
        for i in 0..all.len() {
            for j in 0..i {
                assert_ne!(all[i], all[j], "streams {i} and {j}");
            }
        }
    }

    #[test]
    fn unit_is_in_the_half_open_interval_with_mean_one_half() {
        let mut r = SplitMix64::new(3);
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let u = r.unit();
            assert!((0.0..1.0).contains(&u));
            sum += u;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.005);
    }

    #[test]
    fn samples_follow_area_and_skip_zero_area_triangles() {
        // Triangle 0 has area 1/2, triangle 1 is degenerate, triangle 2 has
        // area 3/2 (three times 0): expect a 1 : 0 : 3 split.
        let m = wildlod_mesh::Mesh::from_triangles(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0, 0.0, 0.0],
                [3.0, 0.0, 0.0],
                [5.0, 0.0, 0.0],
                [5.0, 1.5, 0.0],
            ],
            &[0, 1, 2, 3, 4, 3, 4, 5, 6],
        );
        let e = EvalMesh::from_mesh(&m);
        let s = AreaSampler::new(&e, None);
        assert!((s.total() - 2.0).abs() < 1e-12);
        let pts = s.chunk(&e, 9, (Stream::Surface, Side::Reference), 0, CHUNK);
        let mut hist = [0usize; 3];
        for p in &pts {
            hist[p.triangle as usize] += 1;
            let [a, b, c] = e.triangle(p.triangle as usize);
            let back = a * p.bary[0] + b * p.bary[1] + c * p.bary[2];
            assert_eq!(back, p.point);
            assert!(p.bary.iter().all(|&w| (0.0..=1.0).contains(&w)));
        }
        assert_eq!(hist[1], 0);
        let frac = hist[0] as f64 / CHUNK as f64;
        assert!((frac - 0.25).abs() < 0.03, "{frac}");
        // Leaving triangle 2 out puts every sample on triangle 0.
        let s = AreaSampler::new(&e, Some(&[true, true, false]));
        assert!((s.total() - 0.5).abs() < 1e-12);
        let pts = s.chunk(&e, 9, (Stream::Surface, Side::Reference), 0, CHUNK);
        assert!(pts.iter().all(|p| p.triangle == 0));
    }

    #[test]
    fn triangle_samples_have_uniform_density() {
        // On the right triangle (0,0), (1,0), (0,1) a uniform density gives
        // E[x] = E[y] = 1/3 and P(x + y < 1/2) = 1/4.
        let m = wildlod_mesh::Mesh::from_triangles(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2],
        );
        let e = EvalMesh::from_mesh(&m);
        let s = AreaSampler::new(&e, None);
        let mut n = 0;
        let (mut sx, mut sy, mut inner) = (0.0, 0.0, 0);
        for c in 0..20 {
            for p in s.chunk(&e, 4, (Stream::Paired, Side::Candidate), c, CHUNK) {
                n += 1;
                sx += p.point.x;
                sy += p.point.y;
                if p.point.x + p.point.y < 0.5 {
                    inner += 1;
                }
            }
        }
        let n = n as f64;
        assert!((sx / n - 1.0 / 3.0).abs() < 0.005);
        assert!((sy / n - 1.0 / 3.0).abs() < 0.005);
        assert!((inner as f64 / n - 0.25).abs() < 0.005);
    }
}
