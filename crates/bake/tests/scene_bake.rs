//! Several meshes baked together (`bake_meshes`): one atlas, one material
//! and one image per shared input material, the meshes' charts side by
//! side in it, and every texel baked from its own mesh's input.

use wildlod_bake::{
    bake_meshes, rasterize, BakeInput, BakeOptions, Channel, SceneMesh, NO_TRIANGLE,
};
use wildlod_mesh::shapes::{quad_grid, triangulate};
use wildlod_mesh::{
    Attribute, ComponentFormat, ImageSource, Material, Mesh, Part, Rgba8Image, Sampler, Semantic,
    Texture, TextureRef, Wrap,
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

/// Reference bilinear lookup (clamp to edge) of an sRGB image, filtered in
/// linear, written independently of the baker.
fn bilinear(img: &Rgba8Image, uv: [f32; 2]) -> [f32; 3] {
    let x = uv[0] as f64 * img.width as f64 - 0.5;
    let y = uv[1] as f64 * img.height as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
    let at = |xi: f64, yi: f64| {
        let xi = (xi as i64).clamp(0, img.width as i64 - 1) as usize;
        let yi = (yi as i64).clamp(0, img.height as i64 - 1) as usize;
        let p = img.pixels[yi * img.width as usize + xi];
        [0, 1, 2].map(|k| srgb_to_linear(p[k] as f32 / 255.0))
    };
    let (a, b, c, d) = (
        at(x0, y0),
        at(x0 + 1.0, y0),
        at(x0, y0 + 1.0),
        at(x0 + 1.0, y0 + 1.0),
    );
    [0, 1, 2].map(|k| {
        let top = a[k] + (b[k] - a[k]) * fx;
        let bottom = c[k] + (d[k] - c[k]) * fx;
        top + (bottom - top) * fy
    })
}

/// A 64² checker of 8² squares, every square its own color.
fn checker() -> Rgba8Image {
    let mut img = Rgba8Image::filled(64, 64, [0; 4]);
    for y in 0..64usize {
        for x in 0..64usize {
            let h = ((y / 8 * 8 + x / 8) as u32 + 1).wrapping_mul(2_654_435_761);
            img.pixels[y * 64 + x] = [(h >> 24) as u8, (h >> 16) as u8, (h >> 8) as u8, 255];
        }
    }
    img
}

/// The uv of a point of the unit plane on mesh `k`: mesh 0 shows the
/// checker's left half, mesh 1 its right half.
fn uv_of(k: usize, x: f32, y: f32) -> [f32; 2] {
    [0.5 * k as f32 + 0.5 * x, 1.0 - y]
}

/// Mesh `k`: `n × n` quads on [k, k + 1] × [0, 1], triangulated, with
/// its UVs.
fn plane(n: usize, k: usize) -> Mesh {
    let mut m = triangulate(&quad_grid(n, n));
    for p in &mut m.positions {
        p[0] += k as f32;
    }
    let values: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|p| uv_of(k, p[0] - k as f32, p[1]))
        .collect();
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

/// Whether `p` is inside triangle `q` by more than `eps` (barycentrics).
fn strictly_inside(p: [f32; 2], q: [[f32; 2]; 3], eps: f32) -> bool {
    let d = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
    if d.abs() < 1e-12 {
        return false;
    }
    let b1 = ((p[0] - q[0][0]) * (q[2][1] - q[0][1]) - (p[1] - q[0][1]) * (q[2][0] - q[0][0])) / d;
    let b2 = ((q[1][0] - q[0][0]) * (p[1] - q[0][1]) - (q[1][1] - q[0][1]) * (p[0] - q[0][0])) / d;
    b1 > eps && b2 > eps && 1.0 - b1 - b2 > eps
}

#[test]
fn two_meshes_sharing_a_material_bake_into_one_atlas_each_from_its_own_input() {
    let img = checker();
    // Two planes side by side, of different tessellations (so different
    // histories), each reading its own half of the image.
    let meshes = [plane(16, 0), plane(12, 1)];
    let materials = [Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    }];
    let textures = [Texture {
        name: "t".into(),
        source: ImageSource::Path("t.png".into()),
        sampler: Sampler {
            wrap_u: Wrap::ClampToEdge,
            wrap_v: Wrap::ClampToEdge,
        },
    }];
    let images = [Some(img.clone())];
    let size = 256u32;
    let scene: Vec<SceneMesh> = meshes
        .iter()
        .map(|mesh| SceneMesh {
            input: BakeInput {
                mesh,
                materials: &materials,
                textures: &textures,
                images: &images,
            },
            simplify: Options {
                target: Target {
                    ratio: Some(0.1),
                    ..Target::default()
                },
                ..Options::default()
            },
            world_scale: 1.0,
        })
        .collect();
    let options = BakeOptions {
        texture_size: Some(size),
        bake_normals: false,
        ..BakeOptions::default()
    };
    let baked = bake_meshes(&scene, &options).expect("bakes");
    assert_eq!(baked.materials.len(), 1);
    let base: Vec<_> = baked
        .images
        .iter()
        .filter(|i| i.channel == Channel::BaseColor)
        .collect();
    assert_eq!(base.len(), 1);
    let out = &base[0].image;
    assert_eq!(out.width, size);

    // Every corner of both meshes in the atlas, both meshes on material 0.
    let mut corner_uvs: Vec<[f32; 2]> = Vec::new();
    let mut owner_mesh: Vec<usize> = Vec::new();
    for (k, b) in baked.meshes.iter().enumerate() {
        assert!(!b.keeps_input_materials);
        assert!(b.mesh.parts.iter().all(|p| p.material == Some(0)));
        let uv = b.mesh.attribute(&Semantic::TexCoord(0)).expect("uvs");
        for c in 0..b.mesh.faces.corner_count() {
            let v = uv.corner_value(c).expect("uv");
            assert!(
                (0.0..=1.0).contains(&v[0]) && (0.0..=1.0).contains(&v[1]),
                "{v:?}"
            );
            corner_uvs.push([v[0] * size as f32, v[1] * size as f32]);
        }
        owner_mesh.extend(std::iter::repeat_n(k, b.mesh.faces.len()));
    }
    assert!(owner_mesh.contains(&0) && owner_mesh.contains(&1));

    // No two triangles of different meshes overlap: every sample (four a
    // texel) strictly inside triangles of at most one mesh.
    let n = 4 * size as usize;
    let mut inside = vec![[false; 2]; n * n];
    for (t, &k) in owner_mesh.iter().enumerate() {
        let q = [0, 1, 2].map(|c| corner_uvs[3 * t + c].map(|v| v * 4.0));
        let lo = [0, 1].map(|a| q.iter().map(|v| v[a]).fold(f32::INFINITY, f32::min));
        let hi = [0, 1].map(|a| q.iter().map(|v| v[a]).fold(f32::NEG_INFINITY, f32::max));
        for y in (lo[1].floor().max(0.0) as usize)..(hi[1].ceil() as usize).min(n) {
            for x in (lo[0].floor().max(0.0) as usize)..(hi[0].ceil() as usize).min(n) {
                if strictly_inside([x as f32 + 0.5, y as f32 + 0.5], q, 1e-3) {
                    inside[y * n + x][k] = true;
                }
            }
        }
    }
    for k in 0..2 {
        let covered = inside.iter().filter(|s| s[k]).count();
        assert!(covered > n * n / 10, "mesh {k} covers {covered} samples");
    }
    let both = inside.iter().filter(|s| s[0] && s[1]).count();
    assert_eq!(both, 0, "{both} samples covered by both meshes");

    // Each mesh's texels hold its own input: on the plane the input point
    // is the output point, read through that mesh's UVs.
    let cov = rasterize(&corner_uvs, size, 1.5);
    let mut first_tri = vec![0usize; baked.meshes.len()];
    for k in 1..baked.meshes.len() {
        first_tri[k] = first_tri[k - 1] + baked.meshes[k - 1].mesh.faces.len();
    }
    let mut worst = 0i32;
    let mut counted = [0usize; 2];
    for (i, &t) in cov.triangle.iter().enumerate() {
        if t == NO_TRIANGLE {
            continue;
        }
        let k = owner_mesh[t as usize];
        let m = &baked.meshes[k].mesh;
        let f = m.faces.face(t as usize - first_tri[k]);
        let b = cov.bary[i];
        let p: [f32; 3] =
            [0, 1, 2].map(|a| (0..3).map(|c| b[c] * m.positions[f[c] as usize][a]).sum());
        let want = bilinear(&img, uv_of(k, p[0] - k as f32, p[1]));
        for (&got, &w) in out.pixels[i].iter().zip(&want) {
            let w = (linear_to_srgb(w) * 255.0).round() as i32;
            worst = worst.max((got as i32 - w).abs());
        }
        counted[k] += 1;
    }
    assert!(counted.iter().all(|&c| c > 2000), "{counted:?} texels");
    assert!(worst <= 8, "largest difference {worst}/255");
}

