//! The driver: simplify with the history recorded, lay out a new atlas, map
//! every texel back to the input and bake every channel (W §4.3, Fig. 18).
//!
//! Pipeline: simplify (collapses cross UV seams freely) → triangulate the
//! output → group faces by output material → per group: atlas → texel
//! ownership → successive mapping and channel evaluation, in bands of rows
//! (bounded memory), in parallel → gutter fill → images and a material.

use std::time::Instant;

use rayon::prelude::*;
use wildlod_mesh::tangents::generate_tangents;
use wildlod_mesh::{
    AlphaMode, Attribute, ComponentFormat, Faces, Material, Mesh, Part, Rgba8Image, Semantic,
    TextureRef, ABSENT,
};
use wildlod_simplify::{
    simplify_with_attributes, AttributeInput, FittedSkin, Options, Report, SkinStream,
};

use crate::atlas::{atlas_stats, build_atlas_weighted, AtlasOptions, AtlasStats};
use crate::channels::{
    corner_normals, encode, texel_footprint, Channel, Footprint, Frame, InputChannels,
};
use crate::gutter::{apply_fill, nearest_owned};
use crate::input::BakeInput;
use crate::mapping::SuccessiveMap;
use crate::raster::{rasterize, NO_TRIANGLE};
use crate::texture_detail::{content_scale, uv_coverage};

/// Margin, in texels, within which texels around a chart get their own
/// surface point: everything bilinear filtering at level 0 reads (√2 ≈
/// 1.42, see `raster.rs`).
const BILINEAR_MARGIN: f32 = 1.5;

/// Rows baked at a time: bounds the scratch memory to a band, whatever the
/// atlas size.
const BAND_ROWS: u32 = 64;

/// Faces meeting at a larger angle keep separate normals at their shared
/// vertices: the usual "auto smooth" angle of modelling tools.
const CREASE_DEGREES: f32 = 60.0;

/// Per-corner normals of `triangles`: at each corner, the area-weighted
/// normals of the triangles around its vertex that turn by at most
/// `crease` degrees from its own triangle; equal values shared.
fn smooth_normals(positions: &[[f32; 3]], triangles: &[[u32; 3]], crease: f32) -> Attribute {
    let cos = crease.to_radians().cos();
    let face_n: Vec<glam::Vec3> = triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| glam::Vec3::from(positions[v as usize]));
            (p[1] - p[0]).cross(p[2] - p[0])
        })
        .collect();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); positions.len()];
    for (f, t) in triangles.iter().enumerate() {
        for &v in t {
            around[v as usize].push(f as u32);
        }
    }
    let mut values: Vec<f32> = Vec::new();
    let mut indices = Vec::with_capacity(3 * triangles.len());
    let mut seen = std::collections::HashMap::new();
    for (f, t) in triangles.iter().enumerate() {
        let own = face_n[f].normalize_or_zero();
        for &v in t {
            let mut n = glam::Vec3::ZERO;
            for &g in &around[v as usize] {
                let other = face_n[g as usize];
                if own == glam::Vec3::ZERO || other.normalize_or_zero().dot(own) >= cos {
                    n += other;
                }
            }
            let n = n.try_normalize().unwrap_or(if own == glam::Vec3::ZERO {
                glam::Vec3::Z
            } else {
                own
            });
            let key = n.to_array().map(f32::to_bits);
            let next = seen.len() as u32;
            let i = *seen.entry(key).or_insert_with(|| {
                values.extend_from_slice(&n.to_array());
                next
            });
            indices.push(i);
        }
    }
    Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values,
        indices,
        format: ComponentFormat::F32,
    }
}

