//! The material channels of a point of the input surface, and how they are
//! stored in re-baked images.
//!
//! Every channel of the glTF metallic-roughness model is evaluated as a
//! renderer would: base color = factor × texture × vertex color, colors
//! filtered in linear space (GPUs decode sRGB before filtering), metallic
//! and roughness from the texture's B and G channels times their factors,
//! occlusion from R, emissive = factor × texture, and the shading normal
//! from the normal map in the input's own tangent frame. Factors are baked
//! in, so the output material's factors are 1 and materials with different
//! factors can share one atlas.
//!
//! Normals are re-expressed in the *output* tangent frame (MikkTSpace of
//! the new UVs, [`wildlod_mesh::tangents`]) at the texel, or lighting
//! breaks: the same world-space normal has different tangent-space
//! coordinates under a different parametrization.

use std::sync::OnceLock;

use glam::Vec3;
use wildlod_mesh::{
    AlphaMode, Attribute, Material, Mesh, Rgba8Image, Sampler, Semantic, Texture, TextureRef, Wrap,
    ABSENT,
};

use crate::mapping::SurfacePoint;

/// A channel of a re-baked material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Channel {
    /// Base color (sRGB) and alpha.
    BaseColor,
    /// Metallic (B) and roughness (G), linear; occlusion in R when the
    /// material has both (glTF's packed "ORM" layout).
    MetallicRoughness,
    /// Tangent-space normal, linear, +Y up the image.
    Normal,
    /// Ambient occlusion (R), linear.
    Occlusion,
    /// Emissive color, sRGB.
    Emissive,
}

impl Channel {
    /// Every channel, in the order of [`Material::texture_refs`].
    pub const ALL: [Channel; 5] = [
        Channel::BaseColor,
        Channel::MetallicRoughness,
        Channel::Normal,
        Channel::Occlusion,
        Channel::Emissive,
    ];

    /// Short name, for image file names.
    pub fn name(self) -> &'static str {
        match self {
            Channel::BaseColor => "baseColor",
            Channel::MetallicRoughness => "metallicRoughness",
            Channel::Normal => "normal",
            Channel::Occlusion => "occlusion",
            Channel::Emissive => "emissive",
        }
    }

    /// The material's texture for this channel.
    pub fn texture(self, m: &Material) -> Option<TextureRef> {
        match self {
            Channel::BaseColor => m.base_color_texture,
            Channel::MetallicRoughness => m.metallic_roughness_texture,
            Channel::Normal => m.normal_texture,
            Channel::Occlusion => m.occlusion_texture,
            Channel::Emissive => m.emissive_texture,
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// sRGB-encoded 8-bit value → linear, exact per the sRGB curve.
pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear → sRGB-encoded value in [0, 1].
pub(crate) fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// [0, 1] → u8, rounded.
pub(crate) fn quantize(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// A decoded texture with its wrap modes, sampled bilinearly.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TextureSampler<'a> {
    image: &'a Rgba8Image,
    sampler: Sampler,
    /// Whether RGB is sRGB-encoded (decoded to linear before filtering).
    srgb: bool,
}

fn wrap(i: i64, n: i64, mode: Wrap) -> i64 {
    match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m < n {
                m
            } else {
                2 * n - 1 - m
            }
        }
    }
}

