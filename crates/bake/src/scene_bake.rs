//! Baking several meshes together: one atlas, one set of images and one
//! material per output material group across all of them (W §4.3, Fig.
//! 18), as production tools bake a scene into one atlas per material.
//!
//! Phases: every mesh simplified with its own options and target and its
//! faces grouped (`prepare.rs`) → one layout per group over the charts of
//! every mesh in it (`shared_layout.rs`) → per group, one pixel buffer:
//! texel ownership over the triangles of all its meshes, each owned texel
//! mapped back through *its* mesh's successive map and evaluated against
//! that mesh's input, in bands of rows (bounded memory), in parallel →
//! gutter fill → images and a material that every member mesh's part
//! points at.

use std::time::Instant;

use rayon::prelude::*;
use wildlod_mesh::tangents::generate_tangents;
use wildlod_mesh::{AlphaMode, Material, Mesh, Rgba8Image, Semantic, TextureRef};
use wildlod_simplify::Options;

use crate::alpha_coverage::keep_coverage;
use crate::channels::{
    corner_normals, encode, texel_footprint, Channel, Footprint, Frame, InputChannels, MipCache,
};
use crate::density::input_face_densities;
use crate::gutter::{apply_fill, nearest_owned};
use crate::input::BakeInput;
use crate::interface::{AtlasReport, BakeError, BakeOptions, BakeReport, BakedImage};
use crate::mapping::{SuccessiveMap, SurfacePoint};
use crate::prepare::{ensure_normals, input_tangents, prepare, set_uvs, Prepared};
use crate::raster::{Coverage, Rasterizer, NO_TRIANGLE};
use crate::shared_layout::{lay_out, shared_groups, SharedAtlas, SharedGroup};
use crate::texture_detail::ImageAnalyses;

/// Margin, in texels, within which texels around a chart get their own
/// surface point: everything bilinear filtering at level 0 reads (√2 ≈
/// 1.42, see `raster.rs`).
const BILINEAR_MARGIN: f32 = 1.5;

/// Rows baked at a time: bounds the scratch memory (texel ownership,
/// surface points) to a band, whatever the atlas size.
const BAND_ROWS: u32 = 64;

/// Side of the square tiles a band is mapped in (texels of a triangle in a
/// tile share most of their walk through the history).
const TILE: usize = 32;

/// One mesh of a multi-mesh bake.
#[derive(Clone, Debug)]
pub struct SceneMesh<'a> {
    /// The mesh with the scene's materials, textures and decoded images.
    /// Every mesh of one bake must read the same material list: groups
    /// are keyed by material index.
    pub input: BakeInput<'a>,
    /// Its simplification (target, metric, guards); history recording is
    /// turned on by the baker.
    pub simplify: Options,
    /// Length scale from the mesh's units to the scene's (its largest
    /// instance's): its charts get texels per unit of *world* surface, so
    /// a mesh drawn larger gets more. 1 when all meshes share one space.
    pub world_scale: f64,
}

/// One mesh of a [`SceneBaked`].
#[derive(Clone, Debug)]
pub struct BakedMesh {
    /// The simplified, triangulated mesh (see [`crate::Baked::mesh`]):
    /// one part per output material group it has faces in.
    pub mesh: Mesh,
    /// Whether nothing was baked for it (no texture, no vertex color and
    /// no normal map to bake, or a normal-map-only atlas not worth
    /// making): its parts then name the *input* materials, else
    /// [`SceneBaked::materials`].
    pub keeps_input_materials: bool,
    /// Its simplification's report and the atlases its parts are in.
    pub report: BakeReport,
    /// Indices into [`SceneBaked::atlases`] of its parts' atlases.
    pub atlases: Vec<usize>,
    /// Seconds of the bake spent on it: its simplification and
    /// preparation, plus its share (by triangles) of the shared layout and
    /// texel baking.
    pub seconds: f64,
}

