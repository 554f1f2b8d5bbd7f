//! How coarse a texture may be sampled before its content visibly changes:
//! the floor under a level's smaller atlas
//! ([`crate::BakeOptions::density_follows_level`]).
//!
//! A smooth texture (a scan's gradients, a painted albedo) loses nothing
//! at a quarter of its resolution; a character's face or printed text does.
//! So before an atlas is made smaller than the input's density, the input
//! image is averaged over k × k blocks (the box filter a mip level is) and
//! compared with itself: the mean colour distance between every texel and
//! its block's mean is what the smaller atlas could at best show, and it
//! must stay below [`VISIBLE_BLUR`].

use wildlod_mesh::Rgba8Image;

/// Mean colour difference (RGB in 0..1, Euclidean, as the texture Chamfer
/// distance measures colours) that counts as visible: about one
/// just-noticeable step, the threshold `wildlod_pipeline` uses to decide
/// whether a keep-UV texture needs a re-bake.
pub const VISIBLE_BLUR: f64 = 0.01;

/// [`ImageAnalysis::blur`] of `img`.
#[cfg(test)]
pub(crate) fn block_blur(img: &Rgba8Image, used: &[bool], max_k: u32) -> Vec<f64> {
    ImageAnalysis::new(img).blur(used, max_k)
}

/// The sums of one image's `k × k` blocks (clipped at the border).
struct BlockLevel {
    bw: usize,
    sums: Vec<[f64; 3]>,
    counts: Vec<u32>,
}

/// What a bake reads of one input image's content, computed once however
/// many meshes use it (a scene of many meshes sharing a texture computed
/// it once per mesh: quadratic). Levels are computed as first asked for,
/// from any thread.
pub(crate) struct ImageAnalysis<'a> {
    img: &'a Rgba8Image,
    /// Block sums for `k = 2^(j+1)`.
    levels: Vec<std::sync::OnceLock<BlockLevel>>,
    /// Per 2 × 2 block, the mean distance of its texels to its mean
    /// (`density.rs`).
    detail: std::sync::OnceLock<(usize, usize, Vec<f32>)>,
}

impl<'a> ImageAnalysis<'a> {
    pub(crate) fn new(img: &'a Rgba8Image) -> Self {
        let (w, h) = (img.width as usize, img.height as usize);
        let mut count = 0;
        let mut k = 2usize;
        while k / 2 < w || k / 2 < h {
            count += 1;
            k = k.saturating_mul(2);
        }
        ImageAnalysis {
            img,
            levels: (0..count).map(|_| std::sync::OnceLock::new()).collect(),
            detail: std::sync::OnceLock::new(),
        }
    }

    fn texel(&self, i: usize) -> [f64; 3] {
        let p = self.img.pixels[i];
        [p[0], p[1], p[2]].map(|c| f64::from(c) / 255.0)
    }

    fn level(&self, j: usize) -> &BlockLevel {
        self.levels[j].get_or_init(|| {
            let (w, h) = (self.img.width as usize, self.img.height as usize);
            let k = 2usize << j;
            let (bw, bh) = (w.div_ceil(k), h.div_ceil(k));
            let mut sums = vec![[0.0f64; 3]; bw * bh];
            let mut counts = vec![0u32; bw * bh];
            for y in 0..h {
                for x in 0..w {
                    let b = (y / k) * bw + x / k;
                    let t = self.texel(y * w + x);
                    for c in 0..3 {
                        sums[b][c] += t[c];
                    }
                    counts[b] += 1;
                }
            }
            BlockLevel { bw, sums, counts }
        })
    }

    /// Mean colour distance between every texel of the image that `used`
    /// marks (all when empty) and the mean of its `k × k` block (blocks
    /// clipped at the border), for `k` = 2, 4, 8, … up to `max_k`: entry
    /// `j` is for `k = 2^(j+1)`.
    pub(crate) fn blur(&self, used: &[bool], max_k: u32) -> Vec<f64> {
        let (w, h) = (self.img.width as usize, self.img.height as usize);
        if w == 0 || h == 0 {
            return Vec::new();
        }
        let mut out = Vec::new();
        let mut k = 2usize;
        let mut j = 0;
        while k as u32 <= max_k.max(2) && (k / 2 < w || k / 2 < h) {
            let level = self.level(j);
            let (mut total, mut n_used) = (0.0, 0usize);
            for y in 0..h {
                for x in 0..w {
                    if !used.is_empty() && !used[y * w + x] {
                        continue;
                    }
                    n_used += 1;
                    let b = (y / k) * level.bw + x / k;
                    let n = f64::from(level.counts[b]);
                    let t = self.texel(y * w + x);
                    let d2: f64 = (0..3).map(|c| (t[c] - level.sums[b][c] / n).powi(2)).sum();
                    total += d2.sqrt();
                }
            }
            out.push(if n_used == 0 {
                0.0
            } else {
                total / n_used as f64
            });
            k *= 2;
            j += 1;
        }
        out
    }

