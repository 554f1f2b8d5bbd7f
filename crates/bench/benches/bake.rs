//! Texture re-baking (W §4.3): the time to map one texel back to the input
//! through the collapse history (W reports < 5 µs per point; our bar is
//! 2 µs per texel per core), and the whole bake of a 2048² atlas.
//!
//! `cargo bench -p wildlod-bake --bench bake` (or `-p wildlod-bench`) runs,
//! per corpus mesh (Avocado, CesiumMilkTruck's truck, bob) and generated
//! inputs (`wildlod_bench::bake_inputs`: a 20k-triangle textured torus, a
//! 10k-triangle scan-like sphere) at 10% and 1%:
//!
//! - `map <ratio>`: [`SuccessiveMap::map`] on every texel of every 8th
//!   triangle of the 2048² bake's atlas, one walk per texel (throughput:
//!   texels per second, single thread);
//! - `map coherent <ratio>`: the same texels through
//!   [`SuccessiveMap::map_many`], grouped as the bake groups them (by
//!   triangle within 32×32 tiles), single thread;
//! - `bake 2048 <ratio>`: [`bake_mesh`] with a 2048² atlas, simplification
//!   included (all threads), and `simplify <ratio>` alone for comparison.
//!
//! Then it prints µs per texel: mapping alone on one core, per texel and
//! coherent, as wall time and as the thread's CPU time (`/proc/thread-self/schedstat`, Linux), and
//! the whole bake per mapped texel as wall time and as the process's CPU
//! time. CPU time is what a texel costs a core even when other work shares
//! the machine; wall time is what a user waits. Under `cargo test` it runs
//! once on a small generated mesh so that it keeps compiling and working.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput};
use wildlod_bake::{
    bake_mesh, build_atlas, rasterize, AtlasOptions, BakeInput, BakeOptions, SuccessiveMap,
    SurfacePoint, NO_TRIANGLE,
};
use wildlod_bench::bake_inputs::{scan_like, textured_torus};
use wildlod_mesh::{shapes, Material, Mesh, Rgba8Image, Scene, Texture, TextureRef};
use wildlod_simplify::{simplify_polygons, Options, Target};

struct Case {
    name: String,
    scene: Scene,
    mesh: usize,
    images: Vec<Option<Rgba8Image>>,
}

fn corpus_cases(root: &Path) -> Vec<Case> {
    [
        ("Avocado", "textured/Avocado/Avocado.gltf", 0),
        ("CesiumMilkTruck", "textured/CesiumMilkTruck.glb", 0),
        ("bob", "textured/bob/bob_tri.obj", 0),
    ]
    .iter()
    .filter_map(|(name, rel, mesh)| {
        let doc = wildlod_io::read(root.join(rel)).ok()?;
        let images = doc
            .scene
            .textures
            .iter()
            .map(|t| wildlod_io::decode_image_rgba8(&t.source).ok())
            .collect();
        Some(Case {
            name: name.to_string(),
            scene: doc.scene,
            mesh: *mesh,
            images,
        })
    })
    .collect()
}

/// A torus whose every quad is its own UV island in a 1024² checker
/// image: the worst case of a "wild" mesh.
fn generated_case() -> Case {
    let mut m = shapes::triangulate(&shapes::torus(48, 24, 1.0, 0.3));
    let n = m.faces.len();
    let cols = (n as f32).sqrt().ceil() as usize;
    let mut uv = Vec::with_capacity(2 * 3 * n);
    for f in 0..n {
        let (cx, cy) = ((f % cols) as f32, (f / cols) as f32);
        for (du, dv) in [(0.1, 0.1), (0.9, 0.1), (0.1, 0.9)] {
            uv.extend_from_slice(&[(cx + du) / cols as f32, (cy + dv) / cols as f32]);
        }
    }
    m.attributes.push(wildlod_mesh::Attribute {
        semantic: wildlod_mesh::Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices: (0..3 * n as u32).collect(),
        format: wildlod_mesh::ComponentFormat::F32,
    });
    m.parts[0].material = Some(0);
    let mut scene = Scene::from_mesh(m);
    scene.materials.push(Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    });
    scene.textures.push(Texture {
        name: "checker".into(),
        source: wildlod_mesh::ImageSource::Path("checker.png".into()),
        sampler: Default::default(),
    });
    let mut img = Rgba8Image::filled(1024, 1024, [0; 4]);
    for (i, p) in img.pixels.iter_mut().enumerate() {
        let (x, y) = (i % 1024, i / 1024);
        let c = if (x / 16 + y / 16) % 2 == 0 { 230 } else { 30 };
        *p = [c, (x / 4) as u8, (y / 4) as u8, 255];
    }
    Case {
        name: "generated island torus".into(),
        scene,
        mesh: 0,
        images: vec![Some(img)],
    }
}

