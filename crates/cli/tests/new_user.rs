//! Issue 34, what a new user trips over: OBJ outputs that survive being
//! moved, one triangle count for instanced meshes, conflicting targets,
//! `lod --ratios 0`, smoothing groups, which error is which, and the
//! `compare` table.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::path::{Path, PathBuf};

use serde_json::Value;
use support::{s, stderr, stdout, wildlod};
use wildlod_mesh::ImageSource;

/// A PNG of 8×8 pixels (real, so that readers and decoders accept it).
fn png(path: &Path, shade: u8) {
    let img = image::RgbImage::from_fn(8, 8, |x, y| {
        image::Rgb([shade, (x * 30) as u8, (y * 30) as u8])
    });
    img.save(path).unwrap();
}

/// An OBJ grid (a textured, subdivided square) whose MTL names its image
/// in a subfolder and carries the lines the scene has no field for.
fn textured_obj(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir.join("maps")).unwrap();
    png(&dir.join("maps/paint.png"), 200);
    std::fs::write(
        dir.join("grid.mtl"),
        "newmtl paint\nKd 1 1 1\nKs 0.5 0.25 0\nNs 32\nillum 2\nNi 1.45\nPs 0.2\nmap_Kd maps/paint.png\n",
    )
    .unwrap();
    let n = 12;
    let mut obj = String::from("mtllib grid.mtl\n");
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            // A gentle bump, so that collapses cost something.
            let z = 0.05 * ((x * 6.0).sin() * (y * 5.0).cos());
            obj += &format!("v {x} {y} {z}\nvt {x} {y}\n");
        }
    }
    obj += "usemtl paint\ns 1\n";
    let id = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            obj += &format!("f {a}/{a} {b}/{b} {c}/{c}\nf {a}/{a} {c}/{c} {d}/{d}\n");
        }
    }
    let path = dir.join("grid.obj");
    std::fs::write(&path, obj).unwrap();
    path
}

/// Moves `from` to `to` (a rename: the original path is gone afterwards).
fn move_dir(from: &Path, to: &Path) {
    std::fs::rename(from, to).unwrap();
    assert!(!from.exists());
}

/// Every texture of the OBJ at `path` is an image file inside `root`, and
/// the MTL names no absolute path.
fn textures_inside(path: &Path, root: &Path) -> usize {
    let doc = wildlod_io::read(path).unwrap();
    assert!(
        !doc.warnings.iter().any(|w| w.contains("not on disk")),
        "{}: {:?}",
        path.display(),
        doc.warnings
    );
    let root = root.canonicalize().unwrap();
    for t in &doc.scene.textures {
        match &t.source {
            ImageSource::Path(p) => {
                assert!(
                    p.is_file(),
                    "{} names a missing image {}",
                    path.display(),
                    p.display()
                );
                assert!(
                    p.canonicalize().unwrap().starts_with(&root),
                    "{} reads {} from outside its folder",
                    path.display(),
                    p.display()
                );
            }
            other => panic!("OBJ texture not a file: {other:?}"),
        }
    }
    let mtl = std::fs::read_to_string(path.with_extension("mtl")).unwrap();
    for line in mtl.lines().filter(|l| l.starts_with("map_")) {
        let name = line.split_whitespace().nth(1).unwrap();
        assert!(!Path::new(name).is_absolute(), "{line}");
    }
    doc.scene.textures.len()
}

fn images_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png") || n.ends_with(".jpg"))
        .collect();
    v.sort();
    v
}

#[test]
fn obj_outputs_of_simplify_lod_and_batch_can_be_moved_with_their_textures() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir(&src).unwrap();
    let input = textured_obj(&src);

    // simplify
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out.join("g.obj")),
        "--ratio",
        "0.5",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // lod, one file per level
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&out.join("chain.obj")),
        "--ratios",
        "0.5,0.25",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // batch into a tree
    let bout = out.join("batch");
    let o = wildlod(&["batch", s(&src), "-o", s(&bout), "--ratio", "0.5", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));

    // The MTL keeps what the renderer reads beyond the scene's fields.
    let mtl = std::fs::read_to_string(out.join("g.mtl")).unwrap();
    for line in ["Ks 0.5 0.25 0", "Ns 32", "illum 2", "Ni 1.45", "Ps 0.2"] {
        assert!(mtl.lines().any(|l| l == line), "{line} missing from\n{mtl}");
    }
    // One copy of the image, shared by simplify's and lod's files.
    assert_eq!(images_in(&out), ["paint.png"]);

    // The source and its image go away; the output folder moves.
    std::fs::remove_dir_all(&src).unwrap();
    let moved = dir.path().join("elsewhere");
    move_dir(&out, &moved);
    for f in [
        "g.obj",
        "chain_lod1.obj",
        "chain_lod2.obj",
        "batch/grid.obj",
    ] {
        assert_eq!(textures_inside(&moved.join(f), &moved), 1, "{f}");
    }
}

