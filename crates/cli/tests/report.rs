//! `wildlod report` and `lod --report`: one self-contained HTML page that
//! headless Chromium (Debian's package) opens without a console error and
//! draws both models in (non-background pixels in both halves); a textured
//! input is drawn textured on both sides; the looks (textured, heat map,
//! wireframe) switch when clicked; a chain's slider steps through its
//! levels, naming each one's triangles and error.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::path::{Path, PathBuf};

use image::RgbImage;
use serde_json::Value;
use support::{open_in_chromium, s, stderr, stdout, torus, wildlod};

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

/// Opens the page, checks it loads, draws both models and switches looks;
/// returns what the checker saw (`None` where the browser cannot run).
fn check_page(html: &Path, shot: &Path) -> Option<Value> {
    let page = std::fs::read_to_string(html).unwrap();
    // Self-contained: nothing is fetched from anywhere.
    for external in ["src=\"http", "href=\"http", "import(\"http", "from 'http"] {
        assert!(!page.contains(external), "the page loads {external}…");
    }
    let result = open_in_chromium(html, shot)?;
    assert_eq!(result["errors"], serde_json::json!([]), "{result}");
    assert_eq!(result["ready"], true, "{result}");
    let (left, right) = drawn_fractions(shot);
    assert!(left > 0.05, "left view looks empty: {left}");
    assert!(right > 0.05, "right view looks empty: {right}");
    // Each look, once clicked, is the one selected.
    let modes: Vec<(&str, bool)> = result["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| (m["mode"].as_str().unwrap(), m["checked"] == true))
        .collect();
    assert_eq!(
        modes,
        [("textured", true), ("heat", true), ("wire", true)],
        "{result}"
    );
    Some(result)
}

/// A canvas the checker saved beside `shot`: `SHOT_<name>.png`.
fn canvas(shot: &Path, name: &str) -> RgbImage {
    let stem = shot.file_stem().unwrap().to_str().unwrap();
    image::open(shot.with_file_name(format!("{stem}_{name}.png")))
        .unwrap()
        .to_rgb8()
}

/// Pixels of the model: not the white background.
fn is_model(p: &image::Rgb<u8>) -> bool {
    p.0.iter().any(|&c| c < 235)
}

/// Mean over the model's pixels of the per-pixel color variance (the
/// variance of the three channels, 0 for a gray): a lit plain material
/// has none, a texture with colors has plenty.
fn color_variance(img: &RgbImage) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for p in img.pixels().filter(|p| is_model(p)) {
        let c = p.0.map(f64::from);
        let mean = (c[0] + c[1] + c[2]) / 3.0;
        sum += c.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 3.0;
        n += 1;
    }
    sum / n.max(1) as f64
}

/// Fraction of the model's pixels in bright, saturated colors (the
/// truck's texture: a blue and green logo on a white body; its untextured
/// materials are white, gray, black and a dark green).
fn saturated_fraction(img: &RgbImage) -> f64 {
    let (mut hit, mut n) = (0usize, 0usize);
    for p in img.pixels().filter(|p| is_model(p)) {
        let (hi, lo) = (p.0.iter().max().unwrap(), p.0.iter().min().unwrap());
        n += 1;
        if hi - lo > 60 && *hi > 100 {
            hit += 1;
        }
    }
    hit as f64 / n.max(1) as f64
}

/// Fraction of the pixels where either image shows the model in which the
/// two agree (every channel within 48 of 255): the same look, drawn on
/// nearly the same shape from the same camera.
fn agreement(a: &RgbImage, b: &RgbImage) -> f64 {
    let (mut same, mut n) = (0usize, 0usize);
    for (p, q) in a.pixels().zip(b.pixels()) {
        if is_model(p) || is_model(q) {
            n += 1;
            if p.0.iter().zip(q.0).all(|(&x, y)| x.abs_diff(y) <= 48) {
                same += 1;
            }
        }
    }
    same as f64 / n.max(1) as f64
}

