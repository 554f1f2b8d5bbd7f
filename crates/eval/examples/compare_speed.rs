//! Times `compare` with default options on a generated 1M-triangle torus
//! against a 10k-triangle one:
//! `cargo run --release -p wildlod-eval --example compare_speed`.

use std::time::Instant;

use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::shapes;

fn main() {
    let fine = shapes::torus(1000, 500, 2.0, 0.5);
    let coarse = shapes::torus(100, 50, 2.0, 0.5);
    let t = Instant::now();
    let (a, b) = (EvalMesh::from_mesh(&fine), EvalMesh::from_mesh(&coarse));
    println!(
        "EvalMesh::from_mesh: {:.0} ms ({} + {} triangles)",
        t.elapsed().as_secs_f64() * 1e3,
        a.triangles().len(),
        b.triangles().len()
    );
    let t = Instant::now();
    let c = compare(&a, &b, &CompareOptions::default());
    println!(
        "compare ({} threads): {:.0} ms",
        rayon::current_num_threads(),
        t.elapsed().as_secs_f64() * 1e3
    );
    println!(
        "hausdorff {:.3e}, chamfer mean {:.3e}, squared {:.3e}, {} + {} vertex samples",
        c.hausdorff,
        c.chamfer_mean,
        c.chamfer_squared,
        c.vertex_samples_reference,
        c.vertex_samples_candidate
    );
}
