//! Tests of the whole weight computation: hand-counted meshes, the
//! per-edge brute force, plane grouping, the work cap and the prefilter.

use super::grid::match_plane;
use super::test_support::{brute_matched, opts, Rng};
use super::*;

/// A mesh as plain arrays, with edges and per-edge face normals derived
/// from its faces (each polygon's normal by Newell's method).
struct TestMesh {
    positions: Vec<DVec3>,
    edges: Vec<[u32; 2]>,
    normals: Vec<EdgeNormals>,
}

impl TestMesh {
    /// Builds the edge list (in order of first appearance) and each
    /// edge's faces from polygon faces.
    fn new(positions: Vec<DVec3>, faces: &[Vec<u32>]) -> Self {
        let mut index = std::collections::HashMap::new();
        let mut edges = Vec::new();
        let mut face_normals: Vec<Vec<DVec3>> = Vec::new();
        for f in faces {
            let mut n = DVec3::ZERO;
            for i in 0..f.len() {
                let a = positions[f[i] as usize];
                let b = positions[f[(i + 1) % f.len()] as usize];
                n += a.cross(b);
            }
            let n = n.normalize();
            for i in 0..f.len() {
                let (a, b) = (f[i], f[(i + 1) % f.len()]);
                let e = *index.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    edges.push([a, b]);
                    face_normals.push(Vec::new());
                    edges.len() - 1
                });
                face_normals[e].push(n);
            }
        }
        let normals = face_normals
            .iter()
            .map(|n| EdgeNormals::from_faces(n))
            .collect();
        Self {
            positions,
            edges,
            normals,
        }
    }

    /// The input view of this mesh.
    fn input(&self) -> SymmetryInput<'_> {
        SymmetryInput {
            positions: &self.positions,
            edges: &self.edges,
            edge_normals: &self.normals,
        }
    }

    /// Index of the edge between vertices `a` and `b`.
    fn edge(&self, a: u32, b: u32) -> usize {
        self.edges
            .iter()
            .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
            .unwrap()
    }
}

/// A flat grid of quads in z = 0, `nx × ny` vertices at spacing 1 with
/// x running over `x0, x0 + 1, …`; vertex `(i, j)` is `j · nx + i`.
fn flat_grid(nx: u32, ny: u32, x0: f64) -> TestMesh {
    let mut positions = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            positions.push(DVec3::new(x0 + i as f64, j as f64, 0.0));
        }
    }
    let mut faces = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = j * nx + i;
            faces.push(vec![v, v + 1, v + nx + 1, v + nx]);
        }
    }
    TestMesh::new(positions, &faces)
}

/// Reference: every edge on its own, every vertex pair examined, and the
/// maximum matching by Kuhn's algorithm. Shares with the fast path only
/// the formulas ([`edge_plane`], [`Plane::signed_distance`],
/// [`pair_error`](super::plane::pair_error)), each tested by hand in
/// `plane.rs`.
fn brute_weights(input: &SymmetryInput<'_>, delta: f64) -> Vec<f64> {
    (0..input.edges.len())
        .map(|e| {
            let [a, b] = input.edges[e];
            let (Some(&p0), Some(&p1)) = (
                input.positions.get(a as usize),
                input.positions.get(b as usize),
            ) else {
                return 0.0;
            };
            let faces = input
                .edge_normals
                .get(e)
                .copied()
                .unwrap_or(EdgeNormals::NoFace);
            match edge_plane(p0, p1, faces) {
                Some(plane) if delta > 0.0 && delta.is_finite() => {
                    brute_matched(input.positions, plane, delta) as f64
                        / input.positions.len() as f64
                }
                _ => 0.0,
            }
        })
        .collect()
}

/// Asserts two weight vectors are equal to the last bit, naming the edge.
fn assert_same(got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len());
    for (e, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.to_bits(), w.to_bits(), "edge {e}: {g} vs {w}");
    }
}

