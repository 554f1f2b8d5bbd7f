//! Runs the simplifier on an OBJ/STL-free generated or raw input for
//! profiling: `cargo run --release --example profile -- FILE.bin RATIO`
//! where FILE.bin holds u32 nv, u32 nt, nv*3 f32, nt*3 u32 (little endian).
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let data = std::fs::read(&args[1]).unwrap();
    let r: f64 = args[2].parse().unwrap();
    let u = |i: usize| u32::from_le_bytes(data[i * 4..i * 4 + 4].try_into().unwrap());
    let (nv, nt) = (u(0) as usize, u(1) as usize);
    let pos: Vec<[f32; 3]> = (0..nv)
        .map(|v| [0, 1, 2].map(|k| f32::from_bits(u(2 + v * 3 + k))))
        .collect();
    let idx: Vec<u32> = (0..nt * 3).map(|i| u(2 + nv * 3 + i)).collect();
    let o = wildlod_simplify::Options {
        target: wildlod_simplify::Target {
            ratio: Some(r),
            ..Default::default()
        },
        ..Default::default()
    };
    let repeat: usize = args.get(3).and_then(|r| r.parse().ok()).unwrap_or(1);
    for _ in 1..repeat {
        wildlod_simplify::simplify_triangles(&pos, &idx, &o).unwrap();
    }
    let t = std::time::Instant::now();
    let s = wildlod_simplify::simplify_triangles(&pos, &idx, &o).unwrap();
    eprintln!("{:?} in {:?}", s.report, t.elapsed());
    valence(&s);
}
#[allow(dead_code)]
fn valence(s: &wildlod_simplify::Simplified) {
    let mut deg = vec![0usize; s.positions.len()];
    for f in s.faces.iter() {
        for &v in f {
            deg[v as usize] += 1;
        }
    }
    let mut d = deg.clone();
    d.sort_unstable();
    eprintln!(
        "faces per vertex: median {} p99 {} max {}",
        d[d.len() / 2],
        d[d.len() * 99 / 100],
        d[d.len() - 1]
    );
}
