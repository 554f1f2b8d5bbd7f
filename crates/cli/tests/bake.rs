//! `wildlod simplify --bake` end to end on generated files: glTF and OBJ+MTL
//! outputs carry the baked images, a missing texture is a warning that names
//! it, and JPEG inputs give JPEG outputs. On the corpus: where keeping the
//! UVs shows the texture visibly off, the re-baked LOD's texture Chamfer
//! distance (W Table 2) is lower, and the default (`--textures auto`) is
//! never visibly worse than the better of the two.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::path::{Path, PathBuf};
use support::{s, simplify_json, wildlod, wildlod_ok};

use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{
    shapes, Attribute, ComponentFormat, ImageSource, Material, Scene, Semantic, Texture, TextureRef,
};
use wildlod_testkit::{corpus, short};

/// `scene` written as `dir/name` (glTF by its extension): a generated
/// input for the CLI.
fn scene_file(dir: &Path, name: &str, scene: Scene) -> PathBuf {
    let path = dir.join(name);
    wildlod_io::write(
        &Document::from_scene(scene),
        &path,
        &WriteOptions::default(),
    )
    .unwrap();
    path
}

/// A textured torus (2304 triangles, every quad its own UV island) whose
/// texture is the file `texture` (written by the caller or missing).
fn torus_gltf(dir: &Path, texture: &Path, ext: &str) -> PathBuf {
    torus_with_uvs(dir, texture, ext, false)
}

/// The torus of [`torus_gltf`], or with `continuous` one UV chart: the
/// two angles around the torus, unwrapped per triangle, so its only seams
/// are where the angles wrap.
fn torus_with_uvs(dir: &Path, texture: &Path, ext: &str, continuous: bool) -> PathBuf {
    let mut m = shapes::triangulate(&shapes::torus(48, 24, 1.0, 0.35));
    let n = m.faces.len();
    let mut uv = Vec::new();
    for f in 0..n {
        if continuous {
            let angles: Vec<[f32; 2]> = m
                .faces
                .face(f)
                .iter()
                .map(|&v| {
                    let [x, y, z] = m.positions[v as usize];
                    let around = y.atan2(x);
                    let ring = (x * x + y * y).sqrt() - 1.0;
                    let tube = z.atan2(ring);
                    let turn = std::f32::consts::TAU;
                    [around / turn, tube / turn]
                })
                .collect();
            for c in &angles {
                let unwrap = |a: f32, first: f32| a - (a - first).round();
                uv.extend_from_slice(&[unwrap(c[0], angles[0][0]), unwrap(c[1], angles[0][1])]);
            }
            continue;
        }
        let (cx, cy) = ((f % 48) as f32, (f / 48) as f32);
        for (du, dv) in [(0.1, 0.1), (0.9, 0.1), (0.1, 0.9)] {
            uv.extend_from_slice(&[(cx + du) / 48.0, (cy + dv) / 48.0]);
        }
    }
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices: (0..3 * n as u32).collect(),
        format: ComponentFormat::F32,
    });
    m.name = "torus".into();
    m.parts[0].material = Some(0);
    let mut scene = Scene::from_mesh(m);
    scene.materials.push(Material {
        name: "paint".into(),
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    });
    scene.textures.push(Texture {
        name: "paint".into(),
        source: ImageSource::Path(texture.to_path_buf()),
        sampler: Default::default(),
    });
    scene_file(dir, &format!("torus.{ext}"), scene)
}

fn write_image(path: &Path) {
    let img = image::RgbImage::from_fn(96, 96, |x, y| {
        image::Rgb([(x * 2) as u8, (y * 2) as u8, 128])
    });
    img.save(path).unwrap();
}

#[test]
fn bake_writes_gltf_with_png_files_and_obj_with_an_mtl() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("paint.png");
    write_image(&png);
    let input = torus_gltf(dir.path(), &png, "gltf");
    for ext in ["gltf", "obj"] {
        let out = dir.path().join(format!("lod.{ext}"));
        let o = wildlod(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            "0.05",
            "--bake",
            "--texture-size",
            "128",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let line = String::from_utf8_lossy(&o.stdout).into_owned();
        // Base color and the normal map baked from the torus's geometry.
        assert!(line.contains("baked 2 image(s) in 128²"), "{line}");
        let doc = wildlod_io::read(&out).unwrap();
        let m = &doc.scene.meshes[0];
        assert!(
            m.triangle_count().abs_diff(115) <= 1,
            "{}",
            m.triangle_count()
        );
        assert!(m.attribute(&Semantic::TexCoord(0)).is_some());
        let mat = &doc.scene.materials[m.parts[0].material.unwrap() as usize];
        assert!(mat.normal_texture.is_some(), "{ext}: {mat:?}");
        let tex = &doc.scene.textures[mat.base_color_texture.unwrap().texture as usize];
        // The image is a PNG file beside the output.
        match &tex.source {
            ImageSource::Path(p) => {
                assert_eq!(
                    p.parent().unwrap().canonicalize().unwrap(),
                    dir.path().canonicalize().unwrap()
                );
                let img = wildlod_io::decode_image_rgba8(&tex.source).unwrap();
                assert_eq!((img.width, img.height), (128, 128));
                assert_eq!(p.extension().unwrap(), "png");
            }
            other => panic!("{ext}: image not a file: {other:?}"),
        }
    }
}

#[test]
fn missing_texture_is_a_warning_naming_it_and_the_rest_bakes() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nowhere.png");
    let input = torus_gltf(dir.path(), &missing, "glb");
    let out = dir.path().join("lod.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.1",
        "--bake",
        "--texture-size",
        "64",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(
        err.contains("nowhere.png") && err.contains("warning"),
        "{err}"
    );
    // Base color from the material's factor, and the normal map.
    let doc = wildlod_io::read(&out).unwrap();
    assert_eq!(doc.scene.textures.len(), 2);
}

#[test]
fn a_webp_texture_bakes_as_the_same_png_does() {
    // EXT_texture_webp's images decode (lossless here): the re-baked
    // atlas is the one the PNG of the same pixels gives.
    let dir = tempfile::tempdir().unwrap();
    let mut baked = Vec::new();
    for ext in ["png", "webp"] {
        let img = dir.path().join(format!("paint.{ext}"));
        write_image(&img);
        let input = torus_gltf(dir.path(), &img, "gltf");
        let out = dir.path().join(format!("lod_{ext}.glb"));
        let o = wildlod(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            "0.1",
            "--bake",
            "--texture-size",
            "64",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!err.contains("warning"), "{ext}: {err}");
        let doc = wildlod_io::read(&out).unwrap();
        let t = doc.scene.materials[0].base_color_texture.expect("baked");
        let source = &doc.scene.textures[t.texture as usize].source;
        baked.push(wildlod_io::decode_image_rgba8(source).unwrap().pixels);
    }
    assert_eq!(baked[0], baked[1]);
}

