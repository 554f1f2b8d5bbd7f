//! Parts no one can see (`Guards::drop_enclosed_parts`): a part wholly
//! inside a closed, outward, opaque part goes before simplifying and its
//! budget buys visible detail; a part that can be seen stays. Every mesh
//! is generated here.
#![allow(clippy::unwrap_used)] // test helpers, not library code

mod common;

use common::bumpy_sphere;
use wildlod_mesh::{shapes, Faces, Mesh};
use wildlod_simplify::{simplify_mesh, Options, Report, Target};

/// `m` scaled by `s` about the origin, then moved by `t`.
fn placed(m: &Mesh, s: f32, t: [f32; 3]) -> Mesh {
    let mut out = m.clone();
    for p in &mut out.positions {
        *p = [0, 1, 2].map(|a| p[a] * s + t[a]);
    }
    out
}

/// `m` with every face reversed: the same surface facing the other way.
fn reversed(m: &Mesh) -> Mesh {
    let mut faces = Faces::new();
    for f in m.faces.iter() {
        let mut g = f.to_vec();
        g.reverse();
        faces.push(&g);
    }
    Mesh::from_polygons(m.positions.clone(), faces)
}

/// `m` without its first `k` faces: a hole.
fn holed(m: &Mesh, k: usize) -> Mesh {
    let mut faces = Faces::new();
    for f in m.faces.iter().skip(k) {
        faces.push(f);
    }
    Mesh::from_polygons(m.positions.clone(), faces)
}

/// Parts of `m` (faces joined by shared positions) and the triangles of
/// the largest.
fn parts(m: &Mesh) -> (usize, usize) {
    let n = m.positions.len();
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut v: usize) -> usize {
        while root[v] != v {
            root[v] = root[root[v]];
            v = root[v];
        }
        v
    }
    // Positions, not indices: the output may write a vertex per corner.
    let mut by_position = std::collections::HashMap::new();
    for (v, p) in m.positions.iter().enumerate() {
        let first = *by_position.entry(p.map(f32::to_bits)).or_insert(v);
        let (a, b) = (find(&mut root, v), find(&mut root, first));
        root[a] = b;
    }
    for f in m.faces.iter() {
        for w in f.windows(2) {
            let (a, b) = (
                find(&mut root, w[0] as usize),
                find(&mut root, w[1] as usize),
            );
            root[a] = b;
        }
    }
    let mut triangles = std::collections::HashMap::new();
    for f in m.faces.iter() {
        *triangles
            .entry(find(&mut root, f[0] as usize))
            .or_insert(0usize) += f.len() - 2;
    }
    (
        triangles.len(),
        triangles.values().copied().max().unwrap_or(0),
    )
}

/// A closed L-shaped prism facing out: the square [-1, 1]² without its
/// corner [0, 1]², from z = -1 to 1. Its box holds the notch, which is
/// outside it.
fn l_prism() -> Mesh {
    let l = [
        [-1.0, -1.0],
        [1.0, -1.0],
        [1.0, 0.0],
        [0.0, 0.0],
        [0.0, 1.0],
        [-1.0, 1.0],
    ];
    let mut positions: Vec<[f32; 3]> = l.iter().map(|q| [q[0], q[1], -1.0]).collect();
    positions.extend(l.iter().map(|q| [q[0], q[1], 1.0]));
    let mut faces = Faces::new();
    faces.push(&[5, 4, 3, 2, 1, 0]);
    faces.push(&[6, 7, 8, 9, 10, 11]);
    for i in 0..6u32 {
        let j = (i + 1) % 6;
        faces.push(&[i, j, j + 6, i + 6]);
    }
    Mesh::from_polygons(positions, faces)
}

fn to(triangles: usize) -> Options {
    Options {
        target: Target {
            triangles: Some(triangles),
            ..Target::default()
        },
        ..Options::default()
    }
}

fn run(m: &Mesh, options: &Options) -> (Mesh, Report) {
    simplify_mesh(m, options).unwrap()
}

/// A bumpy sphere of radius about 1, facing out, closed.
fn shell() -> Mesh {
    bumpy_sphere(12)
}

#[test]
fn a_part_wholly_inside_a_closed_part_goes_and_its_budget_buys_detail() {
    let outer = shell();
    let inner = placed(&bumpy_sphere(8), 0.3, [0.2, -0.1, 0.1]);
    let both = shapes::merge(&[outer.clone(), inner.clone()]);
    let target = outer.triangle_count() / 5;
    let (out, report) = run(&both, &to(target));
    assert_eq!(report.enclosed_parts, 1);
    let (count, largest) = parts(&out);
    assert_eq!(count, 1, "only the enclosure is left");
    // Kept, the inner part takes triangles the enclosure then lacks.
    let mut keep = to(target);
    keep.guards.drop_enclosed_parts = false;
    let (kept, report) = run(&both, &keep);
    assert_eq!(report.enclosed_parts, 0);
    let (count_kept, largest_kept) = parts(&kept);
    assert_eq!(count_kept, 2);
    assert!(
        largest > largest_kept,
        "enclosure {largest} triangles with the drop, {largest_kept} without"
    );
    // In the solid part of an L, with its notch in the box: goes.
    let l = shapes::merge(&[
        l_prism(),
        shapes::cuboid([-0.6, -0.6, -0.1], [-0.4, -0.4, 0.1]),
    ]);
    let (_, report) = run(&l, &to(l.triangle_count()));
    assert_eq!(report.enclosed_parts, 1);
    // A part inside a part inside the enclosure goes too.
    let nested = shapes::merge(&[
        outer,
        inner,
        placed(&bumpy_sphere(4), 0.05, [0.2, -0.1, 0.1]),
    ]);
    let (_, report) = run(&nested, &to(target));
    assert_eq!(report.enclosed_parts, 2);
}