/// Options of [`bake_mesh`].
#[derive(Clone, Debug)]
pub struct BakeOptions {
    /// The simplification (target, metric, guards). History recording is
    /// turned on by the baker.
    pub simplify: Options,
    /// Atlas width and height in texels; `None`: the input's texel
    /// density, scaled by the level when [`BakeOptions::density_follows_level`]
    /// (see [`BakeOptions::max_texture_size`]).
    pub texture_size: Option<u32>,
    /// Largest atlas side chosen from the input's texel density. Default
    /// 4096.
    pub max_texture_size: u32,
    /// Without a `texture_size`: texel density = the input's × √(output
    /// triangles / input triangles), at least 256 texels a side (never
    /// above the input's density). A level is shown where its error is
    /// about a pixel; its edges are about 1/√ratio times longer than the
    /// input's, so it is drawn about √ratio times as large on screen, and
    /// the input's density would spend texels no screen samples (a 1% LOD
    /// of a 4k-textured asset got a 4k atlas). But never coarser than the
    /// input's base colour images can be averaged without a visible change
    /// (`texture_detail.rs`): a face or printed text keeps its texels at
    /// any level. Default on; off keeps the input's density at every
    /// ratio.
    pub density_follows_level: bool,
    /// Empty texels between charts (and along the border). Default 4.
    pub padding: u32,
    /// Bake all materials with the same alpha mode and sidedness into one
    /// atlas and material. Off: one atlas per output material.
    pub merge_materials: bool,
    /// Chart cone angle in degrees ([`AtlasOptions::max_chart_angle`]).
    pub max_chart_angle: f64,
    /// Bake a tangent-space normal map for every output material from the
    /// input's shading normals: its normal map applied where it has one,
    /// else its interpolated vertex normals (its face normals without a
    /// normal stream), at each texel's mapped input point, in the LOD's
    /// MikkTSpace frame. The successive mapping gives every texel its
    /// input point exactly, so unlike ray casting (Simplygon, InstaLOD) it
    /// never misses on thin or overlapping parts. Default on: a LOD keeps
    /// the small-scale shape its collapses removed under lighting. Off:
    /// normal maps are baked only where the input has one.
    pub bake_normals: bool,
}

impl Default for BakeOptions {
    fn default() -> Self {
        BakeOptions {
            simplify: Options::default(),
            texture_size: None,
            max_texture_size: 4096,
            density_follows_level: true,
            padding: AtlasOptions::default().padding,
            merge_materials: false,
            max_chart_angle: AtlasOptions::default().max_chart_angle,
            bake_normals: true,
        }
    }
}

/// One re-baked image.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedImage {
    /// Which channel it holds.
    pub channel: Channel,
    /// Which output material it belongs to.
    pub material: usize,
    /// The pixels (sRGB for base color and emissive, linear otherwise).
    pub image: Rgba8Image,
    /// Texels that hold their own surface point (the rest are gutter fill).
    pub mapped: Vec<bool>,
}

/// One atlas: its layout quality and work.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasReport {
    /// Width and height in texels.
    pub size: u32,
    /// Layout statistics.
    pub stats: AtlasStats,
    /// Seconds spent laying out the atlas (charts, parametrization,
    /// packing).
    pub layout_seconds: f64,
    /// Texels mapped to the input through the history.
    pub texels_mapped: usize,
    /// Seconds spent mapping texels and evaluating channels.
    pub seconds: f64,
}

/// What [`bake_mesh`] did.
#[derive(Clone, Debug)]
pub struct BakeReport {
    /// The simplification's report.
    pub simplify: Report,
    /// One entry per atlas (output material).
    pub atlases: Vec<AtlasReport>,
}

/// The result: the simplified mesh with new UVs, its materials, and the
/// images they refer to.
#[derive(Clone, Debug)]
pub struct Baked {
    /// The simplified, triangulated mesh: one part per output material,
    /// `TEXCOORD_0` in the new atlas, normals (and tangents when a normal
    /// map was baked), the input's skin influences and other per-corner
    /// streams carried along; vertex colors are baked into base color and
    /// dropped.
    pub mesh: Mesh,
    /// Output materials, indexed by the mesh's parts. Their texture
    /// references are indices into `images`; factors of baked channels
    /// are 1.
    pub materials: Vec<Material>,
    /// The baked images.
    pub images: Vec<BakedImage>,
    /// What was reached.
    pub report: BakeReport,
}

/// Why a bake failed.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    /// The simplifier refused the input or options.
    #[error(transparent)]
    Simplify(#[from] wildlod_simplify::Error),
    /// The LOD's charts do not fit the largest atlas allowed (each takes a
    /// texel and its padding at least): a surface split into tens of
    /// thousands of charts (a noisy scan's), or a `texture_size` too small.
    #[error("{charts} atlas charts do not fit a {size}² atlas")]
    AtlasFull {
        /// Charts of the layout.
        charts: usize,
        /// The largest atlas side tried.
        size: u32,
    },
}