#[test]
fn auto_keeps_the_uvs_of_a_texture_it_cannot_decode_and_says_why() {
    // A KTX2 file that is only a header (a broken or unsupported image):
    // it does not decode, so `auto` cannot measure the keep-UV result. It
    // keeps the UVs (a re-bake would sample nothing) and says why, in the
    // summary and in `--json`, rather than calling the error "below the
    // visible". A KTX2 texture that decodes is measured
    // (`a_ktx2_basisu_texture_is_measured_and_rebaked_into_png`).
    let dir = tempfile::tempdir().unwrap();
    let ktx = dir.path().join("paint.ktx2");
    let mut bytes = b"\xABKTX 20\xBB\r\n\x1A\n".to_vec();
    bytes.resize(80, 0);
    std::fs::write(&ktx, bytes).unwrap();
    let input = torus_gltf(dir.path(), &ktx, "gltf");
    let out = dir.path().join("lod.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.01",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let json: serde_json::Value =
        serde_json::from_str(text.get(text.find('{').unwrap_or(0)..).unwrap_or(""))
            .unwrap_or_else(|e| panic!("{e}: {text}"));
    let t = &json["textures"];
    assert_eq!(t["chosen"], "keep", "{t}");
    assert!(t["keep_uv_excess"].is_null(), "{t}");
    let why = t["unmeasured"].as_str().unwrap_or_else(|| panic!("{t}"));
    assert!(
        why.contains("do not decode") && why.contains("paint.ktx2"),
        "{why}"
    );
    assert!(!text.contains("below the visible"), "{text}");
}

#[test]
fn jpeg_inputs_give_jpeg_outputs_at_the_requested_quality() {
    let dir = tempfile::tempdir().unwrap();
    let jpg = dir.path().join("paint.jpg");
    write_image(&jpg);
    let input = torus_gltf(dir.path(), &jpg, "gltf");
    let mut sizes = Vec::new();
    for q in ["30", "95"] {
        let out = dir.path().join(format!("lod{q}.glb"));
        let o = wildlod(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            "0.1",
            "--bake",
            "--texture-size",
            "128",
            "--jpeg-quality",
            q,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let doc = wildlod_io::read(&out).unwrap();
        match &doc.scene.textures[0].source {
            ImageSource::Embedded { bytes, mime_type } => {
                assert_eq!(mime_type, "image/jpeg");
                sizes.push(bytes.len());
            }
            other => panic!("{other:?}"),
        }
    }
    assert!(sizes[0] < sizes[1], "{sizes:?}");
    let bad = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        "x.glb",
        "--bake",
        "--jpeg-quality",
        "0",
    ]);
    assert!(!bad.status.success());
}

/// The texture Chamfer distance (W Table 2) of `candidate` against
/// `reference` over the reference's sampling floor, with a seed of its own
/// (the product's choice uses the default seed: this measurement is
/// independent of it).
fn texture_excess(reference: &Document, candidate: &Document) -> Option<f64> {
    texture_error(reference, candidate).map(|(excess, _)| excess)
}

/// [`texture_excess`] and the floor it is over.
fn texture_error(reference: &Document, candidate: &Document) -> Option<(f64, f64)> {
    let images = |d: &Document| -> Vec<Option<wildlod_mesh::Image>> {
        d.scene
            .textures
            .iter()
            .map(|t| wildlod_io::decode_image(&t.source).ok())
            .collect()
    };
    let (ri, ci) = (images(reference), images(candidate));
    let r = EvalMesh::from_scene(&reference.scene, &ri);
    let c = EvalMesh::from_scene(&candidate.scene, &ci);
    let m = compare(
        &r,
        &c,
        &CompareOptions {
            samples: 1000,
            texture_samples: 40_000,
            seed: 0x5eed_7e57,
            ..CompareOptions::default()
        },
    );
    let floor = m.texture_chamfer_floor?;
    Some((m.texture_chamfer? - floor, floor))
}