/// Total UV area (in the atlas's unit square) of a mesh's triangles.
fn uv_area(m: &Mesh) -> f64 {
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uvs");
    (0..m.faces.len())
        .map(|f| {
            let q: Vec<&[f32]> = (0..3)
                .map(|k| uv.corner_value(3 * f + k).expect("uv"))
                .collect();
            0.5 * f64::from(
                ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                    - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]))
                    .abs(),
            )
        })
        .sum()
}

#[test]
fn surface_without_a_density_of_its_own_gets_the_typical_one_per_unit_of_world_area() {
    // A textured unit plane, and a unit plane of the same material with no
    // UVs (no input density of its own: it gets the typical one) drawn at
    // twice the size. Per unit of world surface the two get the same
    // texels, so the second, four times the world area, gets four times
    // the atlas area (one in its own units would give it the same).
    let img = checker();
    let mut bare = plane(8, 1);
    bare.attributes
        .retain(|a| a.semantic != Semantic::TexCoord(0));
    let meshes = [plane(8, 0), bare];
    let materials = [Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    }];
    let textures = [Texture {
        name: "t".into(),
        source: ImageSource::Path("t.png".into()),
        sampler: Sampler::default(),
    }];
    let images = [Some(img)];
    let scene: Vec<SceneMesh> = meshes
        .iter()
        .zip([1.0, 2.0])
        .map(|(mesh, world_scale)| SceneMesh {
            input: BakeInput {
                mesh,
                materials: &materials,
                textures: &textures,
                images: &images,
            },
            simplify: Options {
                target: Target {
                    ratio: Some(0.5),
                    ..Target::default()
                },
                ..Options::default()
            },
            world_scale,
        })
        .collect();
    let options = BakeOptions {
        texture_size: Some(256),
        bake_normals: false,
        ..BakeOptions::default()
    };
    let baked = bake_meshes(&scene, &options).expect("bakes");
    assert_eq!(baked.materials.len(), 1);
    let (a, b) = (
        uv_area(&baked.meshes[0].mesh),
        uv_area(&baked.meshes[1].mesh),
    );
    assert!(a > 0.01, "{a}");
    let ratio = b / a;
    assert!((3.6..=4.4).contains(&ratio), "atlas area ratio {ratio:.3}");
}