/// Pixels drawn in the wireframe's dark blue-gray (#1d2b38), anti-aliased
/// lines included: dark, and bluer than red (lit grays and the heat map's
/// blues are lighter; shaded grays are not bluer).
fn line_pixels(img: &RgbImage) -> usize {
    img.pixels()
        .filter(|p| {
            let [r, g, b] = p.0;
            r.max(g).max(b) < 140 && b > r + 8
        })
        .count()
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
    let shot = dir.path().join("shot.png");
    let Some(result) = check_page(&html, &shot) else {
        return;
    };
    // Untextured: the heat map first; one candidate: no slider.
    assert_eq!(result["default_mode"], "heat", "{result}");
    assert_eq!(result["levels"], serde_json::json!([]), "{result}");
    // The wireframe draws lines the shaded looks do not.
    let wire = line_pixels(&canvas(&shot, "wire_right"));
    let heat = line_pixels(&canvas(&shot, "heat_right"));
    eprintln!("line pixels: wireframe {wire}, heat map {heat}");
    assert!(
        wire > 10 * heat.max(50),
        "wireframe {wire} line pixels, heat map {heat}"
    );
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
fn the_chain_slider_steps_through_the_levels_with_their_triangles_and_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = torus(&dir.path().join("torus.ply"));
    let out = dir.path().join("chain.glb");
    let o = wildlod(&[
        "lod",
        s(&input),
        "--report",
        "-o",
        s(&out),
        "--ratios",
        "0.5,0.25,0.1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let chain: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let html = PathBuf::from(chain["report"].as_str().unwrap());
    let shot = dir.path().join("shot.png");
    let Some(result) = check_page(&html, &shot) else {
        return;
    };
    let levels = result["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 3, "{result}");
    let mut lines = Vec::new();
    for (k, l) in levels.iter().enumerate() {
        let want = &chain["levels"][k + 1];
        let tris = want["triangles"].as_u64().unwrap();
        let label = l["label"].as_str().unwrap();
        assert_eq!(l["value"], k, "{result}");
        assert!(
            label.starts_with(&format!("lod{}: {tris} triangles", k + 1)),
            "{label}"
        );
        // The chain's own error, as the page formats it (JavaScript's
        // toFixed(4), or toExponential(2) below 0.01, which Rust's
        // formats match).
        let e = want["error"].as_f64().unwrap();
        let shown = if e >= 0.01 {
            format!("{e:.4}")
        } else {
            format!("{e:.2e}")
        };
        assert!(
            label.contains(&format!("error {shown}")),
            "{label} does not show the error {e}"
        );
        assert_eq!(l["right_label"], format!("lod{}: {tris} triangles", k + 1));
        lines.push(line_pixels(&canvas(&shot, &format!("level{k}_right"))));
    }
    eprintln!("wireframe line pixels per level: {lines:?}");
    // Coarser levels draw fewer edges.
    assert!(
        lines.windows(2).all(|w| w[1] < w[0]),
        "line pixels per level {lines:?}"
    );
}

/// The CesiumMilkTruck at 10%: both sides show the texture (its blue and
/// green logo), the right one like the left one; the heat map replaces it.
#[test]
fn a_textured_file_is_drawn_textured_on_both_sides() {
    let Some(root) = wildlod_testkit::corpus("a_textured_file_is_drawn_textured_on_both_sides")
    else {
        return;
    };
    let input = root.join("textured/CesiumMilkTruck.glb");
    let dir = tempfile::tempdir().unwrap();
    let lod = dir.path().join("truck10.glb");
    let o = wildlod(&["simplify", s(&input), "-o", s(&lod), "--ratio", "0.1", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let html = dir.path().join("truck.html");
    let o = wildlod(&["report", s(&input), s(&lod), "-o", s(&html), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(report["output"], s(&html));
    assert_eq!(report["reference_triangles"], 3624);
    assert!(
        report["candidates"][0]["metrics"]["hausdorff"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    // The image is in the page, not referred to.
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("\"uri\":\"data:image/jpeg;base64,"));
    let shot = dir.path().join("shot.png");
    let Some(result) = check_page(&html, &shot) else {
        return;
    };
    assert_eq!(result["default_mode"], "textured", "{result}");
    let (tex_l, tex_r) = (
        canvas(&shot, "textured_left"),
        canvas(&shot, "textured_right"),
    );
    let (heat_l, heat_r) = (canvas(&shot, "heat_left"), canvas(&shot, "heat_right"));
    let (vl, vr, vh) = (
        color_variance(&tex_l),
        color_variance(&tex_r),
        color_variance(&heat_l),
    );
    let (sl, sr, sh) = (
        saturated_fraction(&tex_l),
        saturated_fraction(&tex_r),
        saturated_fraction(&heat_l),
    );
    eprintln!(
        "color variance: textured left {vl:.0}, right {vr:.0}, plain {vh:.0}; saturated: {sl:.3}, {sr:.3}, plain {sh:.3}; agreement: {:.2} textured, {:.2} heat",
        agreement(&tex_l, &tex_r),
        agreement(&tex_l, &heat_r)
    );
    // Textured, the logo's blue and green; in the heat map's look the
    // left model is plain gray.
    assert!(vl > 8.0 * vh.max(1.0), "left: textured {vl}, plain {vh}");
    assert!(vr > 8.0 * vh.max(1.0), "right: textured {vr}, plain {vh}");
    assert!(
        sl > 0.05 && sr > 0.05 && sh < 0.005,
        "saturated {sl} {sr} {sh}"
    );
    // The right side is drawn like the left one, not like the heat map.
    let same = agreement(&tex_l, &tex_r);
    let heat = agreement(&tex_l, &heat_r);
    assert!(
        same > 0.7 && heat < same - 0.3,
        "agreement textured {same}, heat {heat}"
    );
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
