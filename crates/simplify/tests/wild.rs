//! W §4.1.1 and §4.2 on wild inputs built in code.
#![allow(clippy::unwrap_used)] // test helpers, not library code

mod common;

use common::{grid_box, ratio, topo};
use wildlod_mesh::shapes;
use wildlod_simplify::{simplify_mesh, Options};

#[test]
fn touching_boxes_merge_through_virtual_edge() {
    // Box B rests against box A's +x side; they share no vertex (B's side
    // is smaller and offset, so no positions coincide, and the nearest
    // vertices are far apart: W Fig. 15's case).
    let a = grid_box([0.0; 3], [1.0; 3], 6);
    let b = grid_box([1.0, 0.13, 0.17], [1.6, 0.83, 0.87], 6);
    let both = shapes::merge(&[a, b]);
    assert_eq!(topo(&both).components, 2);
    // Aggressive: four triangles for two boxes. (The gluing term makes
    // parts merge only once collapsing them separately costs more, so the
    // merge comes late; see `Metric::gluing_weight`.)
    let options = ratio(0.005);
    let (out, rep) = simplify_mesh(&both, &options).unwrap();
    assert!(rep.virtual_edges > 0);
    assert_eq!(topo(&out).components, 1, "{rep:?}");
    assert!(out.triangle_count().abs_diff(rep.target_triangles) <= 1);
    // Without virtual edges the parts cannot merge: no output vertex takes
    // input vertices from both boxes (a box may vanish instead).
    let split = both.positions.len() / 2; // box A's vertices come first
    for r in [0.05, 0.01, 0.005] {
        let mut apart = ratio(r);
        apart.guards.virtual_edge_radius = 0.0;
        let s = wildlod_simplify::simplify_polygons(&both.positions, &both.faces, &apart).unwrap();
        let mut owner = vec![None; s.positions.len()];
        for (v, &o) in s.vertex_map.iter().enumerate() {
            if o == u32::MAX {
                continue;
            }
            let side = v < split;
            let slot = &mut owner[o as usize];
            assert!(slot.is_none_or(|x| x == side), "ratio {r}: boxes merged");
            *slot = Some(side);
        }
    }
}

#[test]
fn nearly_welded_soup_becomes_one_piece() {
    // A triangulated grid whose triangles were exported unwelded, every
    // corner nudged by a different amount below 4e-5 (float noise): 128
    // components to the welder, one surface to the eye. Virtual edges join
    // them at almost no gluing cost.
    let grid = shapes::triangulate(&shapes::quad_grid(8, 8));
    let mut positions = Vec::new();
    let mut idx = Vec::new();
    for (t, f) in grid.faces.iter().enumerate() {
        for (k, &v) in f.iter().enumerate() {
            let p = grid.positions[v as usize];
            let jitter = 1e-7 * (t * 3 + k + 1) as f32;
            positions.push([p[0] + jitter, p[1] - jitter, jitter]);
            idx.push(idx.len() as u32);
        }
    }
    let soup = wildlod_mesh::Mesh::from_triangles(positions, &idx);
    assert_eq!(topo(&soup).components, 128);
    let (out, rep) = simplify_mesh(&soup, &ratio(0.25)).unwrap();
    assert!(out.triangle_count().abs_diff(32) <= 1);
    assert_eq!(topo(&out).components, 1, "{rep:?}");
    // The flat sheet stays flat and covers the square.
    for p in &out.positions {
        assert!(p[2].abs() < 1e-4);
    }
}

