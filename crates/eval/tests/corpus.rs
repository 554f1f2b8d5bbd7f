//! `compare` on the real-mesh corpus: every file against itself is 0 apart,
//! and against a copy shifted by a known amount at most that far.

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

#[test]
fn corpus_meshes_are_zero_from_themselves_and_at_most_a_shift_from_a_shifted_copy() {
    let Some(root) = corpus("corpus_meshes_are_zero_from_themselves") else {
        return;
    };
    let options = CompareOptions {
        samples: 20_000,
        texture_samples: 2_000,
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
            if e.has_texture() {
                assert_eq!(c.texture_chamfer, Some(0.0), "{name}");
            }
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