/// What the default (`--textures auto`) promises on real files, and the
/// property of re-baking it rests on (W §4.3: a re-bake has no bleeding
/// where keeping UVs must cross charts). Baked at 1024² to keep the suite
/// fast (the evaluation uses the default size).
///
/// - Wherever keeping the UVs shows the texture visibly off the input's
///   (texture Chamfer over the input's own sampling floor above
///   [`wildlod_pipeline::VISIBLE_TEXTURE_EXCESS`]), the re-bake measures
///   lower.
/// - The default's output is never visibly worse than the better of the
///   two: its excess is within [`wildlod_pipeline::visible_excess`] of the
///   input's floor of the lower one's (a quarter of the floor on plain
///   textures: Avocado at 10% kept its UVs at 0.0068 over the floor,
///   where the re-bake is at 0.0007 and a quarter of the floor 0.0043).
///
/// Measured with a seed of its own, so a choice that only won on the
/// product's own sampling would fail here.
#[test]
fn the_default_shows_textures_as_well_as_the_better_of_keep_uv_and_rebake() {
    let Some(root) =
        corpus("the_default_shows_textures_as_well_as_the_better_of_keep_uv_and_rebake")
    else {
        return;
    };
    let files = [
        "textured/Avocado/Avocado.gltf",
        "textured/CesiumMilkTruck.glb",
        "textured/bob/bob_tri.obj",
        "textured/sofa_03/sofa_03_1k.gltf",
        "textured/tea_set_01/tea_set_01_1k.gltf",
        "skinned/CesiumMan.glb",
        "skinned/Fox/Fox.gltf",
    ];
    let visible = wildlod_pipeline::VISIBLE_TEXTURE_EXCESS;
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    let mut rebake_needed = 0;
    for rel in files {
        let path = root.join(rel);
        let name = short(&root, &path);
        let input = wildlod_io::read(&path).unwrap();
        for ratio in ["0.1", "0.01"] {
            let mut scores = Vec::new();
            for mode in ["keep", "bake", "auto"] {
                let out = dir.path().join(format!("out_{mode}.glb"));
                let o = wildlod(
                    &[
                        "simplify",
                        s(&path),
                        "-o",
                        s(&out),
                        "--ratio",
                        ratio,
                        "--overwrite",
                        "-q",
                        "--textures",
                        mode,
                        "--texture-size",
                        "1024",
                    ][..if mode == "keep" { 10 } else { 12 }],
                );
                assert!(
                    o.status.success(),
                    "{name}: {}",
                    String::from_utf8_lossy(&o.stderr)
                );
                let lod = wildlod_io::read(&out).unwrap();
                scores.push(texture_error(&input, &lod).unwrap_or((f64::INFINITY, 0.0)));
            }
            let [keep, bake, auto] = [scores[0].0, scores[1].0, scores[2].0];
            let shown = wildlod_pipeline::visible_excess(scores[0].1);
            eprintln!(
                "{name} at {ratio}: over the floor, keep-UV {keep:.4}, re-baked {bake:.4}, default {auto:.4}"
            );
            if keep > visible {
                rebake_needed += 1;
                if bake >= keep {
                    failures.push(format!(
                        "{name} at {ratio}: keep-UV visibly off ({keep:.4}) and re-baked no better ({bake:.4})"
                    ));
                }
            }
            if auto > keep.min(bake) + shown {
                failures.push(format!(
                    "{name} at {ratio}: the default {auto:.4} is visibly worse (by more than {shown:.4}) than the better of keep-UV {keep:.4} and re-baked {bake:.4}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    // The property above is only tested where keeping the UVs fails: the
    // corpus must hold such cases (at 1% most files do).
    assert!(
        rebake_needed >= 5,
        "only {rebake_needed} cases need a re-bake"
    );
}

/// Decision 4 of the defaults issue on generated files: a torus whose
/// every quad is its own UV island (as a lightmap unwrap or a photogrammetry
/// atlas is) under a gradient texture. At 1% the LOD cannot keep any island
/// whole: keeping the UVs gives faces spanning islands, which show the
/// texture between them; `auto` re-bakes and says so, in the summary and in
/// `--json`, with both measurements. The same torus with one UV chart at
/// 50% keeps its UVs (nothing is torn: no re-bake is tried).
#[test]
fn auto_rebakes_where_keeping_uvs_tears_and_keeps_them_where_it_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("paint.png");
    write_image(&png);
    let islands = torus_gltf(dir.path(), &png, "gltf");
    let chart = torus_with_uvs(dir.path(), &png, "glb", true);
    let out = dir.path().join("lod.glb");
    let run = |input: &Path, ratio: &str, json: bool| {
        let mut args = vec!["simplify", s(input), "-o", s(&out), "--ratio", ratio];
        args.extend(["--overwrite", "--texture-size", "128"]);
        if json {
            args.push("--json");
        }
        let o = wildlod(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let j: serde_json::Value = serde_json::from_str(&run(&islands, "0.01", true)).unwrap();
    let t = &j["textures"];
    assert_eq!(t["mode"], "auto", "{j}");
    assert_eq!(t["chosen"], "bake", "{j}");
    let (keep, bake) = (
        t["keep_uv_excess"].as_f64().unwrap(),
        t["rebaked_excess"].as_f64().unwrap(),
    );
    // Past the threshold the run itself used (a quarter of the input's
    // floor, at most 0.01), and the re-bake lower.
    let visible = t["visible_excess"].as_f64().unwrap();
    assert!(
        visible <= wildlod_pipeline::VISIBLE_TEXTURE_EXCESS && keep > visible && bake < keep,
        "{t}"
    );
    // The written file is the re-baked one: a new atlas of the asked size.
    let doc = wildlod_io::read(&out).unwrap();
    let mat = &doc.scene.materials[0];
    let tex = &doc.scene.textures[mat.base_color_texture.unwrap().texture as usize];
    let img = wildlod_io::decode_image_rgba8(&tex.source).unwrap();
    assert_eq!((img.width, img.height), (128, 128));
    let line = run(&islands, "0.01", false);
    assert!(line.contains("textures: re-baked"), "{line}");

    let j: serde_json::Value = serde_json::from_str(&run(&chart, "0.5", true)).unwrap();
    let t = &j["textures"];
    assert_eq!(t["chosen"], "keep", "{j}");
    assert!(t["rebaked_excess"].is_null(), "{j}");
    assert!(
        t["keep_uv_excess"].as_f64().unwrap() <= t["visible_excess"].as_f64().unwrap(),
        "{t}"
    );
    // The input's own image, not a 128² atlas.
    let doc = wildlod_io::read(&out).unwrap();
    let img = wildlod_io::decode_image_rgba8(&doc.scene.textures[0].source).unwrap();
    assert_eq!((img.width, img.height), (96, 96));
    let line = run(&chart, "0.5", false);
    assert!(line.contains("textures: UVs kept"), "{line}");
}

/// Image files (PNG or JPEG) directly in `dir`, sorted.
fn image_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png") || n.ends_with(".jpg"))
        .collect();
    v.sort();
    v
}

#[test]
fn baked_images_get_the_same_names_beside_a_gltf_and_an_obj() {
    let dir = tempfile::tempdir().expect("tempdir");
    let png = dir.path().join("paint.png");
    write_image(&png);
    let input = torus_gltf(dir.path(), &png, "glb");
    let mut names = Vec::new();
    for ext in ["gltf", "obj"] {
        let out_dir = dir.path().join(ext);
        std::fs::create_dir(&out_dir).expect("mkdir");
        let out = out_dir.join(format!("lod.{ext}"));
        let o = wildlod(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            "0.1",
            "--bake",
            "--texture-size",
            "64",
            "-q",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        names.push(image_files(&out_dir));
    }
    assert!(!names[0].is_empty(), "no image beside the .gltf");
    // One rule: named after the input and what was baked, in both formats.
    assert_eq!(names[0], names[1]);
    assert!(names[0].iter().all(|n| n.starts_with("torus")), "{names:?}");
}

/// Decision 4 for chains: `lod` shares the input's texture down to the
/// first level that `auto` re-bakes, then re-bakes that level and every
/// coarser one, each with an atlas of its own; `--json` says which and
/// why. On the torus of one UV chart at 50/10/1% (its texture holds at
/// 50%, as `simplify` found, and tears at 1%, where the chart cannot stay
/// whole), with the chain written as one `MSFT_lod` file and as one file
/// per level.
#[test]
fn lod_shares_the_texture_until_auto_rebakes_then_rebakes_the_coarser_levels() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("paint.png");
    write_image(&png);
    let chart = torus_with_uvs(dir.path(), &png, "glb", true);
    let lod = |out: &Path, split: bool| {
        let mut args = vec!["lod", s(&chart), "-o", s(out), "--ratios", "0.5,0.1,0.01"];
        args.extend(["--texture-size", "128", "--json"]);
        if split {
            args.push("--split");
        }
        let o = wildlod(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let j = lod(&dir.path().join("split.glb"), true);
    let levels = j["levels"].as_array().unwrap();
    assert!(levels[0]["textures"].is_null(), "{j}");
    let chosen: Vec<&str> = levels[1..]
        .iter()
        .map(|l| l["textures"]["chosen"].as_str().unwrap())
        .collect();
    eprintln!("chosen per level: {chosen:?}");
    // Keeps first, then re-bakes to the end, and 1% re-bakes.
    let first_bake = chosen.iter().position(|&c| c == "bake").unwrap();
    assert!(first_bake >= 1, "{chosen:?}");
    assert!(
        chosen[first_bake..].iter().all(|&c| c == "bake"),
        "{chosen:?}"
    );
    assert!(
        chosen[..first_bake].iter().all(|&c| c == "keep"),
        "{chosen:?}"
    );
    // The level that started re-baking measured why: keeping its UVs was
    // visibly off and the re-bake lower.
    let t = &levels[1 + first_bake]["textures"];
    assert_eq!(t["mode"], "auto");
    let (keep, bake) = (
        t["keep_uv_excess"].as_f64().unwrap(),
        t["rebaked_excess"].as_f64().unwrap(),
    );
    // Past the threshold the run itself used (a quarter of the input's
    // floor, at most 0.01), and the re-bake lower.
    let visible = t["visible_excess"].as_f64().unwrap();
    assert!(
        visible <= wildlod_pipeline::VISIBLE_TEXTURE_EXCESS && keep > visible && bake < keep,
        "{t}"
    );
    // Every level reaches its target whatever its textures, and a
    // re-baked level aims at the count the shared one would have had.
    for (l, want) in levels[1..].iter().zip([0.5, 0.1, 0.01]) {
        let m = &l["meshes"][0];
        let (got, target) = (
            m["output_triangles"].as_u64().unwrap(),
            m["target_triangles"].as_u64().unwrap(),
        );
        assert!(got.abs_diff(target) <= 1, "{l}");
        assert!((target as f64 - want * 2304.0).abs() <= 2.0, "{l}");
    }
    // Each file draws with its own images: the input's 96² where shared,
    // a 128² atlas where re-baked.
    let size = |doc: &Document| {
        let mat = &doc.scene.materials[doc.scene.meshes[0].parts[0].material.unwrap() as usize];
        let tex = &doc.scene.textures[mat.base_color_texture.unwrap().texture as usize];
        let img = wildlod_io::decode_image_rgba8(&tex.source).unwrap();
        (img.width, img.height)
    };
    for (k, l) in levels.iter().enumerate() {
        let doc = wildlod_io::read(Path::new(l["file"].as_str().unwrap())).unwrap();
        let want = if k > first_bake { (128, 128) } else { (96, 96) };
        assert_eq!(size(&doc), want, "level {k}");
    }
    // One file: the input's material, then one per re-baked level, each
    // level's mesh on its own.
    let one = dir.path().join("chain.glb");
    lod(&one, false);
    let doc = wildlod_io::read(&one).unwrap();
    let baked_levels = chosen.len() - first_bake;
    assert_eq!(
        doc.scene.materials.len(),
        1 + baked_levels,
        "{:?}",
        doc.scene.materials
    );
    let mut used: Vec<u32> = doc
        .scene
        .meshes
        .iter()
        .filter_map(|m| m.parts[0].material)
        .collect();
    used.sort_unstable();
    used.dedup();
    assert_eq!(used.len(), 1 + baked_levels, "{used:?}");
    // Asked outright: every level shares, or every level re-bakes.
    for (mode, want) in [("keep", "keep"), ("bake", "bake")] {
        let mut args = vec!["lod", s(&chart), "-o", s(&one), "--ratios", "0.5,0.1"];
        args.extend(["--textures", mode, "--json", "--overwrite"]);
        let o = wildlod(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        for l in &j["levels"].as_array().unwrap()[1..] {
            assert_eq!(l["textures"]["mode"], mode, "{l}");
            assert_eq!(l["textures"]["chosen"], want, "{l}");
        }
    }
}

/// `batch` treats every file's textures as `simplify` does: `auto` re-bakes
/// the torus of per-quad UV islands at 1% (as simplify does, above), `keep`
/// keeps the input's image.
#[test]
fn batch_chooses_textures_per_file_as_simplify_does() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("in");
    std::fs::create_dir(&src).unwrap();
    let png = src.join("paint.png");
    write_image(&png);
    torus_gltf(&src, &png, "glb");
    for (textures, want) in [("auto", (128, 128)), ("keep", (96, 96))] {
        let out = dir.path().join(textures);
        let o = wildlod(&[
            "batch",
            s(&src),
            "-o",
            s(&out),
            "--ratio",
            "0.01",
            "--textures",
            textures,
            "--texture-size",
            "128",
            "-q",
        ]);
        // --texture-size with keep is refused, as in simplify.
        if textures == "keep" {
            assert!(!o.status.success());
            assert!(String::from_utf8_lossy(&o.stderr).contains("--texture-size"));
            let o = wildlod(&[
                "batch",
                s(&src),
                "-o",
                s(&out),
                "--ratio",
                "0.01",
                "--textures",
                "keep",
                "-q",
            ]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        } else {
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        let doc = wildlod_io::read(out.join("torus.glb")).unwrap();
        let mat = &doc.scene.materials[doc.scene.meshes[0].parts[0].material.unwrap() as usize];
        let tex = &doc.scene.textures[mat.base_color_texture.unwrap().texture as usize];
        let img = wildlod_io::decode_image_rgba8(&tex.source).unwrap();
        assert_eq!((img.width, img.height), want, "--textures {textures}");
    }
}

/// A bumpy sphere, finely tessellated, smooth-shaded, with one plain
/// material and no texture or normal map: a sculpt or a scan.
fn bumpy_sphere_glb(path: &Path) {
    let mut m = shapes::triangulate(&shapes::quad_sphere(48));
    for p in &mut m.positions {
        let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let u = p.map(|c| c / len);
        let r = 1.0 + 0.03 * (9.0 * u[0]).sin() * (9.0 * u[1]).sin() * (9.0 * u[2]).cos();
        *p = u.map(|c| c * r);
    }
    // Area-weighted vertex normals.
    let mut n = vec![[0.0f32; 3]; m.positions.len()];
    for f in 0..m.faces.len() {
        let c = m.faces.face(f);
        let p = |k: usize| m.positions[c[k] as usize];
        let (a, b) = (
            [0, 1, 2].map(|i| p(1)[i] - p(0)[i]),
            [0, 1, 2].map(|i| p(2)[i] - p(0)[i]),
        );
        let cross = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        for &v in c {
            for i in 0..3 {
                n[v as usize][i] += cross[i];
            }
        }
    }
    let values: Vec<f32> = n
        .iter()
        .flat_map(|v| {
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            v.map(|c| c / len)
        })
        .collect();
    m.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values,
        indices: m.faces.indices.clone(),
        format: ComponentFormat::F32,
    });
    m.name = "bumps".into();
    m.parts[0].material = Some(0);
    let mut scene = Scene::from_mesh(m);
    scene.materials.push(Material {
        name: "clay".into(),
        base_color: [0.8, 0.8, 0.8, 1.0],
        metallic: 0.0,
        roughness: 0.5,
        ..Material::default()
    });
    wildlod_io::write(&Document::from_scene(scene), path, &WriteOptions::default()).unwrap();
}

/// Issue 33's normal maps from geometry: re-baking a bumpy sphere that has
/// no normal map at 1% bakes the input's shading normals into one, and the
/// LOD's shading normals (with the map, in its MikkTSpace frame, as
/// `compare` applies it) are at least twice as close to the input's as
/// without it. (Lit renders of the same kind of sphere, Cycles, 8 views,
/// `tools/blender/lit_compare.py`: 0.025 against 0.054 mean absolute
/// difference, noise floor 0.010.)
#[test]
fn rebaking_bakes_a_normal_map_from_the_input_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bumps.glb");
    bumpy_sphere_glb(&input);
    let shading = |extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let mut args = vec!["simplify", s(&input), "-o", s(&out), "--ratio", "0.01"];
        args.extend(["--bake", "--texture-size", "512", "-q"]);
        args.extend(extra);
        let o = wildlod(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let doc = wildlod_io::read(&out).unwrap();
        let mapped = doc
            .scene
            .materials
            .iter()
            .any(|m| m.normal_texture.is_some());
        let o = wildlod(&[
            "compare",
            s(&input),
            s(&out),
            "--json",
            "--samples",
            "20000",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (mapped, j["shading_normal_chamfer"].as_f64().unwrap())
    };
    let (mapped, with_map) = shading(&[], "mapped.glb");
    let (unmapped, without) = shading(&["--no-normal-bake"], "plain.glb");
    assert!(mapped && !unmapped, "{mapped} {unmapped}");
    assert!(
        with_map <= 0.5 * without,
        "shading-normal Chamfer {with_map:.3}° with the baked map, {without:.3}° without"
    );
    eprintln!("shading-normal Chamfer {with_map:.3}° with the baked map, {without:.3}° without");
}

/// A re-bake that cannot be made (here: an atlas too small for the LOD's
/// charts) is an error naming the file under `--textures bake`, and under
/// `auto` leaves the keep-UV result, saying why.
#[test]
fn a_rebake_that_cannot_be_made_is_named_and_auto_keeps_the_uvs() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("paint.png");
    write_image(&png);
    let islands = torus_gltf(dir.path(), &png, "gltf");
    let out = dir.path().join("lod.glb");
    let run = |mode: &str| {
        wildlod(&[
            "simplify",
            s(&islands),
            "-o",
            s(&out),
            "--ratio",
            "0.01",
            "--textures",
            mode,
            "--texture-size",
            "16",
            "--json",
        ])
    };
    let o = run("bake");
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("torus.gltf") && err.contains("do not fit a 16² atlas"),
        "{err}"
    );
    assert!(!out.exists(), "no half-written output");
    let o = run("auto");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let t = &j["textures"];
    assert_eq!(t["chosen"], "keep", "{j}");
    assert!(
        t["rebake_failed"].as_str().unwrap().contains("do not fit"),
        "{t}"
    );
}

/// The texture Chamfer excess (over the sampling floor) of `candidate`
/// against `reference`, both read from files.
fn file_excess(reference: &Path, candidate: &Path) -> f64 {
    let (r, c) = (
        wildlod_io::read(reference).unwrap(),
        wildlod_io::read(candidate).unwrap(),
    );
    texture_excess(&r, &c).expect("both sides textured")
}

/// A re-bake puts the whole file under one budget, as keeping the UVs
/// does (issue 33): a sky dome around small parts keeps the triangles the
/// file's budget gives it instead of each mesh's own share, so its
/// re-baked LOD shows the texture at least as well as the keep-UV LOD of
/// the same budget.
#[test]
fn a_rebake_shares_one_budget_over_the_file_as_keeping_the_uvs_does() {
    let dir = tempfile::tempdir().unwrap();
    let input = scene_file(
        dir.path(),
        "domed.glb",
        wildlod_testkit::scenes::domed_scene(40),
    );
    let run = |mode: &str| {
        let out = dir.path().join(format!("{mode}.glb"));
        let mut args = vec![
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            "0.1",
            "--textures",
            mode,
        ];
        if mode == "bake" {
            args.extend(["--texture-size", "512"]);
        }
        let o = wildlod(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let lod = wildlod_io::read(&out).unwrap();
        let dome = lod.scene.meshes[0].triangle_count();
        let total: usize = lod.scene.meshes.iter().map(|m| m.triangle_count()).sum();
        (file_excess(&input, &out), dome, total)
    };
    let (keep, keep_dome, keep_total) = run("keep");
    let (bake, bake_dome, bake_total) = run("bake");
    // The same budget, spent the same way: the dome's share is the file's.
    assert!(
        bake_total.abs_diff(keep_total) <= keep_total / 50 + 2,
        "{bake_total} vs {keep_total} triangles"
    );
    assert!(
        bake_dome.abs_diff(keep_dome) <= keep_dome / 20 + 2,
        "dome {bake_dome} vs {keep_dome} triangles"
    );
    assert!(
        bake <= keep,
        "texture excess re-baked {bake:.4} vs kept {keep:.4}"
    );
}

/// Peak resident memory (bytes) of `wildlod` run with `args`, from the
/// kernel's accounting of that child alone (`wait4`), with its output.
// `wait4` is the one call that reports one child's peak memory; it also
// reaps the child, which clippy cannot see.
#[allow(unsafe_code, clippy::zombie_processes)]
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn peak_memory(args: &[&str]) -> (std::process::ExitStatus, u64, String) {
    use std::os::unix::process::ExitStatusExt;
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_wildlod"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run wildlod");
    let pid = child.id() as libc::pid_t;
    let mut stderr = child.stderr.expect("piped stderr");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut s).ok();
        s
    });
    let mut status: libc::c_int = 0;
    // SAFETY: `rusage` is plain data the kernel fills; `pid` is our child,
    // not yet waited for (its `Child` handle was consumed above and never
    // waits), so `wait4` reaps exactly it.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(r, pid, "wait4 failed");
    let err = reader.join().unwrap_or_default();
    // Linux reports the maximum resident set in kilobytes.
    (
        std::process::ExitStatus::from_raw(status),
        usage.ru_maxrss as u64 * 1024,
        err,
    )
}

/// Re-baking a terrain with three vertices at -1e30 (an exporter's sentinel
/// heights) finishes within bounded memory (issue 33): the robust
/// normalization keeps the collapse history at its usual size, and an atlas
/// that cannot hold the outliers' charts leaves them out. Without that the
/// history grew until the machine ran out of memory. Bound: 1 KB per input
/// triangle plus 200 MB for the process and its images, the 1 GB
/// for the million-triangle terrain.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn an_outlier_terrain_rebakes_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = wildlod_testkit::scenes::outlier_terrain(300, 3);
    let m = &mut scene.meshes[0];
    // Planar UVs over a texture, as a terrain's ground texture is mapped.
    let uv: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|p| [p[0] / 100.0, p[2] / 100.0])
        .collect();
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices: m.faces.indices.clone(),
        format: ComponentFormat::F32,
    });
    let triangles = m.triangle_count();
    let png = dir.path().join("ground.png");
    image::RgbImage::from_fn(512, 512, |x, y| {
        image::Rgb([(x / 2) as u8, (y / 2) as u8, ((x ^ y) % 256) as u8])
    })
    .save(&png)
    .unwrap();
    scene.textures.push(Texture {
        name: "ground".into(),
        source: ImageSource::Path(png),
        sampler: Default::default(),
    });
    scene.materials[0].base_color_texture = Some(TextureRef {
        texture: 0,
        tex_coord: 0,
    });
    let input = scene_file(dir.path(), "terrain.glb", scene);
    let out = dir.path().join("lod.glb");
    let (status, peak, err) = peak_memory(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.1",
        "--bake",
    ]);
    assert!(status.success(), "{err}");
    let bound = 1000 * triangles as u64 + (200 << 20);
    assert!(
        peak <= bound,
        "peak {} MB for {triangles} triangles (bound {} MB)",
        peak >> 20,
        bound >> 20
    );
    let lod = wildlod_io::read(&out).unwrap();
    let kept = lod.scene.meshes[0].triangle_count();
    assert!(kept.abs_diff(triangles / 10) <= 1, "{kept} of {triangles}");
}