#[test]
fn area_term_keeps_a_flat_panel_that_plain_qem_eats() {
    // W Fig. 9: a large thin flat panel (an open sheet) next to a curved
    // closed part. Plane quadrics see no error in shrinking the flat sheet;
    // the boundary area term does.
    let mut sheet = shapes::quad_grid(12, 12);
    for p in &mut sheet.positions {
        p[0] = p[0] * 3.0 - 1.5;
        p[1] = p[1] * 3.0 - 1.5;
        p[2] = -1.2;
    }
    let ball = shapes::triangulate(&shapes::quad_sphere(12));
    let both = shapes::merge(&[sheet, ball]);
    let area = |m: &wildlod_mesh::Mesh| -> f64 {
        // Area of faces at the sheet's height.
        m.faces
            .iter()
            .filter(|f| {
                f.iter()
                    .all(|&v| (m.positions[v as usize][2] + 1.2).abs() < 1e-3)
            })
            .map(|f| {
                let p: Vec<glam::DVec3> = f
                    .iter()
                    .map(|&v| glam::DVec3::from(m.positions[v as usize].map(f64::from)))
                    .collect();
                (1..p.len() - 1)
                    .map(|k| 0.5 * (p[k] - p[0]).cross(p[k + 1] - p[0]).length())
                    .sum::<f64>()
            })
            .sum()
    };
    let before = area(&both);
    let (wild, _) = simplify_mesh(&both, &ratio(0.05)).unwrap();
    // Plain QEM: classic without Garland–Heckbert's border planes, which
    // would keep the panel too (checked below).
    let plain = |border_weight: f64| {
        let mut o = Options {
            target: ratio(0.05).target,
            ..Options::classic_qem()
        };
        o.metric.border_weight = border_weight;
        simplify_mesh(&both, &o).unwrap().0
    };
    let classic = plain(0.0);
    let (aw, ac) = (area(&wild) / before, area(&classic) / before);
    assert!(aw > 0.9, "the wild metric kept {aw:.3} of the panel");
    assert!(
        aw > ac,
        "wild {aw:.3} should keep more panel than plain QEM {ac:.3}"
    );
    // Classic QEM as Garland & Heckbert wrote it (and as meshoptimizer and
    // Blender run it) has border planes: they keep the panel on their own.
    let ab = area(&plain(Options::classic_qem().metric.border_weight)) / before;
    assert!(ab > 0.9, "border planes kept {ab:.3} of the panel");
}

#[test]
fn two_lone_quads_at_one_vertex_each_keep_a_face_at_half() {
    use wildlod_mesh::{Faces, Mesh};
    // Two unit-free quads touching only at the origin (a non-manifold
    // vertex), as quads: four triangles, two to keep. Halving each quad
    // costs exactly what deleting one does, and in quad mode the deleted
    // quad's second side is the next of its chord; a part must still not
    // vanish while a collapse of equal cost only shrinks another.
    let positions = vec![
        [-2.0, 0.0, 2.0],
        [0.0, 0.0, 2.0],
        [-2.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, -2.0],
        [2.0, 0.0, -2.0],
    ];
    let mut faces = Faces::new();
    faces.push(&[0, 1, 3, 2]);
    faces.push(&[3, 4, 6, 5]);
    let mesh = Mesh::from_polygons(positions, faces);
    for quad_mode in [
        wildlod_simplify::QuadMode::default(),
        wildlod_simplify::QuadMode::Never,
    ] {
        let mut options = ratio(0.5);
        options.quad.mode = quad_mode;
        let (out, rep) = simplify_mesh(&mesh, &options).unwrap();
        assert_eq!(out.triangle_count(), 2, "{quad_mode:?}: {rep:?}");
        // Each quad keeps a face: some output face has its centroid on
        // each side of the x = 0 plane.
        let side = |f: usize| {
            let c = out.faces.face(f);
            c.iter()
                .map(|&v| out.positions[v as usize][0])
                .sum::<f32>()
                .signum()
        };
        let sides: Vec<f32> = (0..out.faces.len()).map(side).collect();
        assert!(
            sides.contains(&-1.0) && sides.contains(&1.0),
            "{quad_mode:?}: a quad vanished, faces on sides {sides:?}"
        );
    }
}

