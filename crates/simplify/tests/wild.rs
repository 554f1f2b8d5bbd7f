//! W §4.1.1 and §4.2 on wild inputs built in code.
#![allow(clippy::unwrap_used)] // test helpers, not library code

mod common;

use common::{grid_box, ratio, soup, topo};
use wildlod_mesh::shapes;
use wildlod_simplify::{simplify_mesh, Options};

#[test]
fn touching_boxes_merge_through_virtual_edge() {
    // Box B rests against box A's +x side; they share no vertex (B's side
    // is smaller and offset, so no positions coincide).
    let a = grid_box([0.0; 3], [1.0; 3], 6);
    let b = grid_box([1.0, 0.13, 0.17], [1.6, 0.83, 0.87], 6);
    let both = shapes::merge(&[a, b]);
    assert_eq!(topo(&both).components, 2);
    let options = ratio(0.01);
    let (out, rep) = simplify_mesh(&both, &options).unwrap();
    assert!(rep.virtual_edges > 0);
    assert_eq!(topo(&out).components, 1, "{rep:?}");
    assert!(out.triangle_count().abs_diff(rep.target_triangles) <= 1);
    // Without virtual edges the parts cannot merge.
    let apart = Options {
        virtual_edge_radius: 0.0,
        ..options
    };
    let (out, _) = simplify_mesh(&both, &apart).unwrap();
    assert_eq!(topo(&out).components, 2);
}

#[test]
fn soup_merges_into_fewer_components_with_virtual_edges() {
    // 100 triangles in a grid 0.5 apart (spacing 1.5, size 1): with r large
    // enough to bridge the gaps, collapses join them.
    let mesh = soup(100);
    let options = Options {
        virtual_edge_radius: 0.02,
        ..ratio(0.2)
    };
    let (out, rep) = simplify_mesh(&mesh, &options).unwrap();
    assert!(rep.virtual_edges > 0);
    assert!(out.triangle_count().abs_diff(20) <= 1);
    assert!(topo(&out).components < 20);
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
    let (classic, _) = simplify_mesh(
        &both,
        &Options {
            target: ratio(0.05).target,
            ..Options::classic_qem()
        },
    )
    .unwrap();
    let (aw, ac) = (area(&wild) / before, area(&classic) / before);
    assert!(aw > 0.9, "the wild metric kept {aw:.3} of the panel");
    assert!(
        aw > ac,
        "wild {aw:.3} should keep more panel than classic {ac:.3}"
    );
}