/// A re-bake reaches, mesh by mesh, the counts the run over the whole file
/// kept. sofa_03 at 1% with `--lock-borders`: that run is held at 1,034
/// triangles, where it is as close to the input as the free run at 80;
/// held again against a free run at 1,034, the re-bake went on to 1,925.
#[test]
fn a_rebake_keeps_the_triangles_its_held_run_kept() {
    let Some(root) = corpus("a_rebake_keeps_the_triangles_its_held_run_kept") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let input = root.join("textured/sofa_03/sofa_03_1k.gltf");
    let triangles = |textures: &str| {
        let out = dir.path().join(format!("sofa_{textures}.glb"));
        let j = simplify_json(
            &input,
            &out,
            &["--ratio", "0.01", "--lock-borders", "--textures", textures],
        );
        let mesh = &j["meshes"][0];
        assert!(mesh["held_by_constraints"].is_number(), "{textures}: {j}");
        mesh["output_triangles"].as_u64().unwrap()
    };
    let kept = triangles("keep");
    let baked = triangles("bake");
    // The target is 80: the held run keeps an order of magnitude more.
    assert!(kept > 400, "{kept}");
    // Within the two triangles a collapse of a face and its twin may
    // overshoot by.
    assert!(baked <= kept + 2, "re-baked {baked}, kept UVs {kept}");
}