impl TextureSampler<'_> {
    /// Bilinear lookup at `uv` (glTF: `v = 0` is the top row, texel
    /// centers at half-integers), linear values.
    pub(crate) fn sample(&self, uv: [f32; 2], lut: &[f32; 256]) -> [f32; 4] {
        self.bilinear(self.image, uv, lut)
    }

    /// Bilinear lookup in `image` (the texture or one of its mip levels,
    /// stored in the texture's encoding).
    fn bilinear(&self, image: &Rgba8Image, uv: [f32; 2], lut: &[f32; 256]) -> [f32; 4] {
        let (w, h) = (image.width as i64, image.height as i64);
        if w == 0 || h == 0 || !(uv[0].is_finite() && uv[1].is_finite()) {
            return [1.0; 4];
        }
        let x = uv[0] as f64 * w as f64 - 0.5;
        let y = uv[1] as f64 * h as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let xs = [x0, x0 + 1].map(|i| wrap(i, w, self.sampler.wrap_u) as usize);
        let ys = [y0, y0 + 1].map(|i| wrap(i, h, self.sampler.wrap_v) as usize);
        let texel = |xi: usize, yi: usize| {
            let p = image.pixels[yi * w as usize + xi];
            let lin = |v: u8| {
                if self.srgb {
                    lut[v as usize]
                } else {
                    v as f32 / 255.0
                }
            };
            [lin(p[0]), lin(p[1]), lin(p[2]), p[3] as f32 / 255.0]
        };
        let (a, b) = (texel(xs[0], ys[0]), texel(xs[1], ys[0]));
        let (c, d) = (texel(xs[0], ys[1]), texel(xs[1], ys[1]));
        let mut out = [0.0; 4];
        for k in 0..4 {
            let top = a[k] + (b[k] - a[k]) * fx;
            let bottom = c[k] + (d[k] - c[k]) * fx;
            out[k] = top + (bottom - top) * fy;
        }
        out
    }

    /// The average of the texture over the footprint of an output texel:
    /// `axes` are the UV offsets of one output texel step along x and y.
    /// Where the footprint covers at most one input texel (or is unknown)
    /// this is [`TextureSampler::sample`], bilinear at level 0. Beyond, the
    /// footprint's parallelogram is supersampled with a grid of up to
    /// [`BOX_TAPS`]² bilinear lookups at the finest mip level whose texels
    /// are at least the grid's spacing (level 0 up to 4 input texels
    /// across), so that a texel averages every input texel it covers
    /// instead of aliasing them, with little blur beyond the footprint (a
    /// GPU's trilinear lookup at the footprint's level blurs about twice
    /// as wide, and measured slightly worse). `mips` holds the
    /// box-filtered levels 1, 2, …, built on first use.
    pub(crate) fn sample_filtered(
        &self,
        uv: [f32; 2],
        axes: Option<[[f32; 2]; 2]>,
        mips: &OnceLock<Vec<Rgba8Image>>,
        lut: &[f32; 256],
    ) -> [f32; 4] {
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        let Some(axes) = axes else {
            return self.sample(uv, lut);
        };
        // The axes' lengths in input texels.
        let len = axes.map(|a| ((a[0] * w).powi(2) + (a[1] * h).powi(2)).sqrt());
        let major = len[0].max(len[1]);
        if !(len[0].is_finite() && len[1].is_finite()) || major <= 1.0 {
            return self.sample(uv, lut);
        }
        let levels = mips.get_or_init(|| mip_levels(self.image, self.srgb, lut));
        let l = ((major / BOX_TAPS as f32).log2().ceil().max(0.0) as usize).min(levels.len());
        let image = if l == 0 { self.image } else { &levels[l - 1] };
        let cell = (1u64 << l) as f32;
        let n = len.map(|x| ((x / cell).ceil() as usize).clamp(1, BOX_TAPS));
        let mut out = [0.0f32; 4];
        for i in 0..n[0] {
            let s = (i as f32 + 0.5) / n[0] as f32 - 0.5;
            for j in 0..n[1] {
                let t = (j as f32 + 0.5) / n[1] as f32 - 0.5;
                let p = [
                    uv[0] + axes[0][0] * s + axes[1][0] * t,
                    uv[1] + axes[0][1] * s + axes[1][1] * t,
                ];
                let c = self.bilinear(image, p, lut);
                for k in 0..4 {
                    out[k] += c[k];
                }
            }
        }
        out.map(|v| v / (n[0] * n[1]) as f32)
    }
}

/// Most lookups per axis of a footprint: 16 per texel at most.
const BOX_TAPS: usize = 4;