fn options(ratio: f64) -> Options {
    Options {
        target: Target {
            ratio: Some(ratio),
            ..Target::default()
        },
        ..Options::default()
    }
}

/// Texels of one output triangle within one tile: the input face id of
/// its output face, and their surface points.
type TexelGroup = (u32, Vec<[f32; 3]>);

/// The texels the bake of a `size`² atlas maps, of every `stride`-th
/// triangle, grouped as the bake groups them (by triangle within 32×32
/// tiles): (input face of the group's output face, points).
fn texel_groups(
    mesh: &Mesh,
    ratio: f64,
    size: u32,
    stride: usize,
) -> (wildlod_simplify::Simplified, Vec<TexelGroup>) {
    let mut o = options(ratio);
    o.record.history = true;
    let s = simplify_polygons(&mesh.positions, &mesh.faces, &o).expect("simplifies");
    let mut tris = Vec::new();
    let mut tri_face = Vec::new();
    for f in 0..s.faces.len() {
        let face = s.faces.face(f);
        for k in 1..face.len() - 1 {
            tris.push([face[0], face[k], face[k + 1]]);
            tri_face.push(s.face_origin[f]);
        }
    }
    let atlas = build_atlas(
        &s.positions,
        &tris,
        &[],
        &AtlasOptions {
            size,
            ..AtlasOptions::default()
        },
    );
    let cov = rasterize(&atlas.corner_uvs, size, 1.5);
    let mut groups: std::collections::BTreeMap<(usize, u32), Vec<[f32; 3]>> = Default::default();
    let n = size as usize;
    for (i, &t) in cov.triangle.iter().enumerate() {
        if t == NO_TRIANGLE || t as usize % stride != 0 {
            continue;
        }
        let b = cov.bary[i];
        let tri = tris[t as usize];
        let p = [0, 1, 2].map(|a| (0..3).map(|k| b[k] * s.positions[tri[k] as usize][a]).sum());
        let tile = (i / n / 32) * n + (i % n) / 32;
        groups.entry((tile, t)).or_default().push(p);
    }
    let groups = groups
        .into_iter()
        .map(|((_, t), pts)| (tri_face[t as usize], pts))
        .collect();
    (s, groups)
}

