//! Geometric fidelity where the best peers (Blender's Decimate,
//! meshoptimizer) keep what is there: open borders, duplicated sheets, thin
//! parts (issue 12). Every mesh is generated here.
#![allow(clippy::unwrap_used)] // test helpers, not library code

mod common;

use common::{bumpy_sphere, ratio};
use glam::DVec3;
use wildlod_mesh::{shapes, Faces, Mesh};
use wildlod_simplify::{simplify_mesh, simplify_polygons, Metric, Options, Target};
use wildlod_testkit::SplitMix64;

/// Sides used by exactly one face: the border, as vertex pairs.
fn border_sides(faces: &Faces) -> Vec<(u32, u32)> {
    let mut count = std::collections::HashMap::new();
    for f in faces.iter() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut out: Vec<(u32, u32)> = count
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect();
    out.sort_unstable();
    out
}

fn point(p: [f32; 3]) -> DVec3 {
    DVec3::from(p.map(f64::from))
}

fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + t * ab)
}

/// An L-shaped flat patch in the plane z = `z`, on an irregular grid: the
/// interior vertices jittered, each cell a quad or split into two triangles
/// along either diagonal at random. The border is the L's six sides.
/// ```text
///  y=1 +-----------+
///      |  .  .  .  |
///      |  .  .  .  +-----------+  y = 0.5
///      |  .  .  .  .  .  .  .  |
///  y=0 +-----------------------+
///     x=0         x=0.75      x=1.5
/// ```
fn flat_patch(z: f32, seed: u64) -> (Vec<[f32; 3]>, Faces) {
    let (nx, ny) = (30usize, 20usize);
    let (notch_i, notch_j) = (15usize, 10usize);
    let inside = |i: usize, j: usize| !(i > notch_i && j > notch_j);
    let on_border = |i: usize, j: usize| {
        i == 0 || j == 0 || i == nx || j == ny || (i >= notch_i && j >= notch_j)
    };
    let mut rng = SplitMix64(seed);
    let mut id = vec![u32::MAX; (nx + 1) * (ny + 1)];
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            if !inside(i, j) {
                continue;
            }
            let (mut x, mut y) = (1.5 * i as f64 / nx as f64, j as f64 / ny as f64);
            if !on_border(i, j) {
                x += (rng.next_f64() - 0.5) * 0.6 * 1.5 / nx as f64;
                y += (rng.next_f64() - 0.5) * 0.6 / ny as f64;
            }
            id[j * (nx + 1) + i] = positions.len() as u32;
            positions.push([x as f32, y as f32, z]);
        }
    }
    let v = |i: usize, j: usize| id[j * (nx + 1) + i];
    let mut faces = Faces::default();
    for j in 0..ny {
        for i in 0..nx {
            if !(inside(i, j) && inside(i + 1, j) && inside(i, j + 1) && inside(i + 1, j + 1)) {
                continue;
            }
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            let r = rng.next_f64();
            if r < 0.5 {
                faces.push(&[a, b, c, d]);
            } else if r < 0.75 {
                faces.push(&[a, b, c]);
                faces.push(&[a, c, d]);
            } else {
                faces.push(&[a, b, d]);
                faces.push(&[b, c, d]);
            }
        }
    }
    (positions, faces)
}

/// Border vertices where the border turns: the input's corners.
fn border_corners(positions: &[[f32; 3]], sides: &[(u32, u32)]) -> Vec<DVec3> {
    let mut around: std::collections::HashMap<u32, Vec<u32>> = Default::default();
    for &(a, b) in sides {
        around.entry(a).or_default().push(b);
        around.entry(b).or_default().push(a);
    }
    let mut out = Vec::new();
    for (&v, n) in &around {
        let p = point(positions[v as usize]);
        let turns = n.len() != 2 || {
            let (u, w) = (
                p - point(positions[n[0] as usize]),
                point(positions[n[1] as usize]) - p,
            );
            u.cross(w).length() > 1e-9 * u.length() * w.length()
        };
        if turns {
            out.push(p);
        }
    }
    out
}

#[test]
fn flat_open_patch_keeps_its_plane_and_its_border_at_a_tenth() {
    let z = 0.25f32;
    for seed in [1, 2, 3] {
        let (positions, faces) = flat_patch(z, seed);
        let input_border = border_sides(&faces);
        let corners = border_corners(&positions, &input_border);
        assert_eq!(corners.len(), 6, "the L has six corners");
        let out = simplify_polygons(&positions, &faces, &ratio(0.1)).unwrap();
        let target = out.report.target_triangles;
        assert!(out.report.output_triangles.abs_diff(target) <= 1);
        for p in &out.positions {
            assert!((p[2] - z).abs() as f64 <= 1e-9, "left the plane: {p:?}");
        }
        // Every output border vertex lies on the input's border polyline.
        for (a, b) in border_sides(&out.faces) {
            for v in [a, b] {
                let p = point(out.positions[v as usize]);
                let d = input_border
                    .iter()
                    .map(|&(s, t)| {
                        segment_distance(
                            p,
                            point(positions[s as usize]),
                            point(positions[t as usize]),
                        )
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d <= 1e-6,
                    "seed {seed}: border vertex {p} is {d} off the border"
                );
            }
        }
        // Every corner of the input is still a vertex.
        for c in &corners {
            let d = out
                .positions
                .iter()
                .map(|&p| point(p).distance(*c))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 1e-6, "seed {seed}: corner {c} lost ({d} away)");
        }
    }
}