/// The result of [`bake_meshes`].
#[derive(Clone, Debug)]
pub struct SceneBaked {
    /// Every input mesh, same order.
    pub meshes: Vec<BakedMesh>,
    /// One material per atlas; texture references index `images`.
    pub materials: Vec<Material>,
    /// The baked images (each [`BakedImage::material`] indexes
    /// `materials`).
    pub images: Vec<BakedImage>,
    /// One report per atlas (per material).
    pub atlases: Vec<AtlasReport>,
    /// Per atlas: the meshes with faces in it.
    pub atlas_meshes: Vec<Vec<usize>>,
}

/// A multi-mesh bake's failure and the mesh it concerns (for an atlas that
/// does not fit: its group's first mesh).
#[derive(Debug, thiserror::Error)]
#[error("mesh {mesh}: {source}")]
pub struct SceneBakeError {
    /// Index of the mesh in the input.
    pub mesh: usize,
    /// What went wrong.
    #[source]
    pub source: BakeError,
}

/// Simplifies every mesh of `meshes` with its own options and re-bakes
/// their textures by successive mapping (W §4.3, App. B, App. C.2) into
/// **one atlas per output material across all of them**: the charts of
/// every mesh sharing an input material (with
/// [`BakeOptions::merge_materials`]: an alpha mode and sidedness) are
/// packed together, and each texel is mapped through its own mesh's
/// collapse history to its own input. `options.simplify` is not read (each
/// mesh has its own); the rest applies to every atlas. Holds one full-size
/// pixel buffer per channel of the atlas being baked, never one per mesh.
///
/// # Errors
/// [`SceneBakeError`] naming the mesh whose simplification failed, or the
/// first mesh of an atlas whose charts do not fit.
pub fn bake_meshes(
    meshes: &[SceneMesh],
    options: &BakeOptions,
) -> Result<SceneBaked, SceneBakeError> {
    // Phase 1, per mesh; what is read of the images, once for all.
    let analyses = ImageAnalyses::new(meshes.first().map_or(&[][..], |m| m.input.images));
    let prepared: Vec<Result<Prepared, BakeError>> = meshes
        .par_iter()
        .map(|m| prepare(m.input, &m.simplify, options, m.world_scale, &analyses))
        .collect();
    let mut ready = Vec::with_capacity(prepared.len());
    for (mesh, p) in prepared.into_iter().enumerate() {
        ready.push(p.map_err(|source| SceneBakeError { mesh, source })?);
    }
    let mut prepared = ready;
    let mut outs: Vec<Mesh> = prepared
        .iter_mut()
        .map(|p| std::mem::take(&mut p.out))
        .collect();
    let prepared = prepared;
    // Nothing to bake: no texture, no vertex color, no normal map asked.
    let mut kept: Vec<bool> = prepared
        .iter()
        .map(|p| !p.textured && !options.bake_normals)
        .collect();
    let maps: Vec<Option<SuccessiveMap>> = prepared
        .iter()
        .zip(&kept)
        .map(|(p, &k)| {
            (!k).then(|| {
                SuccessiveMap::new(&p.history, &p.input.mesh.positions, &p.input.mesh.faces)
            })
        })
        .collect();
    let face_densities: Vec<Vec<Option<f64>>> = prepared
        .iter()
        .zip(&kept)
        .map(|(p, &k)| {
            if k {
                Vec::new()
            } else {
                input_face_densities(&p.input, &analyses)
            }
        })
        .collect();

    // Phase 2: one layout per group across meshes. A normal-map-only
    // group that does not fit gives its meshes back their materials, and
    // the groups are formed again without them.
    let t_shared = Instant::now();
    let (groups, layouts) = 'layout: loop {
        let groups = shared_groups(&prepared, &kept);
        let mut layouts = Vec::with_capacity(groups.len());
        for g in &groups {
            let first = g.meshes.first().map_or(0, |x| x.0);
            match lay_out(g, &prepared, &maps, &face_densities, options).map_err(|source| {
                SceneBakeError {
                    mesh: first,
                    source,
                }
            })? {
                Some(l) => layouts.push(l),
                None => {
                    for &(m, _) in &g.meshes {
                        kept[m] = true;
                    }
                    continue 'layout;
                }
            }
        }
        break (groups, layouts);
    };
    for (m, p) in prepared.iter().enumerate() {
        if kept[m] {
            // Parts keep the input's materials.
            for (part, &mat) in outs[m].parts.iter_mut().zip(&p.group_first_material) {
                part.material = mat;
            }
        }
    }
    // Each mesh's atlas UVs, per triangle corner.
    let mut corner_uv: Vec<Vec<[f32; 2]>> = prepared
        .iter()
        .map(|p| vec![[0.0f32; 2]; 3 * p.triangles.len()])
        .collect();
    for (g, l) in groups.iter().zip(&layouts) {
        let size = l.atlas.size as f32;
        for (i, &(m, t)) in g.members.iter().enumerate() {
            for k in 0..3 {
                let uv = l.atlas.corner_uvs[3 * i + k];
                corner_uv[m as usize][3 * t as usize + k] = [uv[0] / size, uv[1] / size];
            }
        }
    }
    for (m, out) in outs.iter_mut().enumerate() {
        if !kept[m] {
            set_uvs(out, &corner_uv[m]);
        }
    }
    drop(corner_uv);

    // Per mesh: what its texels evaluate against, the mip chains of each
    // image list built once for every mesh that reads it.
    let mut image_lists: Vec<&[Option<Rgba8Image>]> = Vec::new();
    for p in &prepared {
        if !image_lists.iter().any(|l| std::ptr::eq(*l, p.input.images)) {
            image_lists.push(p.input.images);
        }
    }
    let caches: Vec<MipCache> = image_lists.iter().map(|l| MipCache::new(l.len())).collect();
    let channels_in: Vec<Option<InputChannels>> = prepared
        .iter()
        .zip(&kept)
        .map(|(p, &k)| {
            (!k).then(|| {
                let list = image_lists
                    .iter()
                    .position(|l| std::ptr::eq(*l, p.input.images))
                    .unwrap_or_default();
                input_channels(&p.input, &caches[list])
            })
        })
        .collect();
    let group_channels: Vec<Vec<Channel>> = groups
        .iter()
        .map(|g| channels_of(g, &prepared, &channels_in, options))
        .collect();
    // Per mesh: its output's normals, and tangents where a normal map is
    // baked on any of its parts.
    let mut needs_tangents = vec![false; prepared.len()];
    for (g, chans) in groups.iter().zip(&group_channels) {
        if chans.contains(&Channel::Normal) {
            for &(m, _) in &g.meshes {
                needs_tangents[m] = true;
            }
        }
    }
    let frames: Vec<Option<MeshFrames>> = outs
        .iter_mut()
        .enumerate()
        .map(|(m, out)| (!kept[m]).then(|| mesh_frames(out, needs_tangents[m])))
        .collect();

    // Phase 3: per group, its texels.
    let mut materials = Vec::new();
    let mut images = Vec::new();
    let mut atlases = Vec::new();
    let mut part_material: Vec<Vec<Option<u32>>> = prepared
        .iter()
        .map(|p| vec![None; p.group_keys.len()])
        .collect();
    let mut part_atlas: Vec<Vec<usize>> = vec![Vec::new(); prepared.len()];
    for (gi, (g, l)) in groups.iter().zip(&layouts).enumerate() {
        let ctx = GroupBake {
            group: g,
            layout: l,
            prepared: &prepared,
            maps: &maps,
            channels_in: &channels_in,
            frames: &frames,
            chans: &group_channels[gi],
        };
        let (material, group_images, report) = ctx.bake(materials.len(), images.len());
        let mi = materials.len() as u32;
        for &(m, lg) in &g.meshes {
            part_material[m][lg as usize] = Some(mi);
            part_atlas[m].push(atlases.len());
        }
        materials.push(material);
        images.extend(group_images);
        atlases.push(report);
    }
    let shared_seconds = t_shared.elapsed().as_secs_f64();

    let total_tris: usize = groups.iter().map(|g| g.members.len()).sum();
    let mut tris_in_atlases = vec![0usize; prepared.len()];
    for g in &groups {
        for &(m, _) in &g.members {
            tris_in_atlases[m as usize] += 1;
        }
    }
    let mut baked = Vec::with_capacity(prepared.len());
    for (m, (p, mut out)) in prepared.iter().zip(outs).enumerate() {
        if !kept[m] {
            for (part, &mat) in out.parts.iter_mut().zip(&part_material[m]) {
                part.material = mat;
            }
        }
        // Its atlases in part order.
        let mut own: Vec<usize> = part_atlas[m].clone();
        own.sort_unstable();
        let share = if total_tris > 0 {
            shared_seconds * tris_in_atlases[m] as f64 / total_tris as f64
        } else {
            0.0
        };
        baked.push(BakedMesh {
            mesh: out,
            keeps_input_materials: kept[m],
            report: BakeReport {
                simplify: p.s.report.clone(),
                atlases: own.iter().map(|&a| atlases[a].clone()).collect(),
            },
            atlases: own,
            seconds: p.seconds + share,
        });
    }
    let atlas_meshes = groups
        .iter()
        .map(|g| g.meshes.iter().map(|x| x.0).collect())
        .collect();
    Ok(SceneBaked {
        meshes: baked,
        materials,
        images,
        atlases,
        atlas_meshes,
    })
}