/// Mip levels 1, 2, … down to 1 × 1 of `image`: each texel the mean of the
/// 2 × 2 texels under it (the last row or column of an odd size averages
/// what there is), averaged in linear space (`srgb`: RGB decoded first and
/// encoded back, as GPUs build sRGB mips), from full-precision sums of the
/// level above so that rounding does not pile up.
pub(crate) fn mip_levels(image: &Rgba8Image, srgb: bool, lut: &[f32; 256]) -> Vec<Rgba8Image> {
    let decode = |p: [u8; 4]| {
        let c = |v: u8| {
            if srgb {
                lut[v as usize]
            } else {
                v as f32 / 255.0
            }
        };
        [c(p[0]), c(p[1]), c(p[2]), p[3] as f32 / 255.0]
    };
    // Linear → stored byte: for sRGB, the number of byte midpoints below
    // the value (exact rounding of the curve, without a `powf` per texel).
    let midpoints: Vec<f32> = (0..255)
        .map(|i| srgb_to_linear((i as f32 + 0.5) / 255.0))
        .collect();
    let encode = |v: f32| -> u8 {
        if srgb {
            midpoints.partition_point(|&m| m < v) as u8
        } else {
            quantize(v)
        }
    };
    let (mut w, mut h) = (image.width as usize, image.height as usize);
    // Level 1 reads the image itself; later levels the unrounded values of
    // the level above (a quarter of the image's size, not a copy of it).
    let mut cur: Vec<[f32; 4]> = Vec::new();
    let mut out = Vec::new();
    while w > 1 || h > 1 {
        let (nw, nh) = (w.div_ceil(2).max(1), h.div_ceil(2).max(1));
        let mut next = vec![[0.0f32; 4]; nw * nh];
        for y in 0..nh {
            for x in 0..nw {
                let mut sum = [0.0f32; 4];
                let mut n = 0.0;
                for yy in 2 * y..(2 * y + 2).min(h) {
                    for xx in 2 * x..(2 * x + 2).min(w) {
                        let p = if out.is_empty() {
                            decode(image.pixels[yy * w + xx])
                        } else {
                            cur[yy * w + xx]
                        };
                        for k in 0..4 {
                            sum[k] += p[k];
                        }
                        n += 1.0;
                    }
                }
                next[y * nw + x] = sum.map(|v| v / n);
            }
        }
        let pixels = next
            .iter()
            .map(|p| [encode(p[0]), encode(p[1]), encode(p[2]), quantize(p[3])])
            .collect();
        out.push(Rgba8Image {
            width: nw as u32,
            height: nh as u32,
            pixels,
        });
        cur = next;
        (w, h) = (nw, nh);
    }
    out
}

/// Mip levels of every (image, encoding) a channel samples, built the
/// first time a texel's footprint needs them (most bakes shrink some
/// charts, few need every image's chain). One per image list, shared by
/// every mesh baked from it: meshes sharing a material must not each hold
/// its images' chains.
pub(crate) struct MipCache {
    /// Slot `2 t + srgb`: texture `t` decoded as sRGB or not.
    slots: Vec<OnceLock<Vec<Rgba8Image>>>,
}

impl MipCache {
    /// An empty cache for `textures` images.
    pub(crate) fn new(textures: usize) -> Self {
        MipCache {
            slots: (0..2 * textures).map(|_| OnceLock::new()).collect(),
        }
    }

    fn slot(texture: u32, srgb: bool) -> usize {
        2 * texture as usize + usize::from(srgb)
    }
}

/// One input material, resolved for sampling.
struct Resolved<'a> {
    material: Material,
    /// Per channel: the texture, the UV stream it reads and its slot in
    /// [`MipCache`].
    textures: [Option<(TextureSampler<'a>, &'a Attribute, usize)>; 5],
}

/// Everything needed to evaluate the input's channels at a surface point.
pub(crate) struct InputChannels<'a> {
    mesh: &'a Mesh,
    /// Per part: index into `resolved` (the default material when none).
    part_material: Vec<usize>,
    resolved: Vec<Resolved<'a>>,
    colors: Option<&'a Attribute>,
    /// Per-corner shading normals (the stream, else face normals).
    normals: Vec<Vec3>,
    /// Per-corner tangents (xyz, w) for the normal map's UV set, when a
    /// normal map exists.
    tangents: Option<Vec<[f32; 4]>>,
    lut: [f32; 256],
    /// Mip chains of `images`, shared with the other meshes baked from
    /// them.
    mips: &'a MipCache,
}

/// An output texel's footprint on the surface: how far its surface point
/// moves for one texel step along the atlas's x and along its y.
pub(crate) type Footprint = [Vec3; 2];

/// The [`Footprint`] of the texels of a triangle with corners at
/// `positions` and at `uvs` in the atlas (texels); `None` for a triangle
/// degenerate in either.
pub(crate) fn texel_footprint(positions: [[f32; 3]; 3], uvs: [[f32; 2]; 3]) -> Option<Footprint> {
    let p = positions.map(Vec3::from);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (du1, dv1) = (uvs[1][0] - uvs[0][0], uvs[1][1] - uvs[0][1]);
    let (du2, dv2) = (uvs[2][0] - uvs[0][0], uvs[2][1] - uvs[0][1]);
    let det = du1 * dv2 - du2 * dv1;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // P(u, v) = p0 + e1 s + e2 t with (s, t) = M⁻¹ (u − u0, v − v0).
    let dx = (e1 * dv2 - e2 * dv1) / det;
    let dy = (e2 * du1 - e1 * du2) / det;
    (dx.is_finite() && dy.is_finite()).then_some([dx, dy])
}