#[test]
fn glb_with_a_shared_embedded_image_to_obj_writes_it_once_and_moves() {
    let Some(root) =
        wildlod_testkit::corpus("glb_with_a_shared_embedded_image_to_obj_writes_it_once_and_moves")
    else {
        return;
    };
    let truck = root.join("textured/CesiumMilkTruck.glb");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let o = wildlod(&[
        "simplify",
        s(&truck),
        "-o",
        s(&out.join("t.obj")),
        "--ratio",
        "0.5",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The body and the wheels use one image: one file, not two identical.
    assert_eq!(images_in(&out).len(), 1, "{:?}", images_in(&out));
    let moved = dir.path().join("moved");
    move_dir(&out, &moved);
    assert!(textures_inside(&moved.join("t.obj"), &moved) >= 1);
}

fn json(o: &std::process::Output) -> Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", stdout(o)))
}

#[test]
fn every_command_counts_the_triangles_an_instanced_file_draws() {
    let Some(root) =
        wildlod_testkit::corpus("every_command_counts_the_triangles_an_instanced_file_draws")
    else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let inputs = dir.path().join("in");
    std::fs::create_dir(&inputs).unwrap();
    let truck = inputs.join("truck.glb");
    std::fs::copy(root.join("textured/CesiumMilkTruck.glb"), &truck).unwrap();

    let info = json(&wildlod(&["info", s(&truck), "--json"]));
    let drawn = info["drawn_triangles"].as_u64().unwrap();
    // The wheel mesh is drawn twice: the stored count is smaller.
    assert!(drawn > info["triangulated"].as_u64().unwrap(), "{info}");

    let simplify = json(&wildlod(&[
        "simplify",
        s(&truck),
        "-o",
        s(&dir.path().join("s.glb")),
        "--ratio",
        "0.25",
        "--json",
    ]));
    assert_eq!(
        simplify["input_triangles"].as_u64(),
        Some(drawn),
        "{simplify}"
    );

    let lod_out = dir.path().join("l.glb");
    let lod = json(&wildlod(&[
        "lod",
        s(&truck),
        "-o",
        s(&lod_out),
        "--ratios",
        "0.5,0.25",
        "--json",
    ]));
    let levels = lod["levels"].as_array().unwrap();
    assert_eq!(levels[0]["triangles"].as_u64(), Some(drawn), "{lod}");
    let text = wildlod(&[
        "lod",
        s(&truck),
        "-o",
        s(&lod_out),
        "--ratios",
        "0.5,0.25",
        "--overwrite",
    ]);
    assert!(text.status.success(), "{}", stderr(&text));
    let text = stdout(&text);
    assert!(text.contains(&format!("lod0: {drawn} triangles")), "{text}");
    for l in &levels[1..] {
        let line = format!(
            "lod{}: {} triangles ({:.1}% of the input)",
            l["level"],
            l["triangles"],
            100.0 * l["triangles"].as_f64().unwrap() / drawn as f64
        );
        assert!(text.contains(&line), "{line} not in\n{text}");
    }

    let bout = dir.path().join("b");
    let batch = json(&wildlod(&[
        "batch",
        s(&inputs),
        "-o",
        s(&bout),
        "--ratio",
        "0.25",
        "--json",
        "-q",
    ]));
    let file = &batch["results"][0];
    assert_eq!(file["triangles_in"].as_u64(), Some(drawn), "{batch}");
    let csv = std::fs::read_to_string(bout.join("wildlod-summary.csv")).unwrap();
    assert!(csv.contains(&format!(",ok,{drawn},")), "{csv}");
    // The output, as `info` counts it, is what batch says it wrote.
    let written = json(&wildlod(&["info", s(&bout.join("truck.glb")), "--json"]));
    assert_eq!(written["drawn_triangles"], file["triangles_out"], "{batch}");
    // And the same for simplify.
    let s_info = json(&wildlod(&["info", s(&dir.path().join("s.glb")), "--json"]));
    assert_eq!(s_info["drawn_triangles"], simplify["output_triangles"]);
}

#[test]
fn conflicting_targets_are_an_error_naming_both_flags() {
    let dir = tempfile::tempdir().unwrap();
    let input = support::torus(&dir.path().join("t.obj"));
    let out = dir.path().join("o.obj");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.1",
        "--faces",
        "100",
    ]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("--ratio") && err.contains("--faces") && err.contains("cannot be used with"),
        "{err}"
    );
    assert!(!out.exists());
    let bout = dir.path().join("b");
    let o = wildlod(&[
        "batch",
        s(dir.path()),
        "-o",
        s(&bout),
        "--faces",
        "100",
        "--ratio",
        "0.1",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    assert!(!bout.exists());
}

#[test]
fn lod_accepts_a_zero_ratio_as_simplify_does() {
    let dir = tempfile::tempdir().unwrap();
    let input = support::torus(&dir.path().join("t.obj"));
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&dir.path().join("c.glb")),
        "--ratios",
        "0.5,0",
        "--json",
    ]);
    let j = json(&o);
    let levels = j["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 3, "{j}");
    // As few as possible: the one triangle every mesh keeps, or what the
    // guards leave — far below the previous level.
    let last = levels[2]["triangles"].as_u64().unwrap();
    assert!(
        last >= 1 && last * 10 < levels[1]["triangles"].as_u64().unwrap(),
        "{j}"
    );
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&dir.path().join("d.glb")),
        "--ratios",
        "0.5,-0.1",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("[0, 1]"), "{}", stderr(&o));
}