/// The input's channels of one mesh, with its tangents for the normal
/// map's UV set when a material has a normal map.
fn input_channels<'a>(input: &BakeInput<'a>, mips: &'a MipCache) -> InputChannels<'a> {
    let normal_uv = input
        .materials
        .iter()
        .find_map(|m| m.normal_texture)
        .map(|t| t.tex_coord);
    let tangents = normal_uv.and_then(|set| input_tangents(input.mesh, set));
    InputChannels::new(
        input.mesh,
        input.materials,
        input.textures,
        input.images,
        tangents,
        mips,
    )
}

/// Which channels a group bakes: those any material of its faces (of any
/// mesh) has a texture for (emissive: or a factor, which can differ
/// between merged materials), base color always when a member mesh is
/// textured (an untextured group keeps its factors), the normal map from
/// geometry when asked.
fn channels_of(
    g: &SharedGroup,
    prepared: &[Prepared],
    channels_in: &[Option<InputChannels>],
    options: &BakeOptions,
) -> Vec<Channel> {
    let mut chans = Vec::new();
    if g.textured {
        chans.push(Channel::BaseColor);
    }
    for ch in Channel::ALL {
        if ch == Channel::BaseColor {
            continue;
        }
        let has = g.members.iter().any(|&(m, t)| {
            let Some(c) = &channels_in[m as usize] else {
                return false;
            };
            let mat = c.material(prepared[m as usize].tri_origin[t as usize]);
            ch.texture(mat).is_some() || (ch == Channel::Emissive && mat.emissive != [0.0; 3])
        });
        if has || (ch == Channel::Normal && options.bake_normals) {
            chans.push(ch);
        }
    }
    chans
}

