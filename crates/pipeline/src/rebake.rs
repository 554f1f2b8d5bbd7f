//! Re-baking a file's textures (`--textures bake`, and `auto` where it
//! re-bakes): every mesh simplified with collapses free to cross UV seams
//! and its textures re-baked onto a new atlas (W §4.3, by `wildlod-bake`).
//!
//! Images are decoded here (8-bit, a quarter of the float decoder's
//! memory), baked, encoded as PNG (JPEG when the input's textures were all
//! JPEG) and put into the scene as embedded images named
//! `<stem>_<mesh>_<material>_<channel>`; the writers place them (a `.glb`
//! embeds them, a `.gltf` or `.obj` writes them beside the output). The
//! input's materials and textures are replaced by the baked ones.

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use wildlod_bake::{bake_mesh, BakeError, BakeInput, BakeOptions, Baked, Channel};
use wildlod_io::{decode_image_rgba8, encode_image, Document, ImageEncoding};
use wildlod_mesh::{ImageSource, Material, Mesh, Rgba8Image, Sampler, Texture, TextureRef, Wrap};
use wildlod_simplify::{InputData, Options, Report, StopReason, Target};

use crate::{clear_unused_joint_slots, mesh_name, Error, MeshRun};

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
/// simplifier `options`. Returns every simplified mesh's run and the
/// warnings (a texture that cannot be decoded bakes from its material's
/// factor, and says so).
pub fn rebake_scene(
    doc: &mut Document,
    input: &Path,
    options: &Options,
    settings: &BakeSettings,
    targets: &[Target],
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

    let mut materials: Vec<Material> = Vec::new();
    let mut textures: Vec<Texture> = Vec::new();
    // Input materials kept for meshes that had nothing to bake.
    let mut kept: Vec<Option<u32>> = vec![None; scene.materials.len()];
    let mut meshes = Vec::with_capacity(scene.meshes.len());
    let mut runs = Vec::new();
    let instances = scene.instance_counts();
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
        // Targets and reports count drawn triangles, as without baking: a
        // mesh shown by k nodes counts each face k times.
        let k = instances.get(m).copied().unwrap_or(1);
        let target = targets.get(m).cloned().unwrap_or_default();
        if vanishes(&target) {
            // The file's budget removed it (see `drawn_targets`): written
            // as no mesh, counted as its triangles gone.
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
        }
        let t0 = Instant::now();
        let bake_options = BakeOptions {
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
                ..options.clone()
            },
            texture_size: settings.texture_size,
            merge_materials: settings.merge_materials,
            bake_normals: settings.normal_maps,
            ..BakeOptions::default()
        };
        let bake_input = BakeInput {
            mesh,
            materials: &scene.materials,
            textures: &scene.textures,
            images: &images,
        };
        let baked = bake_mesh(&bake_input, &bake_options).map_err(|e| match e {
            BakeError::Simplify(source) => Error::Simplify {
                file: input.to_path_buf(),
                mesh: name.clone(),
                source,
            },
            source => Error::Bake {
                file: input.to_path_buf(),
                mesh: name.clone(),
                source,
            },
        })?;
        let seconds = t0.elapsed().as_secs_f64();
        let note = atlas_summary(&baked);
        let mut out = baked.mesh.clone();
        clear_unused_joint_slots(&mut out);
        if baked.images.is_empty() {
            for p in &mut out.parts {
                p.material = p
                    .material
                    .map(|i| keep(i, scene, &mut kept, &mut materials));
            }
        } else {
            let (mat0, tex0) = (materials.len() as u32, textures.len() as u32);
            // Images encode in parallel: PNG's deflate is the slowest step
            // after the bake itself.
            let encoded = baked
                .images
                .par_iter()
                .map(|img| {
                    let material = &baked.materials[img.material];
                    let label = format!(
                        "{stem}_{}_{}_{}",
                        file_part(&name),
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
            for mat in &baked.materials {
                let shift = |r: Option<TextureRef>| {
                    r.map(|r| TextureRef {
                        texture: r.texture + tex0,
                        tex_coord: r.tex_coord,
                    })
                };
                materials.push(Material {
                    base_color_texture: shift(mat.base_color_texture),
                    metallic_roughness_texture: shift(mat.metallic_roughness_texture),
                    normal_texture: shift(mat.normal_texture),
                    occlusion_texture: shift(mat.occlusion_texture),
                    emissive_texture: shift(mat.emissive_texture),
                    ..mat.clone()
                });
            }
            for p in &mut out.parts {
                p.material = p.material.map(|i| i + mat0);
            }
        }
        runs.push(RebakedRun {
            run: MeshRun {
                mesh: m,
                name,
                report: baked.report.simplify.clone(),
                seconds,
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

/// What was baked for one mesh, for its summary line.
fn atlas_summary(b: &Baked) -> String {
    if b.report.atlases.is_empty() {
        return "; nothing to bake (no texture, no vertex color)".into();
    }
    let parts: Vec<String> = b
        .report
        .atlases
        .iter()
        .map(|a| {
            format!(
                "{}² ({} charts, {:.0}% used, stretch {:.3}, layout {:.0} ms, bake {:.0} ms)",
                a.size,
                a.stats.charts,
                100.0 * a.stats.utilization,
                a.stats.stretch_l2,
                1000.0 * a.layout_seconds,
                1000.0 * a.seconds
            )
        })
        .collect();
    format!(
        "; baked {} image(s) in {}",
        b.images.len(),
        parts.join(", ")
    )
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