/// An open tube (no caps) along z from `z0` to `z1`, around (`x`, `y`):
/// `around` × `along` quads.
fn tube(x: f32, y: f32, r: f32, z0: f32, z1: f32, around: usize, along: usize) -> Mesh {
    let mut positions = Vec::new();
    for k in 0..=along {
        let z = z0 + (z1 - z0) * k as f32 / along as f32;
        for a in 0..around {
            let t = std::f32::consts::TAU * a as f32 / around as f32;
            positions.push([x + r * t.cos(), y + r * t.sin(), z]);
        }
    }
    let mut faces = Faces::default();
    let id = |k: usize, a: usize| (k * around + a % around) as u32;
    for k in 0..along {
        for a in 0..around {
            faces.push(&[id(k, a), id(k, a + 1), id(k + 1, a + 1), id(k + 1, a)]);
        }
    }
    Mesh::from_polygons(positions, faces)
}

/// A chair: a seat and a back (closed boxes) and four legs (open tubes
/// that stand in the seat: separate parts, as such models come).
fn chair() -> Mesh {
    let mut parts = vec![
        shapes::triangulate(&shapes::box_grid([-0.5, -0.5, 0.45], [0.5, 0.5, 0.55], 6)),
        shapes::box_grid([-0.5, 0.42, 0.55], [0.5, 0.5, 1.2], 5),
    ];
    for (x, y) in [(-0.4, -0.4), (0.4, -0.4), (-0.4, 0.4), (0.4, 0.4)] {
        parts.push(tube(x, y, 0.04, 0.0, 0.47, 8, 6));
    }
    shapes::merge(&parts)
}

/// `m` with every face repeated, on its own copies of the vertices (as
/// exporters write double-sided sheets), reversed or not.
fn doubled(m: &Mesh, reversed: bool) -> Mesh {
    let n = m.positions.len() as u32;
    let mut positions = m.positions.clone();
    positions.extend_from_slice(&m.positions);
    let mut faces = m.faces.clone();
    for f in m.faces.iter() {
        let mut g: Vec<u32> = f.iter().map(|&v| v + n).collect();
        if reversed {
            g.reverse();
        }
        faces.push(&g);
    }
    Mesh::from_polygons(positions, faces)
}

/// The output's faces as sorted lists of corner positions (bit patterns),
/// each face once whatever its orientation or copies: the geometry.
fn geometry(m: &Mesh) -> Vec<Vec<[u32; 3]>> {
    let mut out: Vec<Vec<[u32; 3]>> = m
        .faces
        .iter()
        .map(|f| {
            let mut c: Vec<[u32; 3]> = f
                .iter()
                .map(|&v| m.positions[v as usize].map(f32::to_bits))
                .collect();
            c.sort_unstable();
            c
        })
        .collect();
    out.sort();
    out.dedup();
    out
}

#[test]
fn doubled_faces_simplify_like_the_single_copy() {
    // With every twin riding along (the chair's boxes are closed: by
    // default their twins go, see the hidden-twin tests below).
    let ratio = |r| {
        let mut o = ratio(r);
        o.guards.drop_hidden_twins = false;
        o
    };
    let single = chair();
    let t = single.triangle_count();
    for r in [0.5, 0.2, 0.05] {
        // Ratios whose target is exact for the doubled count too.
        assert_eq!(
            (2.0 * t as f64 * r).round() as usize,
            2 * (t as f64 * r).round() as usize
        );
        let (a, ra) = simplify_mesh(&single, &ratio(r)).unwrap();
        let want = geometry(&a);
        for reversed in [true, false] {
            let (b, rb) = simplify_mesh(&doubled(&single, reversed), &ratio(r)).unwrap();
            assert_eq!(geometry(&b), want, "ratio {r}, reversed {reversed}");
            // Twins stay (a double-sided sheet stays double-sided), exact
            // repeats are cleaned away.
            let copies = if reversed { 2 } else { 1 };
            assert_eq!(rb.output_triangles, copies * ra.output_triangles);
            assert_eq!(b.faces.len(), copies * a.faces.len());
        }
    }
}

/// Six times the volume `m`'s faces enclose (positive when they face out).
fn enclosed_volume(m: &Mesh) -> f64 {
    let p = |v: u32| DVec3::from(m.positions[v as usize].map(f64::from));
    m.faces
        .iter()
        .map(|f| {
            (1..f.len() - 1)
                .map(|k| p(f[0]).dot(p(f[k]).cross(p(f[k + 1]))))
                .sum::<f64>()
        })
        .sum()
}