/// Under the file's one budget a part too small to matter vanishes (the
/// keep-UV run removes it); the re-bake removes the same meshes rather
/// than keep a triangle of each.
#[test]
fn a_rebake_removes_the_meshes_the_file_budget_removes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = wildlod_testkit::scenes::domed_scene(40);
    let input_meshes = scene.meshes.len();
    let input = scene_file(dir.path(), "domed.glb", scene);
    let run = |mode: &str| {
        let out = dir.path().join(format!("{mode}.glb"));
        let o = wildlod(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            "0.01",
            "--textures",
            mode,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let lod = wildlod_io::read(&out).unwrap();
        let names: Vec<String> = lod.scene.meshes.iter().map(|m| m.name.clone()).collect();
        let total: usize = lod.scene.meshes.iter().map(|m| m.triangle_count()).sum();
        (names, total)
    };
    let (keep, keep_total) = run("keep");
    let (bake, bake_total) = run("bake");
    assert!(keep.len() < input_meshes, "no part vanished at 1%");
    assert_eq!(bake, keep, "the re-bake keeps other meshes");
    assert!(
        bake_total.abs_diff(keep_total) <= keep_total / 50 + 2,
        "{bake_total} vs {keep_total} triangles"
    );
}

/// Texture Chamfer distance of the domed scene (40 parts) re-baked at 10%
/// with one atlas per mesh, as main measured it at 973f67c (`wildlod
/// compare IN OUT --json`, field `texture_chamfer`; its floor was 0.0124)
/// before meshes shared atlases: the bound a shared atlas must stay within
/// (plus the sampling floor).
const PER_MESH_ATLAS_TEXTURE_CHAMFER: f64 = 0.0155;