/// Knodt Fig. 3: on a grid symmetric about x = 0, the edges on that line
/// get s = 1; other lines get the hand-counted fraction.
///
/// ```text
///  y=3  o---o---o---o---o      5 × 4 vertices at x = −2 … 2,
///  y=2  o---o---o---o---o      y = 0 … 3, z = 0; every quad faces +z.
///  y=1  o---o---o---o---o
///  y=0  o---o---o---o---o
///      x=-2 -1   0   1   2
/// ```
#[test]
fn grid_edges_on_the_symmetry_line_get_one() {
    let m = flat_grid(5, 4, -2.0);
    let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
    assert!(!w.truncated);
    // Vertex (i, j) is 5j + i; x = i − 2.
    let v = |i: u32, j: u32| 5 * j + i;
    // Column x = 0 (interior, manifold): plane x = 0, all 20 match.
    assert_eq!(w.weights[m.edge(v(2, 1), v(2, 2))], 1.0);
    assert_eq!(w.weights[m.edge(v(2, 0), v(2, 1))], 1.0);
    // Column x = 1: 4 on the plane, x = 0 ↔ x = 2 gives 8, x = −1 and
    // x = −2 have no partner (x = 3, 4): 12 / 20.
    assert_eq!(w.weights[m.edge(v(3, 1), v(3, 2))], 0.6);
    // Row y = 1 (plane y = 1): 5 on it, rows 0 ↔ 2 give 10: 15 / 20.
    assert_eq!(w.weights[m.edge(v(1, 1), v(2, 1))], 0.75);
    // Row y = 0 is a border (one face, normal +z): plane y = 0, only
    // the 5 on it: 5 / 20.
    assert_eq!(w.weights[m.edge(v(1, 0), v(2, 0))], 0.25);
    // Column x = −2 border: 4 on it, nothing beyond: 4 / 20.
    assert_eq!(w.weights[m.edge(v(0, 1), v(0, 2))], 0.2);
    // The four column lines share a plane each, the four row lines too:
    // 5 + 4 distinct planes for 31 edges.
    assert_eq!(w.planes, 9);
    assert_eq!(w.planes_computed, 9);
    assert_same(&w.weights, &brute_weights(&m.input(), 1e-3));
}

