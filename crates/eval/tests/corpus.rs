//! `compare` on the real-mesh corpus: every file against itself is 0 apart
//! in distance and at the sampling floor in the paired metrics, no file has
//! outliers, and against a copy shifted by a known amount it is at most
//! that far.

use std::time::Instant;

use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::{Image, Scene};
use wildlod_testkit::{corpus, mesh_files, short};

fn images(scene: &Scene) -> Vec<Option<Image>> {
    scene
        .textures
        .iter()
        .map(|t| wildlod_io::decode_image(&t.source).ok())
        .collect()
}

/// The scene with every root moved by `dx` along x.
fn shifted(scene: &Scene, dx: f32) -> Scene {
    let mut s = scene.clone();
    for &r in &s.roots.clone() {
        if let Some(n) = s.nodes.get_mut(r as usize) {
            // Left-multiplying by a translation adds to the last column.
            n.matrix[12] += dx * n.matrix[15];
        }
    }
    s
}

/// How far a self-comparison's paired metric may lie from its floor: both
/// are estimates from 40k samples per side. Over 8 seeds on the textured
/// corpus files the texture Chamfer distance of a file against itself lay
/// within 7.7% of the floor (bob, whose texture is flat fields with sharp
/// lines), the normal Chamfer distance within 3.4%; the floor's standard
/// deviation was at most 3.3%.
const FLOOR_TOLERANCE: f64 = 0.15;

/// A flat surface has a normal floor of exactly 0, and then so must the
/// value be.
fn at_floor(value: Option<f64>, floor: Option<f64>) -> bool {
    match (value, floor) {
        (Some(v), Some(f)) => (v - f).abs() <= FLOOR_TOLERANCE * f,
        _ => false,
    }
}

#[test]
fn corpus_meshes_are_zero_from_themselves_and_at_most_a_shift_from_a_shifted_copy() {
    let Some(root) = corpus("corpus_meshes_are_zero_from_themselves") else {
        return;
    };
    let options = CompareOptions {
        samples: 20_000,
        texture_samples: 40_000,
        ..CompareOptions::default()
    };
    for category in ["textured", "quad", "wild", "large"] {
        for path in mesh_files(&root, category) {
            let name = short(&root, &path);
            let doc = match wildlod_io::read(&path) {
                Ok(d) => d,
                Err(e) => panic!("{name}: {e:#}"),
            };
            let imgs = images(&doc.scene);
            let t = Instant::now();
            let e = EvalMesh::from_scene(&doc.scene, &imgs);
            let c = compare(&e, &e, &options);
            eprintln!(
                "{name}: {} triangles, self-compare {:.0} ms",
                e.triangles().len(),
                t.elapsed().as_secs_f64() * 1e3
            );
            assert!(c.hausdorff < 1e-9, "{name}: {c:?}");
            assert!(c.chamfer_mean < 1e-9 && c.chamfer_squared < 1e-18);
            // Independent samplings of one surface: the paired metrics sit
            // at their floors, not at 0.
            if e.has_texture() {
                assert!(c.texture_chamfer_floor > Some(0.0), "{name}");
                assert!(
                    at_floor(c.texture_chamfer, c.texture_chamfer_floor),
                    "{name}: texture {:?}, floor {:?}",
                    c.texture_chamfer,
                    c.texture_chamfer_floor
                );
            }
            assert!(
                at_floor(c.normal_chamfer, c.normal_chamfer_floor),
                "{name}: normals {:?}, floor {:?}",
                c.normal_chamfer,
                c.normal_chamfer_floor
            );
            // No real asset of the corpus has a vertex the outlier rule
            // would leave out.
            assert_eq!(c.outliers_reference, 0, "{name}: {:?}", c.outlier_vertices);
            assert_eq!(c.diagonal, c.diagonal_with_outliers);
            let counts = c.reference;
            assert_eq!(
                counts.faces,
                counts.triangles + counts.quads + counts.ngons,
                "{name}"
            );
            if doc.scene.nodes.is_empty() || e.triangles().is_empty() {
                continue;
            }
            // A shift of 1% of the diagonal moves no point farther than that.
            let dx = 0.01 * c.diagonal;
            let moved_scene = shifted(&doc.scene, dx as f32);
            let m = EvalMesh::from_scene(&moved_scene, &imgs);
            let s = compare(&e, &m, &options);
            assert!(s.hausdorff <= 0.0101, "{name}: {s:?}");
            assert!(s.hausdorff > 0.0, "{name}");
        }
    }
}
