//! End-to-end bakes on generated meshes whose right answer is known: a flat
//! textured plane (the bake must reproduce the input image), a cube with
//! six UV islands on a magenta background (no background may show at any
//! mip level), and a bumpy normal-mapped plane (lighting must survive).

use glam::Vec3;
use wildlod_bake::gutter::mip_chain;
use wildlod_bake::{
    bake_mesh, rasterize, BakeError, BakeInput, BakeOptions, Baked, Channel, NO_TRIANGLE,
};
use wildlod_mesh::shapes::{quad_grid, triangulate};
use wildlod_mesh::{
    Attribute, ComponentFormat, Faces, ImageSource, Material, Mesh, Part, Rgba8Image, Sampler,
    Semantic, Texture, TextureRef, Wrap,
};
use wildlod_simplify::{Options, Target};

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Reference bilinear lookup (clamp to edge), written independently of the
/// baker: `srgb` decodes RGB before filtering, as GPUs do.
fn bilinear(img: &Rgba8Image, uv: [f32; 2], srgb: bool) -> [f32; 4] {
    let x = uv[0] as f64 * img.width as f64 - 0.5;
    let y = uv[1] as f64 * img.height as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
    let at = |xi: f64, yi: f64| {
        let xi = (xi as i64).clamp(0, img.width as i64 - 1) as usize;
        let yi = (yi as i64).clamp(0, img.height as i64 - 1) as usize;
        let p = img.pixels[yi * img.width as usize + xi];
        let f = |k: usize| {
            let c = p[k] as f32 / 255.0;
            if srgb && k < 3 {
                srgb_to_linear(c)
            } else {
                c
            }
        };
        [f(0), f(1), f(2), f(3)]
    };
    let (a, b, c, d) = (
        at(x0, y0),
        at(x0 + 1.0, y0),
        at(x0, y0 + 1.0),
        at(x0 + 1.0, y0 + 1.0),
    );
    let mut out = [0.0; 4];
    for k in 0..4 {
        let top = a[k] + (b[k] - a[k]) * fx;
        let bottom = c[k] + (d[k] - c[k]) * fx;
        out[k] = top + (bottom - top) * fy;
    }
    out
}

fn clamp_sampler() -> Sampler {
    Sampler {
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
    }
}

fn texture() -> Texture {
    Texture {
        name: "t".into(),
        source: ImageSource::Path("t.png".into()),
        sampler: clamp_sampler(),
    }
}

/// A material whose base colour is texture 0 through UV set 0.
fn textured_material() -> Material {
    Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    }
}

/// `n × n` quads on [0, 1]², triangulated, with UVs `uv(x, y)`.
fn plane(n: usize, uv: impl Fn(f32, f32) -> [f32; 2]) -> Mesh {
    let mut m = triangulate(&quad_grid(n, n));
    let values: Vec<f32> = m.positions.iter().flat_map(|p| uv(p[0], p[1])).collect();
    let indices = m.faces.indices.clone();
    m.attributes.retain(|a| a.semantic != Semantic::TexCoord(0));
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values,
        indices,
        format: ComponentFormat::F32,
    });
    m.parts = vec![Part {
        name: "p".into(),
        material: Some(0),
    }];
    m
}

fn options(ratio: f64, size: u32) -> BakeOptions {
    BakeOptions {
        simplify: Options {
            target: Target {
                ratio: Some(ratio),
                ..Target::default()
            },
            ..Options::default()
        },
        texture_size: Some(size),
        ..BakeOptions::default()
    }
}

/// For every texel of `baked`'s image `image` owned by an output triangle
/// (within 1.5 texels), the surface point it stands for.
fn texel_points(baked: &Baked, size: u32) -> Vec<(usize, [f32; 3])> {
    let m = &baked.mesh;
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uvs");
    let corner_uvs: Vec<[f32; 2]> = (0..m.faces.corner_count())
        .map(|c| {
            let v = uv.corner_value(c).expect("uv");
            [v[0] * size as f32, v[1] * size as f32]
        })
        .collect();
    let cov = rasterize(&corner_uvs, size, 1.5);
    let mut out = Vec::new();
    for (i, &t) in cov.triangle.iter().enumerate() {
        if t == NO_TRIANGLE {
            continue;
        }
        let f = m.faces.face(t as usize);
        let b = cov.bary[i];
        let p = [0, 1, 2].map(|a| (0..3).map(|k| b[k] * m.positions[f[k] as usize][a]).sum());
        out.push((i, p));
    }
    out
}