/// A symmetric roof: the ridge uses the halfway normal of its two
/// sloped faces; an eave is a border edge whose plane is orthogonal to
/// its face.
///
/// ```text
///        1 (0,0,1) ---- 4 (0,1,1)        ridge along y at x = 0, z = 1
///       /                    \
///  0 (−1,0,0) - 3 (−1,1,0)  2 (1,0,0) - 5 (1,1,0)   eaves at x = ±1
/// ```
#[test]
fn roof_ridge_is_symmetric_and_eave_matches_only_itself() {
    let positions = vec![
        DVec3::new(-1.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(-1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 1.0),
        DVec3::new(1.0, 1.0, 0.0),
    ];
    let m = TestMesh::new(positions, &[vec![0, 1, 4, 3], vec![1, 2, 5, 4]]);
    let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
    // Ridge: plane x = 0; 1 and 4 on it, 0 ↔ 2 and 3 ↔ 5: 6 / 6.
    assert_eq!(w.weights[m.edge(1, 4)], 1.0);
    // Eave 2–5: plane through (1, 0, 0) with normal (−1, 0, 1)/√2 (up
    // to sign). 2 and 5 on it; the ridge (σ = √2) mirrors to
    // (0, y, 1) − 2(−1, 0, 1) = (2, y, −1), the far eave to (1, y, −2):
    // no partners. 2 / 6.
    assert_eq!(w.weights[m.edge(2, 5)], 2.0 / 6.0);
    // Gable edge 1–2 (border, plane y = 0): 0, 1, 2 on it; y = 1 would
    // mirror to y = −1: 3 / 6.
    assert_eq!(w.weights[m.edge(1, 2)], 0.5);
    assert_same(&w.weights, &brute_weights(&m.input(), 1e-3));
}

/// Alg. 2 line 10: an edge of three faces gets 0, as does an edge of no
/// face, even when its line is a symmetry line.
#[test]
fn non_manifold_and_faceless_edges_get_zero() {
    let mut m = flat_grid(5, 4, -2.0);
    let e = m.edge(12, 7); // on x = 0: s = 1 as a manifold edge
    m.normals[e] = EdgeNormals::NonManifold;
    let f = m.edge(2, 7);
    m.normals[f] = EdgeNormals::NoFace;
    let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
    assert_eq!((w.weights[e], w.weights[f]), (0.0, 0.0));
    // The other edges on x = 0 still share the plane.
    assert_eq!(w.weights[m.edge(12, 17)], 1.0);
}

/// Random small meshes (random edges, including repeated ones with
/// negated normals that share a plane, and reversed ones; random face
/// normals and kinds): the full function equals the per-edge brute
/// force bit for bit when only exact planes are shared.
#[test]
fn weights_equal_brute_force_on_random_meshes() {
    let mut rng = Rng(0x94D0_49BB_1331_11EB);
    let (mut planes, mut with_plane) = (0, 0);
    for case in 0..150 {
        let delta = [0.02, 0.1][rng.below(2)];
        let nv = 1 + rng.below(16);
        let mut positions: Vec<DVec3> = (0..nv)
            .map(|_| DVec3::new(rng.unit(), rng.unit(), rng.unit()))
            .collect();
        // Mirror some vertices across x = ½ (jittered) so that some
        // planes are nearly symmetry planes.
        for i in 0..nv {
            if rng.below(2) == 0 {
                let p = positions[i];
                let j = rng.direction() * rng.range(0.0, delta);
                positions.push(DVec3::new(1.0 - p.x, p.y, p.z) + j);
            }
        }
        let nv = positions.len() as u32;
        let mut edges = Vec::new();
        let mut normals = Vec::new();
        for _ in 0..1 + rng.below(12) {
            let e = [rng.below(nv as usize) as u32, rng.below(nv as usize) as u32];
            let kind = match rng.below(6) {
                0 => EdgeNormals::NoFace,
                1 => EdgeNormals::NonManifold,
                2 | 3 => EdgeNormals::Border(rng.direction()),
                _ => EdgeNormals::Manifold(rng.direction(), rng.direction()),
            };
            edges.push(e);
            normals.push(kind);
            if rng.below(3) == 0 {
                // The same edge with its faces' normals negated: the
                // same plane with the opposite orientation, to the bit
                // (n⊥ and the offset only change sign), so grouped.
                edges.push(e);
                normals.push(match kind {
                    EdgeNormals::Border(n) => EdgeNormals::Border(-n),
                    EdgeNormals::Manifold(a, b) => EdgeNormals::Manifold(-a, -b),
                    other => other,
                });
            }
            if rng.below(3) == 0 {
                // The same edge reversed: the same plane mathematically,
                // with the offset taken at the other end.
                edges.push([e[1], e[0]]);
                normals.push(kind);
            }
        }
        // An out-of-range edge and one without normals.
        edges.push([0, nv + 3]);
        edges.push([0, nv - 1]);
        let input = SymmetryInput {
            positions: &positions,
            edges: &edges,
            edge_normals: &normals,
        };
        let options = SymmetryOptions {
            plane_tolerance: 0.0,
            ..opts(delta)
        };
        let got = edge_symmetry_weights(&input, &options);
        assert_same(&got.weights, &brute_weights(&input, delta));
        assert!(
            got.weights.iter().all(|&s| (0.0..=1.0).contains(&s)),
            "case {case}"
        );
        planes += got.planes;
        with_plane += (0..edges.len())
            .filter(|&e| {
                let [a, b] = edges[e];
                let (Some(&p0), Some(&p1)) = (positions.get(a as usize), positions.get(b as usize))
                else {
                    return false;
                };
                let faces = normals.get(e).copied().unwrap_or(EdgeNormals::NoFace);
                edge_plane(p0, p1, faces).is_some()
            })
            .count();
    }
    // Grouping happened: fewer planes than edges with a plane.
    assert!(
        planes < with_plane,
        "{planes} planes for {with_plane} edges"
    );
}

/// A grid symmetric about several lines, jittered and rotated so that
/// the planes of edges on one line differ in their last bits: the
/// default tolerance groups them, and the weights equal computing every
/// edge on its own.
#[test]
fn plane_grouping_gives_the_same_weights_as_no_grouping() {
    let mut m = flat_grid(9, 7, -4.0);
    // Scale into the unit box and rotate about an oblique axis, so that
    // the normals are no longer exact axis vectors.
    let rot = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    for p in &mut m.positions {
        *p = rot * (*p * 0.1);
    }
    for n in &mut m.normals {
        *n = match *n {
            EdgeNormals::Border(a) => EdgeNormals::Border(rot * a),
            EdgeNormals::Manifold(a, b) => EdgeNormals::Manifold(rot * a, rot * b),
            other => other,
        };
    }
    let input = m.input();
    let grouped = edge_symmetry_weights(&input, &opts(1e-3));
    let exact = edge_symmetry_weights(
        &input,
        &SymmetryOptions {
            plane_tolerance: 0.0,
            ..opts(1e-3)
        },
    );
    let brute = brute_weights(&input, 1e-3);
    assert_same(&grouped.weights, &brute);
    assert_same(&exact.weights, &brute);
    // 9 column lines + 7 row lines; the rotation made exact sharing
    // rarer than the tolerance's.
    assert_eq!(grouped.planes, 16);
    assert!(exact.planes >= grouped.planes);
    // Column x = 0 (i = 4) is the symmetry line.
    assert_eq!(grouped.weights[m.edge(4 + 9, 4 + 18)], 1.0);
}

/// The cap keeps a prefix of the planes in computing order (largest
/// group first): those planes have their weights, later ones 0, and
/// `truncated` says so.
#[test]
fn max_work_keeps_a_prefix_of_planes_and_zeroes_the_rest() {
    let m = flat_grid(6, 5, -2.5);
    let input = m.input();
    let options = opts(1e-3);
    let full = edge_symmetry_weights(&input, &options);
    assert!(!full.truncated);
    assert_eq!(full.planes_computed, full.planes);
    // Per-plane work, computed alone.
    let groups = plane_groups(&input, &options);
    let grid = Grid::new(&m.positions, 1e-3);
    let works: Vec<u64> = groups
        .iter()
        .map(|g| match_plane(&grid, g.plane, 1e-3, u64::MAX, &mut Scratch::default()).work)
        .collect();
    assert_eq!(full.work, works.iter().sum::<u64>());
    // Group sizes never increase along the computing order.
    assert!(groups
        .windows(2)
        .all(|w| w[0].edges.len() >= w[1].edges.len()));
    for kept in 0..groups.len() {
        let budget: u64 = works[..kept].iter().sum();
        // Exactly enough for `kept` planes, and one short of `kept + 1`.
        for max_work in [budget, budget + works[kept] - 1] {
            let w = edge_symmetry_weights(
                &input,
                &SymmetryOptions {
                    max_work,
                    ..options
                },
            );
            assert!(w.truncated);
            assert_eq!(w.planes_computed, kept);
            for (i, g) in groups.iter().enumerate() {
                for &e in &g.edges {
                    let want = if i < kept {
                        full.weights[e as usize]
                    } else {
                        0.0
                    };
                    assert_eq!(w.weights[e as usize], want, "kept {kept}, edge {e}");
                }
            }
        }
    }
    // No work at all: nothing computed, nothing examined.
    let none = edge_symmetry_weights(
        &input,
        &SymmetryOptions {
            max_work: 0,
            ..options
        },
    );
    assert!(none.truncated);
    assert_eq!(none.work, 0);
    assert!(none.weights.iter().all(|&s| s == 0.0));
}

/// Empty and degenerate inputs give zeros, never a panic.
#[test]
fn degenerate_inputs_give_zero_weights() {
    let empty = SymmetryInput {
        positions: &[],
        edges: &[[0, 1]],
        edge_normals: &[EdgeNormals::Border(DVec3::Z)],
    };
    let w = edge_symmetry_weights(&empty, &SymmetryOptions::default());
    assert_eq!(w.weights, vec![0.0]);
    let m = flat_grid(3, 3, -1.0);
    for delta in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let w = edge_symmetry_weights(&m.input(), &opts(delta));
        assert!(w.weights.iter().all(|&s| s == 0.0), "delta {delta}");
        assert!(!w.truncated);
    }
    // NaN and huge positions, a zero-length edge, fewer normals than
    // edges: still weights in [0, 1] and equal to brute force.
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::NAN,
        DVec3::splat(1e300),
        DVec3::new(-1e300, 0.0, 0.0),
        DVec3::Y,
    ];
    let edges = [[0, 1], [0, 0], [0, 2], [3, 4], [1, 5], [5, 0]];
    let normals = [
        EdgeNormals::Border(DVec3::Z),
        EdgeNormals::Border(DVec3::Z),
        EdgeNormals::Border(DVec3::Z),
        EdgeNormals::Manifold(DVec3::Z, DVec3::Y),
        EdgeNormals::Manifold(DVec3::Z, DVec3::Z),
    ];
    let input = SymmetryInput {
        positions: &positions,
        edges: &edges,
        edge_normals: &normals,
    };
    let w = edge_symmetry_weights(&input, &opts(1e-3));
    assert_same(&w.weights, &brute_weights(&input, 1e-3));
    assert_eq!(w.weights[1], 0.0);
    assert_eq!(w.weights[5], 0.0);
    // Edge 0–1 (plane y = 0): 0, 1 and (−1e300, 0, 0) lie on it;
    // 5 = (0, 1, 0) would need (0, −1, 0); NaN never matches: 3 of 6.
    assert_eq!(w.weights[0], 0.5);
}