/// Simplifies `input.mesh` with collapses free to cross UV seams, and
/// re-bakes every texture channel of its materials onto a new atlas by
/// successive mapping (W §4.3, App. B, App. C.2).
///
/// A mesh whose materials have no texture and which has no vertex colors
/// gets only a normal map ([`BakeOptions::bake_normals`]; its materials
/// keep their factors), or with that off is only simplified (no atlas, no
/// image).
///
/// # Errors
/// [`BakeError::Simplify`] when the mesh or options are invalid.
pub fn bake_mesh(input: &BakeInput, options: &BakeOptions) -> Result<Baked, BakeError> {
    let mesh = input.mesh;
    let mut opts = options.simplify.clone();
    opts.record.history = true;
    if opts.data.vertex_joints.is_empty() {
        opts.data.vertex_joints = wildlod_simplify::vertex_joints(mesh);
    }
    // Positions and faces steer the collapses, UVs do not (W: collapses
    // cross seams freely); skin influences are fitted through every
    // collapse (Knodt 2024 §3) so that the LOD deforms like the input.
    let attributes = AttributeInput {
        skin: mesh.skinning.as_ref().map(|sk| SkinStream {
            influences: sk.influences as usize,
            joints: &sk.joints,
            weights: &sk.weights,
            indices: &sk.indices,
            weight: opts.attributes.skin_weight,
        }),
        ..AttributeInput::default()
    };
    let mut s = simplify_with_attributes(&mesh.positions, &mesh.faces, &attributes, &opts)?;
    let history = s.history.take().unwrap_or_default();
    // Triangles of the output, each remembering its output face and the
    // output corners it uses.
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut tri_face: Vec<u32> = Vec::new();
    let mut tri_corners: Vec<[u32; 3]> = Vec::new();
    for f in 0..s.faces.len() {
        let face = s.faces.face(f);
        let start = s.faces.offsets[f];
        for k in 1..face.len().saturating_sub(1) {
            triangles.push([face[0], face[k], face[k + 1]]);
            tri_face.push(f as u32);
            tri_corners.push([start, start + k as u32, start + k as u32 + 1]);
        }
    }
    let material_of_face = |f: u32| -> Option<u32> {
        let input_face = s.face_origin[f as usize] as usize;
        mesh.parts
            .get(mesh.face_parts[input_face] as usize)
            .and_then(|p| p.material)
            .filter(|&m| (m as usize) < input.materials.len())
    };
    let textured = mesh
        .parts
        .iter()
        .filter_map(|p| p.material)
        .filter_map(|m| input.materials.get(m as usize))
        .any(|m| m.texture_refs().next().is_some())
        || mesh.attribute(&Semantic::Color(0)).is_some();

    // Output groups: one per output material.
    let key = |m: Option<u32>| -> (u32, u32, u32) {
        let mat = m.and_then(|m| input.materials.get(m as usize));
        if options.merge_materials {
            let alpha = mat.map_or(0, |m| m.alpha_mode as u32);
            let sides = mat.map_or(0, |m| m.double_sided as u32);
            (alpha, sides, 0)
        } else {
            (0, 0, m.map_or(u32::MAX, |m| m))
        }
    };
    let mut keys: Vec<(u32, u32, u32)> = Vec::new();
    let mut group_first_material: Vec<Option<u32>> = Vec::new();
    let mut tri_group = Vec::with_capacity(triangles.len());
    for &f in &tri_face {
        let m = material_of_face(f);
        let k = key(m);
        let g = match keys.iter().position(|x| *x == k) {
            Some(g) => g,
            None => {
                keys.push(k);
                group_first_material.push(m);
                keys.len() - 1
            }
        };
        tri_group.push(g as u32);
    }

    let mut out = carried_mesh(mesh, &s, &triangles, &tri_corners);
    if let (Some(fitted), Some(input_skin)) = (&s.skin, &mesh.skinning) {
        out.skinning = Some(fitted_skinning(fitted, input_skin, &triangles));
    }
    if mesh.attribute(&Semantic::Normal).is_some() {
        // Carried corner normals belong to whichever input vertex each
        // corner was, so one output vertex gets several: faceted shading.
        // Fresh normals, smooth up to a crease angle, shade the new
        // geometry (and the normal map is baked relative to them).
        out.attributes.retain(|a| a.semantic != Semantic::Normal);
        out.attributes
            .push(smooth_normals(&s.positions, &triangles, CREASE_DEGREES));
    }
    out.face_parts = tri_group.clone();
    out.parts = group_first_material
        .iter()
        .map(|&m| Part {
            name: m
                .and_then(|m| input.materials.get(m as usize))
                .map(|m| m.name.clone())
                .unwrap_or_default(),
            material: None,
        })
        .collect();
    if !textured && !options.bake_normals {
        // Nothing to bake: keep the input's materials on the parts.
        for (p, &m) in out.parts.iter_mut().zip(&group_first_material) {
            p.material = m;
        }
        let materials = input.materials.to_vec();
        return Ok(Baked {
            mesh: out,
            materials,
            images: Vec::new(),
            report: BakeReport {
                simplify: s.report,
                atlases: Vec::new(),
            },
        });
    }

    let map = SuccessiveMap::new(&history, &mesh.positions, &mesh.faces);
    let normal_uv = input
        .materials
        .iter()
        .find_map(|m| m.normal_texture)
        .map(|t| t.tex_coord);
    let input_tangents = normal_uv.and_then(|set| input_tangents(mesh, set));
    let channels_in = InputChannels::new(
        mesh,
        input.materials,
        input.textures,
        input.images,
        input_tangents,
    );

    // The linear scale of the level's texel density against the input's.
    let scale = level_scale(input, &s.report, options);
    let face_density = crate::density::input_face_densities(input);
    // Atlas UVs per triangle corner, group by group.
    let mut corner_uv = vec![[0.0f32; 2]; 3 * triangles.len()];
    let mut materials = Vec::new();
    let mut images = Vec::new();
    let mut atlases = Vec::new();
    let mut group_work = Vec::new();
    // Faces of far outlier vertices (left in place by the simplifier) get
    // no atlas space: one of them would set the charts' common scale and
    // leave every other chart without a texel.
    let mut far = vec![false; s.positions.len()];
    for &o in &s.report.outliers {
        if let Some(&v) = s.vertex_map.get(o as usize) {
            if let Some(f) = far.get_mut(v as usize) {
                *f = true;
            }
        }
    }
    for g in 0..keys.len() {
        let members: Vec<u32> = (0..triangles.len() as u32)
            .filter(|&t| tri_group[t as usize] == g as u32)
            .filter(|&t| !triangles[t as usize].iter().any(|&v| far[v as usize]))
            .collect();
        let group_tris: Vec<[u32; 3]> = members.iter().map(|&t| triangles[t as usize]).collect();
        // Charts get texels where the input has them (`density.rs`).
        let origins: Vec<u32> = members
            .iter()
            .map(|&t| s.face_origin[tri_face[t as usize] as usize])
            .collect();
        let densities = crate::density::triangle_densities(
            &map,
            &face_density,
            &s.positions,
            &group_tris,
            &origins,
        );
        let mut size = options
            .texture_size
            .unwrap_or_else(|| density_size(input, &s.positions, &group_tris, scale, options));
        let t_layout = Instant::now();
        // A size chosen here grows (up to `max_texture_size`) until every
        // chart has a place worth its padding; an asked-for size (or the
        // largest) is used as long as every chart has a place.
        let atlas = loop {
            let atlas = build_atlas_weighted(
                &s.positions,
                &group_tris,
                &[],
                &densities,
                &AtlasOptions {
                    size,
                    padding: options.padding,
                    max_chart_angle: options.max_chart_angle,
                    // A size that may still grow needs a useful packing
                    // or none.
                    useful_only: options.texture_size.is_none() && size < options.max_texture_size,
                },
            );
            if !textured && !atlas.fits {
                // Only a normal map was to be baked: it is an addition, not
                // worth an atlas of mostly gutter; the LOD keeps its
                // materials as an untextured bake does.
                for (p, &m) in out.parts.iter_mut().zip(&group_first_material) {
                    p.material = m;
                }
                return Ok(Baked {
                    mesh: out,
                    materials: input.materials.to_vec(),
                    images: Vec::new(),
                    report: BakeReport {
                        simplify: s.report,
                        atlases: Vec::new(),
                    },
                });
            }
            let fixed = options.texture_size.is_some() || size >= options.max_texture_size;
            if atlas.fits || (fixed && atlas.placed) {
                break atlas;
            }
            if fixed {
                return Err(BakeError::AtlasFull {
                    charts: atlas.chart_count,
                    size,
                });
            }
            size = (2 * size).min(options.max_texture_size.max(size));
        };
        for (i, &t) in members.iter().enumerate() {
            for k in 0..3 {
                let uv = atlas.corner_uvs[3 * i + k];
                corner_uv[3 * t as usize + k] = [uv[0] / size as f32, uv[1] / size as f32];
            }
        }
        let layout_seconds = t_layout.elapsed().as_secs_f64();
        let stats = atlas_stats(&s.positions, &group_tris, &atlas);
        group_work.push((members, atlas, stats, layout_seconds));
    }
    set_uvs(&mut out, &corner_uv);

    // Which channels each group bakes: those any material of its faces has
    // a texture for (emissive: or a factor, which can differ between merged
    // materials), base color always on a textured mesh (an untextured one
    // keeps its factors), the normal map from geometry when asked.
    let mut any_normal_map = false;
    let mut group_channels: Vec<Vec<Channel>> = Vec::new();
    for (members, _, _, _) in &group_work {
        let mut chans = Vec::new();
        if textured {
            chans.push(Channel::BaseColor);
        }
        for ch in Channel::ALL {
            if ch == Channel::BaseColor {
                continue;
            }
            let has = members.iter().any(|&t| {
                let f = s.face_origin[tri_face[t as usize] as usize];
                let m = channels_in.material(f);
                ch.texture(m).is_some() || (ch == Channel::Emissive && m.emissive != [0.0; 3])
            });
            if has || (ch == Channel::Normal && options.bake_normals) {
                chans.push(ch);
                any_normal_map |= ch == Channel::Normal;
            }
        }
        group_channels.push(chans);
    }
    let out_normals = corner_normals(&out);
    let out_tangents = if any_normal_map {
        ensure_normals(&mut out, &out_normals);
        match generate_tangents(&out, 0) {
            Ok(t) => {
                let per_corner: Vec<[f32; 4]> = (0..out.faces.corner_count())
                    .map(|c| match t.corner_value(c) {
                        Some(v) => [v[0], v[1], v[2], v[3]],
                        None => [1.0, 0.0, 0.0, 1.0],
                    })
                    .collect();
                out.attributes.retain(|a| a.semantic != Semantic::Tangent);
                out.attributes.push(t);
                Some(per_corner)
            }
            Err(_) => None,
        }
    } else {
        None
    };

    for (g, (members, atlas, stats, layout_seconds)) in group_work.iter().enumerate() {
        let t0 = Instant::now();
        let size = atlas.size;
        let coverage = rasterize(&atlas.corner_uvs, size, BILINEAR_MARGIN);
        // Each texel averages the input texels its footprint covers.
        let footprints = texel_footprints(&s.positions, &triangles, members, atlas);
        let chans = &group_channels[g];
        let orm =
            chans.contains(&Channel::MetallicRoughness) && chans.contains(&Channel::Occlusion);
        let mut pixels: Vec<Vec<[u8; 4]>> =
            vec![vec![[0u8; 4]; size as usize * size as usize]; chans.len()];
        let w = size as usize;
        let mut y0 = 0u32;
        while y0 < size {
            let y1 = (y0 + BAND_ROWS).min(size);
            // The band's texels mapped back to the input through the
            // history, a triangle's texels together (they share most of
            // their walk): its owner, its input face id, its surface point.
            let surface = map.map_texels(w, y0 as usize..y1 as usize, |i| {
                let owner = coverage.triangle[i];
                if owner == NO_TRIANGLE {
                    return None;
                }
                let t = members[owner as usize] as usize;
                let mut p = [0.0f32; 3];
                for (&v, &wk) in triangles[t].iter().zip(&coverage.bary[i]) {
                    let q = s.positions[v as usize];
                    for a in 0..3 {
                        p[a] += wk * q[a];
                    }
                }
                Some((owner, s.face_origin[tri_face[t] as usize], p))
            });
            // One texel: every channel evaluated at its input point, each
            // texture averaged over the texel's footprint.
            let texel = |i: usize| -> Option<[[u8; 4]; 5]> {
                let hit = surface[i - y0 as usize * w].as_ref()?;
                let owner = coverage.triangle[i] as usize;
                let t = members[owner] as usize;
                let b = coverage.bary[i];
                let v = channels_in.evaluate(hit, footprints[owner].as_ref());
                let frame = out_tangents.as_ref().and_then(|tan| {
                    let (mut n, mut tv, mut sign) = (glam::Vec3::ZERO, glam::Vec3::ZERO, 0.0);
                    for (k, &wk) in b.iter().enumerate() {
                        let c = 3 * t + k;
                        n += out_normals[c] * wk;
                        let tc = tan[c];
                        tv += glam::Vec3::new(tc[0], tc[1], tc[2]) * wk;
                        sign += tc[3] * wk;
                    }
                    Frame::new(n, tv, sign)
                });
                let mut out = [[0u8; 4]; 5];
                for (slot, &ch) in out.iter_mut().zip(chans.iter()) {
                    *slot = encode(ch, &v, frame.as_ref(), orm);
                }
                Some(out)
            };
            let band: Vec<Vec<[[u8; 4]; 5]>> = (y0..y1)
                .into_par_iter()
                .map(|y| {
                    (0..w)
                        .map(|x| texel(y as usize * w + x).unwrap_or_default())
                        .collect()
                })
                .collect();
            for (r, row) in band.into_iter().enumerate() {
                let y = y0 as usize + r;
                for (x, values) in row.into_iter().enumerate() {
                    for (ci, px) in pixels.iter_mut().enumerate() {
                        px[y * w + x] = values[ci];
                    }
                }
            }
            y0 = y1;
        }
        let mapped: Vec<bool> = coverage
            .triangle
            .iter()
            .map(|&t| t != NO_TRIANGLE)
            .collect();
        let fill = nearest_owned(size, size, &mapped);
        let seconds = t0.elapsed().as_secs_f64();
        let mut material = without_textures(
            &group_first_material[g]
                .and_then(|m| input.materials.get(m as usize))
                .cloned()
                .unwrap_or_default(),
        );
        let mi = materials.len();
        for (ci, &ch) in chans.iter().enumerate() {
            if ch == Channel::Occlusion && orm {
                // Packed into the metallic-roughness image's R.
                continue;
            }
            let mut image = Rgba8Image {
                width: size,
                height: size,
                pixels: std::mem::take(&mut pixels[ci]),
            };
            apply_fill(&mut image, &fill);
            let r = Some(TextureRef {
                texture: images.len() as u32,
                tex_coord: 0,
            });
            // Factors are baked into the images: the material's are 1.
            match ch {
                Channel::BaseColor => {
                    material.base_color_texture = r;
                    material.base_color = [1.0; 4];
                }
                Channel::MetallicRoughness => {
                    material.metallic_roughness_texture = r;
                    material.metallic = 1.0;
                    material.roughness = 1.0;
                    if orm {
                        material.occlusion_texture = r;
                    }
                }
                Channel::Normal => material.normal_texture = r,
                Channel::Occlusion => material.occlusion_texture = r,
                Channel::Emissive => {
                    material.emissive_texture = r;
                    material.emissive = [1.0; 3];
                }
            }
            images.push(BakedImage {
                channel: ch,
                material: mi,
                image,
                mapped: mapped.clone(),
            });
        }
        if material.alpha_mode == AlphaMode::Opaque {
            // Alpha means nothing to an opaque material; keep the PNGs
            // opaque so they stay RGB.
            for img in images.iter_mut().filter(|i| i.material == mi) {
                if img.channel == Channel::BaseColor {
                    for p in &mut img.image.pixels {
                        p[3] = 255;
                    }
                }
            }
        }
        out.parts[g].material = Some(mi as u32);
        materials.push(material);
        atlases.push(AtlasReport {
            size,
            stats: *stats,
            layout_seconds: *layout_seconds,
            texels_mapped: coverage.owned(),
            seconds,
        });
    }
    Ok(Baked {
        mesh: out,
        materials,
        images,
        report: BakeReport {
            simplify: s.report,
            atlases,
        },
    })
}