/// Values of all channels at one point, linear (normals: world space).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PointChannels {
    pub base: [f32; 4],
    /// For an alpha-tested (`MASK`) material: whether the input point
    /// passes the test unfiltered (a point sample; see `alpha_coverage.rs`).
    pub passes_alpha_test: Option<bool>,
    pub metal: f32,
    pub rough: f32,
    pub occlusion: f32,
    pub emissive: [f32; 3],
    pub normal: Vec3,
}

impl<'a> InputChannels<'a> {
    /// Resolves the mesh's materials; `images[t]` is texture `t` decoded
    /// (or `None` when it could not be: its channel then uses the factor);
    /// `mips` is the mip cache of `images` (`MipCache::new(images.len())`).
    pub(crate) fn new(
        mesh: &'a Mesh,
        materials: &'a [Material],
        textures: &'a [Texture],
        images: &'a [Option<Rgba8Image>],
        tangents: Option<Vec<[f32; 4]>>,
        mips: &'a MipCache,
    ) -> Self {
        let mut resolved = Vec::with_capacity(materials.len() + 1);
        // One mip chain per (texture, sRGB or not), shared by every
        // material, channel and mesh that samples it.
        let resolve = |m: &Material| {
            let mut t: [Option<(TextureSampler<'a>, &'a Attribute, usize)>; 5] = [None; 5];
            for ch in Channel::ALL {
                let Some(r) = ch.texture(m) else { continue };
                let image = images.get(r.texture as usize).and_then(Option::as_ref);
                let uv = mesh.attribute(&Semantic::TexCoord(r.tex_coord));
                let sampler = textures
                    .get(r.texture as usize)
                    .map(|t| t.sampler)
                    .unwrap_or_default();
                if let (Some(image), Some(uv)) = (image, uv) {
                    let srgb = matches!(ch, Channel::BaseColor | Channel::Emissive);
                    let slot = MipCache::slot(r.texture, srgb);
                    t[ch.index()] = Some((
                        TextureSampler {
                            image,
                            sampler,
                            srgb,
                        },
                        uv,
                        slot,
                    ));
                }
            }
            t
        };
        for m in materials {
            resolved.push(Resolved {
                material: m.clone(),
                textures: resolve(m),
            });
        }
        // glTF's default material for parts without one.
        let default = resolved.len();
        resolved.push(Resolved {
            material: Material::default(),
            textures: [None; 5],
        });
        let part_material = mesh
            .parts
            .iter()
            .map(|p| {
                p.material
                    .map(|m| m as usize)
                    .filter(|&m| m < materials.len())
                    .unwrap_or(default)
            })
            .collect();
        let mut lut = [0.0f32; 256];
        for (i, v) in lut.iter_mut().enumerate() {
            *v = srgb_to_linear(i as f32 / 255.0);
        }
        InputChannels {
            mesh,
            part_material,
            resolved,
            colors: mesh.attribute(&Semantic::Color(0)),
            normals: corner_normals(mesh),
            tangents,
            lut,
            mips,
        }
    }