/// The same weights, work and truncation with 1, 2 and 3 rayon threads:
/// uncapped, with a cap that cuts a batch in the middle, and with the
/// prefilter.
#[test]
fn results_do_not_depend_on_thread_count() {
    let mesh = wavy_mesh(40, 0.2);
    let input = mesh.input();
    let full = edge_symmetry_weights(&input, &SymmetryOptions::default());
    let capped = SymmetryOptions {
        max_work: full.work / 3,
        ..SymmetryOptions::default()
    };
    let prefiltered = SymmetryOptions {
        min_weight: 0.05,
        samples: 256,
        ..capped
    };
    for options in [SymmetryOptions::default(), capped, prefiltered] {
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| edge_symmetry_weights(&input, &options))
        };
        let one = run(1);
        for threads in [2, 3] {
            let other = run(threads);
            assert_same(&one.weights, &other.weights);
            assert_eq!(
                (
                    one.work,
                    one.truncated,
                    one.planes_computed,
                    one.planes_skipped
                ),
                (
                    other.work,
                    other.truncated,
                    other.planes_computed,
                    other.planes_skipped
                )
            );
        }
    }
}

/// With the prefilter on, every edge's weight is its exact weight or 0
/// (skipped); on a symmetric height field no edge whose exact weight
/// reaches `min_weight` is skipped, and most planes are.
#[test]
fn prefilter_keeps_exact_weights_or_skips_low_ones() {
    let m = wavy_mesh(41, 0.2);
    let exact = edge_symmetry_weights(&m.input(), &opts(1e-3));
    let options = SymmetryOptions {
        min_weight: 0.1,
        samples: 256,
        ..opts(1e-3)
    };
    let filtered = edge_symmetry_weights(&m.input(), &options);
    for (e, (&f, &x)) in filtered.weights.iter().zip(&exact.weights).enumerate() {
        assert!(f == x || f == 0.0, "edge {e}: {f} vs exact {x}");
        assert!(x < 0.1 || f == x, "edge {e} skipped at exact {x}");
    }
    assert!(filtered.planes_skipped * 2 > filtered.planes);
    assert!(filtered.work * 2 < exact.work);
    assert_eq!(filtered.planes_computed, filtered.planes);
}