/// A re-bake packs one atlas per input material across meshes (issue 33):
/// forty parts sharing one textured material come out with one material
/// and one base-color image between them, not forty, and show the
/// texture as well as forty atlases of their own did.
#[test]
fn a_rebake_packs_one_atlas_per_material_across_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let parts = 40;
    let input = scene_file(
        dir.path(),
        "domed.glb",
        wildlod_testkit::scenes::domed_scene(parts),
    );
    let out = dir.path().join("lod.glb");
    let o = wildlod(&[
        "simplify",
        s(&input),
        "-o",
        s(&out),
        "--ratio",
        "0.1",
        "--textures",
        "bake",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let lod = wildlod_io::read(&out).unwrap();
    let scene = &lod.scene;
    // The parts' input material ("paint"): one output material, with a
    // base-color texture, that every part's faces use.
    let paint: Vec<usize> = (0..scene.materials.len())
        .filter(|&m| scene.materials[m].name == "paint")
        .collect();
    assert_eq!(paint.len(), 1, "{} paint materials", paint.len());
    let paint = paint[0];
    assert!(scene.materials[paint].base_color_texture.is_some());
    let mut parts_seen = 0;
    for m in scene.meshes.iter().filter(|m| m.name.starts_with("part")) {
        if m.faces.is_empty() {
            continue;
        }
        parts_seen += 1;
        for p in &m.parts {
            assert_eq!(p.material, Some(paint as u32), "{}", m.name);
        }
    }
    assert!(parts_seen > parts / 2, "{parts_seen} parts kept");
    // Sky and paint: two base-color images in the file, not one per mesh.
    let base_color: std::collections::BTreeSet<u32> = scene
        .materials
        .iter()
        .filter_map(|m| m.base_color_texture.map(|t| t.texture))
        .collect();
    assert_eq!(base_color.len(), 2, "{base_color:?}");

    let c = wildlod(&["compare", s(&input), s(&out), "--json"]);
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));
    let j: serde_json::Value = serde_json::from_slice(&c.stdout).unwrap();
    let chamfer = j["texture_chamfer"].as_f64().unwrap();
    let floor = j["texture_chamfer_floor"].as_f64().unwrap();
    assert!(
        chamfer <= PER_MESH_ATLAS_TEXTURE_CHAMFER + floor,
        "texture Chamfer {chamfer:.4} vs one atlas per mesh {PER_MESH_ATLAS_TEXTURE_CHAMFER} + floor {floor:.4}"
    );
}

