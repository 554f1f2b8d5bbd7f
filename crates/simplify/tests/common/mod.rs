//! Shared helpers for the simplifier's integration tests.
#![allow(dead_code)]

use wildlod_mesh::{shapes, Faces, Mesh};
use wildlod_simplify::{Options, Target};

/// Options aiming at `ratio` of the input triangles.
pub fn ratio(r: f64) -> Options {
    Options {
        target: Target {
            ratio: Some(r),
            ..Target::default()
        },
        ..Options::default()
    }
}

/// A closed, generic (no ties) triangle mesh: a triangulated quad sphere
/// with every vertex pushed in or out a little by a deterministic hash.
pub fn bumpy_sphere(n: usize) -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_sphere(n));
    for (k, p) in m.positions.iter_mut().enumerate() {
        let h = ((k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as f32 / (1u64 << 24) as f32;
        let s = 1.0 + 0.05 * (h - 0.5);
        *p = p.map(|c| c * s);
    }
    m
}

/// `count` disjoint triangles scattered on a grid: a pure triangle soup.
pub fn soup(count: usize) -> Mesh {
    let mut positions = Vec::new();
    let mut idx = Vec::new();
    for t in 0..count {
        let (x, y) = ((t % 10) as f32 * 1.5, (t / 10) as f32 * 1.5);
        let base = positions.len() as u32;
        positions.extend_from_slice(&[[x, y, 0.0], [x + 1.0, y, 0.1], [x, y + 1.0, 0.2]]);
        idx.extend_from_slice(&[base, base + 1, base + 2]);
    }
    Mesh::from_polygons(positions, Faces::from_triangles(&idx))
}

/// Boundary and non-manifold edge counts, and components, of a mesh.
pub fn topo(m: &Mesh) -> wildlod_mesh::stats::TopologyStats {
    wildlod_mesh::stats::topology(m)
}

/// Euler characteristic V − E + F of a welded mesh.
pub fn euler(m: &Mesh) -> i64 {
    let (weld, nv) = wildlod_mesh::weld::weld_positions(&m.positions);
    let mut edges = std::collections::HashSet::new();
    for f in m.faces.iter() {
        for k in 0..f.len() {
            let (a, b) = (weld[f[k] as usize], weld[f[(k + 1) % f.len()] as usize]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    let used: std::collections::HashSet<u32> =
        m.faces.indices.iter().map(|&v| weld[v as usize]).collect();
    let _ = nv;
    used.len() as i64 - edges.len() as i64 + m.faces.len() as i64
}

/// A subdivided box (see `shapes::box_grid`).
pub fn grid_box(lo: [f32; 3], hi: [f32; 3], n: usize) -> Mesh {
    shapes::box_grid(lo, hi, n)
}

/// Issue 31's bound: an output (the default's, a held run's) within 1.15×
/// of a geometry-only output in Hausdorff and Chamfer distance, differences below 1e-4 and
/// 1e-5 of the diagonal counting as equal (no screen shows them).
pub fn assert_within_geometry_bound(
    name: &str,
    default: &wildlod_eval::Comparison,
    geometry: &wildlod_eval::Comparison,
) {
    let ok = |d: f64, g: f64, invisible: f64| d <= (1.15 * g).max(g + invisible);
    assert!(
        ok(default.hausdorff, geometry.hausdorff, 1e-4),
        "{name}: Hausdorff {:e} against geometry-only {:e}",
        default.hausdorff,
        geometry.hausdorff
    );
    assert!(
        ok(default.chamfer_mean, geometry.chamfer_mean, 1e-5),
        "{name}: Chamfer {:e} against geometry-only {:e}",
        default.chamfer_mean,
        geometry.chamfer_mean
    );
}