/// An output mesh's shading frame per corner.
struct MeshFrames {
    normals: Vec<glam::Vec3>,
    /// MikkTSpace tangents (xyz, sign) over the new UVs, when a normal map
    /// is baked on the mesh and they could be generated.
    tangents: Option<Vec<[f32; 4]>>,
}

/// The output's corner normals, and with `tangents` its MikkTSpace
/// tangents (added to the mesh as its tangent stream).
fn mesh_frames(out: &mut Mesh, tangents: bool) -> MeshFrames {
    let normals = corner_normals(out);
    if !tangents {
        return MeshFrames {
            normals,
            tangents: None,
        };
    }
    ensure_normals(out, &normals);
    let tangents = match generate_tangents(out, 0) {
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
    };
    MeshFrames { normals, tangents }
}

/// Everything one group's texel bake reads.
struct GroupBake<'s, 'a> {
    group: &'s SharedGroup,
    layout: &'s SharedAtlas,
    prepared: &'s [Prepared<'a>],
    maps: &'s [Option<SuccessiveMap<'s>>],
    channels_in: &'s [Option<InputChannels<'a>>],
    frames: &'s [Option<MeshFrames>],
    chans: &'s [Channel],
}

impl GroupBake<'_, '_> {
    /// Bakes the group's atlas: its material (material index `mi`, images
    /// numbered from `first_image`), images and report.
    fn bake(&self, mi: usize, first_image: usize) -> (Material, Vec<BakedImage>, AtlasReport) {
        let t0 = Instant::now();
        let atlas = &self.layout.atlas;
        let size = atlas.size;
        // Owners are indices into the group's members: (mesh, triangle).
        let raster = Rasterizer::new(&atlas.corner_uvs, size, BILINEAR_MARGIN);
        // Each texel averages the input texels its footprint covers.
        let footprints: Vec<Option<Footprint>> = self
            .group
            .members
            .iter()
            .enumerate()
            .map(|(i, &(m, t))| {
                let p = &self.prepared[m as usize];
                let q = p.triangles[t as usize].map(|v| p.s.positions[v as usize]);
                let uv = [0, 1, 2].map(|k| atlas.corner_uvs[3 * i + k]);
                texel_footprint(q, uv)
            })
            .collect();
        let chans = self.chans;
        let orm =
            chans.contains(&Channel::MetallicRoughness) && chans.contains(&Channel::Occlusion);
        let w = size as usize;
        let mut pixels: Vec<Vec<[u8; 4]>> = vec![vec![[0u8; 4]; w * w]; chans.len()];
        let mut mapped = vec![false; w * w];
        let mut texels_mapped = 0;
        // Owned texels evaluated, and those whose input point passes the
        // alpha test (MASK).
        let (mut alpha_evaluated, mut alpha_passing) = (0usize, 0usize);
        let mut y0 = 0u32;
        while y0 < size {
            let y1 = (y0 + BAND_ROWS).min(size);
            let coverage = raster.rows(y0..y1);
            let surface = self.map_band(&coverage);
            // One texel of the band: every channel evaluated at its input
            // point, each texture averaged over the texel's footprint.
            let texel = |i: usize| -> Option<TexelValues> {
                let hit = surface[i].as_ref()?;
                let owner = coverage.triangle[i] as usize;
                let (m, t) = self.group.members[owner];
                let (m, t) = (m as usize, t as usize);
                let channels_in = self.channels_in[m].as_ref()?;
                let frames = self.frames[m].as_ref()?;
                let b = coverage.bary[i];
                let v = channels_in.evaluate(hit, footprints[owner].as_ref());
                let frame = frames.tangents.as_ref().and_then(|tan| {
                    let (mut n, mut tv, mut sign) = (glam::Vec3::ZERO, glam::Vec3::ZERO, 0.0);
                    for (k, &wk) in b.iter().enumerate() {
                        let c = 3 * t + k;
                        n += frames.normals[c] * wk;
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
                Some((out, v.passes_alpha_test.unwrap_or(false)))
            };
            let band: Vec<Vec<Option<TexelValues>>> = (0..(y1 - y0) as usize)
                .into_par_iter()
                .map(|r| (0..w).map(|x| texel(r * w + x)).collect())
                .collect();
            let at = y0 as usize * w;
            for (r, row) in band.into_iter().enumerate() {
                for (x, cell) in row.into_iter().enumerate() {
                    let (values, passes) = cell.unwrap_or_default();
                    for (ci, px) in pixels.iter_mut().enumerate() {
                        px[at + r * w + x] = values[ci];
                    }
                    alpha_evaluated += usize::from(cell.is_some());
                    alpha_passing += usize::from(passes);
                }
            }
            for (m, &t) in mapped[at..].iter_mut().zip(&coverage.triangle) {
                *m = t != NO_TRIANGLE;
            }
            texels_mapped += coverage.owned();
            y0 = y1;
        }
        let fill = nearest_owned(size, size, &mapped);
        let seconds = t0.elapsed().as_secs_f64();
        let first = self.group.meshes.first().map(|x| x.0);
        let mut material = without_textures(
            &self
                .group
                .first_material
                .zip(first)
                .and_then(|(mat, m)| self.prepared[m].input.materials.get(mat as usize))
                .cloned()
                .unwrap_or_default(),
        );
        let mut images = Vec::new();
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
            if ch == Channel::BaseColor && material.alpha_mode == AlphaMode::Mask {
                keep_coverage(
                    &mut image.pixels,
                    w,
                    &mapped,
                    alpha_passing as f64 / alpha_evaluated.max(1) as f64,
                    material.alpha_cutoff,
                );
            }
            let r = Some(TextureRef {
                texture: (first_image + images.len()) as u32,
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
            for img in images.iter_mut() {
                if img.channel == Channel::BaseColor {
                    for p in &mut img.image.pixels {
                        p[3] = 255;
                    }
                }
            }
        }
        let report = AtlasReport {
            size,
            stats: self.layout.stats,
            layout_seconds: self.layout.layout_seconds,
            texels_mapped,
            seconds,
        };
        (material, images, report)
    }

    /// The input surface point of every owned texel of a band's
    /// `coverage` (indexed as it is), each through its own mesh's history;
    /// a triangle's texels of a tile together (they share most of their
    /// walk).
    fn map_band(&self, coverage: &Coverage) -> Vec<Option<SurfacePoint>> {
        let width = coverage.size as usize;
        let rows = 0..coverage.triangle.len() / width.max(1);
        let mut out = vec![None; coverage.triangle.len()];
        let tiles: Vec<(usize, usize)> = rows
            .clone()
            .step_by(TILE)
            .flat_map(|y| (0..width).step_by(TILE).map(move |x| (y, x)))
            .collect();
        let mapped: Vec<Vec<(usize, SurfacePoint)>> = tiles
            .par_iter()
            .map(|&(y, x)| {
                let mut items: Vec<(u32, [f32; 3], usize)> = Vec::new();
                for yy in y..(y + TILE).min(rows.end) {
                    for xx in x..(x + TILE).min(width) {
                        let i = yy * width + xx;
                        let owner = coverage.triangle[i];
                        if owner == NO_TRIANGLE {
                            continue;
                        }
                        let (m, t) = self.group.members[owner as usize];
                        let p = &self.prepared[m as usize];
                        let mut q = [0.0f32; 3];
                        for (&v, &wk) in p.triangles[t as usize].iter().zip(&coverage.bary[i]) {
                            let pv = p.s.positions[v as usize];
                            for a in 0..3 {
                                q[a] += wk * pv[a];
                            }
                        }
                        items.push((owner, q, i));
                    }
                }
                // Stable: texels of a triangle stay in scan order.
                items.sort_by_key(|it| it.0);
                let mut done = Vec::with_capacity(items.len());
                let mut points = Vec::new();
                let mut hits = Vec::new();
                for run in items.chunk_by(|a, b| a.0 == b.0) {
                    let (m, t) = self.group.members[run[0].0 as usize];
                    let Some(map) = &self.maps[m as usize] else {
                        continue;
                    };
                    let face = self.prepared[m as usize].tri_origin[t as usize];
                    points.clear();
                    points.extend(run.iter().map(|it| it.1));
                    hits.clear();
                    hits.resize(
                        run.len(),
                        SurfacePoint {
                            face: 0,
                            corners: [0; 3],
                            bary: [1.0, 0.0, 0.0],
                        },
                    );
                    map.map_many(face, &points, &mut hits);
                    done.extend(run.iter().map(|it| it.2).zip(hits.iter().copied()));
                }
                done
            })
            .collect();
        for (i, hit) in mapped.into_iter().flatten() {
            out[i] = Some(hit);
        }
        out
    }
}

/// One texel's encoded value in every baked channel, and whether its
/// input point passes the alpha test (`MASK` materials).
type TexelValues = ([[u8; 4]; 5], bool);

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