/// A triangulated height field on `n × n` vertices in the unit box,
/// mirror-symmetric about x = ½ with a wave of relative height `amp`
/// (so the planes of most edges are distinct and a few are symmetry
/// planes), normalized to a unit diagonal.
fn wavy_mesh(n: u32, amp: f64) -> TestMesh {
    let mut positions = Vec::new();
    let k = 1.0 / (n - 1) as f64;
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f64 * k, j as f64 * k);
            let z = amp * ((6.0 * (x - 0.5)).powi(2) * 0.3 + (7.0 * y).sin() * 0.5);
            positions.push(DVec3::new(x, y, z));
        }
    }
    let diag = {
        let (lo, hi) = positions.iter().fold(
            (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        (hi - lo).length()
    };
    for p in &mut positions {
        *p /= diag;
    }
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = j * n + i;
            // Diagonals mirrored across x = ½ as well.
            if 2 * i < n - 1 {
                faces.push(vec![v, v + 1, v + n + 1]);
                faces.push(vec![v, v + n + 1, v + n]);
            } else {
                faces.push(vec![v, v + 1, v + n]);
                faces.push(vec![v + 1, v + n + 1, v + n]);
            }
        }
    }
    TestMesh::new(positions, &faces)
}

/// The wavy mesh's centre column is its symmetry line: s = 1 there.
#[test]
fn wavy_mesh_centre_column_is_a_symmetry_plane() {
    let m = wavy_mesh(21, 0.2);
    let w = edge_symmetry_weights(&m.input(), &opts(1e-3));
    // Column i = 10 is x = ½; its vertical edges lie in the plane.
    assert_eq!(w.weights[m.edge(10 + 21 * 5, 10 + 21 * 6)], 1.0);
    assert_same(&w.weights, &brute_weights(&m.input(), 1e-3));
}
