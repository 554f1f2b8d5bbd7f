//! The quad-preserving ordering (Knodt 2024 §3.2, Alg. 1) on the quad
//! meshes of the corpus, against Knodt's own simplifier on the same meshes
//! (`simple_qem`, measured in `../shared/peers/knodt_simple_qem_corpus.csv`)
//! and against cost order alone: at 50% / 25% / 10% the default keeps a
//! median quad ratio at least his, more quads than the ordering off, and a
//! mean Chamfer distance within 10% of the ordering off (each file's is
//! held within 1.15×, `QuadSettings::distance_tolerance`).
#![allow(clippy::unwrap_used)] // test code

use std::collections::BTreeMap;
use std::path::Path;

use wildlod_bench::evaluation::{evaluate, median, Config, Row};
use wildlod_bench::methods::Method;

/// Knodt's quad ratio of `simple_qem` per (mesh name, ratio), from the
/// peers' CSV beside the corpus; meshes without input quads are left out.
fn simple_qem(corpus: &Path) -> BTreeMap<(String, String), f64> {
    let csv = corpus.join("../peers/knodt_simple_qem_corpus.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (mesh, ratio) = (col("mesh"), col("ratio"));
    let (in_quads, in_tris) = (col("in_quads"), col("in_tris"));
    let (out_quads, out_tris) = (col("out_quads"), col("out_tris"));
    let mut out = BTreeMap::new();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| f[i].parse::<f64>().unwrap();
        if num(in_quads) > 0.0 {
            let q = (num(out_quads) / num(out_tris)) / (num(in_quads) / num(in_tris));
            out.insert((f[mesh].to_string(), f[ratio].to_string()), q);
        }
    }
    out
}

#[test]
fn quad_corpus_keeps_more_quads_than_knodts_simplifier_within_ten_percent_chamfer() {
    let Some(corpus) = wildlod_testkit::corpus("quad_corpus") else {
        return;
    };
    let knodt = simple_qem(&corpus);
    let ratios = [0.5, 0.25, 0.1];
    let cfg = Config {
        corpus,
        categories: vec!["quad".into()],
        ratios: ratios.to_vec(),
        samples: 50_000,
        methods: vec![Method::Wildlod, Method::WildlodNoQuads],
    };
    let rows = evaluate(&cfg, |_| {}).unwrap();
    assert!(
        rows.iter().all(Row::reached),
        "every run reaches its target"
    );
    for ratio in ratios {
        let of = |m: Method| -> Vec<&Row> {
            rows.iter()
                .filter(|r| r.method == m && r.ratio == ratio)
                .collect()
        };
        let (on, off) = (of(Method::Wildlod), of(Method::WildlodNoQuads));
        assert_eq!(on.len(), off.len());
        assert!(on.len() >= 5, "the quad corpus is there: {}", on.len());
        let quads = median(on.iter().filter_map(|r| r.quad_ratio).collect()).unwrap();
        let plain = median(off.iter().filter_map(|r| r.quad_ratio).collect()).unwrap();
        let theirs: Vec<f64> = knodt
            .iter()
            .filter(|((_, r), _)| r.parse::<f64>().ok() == Some(ratio))
            .map(|(_, &q)| q)
            .collect();
        assert!(
            theirs.len() >= 5,
            "{ratio}: simple_qem rows {}",
            theirs.len()
        );
        let bar = median(theirs).unwrap();
        let mean = |rs: &[&Row]| rs.iter().map(|r| r.chamfer_mean).sum::<f64>() / rs.len() as f64;
        let (c_on, c_off) = (mean(&on), mean(&off));
        eprintln!(
            "{ratio}: median quad ratio {quads:.3} (quads off {plain:.3}, simple_qem {bar:.3}), \
             mean Chamfer {c_on:.6} vs {c_off:.6}"
        );
        for r in &on {
            let name = Path::new(&r.file)
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_default();
            let k = knodt.get(&(name.clone(), ratio.to_string()));
            eprintln!("  {name}: quad ratio {:?} (simple_qem {k:?})", r.quad_ratio);
        }
        assert!(quads >= bar, "{ratio}: median quad ratio {quads} < {bar}");
        assert!(quads > plain, "{ratio}: the ordering keeps more quads");
        assert!(
            c_on <= 1.1 * c_off,
            "{ratio}: Chamfer {c_on} more than 10% above quads off {c_off}"
        );
    }
}
