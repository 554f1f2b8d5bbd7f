//! Generated inputs for the re-baking benchmarks (issue 33): a textured
//! mesh of about 20,000 triangles with a continuous UV layout and a 2048²
//! base colour image, and a scan-like mesh of about 10,000 triangles (a
//! jittered bumpy sphere) whose every quad is its own UV island in a 4096²
//! image, as photogrammetry atlases are, and a noisy terrain (a height
//! field whose every height carries a survey's noise, planar UVs), and a
//! scene of thousands of small textured meshes. Made in
//! code, so that no corpus
//! file is copied into the repository; `--bin bake-inputs` writes them as
//! GLB for the whole-process timings.

use wildlod_mesh::{
    shapes, Attribute, ComponentFormat, ImageSource, Material, Mesh, Rgba8Image, Scene, Semantic,
    Texture, TextureRef,
};

/// A generated input: the scene and its decoded base colour image.
pub struct BakeInput {
    /// One mesh, one material with a base colour texture.
    pub scene: Scene,
    /// The decoded image of texture 0.
    pub image: Rgba8Image,
}

/// A bumpy torus of `2 · nu · nv` triangles with UVs following its
/// (u, v) parametrization, seamed once each way, and a `size`² image of a
/// checker with gradients (detail everywhere).
pub fn textured_torus(nu: usize, nv: usize, size: u32) -> BakeInput {
    let mut m = shapes::triangulate(&shapes::torus(nu, nv, 1.0, 0.35));
    // Bumps in the normal-ish direction: something for the LOD to lose.
    for p in &mut m.positions {
        let r = 1.0 + 0.04 * (7.0 * p[0]).sin() * (5.0 * p[1]).cos() * (9.0 * p[2]).sin();
        *p = p.map(|c| c * r);
    }
    // UV per corner from the angle around the axis and around the tube.
    let mut uv = Vec::with_capacity(2 * m.faces.corner_count());
    for f in 0..m.faces.len() {
        let face = m.faces.face(f);
        let angles: Vec<[f32; 2]> = face
            .iter()
            .map(|&v| {
                let p = m.positions[v as usize];
                let u = p[1].atan2(p[0]) / std::f32::consts::TAU + 0.5;
                let ring = (p[0] * p[0] + p[1] * p[1]).sqrt() - 1.0;
                let w = p[2].atan2(ring) / std::f32::consts::TAU + 0.5;
                [u, w]
            })
            .collect();
        // Faces across the seam get their wrapped corners moved by one.
        let fix = |k: usize| {
            let max = angles
                .iter()
                .fold([0f32; 2], |a, b| [a[0].max(b[0]), a[1].max(b[1])]);
            let mut q = angles[k];
            for a in 0..2 {
                if max[a] - q[a] > 0.5 {
                    q[a] += 1.0;
                }
            }
            q
        };
        for k in 0..face.len() {
            uv.extend_from_slice(&fix(k));
        }
    }
    set_uv(&mut m, uv);
    let image = pattern(size, 32);
    BakeInput {
        scene: scene(m, "torus"),
        image,
    }
}

/// A bumpy quad sphere of `12 n²` triangles, every vertex jittered (a
/// scan's noise), every quad its own UV island in a grid over a `size`²
/// image of fine detail.
pub fn scan_like(n: usize, size: u32) -> BakeInput {
    let quads = shapes::bumpy_quad_sphere(n);
    let mut m = shapes::triangulate(&quads);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for p in &mut m.positions {
        for c in p.iter_mut() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            *c += ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.4 / n as f32;
        }
    }
    // Two triangles per quad, in order: quad q = triangles 2q, 2q + 1.
    let nq = m.faces.len().div_ceil(2);
    let cols = (nq as f32).sqrt().ceil() as usize;
    let mut uv = Vec::with_capacity(2 * m.faces.corner_count());
    for f in 0..m.faces.len() {
        let q = f / 2;
        let (cx, cy) = ((q % cols) as f32, (q / cols) as f32);
        let corners: [(f32, f32); 3] = if f % 2 == 0 {
            [(0.05, 0.05), (0.95, 0.05), (0.95, 0.95)]
        } else {
            [(0.05, 0.05), (0.95, 0.95), (0.05, 0.95)]
        };
        for (du, dv) in corners {
            uv.extend_from_slice(&[(cx + du) / cols as f32, (cy + dv) / cols as f32]);
        }
    }
    set_uv(&mut m, uv);
    let image = pattern(size, 8);
    BakeInput {
        scene: scene(m, "scan"),
        image,
    }
}