/// The surface footprint of a texel of each of a group's triangles
/// (`members`, laid out in `atlas`).
fn texel_footprints(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    members: &[u32],
    atlas: &crate::atlas::Atlas,
) -> Vec<Option<Footprint>> {
    members
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let p = triangles[t as usize].map(|v| positions[v as usize]);
            let q = [0, 1, 2].map(|k| atlas.corner_uvs[3 * i + k]);
            texel_footprint(p, q)
        })
        .collect()
}

/// The output material of a group: the group's first material with no
/// texture yet; the caller sets each baked channel's texture and factor.
fn without_textures(m: &Material) -> Material {
    Material {
        base_color_texture: None,
        metallic_roughness_texture: None,
        normal_texture: None,
        occlusion_texture: None,
        emissive_texture: None,
        ..m.clone()
    }
}

/// The simplified triangles with every per-corner stream except UVs,
/// tangents and colors carried from the input corner each output corner
/// is (normals, morph deltas, custom streams, skin influences).
fn carried_mesh(
    mesh: &Mesh,
    s: &wildlod_simplify::Simplified,
    triangles: &[[u32; 3]],
    tri_corners: &[[u32; 3]],
) -> Mesh {
    let mut faces = Faces::with_capacity(triangles.len(), 3 * triangles.len());
    for t in triangles {
        faces.push(t);
    }
    let input_corner = |out_corner: u32| s.corner_origin[out_corner as usize] as usize;
    let corners: Vec<usize> = tri_corners
        .iter()
        .flatten()
        .map(|&c| input_corner(c))
        .collect();
    let attributes = mesh
        .attributes
        .iter()
        .filter(|a| {
            !matches!(
                a.semantic,
                Semantic::TexCoord(_) | Semantic::Tangent | Semantic::Color(_)
            )
        })
        .map(|a| Attribute {
            indices: corners.iter().map(|&c| a.indices[c]).collect(),
            ..a.clone()
        })
        .collect();
    let skinning = mesh.skinning.as_ref().map(|sk| wildlod_mesh::Skinning {
        indices: corners.iter().map(|&c| sk.indices[c]).collect(),
        ..sk.clone()
    });
    let mut out = Mesh {
        name: mesh.name.clone(),
        positions: s.positions.clone(),
        faces,
        face_parts: vec![0; triangles.len()],
        parts: vec![Part::default()],
        attributes,
        skinning,
    };
    out.compact();
    out
}