fn image_of(baked: &Baked, ch: Channel) -> &Rgba8Image {
    &baked
        .images
        .iter()
        .find(|i| i.channel == ch)
        .expect("channel baked")
        .image
}

#[test]
fn flat_plane_at_one_percent_reproduces_the_input_image_at_every_texel() {
    // A 32×32 image of unrelated colors, so any misplaced lookup shows.
    let mut img = Rgba8Image::filled(32, 32, [0; 4]);
    for (i, p) in img.pixels.iter_mut().enumerate() {
        let h = (i as u32).wrapping_mul(2_654_435_761);
        *p = [(h >> 24) as u8, (h >> 16) as u8, (h >> 8) as u8, 255];
    }
    let mesh = plane(40, |x, y| [x, 1.0 - y]);
    let materials = [textured_material()];
    let textures = [texture()];
    let images = [Some(img.clone())];
    let input = BakeInput {
        mesh: &mesh,
        materials: &materials,
        textures: &textures,
        images: &images,
    };
    let baked = bake_mesh(&input, &options(0.01, 128)).expect("bakes");
    assert!(
        baked.mesh.triangle_count() <= 33,
        "{}",
        baked.mesh.triangle_count()
    );
    let out = image_of(&baked, Channel::BaseColor);
    let points = texel_points(&baked, 128);
    assert!(points.len() > 4000, "{} texels", points.len());
    let mut worst = 0i32;
    for (i, p) in points {
        // On the plane, the input point is the output point itself.
        let want = bilinear(&img, [p[0], 1.0 - p[1]], true);
        for (&got, &w) in out.pixels[i].iter().zip(&want).take(3) {
            let w = (linear_to_srgb(w) * 255.0).round() as i32;
            worst = worst.max((got as i32 - w).abs());
        }
    }
    assert!(worst <= 1, "largest difference {worst}/255");
}