#[test]
fn smoothing_groups_are_read_without_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let input = textured_obj(dir.path());
    let o = wildlod(&["info", s(&input)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = stdout(&o) + &stderr(&o);
    assert!(!all.contains("'s'") && !all.contains("ignored"), "{all}");
}

#[test]
fn the_summary_says_which_error_is_relative_and_which_in_file_units() {
    let dir = tempfile::tempdir().unwrap();
    let input = support::torus(&dir.path().join("t.obj"));
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&dir.path().join("o.obj")),
        "--ratio",
        "0.2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let line = stdout(&o);
    assert!(
        line.contains("error ") && line.contains(" of the diagonal"),
        "{line}"
    );
    assert!(
        line.contains("world error ") && line.contains(" in file units"),
        "{line}"
    );
    let o = wildlod(&[
        "lod",
        s(&input),
        "-o",
        s(&dir.path().join("c.glb")),
        "--ratios",
        "0.5",
    ]);
    assert!(stdout(&o).contains(" of the diagonal"), "{}", stdout(&o));
}

#[test]
fn compare_text_is_a_table_with_aligned_values_and_singular_counts() {
    let dir = tempfile::tempdir().unwrap();
    let input = support::torus(&dir.path().join("t.obj"));
    let lod = dir.path().join("o.obj");
    assert!(
        wildlod(&["simplify", s(&input), "-o", s(&lod), "--ratio", "0.5", "-q"])
            .status
            .success()
    );
    let o = wildlod(&["compare", s(&input), s(&lod), "--samples", "2000"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    // Rows: two spaces, a label, spaces, a value. Every value starts in
    // the same column (counted in characters: Chamfer² is one wider in
    // bytes).
    let columns: Vec<usize> = text
        .lines()
        .filter(|l| l.starts_with("  ") && !l.starts_with("  note"))
        .map(|l| {
            let chars: Vec<char> = l.chars().collect();
            let mut k = 2;
            // The label ends at the first run of two spaces.
            while k + 1 < chars.len() && !(chars[k] == ' ' && chars[k + 1] == ' ') {
                k += 1;
            }
            while k < chars.len() && chars[k] == ' ' {
                k += 1;
            }
            k
        })
        .collect();
    assert!(columns.len() >= 9, "{text}");
    assert!(
        columns.iter().all(|&c| c == columns[0]),
        "{columns:?}\n{text}"
    );
    // One torus is one component, said in the singular.
    assert!(
        text.contains(" 1 component\n") && !text.contains(" 1 components"),
        "{text}"
    );
}

/// (element, slot, joint) of every influence slot that has zero weight but
/// names a joint other than 0, over every skinned primitive of a GLB: what
/// the Khronos validator reports as ACCESSOR_JOINTS_USED_ZERO_WEIGHT.
fn joints_used_with_zero_weight(glb: &Path) -> (usize, Vec<(usize, usize, u32)>) {
    let data = std::fs::read(glb).unwrap();
    let u32_at = |o: usize| u32::from_le_bytes(data[o..o + 4].try_into().unwrap()) as usize;
    let json_len = u32_at(12);
    let json: Value = serde_json::from_slice(&data[20..20 + json_len]).unwrap();
    let bin = &data[20 + json_len + 8..];
    // The values of one accessor as f64 (normalized integers scaled to 0..1).
    let read = |a: usize| -> Vec<f64> {
        let acc = &json["accessors"][a];
        let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        let count = acc["count"].as_u64().unwrap() as usize;
        let comps = 4;
        let (size, norm) = match acc["componentType"].as_u64().unwrap() {
            5121 => (1, 255.0),
            5123 => (2, 65535.0),
            5126 => (4, 0.0),
            t => panic!("component type {t}"),
        };
        let normalized = acc["normalized"].as_bool().unwrap_or(false);
        let stride = view["byteStride"]
            .as_u64()
            .map_or(size * comps, |s| s as usize);
        let base = view["byteOffset"].as_u64().unwrap_or(0) as usize
            + acc["byteOffset"].as_u64().unwrap_or(0) as usize;
        let mut out = Vec::with_capacity(count * comps);
        for e in 0..count {
            for c in 0..comps {
                let o = base + e * stride + c * size;
                let v = match size {
                    1 => bin[o] as f64,
                    2 => u16::from_le_bytes([bin[o], bin[o + 1]]) as f64,
                    _ => f32::from_le_bytes(bin[o..o + 4].try_into().unwrap()) as f64,
                };
                out.push(if normalized { v / norm } else { v });
            }
        }
        out
    };
    let mut slots = 0;
    let mut bad = Vec::new();
    for mesh in json["meshes"].as_array().unwrap() {
        for prim in mesh["primitives"].as_array().unwrap() {
            let attrs = prim["attributes"].as_object().unwrap();
            for set in 0.. {
                let (Some(j), Some(w)) = (
                    attrs.get(&format!("JOINTS_{set}")),
                    attrs.get(&format!("WEIGHTS_{set}")),
                ) else {
                    break;
                };
                let (j, w) = (
                    read(j.as_u64().unwrap() as usize),
                    read(w.as_u64().unwrap() as usize),
                );
                slots += j.len();
                for (k, (jv, wv)) in j.iter().zip(&w).enumerate() {
                    if *wv == 0.0 && *jv != 0.0 {
                        bad.push((k / 4, k % 4, *jv as u32));
                    }
                }
            }
        }
    }
    (slots, bad)
}

#[test]
fn skinned_levels_name_joint_zero_in_every_slot_without_weight() {
    let Some(root) =
        wildlod_testkit::corpus("skinned_levels_name_joint_zero_in_every_slot_without_weight")
    else {
        return;
    };
    let man = root.join("skinned/CesiumMan.glb");
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one.glb");
    let o = wildlod(&["simplify", s(&man), "-o", s(&one), "--ratio", "0.25", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let chain = dir.path().join("chain.glb");
    let o = wildlod(&[
        "lod",
        s(&man),
        "-o",
        s(&chain),
        "--ratios",
        "0.5,0.25,0.1",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [&one, &chain] {
        let (slots, bad) = joints_used_with_zero_weight(f);
        assert!(slots > 1000, "{}: no skin read", f.display());
        assert!(
            bad.is_empty(),
            "{}: {} slots, e.g. {:?}",
            f.display(),
            bad.len(),
            &bad[..bad.len().min(5)]
        );
        // And the validator agrees, where it can run.
        if let Some(v) = support::validate(f) {
            assert!(
                v["codes"].get("ACCESSOR_JOINTS_USED_ZERO_WEIGHT").is_none(),
                "{v}"
            );
        }
    }
}

/// Words that cite the papers behind the options; they belong in
/// docs/cli.md, not in the help a user reads to run the tool.
const CITATIONS: &[&str] = &[
    "§",
    "λ",
    "Knodt",
    "Garland",
    "Hoppe",
    "Liu,",
    "Yuksel",
    "link condition",
    "W's",
    "(W ",
];

#[test]
fn short_help_is_one_short_line_per_flag_without_paper_citations() {
    for cmd in ["simplify", "lod", "batch"] {
        let o = wildlod(&[cmd, "-h"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let h = stdout(&o);
        for line in h.lines() {
            assert!(
                line.chars().count() <= 100,
                "{cmd} -h: {} chars: {line}",
                line.chars().count()
            );
        }
        // Every flag is on its own line with its summary.
        let flags = h
            .lines()
            .filter(|l| l.trim_start().starts_with("--"))
            .count();
        assert!(flags >= 30, "{cmd} -h lists {flags} flags:\n{h}");
        for long in [false, true] {
            let text = if long {
                stdout(&wildlod(&[cmd, "--help"]))
            } else {
                h.clone()
            };
            for c in CITATIONS {
                assert!(
                    !text.contains(c),
                    "{cmd} {}: cites {c:?}",
                    if long { "--help" } else { "-h" }
                );
            }
        }
    }
    // The long help keeps the detail.
    let long = stdout(&wildlod(&["simplify", "--help"]));
    assert!(
        long.contains("Exporters make surfaces double-sided"),
        "{long}"
    );
    // The references are in docs/cli.md.
    let docs =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/cli.md"))
            .unwrap();
    for c in ["Knodt", "λ_sym", "link condition", "Hoppe 1999", "W §4.3"] {
        assert!(docs.contains(c), "docs/cli.md lacks {c}");
    }
}

#[test]
fn every_flag_the_help_lists_is_in_docs_cli() {
    // Users script against the command line from docs/cli.md; a flag the
    // help shows but the reference does not (five were, found by hand) is
    // one they cannot look up.
    let docs =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/cli.md"))
            .unwrap();
    let mut missing = Vec::new();
    for cmd in ["simplify", "lod", "batch", "info", "compare", "report"] {
        let h = stdout(&wildlod(&[cmd, "--help"]));
        let flags: Vec<&str> = h
            .lines()
            .map(str::trim_start)
            // `-o, --output <OUTPUT>`: the long name is the one documented.
            .map(|l| match l.split_once(", --") {
                Some((short, rest)) if short.len() == 2 && short.starts_with('-') => {
                    &l[short.len() + 2..][..rest.len() + 2]
                }
                _ => l,
            })
            .filter(|l| l.starts_with("--"))
            .filter_map(|l| l.split([' ', '=', '<', ',']).next())
            .filter(|f| !matches!(*f, "--help" | "--version"))
            .collect();
        assert!(!flags.is_empty(), "{cmd} --help lists no flag:\n{h}");
        for f in flags {
            // In a table row or a heading's synopsis, as code.
            if !(docs.contains(&format!("`{f}")) || docs.contains(&format!("|{f}"))) {
                missing.push(format!("{cmd} {f}"));
            }
        }
    }
    assert!(missing.is_empty(), "docs/cli.md lacks {missing:?}");
}

#[test]
fn lod_and_batch_help_print_each_example_on_its_own_line() {
    for (cmd, examples) in [
        (
            "lod",
            [
                "wildlod lod chair.glb -o chair_lods.glb --ratios 0.5,0.25,0.1",
                "wildlod lod scan.obj -o out/scan.obj --errors 0.001,0.005,0.02",
                "wildlod lod truck.glb -o truck.glb --faces 20000,5000,1000 --split",
            ],
        ),
        (
            "batch",
            [
                "wildlod batch assets/ -o lods/ --ratio 0.25",
                "wildlod batch assets/ -o lods/ --lod-ratios 0.5,0.25,0.1 --jobs 4",
                "wildlod batch assets/ -o lods/ --ratio 0.25 --skip-existing",
            ],
        ),
    ] {
        let h = stdout(&wildlod(&[cmd, "--help"]));
        for e in examples {
            assert!(
                h.lines().any(|l| l.trim() == e),
                "{cmd}: no line holds just `{e}`:\n{h}"
            );
        }
    }
}
