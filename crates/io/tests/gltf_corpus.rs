//! Every glTF/GLB file of the corpus: read, validated, counted as the
//! corpus README says.

use std::path::Path;

use wildlod_testkit::{corpus, mesh_files, short};

/// (file, triangles per instance, skin joints, animations) from the corpus README.
const EXPECTED: &[(&str, usize, Option<usize>, usize)] = &[
    ("large/dragon_vrip.glb", 871_414, None, 0),
    ("skinned/CesiumMan.glb", 4_672, Some(19), 1),
    ("skinned/Fox/Fox.gltf", 576, Some(24), 3),
    ("skinned/RiggedFigure.glb", 256, Some(19), 1),
    ("skinned/RiggedSimple.glb", 188, Some(2), 1),
    ("skinned/SimpleSkin.gltf", 8, Some(2), 1),
    ("textured/Avocado/Avocado.gltf", 682, None, 0),
    ("textured/CesiumMilkTruck.glb", 3_624, None, 1),
    ("textured/MultiUVTest.glb", 12, None, 0),
    ("textured/sofa_03/sofa_03_1k.gltf", 8_004, None, 0),
    ("textured/tea_set_01/tea_set_01_1k.gltf", 40_296, None, 0),
];

fn is_gltf(p: &Path) -> bool {
    matches!(p.extension().and_then(|e| e.to_str()), Some("gltf" | "glb"))
}

#[test]
fn every_corpus_gltf_reads_with_the_readme_triangle_joint_and_animation_counts() {
    let Some(c) =
        corpus("every_corpus_gltf_reads_with_the_readme_triangle_joint_and_animation_counts")
    else {
        return;
    };
    let files: Vec<_> = mesh_files(&c, "")
        .into_iter()
        .filter(|p| is_gltf(p))
        .collect();
    assert_eq!(
        files.len(),
        EXPECTED.len(),
        "corpus glTF files changed: {files:?}"
    );
    for f in files {
        let name = short(&c, &f);
        let (_, tris, joints, anims) = EXPECTED
            .iter()
            .find(|e| e.0 == name)
            .unwrap_or_else(|| panic!("{name} is not in the expected table"));
        let doc = wildlod_io::read(&f).unwrap_or_else(|e| panic!("{e}"));
        doc.scene.validate().unwrap();
        let counts = doc.scene.instance_counts();
        let total: usize = doc
            .scene
            .meshes
            .iter()
            .zip(&counts)
            .map(|(m, n)| m.triangle_count() * n)
            .sum();
        assert_eq!(total, *tris, "{name}: triangles per instance");
        assert_eq!(
            doc.scene.skins.first().map(|s| s.joints.len()),
            *joints,
            "{name}: joints"
        );
        assert_eq!(doc.scene.animations.len(), *anims, "{name}: animations");
        eprintln!("{name}: ok, warnings {:?}", doc.warnings);
    }
}

mod gltf_support;

use gltf_support::{assert_same_scene, check_written};
use wildlod_io::WriteOptions;

/// Reads a corpus file, writes it as `.glb` and as `.gltf` into a fresh
/// directory, checks each output, reads it back and compares.
fn round_trip(test: &str, rel: &str) {
    let Some(c) = corpus(test) else {
        return;
    };
    let src = c.join(rel);
    let doc = wildlod_io::read(&src).unwrap_or_else(|e| panic!("{e}"));
    for ext in ["glb", "gltf"] {
        let dir = tempfile::tempdir().expect("temp dir");
        let out = dir.path().join(format!("out.{ext}"));
        let warnings = wildlod_io::write(&doc, &out, &WriteOptions::default())
            .unwrap_or_else(|e| panic!("{rel} → .{ext}: {e}"));
        assert!(warnings.is_empty(), "{rel} → .{ext}: {warnings:?}");
        check_written(&out);
        let back = wildlod_io::read(&out).unwrap_or_else(|e| panic!("{rel} → .{ext} → read: {e}"));
        assert_same_scene(&format!("{rel} via .{ext}"), &doc.scene, &back.scene);
    }
}

macro_rules! round_trips {
    ($($test:ident => $rel:expr,)*) => {$(
        #[test]
        fn $test() {
            round_trip(stringify!($test), $rel);
        }
    )*};
}

round_trips! {
    dragon_round_trips_through_glb_and_gltf => "large/dragon_vrip.glb",
    cesium_man_round_trips_through_glb_and_gltf => "skinned/CesiumMan.glb",
    fox_round_trips_through_glb_and_gltf => "skinned/Fox/Fox.gltf",
    rigged_figure_round_trips_through_glb_and_gltf => "skinned/RiggedFigure.glb",
    rigged_simple_round_trips_through_glb_and_gltf => "skinned/RiggedSimple.glb",
    simple_skin_round_trips_through_glb_and_gltf => "skinned/SimpleSkin.gltf",
    avocado_round_trips_through_glb_and_gltf => "textured/Avocado/Avocado.gltf",
    milk_truck_round_trips_through_glb_and_gltf => "textured/CesiumMilkTruck.glb",
    multi_uv_round_trips_through_glb_and_gltf => "textured/MultiUVTest.glb",
    sofa_round_trips_through_glb_and_gltf => "textured/sofa_03/sofa_03_1k.gltf",
    tea_set_round_trips_through_glb_and_gltf => "textured/tea_set_01/tea_set_01_1k.gltf",
}

#[test]
fn corpus_textures_decode_to_rgba_in_unit_range() {
    let Some(c) = corpus("corpus_textures_decode_to_rgba_in_unit_range") else {
        return;
    };
    // Embedded PNG (bufferView), external PNG, external JPEG.
    for (rel, textures) in [
        ("textured/MultiUVTest.glb", 2),
        ("skinned/Fox/Fox.gltf", 1),
        ("textured/sofa_03/sofa_03_1k.gltf", 6),
    ] {
        let doc = wildlod_io::read(c.join(rel)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(doc.scene.textures.len(), textures, "{rel}");
        let t = &doc.scene.textures[0];
        let img = wildlod_io::decode_image(&t.source).unwrap_or_else(|e| panic!("{e}"));
        assert!(img.width > 0 && img.height > 0, "{rel}");
        // 8-bit files are held as their bytes.
        assert_eq!(img.bytes.len(), (img.width * img.height) as usize);
        assert!(img.pixels.is_empty(), "{rel}");
        let texels: Vec<[f32; 4]> = (0..img.height as i64)
            .flat_map(|y| (0..img.width as i64).map(move |x| (x, y)))
            .map(|(x, y)| img.texel(x, y))
            .collect();
        assert!(texels.iter().flatten().all(|&v| (0.0..=1.0).contains(&v)));
        // A texture is not one flat color.
        assert!(texels.iter().any(|p| p != &texels[0]), "{rel}");
    }
}