    fn material_of(&self, face: u32) -> &Resolved<'a> {
        let part = self.mesh.face_parts[face as usize] as usize;
        let m = self
            .part_material
            .get(part)
            .copied()
            .unwrap_or(self.resolved.len() - 1);
        &self.resolved[m]
    }

    /// The material (as read) of an input face.
    pub(crate) fn material(&self, face: u32) -> &Material {
        &self.material_of(face).material
    }

    fn interpolate<const N: usize>(a: &Attribute, s: &SurfacePoint) -> Option<[f32; N]> {
        let mut out = [0.0; N];
        for (k, &c) in s.corners.iter().enumerate() {
            let v = a.corner_value(c as usize)?;
            for (i, o) in out.iter_mut().enumerate() {
                *o += s.bary[k] * v.get(i).copied().unwrap_or(if i == 3 { 1.0 } else { 0.0 });
            }
        }
        Some(out)
    }

    /// The UV offsets, in UV stream `uv` of the input face under `s`, of
    /// the surface offsets `footprint` (projected onto the face's plane):
    /// the input texture's derivatives along an output texel's axes.
    fn uv_axes(
        &self,
        uv: &Attribute,
        s: &SurfacePoint,
        footprint: &Footprint,
    ) -> Option<[[f32; 2]; 2]> {
        let p = s
            .corners
            .map(|c| Vec3::from(self.mesh.positions[self.mesh.faces.indices[c as usize] as usize]));
        let mut q = [[0.0f32; 2]; 3];
        for (k, &c) in s.corners.iter().enumerate() {
            let v = uv.corner_value(c as usize)?;
            q[k] = [v[0], *v.get(1)?];
        }
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let det = a * c - b * b;
        // Degenerate (or NaN) input triangles have no UV derivative.
        let flat = det.is_nan() || det <= 1e-12 * (a * c).max(f32::MIN_POSITIVE);
        if flat || !det.is_finite() {
            return None;
        }
        let out = footprint.map(|d| {
            // d ≈ x e1 + y e2 in the face's plane (least squares).
            let (r1, r2) = (d.dot(e1), d.dot(e2));
            let x = (c * r1 - b * r2) / det;
            let y = (a * r2 - b * r1) / det;
            [
                x * (q[1][0] - q[0][0]) + y * (q[2][0] - q[0][0]),
                x * (q[1][1] - q[0][1]) + y * (q[2][1] - q[0][1]),
            ]
        });
        out.iter().flatten().all(|v| v.is_finite()).then_some(out)
    }

    /// Every channel at `s`, linear, each texture averaged over the input
    /// texels under `footprint` (the surface offsets of one output texel
    /// step; `None`: a point sample, bilinear at level 0).
    pub(crate) fn evaluate(
        &self,
        s: &SurfacePoint,
        footprint: Option<&Footprint>,
    ) -> PointChannels {
        let r = self.material_of(s.face);
        let m = &r.material;
        let sample = |ch: Channel| -> Option<[f32; 4]> {
            let (tex, uv, slot) = r.textures[ch.index()].as_ref()?;
            let axes = footprint.and_then(|f| self.uv_axes(uv, s, f));
            let uv = Self::interpolate::<2>(uv, s)?;
            Some(tex.sample_filtered(uv, axes, &self.mips.slots[*slot], &self.lut))
        };
        let mut base = m.base_color;
        let mut point_alpha = m.base_color[3];
        if let Some(t) = sample(Channel::BaseColor) {
            for k in 0..4 {
                base[k] *= t[k];
            }
            if m.alpha_mode == AlphaMode::Mask {
                point_alpha *= r.textures[Channel::BaseColor.index()]
                    .as_ref()
                    .and_then(|(tex, uv, _)| {
                        Some(tex.sample(Self::interpolate::<2>(uv, s)?, &self.lut)[3])
                    })
                    .unwrap_or(1.0);
            }
        }
        if let Some(c) = self.colors.and_then(|a| Self::interpolate::<4>(a, s)) {
            for k in 0..4 {
                base[k] *= c[k];
            }
            point_alpha *= c[3];
        }
        let passes_alpha_test =
            (m.alpha_mode == AlphaMode::Mask).then_some(point_alpha >= m.alpha_cutoff);
        let (mut metal, mut rough) = (m.metallic, m.roughness);
        if let Some(t) = sample(Channel::MetallicRoughness) {
            rough *= t[1];
            metal *= t[2];
        }
        let occlusion = sample(Channel::Occlusion).map_or(1.0, |t| t[0]);
        let mut emissive = m.emissive;
        if let Some(t) = sample(Channel::Emissive) {
            for k in 0..3 {
                emissive[k] *= t[k];
            }
        }
        let mut n = Vec3::ZERO;
        for (k, &c) in s.corners.iter().enumerate() {
            n += self.normals[c as usize] * s.bary[k];
        }
        let mut normal = n.normalize_or_zero();
        if let (Some(t), Some(tangents)) = (sample(Channel::Normal), &self.tangents) {
            let mut tan = Vec3::ZERO;
            let mut w = 0.0;
            for (k, &c) in s.corners.iter().enumerate() {
                let tc = tangents[c as usize];
                tan += Vec3::new(tc[0], tc[1], tc[2]) * s.bary[k];
                w += tc[3] * s.bary[k];
            }
            if let Some(frame) = Frame::new(normal, tan, w) {
                normal = frame.to_world(decode_normal(t));
            }
        }
        PointChannels {
            base,
            passes_alpha_test,
            metal,
            rough,
            occlusion,
            emissive,
            normal,
        }
    }
}

/// A tangent frame as a glTF shader builds it from interpolated vertex
/// data: N normalized, T made orthogonal to N and normalized, B = N × T · w.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    t: Vec3,
    b: Vec3,
    n: Vec3,
}