    /// The smallest linear scale, `1` or `1/k` for a power of two `k`, at
    /// least `min_scale`, at which the image keeps its content within
    /// [`VISIBLE_BLUR`] over the texels `used` marks (see [`Self::blur`]).
    pub(crate) fn content_scale(&self, used: &[bool], min_scale: f64) -> f64 {
        content_scale_of(|max_k| self.blur(used, max_k), min_scale)
    }

    /// The image's 2 × 2 block detail (see `density.rs`), computed once.
    pub(crate) fn detail(
        &self,
        f: impl FnOnce(&Rgba8Image) -> (usize, usize, Vec<f32>),
    ) -> &(usize, usize, Vec<f32>) {
        self.detail.get_or_init(|| f(self.img))
    }
}

/// One [`ImageAnalysis`] per image of a bake's input (`None` where the
/// image did not decode), shared by all the meshes that read them.
pub(crate) struct ImageAnalyses<'a> {
    images: &'a [Option<Rgba8Image>],
    per: Vec<Option<ImageAnalysis<'a>>>,
    /// Content scales already found, by image, level scale and the UV
    /// triangles read (meshes with the same UVs, such as copies of one
    /// object or surfaces tiling one texture, share the answer).
    scales: std::sync::Mutex<ScaleCache>,
}

/// Key: image, `min_scale`'s bits, the UV triangles' bits.
type ScaleCache = std::collections::HashMap<(usize, u64, Vec<[[u32; 2]; 3]>), f64>;

impl<'a> ImageAnalyses<'a> {
    pub(crate) fn new(images: &'a [Option<Rgba8Image>]) -> Self {
        ImageAnalyses {
            images,
            per: images
                .iter()
                .map(|i| i.as_ref().map(ImageAnalysis::new))
                .collect(),
            scales: std::sync::Mutex::new(ScaleCache::new()),
        }
    }

    /// [`ImageAnalysis::content_scale`] of image `t` of `images` over the texels the UV
    /// triangles `tris` cover ([`uv_coverage`]), found once per distinct
    /// triangles.
    pub(crate) fn content_scale(
        &self,
        images: &[Option<Rgba8Image>],
        t: usize,
        tris: &[[[f32; 2]; 3]],
        min_scale: f64,
    ) -> Option<f64> {
        let img = images.get(t)?.as_ref()?;
        let compute = |a: &ImageAnalysis| {
            let used = uv_coverage(img.width, img.height, tris);
            a.content_scale(&used, min_scale)
        };
        let Some(a) = self.get(images, t) else {
            return Some(compute(&ImageAnalysis::new(img)));
        };
        let key = (
            t,
            min_scale.to_bits(),
            tris.iter()
                .map(|q| q.map(|p| p.map(f32::to_bits)))
                .collect::<Vec<_>>(),
        );
        if let Some(&v) = self.scales.lock().ok()?.get(&key) {
            return Some(v);
        }
        // Computed outside the lock: meshes in parallel do not wait on
        // each other (two may compute one answer, which is the same).
        let v = compute(a);
        if let Ok(mut m) = self.scales.lock() {
            m.insert(key, v);
        }
        Some(v)
    }

    /// The analysis of image `t` of `images`, when `images` is the slice
    /// these analyses were made for (a mesh reading other images gets a
    /// fresh one).
    pub(crate) fn get(
        &self,
        images: &[Option<Rgba8Image>],
        t: usize,
    ) -> Option<&ImageAnalysis<'a>> {
        if !std::ptr::eq(self.images, images) {
            return None;
        }
        self.per.get(t)?.as_ref()
    }
}

