//! wildlod against meshoptimizer (`simplify` and `simplify_with_update`,
//! crate `meshopt`) in the same run, on corpus meshes including the 871k
//! triangle dragon, at 10% and 1%.
//!
//! `cargo bench -p wildlod-bench` prints criterion's timings (with
//! throughput in input triangles per second) and then a table of the ratio
//! of wildlod's time to meshoptimizer's. Quad meshes are also run with the
//! quad ordering off (`QuadMode::Never`), for the cost of the quad terms,
//! and with soft symmetry on (Knodt's λ_sym = 1 with tangent quadrics at
//! 1/3), for the cost of Alg. 2. Under `cargo test` the benchmark runs once
//! on a small generated mesh, so that it keeps compiling and working.

use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput};
use wildlod_bench::mean_seconds;
use wildlod_bench::methods::{flatten, meshopt_simplify, meshopt_simplify_with_update};
use wildlod_mesh::{shapes, Faces, Scene};
use wildlod_simplify::{simplify_polygons, Options, QuadMode, QuadSettings, Target};

/// One input: its name, its faces as stored (polygons: wildlod keeps
/// quads) and triangulated (what meshoptimizer takes).
struct Case {
    name: String,
    positions: Vec<[f32; 3]>,
    faces: Faces,
    indices: Vec<u32>,
    has_quads: bool,
}

impl Case {
    fn new(name: &str, scene: &Scene) -> Case {
        let (positions, indices) = flatten(scene);
        // One stored mesh without transforms keeps its polygons (the quad
        // meshes); anything else is compared on the flattened triangles.
        let polygons = match (&scene.meshes[..], scene.instances().len()) {
            ([m], 1) if m.positions.len() == positions.len() => Some(m.faces.clone()),
            _ => None,
        };
        let has_quads = polygons.as_ref().is_some_and(|f| f.arity_counts().1 > 0);
        Case {
            name: name.to_string(),
            faces: polygons.unwrap_or_else(|| Faces::from_triangles(&indices)),
            positions,
            indices,
            has_quads,
        }
    }
}

fn corpus_cases(root: &Path) -> Vec<Case> {
    [
        "manifold/bunny.obj",
        "manifold/armadillo.obj",
        "manifold/nefertiti_lowres.obj",
        "wild/plane_holes.obj",
        "wild/chair_model.obj",
        "quad/spot_quadrangulated.obj",
        "quad/quadknot.obj",
        "large/dragon_vrip.glb",
    ]
    .iter()
    .filter_map(|rel| {
        let doc = wildlod_io::read(root.join(rel)).ok()?;
        Some(Case::new(rel.rsplit('/').next().unwrap_or(rel), &doc.scene))
    })
    .collect()
}

fn generated_case() -> Case {
    Case::new(
        "generated quad torus",
        &Scene::from_mesh(shapes::torus(40, 20, 1.0, 0.3)),
    )
}

/// How wildlod is run on a case.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    /// Default options (quads kept when the input has them).
    Default,
    /// The same engine without the quad ordering (`--no-quads`).
    NoQuads,
    /// Quads kept, with soft symmetry (`--symmetry 1 --tangent-weight 0.33`).
    Symmetry,
}

impl Variant {
    fn name(self) -> &'static str {
        match self {
            Variant::Default => "wildlod",
            Variant::NoQuads => "wildlod no quads",
            Variant::Symmetry => "wildlod symmetry",
        }
    }
}

fn wildlod(case: &Case, ratio: f64, variant: Variant) -> usize {
    let options = Options {
        target: Target {
            ratio: Some(ratio),
            ..Target::default()
        },
        quad: QuadSettings {
            mode: if variant == Variant::NoQuads {
                QuadMode::Never
            } else {
                QuadMode::Auto
            },
            ..if variant == Variant::Symmetry {
                QuadSettings {
                    symmetry: 1.0,
                    tangent_weight: 1.0 / 3.0,
                    ..QuadSettings::default()
                }
            } else {
                QuadSettings::default()
            }
        },
        ..Options::default()
    };
    simplify_polygons(&case.positions, &case.faces, &options)
        .map(|s| s.report.output_triangles)
        .unwrap_or(0)
}

