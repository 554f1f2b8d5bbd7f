//! Inputs that once made wildlod run for minutes, timed so that a
//! regression shows: one polygon of 100,000 corners, a fan of 100,000
//! triangles around one vertex, and a glTF whose nodes form a chain
//! 100,000 deep, each node showing a mesh. Time must grow
//! near-linearly with faces, corners, nodes and depth; each case here is
//! meant to stay under a second.
//!
//! `cargo bench -p wildlod-bench --bench hostile` runs them at 100,000;
//! under `cargo test` they run once at 2,000 so that they keep compiling
//! and working. Results are in docs/robustness.md.

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput};
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Faces, Mesh, Node, Scene};
use wildlod_simplify::{simplify_mesh, Options, Target};

/// A flat convex polygon of `k` corners on the unit circle: the worst
/// case of the old per-face cost (every edge sees every corner).
fn ngon(k: usize) -> Mesh {
    let positions = (0..k)
        .map(|i| {
            let a = i as f32 / k as f32 * std::f32::consts::TAU;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let mut faces = Faces::new();
    faces.push(&(0..k as u32).collect::<Vec<u32>>());
    Mesh::from_polygons(positions, faces)
}

/// `n` triangles around one centre, the rim wavy (a flat fan is a known
/// limit, see docs/robustness.md): the centre's star holds every face, so
/// a cost per collapse that grows with a star makes the run quadratic.
fn fan(n: usize) -> Mesh {
    let mut positions = vec![[0.0f32; 3]];
    positions.extend((0..n).map(|i| {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        [a.cos(), a.sin(), 0.05 * (7.0 * a).sin()]
    }));
    let indices: Vec<u32> = (0..n as u32)
        .flat_map(|i| [0, 1 + i, 1 + (i + 1) % n as u32])
        .collect();
    Mesh::from_triangles(positions, &indices)
}

/// `depth` nodes, each the only child of the one before, each translated a
/// little and showing the same small mesh: `depth` instances whose world
/// matrices compose the whole chain.
fn chain(depth: usize) -> Scene {
    let mut scene = Scene::from_mesh(shapes::cube());
    scene.nodes = (0..depth)
        .map(|i| {
            let mut matrix = wildlod_mesh::IDENTITY;
            matrix[12] = 0.001;
            Node {
                name: format!("n{i}"),
                matrix,
                mesh: Some(0),
                children: if i + 1 < depth {
                    vec![i as u32 + 1]
                } else {
                    Vec::new()
                },
                ..Node::default()
            }
        })
        .collect();
    scene.roots = vec![0];
    scene
}

fn main() {
    let bench_mode = std::env::args().any(|a| a == "--bench");
    let n = if bench_mode { 100_000 } else { 2_000 };
    let mut c = Criterion::default().configure_from_args();

    let mut group = c.benchmark_group("large polygon");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Elements(n as u64));
    let polygon = ngon(n);
    group.bench_with_input(
        BenchmarkId::new("simplify_mesh 50%", n),
        &polygon,
        |b, m| {
            b.iter(|| {
                simplify_mesh(m, &Options::default())
                    .map(|(lod, _)| lod.faces.len())
                    .unwrap_or(0)
            })
        },
    );
    group.bench_with_input(BenchmarkId::new("triangulate", n), &polygon, |b, m| {
        b.iter(|| shapes::triangulate(m).faces.len())
    });
    let dir = tempfile::tempdir().expect("a temporary folder for the benchmark files");
    let obj = dir.path().join("ngon.obj");
    let doc = Document::from_scene(Scene::from_mesh(polygon.clone()));
    wildlod_io::write(&doc, &obj, &WriteOptions::default()).expect("writing the n-gon");
    group.bench_with_input(BenchmarkId::new("read OBJ", n), &obj, |b, p| {
        b.iter(|| {
            wildlod_io::read(p)
                .map(|d| d.scene.meshes.len())
                .unwrap_or(0)
        })
    });
    group.bench_with_input(BenchmarkId::new("write GLB", n), &doc, |b, d| {
        let out = dir.path().join("ngon_out.glb");
        b.iter(|| wildlod_io::write(d, &out, &WriteOptions::default()).is_ok())
    });
    group.finish();

    let mut group = c.benchmark_group("fan");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Elements(n as u64));
    let to_tenth = Options {
        target: Target {
            ratio: Some(0.1),
            ..Target::default()
        },
        ..Options::default()
    };
    group.bench_with_input(BenchmarkId::new("simplify_mesh 10%", n), &fan(n), |b, m| {
        b.iter(|| {
            simplify_mesh(m, &to_tenth)
                .map(|(lod, _)| lod.faces.len())
                .unwrap_or(0)
        })
    });
    group.finish();

    let mut group = c.benchmark_group("node chain");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Elements(n as u64));
    let doc = Document::from_scene(chain(n));
    for ext in ["obj", "glb", "ply", "stl"] {
        let out = dir.path().join(format!("chain.{ext}"));
        group.bench_with_input(BenchmarkId::new(format!("write {ext}"), n), &doc, |b, d| {
            b.iter(|| wildlod_io::write(d, &out, &WriteOptions::default()).is_ok())
        });
    }
    let gltf = dir.path().join("chain_in.gltf");
    wildlod_io::write(&doc, &gltf, &WriteOptions::default()).expect("writing the chain");
    group.bench_with_input(BenchmarkId::new("read glTF", n), &gltf, |b, p| {
        b.iter(|| {
            wildlod_io::read(p)
                .map(|d| d.scene.nodes.len())
                .unwrap_or(0)
        })
    });
    group.bench_with_input(BenchmarkId::new("instances", n), &doc.scene, |b, s| {
        b.iter(|| s.instances().len())
    });
    group.finish();
    c.final_summary();
}