/// The simplifier's fitted influences (one set per output vertex) as the
/// triangulated mesh's per-corner skinning; a vertex no skinned corner
/// reached (all weights 0) has none.
fn fitted_skinning(
    fitted: &FittedSkin,
    input: &wildlod_mesh::Skinning,
    triangles: &[[u32; 3]],
) -> wildlod_mesh::Skinning {
    let k = fitted.influences.max(1);
    let indices = triangles
        .iter()
        .flatten()
        .map(|&v| {
            let w = fitted.weights.get(v as usize * k..(v as usize + 1) * k);
            match w {
                Some(w) if w.iter().any(|&x| x > 0.0) => v,
                _ => ABSENT,
            }
        })
        .collect();
    wildlod_mesh::Skinning {
        influences: fitted.influences as u8,
        joints: fitted.joints.clone(),
        weights: fitted.weights.clone(),
        indices,
        weight_format: input.weight_format,
        joint_format: input.joint_format,
    }
}

/// Sets `TEXCOORD_0` from per-corner UVs, sharing equal values.
fn set_uvs(out: &mut Mesh, corner_uv: &[[f32; 2]]) {
    let mut values = Vec::new();
    let mut indices = Vec::with_capacity(corner_uv.len());
    let mut seen = std::collections::HashMap::new();
    for uv in corner_uv {
        let key = [uv[0].to_bits(), uv[1].to_bits()];
        let next = seen.len() as u32;
        let i = *seen.entry(key).or_insert_with(|| {
            values.extend_from_slice(uv);
            next
        });
        indices.push(i);
    }
    out.attributes
        .retain(|a| a.semantic != Semantic::TexCoord(0));
    out.attributes.insert(
        0,
        Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values,
            indices,
            format: ComponentFormat::F32,
        },
    );
}