fn main() {
    let bench_mode = std::env::args().any(|a| a == "--bench");
    let corpus = std::env::var_os("WILDLOD_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus"));
    let (cases, ratios): (Vec<Case>, &[f64]) = if bench_mode {
        let c = corpus_cases(&corpus);
        if c.is_empty() {
            eprintln!(
                "corpus not found at {}: benchmarking a generated mesh",
                corpus.display()
            );
            (vec![generated_case()], &[0.1, 0.01])
        } else {
            (c, &[0.1, 0.01])
        }
    } else {
        (vec![generated_case()], &[0.1])
    };
    let mut c = Criterion::default().configure_from_args();
    for case in &cases {
        let tris = case.indices.len() / 3;
        let mut group = c.benchmark_group(case.name.as_str());
        group.throughput(Throughput::Elements(tris as u64));
        // Large inputs take seconds per run: ten samples are plenty.
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(if tris > 200_000 { 60 } else { 5 }));
        for &ratio in ratios {
            let target = ((tris as f64) * ratio).round() as usize;
            let label = format!("{}%", ratio * 100.0);
            let variants: &[Variant] = if case.has_quads {
                &[Variant::Default, Variant::NoQuads, Variant::Symmetry]
            } else {
                &[Variant::Default]
            };
            for &v in variants {
                group.bench_with_input(BenchmarkId::new(v.name(), &label), &ratio, |b, &r| {
                    b.iter(|| wildlod(case, r, v))
                });
            }
            group.bench_with_input(
                BenchmarkId::new("meshopt simplify", &label),
                &target,
                |b, &t| b.iter(|| meshopt_simplify(&case.positions, &case.indices, t).len()),
            );
            group.bench_with_input(
                BenchmarkId::new("meshopt simplify_with_update", &label),
                &target,
                |b, &t| {
                    b.iter(|| {
                        let mut p = case.positions.clone();
                        meshopt_simplify_with_update(&mut p, &case.indices, t).len()
                    })
                },
            );
        }
        group.finish();
    }
    c.final_summary();
    if bench_mode {
        print_ratios(&cases, ratios);
    }
}

/// The tables the issues ask for: triangles per second and the ratio of
/// wildlod's time to meshoptimizer's, and on quad meshes the ratio of the
/// quad ordering's time to the same engine without it, measured in this run.
fn print_ratios(cases: &[Case], ratios: &[f64]) {
    println!("\n| mesh | triangles | ratio | wildlod | tris/s | meshopt simplify | wildlod ÷ meshopt | simplify_with_update | wildlod ÷ with_update |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for case in cases {
        let tris = case.indices.len() / 3;
        for &r in ratios {
            let label = format!("{}%", r * 100.0);
            let w = mean_seconds(&case.name, "wildlod", &label);
            let m = mean_seconds(&case.name, "meshopt simplify", &label);
            let u = mean_seconds(&case.name, "meshopt simplify_with_update", &label);
            let f = |x: Option<f64>| x.map_or("?".into(), |s| format!("{:.1} ms", s * 1e3));
            let q = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) if b > 0.0 => format!("{:.2}×", a / b),
                _ => "?".into(),
            };
            println!(
                "| {} | {tris} | {label} | {} | {} | {} | {} | {} | {} |",
                case.name,
                f(w),
                w.map_or("?".into(), |s| format!("{:.2} M", tris as f64 / s / 1e6)),
                f(m),
                q(w, m),
                f(u),
                q(w, u)
            );
        }
    }
    if cases.iter().any(|c| c.has_quads) {
        println!("\n| quad mesh | triangles | ratio | wildlod (quads kept) | wildlod (quads off) | quads ÷ off | with symmetry | symmetry ÷ quads kept |");
        println!("|---|---|---|---|---|---|---|---|");
        for case in cases.iter().filter(|c| c.has_quads) {
            let tris = case.indices.len() / 3;
            for &r in ratios {
                let label = format!("{}%", r * 100.0);
                let time = |v: Variant| mean_seconds(&case.name, v.name(), &label);
                let (w, n, s) = (
                    time(Variant::Default),
                    time(Variant::NoQuads),
                    time(Variant::Symmetry),
                );
                let f = |x: Option<f64>| x.map_or("?".into(), |s| format!("{:.1} ms", s * 1e3));
                let q = |a: Option<f64>, b: Option<f64>| match (a, b) {
                    (Some(a), Some(b)) if b > 0.0 => format!("{:.2}×", a / b),
                    _ => "?".into(),
                };
                println!(
                    "| {} | {tris} | {label} | {} | {} | {} | {} | {} |",
                    case.name,
                    f(w),
                    f(n),
                    q(w, n),
                    f(s),
                    q(s, w)
                );
            }
        }
    }
}