/// A unit cube, each face an `n × n` grid, face `k` mapped to island `k` of
/// a 3 × 2 layout of a 96 × 64 image: 32 × 32 cells, each island 24 × 24
/// texels of one color with its color dilated 2 texels around it (as
/// real atlases are), and magenta in between.
fn island_cube(n: usize) -> (Mesh, Rgba8Image, [[u8; 4]; 6]) {
    // Every island color has green 230 and magenta has none: any blend of
    // surface colors keeps green 230, any background in a blend lowers it.
    let colors = [
        [230, 230, 40, 255],
        [40, 230, 40, 255],
        [40, 230, 230, 255],
        [230, 230, 230, 255],
        [120, 230, 40, 255],
        [40, 230, 120, 255],
    ];
    let magenta = [255, 0, 255, 255];
    let mut img = Rgba8Image::filled(96, 64, magenta);
    for (k, c) in colors.iter().enumerate() {
        let (cx, cy) = ((k % 3) * 32, (k / 3) * 32);
        for y in cy + 2..cy + 30 {
            for x in cx + 2..cx + 30 {
                img.pixels[y * 96 + x] = *c;
            }
        }
    }
    // Faces: (origin, u axis, v axis), outward normal u × v.
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([1.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut f = Faces::new();
    for (k, (o, u, v)) in faces.iter().enumerate() {
        let base = positions.len() as u32;
        let (cx, cy) = ((k % 3) as f32 * 32.0 + 4.0, (k / 3) as f32 * 32.0 + 4.0);
        for j in 0..=n {
            for i in 0..=n {
                let (s, t) = (i as f32 / n as f32, j as f32 / n as f32);
                positions.push([0, 1, 2].map(|a| o[a] + s * u[a] + t * v[a]));
                uvs.extend_from_slice(&[(cx + 24.0 * s) / 96.0, (cy + 24.0 * t) / 64.0]);
            }
        }
        let id = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                f.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                f.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    let mut m = Mesh::from_polygons(positions, f);
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uvs,
        indices,
        format: ComponentFormat::F32,
    });
    m.parts[0].material = Some(0);
    (m, img, colors)
}

#[test]
fn no_background_color_at_any_mip_level_on_an_island_cube() {
    let (mesh, img, _) = island_cube(8);
    let materials = [textured_material()];
    let textures = [texture()];
    let images = [Some(img)];
    let input = BakeInput {
        mesh: &mesh,
        materials: &materials,
        textures: &textures,
        images: &images,
    };
    let size = 128;
    let baked = bake_mesh(&input, &options(0.1, size)).expect("bakes");
    let b = baked
        .images
        .iter()
        .find(|i| i.channel == Channel::BaseColor)
        .expect("base color");
    let m = &baked.mesh;
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uvs");
    let chain = mip_chain(&b.image);
    // Interior and edge points of every triangle.
    let weights: [[f32; 3]; 7] = [
        [1.0 / 3.0; 3],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
        [0.98, 0.01, 0.01],
        [0.01, 0.98, 0.01],
        [0.01, 0.01, 0.98],
    ];
    // Green below 230 (less rounding through the mip levels) means some
    // background was blended in.
    let magenta_like = |c: [f32; 4]| c[1] < 226.0 / 255.0;
    let mut samples = 0;
    for t in 0..m.faces.len() {
        let q: Vec<[f32; 2]> = (0..3)
            .map(|k| {
                let v = uv.corner_value(3 * t + k).expect("uv");
                [v[0], v[1]]
            })
            .collect();
        for w in &weights {
            let p = [0, 1].map(|a| w[0] * q[0][a] + w[1] * q[1][a] + w[2] * q[2][a]);
            // Level 0: every texel bilinear filtering reads holds the
            // surface's own color (mapped), none is gutter fill.
            let x = (p[0] * size as f32 - 0.5).floor() as i64;
            let y = (p[1] * size as f32 - 0.5).floor() as i64;
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (xi, yi) = (
                    (x + dx).clamp(0, size as i64 - 1),
                    (y + dy).clamp(0, size as i64 - 1),
                );
                assert!(
                    b.mapped[(yi * size as i64 + xi) as usize],
                    "triangle {t} at {p:?}: texel ({xi}, {yi}) is not mapped"
                );
            }
            // Every mip level down to 4×4: no background color, opaque.
            for (level, l) in chain.iter().enumerate().take_while(|(_, l)| l.width >= 4) {
                let c = bilinear(l, p, false);
                assert!(
                    !magenta_like(c) && c[3] > 0.999,
                    "triangle {t} at {p:?}, level {level}: {c:?}"
                );
                samples += 1;
            }
        }
    }
    assert!(samples > 1000, "{samples}");
    // And no texel of the atlas is left unwritten (transparent black).
    assert!(b.image.pixels.iter().all(|p| p[3] == 255));
}

/// Tangent-space normal field of the test: bumps along u and v.
fn bump(u: f32, v: f32) -> Vec3 {
    let tau = std::f32::consts::TAU;
    Vec3::new(
        0.5 * (tau * 2.0 * u).sin(),
        0.5 * (tau * 3.0 * v).cos(),
        1.0,
    )
    .normalize()
}

fn lambert(n: Vec3) -> f32 {
    n.dot(Vec3::new(0.3, 0.5, 0.8).normalize()).max(0.0)
}

