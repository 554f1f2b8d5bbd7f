//! Re-baking a file's textures (`--textures bake`, and `auto` where it
//! re-bakes): every mesh simplified with collapses free to cross UV seams
//! and the textures re-baked onto new atlases (W §4.3, by `wildlod-bake`),
//! one atlas and material per output material across the whole file: the
//! meshes that share an input material share its atlas, as Simplygon and
//! InstaLOD bake a scene.
//!
//! Images are decoded here (8-bit, a quarter of the float decoder's
//! memory), baked, encoded as PNG (JPEG when the input's textures were all
//! JPEG) and put into the scene as embedded images named
//! `<stem>_<mesh>_<material>_<channel>` (`<mesh>`: the first mesh of the
//! atlas); the writers place them (a `.glb`
//! embeds them, a `.gltf` or `.obj` writes them beside the output). The
//! input's materials and textures are replaced by the baked ones.

use std::path::Path;

use rayon::prelude::*;
use wildlod_bake::{bake_meshes, BakeError, BakeInput, BakeOptions, BakedMesh, Channel, SceneMesh};
use wildlod_io::{decode_image_rgba8, encode_image, Document, ImageEncoding};
use wildlod_mesh::{ImageSource, Material, Mesh, Rgba8Image, Sampler, Texture, Wrap};
use wildlod_simplify::{Guards, InputData, Options, Report, StopReason, Target};

use crate::{clear_unused_joint_slots, mesh_name, share_budget, Error, MeshRun};

/// How textures are re-baked (`--texture-size`, `--merge-materials`,
/// `--jpeg-quality`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BakeSettings {
    /// Atlas size in texels; `None` keeps the input's texel density,
    /// rounded to a power of two, at most 4096.
    pub texture_size: Option<u32>,
    /// One atlas per alpha mode and sidedness instead of one per material.
    pub merge_materials: bool,
    /// JPEG quality (1 to 100) for inputs whose textures were all JPEG.
    pub jpeg_quality: u8,
    /// Bake a normal map from the input's shading normals for every
    /// re-baked material (see `wildlod_bake::BakeOptions::bake_normals`);
    /// off: only where the input has a normal map (`--no-normal-bake`).
    pub normal_maps: bool,
}

impl Default for BakeSettings {
    /// The input's texel density, an atlas per material, JPEG quality 90,
    /// normal maps from geometry.
    fn default() -> Self {
        BakeSettings {
            texture_size: None,
            merge_materials: false,
            jpeg_quality: 90,
            normal_maps: true,
        }
    }
}

impl BakeSettings {
    /// Checks the ranges.
    pub fn checked(self) -> Result<BakeSettings, Error> {
        if let Some(n) = self.texture_size {
            if !(16..=16384).contains(&n) {
                return Err(Error::setting(
                    "texture_size",
                    "between 16 and 16384",
                    n as f64,
                ));
            }
        }
        if !(1..=100).contains(&self.jpeg_quality) {
            return Err(Error::setting(
                "jpeg_quality",
                "between 1 and 100",
                f64::from(self.jpeg_quality),
            ));
        }
        Ok(self)
    }
}

/// One re-baked mesh: its simplifier run and what was baked for it (the
/// atlases, for its summary line).
#[derive(Clone, Debug)]
pub struct RebakedRun {
    /// The simplifier's run.
    pub run: MeshRun,
    /// `; baked N image(s) in SIZE² (…)` or `; nothing to bake (…)`.
    pub atlases: String,
}

