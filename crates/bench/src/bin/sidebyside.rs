//! Quick side-by-side timing: `sidebyside FILE RATIO`.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = std::path::Path::new(&args[1]);
    let ratio: f64 = args[2].parse().unwrap_or(0.1);
    let (pos, idx) = wildlod_bench::load_triangles(path).expect("load");
    let tris = idx.len() / 3;
    let target = (tris as f64 * ratio).round() as usize;
    for round in 0..2 {
        let t = std::time::Instant::now();
        let m = wildlod_bench::meshopt_simplify(&pos, &idx, target, false);
        let tm = t.elapsed().as_secs_f64();
        let o = wildlod_simplify::Options {
            target: wildlod_simplify::Target {
                ratio: Some(ratio),
                ..Default::default()
            },
            ..Default::default()
        };
        let t = std::time::Instant::now();
        let w = wildlod_simplify::simplify_triangles(&pos, &idx, &o).expect("simplify");
        let tw = t.elapsed().as_secs_f64();
        println!(
            "round {round}: meshopt {} tris {:.3}s | wildlod {} tris {:.3}s | ratio {:.2}x",
            m.len() / 3,
            tm,
            w.report.output_triangles,
            tw,
            tw / tm
        );
    }
}
