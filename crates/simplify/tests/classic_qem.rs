//! W App. B: "our error metric converges to the edge quadric error metric
//! when the input mesh is a closed manifold mesh". Two checks: the default
//! metric and the classic-QEM setting of the engine give the same result on
//! closed manifolds, and both equal an independent, brute-force
//! implementation of Garland–Heckbert 1997 written here.
#![allow(clippy::unwrap_used)] // test helpers, not library code

mod common;

use glam::DVec3;
use wildlod_mesh::Mesh;
use wildlod_simplify::{place_by_planes, simplify_mesh, Guards, Options, Quadric, Target};

fn no_flip_guard(mut o: Options) -> Options {
    o.guards = Guards {
        max_normal_turn_degrees: None,
        ..Guards::default()
    };
    o
}

fn triangles_as_position_sets(m: &Mesh) -> Vec<[[u32; 3]; 3]> {
    let mut out: Vec<[[u32; 3]; 3]> = m
        .faces
        .iter()
        .map(|f| {
            let mut t = [0usize, 1, 2].map(|k| m.positions[f[k] as usize].map(f32::to_bits));
            t.sort();
            t
        })
        .collect();
    out.sort();
    out
}

#[test]
fn default_metric_equals_classic_qem_on_closed_manifolds() {
    for mesh in [
        common::bumpy_sphere(8),
        wildlod_mesh::shapes::triangulate(&wildlod_mesh::shapes::torus(20, 10, 1.0, 0.35)),
    ] {
        // The pinch cost is an ordering rule outside W's metric (the torus
        // at 2% must change topology), and the face weight floor a
        // weighting of the planes both metrics share: the claim holds with
        // them off on both sides and with them on on both sides. The final
        // refit moves vertices after the metric has done its work (classic
        // QEM does not refit): the claim is about the collapses. The
        // present faces' planes are ours, not W's: the claim is about W's
        // metric, so they are off here.
        for (r, pinch) in [0.5, 0.1, 0.02]
            .into_iter()
            .flat_map(|r| [(r, 0.0), (r, 1.0)])
        {
            let target = Target {
                ratio: Some(r),
                ..Target::default()
            };
            let mut wild = Options {
                target,
                ..Options::default()
            };
            wild.metric.refit_sweeps = 0;
            wild.metric.current_face_weight = 0.0;
            wild.metric.pinch_cost = pinch;
            wild.metric.face_weight_floor = pinch / 2.0;
            let mut classic = Options {
                target,
                ..Options::classic_qem()
            };
            classic.metric.pinch_cost = pinch;
            classic.metric.face_weight_floor = pinch / 2.0;
            let (a, ra) = simplify_mesh(&mesh, &wild).unwrap();
            let (b, rb) = simplify_mesh(&mesh, &classic).unwrap();
            assert_eq!(
                a,
                b,
                "ratio {r}, pinch cost {pinch}, face floor {}",
                pinch / 2.0
            );
            assert_eq!(ra.output_triangles, rb.output_triangles);
            assert_eq!(ra.virtual_edges, 0);
        }
    }
}