#[test]
fn a_mesh_with_nothing_to_bake_keeps_its_materials_beside_a_baked_one() {
    // Mesh 0 textured (material 0), mesh 1 plain (material 1, a factor
    // only); no normal maps asked: mesh 1 has nothing to bake.
    let img = checker();
    let mut plain = plane(8, 1);
    plain.parts[0].material = Some(1);
    let meshes = [plane(8, 0), plain];
    let materials = [
        Material {
            base_color_texture: Some(TextureRef {
                texture: 0,
                tex_coord: 0,
            }),
            ..Material::default()
        },
        Material {
            name: "plain".into(),
            base_color: [0.2, 0.4, 0.6, 1.0],
            ..Material::default()
        },
    ];
    let textures = [Texture {
        name: "t".into(),
        source: ImageSource::Path("t.png".into()),
        sampler: Sampler::default(),
    }];
    let images = [Some(img)];
    let scene: Vec<SceneMesh> = meshes
        .iter()
        .map(|mesh| SceneMesh {
            input: BakeInput {
                mesh,
                materials: &materials,
                textures: &textures,
                images: &images,
            },
            simplify: Options {
                target: Target {
                    ratio: Some(0.5),
                    ..Target::default()
                },
                ..Options::default()
            },
            world_scale: 1.0,
        })
        .collect();
    let options = BakeOptions {
        texture_size: Some(128),
        bake_normals: false,
        ..BakeOptions::default()
    };
    let baked = bake_meshes(&scene, &options).expect("bakes");
    assert_eq!(baked.materials.len(), 1);
    assert_eq!(baked.atlases.len(), 1);
    assert_eq!(baked.atlas_meshes, vec![vec![0]]);
    let (a, b) = (&baked.meshes[0], &baked.meshes[1]);
    assert!(!a.keeps_input_materials && a.mesh.parts[0].material == Some(0));
    assert!(a.mesh.attribute(&Semantic::TexCoord(0)).is_some());
    assert!(b.keeps_input_materials, "nothing to bake on mesh 1");
    assert_eq!(b.mesh.parts[0].material, Some(1));
    assert!(b.atlases.is_empty() && b.report.atlases.is_empty());
    assert!(b.mesh.attribute(&Semantic::TexCoord(0)).is_none());
}