/// `m` with every face reversed.
fn reversed(m: &Mesh) -> Mesh {
    let mut faces = Faces::default();
    for f in m.faces.iter() {
        let g: Vec<u32> = f.iter().rev().copied().collect();
        faces.push(&g);
    }
    Mesh::from_polygons(m.positions.clone(), faces)
}

fn faces_target(n: usize) -> Options {
    Options {
        target: Target {
            triangles: Some(n),
            ..Target::default()
        },
        ..Options::default()
    }
}

#[test]
fn hidden_twins_of_a_closed_surface_are_dropped_and_their_budget_buys_detail() {
    let single = bumpy_sphere(6);
    let t = single.triangle_count();
    let want = geometry(&single);
    for inward_first in [false, true] {
        // The exporter's first copy faces out, or in.
        let first = if inward_first {
            reversed(&single)
        } else {
            single.clone()
        };
        let double = doubled(&first, true);
        // Half of the doubled count is the whole visible surface: nothing
        // to collapse, every face kept once, facing out.
        let (out, report) = simplify_mesh(&double, &ratio(0.5)).unwrap();
        assert_eq!(report.hidden_twins, t, "inward first {inward_first}");
        assert_eq!(out.triangle_count(), t);
        let got = geometry(&out);
        let same = got.iter().zip(&want).filter(|(a, b)| a == b).count();
        assert!(
            got == want,
            "{same} of {} faces as input, stop {:?}",
            want.len(),
            report.stop
        );
        assert!(enclosed_volume(&out) > 0.0, "inward first {inward_first}");
        // A smaller budget: the same faces as the single copy gets.
        let (a, _) = simplify_mesh(&single, &faces_target(t / 4)).unwrap();
        let (b, rb) = simplify_mesh(&double, &faces_target(t / 4)).unwrap();
        assert_eq!(rb.output_triangles, t / 4);
        assert_eq!(geometry(&b), geometry(&a), "inward first {inward_first}");
        assert!(enclosed_volume(&b) > 0.0);
    }
}

/// An open pipe of radius 1 and the given length along z: `around` quads
/// per ring, `along` rings of quads.
fn pipe(around: u32, along: u32, length: f32) -> Mesh {
    let mut positions = Vec::new();
    for r in 0..=along {
        for k in 0..around {
            let a = k as f32 * std::f32::consts::TAU / around as f32;
            positions.push([a.cos(), a.sin(), length * r as f32 / along as f32]);
        }
    }
    let mut faces = Faces::default();
    let v = |r: u32, k: u32| r * around + k % around;
    for r in 0..along {
        for k in 0..around {
            faces.push(&[v(r, k), v(r, k + 1), v(r + 1, k + 1), v(r + 1, k)]);
        }
    }
    Mesh::from_polygons(positions, faces)
}

/// `m` without the faces `drop` picks (by their middle).
fn without(m: &Mesh, drop: impl Fn(DVec3) -> bool) -> Mesh {
    let mut faces = Faces::default();
    for f in m.faces.iter() {
        let middle = f
            .iter()
            .map(|&v| DVec3::from(m.positions[v as usize].map(f64::from)))
            .sum::<DVec3>()
            / f.len() as f64;
        if !drop(middle) {
            faces.push(f);
        }
    }
    Mesh::from_polygons(m.positions.clone(), faces)
}

#[test]
fn twins_go_where_no_line_of_sight_reaches_them_and_stay_where_one_does() {
    // A torus missing one face: open by topology, but the tube's inside
    // curves away from the hole, so most of it cannot be seen through it.
    let torus = shapes::triangulate(&shapes::torus(48, 12, 1.0, 0.3));
    let first = torus.faces.iter().next().unwrap().to_vec();
    let middle_of = |m: &Mesh, f: &[u32]| {
        f.iter()
            .map(|&v| DVec3::from(m.positions[v as usize].map(f64::from)))
            .sum::<DVec3>()
            / f.len() as f64
    };
    let p0 = middle_of(&torus, &first);
    let holed = without(&torus, |m| m.distance(p0) < 1e-6);
    let n = holed.faces.len();
    assert_eq!(n + 1, torus.faces.len());
    let (out, report) = simplify_mesh(&doubled(&holed, true), &ratio(0.5)).unwrap();
    assert!(
        report.hidden_twins * 2 > n,
        "{} of {n}",
        report.hidden_twins
    );
    assert!(
        report.hidden_twins < n,
        "the faces around the hole can be seen"
    );
    assert!(enclosed_volume(&out) > 0.0);
    // A sphere missing one face: its inside is convex, every inside face
    // can be seen through the hole, and (nearly) every twin stays.
    let sphere = bumpy_sphere(6);
    let first = sphere.faces.iter().next().unwrap().to_vec();
    let p0 = middle_of(&sphere, &first);
    let holed = without(&sphere, |m| m.distance(p0) < 1e-6);
    let n = holed.faces.len();
    let (_, report) = simplify_mesh(&doubled(&holed, true), &ratio(1.0)).unwrap();
    assert!(
        report.hidden_twins * 50 <= n,
        "{} of {n}",
        report.hidden_twins
    );
    // A pipe ten times as long as it is wide, open at both ends: deep in
    // it a face sees out only along the pipe, through the far end, which
    // no fixed set of directions finds; the lines of sight to the
    // openings do. Every twin stays.
    let tube = pipe(24, 40, 20.0);
    let (out, report) = simplify_mesh(&doubled(&tube, true), &ratio(1.0)).unwrap();
    assert_eq!(report.hidden_twins, 0);
    assert_eq!(out.faces.len(), 2 * tube.faces.len());
    // Half a sphere: every inside face sees out of the bowl.
    let bowl = without(&sphere, |m| m.z > 0.0);
    let (out, report) = simplify_mesh(&doubled(&bowl, true), &ratio(1.0)).unwrap();
    assert_eq!(report.hidden_twins, 0);
    assert_eq!(out.faces.len(), 2 * bowl.faces.len());
}