#[test]
fn normal_mapped_plane_keeps_its_lighting_under_the_new_tangent_frame() {
    let size = 64u32;
    let mut map = Rgba8Image::filled(size, size, [0; 4]);
    for y in 0..size {
        for x in 0..size {
            let n = bump(
                (x as f32 + 0.5) / size as f32,
                (y as f32 + 0.5) / size as f32,
            );
            let e = |c: f32| ((0.5 * c + 0.5) * 255.0).round() as u8;
            map.pixels[(y * size + x) as usize] = [e(n.x), e(n.y), e(n.z), 255];
        }
    }
    // UVs turned by 90° (u along +y, v along +x): the input's tangent is
    // −y and its bitangent +x, unlike any frame an atlas chart gets.
    let mesh = plane(24, |x, y| [1.0 - y, 1.0 - x]);
    let materials = [Material {
        normal_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    }];
    let textures = [texture()];
    let images = [Some(map.clone())];
    let input = BakeInput {
        mesh: &mesh,
        materials: &materials,
        textures: &textures,
        images: &images,
    };
    let baked = bake_mesh(&input, &options(0.05, 256)).expect("bakes");
    let out_map = image_of(&baked, Channel::Normal);
    let m = &baked.mesh;
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uvs");
    let nrm = m.attribute(&Semantic::Normal).expect("normals");
    let tan = m.attribute(&Semantic::Tangent).expect("tangents written");
    let decode =
        |c: [f32; 4]| Vec3::new(2.0 * c[0] - 1.0, 2.0 * c[1] - 1.0, 2.0 * c[2] - 1.0).normalize();
    let (mut sum, mut worst, mut naive_worst, mut count) = (0.0f32, 0.0f32, 0.0f32, 0);
    for t in 0..m.faces.len() {
        for w in [
            [1.0 / 3.0; 3],
            [0.6, 0.2, 0.2],
            [0.2, 0.6, 0.2],
            [0.2, 0.2, 0.6],
        ] {
            let c = |k: usize| 3 * t + k;
            let mix = |a: &Attribute, n: usize| -> Vec<f32> {
                (0..n)
                    .map(|i| {
                        (0..3)
                            .map(|k| w[k] * a.corner_value(c(k)).expect("value")[i])
                            .sum()
                    })
                    .collect()
            };
            let f = m.faces.face(t);
            let p: Vec<f32> = (0..3)
                .map(|a| (0..3).map(|k| w[k] * m.positions[f[k] as usize][a]).sum())
                .collect();
            // Input: the map in the input's frame T = −y, B = +x, N = +z.
            let n_in = decode(bilinear(&map, [1.0 - p[1], 1.0 - p[0]], false));
            let world_in =
                (Vec3::new(0.0, -1.0, 0.0) * n_in.x + Vec3::X * n_in.y + Vec3::Z * n_in.z)
                    .normalize();
            // Output: the baked map in the output's frame, built as a
            // glTF shader builds it.
            let q = mix(uv, 2);
            let n = Vec3::from_slice(&mix(nrm, 3)).normalize();
            let tv = mix(tan, 4);
            let tt = (Vec3::new(tv[0], tv[1], tv[2]) - n * n.dot(Vec3::new(tv[0], tv[1], tv[2])))
                .normalize();
            let bb = n.cross(tt) * tv[3].signum();
            let n_out = decode(bilinear(out_map, [q[0], q[1]], false));
            let world_out = (tt * n_out.x + bb * n_out.y + n * n_out.z).normalize();
            let d = (lambert(world_in) - lambert(world_out)).abs();
            // Copying the input's tangent-space values without
            // re-expressing them would light the surface like this:
            let naive = (tt * n_in.x + bb * n_in.y + n * n_in.z).normalize();
            naive_worst = naive_worst.max((lambert(world_in) - lambert(naive)).abs());
            sum += d;
            worst = worst.max(d);
            count += 1;
        }
    }
    let mean = sum / count as f32;
    assert!(mean < 0.01 && worst < 0.05, "mean {mean}, worst {worst}");
    // The test can tell: ignoring the change of frame breaks lighting.
    assert!(naive_worst > 0.2, "naive {naive_worst}");
}