/// Re-bakes every mesh of `doc` (read from `input`) in place, each to its
/// target in `targets` (drawn triangles, as without baking; a target of
/// exactly 0 triangles and no other limit removes the mesh), with the
/// simplifier `options`, all baked together (`wildlod_bake::bake_meshes`):
/// one material and one set of images per output material group across
/// the file, every mesh's parts of the group pointing at it; a mesh with
/// nothing to bake keeps its materials (without textures). `hold`, when
/// not empty, gives per mesh the target of the run without constraints a
/// constrained re-bake is held to (`Guards::hold_target`; see
/// `Held::hold_targets`). Returns every simplified mesh's run and the
/// warnings (a texture that cannot be decoded bakes from its material's
/// factor, and says so).
pub fn rebake_scene(
    doc: &mut Document,
    input: &Path,
    options: &Options,
    settings: &BakeSettings,
    targets: &[Target],
    hold: &[usize],
    stem: &str,
) -> Result<(Vec<RebakedRun>, Vec<String>), Error> {
    let mut warnings = Vec::new();
    let scene = &doc.scene;
    // Decode every texture a material uses; a missing or broken one is a
    // warning and its channel bakes from the material's factor.
    let mut used = vec![false; scene.textures.len()];
    for m in &scene.materials {
        for r in m.texture_refs() {
            if let Some(u) = used.get_mut(r.texture as usize) {
                *u = true;
            }
        }
    }
    let mut images: Vec<Option<Rgba8Image>> = vec![None; scene.textures.len()];
    for (t, tex) in scene.textures.iter().enumerate() {
        if !used[t] {
            continue;
        }
        match decode_image_rgba8(&tex.source) {
            Ok(img) => images[t] = Some(img),
            Err(e) => {
                warnings.push(format!(
                    "{}: texture {t} ({}) cannot be baked from: {e}; its channel uses the material's factor",
                    input.display(),
                    texture_label(tex)
                ));
            }
        }
    }
    let all_jpeg = (0..scene.textures.len())
        .filter(|&t| used[t])
        .all(|t| is_jpeg(&scene.textures[t].source))
        && used.iter().any(|&u| u);

    // Every mesh with something to simplify is baked with the others:
    // one atlas, one set of images and one material per output material
    // group across the file (`wildlod_bake::bake_meshes`).
    let instances = scene.instance_counts();
    let world_scales = world_scales(scene);
    let mut baked_index: Vec<Option<usize>> = vec![None; scene.meshes.len()];
    let mut to_bake: Vec<SceneMesh> = Vec::new();
    for (m, mesh) in scene.meshes.iter().enumerate() {
        let target = targets.get(m).cloned().unwrap_or_default();
        if mesh.faces.is_empty() || vanishes(&target) {
            continue;
        }
        // Targets and reports count drawn triangles, as without baking: a
        // mesh shown by k nodes counts each face k times.
        let k = instances.get(m).copied().unwrap_or(1);
        baked_index[m] = Some(to_bake.len());
        to_bake.push(SceneMesh {
            input: BakeInput {
                mesh,
                materials: &scene.materials,
                textures: &scene.textures,
                images: &images,
            },
            simplify: Options {
                target,
                data: InputData {
                    face_instances: if k > 1 {
                        vec![u32::try_from(k).unwrap_or(u32::MAX); mesh.faces.len()]
                    } else {
                        Vec::new()
                    },
                    ..options.data.clone()
                },
                guards: Guards {
                    hold_target: hold.get(m).copied(),
                    ..options.guards
                },
                ..options.clone()
            },
            world_scale: world_scales.get(m).copied().unwrap_or(1.0),
        });
    }
    let bake_options = BakeOptions {
        texture_size: settings.texture_size,
        merge_materials: settings.merge_materials,
        bake_normals: settings.normal_maps,
        ..BakeOptions::default()
    };
    let baked = if to_bake.is_empty() {
        None
    } else {
        let mesh_of = |i: usize| {
            baked_index
                .iter()
                .position(|&b| b == Some(i))
                .unwrap_or_default()
        };
        Some(bake_meshes(&to_bake, &bake_options).map_err(|e| {
            let name = mesh_name(scene, mesh_of(e.mesh), stem);
            match e.source {
                BakeError::Simplify(source) => Error::Simplify {
                    file: input.to_path_buf(),
                    mesh: name,
                    source,
                },
                source => Error::Bake {
                    file: input.to_path_buf(),
                    mesh: name,
                    source,
                },
            }
        })?)
    };
    drop(to_bake);

    // The shared images, encoded once each, in parallel (PNG's deflate is
    // the slowest step after the bake itself); named after the first mesh
    // of their atlas.
    let mut materials: Vec<Material> = Vec::new();
    let mut textures: Vec<Texture> = Vec::new();
    if let Some(b) = &baked {
        let encoded = b
            .images
            .par_iter()
            .map(|img| {
                let material = &b.materials[img.material];
                let first = b.atlas_meshes[img.material]
                    .first()
                    .and_then(|&i| baked_index.iter().position(|&x| x == Some(i)))
                    .unwrap_or_default();
                let label = format!(
                    "{stem}_{}_{}_{}",
                    file_part(&mesh_name(scene, first, stem)),
                    file_part(if material.name.is_empty() {
                        "material"
                    } else {
                        &material.name
                    }),
                    img.channel.name()
                );
                let opaque = img.image.pixels.iter().all(|p| p[3] == 255);
                let encoding = if all_jpeg && (opaque || img.channel != Channel::BaseColor) {
                    ImageEncoding::Jpeg {
                        quality: settings.jpeg_quality,
                    }
                } else {
                    ImageEncoding::Png
                };
                let bytes = encode_image(&img.image, encoding, &label)?;
                Ok((label, bytes, encoding))
            })
            .collect::<Result<Vec<_>, wildlod_io::Error>>()?;
        for (label, bytes, encoding) in encoded {
            textures.push(Texture {
                name: label,
                source: ImageSource::Embedded {
                    bytes,
                    mime_type: encoding.mime_type().into(),
                },
                // The atlas must not wrap: its border is gutter.
                sampler: Sampler {
                    wrap_u: Wrap::ClampToEdge,
                    wrap_v: Wrap::ClampToEdge,
                },
            });
        }
        // Baked materials first; their texture references are already
        // indices into `textures`.
        materials.extend(b.materials.iter().cloned());
    }
    // Input materials kept for meshes that had nothing to bake.
    let mut kept: Vec<Option<u32>> = vec![None; scene.materials.len()];
    let mut meshes = Vec::with_capacity(scene.meshes.len());
    let mut runs = Vec::new();
    let (images_per_atlas, sharing): (Vec<usize>, Vec<usize>) = match &baked {
        Some(b) => (0..b.atlases.len())
            .map(|a| {
                (
                    b.images.iter().filter(|i| i.material == a).count(),
                    b.atlas_meshes[a].len(),
                )
            })
            .unzip(),
        None => (Vec::new(), Vec::new()),
    };
    let mut described = vec![false; sharing.len()];
    let mut baked_meshes: Vec<Option<BakedMesh>> = match baked {
        Some(b) => b.meshes.into_iter().map(Some).collect(),
        None => Vec::new(),
    };
    for (m, mesh) in scene.meshes.iter().enumerate() {
        let name = mesh_name(scene, m, stem);
        if mesh.faces.is_empty() {
            let mut mesh = mesh.clone();
            for p in &mut mesh.parts {
                p.material = p
                    .material
                    .map(|i| keep(i, scene, &mut kept, &mut materials));
            }
            meshes.push(mesh);
            continue;
        }
        let Some(b) = baked_index[m].and_then(|i| baked_meshes[i].take()) else {
            // The file's budget removed it (see `drawn_targets`): written
            // as no mesh, counted as its triangles gone.
            let k = instances.get(m).copied().unwrap_or(1);
            runs.push(RebakedRun {
                run: MeshRun {
                    mesh: m,
                    name,
                    report: Report {
                        input_triangles: mesh.triangle_count() * k,
                        stop: Some(StopReason::TargetReached),
                        ..Report::default()
                    },
                    seconds: 0.0,
                },
                atlases: "; removed under the file's budget".into(),
            });
            meshes.push(Mesh {
                name: mesh.name.clone(),
                ..Mesh::default()
            });
            continue;
        };
        let note = atlas_summary(&b, &images_per_atlas, &sharing, &mut described);
        let mut out = b.mesh;
        clear_unused_joint_slots(&mut out);
        if b.keeps_input_materials {
            for p in &mut out.parts {
                p.material = p
                    .material
                    .map(|i| keep(i, scene, &mut kept, &mut materials));
            }
        }
        runs.push(RebakedRun {
            run: MeshRun {
                mesh: m,
                name,
                report: b.report.simplify,
                seconds: b.seconds,
            },
            atlases: note,
        });
        meshes.push(out);
    }
    doc.scene.meshes = meshes;
    doc.scene.materials = materials;
    doc.scene.textures = textures;
    Ok((runs, warnings))
}