/// A re-baked LOD carries its blend shapes as the simplified one does:
/// fitted, one delta per position (the bake used to copy each output
/// corner's input delta, so copies of a vertex could disagree), and as
/// close to every target's shape at its peak.
#[test]
fn a_rebake_keeps_blend_shapes_as_simplifying_does() {
    let dir = tempfile::tempdir().unwrap();
    let targets = 4;
    let input = scene_file(
        dir.path(),
        "morphs.glb",
        wildlod_testkit::scenes::morph_sphere(24, targets),
    );
    let run = |extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let mut args = vec!["simplify", s(&input), "-o", s(&out), "--ratio", "0.1", "-q"];
        args.extend(extra);
        let o = wildlod(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let kept = run(&[], "kept.glb");
    let baked = run(&["--bake", "--texture-size", "256"], "baked.glb");
    let doc = wildlod_io::read(&baked).unwrap();
    let m = &doc.scene.meshes[0];
    let mut deltas = 0;
    for a in &m.attributes {
        if !matches!(a.semantic, Semantic::Morph { .. }) {
            continue;
        }
        deltas += 1;
        let mut at: Vec<Option<&[f32]>> = vec![None; m.positions.len()];
        for (c, &v) in m.faces.indices.iter().enumerate() {
            let d = a.corner_value(c).unwrap();
            match at[v as usize] {
                Some(first) => assert_eq!(first, d, "two deltas at position {v}"),
                None => at[v as usize] = Some(d),
            }
        }
    }
    assert_eq!(deltas, targets);
    // Frame k shows target k − 1 at full weight (frame 0: the rest pose).
    let frames = (targets + 1).to_string();
    let peaks = |c: &Path| {
        support::posed_hausdorff(
            &input,
            c,
            &["--frames", &frames, "--fps", "1", "--samples", "20000"],
        )
    };
    let (plain, rebaked) = (peaks(&kept), peaks(&baked));
    for (k, (p, b)) in plain.iter().zip(&rebaked).enumerate().skip(1) {
        assert!(*b <= 1.5 * p, "target {}: {b} re-baked against {p}", k - 1);
    }
}

/// A tree of 1,500 leaf cards that all show one 128² leaf image: a re-bake
/// gives each card its own texels, so at the input's density its atlas
/// was 4096² (an 11.8 MB LOD of a 0.24 MB file, 7.7 s). The atlas now
/// stays within the input image's texels, growing only until every chart
/// has a place, and the default, measuring such a re-bake against the
/// kept UVs, keeps the one leaf image.
#[test]
fn leaf_cards_sharing_one_image_never_get_an_atlas_larger_than_it() {
    let dir = tempfile::tempdir().unwrap();
    let input = scene_file(
        dir.path(),
        "tree.glb",
        wildlod_testkit::scenes::foliage_tree(1500),
    );
    let sides = |out: &Path| -> Vec<u32> {
        let doc = wildlod_io::read(out).unwrap();
        doc.scene
            .materials
            .iter()
            .filter_map(|m| m.base_color_texture)
            .map(|r| {
                let img =
                    wildlod_io::decode_image_rgba8(&doc.scene.textures[r.texture as usize].source)
                        .unwrap();
                img.width.max(img.height)
            })
            .collect()
    };
    for ratio in ["0.5", "0.1"] {
        let out = dir.path().join(format!("bake{ratio}.glb"));
        rebake(&input, &out, ratio);
        let baked = sides(&out);
        assert!(
            !baked.is_empty() && baked.iter().all(|&n| n <= 512),
            "{baked:?}"
        );

        let out = dir.path().join(format!("auto{ratio}.glb"));
        let o = wildlod_ok(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            "--ratio",
            ratio,
            "--json",
        ]);
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(j["textures"]["chosen"], "keep", "{}", j["textures"]);
        assert_eq!(sides(&out), vec![128], "the input's leaf image");
    }
}

/// A chain-link fence whose wires are 3 texels of 24: re-baked into a
/// smaller atlas, averaged alpha fell under the cutoff and half the wires
/// vanished (coverage 0.11 of the surface against the input's 0.234 at
/// 10%). The re-bake now scales the atlas's alpha until the alpha test
/// draws as much of the surface as the input's does.
#[test]
fn a_rebaked_alpha_tested_fence_keeps_its_wires() {
    let dir = tempfile::tempdir().unwrap();
    let input = scene_file(
        dir.path(),
        "fence.glb",
        wildlod_testkit::scenes::chain_link_fence(),
    );
    // `compare` measures the fraction of the alpha-tested surface drawn
    // (bilinear alpha at the cutoff, as a renderer draws a level).
    let coverage = |out: &Path| {
        let o = wildlod_ok(&["compare", s(&input), s(out), "--json"]);
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        [
            j["alpha_coverage_reference"].as_f64().unwrap(),
            j["alpha_coverage_candidate"].as_f64().unwrap(),
        ]
    };
    let [before, itself] = coverage(&input);
    // Wires 3 texels of 24 along both diagonals: 67/288 of the texels.
    assert!((before - 0.233).abs() < 0.01, "{before}");
    assert!((itself - before).abs() < 0.01, "{itself} {before}");
    for ratio in ["0.1", "0.01"] {
        let out = dir.path().join(format!("fence{ratio}.glb"));
        rebake(&input, &out, ratio);
        let doc = wildlod_io::read(&out).unwrap();
        let m = &doc.scene.materials[0];
        assert_eq!(m.alpha_mode, wildlod_mesh::AlphaMode::Mask);
        let img = wildlod_io::decode_image_rgba8(
            &doc.scene.textures[m.base_color_texture.unwrap().texture as usize].source,
        )
        .unwrap();
        // A smaller atlas than the input's 1024 × 256: its texels average
        // several of the input's.
        assert!(img.width <= 512, "{}", img.width);
        let [_, after] = coverage(&out);
        assert!(
            (after - before).abs() <= 0.1 * before,
            "{ratio}: coverage {after} against the input's {before}"
        );
    }
}

/// `wildlod simplify INPUT -o OUT --ratio RATIO --bake`, which must
/// succeed.
fn rebake(input: &Path, out: &Path, ratio: &str) -> std::process::Output {
    wildlod_ok(&[
        "simplify",
        s(input),
        "-o",
        s(out),
        "--ratio",
        ratio,
        "--bake",
    ])
}

/// The double-sided sheet written as `.gltf` with `edit` applied to its
/// JSON (extensions a generated scene cannot hold), as `dir/name`.
fn sheet_gltf_with(dir: &Path, name: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let plain = scene_file(
        dir,
        "sheet.gltf",
        wildlod_testkit::scenes::double_sided_sheet(),
    );
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plain).unwrap()).unwrap();
    edit(&mut json);
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    path
}

/// `input` re-baked at 10% into `dir/lod.glb`: its stderr and the JSON of
/// the written file, which the Khronos validator (where it can run) finds
/// without error.
fn rebake_to_glb_json(input: &Path, dir: &Path) -> (String, serde_json::Value) {
    let out = dir.join("lod.glb");
    let o = rebake(input, &out, "0.1");
    if let Some(v) = support::validate(&out) {
        assert_eq!(v["errors"], 0, "{v}");
    }
    let bytes = std::fs::read(&out).unwrap();
    let n = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    (
        support::stderr(&o),
        serde_json::from_slice(&bytes[20..20 + n]).unwrap(),
    )
}