#[test]
fn an_untextured_mesh_bakes_only_a_normal_map_and_keeps_its_factors() {
    let mesh = plane(12, |x, y| [x, y]);
    let materials = [Material {
        name: "paint".into(),
        base_color: [0.2, 0.4, 0.6, 1.0],
        metallic: 0.1,
        roughness: 0.7,
        ..Material::default()
    }];
    let input = BakeInput {
        mesh: &mesh,
        materials: &materials,
        textures: &[],
        images: &[],
    };
    let baked = bake_mesh(&input, &options(0.1, 64)).expect("bakes");
    let channels: Vec<Channel> = baked.images.iter().map(|i| i.channel).collect();
    assert_eq!(channels, vec![Channel::Normal]);
    let m = &baked.materials[baked.mesh.parts[0].material.expect("material") as usize];
    assert!(
        m.normal_texture.is_some() && m.base_color_texture.is_none(),
        "{m:?}"
    );
    assert_eq!(
        (m.base_color, m.metallic, m.roughness),
        ([0.2, 0.4, 0.6, 1.0], 0.1, 0.7)
    );
    // A flat plane's shading normal is its face normal: the neutral texel
    // wherever a texel is mapped.
    let img = image_of(&baked, Channel::Normal);
    let mapped = &baked.images[0].mapped;
    for (px, _) in img.pixels.iter().zip(mapped).filter(|(_, &m)| m) {
        for (c, want) in px[..3].iter().zip([128u8, 128, 255]) {
            assert!(c.abs_diff(want) <= 2, "{px:?}");
        }
    }
    // Off: nothing to bake, the input's material as it was.
    let plain = bake_mesh(
        &input,
        &BakeOptions {
            bake_normals: false,
            ..options(0.1, 64)
        },
    )
    .expect("bakes");
    assert!(plain.images.is_empty());
    assert_eq!(plain.materials, materials.to_vec());
}

/// The atlas side a bake of `mesh` at `ratio` chooses (no
/// `texture_size`, no normal map), its one texture's image `img`, the
/// density following the level or not.
fn chosen_side(
    mesh: &Mesh,
    materials: &[Material],
    textures: &[Texture],
    img: Rgba8Image,
    follow: bool,
    ratio: f64,
) -> u32 {
    let images = [Some(img)];
    let input = BakeInput {
        mesh,
        materials,
        textures,
        images: &images,
    };
    let options = BakeOptions {
        texture_size: None,
        density_follows_level: follow,
        bake_normals: false,
        ..options(ratio, 0)
    };
    bake_mesh(&input, &options).expect("bakes").report.atlases[0].size
}

#[test]
fn a_levels_atlas_follows_the_level_unless_the_texture_has_fine_detail() {
    // A plane whose 1024² texture maps onto it once: the input's density
    // asks for a 1024² atlas at any ratio.
    let mesh = plane(24, |x, y| [x, y]);
    let materials = [textured_material()];
    let textures = [texture()];
    let atlas_side = |img: Rgba8Image, follow: bool| {
        chosen_side(&mesh, &materials, &textures, img, follow, 0.01)
    };
    let n = 1024u32;
    let image = |f: &dyn Fn(u32, u32) -> [u8; 4]| Rgba8Image {
        width: n,
        height: n,
        pixels: (0..n * n).map(|i| f(i % n, i / n)).collect(),
    };
    // A slow gradient survives any averaging: at 1% (a tenth of the
    // input's density) the atlas drops to the 256 floor.
    let smooth = |x: u32, y: u32| [(x / 8) as u8, (y / 8) as u8, 100, 255];
    assert_eq!(atlas_side(image(&smooth), false), 1024);
    assert_eq!(atlas_side(image(&smooth), true), 256);
    // A texel checker (printed text) does not: the input's density stays.
    let fine = |x: u32, y: u32| {
        let v = if (x + y) % 2 == 0 { 20 } else { 230 };
        [v, v, v, 255]
    };
    assert_eq!(atlas_side(image(&fine), true), 1024);
}

