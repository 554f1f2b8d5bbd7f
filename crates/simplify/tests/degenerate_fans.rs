//! Work bounded by the input's size on near-degenerate inputs: fans of
//! slivers with coordinates rounded as exporters write them, and grids of
//! nearly collinear slivers (issue 32). The bounds are on the loop's work
//! (`Report::evaluations`), never on time.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod common;

use common::ratio;
use wildlod_mesh::{Faces, Mesh};
use wildlod_simplify::{simplify_mesh, Options, Report, StopReason};

/// `v` rounded to `decimals` decimals, as a text exporter writes it, then
/// read back as the f32 a reader stores.
fn rounded(v: f64, decimals: i32) -> f32 {
    let s = 10f64.powi(decimals);
    ((v * s).round() / s) as f32
}

/// A unit disc written as one polygon fan-triangulated from a rim vertex
/// (triangles (0, k, k + 1)): `n` rim vertices, n − 2 slivers, the thinnest
/// next to vertex 0, whose rounded corners fold some of them over.
fn rim_fan(n: usize, decimals: i32) -> Mesh {
    let positions = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [rounded(a.cos(), decimals), rounded(a.sin(), decimals), 0.0]
        })
        .collect();
    let idx: Vec<u32> = (1..n as u32 - 1).flat_map(|k| [0, k, k + 1]).collect();
    Mesh::from_polygons(positions, Faces::from_triangles(&idx))
}

/// A unit disc written as one fan around its center (triangles
/// (0, k, k + 1) over `n` rim vertices), flat: every edge of the center
/// costs nothing, and with f32 corners (as every reader stores them) the
/// rim's turns next to a rim vertex are below rounding, so moving the
/// center there flattens or folds a sliver next to it.
fn center_fan(n: usize) -> Mesh {
    let mut positions = vec![[0.0f32; 3]];
    positions.extend((0..n).map(|k| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        [a.cos() as f32, a.sin() as f32, 0.0]
    }));
    let n = n as u32;
    let idx: Vec<u32> = (0..n).flat_map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
    Mesh::from_polygons(positions, Faces::from_triangles(&idx))
}

/// A grid of `w` × `h` cells, each two triangles, stretched so that a cell
/// is `aspect` times wider than high and jittered by rounding: rows of
/// nearly collinear slivers.
fn sliver_grid(w: usize, h: usize, aspect: f64, decimals: i32) -> Mesh {
    let mut positions = Vec::new();
    for y in 0..=h {
        for x in 0..=w {
            let (fx, fy) = (x as f64 / w as f64, y as f64 / h as f64 / aspect);
            // A slight bend, so that the rounding does not fall on a lattice.
            let z = 1e-4 * (7.0 * fx).sin();
            positions.push([
                rounded(fx, decimals),
                rounded(fy, decimals),
                rounded(z, decimals),
            ]);
        }
    }
    let at = |x: usize, y: usize| (y * (w + 1) + x) as u32;
    let mut idx = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (a, b, c, d) = (at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1));
            idx.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    Mesh::from_polygons(positions, Faces::from_triangles(&idx))
}

/// The faces a collapse's face tests read on an ordinary mesh: those
/// around both endpoints, each of valence six.
const FACES_PER_TRY: f64 = 12.0;

/// Simplifies `mesh` to 10% with `options`' other settings and checks that
/// the target is reached and the loop's work stays within `per_triangle`
/// evaluations per input triangle times log₂ of the input's triangles.
fn reaches_target_within(mesh: &Mesh, mut options: Options, per_triangle: f64) -> Report {
    options.target = ratio(0.1).target;
    let (out, rep) = simplify_mesh(mesh, &options).unwrap();
    let t = rep.input_triangles;
    assert_eq!(rep.stop, Some(StopReason::TargetReached), "{rep:?}");
    assert!(
        rep.output_triangles <= rep.target_triangles + 1
            && rep.output_triangles + 1 >= rep.target_triangles,
        "{} triangles for a target of {}",
        rep.output_triangles,
        rep.target_triangles
    );
    assert_eq!(out.faces.len(), rep.output_triangles);
    let bound = per_triangle * t as f64 * (t as f64).log2();
    assert!(
        (rep.evaluations as f64) <= bound,
        "{} evaluations for {t} triangles (bound {bound:.0})",
        rep.evaluations
    );
    // The face tests read the faces a collapse moves, a dozen on an
    // ordinary mesh (two vertices of valence six): so many per evaluation
    // the bound allows. A vertex of high valence must not read all of its
    // faces at every try.
    let faces_bound = FACES_PER_TRY * bound;
    assert!(
        (rep.faces_tested as f64) <= faces_bound,
        "{} faces tested for {t} triangles (bound {faces_bound:.0})",
        rep.faces_tested
    );
    rep
}

#[test]
fn a_rounded_rim_fan_reaches_its_target_in_bounded_work() {
    // 20,000 rim vertices at 6 decimals: never finished (each collapse
    // along the rim retried every edge of vertex 0 that the flip guard had
    // refused, and every evaluation at vertex 0 scanned its 20,000 faces
    // for creases, pairwise).
    let mesh = rim_fan(20_000, 6);
    reaches_target_within(&mesh, Options::default(), 1.0);
    reaches_target_within(&mesh, Options::classic_qem(), 1.0);
    // Written with 12 decimals (no fold-overs), and at 7,000.
    reaches_target_within(&rim_fan(20_000, 12), Options::default(), 1.0);
    reaches_target_within(&rim_fan(7_000, 6), Options::default(), 1.0);
}

#[test]
fn a_flat_center_fan_reaches_its_target_in_bounded_work() {
    // 85,000 triangles around one vertex never finished: the center was
    // tried towards each rim vertex in turn, and each try read the
    // center's faces from the first up to the sliver next to that rim
    // vertex (half of them on average) before refusing.
    reaches_target_within(&center_fan(20_000), Options::default(), 1.0);
    let rep = reaches_target_within(&center_fan(85_000), Options::default(), 1.0);
    // The refusals this is about were there.
    assert!(rep.rejected.flat_border > 100, "{rep:?}");
    assert!(rep.rejected.normal_flip > 100, "{rep:?}");
}

#[test]
fn a_grid_of_rounded_slivers_reaches_its_target_in_bounded_work() {
    for aspect in [100.0, 10_000.0] {
        let mesh = sliver_grid(100, 50, aspect, 6);
        reaches_target_within(&mesh, Options::default(), 1.0);
        reaches_target_within(&mesh, Options::classic_qem(), 1.0);
    }
}