#[test]
fn a_grid_line_split_by_rounding_noise_does_not_open_into_a_crack() {
    // A wavy 4 × 2.4 sheet of 40 × 24 quads. Its height crosses zero
    // along y = 1.2, where a generator computing sin(π) per quad leaves
    // the quads below the line their own copies of two vertices in three
    // on it, at z = +1e-17, and those above theirs at -1e-17 (the third
    // comes out 0 on both sides). One surface to the eye; to an exact
    // welder one part with slits along the line, and no virtual edge
    // bridges a part to itself. Simplified, the slits opened into a crack
    // with sideways slivers.
    let (nx, ny, line) = (40usize, 24usize, 12usize);
    let height = |i: usize, j: usize| -> f32 {
        let (x, y) = (i as f32 * 0.1, j as f32 * 0.1);
        let wave = 0.05 * (std::f32::consts::TAU * x / 4.0 + 0.5).sin();
        let ripple = 0.006 * (std::f32::consts::TAU * x / 1.1).sin();
        (wave + ripple) * (std::f32::consts::TAU * y / 2.4).sin()
    };
    let mut positions = Vec::new();
    let mut quads = wildlod_mesh::Faces::new();
    let mut vertex = |i: usize, j: usize, below: bool| -> u32 {
        let z = match (j == line && i % 3 != 0, below) {
            (true, true) => 1e-17,
            (true, false) => -1e-17,
            _ => height(i, j),
        };
        positions.push([i as f32 * 0.1, j as f32 * 0.1, z]);
        positions.len() as u32 - 1
    };
    for j in 0..ny {
        for i in 0..nx {
            let below = j < line;
            let q = [
                vertex(i, j, below),
                vertex(i + 1, j, below),
                vertex(i + 1, j + 1, below),
                vertex(i, j + 1, below),
            ];
            quads.push(&q);
        }
    }
    let sheet = wildlod_mesh::Mesh::from_polygons(positions, quads);
    // The exact welder sees the slits: both sides of the 40 edges along
    // the line are border edges, besides the rim's 2 × (40 + 24), and the
    // sheet is still one part.
    assert_eq!(topo(&sheet).boundary_edges, 2 * (nx + ny) + 2 * nx);
    assert_eq!(topo(&sheet).components, 1);
    let (out, rep) = simplify_mesh(&sheet, &ratio(0.1)).unwrap();
    let t = topo(&out);
    assert_eq!(t.components, 1, "{rep:?}");
    // Every border edge of the output lies along the sheet's rim (whose
    // vertices the wave lets slide by a fraction of a millimetre).
    let on_rim = |p: [f32; 3]| {
        let d = p[0]
            .abs()
            .min((p[0] - 4.0).abs())
            .min(p[1].abs())
            .min((p[1] - 2.4).abs());
        d < 0.01
    };
    let (weld, _) = wildlod_mesh::weld::weld_positions(&out.positions);
    let mut uses = std::collections::HashMap::new();
    for f in out.faces.iter() {
        for k in 0..f.len() {
            let (a, b) = (weld[f[k] as usize], weld[f[(k + 1) % f.len()] as usize]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let rep_of = |w: u32| out.positions[weld.iter().position(|&x| x == w).unwrap()];
    let inner: Vec<_> = uses
        .iter()
        .filter(|&(&(a, b), &n)| n == 1 && !(on_rim(rep_of(a)) && on_rim(rep_of(b))))
        .map(|(&(a, b), _)| (rep_of(a), rep_of(b)))
        .collect();
    assert!(
        inner.is_empty(),
        "{} border edges inside the sheet: {:?}",
        inner.len(),
        &inner[..inner.len().min(3)]
    );
    // And no face stands sideways out of a sheet that tilts by at most 10°.
    for f in out.faces.iter() {
        let p = [0, 1, 2].map(|k| glam::Vec3::from(out.positions[f[k] as usize]));
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        assert!(n.z.abs() > 0.9, "a face with normal {n}");
    }
}
