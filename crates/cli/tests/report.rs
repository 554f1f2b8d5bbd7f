//! `wildlod report` and `lod --report`: one self-contained HTML page that
//! headless Chromium (Debian's package) opens without a console error and
//! draws both models in (non-background pixels in both halves).
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::path::Path;

use support::{open_in_chromium, s, stderr, torus, wildlod};

/// Fraction of pixels in the middle of each half of the screenshot that
/// differ from the viewers' white background.
fn drawn_fractions(shot: &Path) -> (f64, f64) {
    let img = image::open(shot).unwrap().to_rgb8();
    let (w, h) = img.dimensions();
    let fraction = |x0: u32, x1: u32| {
        let (mut drawn, mut all) = (0usize, 0usize);
        for y in h / 5..h * 4 / 5 {
            for x in x0..x1 {
                let p = img.get_pixel(x, y);
                all += 1;
                if p.0.iter().any(|&c| c < 235) {
                    drawn += 1;
                }
            }
        }
        drawn as f64 / all.max(1) as f64
    };
    // The middle 60% of each half, away from labels and the legend.
    (
        fraction(w / 10, w * 4 / 10),
        fraction(w * 6 / 10, w * 9 / 10),
    )
}

fn check_page(html: &Path, shot: &Path) {
    let page = std::fs::read_to_string(html).unwrap();
    // Self-contained: nothing is fetched from anywhere.
    for external in ["src=\"http", "href=\"http", "import(\"http", "from 'http"] {
        assert!(!page.contains(external), "the page loads {external}…");
    }
    let Some(result) = open_in_chromium(html, shot) else {
        return;
    };
    assert_eq!(result["errors"], serde_json::json!([]), "{result}");
    assert_eq!(result["ready"], true, "{result}");
    let (left, right) = drawn_fractions(shot);
    assert!(left > 0.05, "left view looks empty: {left}");
    assert!(right > 0.05, "right view looks empty: {right}");
}

#[test]
fn report_page_draws_both_models_without_console_errors() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.obj"));
    let lod = dir.path().join("lod.glb");
    let o = wildlod(&["simplify", s(&input), "-o", s(&lod), "--ratio", "0.1", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let html = dir.path().join("report.html");
    let o = wildlod(&[
        "report",
        s(&input),
        s(&lod),
        "-o",
        s(&html),
        "--samples",
        "20000",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("\"hausdorff\""), "metrics missing");
    check_page(&html, &dir.path().join("shot.png"));
}

#[test]
fn lod_report_shows_the_chain() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.ply"));
    let out = dir.path().join("torus_lods.glb");
    let o = wildlod(&[
        "lod",
        s(&input),
        "--report",
        "-o",
        s(&out),
        "--ratios",
        "0.5,0.1",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let html = dir.path().join("torus_lods_report.html");
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("\"label\":\"lod1\"") && page.contains("\"label\":\"lod2\""));
    check_page(&html, &dir.path().join("shot.png"));
}

#[test]
fn report_refuses_to_overwrite_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.obj"));
    let o = wildlod(&["report", s(&input), s(&input), "-o", s(&input)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("refusing to overwrite"),
        "{}",
        stderr(&o)
    );
    assert!(wildlod_io::read(&input).is_ok());
}
