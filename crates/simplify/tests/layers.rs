//! Layers (decals and other sheets lying on a part) stay in front of the
//! simplified surface under them: `Metric::keep_layers`.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use glam::DVec2;
use wildlod_mesh::{Mesh, Scene};
use wildlod_simplify::{simplify_scene, Options, Target};
use wildlod_testkit::scenes::{self, DECAL_GAP};

fn at_ratio(ratio: f64, keep_layers: bool) -> Options {
    let mut o = Options {
        target: Target {
            ratio: Some(ratio),
            ..Target::default()
        },
        ..Options::default()
    };
    o.metric.keep_layers = keep_layers;
    // The wall is quads: with the ordering held to the output's distance
    // (`QuadSettings::distance_tolerance`), sunk decals could choose
    // another tie width than placed ones, and the wall compared below
    // would differ for that reason alone.
    o.quad.distance_tolerance = f64::INFINITY;
    o
}

/// The wall's height under `(x, y)` on `mesh`'s wall faces (part 0),
/// seen along z (the wall faces +z), if any wall triangle covers it.
fn wall_height(mesh: &Mesh, x: f64, y: f64) -> Option<f64> {
    let p = |v: u32| mesh.positions[v as usize].map(f64::from);
    let q = DVec2::new(x, y);
    for (f, ids) in mesh.faces.iter().enumerate() {
        if mesh.face_parts[f] != 0 {
            continue;
        }
        for k in 1..ids.len() - 1 {
            let [a, b, c] = [ids[0], ids[k], ids[k + 1]].map(p);
            let (a2, b2, c2) = (
                DVec2::new(a[0], a[1]),
                DVec2::new(b[0], b[1]),
                DVec2::new(c[0], c[1]),
            );
            let d = (b2 - a2).perp_dot(c2 - a2);
            if d.abs() < 1e-15 {
                continue;
            }
            let l1 = (q - a2).perp_dot(c2 - a2) / d;
            let l2 = (b2 - a2).perp_dot(q - a2) / d;
            let l0 = 1.0 - l1 - l2;
            if l0.min(l1).min(l2) >= -1e-9 {
                return Some(l0 * a[2] + l1 * b[2] + l2 * c[2]);
            }
        }
    }
    None
}

/// The height over the simplified wall under it of every decal vertex and
/// of points spread over every decal triangle (a decal's faces can pass
/// behind a surface whose vertices and edges lie under them while its
/// own vertices stay in front).
fn decal_offsets(out: &Scene) -> Vec<f64> {
    const STEPS: usize = 8;
    let mesh = &out.meshes[0];
    let p = |v: u32| glam::DVec3::from(mesh.positions[v as usize].map(f64::from));
    let mut offsets = Vec::new();
    for (f, ids) in mesh.faces.iter().enumerate() {
        if mesh.face_parts[f] != 1 {
            continue;
        }
        for k in 1..ids.len() - 1 {
            let [a, b, c] = [ids[0], ids[k], ids[k + 1]].map(p);
            for i in 0..=STEPS {
                for j in 0..=STEPS - i {
                    let (s, t) = (i as f64 / STEPS as f64, j as f64 / STEPS as f64);
                    let q = a + (b - a) * s + (c - a) * t;
                    if let Some(h) = wall_height(mesh, q.x, q.y) {
                        offsets.push(q.z - h);
                    }
                }
            }
        }
    }
    offsets
}

#[test]
fn decals_stay_in_front_of_a_simplified_wall() {
    let input = scenes::decal_wall();
    // The geometry under test: the offsets are the gap in the input.
    let before = decal_offsets(&input);
    let least = before.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        least > 0.5 * DECAL_GAP,
        "input: a decal vertex {least} over the wall"
    );
    for ratio in [0.1, 0.02] {
        let (kept, report) = simplify_scene(&input, &at_ratio(ratio, true)).unwrap();
        let (sunk, _) = simplify_scene(&input, &at_ratio(ratio, false)).unwrap();
        let with = decal_offsets(&kept);
        let without = decal_offsets(&sunk);
        assert!(!with.is_empty(), "{ratio}: decals left");
        // Without the layer pass the wall moves past the gap: decals sink.
        let behind = without.iter().filter(|&&o| o < 0.0).count();
        assert!(behind > 0, "{ratio}: the scene no longer tests anything");
        // With it, every point of every decal keeps most of its gap over
        // the LOD wall (measured along z; it is kept along the normal).
        let least = with.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            least > 0.5 * DECAL_GAP,
            "{ratio}: a decal point {least} over the wall ({behind} of {} behind without the pass)",
            without.len()
        );
        let placed: usize = report.groups.iter().map(|g| g.report.layer_vertices).sum();
        assert!(placed > 0, "{ratio}: no layer vertex placed");
        // The wall itself is the same with and without the pass.
        let wall = |s: &Scene| {
            let m = &s.meshes[0];
            let mut w: Vec<[u32; 3]> = m
                .faces
                .iter()
                .enumerate()
                .filter(|&(f, _)| m.face_parts[f] == 0)
                .flat_map(|(_, ids)| {
                    ids.iter()
                        .map(|&v| m.positions[v as usize].map(f32::to_bits))
                })
                .collect();
            w.sort_unstable();
            w
        };
        assert_eq!(wall(&kept), wall(&sunk), "{ratio}: the wall moved");
    }
}
