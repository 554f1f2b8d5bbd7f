//! The cost of attributes: `simplify_mesh` with every stream fitted (UVs,
//! normals, skins; Hoppe 1999) against the same mesh with its attributes
//! removed, and meshoptimizer's `simplify` on the same triangles, in one
//! run, at 10% and 1%.
//!
//! `cargo bench -p wildlod-bench --bench attributes` prints criterion's
//! timings and then the ratios. Under `cargo test` it runs once on a small
//! generated mesh, so that it keeps compiling and working.

use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput};
use wildlod_bench::mean_seconds;
use wildlod_bench::methods::meshopt_simplify;
use wildlod_mesh::{shapes, Attribute, ComponentFormat, Mesh, Semantic};
use wildlod_simplify::{simplify_mesh, Options, Target};

/// A mesh with its attributes and the same mesh without.
struct Case {
    name: String,
    with: Mesh,
    without: Mesh,
    indices: Vec<u32>,
}

impl Case {
    fn new(name: &str, mesh: Mesh) -> Case {
        let without = Mesh {
            attributes: Vec::new(),
            skinning: None,
            ..mesh.clone()
        };
        let indices = shapes::triangulate(&mesh).faces.indices;
        Case {
            name: name.into(),
            with: mesh,
            without,
            indices,
        }
    }
}

/// A bumpy triangulated grid with UVs and normals.
fn generated() -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_grid(60, 60));
    for p in &mut m.positions {
        p[2] = 0.05 * (7.0 * p[0]).sin() * (5.0 * p[1]).cos();
    }
    let normals: Vec<f32> = m.positions.iter().flat_map(|_| [0.0, 0.0, 1.0]).collect();
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values: normals,
        indices,
        format: ComponentFormat::F32,
    });
    m
}

/// The largest mesh of each textured or skinned corpus file used here.
fn corpus_cases(root: &Path) -> Vec<Case> {
    [
        "textured/bob/bob_tri.obj",
        "textured/tea_set_01/tea_set_01_1k.gltf",
        "skinned/CesiumMan.glb",
    ]
    .iter()
    .filter_map(|rel| {
        let doc = wildlod_io::read(root.join(rel)).ok()?;
        let mesh = doc
            .scene
            .meshes
            .into_iter()
            .max_by_key(|m| m.triangle_count())?;
        Some(Case::new(rel.rsplit('/').next().unwrap_or(rel), mesh))
    })
    .collect()
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

fn run(mesh: &Mesh, ratio: f64) -> usize {
    simplify_mesh(mesh, &options(ratio)).map_or(0, |(m, _)| m.triangle_count())
}

fn main() {
    let bench_mode = std::env::args().any(|a| a == "--bench");
    let corpus = std::env::var_os("WILDLOD_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus"));
    let mut cases = vec![Case::new("generated grid", generated())];
    let ratios: &[f64] = if bench_mode {
        cases.extend(corpus_cases(&corpus));
        &[0.1, 0.01]
    } else {
        &[0.1]
    };
    let mut c = Criterion::default().configure_from_args();
    let mut rows = Vec::new();
    for case in &cases {
        let tris = case.indices.len() / 3;
        let mut group = c.benchmark_group(format!("attributes {}", case.name));
        group.throughput(Throughput::Elements(tris as u64));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(5));
        for &r in ratios {
            let label = format!("{}%", r * 100.0);
            let target = ((tris as f64) * r).round() as usize;
            group.bench_with_input(BenchmarkId::new("with attributes", &label), &r, |b, &r| {
                b.iter(|| run(&case.with, r))
            });
            group.bench_with_input(BenchmarkId::new("positions only", &label), &r, |b, &r| {
                b.iter(|| run(&case.without, r))
            });
            group.bench_with_input(
                BenchmarkId::new("meshopt simplify", &label),
                &target,
                |b, &t| b.iter(|| meshopt_simplify(&case.with.positions, &case.indices, t).len()),
            );
            rows.push((case.name.clone(), tris, label));
        }
        group.finish();
    }
    c.final_summary();
    if bench_mode {
        println!("\n| mesh | triangles | ratio | with attributes ÷ positions only | with attributes ÷ meshopt simplify |");
        println!("|---|---|---|---|---|");
        for (name, tris, label) in rows {
            let group = format!("attributes {name}");
            let time = |f: &str| mean_seconds(&group, f, &label);
            let q = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) if b > 0.0 => format!("{:.2}×", a / b),
                _ => "?".into(),
            };
            let w = time("with attributes");
            println!(
                "| {name} | {tris} | {label} | {} | {} |",
                q(w, time("positions only")),
                q(w, time("meshopt simplify"))
            );
        }
    }
}