/// Gives the mesh a normal stream when it has none (flat normals, what a
/// renderer would use), so tangents can be generated.
fn ensure_normals(out: &mut Mesh, normals: &[glam::Vec3]) {
    if out.attribute(&Semantic::Normal).is_some() {
        return;
    }
    out.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values: normals.iter().flat_map(|n| n.to_array()).collect(),
        indices: (0..normals.len() as u32).collect(),
        format: ComponentFormat::F32,
    });
}

/// Per-corner tangents of the input for UV set `set`: its stream when it
/// has one, else MikkTSpace.
fn input_tangents(mesh: &Mesh, set: u32) -> Option<Vec<[f32; 4]>> {
    let from = |a: &Attribute| -> Vec<[f32; 4]> {
        (0..mesh.faces.corner_count())
            .map(|c| match a.corner_value(c) {
                Some(v) if v.len() >= 4 => [v[0], v[1], v[2], v[3]],
                Some(v) if v.len() == 3 => [v[0], v[1], v[2], 1.0],
                _ => [1.0, 0.0, 0.0, 1.0],
            })
            .collect()
    };
    if let Some(t) = mesh.attribute(&Semantic::Tangent) {
        return Some(from(t));
    }
    let generated = if mesh.attribute(&Semantic::Normal).is_some() {
        generate_tangents(mesh, set).ok()?
    } else {
        let mut m = mesh.clone();
        let n = corner_normals(mesh);
        ensure_normals(&mut m, &n);
        generate_tangents(&m, set).ok()?
    };
    Some(from(&generated))
}

