//! `wildlod simplify` on whole files: one budget for every mesh of a file
//! (W §1, Fig. 1), `--per-mesh` for the old behaviour, and wild input
//! (two-vertex faces, OFF) accepted.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::path::Path;
use support::{s, wildlod};

use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Mesh, Node, Scene, IDENTITY};
use wildlod_simplify::{simplify_mesh, Options, Target};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A closed sphere with every vertex pushed in or out a little (no ties).
fn bumpy_sphere(n: usize, name: &str) -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_sphere(n));
    for (k, p) in m.positions.iter_mut().enumerate() {
        let h = ((k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as f32 / (1u64 << 24) as f32;
        let f = 1.0 + 0.05 * (h - 0.5);
        *p = p.map(|c| c * f);
    }
    m.name = name.into();
    m
}

fn placed(t: [f32; 3], scale: f32) -> [f32; 16] {
    let mut m = IDENTITY;
    for k in 0..3 {
        m[5 * k] = scale;
        m[12 + k] = t[k];
    }
    m
}

/// A big sphere, a box touching it, and a tiny sphere far away, each its
/// own mesh under its own node, written as GLB.
fn three_part_glb(path: &Path) -> Scene {
    let big = bumpy_sphere(12, "big");
    let mut plate = shapes::triangulate(&shapes::box_grid([0.98, -0.5, -0.5], [1.5, 0.5, 0.5], 6));
    plate.name = "plate".into();
    let tiny = bumpy_sphere(8, "tiny");
    let scene = Scene {
        meshes: vec![big, plate, tiny],
        nodes: [IDENTITY, IDENTITY, placed([20.0, 0.0, 0.0], 0.002)]
            .iter()
            .enumerate()
            .map(|(m, &matrix)| Node {
                name: format!("node{m}"),
                mesh: Some(m as u32),
                matrix,
                ..Node::default()
            })
            .collect(),
        roots: vec![0, 1, 2],
        ..Scene::default()
    };
    wildlod_io::write(
        &Document::from_scene(scene.clone()),
        path,
        &WriteOptions::default(),
    )
    .unwrap();
    scene
}

fn mesh_named<'a>(scene: &'a Scene, name: &str) -> Option<&'a Mesh> {
    scene.meshes.iter().find(|m| m.name == name)
}

fn hausdorff(reference: &Mesh, candidate: &Mesh) -> f64 {
    compare(
        &EvalMesh::from_mesh(reference),
        &EvalMesh::from_mesh(candidate),
        &CompareOptions {
            samples: 20_000,
            ..CompareOptions::default()
        },
    )
    .hausdorff
}

#[test]
fn touching_meshes_in_one_gltf_share_one_budget_and_a_tiny_far_part_goes_first() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("scene.glb");
    let scene = three_part_glb(&input);
    let total_in: usize = scene.meshes.iter().map(Mesh::triangle_count).sum();
    let target = (total_in as f64 * 0.2).round() as usize;

    let out = dir.path().join("lod.glb");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out), "--ratio", "0.2"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let line = text(&o.stdout);
    assert!(line.contains("under one budget, world error "), "{line}");
    assert!(
        line.contains("1 mesh removed (every triangle went): tiny"),
        "{line}"
    );
    let lod = wildlod_io::read(&out).unwrap().scene;
    let total: usize = lod.meshes.iter().map(Mesh::triangle_count).sum();
    assert!(
        total.abs_diff(target) <= 1,
        "{total} triangles for {target}"
    );
    // The tiny part is gone from the file: no empty mesh, no node showing
    // one.
    assert!(mesh_named(&lod, "tiny").is_none());
    assert_eq!(lod.meshes.len(), 2);
    for n in &lod.nodes {
        if let Some(m) = n.mesh {
            assert!(!lod.meshes[m as usize].faces.is_empty(), "{}", n.name);
        }
    }
    // The big part keeps more detail than the old per-mesh run gives it.
    let per = dir.path().join("per_mesh.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&per),
        "--ratio",
        "0.2",
        "--per-mesh",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let per = wildlod_io::read(&per).unwrap().scene;
    let big_in = &scene.meshes[0];
    let (big_scene, big_alone) = (
        mesh_named(&lod, "big").unwrap(),
        mesh_named(&per, "big").unwrap(),
    );
    assert!(
        big_scene.triangle_count() > big_alone.triangle_count(),
        "big part: {} triangles in the scene run, {} per mesh",
        big_scene.triangle_count(),
        big_alone.triangle_count()
    );
    let (e_scene, e_alone) = (hausdorff(big_in, big_scene), hausdorff(big_in, big_alone));
    assert!(
        e_scene < e_alone,
        "big part Hausdorff {e_scene} in the scene run vs {e_alone} per mesh"
    );
}