impl Frame {
    /// `None` when the normal or tangent is degenerate.
    pub(crate) fn new(n: Vec3, t: Vec3, w: f32) -> Option<Frame> {
        let n = n.try_normalize()?;
        let t = (t - n * n.dot(t)).try_normalize()?;
        let sign = if w < 0.0 { -1.0 } else { 1.0 };
        Some(Frame {
            t,
            b: n.cross(t) * sign,
            n,
        })
    }

    /// A tangent-space vector in world space.
    pub(crate) fn to_world(self, v: Vec3) -> Vec3 {
        (self.t * v.x + self.b * v.y + self.n * v.z).normalize_or_zero()
    }

    /// A world-space vector in tangent space.
    pub(crate) fn to_tangent(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }
}

/// A normal-map texel (linear [0, 1]) as a unit tangent-space vector.
pub(crate) fn decode_normal(t: [f32; 4]) -> Vec3 {
    Vec3::new(2.0 * t[0] - 1.0, 2.0 * t[1] - 1.0, 2.0 * t[2] - 1.0).normalize_or_zero()
}

/// A unit tangent-space vector as a normal-map texel.
///
/// A normal map cannot hold a vector below the surface (two-channel
/// encodings rebuild z ≥ 0, and a light from the front would leave the
/// texel black). One comes from an input point that faces away from the
/// output face: the far side of a thin part the level merged into one
/// sheet (a plate's underside under its top, a leaf's back, a cloth's
/// hem), or a fold. The output face shows that part's near side, whose
/// normal is the far side's turned around: the vector is negated (the
/// tea set's plates at 1%, lifted to the horizon instead, were crossed by
/// black wedges in lit renders). What is left within a hair of the
/// horizon is lifted to it.
pub(crate) fn encode_normal(v: Vec3) -> [u8; 4] {
    let mut v = if v.z < 0.0 { -v } else { v };
    if v.z < 0.01 {
        v.z = 0.01;
    }
    let v = v.normalize_or_zero();
    [
        quantize(0.5 * v.x + 0.5),
        quantize(0.5 * v.y + 0.5),
        quantize(0.5 * v.z + 0.5),
        255,
    ]
}

/// Per-corner shading normals: the mesh's stream where present, else the
/// face's (flat) normal — what a glTF renderer uses without normals.
pub(crate) fn corner_normals(mesh: &Mesh) -> Vec<Vec3> {
    let stream = mesh.attribute(&Semantic::Normal);
    let mut out = vec![Vec3::ZERO; mesh.faces.corner_count()];
    for f in 0..mesh.faces.len() {
        let start = mesh.faces.offsets[f] as usize;
        let face = mesh.faces.face(f);
        let p = |k: usize| Vec3::from(mesh.positions[face[k] as usize]);
        let mut flat = Vec3::ZERO;
        for k in 1..face.len().saturating_sub(1) {
            flat += (p(k) - p(0)).cross(p(k + 1) - p(0));
        }
        let flat = flat.normalize_or_zero();
        for k in 0..face.len() {
            let c = start + k;
            out[c] = match stream.and_then(|a| {
                let i = a.indices[c];
                (i != ABSENT).then(|| a.value(i))
            }) {
                Some(v) if v.len() >= 3 => Vec3::new(v[0], v[1], v[2]).normalize_or_zero(),
                _ => flat,
            };
        }
    }
    out
}