#[test]
fn parts_that_can_be_seen_stay() {
    let outer = shell();
    let inner = placed(&bumpy_sphere(8), 0.3, [0.2, -0.1, 0.1]);
    let target = outer.triangle_count() / 5;
    let stays = |what: &str, m: &Mesh, options: &Options| {
        let (out, report) = run(m, options);
        assert_eq!(report.enclosed_parts, 0, "{what}");
        assert_eq!(parts(&out).0, 2, "{what}");
    };
    // Poking out through the enclosure.
    let poking = placed(&bumpy_sphere(8), 0.3, [0.9, 0.0, 0.0]);
    stays(
        "poking out",
        &shapes::merge(&[outer.clone(), poking]),
        &to(target),
    );
    // Seen through an opening.
    stays(
        "behind an opening",
        &shapes::merge(&[holed(&outer, 12), inner.clone()]),
        &to(target),
    );
    // Inside a surface that faces in: a room modelled from the inside.
    stays(
        "in a room",
        &shapes::merge(&[reversed(&outer), inner.clone()]),
        &to(target),
    );
    // In an L's notch, inside its box but outside it; and across the
    // notch's wall, one corner inside it.
    let l = l_prism();
    for (what, lo, hi) in [
        ("in the notch", [0.4, 0.4, -0.1], [0.6, 0.6, 0.1]),
        ("across a wall", [-0.1, 0.3, -0.1], [0.1, 0.5, 0.1]),
    ] {
        let m = shapes::merge(&[l.clone(), shapes::cuboid(lo, hi)]);
        stays(what, &m, &to(m.triangle_count()));
    }
    // Resting on the enclosure's inner wall: a box on the floor of a box.
    // (Nothing to simplify: touching parts may merge when they are.)
    let room = shapes::cuboid([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]);
    let crate_on_floor = shapes::cuboid([-0.2, -1.0, -0.2], [0.2, -0.6, 0.2]);
    let floor = shapes::merge(&[room, crate_on_floor]);
    stays("resting on the floor", &floor, &to(floor.triangle_count()));
    let both = shapes::merge(&[outer.clone(), inner.clone()]);
    // Behind a blended (seen-through) enclosure.
    let mut see_through = to(target);
    see_through.data.see_through_faces = vec![true; both.faces.len()];
    stays("seen through", &both, &see_through);
    // Posed: a morph target may move it out.
    let mut morphed = to(target);
    morphed.data.morph_targets = vec![vec![[0.0; 3]; both.positions.len()]];
    stays("morphed", &both, &morphed);
    // Asked to keep it.
    let mut keep = to(target);
    keep.guards.drop_enclosed_parts = false;
    stays("kept by the option", &both, &keep);
}

/// A file's enclosures hide only what no material or motion can show:
/// two-sided, alpha-tested and blended materials, skins and morph targets
/// all keep the parts inside, through the whole-file path too.
#[test]
fn a_file_whose_enclosure_may_show_keeps_its_parts() {
    use wildlod_mesh::{AlphaMode, Material, Scene};
    use wildlod_simplify::{enclosures_hide, simplify_scene};
    let outer = shell();
    let inner = placed(&bumpy_sphere(8), 0.3, [0.2, -0.1, 0.1]);
    let mut scene = Scene::default();
    scene.meshes.push(shapes::merge(&[outer.clone(), inner]));
    scene.materials.push(Material::default());
    let options = to(outer.triangle_count() / 5);
    assert!(enclosures_hide(&scene));
    let (_, report) = simplify_scene(&scene, &options).unwrap();
    let enclosed: usize = report.groups.iter().map(|g| g.report.enclosed_parts).sum();
    assert_eq!(enclosed, 1);
    let showing = [
        Material {
            double_sided: true,
            ..Material::default()
        },
        Material {
            alpha_mode: AlphaMode::Mask,
            ..Material::default()
        },
        Material {
            alpha_mode: AlphaMode::Blend,
            ..Material::default()
        },
    ];
    for m in showing {
        let mut s = scene.clone();
        s.materials[0] = m.clone();
        assert!(!enclosures_hide(&s), "{m:?}");
        let (_, report) = simplify_scene(&s, &options).unwrap();
        let enclosed: usize = report.groups.iter().map(|g| g.report.enclosed_parts).sum();
        assert_eq!(enclosed, 0, "{m:?}");
    }
}