#[test]
fn twins_stay_on_open_sheets_and_on_see_through_faces() {
    // An open sheet: both sides show.
    let sheet = shapes::triangulate(&shapes::quad_grid(8, 8));
    let (out, report) = simplify_mesh(&doubled(&sheet, true), &ratio(1.0)).unwrap();
    assert_eq!(report.hidden_twins, 0);
    assert_eq!(out.faces.len(), 2 * sheet.faces.len());
    // A closed surface seen through (a blended material): the inside shows.
    let single = bumpy_sphere(4);
    let double = doubled(&single, true);
    let mut options = ratio(1.0);
    options.data.see_through_faces = vec![true; double.faces.len()];
    let (out, report) = simplify_mesh(&double, &options).unwrap();
    assert_eq!(report.hidden_twins, 0);
    assert_eq!(out.faces.len(), double.faces.len());
    // One flag per input face, or an error naming both counts.
    let mut short = ratio(1.0);
    short.data.see_through_faces = vec![true; 3];
    let err = simplify_mesh(&double, &short).unwrap_err();
    assert!(
        matches!(err, wildlod_simplify::Error::SeeThroughCount { flags: 3, faces } if faces == double.faces.len()),
        "{err}"
    );
    // And with the option off.
    let mut options = ratio(1.0);
    options.guards.drop_hidden_twins = false;
    let (out, _) = simplify_mesh(&double, &options).unwrap();
    assert_eq!(out.faces.len(), double.faces.len());
}

