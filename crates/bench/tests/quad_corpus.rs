//! Knodt 2024's claims on the quad meshes of the corpus (§4, Table 2):
//! the quad-preserving ordering keeps the paper's median quad ratios at
//! 50% / 25% / 10%, for little more distance than cost order alone.
#![allow(clippy::unwrap_used)] // test code

use wildlod_bench::evaluation::{evaluate, median, Config, Row};
use wildlod_bench::methods::Method;

#[test]
fn quad_corpus_keeps_knodts_median_quad_ratios_within_ten_percent_chamfer() {
    let Some(corpus) = wildlod_testkit::corpus("quad_corpus") else {
        return;
    };
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
    // Knodt's medians (§4): 0.949 / 0.761 / 0.622.
    for (ratio, bar) in ratios.into_iter().zip([0.95, 0.76, 0.62]) {
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
        let mean = |rs: &[&Row]| rs.iter().map(|r| r.chamfer_mean).sum::<f64>() / rs.len() as f64;
        let (c_on, c_off) = (mean(&on), mean(&off));
        eprintln!(
            "{ratio}: median quad ratio {quads:.3} (quads off {plain:.3}), \
             mean Chamfer {c_on:.6} vs {c_off:.6}"
        );
        assert!(quads >= bar, "{ratio}: median quad ratio {quads} < {bar}");
        assert!(quads > plain, "{ratio}: the ordering keeps more quads");
        assert!(
            c_on <= 1.1 * c_off,
            "{ratio}: Chamfer {c_on} more than 10% above quads off {c_off}"
        );
    }
}