/// Whether `target` asks for nothing of a mesh: no triangle, with no
/// ratio or error limit that could keep some.
fn vanishes(target: &Target) -> bool {
    target.triangles == Some(0) && target.ratio.is_none() && target.error.is_none()
}

/// Index of input material `i` among the output materials, copying it
/// (textures dropped: only meshes without textures keep input materials)
/// the first time.
fn keep(
    i: u32,
    scene: &wildlod_mesh::Scene,
    kept: &mut [Option<u32>],
    materials: &mut Vec<Material>,
) -> u32 {
    if let Some(Some(k)) = kept.get(i as usize) {
        return *k;
    }
    let Some(m) = scene.materials.get(i as usize) else {
        return i;
    };
    let k = materials.len() as u32;
    materials.push(Material {
        base_color_texture: None,
        metallic_roughness_texture: None,
        normal_texture: None,
        occlusion_texture: None,
        emissive_texture: None,
        ..m.clone()
    });
    kept[i as usize] = Some(k);
    k
}

/// What was baked for one mesh, for its summary line: its atlases'
/// images (`images[a]`: atlas `a`'s), sizes and layouts, and how many
/// meshes share each (`sharing[a]`). A shared atlas is described on the
/// first line that names it (`described[a]` then set); later lines only
/// point at it.
fn atlas_summary(
    b: &BakedMesh,
    images: &[usize],
    sharing: &[usize],
    described: &mut Vec<bool>,
) -> String {
    if b.report.atlases.is_empty() {
        return "; nothing to bake (no texture, no vertex color)".into();
    }
    let parts: Vec<String> = b
        .report
        .atlases
        .iter()
        .zip(&b.atlases)
        .map(|(a, &i)| {
            let shared = match sharing.get(i).copied().unwrap_or(1) {
                0 | 1 => String::new(),
                n => format!(", atlas {i} shared by {n} meshes"),
            };
            if described.len() <= i {
                described.resize(i + 1, false);
            }
            if !shared.is_empty() && std::mem::replace(&mut described[i], true) {
                return format!("{}² (atlas {i}, above)", a.size);
            }
            format!(
                "{}² ({} charts, {:.0}% used, stretch {:.3}, layout {:.0} ms, bake {:.0} ms{shared})",
                a.size,
                a.stats.charts,
                100.0 * a.stats.utilization,
                a.stats.stretch_l2,
                1000.0 * a.layout_seconds,
                1000.0 * a.seconds
            )
        })
        .collect();
    let n: usize = b.atlases.iter().filter_map(|&i| images.get(i)).sum();
    format!("; baked {n} image(s) in {}", parts.join(", "))
}