#[test]
fn an_atlas_never_holds_more_texels_than_the_images_it_replaces() {
    // A floor whose 64² tile repeats 8 × 8 times (UVs to 8, repeat
    // sampling), as leaf cards, tiled walls and trim sheets reuse one
    // image: at the input's density every repeat would get its own
    // texels, a 512² atlas for a 64² image. Mapped once, a 512² image asks
    // for the same 512²: the bound is on the images, not the density.
    let atlas_side = |repeats: f32, n: u32| {
        let mesh = plane(16, |x, y| [x * repeats, y * repeats]);
        let materials = [textured_material()];
        let textures = [Texture {
            sampler: Sampler::default(),
            ..texture()
        }];
        let img = Rgba8Image {
            width: n,
            height: n,
            pixels: (0..n * n)
                .map(|i| [(i % n * 4) as u8, (i / n * 4) as u8, 90, 255])
                .collect(),
        };
        chosen_side(&mesh, &materials, &textures, img, false, 0.5)
    };
    assert_eq!(atlas_side(8.0, 64), 64);
    assert_eq!(atlas_side(1.0, 512), 512);
}

#[test]
fn an_atlas_too_small_for_the_charts_is_an_error_and_a_chosen_size_grows() {
    // A bumpy plane: at 20% its charts cannot share a 16² atlas (each
    // takes a texel and its padding at least).
    let mut mesh = plane(16, |x, y| [x, y]);
    for (k, p) in mesh.positions.iter_mut().enumerate() {
        p[2] = 0.3 * ((k * 7919) % 13) as f32 / 13.0;
    }
    let materials = [textured_material()];
    let textures = [texture()];
    let images = [Some(Rgba8Image::filled(8, 8, [200, 100, 50, 255]))];
    let input = BakeInput {
        mesh: &mesh,
        materials: &materials,
        textures: &textures,
        images: &images,
    };
    match bake_mesh(&input, &options(0.2, 16)) {
        Err(BakeError::AtlasFull { charts, size }) => {
            assert_eq!(size, 16);
            assert!(charts > 2, "{charts}");
        }
        other => panic!(
            "expected AtlasFull, got {:?}",
            other.map(|b| b.report.atlases)
        ),
    }
    // Chosen by density (an 8² texture asks for the 64² floor), the
    // atlas grows until every chart has a place.
    let grown = bake_mesh(
        &input,
        &BakeOptions {
            texture_size: None,
            ..options(0.2, 16)
        },
    )
    .expect("grows");
    let a = &grown.report.atlases[0];
    assert!(a.size >= 64 && a.stats.utilization > 0.0, "{a:?}");
}

/// Side of the logo box's texture.
const LOGO_SIDE: u32 = 256;