/// A material extension's texture (here `KHR_materials_clearcoat`'s) is
/// laid out on the input's UVs and indexes the input's textures. A re-bake
/// that kept the material as it was left it naming a texture the output
/// does not have (the Khronos validator: `UNRESOLVED_REFERENCE`), or one of
/// the new atlases; it is now dropped with a warning, the extension's
/// factors kept.
#[test]
fn a_rebake_drops_extension_textures_it_does_not_bake() {
    let dir = tempfile::tempdir().unwrap();
    let input = sheet_gltf_with(dir.path(), "clearcoat.gltf", |json| {
        // A second texture on the same image, named only by the extension.
        let textures = json["textures"].as_array_mut().unwrap();
        textures.push(textures[0].clone());
        let extra = textures.len() - 1;
        json["materials"][0]["extensions"] = serde_json::json!({
            "KHR_materials_clearcoat": {
                "clearcoatFactor": 0.75,
                "clearcoatTexture": {"index": extra}
            }
        });
        json["extensionsUsed"] = serde_json::json!(["KHR_materials_clearcoat"]);
    });
    let (err, j) = rebake_to_glb_json(&input, dir.path());
    assert!(
        err.contains("KHR_materials_clearcoat.clearcoatTexture"),
        "{err}"
    );
    // The factor stays, the texture is gone.
    let coat = &j["materials"][0]["extensions"]["KHR_materials_clearcoat"];
    assert_eq!(coat["clearcoatFactor"], 0.75, "{j}");
    assert!(coat.get("clearcoatTexture").is_none(), "{coat}");
}

/// `KHR_materials_variants` maps a primitive to other materials by index.
/// A re-bake rebuilds the materials (one per atlas), so a mapping to a
/// variant material named one the output did not have (the Khronos
/// validator: `UNRESOLVED_REFERENCE`). Mappings now follow their material
/// by name into the rebuilt list, and those with no counterpart go, with
/// a warning.
#[test]
fn a_rebake_keeps_material_variants_pointing_at_materials_that_exist() {
    let dir = tempfile::tempdir().unwrap();
    let mut default_name = serde_json::Value::Null;
    let input = sheet_gltf_with(dir.path(), "variants.gltf", |json| {
        default_name = json["materials"][0]["name"].clone();
        let mut faded = json["materials"][0].clone();
        faded["name"] = "faded".into();
        json["materials"].as_array_mut().unwrap().push(faded);
        json["extensions"] = serde_json::json!({
            "KHR_materials_variants": {"variants": [{"name": "new"}, {"name": "old"}]}
        });
        json["meshes"][0]["primitives"][0]["extensions"] = serde_json::json!({
            "KHR_materials_variants": {"mappings": [
                {"material": 0, "variants": [0]},
                {"material": 1, "variants": [1]}
            ]}
        });
        json["extensionsUsed"] = serde_json::json!(["KHR_materials_variants"]);
    });
    let (err, j) = rebake_to_glb_json(&input, dir.path());
    assert!(err.contains("KHR_materials_variants"), "{err}");
    let materials = j["materials"].as_array().unwrap().len();
    let mappings = j["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]
        ["mappings"]
        .as_array()
        .unwrap();
    // The default material's mapping follows it; "faded" was not re-baked.
    assert_eq!(mappings.len(), 1, "{j}");
    let m = mappings[0]["material"].as_u64().unwrap() as usize;
    assert!(m < materials, "{j}");
    assert_eq!(j["materials"][m]["name"], default_name, "{j}");
}

/// A textured 16 × 16 grid whose base color texture is a KTX2 file under
/// `KHR_texture_basisu` (as `gltfpack -tc` writes them): a 64² texture of
/// 4 × 4 blocks, each one color.
fn basisu_grid(dir: &Path) -> PathBuf {
    let colors: Vec<[u8; 4]> = (0..256u32)
        .map(|b| {
            let (x, y) = (b % 16, b / 16);
            [
                (x * 16) as u8,
                (y * 16) as u8,
                if (x + y) % 2 == 0 { 32 } else { 128 },
                255,
            ]
        })
        .collect();
    std::fs::write(
        dir.join("tex.ktx2"),
        wildlod_testkit::ktx2::solid_astc(64, 64, &colors),
    )
    .unwrap();
    let n = 16u32;
    let mut bin = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            for c in [u, 0.2 * (4.0 * u).sin() * (3.0 * v).cos(), v] {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let uv_at = bin.len();
    for j in 0..=n {
        for i in 0..=n {
            for c in [i as f32 / n as f32, j as f32 / n as f32] {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let index_at = bin.len();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            for k in [a, a + n + 1, a + 1, a + 1, a + n + 1, a + n + 2] {
                bin.extend_from_slice(&k.to_le_bytes());
            }
        }
    }
    std::fs::write(dir.join("grid.bin"), &bin).unwrap();
    let vertices = (n + 1) * (n + 1);
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_texture_basisu"],
        "extensionsRequired": ["KHR_texture_basisu"],
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
        "textures": [{"extensions": {"KHR_texture_basisu": {"source": 0}}}],
        "images": [{"uri": "tex.ktx2", "mimeType": "image/ktx2"}],
        "buffers": [{"uri": "grid.bin", "byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": uv_at},
            {"buffer": 0, "byteOffset": uv_at, "byteLength": index_at - uv_at},
            {"buffer": 0, "byteOffset": index_at, "byteLength": bin.len() - index_at}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": vertices, "type": "VEC3",
             "min": [0.0, -0.2, 0.0], "max": [1.0, 0.2, 1.0]},
            {"bufferView": 1, "componentType": 5126, "count": vertices, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 6 * n * n, "type": "SCALAR"}
        ]
    });
    let path = dir.join("grid.gltf");
    std::fs::write(&path, gltf.to_string()).unwrap();
    path
}

#[test]
fn a_ktx2_basisu_texture_is_measured_and_rebaked_into_png() {
    let dir = tempfile::tempdir().unwrap();
    let input = basisu_grid(dir.path());
    // Keeping the UVs: the texture decodes, so the choice is measured.
    let v = support::simplify_json(&input, &dir.path().join("keep.glb"), &["--ratio", "0.1"]);
    let t = &v["textures"];
    assert!(t["keep_uv_excess"].is_number(), "{t}");
    assert!(t.get("unmeasured").is_none(), "{t}");
    // Re-baked: PNG images, the extension gone, the input's colors in them.
    let (_, json) = rebake_to_glb_json(&input, dir.path());
    assert!(!json.to_string().contains("KHR_texture_basisu"), "{json}");
    assert!(json["images"]
        .as_array()
        .unwrap()
        .iter()
        .all(|i| i["mimeType"] == "image/png"));
    let reference = wildlod_io::read(&input).unwrap().scene;
    let lod = wildlod_io::read(dir.path().join("lod.glb")).unwrap().scene;
    let images = |scene: &wildlod_mesh::Scene| -> Vec<_> {
        scene
            .textures
            .iter()
            .map(|t| wildlod_io::decode_image(&t.source).ok())
            .collect()
    };
    let c = compare(
        &EvalMesh::from_scene(&reference, &images(&reference)),
        &EvalMesh::from_scene(&lod, &images(&lod)),
        &CompareOptions::default(),
    );
    let tex = c
        .texture_chamfer
        .expect("both sides have a decoded texture");
    assert!(tex < 0.1, "re-baked texture Chamfer {tex}");
}
