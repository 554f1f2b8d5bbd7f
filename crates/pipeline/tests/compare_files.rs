//! `compare_files` as `wildlod compare --json` reports it: the sampling
//! floors and the outliers are in the JSON.

use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{Faces, Mesh, Scene};
use wildlod_pipeline::{compare_files, CompareFilesOptions};
use wildlod_testkit::corpus;

fn options() -> CompareFilesOptions {
    CompareFilesOptions {
        samples: 5_000,
        ..CompareFilesOptions::default()
    }
}

#[test]
fn a_textured_file_against_itself_reports_texture_chamfer_at_its_floor() {
    let Some(root) = corpus("a_textured_file_against_itself_reports_texture_chamfer_at_its_floor")
    else {
        return;
    };
    let truck = root.join("textured/CesiumMilkTruck.glb");
    let json = compare_files(&truck, &truck, &options())
        .unwrap()
        .to_json()
        .unwrap();
    assert_eq!(json["texture_samples"], 40_000);
    let (t, floor) = (
        json["texture_chamfer"].as_f64().unwrap(),
        json["texture_chamfer_floor"].as_f64().unwrap(),
    );
    // Not 0 (each side draws its own samples), and at the floor: over 8
    // seeds the truck's self-comparison lay within 3.6% of its floor.
    assert!(floor > 0.01, "{json}");
    assert!((t - floor).abs() <= 0.15 * floor, "{t} against {floor}");
    for key in ["normal_chamfer_floor", "shading_normal_chamfer_floor"] {
        assert!(json[key].as_f64().is_some(), "{key}");
    }
}

#[test]
fn a_file_with_a_far_vertex_names_it_in_the_json() {
    // A 9 × 9 grid of the unit square, vertex 40 (the middle) at z = −1e30.
    let n = 9;
    let mut positions: Vec<[f32; 3]> = (0..n * n)
        .map(|i| [(i % n) as f32 / 8.0, (i / n) as f32 / 8.0, 0.0])
        .collect();
    positions[40][2] = -1e30;
    let mut idx = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = (j * n + i) as u32;
            idx.extend([
                v,
                v + 1,
                v + n as u32 + 1,
                v,
                v + n as u32 + 1,
                v + n as u32,
            ]);
        }
    }
    let mesh = Mesh::from_polygons(positions, Faces::from_triangles(&idx));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("spike.obj");
    wildlod_io::write(
        &Document::from_scene(Scene::from_mesh(mesh)),
        &path,
        &WriteOptions::default(),
    )
    .unwrap();
    let json = compare_files(&path, &path, &options())
        .unwrap()
        .to_json()
        .unwrap();
    assert_eq!(json["outliers_reference"], 1);
    assert_eq!(json["outlier_triangles_reference"], 6);
    let named = &json["outlier_vertices"][0];
    assert_eq!(
        (named["mesh"].as_u64(), named["vertex"].as_u64()),
        (Some(0), Some(40))
    );
    assert_eq!(named["position"][2].as_f64(), Some(f64::from(-1e30f32)));
    // The unit is the unit square's diagonal, not 1e30.
    let d = json["diagonal"].as_f64().unwrap();
    assert!((d - 2f64.sqrt()).abs() < 1e-9, "{d}");
    assert!(json["diagonal_with_outliers"].as_f64().unwrap() > 1e29);
    assert_eq!(json["hausdorff"].as_f64(), Some(0.0));
}
