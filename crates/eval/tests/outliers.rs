//! `compare` on a reference with far-away outlier vertices (issue 31,
//! decision 9): errors stay relative to the size the bulk sets, the
//! outliers are named, and a level of detail reads as it would without
//! them.

use wildlod_eval::{compare, CompareOptions, Comparison, EvalMesh};
use wildlod_mesh::{Faces, Mesh};

/// The terrain: smooth hills plus detail at about four fine cells, so that
/// a grid of a quarter the resolution misses something.
fn height(x: f64, y: f64) -> f64 {
    0.08 * (6.0 * x).sin() * (5.0 * y).cos() + 0.01 * (40.0 * x + 27.0 * y).sin()
}

/// An `n × n`-vertex heightfield over the unit square, two triangles per
/// cell. Vertex `(i, j)` has index `j · n + i`.
fn heightfield(n: usize) -> Mesh {
    let mut positions = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
            positions.push([x as f32, y as f32, height(x, y) as f32]);
        }
    }
    let id = |i: usize, j: usize| (j * n + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            idx.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_polygons(positions, Faces::from_triangles(&idx))
}

const FINE: usize = 65;
const COARSE: usize = 17;
/// Grid points (in coarse-grid steps) that become outliers: the same
/// points of the fine grid (every fourth vertex) and of the coarse one.
const SPIKES: [(usize, usize); 3] = [(3, 4), (10, 9), (13, 2)];

/// `mesh` (an `n × n` heightfield, `step` fine cells per cell) with the
/// spike points sunk to −1e30; returns the vertex indices.
fn sink(mesh: &mut Mesh, n: usize, step: usize) -> Vec<u32> {
    SPIKES
        .iter()
        .map(|&(i, j)| {
            let v = (j * 4 / step) * n + i * 4 / step;
            mesh.positions[v][2] = -1e30;
            v as u32
        })
        .collect()
}

fn run(reference: &Mesh, candidate: &Mesh) -> Comparison {
    compare(
        &EvalMesh::from_mesh(reference),
        &EvalMesh::from_mesh(candidate),
        &CompareOptions {
            samples: 20_000,
            texture_samples: 5_000,
            ..CompareOptions::default()
        },
    )
}

#[test]
fn a_coarse_lod_of_a_terrain_with_sunk_vertices_reads_as_without_them() {
    let (fine, coarse) = (heightfield(FINE), heightfield(COARSE));
    let clean = run(&fine, &coarse);
    assert_eq!(clean.outliers_reference, 0);
    assert!(clean.hausdorff > 1e-3, "{clean:?}");
    let mut spiked = fine.clone();
    let sunk = sink(&mut spiked, FINE, 1);
    // The level of detail keeps the outliers (at its own grid points) or
    // drops them: both read within 2× of the clean comparison.
    let mut kept = coarse.clone();
    sink(&mut kept, COARSE, 4);
    for (what, candidate) in [("keeps", &kept), ("drops", &coarse)] {
        let c = run(&spiked, candidate);
        let ratio = c.hausdorff / clean.hausdorff;
        eprintln!(
            "LOD {what} the outliers: Hausdorff {:.5} against {:.5} clean ({ratio:.3}×), Chamfer {:.3e} against {:.3e}",
            c.hausdorff, clean.hausdorff, c.chamfer_mean, clean.chamfer_mean
        );
        assert!((0.5..=2.0).contains(&ratio), "{what}: {c:?}");
        let chamfer = c.chamfer_mean / clean.chamfer_mean;
        assert!((0.5..=2.0).contains(&chamfer), "{what}: {c:?}");
        // The unit is the bulk's diagonal, not 1e30.
        assert!((c.diagonal / clean.diagonal - 1.0).abs() < 0.05, "{c:?}");
        assert!(c.diagonal_with_outliers > 1e29);
        // Named: mesh 0, the sunk vertices, their positions.
        assert_eq!(c.outliers_reference, 3);
        let named: Vec<u32> = c.outlier_vertices.iter().map(|o| o.vertex).collect();
        let mut want = sunk.clone();
        want.sort_unstable();
        assert_eq!(named, want);
        for o in &c.outlier_vertices {
            assert_eq!((o.mesh, o.instance), (0, 0));
            assert_eq!(o.position[2], f64::from(-1e30f32));
        }
        // Six triangles around each interior grid vertex are left out.
        assert_eq!(c.outlier_triangles_reference, 18);
        let expected_candidate = if what == "keeps" { (3, 18) } else { (0, 0) };
        assert_eq!(
            (c.outliers_candidate, c.outlier_triangles_candidate),
            expected_candidate
        );
        assert!(
            c.notes.iter().any(|n| n.contains("outliers")),
            "{:?}",
            c.notes
        );
    }
}

#[test]
fn a_lifted_copy_is_exactly_as_far_with_outliers_as_without() {
    // The same terrain raised by 0.01 everywhere but at the outliers: the
    // holes the outliers leave coincide, and the metrics are those of the
    // clean pair.
    let lift = |m: &Mesh| {
        let mut out = m.clone();
        for p in &mut out.positions {
            if p[2] > -1e29 {
                p[2] += 0.01;
            }
        }
        out
    };
    let fine = heightfield(FINE);
    let clean = run(&fine, &lift(&fine));
    let mut spiked = fine.clone();
    sink(&mut spiked, FINE, 1);
    let c = run(&spiked, &lift(&spiked));
    assert!(
        (c.hausdorff / clean.hausdorff - 1.0).abs() < 0.02,
        "{} vs {}",
        c.hausdorff,
        clean.hausdorff
    );
    assert!((c.chamfer_mean / clean.chamfer_mean - 1.0).abs() < 0.02);
    // 0.01 on a diagonal of about √2 (the hills add a little).
    assert!(clean.hausdorff < 0.01 / 2f64.sqrt() && clean.hausdorff > 0.006);
}

#[test]
fn without_reference_outliers_a_candidates_far_vertex_counts_in_full() {
    // The defect must show: a level of detail that throws a vertex to
    // −1e30 is 1e30 off, relative to the reference's own diagonal.
    let (fine, mut coarse) = (heightfield(FINE), heightfield(COARSE));
    sink(&mut coarse, COARSE, 4);
    let c = run(&fine, &coarse);
    assert_eq!((c.outliers_reference, c.outliers_candidate), (0, 0));
    assert_eq!(c.outlier_triangles_candidate, 0);
    assert!(c.hausdorff > 1e29, "{c:?}");
    assert!(c.diagonal < 2.0);
}