#[test]
fn a_mesh_reduced_further_gets_fewer_texels_in_the_shared_atlas() {
    // Two equal planes over equal halves of one flat colour (which may be
    // averaged down without a visible change): one kept whole, one reduced
    // to a few triangles. Each mesh's own atlas would follow its level (√
    // of the triangles kept); in the shared atlas its charts do.
    let img = Rgba8Image::filled(64, 64, [200, 120, 40, 255]);
    let meshes = [plane(8, 0), plane(8, 1)];
    let materials = [Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    }];
    let textures = [Texture {
        name: "t".into(),
        source: ImageSource::Path("t.png".into()),
        sampler: Sampler::default(),
    }];
    let images = [Some(img)];
    let scene: Vec<SceneMesh> = meshes
        .iter()
        .zip([1.0, 0.03])
        .map(|(mesh, ratio)| SceneMesh {
            input: BakeInput {
                mesh,
                materials: &materials,
                textures: &textures,
                images: &images,
            },
            simplify: Options {
                target: Target {
                    ratio: Some(ratio),
                    ..Target::default()
                },
                ..Options::default()
            },
            world_scale: 1.0,
        })
        .collect();
    let options = BakeOptions {
        bake_normals: false,
        ..BakeOptions::default()
    };
    let baked = bake_meshes(&scene, &options).expect("bakes");
    assert_eq!(baked.materials.len(), 1);
    let level = |k: usize| {
        let r = &baked.meshes[k].report.simplify;
        r.output_triangles as f64 / r.input_triangles as f64
    };
    assert!(
        level(0) > 0.99 && level(1) < 0.1,
        "{} {}",
        level(0),
        level(1)
    );
    let (a, b) = (
        uv_area(&baked.meshes[0].mesh),
        uv_area(&baked.meshes[1].mesh),
    );
    let ratio = b / a;
    assert!(
        ratio < 0.5,
        "atlas area ratio {ratio:.3}, level {:.3}",
        level(1)
    );
}