/// A long box (1 × 1 × 4.5, a closed welded mesh of 8 × 8 × 36 cells)
/// whose end face z = 4.5 (5% of the surface) is a logo: its UV island is
/// the image's top-left quarter, concentric rings 12 texels apart (drawn 4
/// texels past the island's edge); the
/// other five faces show a flat colour from small strips of the rest. The
/// logo has 0.25 of the texture's texels, the other faces 0.33 together:
/// the island's share of the used texels is 0.25 / 0.58.
fn logo_box() -> (Mesh, Rgba8Image, f64) {
    let s = LOGO_SIDE;
    let flat = [90u8, 140, 200, 255];
    let mut img = Rgba8Image::filled(s, s, flat);
    // The rings run 4 texels past the island, as real atlases dilate
    // their islands' content.
    for y in 0..s / 2 + 4 {
        for x in 0..s / 2 + 4 {
            let r = ((x as f32 + 0.5 - 64.0).powi(2) + (y as f32 + 0.5 - 64.0).powi(2)).sqrt();
            let v = 128.0 + 100.0 * (std::f32::consts::TAU * r / 12.0).sin();
            img.pixels[(y * s + x) as usize] = [v as u8, (255.0 - v) as u8, 128, 255];
        }
    }
    let n = [8i32, 8, 36];
    // (fixed axis, at its far side, u axis, v axis, UV rectangle), u × v
    // outward.
    let long = |k: f32| [0.51 + 0.12 * k, 0.02, 0.59 + 0.12 * k, 0.98];
    let faces: [(usize, bool, usize, usize, [f32; 4]); 6] = [
        (2, true, 0, 1, [0.0, 0.0, 0.5, 0.5]),
        (2, false, 1, 0, [0.05, 0.6, 0.2, 0.75]),
        (0, true, 1, 2, long(0.0)),
        (0, false, 2, 1, long(1.0)),
        (1, true, 2, 0, long(2.0)),
        (1, false, 0, 2, long(3.0)),
    ];
    let used: f64 = faces
        .iter()
        .map(|f| f64::from((f.4[2] - f.4[0]) * (f.4[3] - f.4[1])))
        .sum();
    let mut ids = std::collections::HashMap::new();
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut f = Faces::new();
    for &(axis, far, ua, va, rect) in &faces {
        let (nu, nv) = (n[ua], n[va]);
        let mut id = |i: i32, j: i32, uvs: &mut Vec<f32>| {
            let mut c = [0i32; 3];
            c[axis] = if far { n[axis] } else { 0 };
            c[ua] = i;
            c[va] = j;
            let next = positions.len() as u32;
            let v = *ids.entry(c).or_insert_with(|| {
                positions.push(c.map(|x| x as f32 / 8.0));
                next
            });
            let (s, t) = (i as f32 / nu as f32, j as f32 / nv as f32);
            uvs.extend_from_slice(&[
                rect[0] + s * (rect[2] - rect[0]),
                rect[1] + t * (rect[3] - rect[1]),
            ]);
            v
        };
        for j in 0..nv {
            for i in 0..nu {
                for tri in [
                    [(i, j), (i + 1, j), (i + 1, j + 1)],
                    [(i, j), (i + 1, j + 1), (i, j + 1)],
                ] {
                    let t = tri.map(|(a, b)| id(a, b, &mut uvs));
                    f.push(&t);
                }
            }
        }
    }
    let mut m = Mesh::from_polygons(positions, f);
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uvs,
        indices: (0..m.faces.corner_count() as u32).collect(),
        format: ComponentFormat::F32,
    });
    m.parts[0].material = Some(0);
    (m, img, 0.25 / used)
}

/// The logo's output triangles (on the end face z = 4.5) of a bake with a
/// `size`² atlas: their texels per unit of area, and their share of the
/// texels inside charts.
fn logo_density_and_share(baked: &Baked, size: u32) -> (f64, f64, Vec<bool>) {
    let m = &baked.mesh;
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uvs");
    let corner_uvs: Vec<[f32; 2]> = (0..m.faces.corner_count())
        .map(|c| {
            let v = uv.corner_value(c).expect("uv");
            [v[0] * size as f32, v[1] * size as f32]
        })
        .collect();
    let logo: Vec<bool> = (0..m.faces.len())
        .map(|t| {
            m.faces
                .face(t)
                .iter()
                .all(|&v| (m.positions[v as usize][2] - 4.5).abs() < 1e-4)
        })
        .collect();
    let (mut texels, mut area) = (0.0, 0.0);
    for t in (0..m.faces.len()).filter(|&t| logo[t]) {
        let p: Vec<Vec3> = m
            .faces
            .face(t)
            .iter()
            .map(|&v| Vec3::from(m.positions[v as usize]))
            .collect();
        let q = &corner_uvs[3 * t..3 * t + 3];
        area += 0.5 * f64::from((p[1] - p[0]).cross(p[2] - p[0]).length());
        texels += 0.5
            * f64::from(
                ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                    - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]))
                    .abs(),
            );
    }
    let cov = rasterize(&corner_uvs, size, 0.0);
    let inside: Vec<u32> = cov
        .triangle
        .iter()
        .zip(&cov.distance)
        .filter(|(&t, &d)| t != NO_TRIANGLE && d == 0.0)
        .map(|(&t, _)| t)
        .collect();
    let on_logo = inside.iter().filter(|&&t| logo[t as usize]).count();
    assert!(
        area > 0.9,
        "the logo face survives as output triangles: {area}"
    );
    (texels / area, on_logo as f64 / inside.len() as f64, logo)
}