#[test]
fn per_mesh_reproduces_simplifying_every_mesh_alone() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("scene.glb");
    let scene = three_part_glb(&input);
    let out = dir.path().join("lod.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.2",
        "--per-mesh",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // One line per mesh, as before.
    let stdout = text(&o.stdout);
    assert_eq!(stdout.lines().count(), 3, "{stdout}");
    let lod = wildlod_io::read(&out).unwrap().scene;
    assert_eq!(lod.meshes.len(), 3);
    for (m, input) in scene.meshes.iter().enumerate() {
        let options = Options {
            target: Target {
                ratio: Some(0.2),
                triangles: Some(1),
                error: None,
            },
            ..Options::default()
        };
        let (alone, _) = simplify_mesh(input, &options).unwrap();
        assert_eq!(
            lod.meshes[m].triangle_count(),
            alone.triangle_count(),
            "mesh {m}"
        );
    }
}

#[test]
fn two_vertex_obj_faces_warn_once_and_the_file_simplifies() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("wild.obj");
    let mut m = bumpy_sphere(6, "s");
    m.name = String::new();
    wildlod_io::write(
        &Document::from_scene(Scene::from_mesh(m.clone())),
        &input,
        &WriteOptions::default(),
    )
    .unwrap();
    // What scene exports carry: two-vertex faces, a face of one repeated
    // vertex, lines and points.
    let mut obj = std::fs::read_to_string(&input).unwrap();
    obj.push_str("f 1 2\nf 3 3 3\nl 1 2 3\np 4\nf 5 6\n");
    std::fs::write(&input, obj).unwrap();
    let out = dir.path().join("lod.obj");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out), "--ratio", "0.5"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert_eq!(
        err.matches("skipped 3 faces with fewer than 3 distinct vertices")
            .count(),
        1,
        "{err}"
    );
    let t = wildlod_io::read(&out).unwrap().scene.meshes[0].triangle_count();
    assert!(t.abs_diff(m.triangle_count() / 2) <= 1, "{t}");
}

#[test]
fn off_files_simplify_to_off() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.off");
    let m = bumpy_sphere(8, "sphere");
    wildlod_io::write(
        &Document::from_scene(Scene::from_mesh(m.clone())),
        &input,
        &WriteOptions::default(),
    )
    .unwrap();
    let out = dir.path().join("lod.off");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out), "--ratio", "0.25"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let head = std::fs::read_to_string(&out).unwrap();
    assert!(head.starts_with("OFF\n"), "{}", &head[..20.min(head.len())]);
    let t = wildlod_io::read(&out).unwrap().scene.meshes[0].triangle_count();
    assert!(t.abs_diff(m.triangle_count() / 4) <= 1, "{t}");
}

#[test]
fn faces_budget_counts_a_mesh_once_per_node_that_shows_it() {
    // One sphere shown by three nodes beside another shown once: the file
    // draws four spheres. `--faces 800` is met by what a renderer draws,
    // in the whole-file budget and with `--per-mesh`, and `--json` says so.
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("instanced.glb");
    let sphere = bumpy_sphere(10, "a");
    let per = sphere.triangle_count();
    let scene = Scene {
        meshes: vec![sphere.clone(), bumpy_sphere(10, "b")],
        nodes: [(0, 0.0), (0, 5.0), (0, 10.0), (1, 15.0)]
            .iter()
            .map(|&(m, x)| Node {
                mesh: Some(m),
                matrix: placed([x, 0.0, 0.0], 1.0),
                ..Node::default()
            })
            .collect(),
        roots: vec![0, 1, 2, 3],
        ..Scene::default()
    };
    wildlod_io::write(
        &Document::from_scene(scene),
        &input,
        &WriteOptions::default(),
    )
    .unwrap();
    for extra in [None, Some("--per-mesh")] {
        let out = dir.path().join("lod.glb");
        let mut args = vec!["simplify", s(&input), "-o", s(&out), "--faces", "800"];
        args.extend(extra);
        args.extend(["--json", "--overwrite"]);
        let o = wildlod(&args);
        assert!(o.status.success(), "{extra:?}: {}", text(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(j["input_triangles"], 4 * per, "{extra:?}");
        let lod = wildlod_io::read(&out).unwrap().scene;
        let drawn = 3 * lod.meshes[0].triangle_count() + lod.meshes[1].triangle_count();
        assert_eq!(j["output_triangles"], drawn, "{extra:?}");
        assert!(
            (780..=800).contains(&drawn),
            "{extra:?}: draws {drawn} for --faces 800"
        );
    }
}