/// CPU time of the calling thread in seconds (Linux; `None` elsewhere).
fn thread_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// CPU time (user + system) of the whole process in seconds (Linux).
fn process_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesized command name; utime and stime are the
    // 14th and 15th fields, in clock ticks (100 per second on Linux).
    let rest = s.rsplit_once(')')?.1;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn main() {
    let bench_mode = std::env::args().any(|a| a == "--bench");
    let corpus = std::env::var_os("WILDLOD_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus"));
    let (cases, ratios, size): (Vec<Case>, &[f64], u32) = if bench_mode {
        let mut c = corpus_cases(&corpus);
        c.push(generated_case());
        for (name, g) in [
            (
                "generated textured torus 20k",
                textured_torus(100, 100, 2048),
            ),
            ("generated scan 10k", scan_like(29, 4096)),
        ] {
            c.push(Case {
                name: name.into(),
                scene: g.scene,
                mesh: 0,
                images: vec![Some(g.image)],
            });
        }
        (c, &[0.1, 0.01], 2048)
    } else {
        (vec![generated_case()], &[0.1], 256)
    };
    // `WILDLOD_BAKE_CASES=scan,torus` keeps the cases whose name holds one
    // of the words; `WILDLOD_BAKE_SECONDS` sets each measurement's time
    // (default 20 s): the machine is shared.
    let keep: Option<Vec<String>> = std::env::var("WILDLOD_BAKE_CASES")
        .ok()
        .map(|v| v.split(',').map(str::to_string).collect());
    let cases: Vec<Case> = cases
        .into_iter()
        .filter(|c| {
            keep.as_ref()
                .map_or(true, |k| k.iter().any(|w| c.name.contains(w.as_str())))
        })
        .collect();
    let seconds: u64 = std::env::var("WILDLOD_BAKE_SECONDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    let mut c = Criterion::default().configure_from_args();
    let mut rows = Vec::new();
    for case in &cases {
        let mesh = &case.scene.meshes[case.mesh];
        let mut group = c.benchmark_group(case.name.as_str());
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(if bench_mode { seconds } else { 1 }));
        for &ratio in ratios {
            let label = format!("{}%", ratio * 100.0);
            let (s, groups) = texel_groups(mesh, ratio, size, 8);
            let history = s.history.as_ref().expect("history recorded");
            let map = SuccessiveMap::new(history, &mesh.positions, &mesh.faces);
            let texels: usize = groups.iter().map(|g| g.1.len()).sum();
            let mut outs: Vec<Vec<SurfacePoint>> = groups
                .iter()
                .map(|g| vec![map.map(g.0, g.1[0]); g.1.len()])
                .collect();
            group.throughput(Throughput::Elements(texels as u64));
            group.bench_with_input(
                BenchmarkId::new("map (1 thread)", &label),
                &groups,
                |b, groups| {
                    b.iter(|| {
                        let mut acc = 0u64;
                        for (f, pts) in groups {
                            for &p in pts {
                                acc += map.map(*f, p).face as u64;
                            }
                        }
                        acc
                    })
                },
            );
            group.bench_function(BenchmarkId::new("map coherent (1 thread)", &label), |b| {
                b.iter(|| {
                    for ((f, pts), out) in groups.iter().zip(outs.iter_mut()) {
                        map.map_many(*f, pts, out);
                    }
                    outs.len()
                })
            });
            // One timed pass of each for the summary table.
            let n = texels.max(1) as f64;
            let (t0, c0) = (Instant::now(), thread_cpu_seconds());
            for (f, pts) in &groups {
                for &p in pts {
                    std::hint::black_box(map.map(*f, p));
                }
            }
            let per_point = t0.elapsed().as_secs_f64() / n;
            let cpu_per_point = c0.zip(thread_cpu_seconds()).map(|(a, b)| (b - a) / n);
            let (t0, c0) = (Instant::now(), thread_cpu_seconds());
            for ((f, pts), out) in groups.iter().zip(outs.iter_mut()) {
                map.map_many(*f, pts, out);
            }
            let coherent = t0.elapsed().as_secs_f64() / n;
            let cpu_coherent = c0.zip(thread_cpu_seconds()).map(|(a, b)| (b - a) / n);
            // The coherent walk is exact: every texel as on its own.
            for ((f, pts), out) in groups.iter().zip(&outs) {
                for (&p, hit) in pts.iter().zip(out) {
                    assert_eq!(*hit, map.map(*f, p), "coherent mapping differs");
                }
            }
            let input = BakeInput {
                mesh,
                materials: &case.scene.materials,
                textures: &case.scene.textures,
                images: &case.images,
            };
            let bo = BakeOptions {
                simplify: options(ratio),
                texture_size: Some(size),
                ..BakeOptions::default()
            };
            group.throughput(Throughput::Elements(1));
            group.bench_with_input(
                BenchmarkId::new(format!("bake {size}"), &label),
                &bo,
                |b, bo| b.iter(|| bake_mesh(&input, bo).expect("bakes").images.len()),
            );
            group.bench_with_input(BenchmarkId::new("simplify", &label), &ratio, |b, &r| {
                b.iter(|| {
                    simplify_polygons(&mesh.positions, &mesh.faces, &options(r))
                        .expect("simplifies")
                        .report
                        .output_triangles
                })
            });
            let (t0, c0) = (Instant::now(), process_cpu_seconds());
            let baked = bake_mesh(&input, &bo).expect("bakes");
            let bake_s = t0.elapsed().as_secs_f64();
            let bake_cpu = c0.zip(process_cpu_seconds()).map(|(a, b)| b - a);
            let texels: usize = baked.report.atlases.iter().map(|a| a.texels_mapped).sum();
            let baking: f64 = baked.report.atlases.iter().map(|a| a.seconds).sum();
            let t = texels.max(1) as f64;
            let opt = |v: Option<f64>| v.map_or("n/a".to_string(), |x| format!("{x:.2}"));
            rows.push(format!(
                "| {} | {label} | {} | {:.2} | {} | {:.2} | {} | {:.2} | {} | {:.1} | {} |",
                case.name,
                baked.mesh.triangle_count(),
                per_point * 1e6,
                opt(cpu_per_point.map(|x| x * 1e6)),
                coherent * 1e6,
                opt(cpu_coherent.map(|x| x * 1e6)),
                baking * 1e6 / t,
                opt(bake_cpu.map(|x| x * 1e6 / t)),
                bake_s,
                texels
            ));
        }
        group.finish();
    }
    c.final_summary();
    println!(
        "\n| mesh | ratio | triangles | map µs/texel, wall (1 thread) | map µs/texel, CPU | coherent map µs/texel, wall (1 thread) | coherent map µs/texel, CPU | bake µs/texel, wall (all threads) | bake µs/texel, CPU (all threads) | bake total s, wall | texels mapped |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        println!("{r}");
    }
}