#[test]
fn a_small_high_detail_island_keeps_its_texel_density_and_share_of_the_atlas() {
    let (mesh, img, input_share) = logo_box();
    let materials = [textured_material()];
    let textures = [texture()];
    let images = [Some(img.clone())];
    let input = BakeInput {
        mesh: &mesh,
        materials: &materials,
        textures: &textures,
        images: &images,
    };
    let s = LOGO_SIDE;
    // (a) An atlas as large as the input: the logo keeps its density.
    let opts = BakeOptions {
        bake_normals: false,
        ..options(0.01, s)
    };
    let baked = bake_mesh(&input, &opts).expect("bakes");
    assert!(baked.mesh.faces.len() <= 40, "{}", baked.mesh.faces.len());
    let (density, _, logo) = logo_density_and_share(&baked, s);
    // Input: a quarter of the image on a unit square.
    let input_density = 0.25 * f64::from(s * s);
    let linear = (density / input_density).sqrt();
    assert!(
        linear >= 0.8,
        "logo at {linear:.3}× the input's linear density"
    );
    // Its texels are the input's, filtered at the matching scale: every
    // output texel center inside a logo triangle, at surface point (x, y,
    // 4.5), shows the input around UV (x/2, y/2), averaged over the
    // output texel's footprint when it covers more than an input texel.
    let base = image_of(&baked, Channel::BaseColor);
    let m = &baked.mesh;
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uvs");
    let corner_uvs: Vec<[f32; 2]> = (0..m.faces.corner_count())
        .map(|c| {
            let v = uv.corner_value(c).expect("uv");
            [v[0] * s as f32, v[1] * s as f32]
        })
        .collect();
    let cov = rasterize(&corner_uvs, s, 0.0);
    let footprint = (1.0 / linear) as f32;
    let reference = |q: [f32; 2]| -> [f32; 4] {
        if footprint <= 1.0 {
            return bilinear(&img, q, true);
        }
        let k = 8;
        let mut sum = [0.0f32; 4];
        for j in 0..k {
            for i in 0..k {
                let d = |a: usize| ((a as f32 + 0.5) / k as f32 - 0.5) * footprint / s as f32;
                let c = bilinear(&img, [q[0] + d(i), q[1] + d(j)], true);
                for a in 0..4 {
                    sum[a] += c[a] / (k * k) as f32;
                }
            }
        }
        sum
    };
    let mut checked = 0;
    for (i, &t) in cov.triangle.iter().enumerate() {
        if t == NO_TRIANGLE || cov.distance[i] > 0.0 || !logo[t as usize] {
            continue;
        }
        let f = m.faces.face(t as usize);
        let b = cov.bary[i];
        let p = [0, 1].map(|a| {
            (0..3)
                .map(|k| b[k] * m.positions[f[k] as usize][a])
                .sum::<f32>()
        });
        let want = reference([p[0] / 2.0, p[1] / 2.0]);
        let got = base.pixels[i];
        for a in 0..3 {
            let w = (linear_to_srgb(want[a]) * 255.0).round();
            assert!(
                (f32::from(got[a]) - w).abs() <= 8.0,
                "texel {i} at {p:?}: {got:?} against {w} (channel {a})"
            );
        }
        checked += 1;
    }
    // The logo's 128² input texels come back as about as many.
    assert!(checked as f64 >= 0.6 * 128.0 * 128.0, "{checked}");

    // (b) Smaller atlases (the default a level picks, and a quarter of the
    // input's side): the logo keeps its share of the texels.
    for size in [None, Some(s / 2), Some(s / 4)] {
        let opts = BakeOptions {
            bake_normals: false,
            texture_size: size,
            ..options(0.01, s)
        };
        let baked = bake_mesh(&input, &opts).expect("bakes");
        let side = baked.report.atlases[0].size;
        let (_, share, _) = logo_density_and_share(&baked, side);
        assert!(
            share >= 0.8 * input_share,
            "{side}² atlas: the logo has {share:.3} of the chart texels, {input_share:.3} of the input's"
        );
    }
}