/// The smallest atlas side a level's density is scaled down to (unless the
/// input's own density gives less): below it charts of a few texels blur
/// whatever they hold.
const MIN_LEVEL_SIDE: f64 = 256.0;

/// The linear scale of a level's texel density against the input's (see
/// [`BakeOptions::density_follows_level`]): √(triangles kept), but no
/// smaller than the most detailed base colour image the mesh uses allows
/// ([`content_scale`]); 1 with the option off.
fn level_scale(input: &BakeInput, report: &Report, options: &BakeOptions) -> f64 {
    let level = report.output_triangles as f64 / report.input_triangles.max(1) as f64;
    // An asked-for size needs no scale (and no pass over the images).
    if options.texture_size.is_some()
        || !(options.density_follows_level && level.is_finite() && level > 0.0)
    {
        return 1.0;
    }
    let min_scale = level.min(1.0).sqrt();
    // Per base colour image: the UV triangles of the faces showing it.
    let mesh = input.mesh;
    let mut uvs: Vec<(u32, Vec<[[f32; 2]; 3]>)> = Vec::new();
    for f in 0..mesh.faces.len() {
        let Some(r) = mesh
            .parts
            .get(mesh.face_parts[f] as usize)
            .and_then(|p| p.material)
            .and_then(|m| input.materials.get(m as usize))
            .and_then(|m| m.base_color_texture)
        else {
            continue;
        };
        let Some(uv) = mesh.attribute(&Semantic::TexCoord(r.tex_coord)) else {
            continue;
        };
        let start = mesh.faces.offsets[f] as usize;
        let n = mesh.faces.face(f).len();
        let at = |c: usize| uv.corner_value(c).map(|v| [v[0], v[1]]);
        let k = match uvs.iter().position(|(t, _)| *t == r.texture) {
            Some(k) => k,
            None => {
                uvs.push((r.texture, Vec::new()));
                uvs.len() - 1
            }
        };
        for j in 1..n.saturating_sub(1) {
            if let (Some(a), Some(b), Some(c)) = (at(start), at(start + j), at(start + j + 1)) {
                uvs[k].1.push([a, b, c]);
            }
        }
    }
    uvs.iter()
        .filter_map(|(t, tris)| {
            let img = input.images.get(*t as usize).and_then(Option::as_ref)?;
            let used = uv_coverage(img.width, img.height, tris);
            Some(content_scale(img, &used, min_scale))
        })
        .fold(min_scale, f64::max)
}

