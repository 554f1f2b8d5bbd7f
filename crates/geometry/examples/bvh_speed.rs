//! Measures BVH build and closest-point queries on a generated
//! 1M-triangle torus: `cargo run --release -p wildlod-geometry --example bvh_speed`.

use std::time::Instant;

use glam::DVec3;
use wildlod_geometry::{triangle_triangle_distance, Aabb, Bvh, TriangleSet};
use wildlod_mesh::shapes;

fn main() {
    let mesh = shapes::triangulate(&shapes::torus(1000, 500, 2.0, 0.5));
    let pos: Vec<DVec3> = mesh
        .positions
        .iter()
        .map(|p| DVec3::from(p.map(f64::from)))
        .collect();
    let tris: Vec<[u32; 3]> = mesh.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
    println!("{} triangles", tris.len());

    let boxes: Vec<Aabb> = tris
        .iter()
        .map(|t| Aabb::from_triangle(pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]))
        .collect();
    for _ in 0..2 {
        let t = Instant::now();
        let bvh = Bvh::build(&boxes);
        println!(
            "warm-up build {:.1} ms ({})",
            t.elapsed().as_secs_f64() * 1e3,
            bvh.len()
        );
    }
    let t = Instant::now();
    let bvh = Bvh::build(&boxes);
    println!(
        "Bvh::build: {:.1} ms ({} nodes, depth {})",
        t.elapsed().as_secs_f64() * 1e3,
        bvh.node_count(),
        bvh.depth()
    );

    let t = Instant::now();
    let set = TriangleSet::new(&pos, &tris);
    println!(
        "TriangleSet::new: {:.1} ms",
        t.elapsed().as_secs_f64() * 1e3
    );

    // Query points near the surface (as when measuring one surface against
    // a simplified copy of it), then anywhere in the bounding box. Points
    // near the torus axis are the worst case: a whole ring of triangles is
    // (nearly) equally far from them.
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut unit = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let near_surface: Vec<DVec3> = (0..100_000)
        .map(|_| {
            let p = pos[(unit() * pos.len() as f64) as usize];
            p + DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) * 0.02
        })
        .collect();
    let anywhere: Vec<DVec3> = (0..100_000)
        .map(|_| DVec3::new(5.0 * unit() - 2.5, 5.0 * unit() - 2.5, 1.4 * unit() - 0.7))
        .collect();
    for (name, queries) in [
        ("near the surface", &near_surface),
        ("anywhere in the box", &anywhere),
    ] {
        let t = Instant::now();
        let mut sum = 0.0;
        for &q in queries {
            sum += set.closest(q).map_or(0.0, |h| h.distance2);
        }
        let dt = t.elapsed().as_secs_f64();
        println!(
            "100k closest-point queries {name} (1 thread): {:.1} ms, {:.2} µs/query (checksum {sum:.6})",
            dt * 1e3,
            dt * 1e6 / queries.len() as f64
        );
    }

    // The simplifier's virtual-edge search: all triangle pairs within 1e-3.
    let t = Instant::now();
    let near = bvh.par_self_pairs_within(1e-3, |i, j| {
        let a = tris[i as usize].map(|v| pos[v as usize]);
        let b = tris[j as usize].map(|v| pos[v as usize]);
        (triangle_triangle_distance(&a, &b) < 1e-3).then_some((i, j))
    });
    println!(
        "par_self_pairs_within(1e-3) + exact distances: {:.1} ms, {} pairs",
        t.elapsed().as_secs_f64() * 1e3,
        near.len()
    );
}