/// Garland–Heckbert 1997, brute force: every step evaluates every edge with
/// the same quadrics and placement, and collapses the cheapest.
fn reference_qem(mesh: &Mesh, target_triangles: usize, regularization: f64) -> Vec<[[u32; 3]; 3]> {
    let mut pos: Vec<DVec3> = mesh
        .positions
        .iter()
        .map(|p| DVec3::from(p.map(f64::from)))
        .collect();
    // The engine works on the mesh normalized to a unit-diagonal box.
    let lo = pos.iter().fold(DVec3::splat(f64::MAX), |a, &p| a.min(p));
    let hi = pos.iter().fold(DVec3::splat(f64::MIN), |a, &p| a.max(p));
    let (center, scale) = (0.5 * (lo + hi), (hi - lo).length());
    for p in &mut pos {
        *p = (*p - center) / scale;
    }
    let mut tris: Vec<[usize; 3]> = mesh
        .faces
        .iter()
        .map(|f| [f[0] as usize, f[1] as usize, f[2] as usize])
        .collect();
    let mut q = vec![Quadric::ZERO; pos.len()];
    for t in &tris {
        let (a, b, c) = (pos[t[0]], pos[t[1]], pos[t[2]]);
        let n2 = (b - a).cross(c - a);
        let area = 0.5 * n2.length();
        let plane = Quadric::plane(n2.normalize(), (a + b + c) / 3.0, area / 3.0);
        for &v in t {
            q[v] += plane;
        }
    }
    // The regularization of each vertex, also kept apart: the planes alone
    // rank and place, the regularization only decides where they do not
    // determine a point (see `place_by_planes`).
    let mut reg = vec![Quadric::ZERO; pos.len()];
    for v in 0..pos.len() {
        let area: f64 = tris
            .iter()
            .filter(|t| t.contains(&v))
            .map(|t| {
                0.5 * (pos[t[1]] - pos[t[0]])
                    .cross(pos[t[2]] - pos[t[0]])
                    .length()
                    / 3.0
            })
            .sum();
        reg[v] = Quadric::point(pos[v], regularization * area);
        q[v] += reg[v];
    }
    while tris.len() > target_triangles {
        let mut edges: Vec<(usize, usize)> = tris
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
            .collect();
        edges.sort();
        edges.dedup();
        let best = edges
            .iter()
            .map(|&(i, j)| {
                let p = place_by_planes(&(q[i] + q[j]), &(reg[i] + reg[j]), pos[i], pos[j], 4.0);
                (p.error, i, j, p.position)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap();
        let (_, i, j, x) = best;
        pos[i] = x;
        q[i] = q[i] + q[j];
        reg[i] = reg[i] + reg[j];
        tris.retain(|t| !(t.contains(&i) && t.contains(&j)));
        for t in &mut tris {
            for v in t.iter_mut() {
                if *v == j {
                    *v = i;
                }
            }
        }
        // Same-orientation duplicates are one face.
        let mut seen = std::collections::HashSet::new();
        tris.retain(|t| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            seen.insert([t[k], t[(k + 1) % 3], t[(k + 2) % 3]])
        });
    }
    let mut out: Vec<[[u32; 3]; 3]> = tris
        .iter()
        .map(|t| {
            let mut s = t.map(|v| {
                let p = pos[v] * scale + center;
                [p.x as f32, p.y as f32, p.z as f32].map(f32::to_bits)
            });
            s.sort();
            s
        })
        .collect();
    out.sort();
    out
}

#[test]
fn engine_matches_brute_force_garland_heckbert_on_a_closed_mesh() {
    let mesh = common::bumpy_sphere(5); // 300 triangles
    for target in [200usize, 80, 20] {
        let mut options = no_flip_guard(Options {
            target: Target {
                triangles: Some(target),
                ..Target::default()
            },
            ..Options::default()
        });
        // The reference weighs planes by area, as Garland and Heckbert do,
        // with memory only, and places vertices only by collapses.
        options.metric.face_weight_floor = 0.0;
        options.metric.current_face_weight = 0.0;
        options.metric.refit_sweeps = 0;
        let (ours, report) = simplify_mesh(&mesh, &options).unwrap();
        assert_eq!(report.output_triangles, target);
        let reference = reference_qem(&mesh, target, options.metric.regularization);
        assert_same_triangles(&triangles_as_position_sets(&ours), &reference, target);
    }
}

/// Every triangle of `ours` matches one of `reference` (and the counts
/// agree), vertex by vertex within 1e-5 of the unit sphere: the engine
/// keeps its vertex quadrics in single precision between collapses
/// (`stored.rs`), the reference in double, so the positions agree to about
/// 1e-7, and a single collapse taken in another order moves vertices by
/// the bumps' size (0.05) or more.
fn assert_same_triangles(ours: &[[[u32; 3]; 3]], reference: &[[[u32; 3]; 3]], target: usize) {
    assert_eq!(ours.len(), reference.len(), "target {target}");
    let pos = |b: [u32; 3]| b.map(f32::from_bits);
    let near = |a: [u32; 3], b: [u32; 3]| {
        let (a, b) = (pos(a), pos(b));
        (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-5)
    };
    let mut taken = vec![false; reference.len()];
    for t in ours {
        let found = reference
            .iter()
            .enumerate()
            .position(|(k, r)| !taken[k] && (0..3).all(|x| near(t[x], r[x])));
        let Some(k) = found else {
            panic!("target {target}: {:?} is not in the reference", t.map(pos));
        };
        taken[k] = true;
    }
}