/// A gently curved square sheet `n × n` (triangles) with a long thin spur
/// standing on it: a tube of radius `r` and height `h` with a pointed tip,
/// closed at its foot by a fan to the sheet's middle vertex, so the whole
/// is one piece.
fn sheet_with_spur(n: usize, r: f32, h: f32) -> Mesh {
    let wave = |x: f32, y: f32| 0.01 * ((7.0 * x).sin() + (5.0 * y).cos());
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push([x, y, wave(x, y)]);
        }
    }
    let mut faces = Faces::default();
    for j in 0..n {
        for i in 0..n {
            let v = |a: usize, b: usize| (b * (n + 1) + a) as u32;
            faces.push(&[v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            faces.push(&[v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    // The spur: rings of 6 around (0.5, 0.5), from the sheet up to h, then
    // a tip vertex.
    let (around, along) = (6usize, 40usize);
    let base = positions.len() as u32;
    for k in 0..=along {
        let z = wave(0.5, 0.5) + h * k as f32 / along as f32;
        for a in 0..around {
            let t = std::f32::consts::TAU * a as f32 / around as f32;
            positions.push([0.5 + r * t.cos(), 0.5 + r * t.sin(), z]);
        }
    }
    let tip = positions.len() as u32;
    positions.push([0.5, 0.5, wave(0.5, 0.5) + h + 2.0 * r]);
    let ring = |k: usize, a: usize| base + (k * around + a % around) as u32;
    for k in 0..along {
        for a in 0..around {
            faces.push(&[ring(k, a), ring(k, a + 1), ring(k + 1, a + 1)]);
            faces.push(&[ring(k, a), ring(k + 1, a + 1), ring(k + 1, a)]);
        }
    }
    let middle = ((n / 2) * (n + 1) + n / 2) as u32;
    for a in 0..around {
        faces.push(&[ring(along, a), ring(along, a + 1), tip]);
        faces.push(&[ring(0, a + 1), ring(0, a), middle]);
    }
    Mesh::from_polygons(positions, faces)
}

#[test]
fn thin_spur_on_a_sheet_survives_at_half() {
    let (r, h) = (0.004f32, 0.4f32);
    let mesh = sheet_with_spur(40, r, h);
    assert_eq!(common::topo(&mesh).components, 1);
    let (out, report) = simplify_mesh(&mesh, &ratio(0.5)).unwrap();
    assert!(report.output_triangles.abs_diff(report.target_triangles) <= 1);
    // The spur keeps its height: some vertex still near its tip.
    let top = out.positions.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
    let want = mesh.positions.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
    assert!(
        want - top <= 0.05 * h,
        "the spur lost {:.3} of its {h} height",
        want - top
    );
    // And the whole stays one piece.
    assert_eq!(common::topo(&out).components, 1);
}

/// Radius and height of the hair-thin spur below.
const HAIR: (f32, f32) = (0.0005, 0.1);

/// How much of its height the hair-thin spur on a 60 × 60 sheet loses at
/// `r` of its triangles under the default options changed by `tune`; the
/// target is reached (within one triangle) either way.
fn hair_height_lost(r: f64, tune: impl Fn(&mut wildlod_simplify::Options)) -> f32 {
    let mesh = sheet_with_spur(60, HAIR.0, HAIR.1);
    let top = |m: &Mesh| m.positions.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
    let mut o = ratio(r);
    tune(&mut o);
    let (out, report) = simplify_mesh(&mesh, &o).unwrap();
    assert!(report.output_triangles.abs_diff(report.target_triangles) <= 1);
    top(&mesh) - top(&out)
}

/// A spur much thinner than the sheet's faces (radius 5e-4 of a unit
/// sheet whose faces are 1/60 wide): its tip has almost no area, so with
/// area-weighted ranking alone shortening it costs next to nothing. With
/// the regularization ranking too (shortest travel first) it loses 70% of
/// its height at 20%; the area floor ranks it by distance. (The pinch
/// cost, off here, keeps it too; see below.)
#[test]
fn hair_thin_spur_keeps_its_height_under_the_area_floor() {
    let h = HAIR.1;
    let lost = |floor: f64| {
        hair_height_lost(0.2, |o| {
            o.metric.area_floor = floor;
            o.metric.pinch_cost = 0.0;
            o.metric.face_weight_floor = 0.0;
            o.metric.crease_area_weight = 0.0;
            o.metric.regularized_choice = true;
        })
    };
    let with = lost(1.0);
    assert!(with <= 0.02 * h, "lost {with} of {h} with the floor");
    // Without it the spur retracts: the floor is what keeps it.
    let without = lost(0.0);
    assert!(
        without >= 0.3 * h,
        "lost only {without} of {h} without the floor"
    );
}

/// The face weight floor keeps the same spur at 5% with neither the
/// area floor nor the pinch cost (without it, 70% of its height goes):
/// its tiny tip faces weigh half a mean face, so shortening it costs what
/// it costs elsewhere on the sheet.
#[test]
fn hair_thin_spur_keeps_its_height_under_the_face_weight_floor() {
    let h = HAIR.1;
    let lost = |floor: f64| {
        hair_height_lost(0.05, |o| {
            o.metric.face_weight_floor = floor;
            o.metric.pinch_cost = 0.0;
            o.metric.crease_area_weight = 0.0;
        })
    };
    let with = lost(0.5);
    assert!(with <= 0.02 * h, "lost {with} of {h} with the face floor");
    let without = lost(0.0);
    assert!(
        without >= 0.3 * h,
        "lost only {without} of {h} without the face floor"
    );
}

/// The same spur at 5%: by then collapsing across it is cheaper than
/// anything left on the sheet, and without the pinch cost it flattens
/// into faceless edges (70% of its height gone); with it, it stays a tube.
#[test]
fn hair_thin_spur_survives_a_twentieth_under_the_pinch_cost() {
    let h = HAIR.1;
    // Under W's plain area weighting: the face weight floor keeps the
    // spur too (see above), and this is about the pinch cost.
    let lost = |pinch: f64| {
        hair_height_lost(0.05, |o| {
            o.metric.pinch_cost = pinch;
            o.metric.face_weight_floor = 0.0;
            o.metric.crease_area_weight = 0.0;
        })
    };
    let with = lost(1.0);
    assert!(with <= 0.02 * h, "lost {with} of {h} with the pinch cost");
    let without = lost(0.0);
    assert!(without >= 0.3 * h, "lost only {without} of {h} without it");
}

/// The same spur at 5% with neither the pinch cost nor the face weight
/// floor: its sides meet the sheet at sharp creases, and the crease area
/// term (`Metric::crease_area_weight`) charges shortening it for the area
/// it sweeps against them, as a border would. Each of the three keeps the
/// spur alone; the tests above turn this one off to see the others.
#[test]
fn hair_thin_spur_keeps_its_height_under_the_crease_area_term() {
    let h = HAIR.1;
    let lost = |weight: f64| {
        hair_height_lost(0.05, |o| {
            o.metric.crease_area_weight = weight;
            o.metric.pinch_cost = 0.0;
            o.metric.face_weight_floor = 0.0;
        })
    };
    let with = lost(1.0);
    assert!(with <= 0.02 * h, "lost {with} of {h} with the crease term");
    let without = lost(0.0);
    assert!(
        without >= 0.3 * h,
        "lost only {without} of {h} without the crease term"
    );
}

/// Pinching is ranked last, not forbidden: a torus cannot be triangulated
/// with fewer than 14 triangles without changing its topology, and asked
/// for 8 it still gets there.
#[test]
fn pinch_cost_still_reaches_a_target_below_the_topology_minimum() {
    let torus = shapes::triangulate(&shapes::torus(24, 12, 1.0, 0.3));
    let mut o = wildlod_simplify::Options {
        target: wildlod_simplify::Target {
            ratio: None,
            triangles: Some(8),
            error: None,
        },
        ..Default::default()
    };
    o.metric.pinch_cost = 1.0;
    let (_, report) = simplify_mesh(&torus, &o).unwrap();
    o.metric.pinch_cost = 0.0;
    let (_, plain) = simplify_mesh(&torus, &o).unwrap();
    assert!(
        report.output_triangles <= 8,
        "{} ({} without the pinch cost, {:?} / {:?})",
        report.output_triangles,
        plain.output_triangles,
        report.stop,
        report.rejected
    );
}

/// Small parts pinch at no extra cost: 300 closed boxes (none near
/// another, so no virtual edge merges them) at 1% of their triangles are
/// each too small to stay closed, and whole boxes go.
#[test]
fn pinch_cost_lets_parts_too_small_for_the_target_vanish() {
    let mut parts = Vec::new();
    for k in 0..300 {
        let (x, y) = ((k % 20) as f32, (k / 20) as f32);
        let s = 0.2 + 0.002 * k as f32;
        parts.push(shapes::cuboid([x, y, 0.0], [x + s, y + s, s]));
    }
    let mesh = shapes::merge(&parts);
    let mut o = ratio(0.01);
    o.metric.pinch_cost = 1.0;
    let (out, report) = simplify_mesh(&mesh, &o).unwrap();
    assert_eq!(report.target_triangles, 36);
    assert!(report.output_triangles <= 36, "{}", report.output_triangles);
    assert!(!out.faces.is_empty());
}

#[test]
fn faces_with_twins_reach_a_face_budget_within_one_face_and_say_so_when_below() {
    // A closed sphere written twice, once each way, seen through (so every
    // twin stays): a collapse removes two faces with their twins, four
    // triangles, so some budgets cannot be met within one triangle.
    let single = bumpy_sphere(4);
    let double = doubled(&single, true);
    let mut slack_seen = 0;
    for t in 8..80 {
        let mut options = faces_target(t);
        options.data.see_through_faces = vec![true; double.faces.len()];
        let (out, report) = simplify_mesh(&double, &options).unwrap();
        let n = out.triangle_count();
        assert_eq!(report.hidden_twins, 0);
        if n.abs_diff(t) <= 1 {
            assert!(!report.twin_slack || n < t, "target {t}: {n}");
            continue;
        }
        // Otherwise below by at most one face with its twin, and reported.
        assert!(
            report.twin_slack && n < t && t - n <= 2,
            "target {t}: {n}, {report:?}"
        );
        slack_seen += 1;
    }
    // Budgets two above a multiple of four need it.
    assert!(slack_seen > 5, "{slack_seen}");
}

/// An `n × n/2` grid over [0, 2] × [0, 1], flat for x ≤ 1 and curved both
/// ways as z = 0.16 (x − 1)² (1 + 4 (y − ½)²) beyond, where its columns
/// are twice as dense: a
/// collapse on the curved half deviates from its planes by about a
/// thousandth of its length, and travels half as far as a flat one.
fn half_flat_sheet(n: usize) -> Mesh {
    let mut m = half_flat_sheet_with_uvs(n);
    m.attributes.clear();
    m
}

/// [`half_flat_sheet`] with the grid's UVs.
fn half_flat_sheet_with_uvs(n: usize) -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_grid(n, n / 2));
    for p in &mut m.positions {
        let u = p[0];
        let x = if u <= 1.0 / 3.0 {
            3.0 * u
        } else {
            1.0 + 1.5 * (u - 1.0 / 3.0)
        };
        let y = p[1];
        let z = if x > 1.0 {
            0.16 * (x - 1.0) * (x - 1.0) * (1.0 + 4.0 * (y - 0.5) * (y - 0.5))
        } else {
            0.0
        };
        *p = [x, y, z];
    }
    m
}

#[test]
fn free_collapses_go_first_where_the_planes_decide() {
    // A fifth of the triangles can go from the flat third alone, at no
    // error. Ranked by the regularization as well (travel first), the
    // shorter curved collapses come first: the control shows the test
    // would see it.
    use wildlod_eval::{compare, CompareOptions, EvalMesh};
    let input = half_flat_sheet(40);
    let hausdorff = |o: &Options| {
        let (out, report) = simplify_mesh(&input, o).unwrap();
        assert!(report.output_triangles <= report.target_triangles);
        compare(
            &EvalMesh::from_mesh(&input),
            &EvalMesh::from_mesh(&out),
            &CompareOptions::default(),
        )
        .hausdorff
    };
    let free = hausdorff(&ratio(0.8));
    let mut regularized = ratio(0.8);
    regularized.metric.regularized_choice = true;
    let ranked_by_travel = hausdorff(&regularized);
    assert!(free < 1e-6, "flat collapses first: {free}");
    assert!(
        ranked_by_travel > 10.0 * free.max(1e-7),
        "the control ({ranked_by_travel}) shows no difference"
    );
}

#[test]
fn steering_attributes_and_quad_mode_keep_the_regularization_choosing() {
    // With UVs that steer, the regularization's travel steers too
    // (`AttributeOptions::regularized_choice`), as appearance: bounded by
    // the geometric cost (`AttributeOptions::geometry_tolerance`), not
    // ranking as geometry does under `Metric::regularized_choice`. Turned
    // off, the result changes. Without UVs the default is the planes'
    // choice.
    let uv = half_flat_sheet_with_uvs(40);
    let run = |m: &Mesh, tune: &dyn Fn(&mut Options)| {
        let mut o = ratio(0.3);
        tune(&mut o);
        simplify_mesh(m, &o).unwrap().0.positions
    };
    let default = run(&uv, &|_| {});
    assert_ne!(default, run(&uv, &|o| o.metric.regularized_choice = true));
    assert_ne!(
        default,
        run(&uv, &|o| o.attributes.regularized_choice = false)
    );
    let plain = half_flat_sheet(40);
    let default = run(&plain, &|_| {});
    assert_ne!(
        default,
        run(&plain, &|o| o.metric.regularized_choice = true)
    );
    // Quad mode: the same sheet as quads keeps the regularized choice
    // unless `QuadSettings::regularized_choice` is off.
    let mut quads = shapes::quad_grid(40, 20);
    quads.attributes.clear();
    for p in &mut quads.positions {
        let x = 2.0 * p[0];
        p[2] = if x > 1.0 {
            0.16 * (x - 1.0) * (x - 1.0) * (1.0 + 4.0 * (p[1] - 0.5) * (p[1] - 0.5))
        } else {
            0.0
        };
        p[0] = x;
    }
    // (The ordered run alone: the run without the ordering that holds it,
    // `QuadSettings::distance_tolerance`, follows `Metric`.)
    let unheld = |o: &mut Options| o.quad.distance_tolerance = f64::INFINITY;
    let default = run(&quads, &unheld);
    assert_eq!(
        default,
        run(&quads, &|o| {
            unheld(o);
            o.metric.regularized_choice = true
        })
    );
    assert_ne!(
        default,
        run(&quads, &|o| {
            unheld(o);
            o.quad.regularized_choice = false
        })
    );
}

/// A unit sphere (16 × 16 quads a side, triangulated) with a small box
/// beside it, apart from it: a side mirror beside a truck's body.
fn sphere_with_mirror() -> Mesh {
    let body = shapes::triangulate(&shapes::quad_sphere(16));
    let mirror = shapes::cuboid([1.1, -0.03, -0.03], [1.2, 0.03, 0.03]);
    shapes::merge(&[body, mirror])
}

#[test]
fn a_small_part_stays_while_it_is_larger_than_the_error_and_goes_when_smaller() {
    // The box has 0.4% of the area: at a tenth of the triangles its share
    // is 1.3 triangles, too few to stay closed, and it used to vanish for
    // its planes' cost. It is 0.13 across and the sphere's chords at that
    // budget are off by about 0.01: it is worth its twelve triangles. At
    // 0.5% (15 triangles) the sphere is off by far more than the box's
    // size, and the box goes. (The old rule let every part below a
    // tetrahedron's share vanish for its planes' cost: the box went at
    // 10%.)
    let mesh = sphere_with_mirror();
    let parts = |r: f64| {
        let (out, report) = simplify_mesh(&mesh, &ratio(r)).unwrap();
        assert!(report.output_triangles <= report.target_triangles + 1);
        let reach = out.positions.iter().map(|p| p[0]).fold(f32::MIN, f32::max);
        (common::topo(&out).components, reach)
    };
    let (fine, reach) = parts(0.1);
    assert_eq!(fine, 2, "the box goes at 10%");
    assert!(
        reach > 1.15,
        "the box shrank to x = {reach} (1.2 in the input)"
    );
    assert_eq!(parts(0.005).0, 1, "the box stays at 0.5%");
}

/// A bumpy sphere standing on `legs` thin tubes of radius `r` and length
/// `len` (both relative to the sphere's radius), each of `along` rings of
/// 6 and closed at its foot by a fan to a vertex of the sphere's
/// underside, so the whole is one piece: a chair's seat on its wire legs.
fn body_on_legs(legs: usize, r: f32, len: f32, along: usize) -> Mesh {
    let mut m = bumpy_sphere(12);
    let radius = m
        .positions
        .iter()
        .map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt())
        .fold(0.0f32, f32::max);
    let (r, len) = (r * radius, len * radius);
    let mut faces = m.faces.clone();
    let around = 6usize;
    for l in 0..legs {
        // The vertex nearest a direction below the equator, spread around.
        let t = std::f32::consts::TAU * l as f32 / legs as f32;
        let dir = [0.6 * t.cos(), 0.6 * t.sin(), -0.8];
        let foot = (0..m.positions.len())
            .max_by(|&a, &b| {
                let d = |v: usize| {
                    let p = m.positions[v];
                    p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2]
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap_or(0);
        let f = m.positions[foot];
        let base = m.positions.len() as u32;
        for k in 0..=along {
            let z = f[2] - len * k as f32 / along as f32;
            for a in 0..around {
                let s = std::f32::consts::TAU * a as f32 / around as f32;
                m.positions
                    .push([f[0] + r * s.cos(), f[1] + r * s.sin(), z]);
            }
        }
        let tip = m.positions.len() as u32;
        m.positions.push([f[0], f[1], f[2] - len - 2.0 * r]);
        let ring = |k: usize, a: usize| base + (k * around + a % around) as u32;
        for k in 0..along {
            for a in 0..around {
                faces.push(&[ring(k, a), ring(k + 1, a + 1), ring(k, a + 1)]);
                faces.push(&[ring(k, a), ring(k + 1, a), ring(k + 1, a + 1)]);
            }
        }
        for a in 0..around {
            faces.push(&[ring(along, a), tip, ring(along, a + 1)]);
            faces.push(&[ring(0, a + 1), foot as u32, ring(0, a)]);
        }
    }
    Mesh::from_polygons(m.positions, faces)
}

/// Thin legs are kept until the rest of the model would move by about
/// half the pinch distance, not at any price: asked for 22 triangles, a
/// body on four wire legs keeps its shape and gives up parts of legs
/// (mean distance 0.0135 of the diagonal), where ranking every pinch last
/// crushes the body to keep whole wires (0.028; as `wild/chair_model`'s
/// seat at 1%). At a tenth the legs stay.
#[test]
fn thin_legs_give_way_before_the_body_folds_at_an_extreme_target() {
    use wildlod_eval::{compare, CompareOptions, EvalMesh};
    let mesh = body_on_legs(4, 0.02, 1.0, 60);
    assert_eq!(common::topo(&mesh).components, 1);
    let run = |r: f64, distance: f64| {
        let mut o = ratio(r);
        o.metric.pinch_distance = distance;
        let (out, report) = simplify_mesh(&mesh, &o).unwrap();
        assert!(report.output_triangles <= report.target_triangles + 1);
        out
    };
    let mean = |out: &Mesh| {
        compare(
            &EvalMesh::from_mesh(&mesh),
            &EvalMesh::from_mesh(out),
            &CompareOptions::default(),
        )
        .chamfer_mean
    };
    let capped = mean(&run(0.005, Metric::default().pinch_distance));
    let uncapped = mean(&run(0.005, 0.0));
    assert!(
        capped < 0.7 * uncapped,
        "mean distance {capped} with the cap, {uncapped} without"
    );
    // At a tenth the legs keep their length: some vertex near the feet.
    let z = |m: &Mesh| {
        let z = m.positions.iter().map(|p| p[2]);
        (
            z.clone().fold(f32::MAX, f32::min),
            z.fold(f32::MIN, f32::max),
        )
    };
    let (bottom, top) = z(&mesh);
    let lost = z(&run(0.1, Metric::default().pinch_distance)).0 - bottom;
    assert!(
        lost < 0.01 * (top - bottom),
        "the legs lost {lost} of the model's height {} at 10%",
        top - bottom
    );
}

/// The present faces rank collapses too (`Metric::current_face_weight`): on
/// a plate one voxel thick with staircase holes at 2%, memory quadrics alone
/// let the hole walls' top and bottom rims merge at mid-height (a rim
/// vertex holds its plane by its few input faces, not by the large
/// triangles it anchors by then). With the present faces' planes fewer
/// output vertices leave the plate's two planes, and the mean distance
/// drops.
#[test]
fn present_faces_keep_a_plates_hole_walls_from_pinching() {
    use wildlod_eval::{compare, CompareOptions, EvalMesh};
    let scene = wildlod_testkit::scenes::holed_voxel_plate();
    let run = |weight: f64| {
        let mut o = faces_target(scene.meshes[0].faces.len() / 25);
        o.metric.current_face_weight = weight;
        let (out, _) = wildlod_simplify::simplify_scene(&scene, &o).unwrap();
        let between = out.meshes[0]
            .positions
            .iter()
            .filter(|p| p[2] > 0.01 && p[2] < 0.99)
            .count();
        let images = vec![None; scene.textures.len()];
        let c = compare(
            &EvalMesh::from_scene(&scene, &images),
            &EvalMesh::from_scene(&out, &images),
            &CompareOptions {
                samples: 50_000,
                ..CompareOptions::default()
            },
        );
        (between, c.chamfer_mean)
    };
    let (memory_only, memory_chamfer) = run(0.0);
    let (present, present_chamfer) = run(1.0);
    eprintln!(
        "mid-height vertices {memory_only} → {present}, Chamfer {memory_chamfer:e} → {present_chamfer:e}"
    );
    assert!(present < memory_only, "{present} vs {memory_only}");
    assert!(present_chamfer < memory_chamfer);
}