/// Atlas side for the input's texel density: the input's texels per unit
/// area (over its textured faces) times the group's area, over an expected
/// atlas use of 60%, times `scale` ([`level_scale`]; at least 256 texels,
/// never above the input's density), rounded to a power of two in
/// `[64, max_texture_size]`.
fn density_size(
    input: &BakeInput,
    out_positions: &[[f32; 3]],
    group: &[[u32; 3]],
    scale: f64,
    options: &BakeOptions,
) -> u32 {
    let mesh = input.mesh;
    let (mut texels, mut area) = (0.0f64, 0.0f64);
    for f in 0..mesh.faces.len() {
        let part = mesh.face_parts[f] as usize;
        let Some(m) = mesh
            .parts
            .get(part)
            .and_then(|p| p.material)
            .and_then(|m| input.materials.get(m as usize))
        else {
            continue;
        };
        let Some(r) = m.base_color_texture.or_else(|| m.texture_refs().next()) else {
            continue;
        };
        let Some(img) = input
            .images
            .get(r.texture as usize)
            .and_then(Option::as_ref)
        else {
            continue;
        };
        let Some(uv) = mesh.attribute(&Semantic::TexCoord(r.tex_coord)) else {
            continue;
        };
        let start = mesh.faces.offsets[f] as usize;
        let face = mesh.faces.face(f);
        for k in 1..face.len().saturating_sub(1) {
            let c = [start, start + k, start + k + 1];
            let p = c.map(|c| {
                glam::DVec3::from(mesh.positions[mesh.faces.indices[c] as usize].map(f64::from))
            });
            let q: Option<Vec<&[f32]>> = c.iter().map(|&c| uv.corner_value(c)).collect();
            let Some(q) = q else { continue };
            let a3 = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            let a2 = 0.5
                * ((q[1][0] - q[0][0]) as f64 * (q[2][1] - q[0][1]) as f64
                    - (q[1][1] - q[0][1]) as f64 * (q[2][0] - q[0][0]) as f64)
                    .abs();
            area += a3;
            texels += a2 * img.width as f64 * img.height as f64;
        }
    }
    let mut out_area = 0.0;
    for t in group {
        let p = t.map(|v| glam::DVec3::from(out_positions[v as usize].map(f64::from)));
        out_area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    }
    let cap = options.max_texture_size.max(64);
    if !(area > 0.0 && texels > 0.0 && out_area > 0.0) {
        return 1024.min(cap);
    }
    let full = (texels / area * out_area / 0.6).sqrt();
    let side = (full * scale.min(1.0)).max(full.min(MIN_LEVEL_SIDE));
    let pow = side.max(1.0).log2().round().clamp(6.0, 31.0);
    (2f64.powf(pow) as u32).clamp(64, cap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normals_average_within_the_crease_and_split_beyond_it() {
        // Two triangles hinged along x at 30° (smoothed) and at 90° (split).
        for (angle, split) in [(30f32, false), (90f32, true)] {
            let (c, s) = (angle.to_radians().cos(), angle.to_radians().sin());
            let p = vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.5, -c, s],
            ];
            let t = [[0u32, 1, 2], [1, 0, 3]];
            let a = smooth_normals(&p, &t, 60.0);
            let n0 = a.corner_value(0).expect("normal");
            let n3 = a.corner_value(4).expect("normal");
            if split {
                assert!((n0[2] - 1.0).abs() < 1e-6, "{n0:?}");
                assert!(n3[2] < 0.1, "{n3:?}");
            } else {
                // Vertex 0 is shared: both corners get the same average.
                assert_eq!(n0, n3);
                assert!(n0[2] < 1.0 && n0[2] > 0.9, "{n0:?}");
            }
        }
    }
}