/// [`ImageAnalysis::content_scale`] of `img`.
#[cfg(test)]
pub(crate) fn content_scale(img: &Rgba8Image, used: &[bool], min_scale: f64) -> f64 {
    ImageAnalysis::new(img).content_scale(used, min_scale)
}

/// [`ImageAnalysis::content_scale`] from the image's blur up to a block size.
fn content_scale_of(blur: impl FnOnce(u32) -> Vec<f64>, min_scale: f64) -> f64 {
    if !(min_scale > 0.0 && min_scale < 1.0) {
        return 1.0;
    }
    // Up to the first power of two at or past the level's own scale: a
    // texture that survives averaging over it may follow the level all
    // the way.
    let max_k = ((1.0 / min_scale).ceil().min(f64::from(1u32 << 30)) as u32).next_power_of_two();
    let mut scale = 1.0;
    for (j, blur) in blur(max_k).into_iter().enumerate() {
        if blur > VISIBLE_BLUR {
            break;
        }
        scale = 1.0 / f64::from(1u32 << (j + 1));
    }
    scale.max(min_scale)
}

/// The texels of a `width × height` image that the UV triangles `uvs`
/// (three UV pairs each, wrapped into [0, 1) as a repeating sampler reads
/// them) cover, with every texel a triangle touches counted: what a
/// surface shows of the image, so that unused atlas space and gutters do
/// not water down [`ImageAnalysis::blur`].
pub(crate) fn uv_coverage(width: u32, height: u32, uvs: &[[[f32; 2]; 3]]) -> Vec<bool> {
    let (w, h) = (width as usize, height as usize);
    let mut used = vec![false; w * h];
    for tri in uvs {
        // One wrap for the whole triangle (by its lowest corner), so it
        // stays in one piece.
        let du = tri
            .iter()
            .map(|q| q[0])
            .fold(f32::INFINITY, f32::min)
            .floor();
        let dv = tri
            .iter()
            .map(|q| q[1])
            .fold(f32::INFINITY, f32::min)
            .floor();
        let p = tri.map(|q| [(q[0] - du) * width as f32, (q[1] - dv) * height as f32]);
        let lo = [0, 1].map(|a| p.iter().map(|q| q[a]).fold(f32::INFINITY, f32::min).floor());
        let hi = [0, 1].map(|a| {
            p.iter()
                .map(|q| q[a])
                .fold(f32::NEG_INFINITY, f32::max)
                .ceil()
        });
        if !(lo[0].is_finite() && hi[0].is_finite() && lo[1].is_finite() && hi[1].is_finite()) {
            continue;
        }
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        for y in (lo[1] as i64).max(0)..(hi[1] as i64).min(2 * h as i64) {
            for x in (lo[0] as i64).max(0)..(hi[0] as i64).min(2 * w as i64) {
                let c = [x as f32 + 0.5, y as f32 + 0.5];
                let inside = area.abs() < 1e-12 || {
                    let e = |a: [f32; 2], b: [f32; 2]| {
                        (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
                    };
                    let s = [e(p[0], p[1]), e(p[1], p[2]), e(p[2], p[0])];
                    // Within half a texel of the triangle counts: a
                    // sliver still shows the texels it crosses.
                    let slack = 0.75 * area.abs().sqrt().max(1.0);
                    s.iter().all(|&v| v * area.signum() >= -slack)
                };
                if inside {
                    used[(y as usize % h) * w + x as usize % w] = true;
                }
            }
        }
    }
    used
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Rgba8Image {
        let mut pixels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                pixels.push(f(x, y));
            }
        }
        Rgba8Image {
            width: w,
            height: h,
            pixels,
        }
    }

    #[test]
    fn block_blur_is_the_mean_distance_to_the_block_mean() {
        // Columns alternating 0 and 255 in red: every 2 × 2 block's mean is
        // 127.5/255 = 0.5, every texel 0.5 away from it.
        let stripes = image(4, 4, |x, _| [if x % 2 == 0 { 0 } else { 255 }, 0, 0, 255]);
        let b = block_blur(&stripes, &[], 4);
        assert_eq!(b.len(), 2);
        assert!(
            (b[0] - 0.5).abs() < 1e-12 && (b[1] - 0.5).abs() < 1e-12,
            "{b:?}"
        );
        // A flat image loses nothing.
        let flat = image(8, 8, |_, _| [10, 200, 30, 255]);
        assert!(block_blur(&flat, &[], 8).iter().all(|&e| e < 1e-12));
        // One grey step of 3/255 in one corner texel of a 2 × 2 block:
        // mean moves by 0.75 of it; the texel is 3/4·√3·3/255 away, the
        // three others 1/4·√3·3/255; mean over the block's 4 texels.
        let corner = image(2, 2, |x, y| {
            if x == 0 && y == 0 {
                [3, 3, 3, 255]
            } else {
                [0, 0, 0, 255]
            }
        });
        let want = (0.75 + 3.0 * 0.25) * 3f64.sqrt() * 3.0 / 255.0 / 4.0;
        assert!((block_blur(&corner, &[], 2)[0] - want).abs() < 1e-12);
        // Only the texels a surface uses count: the dark three alone.
        let used = [false, true, true, true];
        let dark = 3f64.sqrt() * 3.0 * 0.25 / 255.0;
        assert!((block_blur(&corner, &used, 2)[0] - dark).abs() < 1e-12);
    }

    /// A 64² image: a slow gradient on the left half, a checker of single
    /// texels on the right.
    fn half_smooth_half_checker() -> Rgba8Image {
        image(64, 64, |x, y| {
            if x < 32 {
                [(x / 2) as u8, (y / 2) as u8, 128, 255]
            } else {
                let v = if (x + y) % 2 == 0 { 0 } else { 255 };
                [v, v, v, 255]
            }
        })
    }

    #[test]
    fn smooth_textures_shrink_to_the_level_and_detailed_ones_do_not() {
        // A slow gradient: any block's texels are within a level or two of
        // its mean, so the atlas may follow the level down to 1/8.
        let smooth = image(64, 64, |x, y| [(x / 2) as u8, (y / 2) as u8, 128, 255]);
        assert_eq!(content_scale(&smooth, &[], 0.1), 0.125);
        // Never below the level's own scale, and down to it when the next
        // power of two past it keeps the content.
        assert_eq!(content_scale(&smooth, &[], 0.3), 0.3);
        // A checker of single texels (printed text, a fine pattern): any
        // averaging erases it, so the input's density stays.
        let checker = image(64, 64, |x, y| {
            let v = if (x + y) % 2 == 0 { 0 } else { 255 };
            [v, v, v, 255]
        });
        assert_eq!(content_scale(&checker, &[], 0.1), 1.0);
        // A level that keeps everything needs no scaling.
        assert_eq!(content_scale(&checker, &[], 1.0), 1.0);
        // Half smooth, half checker: the checker half decides if a surface
        // uses it, not if only the smooth half is mapped.
        let half = half_smooth_half_checker();
        let left = uv_coverage(64, 64, &[[[0.0, 0.0], [0.49, 0.0], [0.0, 1.0]]]);
        assert!(
            left[0] && !left[63],
            "the triangle covers the left side only"
        );
        assert_eq!(content_scale(&half, &left, 0.1), 0.125);
        let all = uv_coverage(
            64,
            64,
            &[
                [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
                [[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            ],
        );
        assert!(all.iter().all(|&u| u));
        assert_eq!(content_scale(&half, &all, 0.1), 1.0);
    }

    #[test]
    fn shared_analyses_answer_each_mesh_for_its_own_uvs() {
        // One image read by meshes with different UVs: the smooth half and
        // the checker half get their own scales, asked in any order and
        // again (the second time from the cache), as the uncached
        // function gives them.
        let half = half_smooth_half_checker();
        let images = [Some(half)];
        let shared = ImageAnalyses::new(&images);
        let left = [[[0.0, 0.0], [0.49, 0.0], [0.0, 1.0]]];
        let right = [[[0.55, 0.0], [1.0, 0.0], [1.0, 1.0]]];
        let img = images[0].as_ref().expect("image");
        for tris in [&left[..], &right[..], &left[..], &right[..]] {
            let direct = content_scale(img, &uv_coverage(64, 64, tris), 0.1);
            assert_eq!(shared.content_scale(&images, 0, tris, 0.1), Some(direct));
        }
        assert_eq!(shared.content_scale(&images, 0, &left, 0.1), Some(0.125));
        assert_eq!(shared.content_scale(&images, 0, &right, 0.1), Some(1.0));
        // Another image list is not the shared one: computed afresh.
        let other = images.clone();
        assert_eq!(shared.content_scale(&other, 0, &right, 0.1), Some(1.0));
    }
}