/// An open height field of `n × n` vertices (`2 (n − 1)²` triangles, 100 ×
/// 100 units, hills of a few units) whose every height is jittered by up to
/// a cell size either way (a terrain survey's or a scan's noise: its LOD
/// keeps the spikes, and a fifth of the LOD's faces tilt by more than 45°),
/// with planar UVs over a `size`² image.
pub fn noisy_terrain(n: usize, size: u32) -> BakeInput {
    let n = n.max(2);
    let cell = 100.0 / (n - 1) as f32;
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut positions = Vec::with_capacity(n * n);
    let mut uv = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let r = (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5;
            let (x, z) = (i as f32 * cell, j as f32 * cell);
            let y = 4.0 * (0.07 * x).sin() * (0.05 * z + 0.3).cos()
                + 2.0 * (0.13 * x + 0.11 * z).sin()
                + 2.0 * cell * r;
            positions.push([x, y, z]);
            uv.extend_from_slice(&[x / 100.0, z / 100.0]);
        }
    }
    let indices = wildlod_testkit::height_field_triangles(n);
    let mut m = Mesh::from_triangles(positions, &indices);
    // UVs per corner, from the corner's vertex.
    let corner_uv: Vec<f32> = m
        .faces
        .indices
        .iter()
        .flat_map(|&v| [uv[2 * v as usize], uv[2 * v as usize + 1]])
        .collect();
    set_uv(&mut m, corner_uv);
    let image = pattern(size, 16);
    BakeInput {
        scene: scene(m, "terrain"),
        image,
    }
}

/// Per-corner `TEXCOORD_0`.
fn set_uv(m: &mut Mesh, uv: Vec<f32>) {
    let n = uv.len() as u32 / 2;
    set_uv_indexed(m, uv, (0..n).collect());
}

/// Sets UV set 0 to the pairs `uv`, corner `c` reading pair `indices[c]`.
fn set_uv_indexed(m: &mut Mesh, uv: Vec<f32>, indices: Vec<u32>) {
    m.attributes.retain(|a| a.semantic != Semantic::TexCoord(0));
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices,
        format: ComponentFormat::F32,
    });
}

/// `n` meshes, each a box of 12 triangles with its own proportions and
/// place (a kit-bashed scene, an assembly of parts), every face mapped to
/// one cell of a 3 × 2 grid of a `size`² image they all share: the scene
/// of many meshes a whole-file budget and a scene-wide bake must stay
/// linear on.
pub fn many_boxes(n: usize, size: u32) -> BakeInput {
    let grid = (n as f64).sqrt().ceil().max(1.0) as usize;
    // (normal, u axis, v axis) of the six faces.
    let sides: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    let mut scene = Scene::default();
    for k in 0..n {
        // Deterministic proportions between 0.2 and 1.
        let f = |a: usize| 0.2 + 0.8 * (((k * 7 + a * 13) * 2654435761) % 1000) as f32 / 1000.0;
        let size3 = [f(0), f(1), f(2)];
        let (mut positions, mut uv, mut indices) = (Vec::new(), Vec::new(), Vec::new());
        for (s, (nrm, u, v)) in sides.iter().enumerate() {
            let base = positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p: [f32; 3] =
                    std::array::from_fn(|i| (nrm[i] + a * u[i] + b * v[i]) * size3[i]);
                positions.push(p);
                uv.extend_from_slice(&[
                    ((s % 3) as f32 + (a + 1.0) / 2.0) / 3.0,
                    ((s / 3) as f32 + (b + 1.0) / 2.0) / 2.0,
                ]);
            }
            indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        let mut m = Mesh::from_triangles(positions, &indices);
        m.name = format!("box {k}");
        // One UV per vertex (the corners of a side share its four).
        set_uv_indexed(&mut m, uv, indices);
        m.parts[0].material = Some(0);
        scene.meshes.push(m);
        let mut matrix = wildlod_mesh::IDENTITY;
        matrix[12] = 2.5 * (k % grid) as f32;
        matrix[14] = 2.5 * (k / grid) as f32;
        scene.nodes.push(wildlod_mesh::Node {
            name: format!("box {k}"),
            matrix,
            mesh: Some(k as u32),
            ..Default::default()
        });
        scene.roots.push(k as u32);
    }
    add_textured_material(&mut scene, "boxes");
    BakeInput {
        scene,
        image: pattern(size, 16),
    }
}

/// A checker of `cell`-texel squares with colour gradients.
fn pattern(size: u32, cell: usize) -> Rgba8Image {
    let mut img = Rgba8Image {
        width: size,
        height: size,
        pixels: vec![[0; 4]; size as usize * size as usize],
    };
    let s = size as usize;
    for (i, p) in img.pixels.iter_mut().enumerate() {
        let (x, y) = (i % s, i / s);
        let c = if (x / cell + y / cell) % 2 == 0 {
            220
        } else {
            40
        };
        *p = [c, (x * 255 / s) as u8, (y * 255 / s) as u8, 255];
    }
    img
}

/// The scene around a mesh: one material whose base colour is texture 0,
/// a placeholder path as its source (the benchmarks pass decoded images;
/// `bake-inputs` embeds the PNG).
fn scene(mut m: Mesh, name: &str) -> Scene {
    m.parts[0].material = Some(0);
    let mut scene = Scene::from_mesh(m);
    add_textured_material(&mut scene, name);
    scene
}

/// Adds material 0, whose base colour is texture 0 named `name` (a
/// placeholder path as its source).
fn add_textured_material(scene: &mut Scene, name: &str) {
    scene.materials.push(Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    });
    scene.textures.push(Texture {
        name: name.into(),
        source: ImageSource::Path(format!("{name}.png").into()),
        sampler: Default::default(),
    });
}