/// The output pixel of `ch` for values `v`; `frame` is the output tangent
/// frame at the texel (for normals).
pub(crate) fn encode(ch: Channel, v: &PointChannels, frame: Option<&Frame>, orm: bool) -> [u8; 4] {
    match ch {
        Channel::BaseColor => [
            quantize(linear_to_srgb(v.base[0])),
            quantize(linear_to_srgb(v.base[1])),
            quantize(linear_to_srgb(v.base[2])),
            quantize(v.base[3]),
        ],
        Channel::MetallicRoughness => [
            if orm { quantize(v.occlusion) } else { 255 },
            quantize(v.rough),
            quantize(v.metal),
            255,
        ],
        Channel::Occlusion => {
            let o = quantize(v.occlusion);
            [o, o, o, 255]
        }
        Channel::Emissive => [
            quantize(linear_to_srgb(v.emissive[0])),
            quantize(linear_to_srgb(v.emissive[1])),
            quantize(linear_to_srgb(v.emissive[2])),
            255,
        ],
        Channel::Normal => match frame {
            Some(f) => encode_normal(f.to_tangent(v.normal)),
            None => [128, 128, 255, 255],
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_round_trips_and_hits_known_values() {
        // sRGB 0.5 is linear 0.2140 (IEC 61966-2-1).
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        for i in 0..=255u8 {
            let c = i as f32 / 255.0;
            assert_eq!(quantize(linear_to_srgb(srgb_to_linear(c))), i);
        }
    }

    #[test]
    fn wrap_modes_fold_indices_like_gl() {
        assert_eq!(wrap(-1, 4, Wrap::Repeat), 3);
        assert_eq!(wrap(5, 4, Wrap::Repeat), 1);
        assert_eq!(wrap(-1, 4, Wrap::ClampToEdge), 0);
        assert_eq!(wrap(9, 4, Wrap::ClampToEdge), 3);
        // Mirrored: 0 1 2 3 | 3 2 1 0 | 0 1 …
        assert_eq!(wrap(4, 4, Wrap::MirroredRepeat), 3);
        assert_eq!(wrap(7, 4, Wrap::MirroredRepeat), 0);
        assert_eq!(wrap(-1, 4, Wrap::MirroredRepeat), 0);
        assert_eq!(wrap(-2, 4, Wrap::MirroredRepeat), 1);
    }

    #[test]
    fn bilinear_sample_between_texel_centers_with_clamp_and_repeat() {
        // 2×1: black | white (linear data).
        let img = Rgba8Image {
            width: 2,
            height: 1,
            pixels: vec![[0, 0, 0, 255], [255, 255, 255, 255]],
        };
        let lut = [0.0; 256];
        let mut s = TextureSampler {
            image: &img,
            sampler: Sampler::default(),
            srgb: false,
        };
        assert_eq!(s.sample([0.5, 0.5], &lut)[0], 0.5);
        assert_eq!(s.sample([0.25, 0.5], &lut)[0], 0.0);
        // u = 0: halfway between the last texel (white, by repeat) and the
        // first (black).
        assert_eq!(s.sample([0.0, 0.5], &lut)[0], 0.5);
        s.sampler.wrap_u = Wrap::ClampToEdge;
        assert_eq!(s.sample([0.0, 0.5], &lut)[0], 0.0);
    }

    #[test]
    fn a_footprint_of_many_texels_averages_them_and_one_of_a_texel_is_bilinear() {
        // A 64² checker of single texels, black and white.
        let pixels = (0..64 * 64)
            .map(|i| {
                let v = if (i % 64 + i / 64) % 2 == 0 { 0 } else { 255 };
                [v, v, v, 255]
            })
            .collect();
        let img = Rgba8Image {
            width: 64,
            height: 64,
            pixels,
        };
        let mut lut = [0.0f32; 256];
        for (i, v) in lut.iter_mut().enumerate() {
            *v = srgb_to_linear(i as f32 / 255.0);
        }
        for srgb in [false, true] {
            let s = TextureSampler {
                image: &img,
                sampler: Sampler::default(),
                srgb,
            };
            let mips = OnceLock::new();
            // An output texel 8 input texels wide, at points between and on
            // texel centers: the mean of black and white, linear 0.5.
            let eight = Some([[8.0 / 64.0, 0.0], [0.0, 8.0 / 64.0]]);
            for uv in [
                [0.5, 0.5],
                [0.3, 0.71],
                [0.123, 0.877],
                [0.5 + 0.5 / 64.0, 0.5],
            ] {
                let c = s.sample_filtered(uv, eight, &mips, &lut);
                for k in 0..3 {
                    assert!(
                        (c[k] - 0.5).abs() <= 2.0 / 255.0,
                        "srgb {srgb} at {uv:?}: {c:?}"
                    );
                }
            }
            // Anisotropic: 8 texels along u, one along v, still grey.
            let long = Some([[8.0 / 64.0, 0.0], [0.0, 1.0 / 64.0]]);
            let c = s.sample_filtered([0.3, 0.71], long, &mips, &lut);
            assert!((c[0] - 0.5).abs() <= 2.0 / 255.0, "anisotropic: {c:?}");
            // At most a texel (or no footprint): exactly the bilinear value.
            for f in [
                None,
                Some([[1.0 / 64.0, 0.0], [0.0, 1.0 / 64.0]]),
                Some([[0.25 / 64.0, 0.1 / 64.0], [0.0, 0.5 / 64.0]]),
            ] {
                for uv in [
                    [0.5 / 64.0, 0.5 / 64.0],
                    [0.3, 0.71],
                    [1.5 / 64.0, 0.5 / 64.0],
                ] {
                    assert_eq!(s.sample_filtered(uv, f, &mips, &lut), s.sample(uv, &lut));
                }
            }
        }
        // A texel center is the texel itself: black, then white.
        let s = TextureSampler {
            image: &img,
            sampler: Sampler::default(),
            srgb: false,
        };
        let one = Some([[1.0 / 64.0, 0.0], [0.0, 1.0 / 64.0]]);
        let mips = OnceLock::new();
        assert_eq!(
            s.sample_filtered([0.5 / 64.0, 0.5 / 64.0], one, &mips, &lut)[0],
            0.0
        );
        assert_eq!(
            s.sample_filtered([1.5 / 64.0, 0.5 / 64.0], one, &mips, &lut)[0],
            1.0
        );
    }

    #[test]
    fn mip_levels_average_in_linear_space_down_to_one_texel() {
        // 3 × 1, sRGB: black, white, white. Level 1 is 2 × 1: mean of black
        // and white (linear 0.5, sRGB 188), then the lone white; level 2 is
        // 1 × 1: mean of those two levels' values.
        let img = Rgba8Image {
            width: 3,
            height: 1,
            pixels: vec![[0, 0, 0, 255], [255, 255, 255, 255], [255, 255, 255, 255]],
        };
        let mut lut = [0.0f32; 256];
        for (i, v) in lut.iter_mut().enumerate() {
            *v = srgb_to_linear(i as f32 / 255.0);
        }
        let l = mip_levels(&img, true, &lut);
        assert_eq!(l.len(), 2);
        assert_eq!((l[0].width, l[0].height, l[1].width), (2, 1, 1));
        assert_eq!(l[0].pixels[0][0], quantize(linear_to_srgb(0.5)));
        assert_eq!(l[0].pixels[1][0], 255);
        assert_eq!(l[1].pixels[0][0], quantize(linear_to_srgb(0.75)));
        // Linear data averages as stored.
        let l = mip_levels(&img, false, &lut);
        assert_eq!(l[0].pixels[0][0], 128);
    }

    #[test]
    fn a_texel_footprint_is_the_surface_step_of_one_texel() {
        // A right triangle 2 units wide laid out 8 texels wide, turned by
        // 90° in the atlas: x in the atlas runs along the surface's y.
        let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let q = [[0.0, 0.0], [0.0, 8.0], [8.0, 0.0]];
        let f = texel_footprint(p, q).expect("footprint");
        assert!((f[0] - Vec3::new(0.0, 0.25, 0.0)).length() < 1e-6, "{f:?}");
        assert!((f[1] - Vec3::new(0.25, 0.0, 0.0)).length() < 1e-6, "{f:?}");
        assert!(texel_footprint(p, [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_none());
    }

    #[test]
    fn tangent_frame_round_trips_and_honours_handedness() {
        let f = Frame::new(Vec3::Z, Vec3::X, 1.0).expect("frame");
        // +Y of the map is the bitangent N × T = +y.
        assert!((f.to_world(Vec3::Y) - Vec3::Y).length() < 1e-6);
        let v = Vec3::new(0.3, -0.4, 0.866).normalize();
        assert!((f.to_tangent(f.to_world(v)) - v).length() < 1e-6);
        let mirrored = Frame::new(Vec3::Z, Vec3::X, -1.0).expect("frame");
        assert!((mirrored.to_world(Vec3::Y) + Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn a_normal_below_the_surface_is_turned_around_not_laid_flat() {
        // The underside of a thin plate seen through the output's top face:
        // (0.3, 0, -0.954) stands for the top's (-0.3, 0, 0.954).
        let below = Vec3::new(0.3, 0.0, -0.954).normalize();
        let t = encode_normal(below);
        let back = decode_normal(t.map(|c| c as f32 / 255.0));
        assert!((back - (-below)).length() < 0.01, "{back:?}");
        // Straight down is straight up, not a grazing normal.
        assert_eq!(encode_normal(-Vec3::Z), [128, 128, 255, 255]);
    }

    #[test]
    fn flat_normal_encodes_to_the_neutral_texel() {
        assert_eq!(encode_normal(Vec3::Z), [128, 128, 255, 255]);
        assert_eq!(decode_normal([0.5, 0.5, 1.0, 1.0]), Vec3::Z);
    }
}