/// Each mesh's length scale in the scene: the largest over the nodes that
/// show it of the cube root of the determinant of their world matrix's
/// linear part (1 for a mesh no node shows), so that its charts get
/// texels per unit of world surface.
fn world_scales(scene: &wildlod_mesh::Scene) -> Vec<f64> {
    let mut out = vec![0.0f64; scene.meshes.len()];
    for (m, w) in scene.instances() {
        let d = glam::Mat4::from_cols_array(&w).determinant();
        let s = f64::from(d.abs()).cbrt();
        if let Some(o) = out.get_mut(m as usize) {
            if s.is_finite() {
                *o = o.max(s);
            }
        }
    }
    for s in &mut out {
        if *s <= 0.0 {
            *s = 1.0;
        }
    }
    out
}

/// A texture as warnings name it.
fn texture_label(t: &Texture) -> String {
    match (&t.source, t.name.as_str()) {
        (ImageSource::Path(p), _) => p.display().to_string(),
        (_, "") => "embedded image".into(),
        (_, n) => n.to_string(),
    }
}

/// Whether an image is JPEG (by extension or MIME type).
fn is_jpeg(s: &ImageSource) -> bool {
    match s {
        ImageSource::Path(p) => Path::new(p)
            .extension()
            .map(|e| {
                let e = e.to_string_lossy().to_ascii_lowercase();
                e == "jpg" || e == "jpeg"
            })
            .unwrap_or(false),
        ImageSource::Embedded { mime_type, .. } => mime_type == "image/jpeg",
    }
}

/// A name made safe for a file name.
fn file_part(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Runs that their constraints held above their target
/// (`Report::held_by_constraints`): the level they stopped at and their
/// target.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Held {
    level: f64,
    target: usize,
}

impl Held {
    /// `None` unless some run of `runs` was held.
    pub(crate) fn of(runs: &[MeshRun]) -> Option<Held> {
        let level = runs
            .iter()
            .filter_map(|r| r.report.held_by_constraints)
            .reduce(f64::max)?;
        Some(Held {
            level,
            target: runs.iter().map(|r| r.report.target_triangles).sum(),
        })
    }

    /// Per mesh, the target a re-bake aiming at `targets` (the held runs'
    /// counts, [`crate::drawn_targets`]) is held to when its constraints
    /// hold it: the held runs' target shared in proportion to the counts.
    /// Held instead against a free run at the counts, the constraints
    /// would cost triangles twice: once in the held run that reached them,
    /// again in the re-bake.
    pub(crate) fn hold_targets(self, targets: &[Target]) -> Vec<usize> {
        let counts: Vec<usize> = targets.iter().map(|t| t.triangles.unwrap_or(0)).collect();
        share_budget(self.target, &counts)
            .into_iter()
            .map(|n| n.max(1))
            .collect()
    }

    /// A re-bake reaches, mesh by mesh, the counts held runs kept: each
    /// mesh's report says so, with the held level and its share of the
    /// target (in proportion to those counts) as the target the
    /// constraints put out of reach, as the runs it follows would.
    pub(crate) fn mark(self, runs: &mut [MeshRun]) {
        let counts: Vec<usize> = runs.iter().map(|r| r.report.target_triangles).collect();
        for (r, share) in runs.iter_mut().zip(share_budget(self.target, &counts)) {
            r.report.held_by_constraints = Some(self.level);
            r.report.target_triangles = share;
        }
    }
}
