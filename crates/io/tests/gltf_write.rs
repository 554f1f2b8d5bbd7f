//! Writing glTF: simplified and polygonal meshes, scenes built in code,
//! quantized and sparse data, kept extensions, changed materials, and
//! never overwriting an input.

mod gltf_support;

use std::path::{Path, PathBuf};

use gltf_support::{assert_same_mesh, check_written, read_bytes, triangle, Builder};
use serde_json::{json, Value};
use wildlod_io::{read, write, Document, ErrorKind, WriteOptions};
use wildlod_mesh::{
    shapes, Attribute, ComponentFormat, Faces, ImageSource, Material, Mesh, MorphChannel, Part,
    Scene, Semantic, Texture, TextureRef,
};
use wildlod_testkit::corpus;

/// Writes `doc` to `dir/name`, checks the output, reads it back.
fn write_read(doc: &Document, dir: &Path, name: &str) -> (Document, Vec<String>, Value) {
    let out = dir.join(name);
    let warnings = write(doc, &out, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let json = check_written(&out);
    let back = read(&out).unwrap_or_else(|e| panic!("{e}"));
    (back, warnings, json)
}

/// Keeps the faces `keep` says yes to, then drops unused positions and
/// values, as a simplifier's output would look.
fn drop_faces(m: &Mesh, keep: impl Fn(usize) -> bool) -> Mesh {
    let mut out = m.clone();
    out.faces = Faces::new();
    out.face_parts.clear();
    let mut corners = Vec::new();
    for f in 0..m.faces.len() {
        if keep(f) {
            out.faces.push(m.faces.face(f));
            out.face_parts.push(m.face_parts[f]);
            corners.extend(m.faces.corner_range(f));
        }
    }
    for (a, src) in out.attributes.iter_mut().zip(&m.attributes) {
        a.indices = corners.iter().map(|&c| src.indices[c]).collect();
    }
    if let (Some(s), Some(src)) = (&mut out.skinning, &m.skinning) {
        s.indices = corners.iter().map(|&c| src.indices[c]).collect();
    }
    out.compact();
    out
}

#[test]
fn half_the_faces_of_corpus_meshes_write_and_read_back_the_same() {
    let Some(c) = corpus("half_the_faces_of_corpus_meshes_write_and_read_back_the_same") else {
        return;
    };
    for rel in [
        "skinned/CesiumMan.glb",
        "textured/CesiumMilkTruck.glb",
        "skinned/Fox/Fox.gltf",
    ] {
        let mut doc = read(c.join(rel)).unwrap_or_else(|e| panic!("{e}"));
        for m in &mut doc.scene.meshes {
            *m = drop_faces(m, |f| f % 2 == 0);
        }
        doc.scene.validate().expect("valid");
        for ext in ["glb", "gltf"] {
            let dir = tempfile::tempdir().expect("temp dir");
            let (back, warnings, _) = write_read(&doc, dir.path(), &format!("half.{ext}"));
            assert!(warnings.is_empty(), "{rel}: {warnings:?}");
            for (i, (a, b)) in doc.scene.meshes.iter().zip(&back.scene.meshes).enumerate() {
                assert_same_mesh(&format!("{rel} mesh {i}"), a, b);
                // compact() left only used positions, and they keep their order.
                assert_eq!(a.positions, b.positions, "{rel} mesh {i}");
            }
            assert_eq!(doc.scene.skins, back.scene.skins);
            assert_eq!(doc.scene.animations, back.scene.animations);
        }
    }
}

#[test]
fn polygons_are_fan_triangulated_and_keep_their_corner_values() {
    let Some(c) = corpus("polygons_are_fan_triangulated_and_keep_their_corner_values") else {
        return;
    };
    let mut doc = read(c.join("textured/Avocado/Avocado.gltf")).unwrap_or_else(|e| panic!("{e}"));
    let m = &mut doc.scene.meshes[0];
    // Merge pairs of triangles sharing an edge into quads and add a
    // pentagon, as a quad-dominant simplifier might leave them.
    let mut faces = Faces::new();
    let mut corners = Vec::new();
    for f in (0..m.faces.len()).step_by(2) {
        let r = m.faces.corner_range(f);
        let mut poly: Vec<usize> = r.collect();
        if f + 1 < m.faces.len() && f % 4 == 0 {
            poly.push(m.faces.corner_range(f + 1).start);
        }
        if f == 0 {
            poly.push(m.faces.corner_range(3).start);
        }
        faces.push(&poly.iter().map(|&c| m.faces.indices[c]).collect::<Vec<_>>());
        corners.extend(poly);
    }
    let parts = vec![0; faces.len()];
    for a in &mut m.attributes {
        a.indices = corners.iter().map(|&c| a.indices[c]).collect();
    }
    m.faces = faces;
    m.face_parts = parts;
    m.validate().expect("valid polygon mesh");
    assert_eq!(m.faces.arity(0), 5);
    let expected = shapes::triangulate(m);
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, _, _) = write_read(&doc, dir.path(), "poly.glb");
    assert_same_mesh("avocado polygons", &expected, &back.scene.meshes[0]);
}

#[test]
fn empty_parts_and_empty_meshes_are_not_written() {
    let Some(c) = corpus("empty_parts_and_empty_meshes_are_not_written") else {
        return;
    };
    let mut doc = read(c.join("textured/CesiumMilkTruck.glb")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(doc.scene.meshes.len(), 2);
    assert_eq!(doc.scene.meshes[0].parts.len(), 3);
    // Part 1 loses every face; the wheels lose all of theirs.
    let m = &doc.scene.meshes[0];
    let keep: Vec<bool> = m.face_parts.iter().map(|&p| p != 1).collect();
    doc.scene.meshes[0] = drop_faces(m, |f| keep[f]);
    doc.scene.meshes[1] = drop_faces(&doc.scene.meshes[1], |_| false);
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, warnings, json) = write_read(&doc, dir.path(), "truck.gltf");
    assert!(
        warnings.iter().any(|w| w.contains("mesh 1 has no faces")),
        "{warnings:?}"
    );
    assert_eq!(json["meshes"].as_array().map(Vec::len), Some(1));
    assert_eq!(back.scene.meshes.len(), 1);
    let materials: Vec<_> = back.scene.meshes[0]
        .parts
        .iter()
        .map(|p| p.material)
        .collect();
    assert_eq!(materials, vec![Some(0), Some(2)]);
    // The nodes that instanced the wheels no longer refer to any mesh.
    assert_eq!(back.scene.instance_counts(), vec![1]);
    back.scene.validate().expect("valid");
}

/// A 2×2 PNG.
fn png_bytes() -> Vec<u8> {
    let img = image::RgbaImage::from_raw(2, 2, (0..16).map(|i| (i * 16) as u8).collect())
        .expect("2×2 pixels");
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("encode png");
    out.into_inner()
}

/// A scene as the OBJ reader makes it: quads with UVs, a textured
/// material whose image is a file.
fn obj_like_scene(texture: &Path) -> Scene {
    let mut grid = shapes::quad_grid(3, 2);
    grid.name = "grid".into();
    grid.parts = vec![Part {
        name: "g0".into(),
        material: Some(0),
    }];
    let mut scene = Scene::from_mesh(grid);
    scene.materials.push(Material {
        name: "paint".into(),
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        roughness: 0.5,
        ..Material::default()
    });
    scene.textures.push(Texture {
        name: "albedo".into(),
        source: ImageSource::Path(texture.to_path_buf()),
        sampler: Default::default(),
    });
    scene
}

#[test]
fn obj_like_scene_with_quads_and_a_texture_file_writes_valid_glb_and_gltf() {
    let src = tempfile::tempdir().expect("temp dir");
    let png = src.path().join("albedo.png");
    std::fs::write(&png, png_bytes()).expect("write png");
    let scene = obj_like_scene(&png);
    let doc = Document::from_scene(scene.clone());
    let expected = shapes::triangulate(&scene.meshes[0]);
    for ext in ["glb", "gltf"] {
        let out = tempfile::tempdir().expect("temp dir");
        let (back, warnings, json) = write_read(&doc, out.path(), &format!("grid.{ext}"));
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(back.scene.meshes[0].triangle_count(), 12);
        assert_same_mesh(ext, &expected, &back.scene.meshes[0]);
        assert_eq!(back.scene.materials, scene.materials);
        assert_eq!(back.scene.meshes[0].parts, scene.meshes[0].parts);
        assert_eq!(back.scene.meshes[0].name, "grid");
        assert_eq!(back.scene.textures[0].name, "albedo");
        let img = &json["images"][0];
        match ext {
            "glb" => {
                assert!(img.get("bufferView").is_some(), "{img}");
                assert_eq!(img["mimeType"], "image/png");
                assert!(matches!(&back.scene.textures[0].source,
                    ImageSource::Embedded { bytes, .. } if *bytes == png_bytes()));
            }
            _ => {
                assert_eq!(img["uri"], "albedo.png");
                assert_eq!(
                    std::fs::read(out.path().join("albedo.png")).expect("copied image"),
                    png_bytes()
                );
            }
        }
    }
}

#[test]
fn texture_wrap_modes_are_written_as_samplers_and_read_back() {
    let src = tempfile::tempdir().expect("temp dir");
    let png = src.path().join("albedo.png");
    std::fs::write(&png, png_bytes()).expect("write png");
    let mut scene = obj_like_scene(&png);
    scene.textures[0].sampler = wildlod_mesh::Sampler {
        wrap_u: wildlod_mesh::Wrap::ClampToEdge,
        wrap_v: wildlod_mesh::Wrap::MirroredRepeat,
    };
    let out = tempfile::tempdir().expect("temp dir");
    let (back, _, json) = write_read(&Document::from_scene(scene.clone()), out.path(), "g.gltf");
    assert_eq!(json["samplers"][0]["wrapS"], 33071);
    assert_eq!(json["samplers"][0]["wrapT"], 33648);
    assert_eq!(back.scene.textures[0].sampler, scene.textures[0].sampler);
    // The default sampler needs no sampler object at all.
    let plain = obj_like_scene(&png);
    let out = tempfile::tempdir().expect("temp dir");
    let (_, _, json) = write_read(&Document::from_scene(plain), out.path(), "g.gltf");
    assert!(json.get("samplers").is_none(), "{json}");
}

#[test]
fn scene_without_nodes_gets_a_root_per_mesh() {
    let scene = Scene {
        meshes: vec![shapes::cube(), shapes::torus(6, 4, 1.0, 0.25)],
        ..Scene::default()
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, _, _) = write_read(&Document::from_scene(scene), dir.path(), "two.glb");
    assert_eq!(back.scene.roots.len(), 2);
    assert_eq!(back.scene.instance_counts(), vec![1, 1]);
    assert_eq!(back.scene.meshes[0].triangle_count(), 12);
}

#[test]
fn writing_never_overwrites_the_source_or_its_files() {
    let Some(c) = corpus("writing_never_overwrites_the_source_or_its_files") else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let avocado = c.join("textured/Avocado");
    for f in [
        "Avocado.bin",
        "Avocado_baseColor.png",
        "Avocado_normal.png",
        "Avocado_roughnessMetallic.png",
    ] {
        std::fs::copy(avocado.join(f), dir.path().join(f)).expect("copy");
    }
    // Named unlike its buffer, so that an output can collide with the buffer.
    let src = dir.path().join("model.gltf");
    std::fs::copy(avocado.join("Avocado.gltf"), &src).expect("copy");
    let before = std::fs::read(&src).expect("read");
    let bin_before = std::fs::read(dir.path().join("Avocado.bin")).expect("read");
    let doc = read(&src).unwrap_or_else(|e| panic!("{e}"));
    let e = write(&doc, &src, &WriteOptions::default()).expect_err("source");
    assert!(matches!(e.kind, ErrorKind::WouldOverwriteInput(_)), "{e}");
    // Avocado.gltf would need Avocado.bin beside it: the source's buffer.
    let e = write(
        &doc,
        dir.path().join("Avocado.gltf"),
        &WriteOptions::default(),
    )
    .expect_err("buffer");
    assert!(
        matches!(&e.kind, ErrorKind::WouldOverwriteInput(p) if p.ends_with("Avocado.bin")),
        "{e}"
    );
    assert!(!dir.path().join("Avocado.gltf").exists(), "nothing written");
    assert_eq!(std::fs::read(&src).expect("read"), before);
    assert_eq!(
        std::fs::read(dir.path().join("Avocado.bin")).expect("read"),
        bin_before
    );
    // Beside the source under another name: images keep their URIs and
    // are not copied.
    let (back, _, json) = write_read(&doc, dir.path(), "lod.gltf");
    assert_eq!(json["images"][0]["uri"], "Avocado_baseColor.png");
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        vec![
            "Avocado.bin",
            "Avocado_baseColor.png",
            "Avocado_normal.png",
            "Avocado_roughnessMetallic.png",
            "lod.bin",
            "lod.gltf",
            "model.gltf"
        ]
    );
    assert_eq!(back.scene.textures, doc.scene.textures);
}

#[test]
fn images_in_an_existing_subdirectory_keep_their_relative_path() {
    let Some(c) = corpus("images_in_an_existing_subdirectory_keep_their_relative_path") else {
        return;
    };
    let doc = read(c.join("textured/sofa_03/sofa_03_1k.gltf")).unwrap_or_else(|e| panic!("{e}"));
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::create_dir(dir.path().join("textures")).expect("mkdir");
    let (back, _, json) = write_read(&doc, dir.path(), "sofa.gltf");
    assert_eq!(json["images"][0]["uri"], "textures/sofa_03_nor_gl_1k.jpg");
    // Two images share one file: it is copied once.
    assert_eq!(json["images"][1]["uri"], json["images"][3]["uri"]);
    assert!(dir.path().join("textures/sofa_03_diff_1k.jpg").is_file());
    for (a, b) in doc.scene.textures.iter().zip(&back.scene.textures) {
        assert_eq!(
            gltf_support::image_bytes(&a.source),
            gltf_support::image_bytes(&b.source)
        );
    }
}

/// A triangle with quantized attributes of every kind.
fn quantized() -> Builder {
    let mut b = Builder::new();
    let pos = b.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let acc =
        |b: &mut Builder, bytes: &[u8], stride: Option<usize>, ct: u32, ty: &str, norm: bool| {
            let v = b.view(bytes, stride);
            b.accessor(Some(v), ct, 3, ty, json!({ "normalized": norm }))
        };
    let uv: Vec<u8> = [0u16, 0, 65535, 0, 0, 32768]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let uv = acc(&mut b, &uv, None, 5123, "VEC2", true);
    // VEC3 of bytes: 3-byte elements padded to a 4-byte stride.
    let normal = acc(
        &mut b,
        &[0, 0, 127, 0, 0, 0, 128, 0, 127, 0, 0, 0],
        Some(4),
        5120,
        "VEC3",
        true,
    );
    let color = acc(
        &mut b,
        &[255, 0, 0, 0, 0, 255, 0, 0, 10, 20, 30, 0],
        Some(4),
        5121,
        "VEC3",
        true,
    );
    let joints = acc(
        &mut b,
        &[0, 1, 0, 0, 1, 0, 0, 0, 2, 1, 0, 0],
        None,
        5121,
        "VEC4",
        false,
    );
    let weights = acc(
        &mut b,
        &[255, 0, 0, 0, 128, 127, 0, 0, 85, 85, 85, 0],
        None,
        5121,
        "VEC4",
        true,
    );
    let idx = b.indices(&[0, 1, 2]);
    b.mesh(json!([{
        "attributes": {"POSITION": pos, "TEXCOORD_0": uv, "NORMAL": normal, "COLOR_0": color,
                       "JOINTS_0": joints, "WEIGHTS_0": weights},
        "indices": idx
    }]));
    b.json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    b.json["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    b
}

#[test]
fn quantized_attributes_are_normalized_and_written_back_in_their_encoding() {
    let doc = read_bytes("q.glb", &quantized().glb()).unwrap_or_else(|e| panic!("{e}"));
    let m = &doc.scene.meshes[0];
    let fmt = |s: Semantic| m.attribute(&s).map(|a| a.format);
    assert_eq!(fmt(Semantic::TexCoord(0)), Some(ComponentFormat::U16Norm));
    assert_eq!(fmt(Semantic::Normal), Some(ComponentFormat::I8Norm));
    assert_eq!(fmt(Semantic::Color(0)), Some(ComponentFormat::U8Norm));
    let skin = m.skinning.as_ref().expect("skinned");
    assert_eq!(
        (skin.joint_format, skin.weight_format),
        (ComponentFormat::U8, ComponentFormat::U8Norm)
    );
    let uv = m.attribute(&Semantic::TexCoord(0)).expect("uv");
    assert_eq!(uv.value(1), &[1.0, 0.0]);
    let n = m.attribute(&Semantic::Normal).expect("normal");
    // -127 and -128 both mean -1.
    assert_eq!(n.value(1), &[0.0, 0.0, -1.0]);
    assert_eq!(skin.entry(2).0, &[2, 1, 0, 0]);

    let dir = tempfile::tempdir().expect("temp dir");
    for ext in ["glb", "gltf"] {
        let (back, _, json) = write_read(&doc, dir.path(), &format!("q.{ext}"));
        assert_same_mesh(ext, m, &back.scene.meshes[0]);
        assert_eq!(json["extensionsRequired"], json!(["KHR_mesh_quantization"]));
        let prim = &json["meshes"][0]["primitives"][0]["attributes"];
        let accessor =
            |name: &str| &json["accessors"][prim[name].as_u64().expect("index") as usize];
        assert_eq!(accessor("NORMAL")["componentType"], 5120);
        assert_eq!(accessor("COLOR_0")["componentType"], 5121);
        let view = accessor("COLOR_0")["bufferView"].as_u64().expect("view") as usize;
        assert_eq!(json["bufferViews"][view]["byteStride"], 4);
        assert_eq!(accessor("WEIGHTS_0")["normalized"], true);
    }
}

#[test]
fn quantized_encodings_need_the_extension_otherwise_floats_are_written() {
    // A scene from elsewhere carrying an i8 normal hint: core glTF only
    // allows float normals.
    let mut m = Mesh::from_triangles(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2]);
    m.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values: [0.0, 0.0, 1.0].repeat(3),
        indices: vec![0, 1, 2],
        format: ComponentFormat::I8Norm,
    });
    // And UVs outside [0, 1], which a normalized u16 cannot hold.
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: vec![0.0, 0.0, 2.0, 0.0, 0.0, 1.0],
        indices: vec![0, 1, 2],
        format: ComponentFormat::U16Norm,
    });
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, _, json) = write_read(
        &Document::from_scene(Scene::from_mesh(m)),
        dir.path(),
        "f.glb",
    );
    assert!(json.get("extensionsUsed").is_none());
    for a in &back.scene.meshes[0].attributes {
        assert_eq!(a.format, ComponentFormat::F32, "{:?}", a.semantic);
    }
    let uv = back.scene.meshes[0]
        .attribute(&Semantic::TexCoord(0))
        .expect("uv");
    assert_eq!(uv.value(1), &[2.0, 0.0]);
}

#[test]
fn sparse_accessors_override_their_base_values() {
    let mut b = triangle();
    let si = b.view(&1u16.to_le_bytes(), None);
    let sv = b.view(
        &[5.0f32, 5.0, 5.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
        None,
    );
    b.json["accessors"][0]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": si, "componentType": 5123},
        "values": {"bufferView": sv}
    });
    b.json["accessors"][0]["max"] = json!([5.0, 5.0, 5.0]);
    let doc = read_bytes("s.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        doc.scene.meshes[0].positions,
        vec![[0.0; 3], [5.0; 3], [0.0, 1.0, 0.0]]
    );
}

#[test]
fn strips_and_fans_become_triangles_with_the_first_winding() {
    // glTF 2.0 §3.7.2.1: strip triangle i is (i, i + 1 + i % 2, i + 2 - i % 2),
    // fan triangle i is (i + 1, i + 2, 0).
    for (mode, expected) in [(5, vec![0, 1, 2, 1, 3, 2]), (6, vec![1, 2, 0, 2, 3, 0])] {
        let mut b = Builder::new();
        let pos = b.floats(
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
            "VEC3",
        );
        b.mesh(json!([{"attributes": {"POSITION": pos}, "mode": mode}]));
        let doc = read_bytes("strip.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(doc.scene.meshes[0].faces.indices, expected, "mode {mode}");
    }
}

#[test]
fn point_primitives_are_kept_verbatim_with_a_warning() {
    let mut b = triangle();
    let pts = b.floats(&[7.0, 8.0, 9.0, 1.0, 2.0, 3.0], "VEC3");
    b.json["meshes"][0]["primitives"]
        .as_array_mut()
        .expect("primitives")
        .push(json!({"attributes": {"POSITION": pts}, "mode": 0, "extras": {"kind": "dots"}}));
    let doc = read_bytes("p.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        doc.warnings.iter().any(|w| w.contains("points")),
        "{:?}",
        doc.warnings
    );
    assert_eq!(doc.scene.meshes[0].parts.len(), 1);
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("p.glb");
    write(&doc, &out, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    check_written(&out);
    let g = gltf::Gltf::from_slice(&std::fs::read(&out).expect("read")).expect("valid");
    let prim = g
        .meshes()
        .next()
        .expect("mesh")
        .primitives()
        .nth(1)
        .expect("points");
    assert_eq!(prim.mode(), gltf::mesh::Mode::Points);
    let reader = prim.reader(|_| g.blob.as_deref());
    let points: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
    assert_eq!(points, vec![[7.0, 8.0, 9.0], [1.0, 2.0, 3.0]]);
    assert_eq!(
        prim.extras().as_ref().map(|r| r.get()),
        Some(r#"{"kind":"dots"}"#)
    );
}

#[test]
fn morph_targets_keep_their_deltas_weights_and_names() {
    let mut b = triangle();
    let d = b.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 3.0], "VEC3");
    // A second target of zeros: an accessor without a buffer view.
    let z = b.accessor(
        None,
        5126,
        3,
        "VEC3",
        json!({"min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, 0.0]}),
    );
    b.json["meshes"][0]["primitives"][0]["targets"] = json!([{"POSITION": d}, {"POSITION": z}]);
    b.json["meshes"][0]["weights"] = json!([0.5, 0.0]);
    b.json["meshes"][0]["extras"] = json!({"targetNames": ["up", "none"]});
    let doc = read_bytes("m.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    let m = &doc.scene.meshes[0];
    let up = m
        .attribute(&Semantic::Morph {
            target: 0,
            channel: MorphChannel::Position,
        })
        .expect("target 0");
    assert_eq!(up.value(2), &[0.0, 0.0, 3.0]);
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, _, json) = write_read(&doc, dir.path(), "m.gltf");
    assert_same_mesh("morph", m, &back.scene.meshes[0]);
    assert_eq!(json["meshes"][0]["weights"], json!([0.5, 0.0]));
    assert_eq!(
        json["meshes"][0]["extras"]["targetNames"],
        json!(["up", "none"])
    );
    let t = json["meshes"][0]["primitives"][0]["targets"][0]["POSITION"]
        .as_u64()
        .expect("index");
    assert_eq!(json["accessors"][t as usize]["max"], json!([0.0, 0.0, 3.0]));
}

#[test]
fn extensions_extras_cameras_and_samplers_survive_a_round_trip() {
    let mut b = triangle();
    b.json["extensionsUsed"] = json!([
        "KHR_lights_punctual",
        "KHR_materials_emissive_strength",
        "EXT_unknown"
    ]);
    b.json["extensions"] = json!({"KHR_lights_punctual": {"lights": [{"type": "point"}]}});
    b.json["nodes"][0]["extensions"] = json!({"KHR_lights_punctual": {"light": 0}});
    b.json["nodes"][0]["extras"] = json!({"id": 42});
    b.json["cameras"] =
        json!([{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]);
    b.json["nodes"]
        .as_array_mut()
        .expect("nodes")
        .push(json!({"camera": 0, "name": "cam"}));
    b.json["scenes"][0]["nodes"] = json!([0, 1]);
    b.json["materials"] = json!([{
        "name": "glow",
        "emissiveFactor": [1.0, 0.5, 0.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}},
        "extras": {"note": "kept"}
    }]);
    b.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    b.json["meshes"][0]["primitives"][0]["extras"] = json!({"prim": true});
    b.json["samplers"] = json!([{"wrapS": 33071}]);
    b.json["asset"]["copyright"] = json!("someone");
    b.json["extras"] = json!({"root": [1, 2]});
    let src = b.json.clone();
    let doc = read_bytes("x.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    let dir = tempfile::tempdir().expect("temp dir");
    for ext in ["glb", "gltf"] {
        let (_, _, json) = write_read(&doc, dir.path(), &format!("x.{ext}"));
        for key in [
            "extensions",
            "cameras",
            "materials",
            "samplers",
            "extras",
            "nodes",
            "scenes",
        ] {
            assert_eq!(json[key], src[key], "{ext}: {key}");
        }
        // The asset keeps its properties; the generator is now wildlod.
        let mut asset = src["asset"].clone();
        asset["generator"] = json!(concat!("wildlod ", env!("CARGO_PKG_VERSION")));
        assert_eq!(json["asset"], asset, "{ext}");
        assert_eq!(
            json["meshes"][0]["primitives"][0]["extras"],
            json!({"prim": true})
        );
        // Extensions no object uses any more are no longer declared;
        // unknown ones used nowhere go too.
        assert_eq!(
            json["extensionsUsed"],
            json!(["KHR_lights_punctual", "KHR_materials_emissive_strength"])
        );
    }
}

#[test]
fn changed_materials_and_textures_are_written_from_the_scene() {
    let Some(c) = corpus("changed_materials_and_textures_are_written_from_the_scene") else {
        return;
    };
    let mut doc = read(c.join("textured/Avocado/Avocado.gltf")).unwrap_or_else(|e| panic!("{e}"));
    doc.scene.materials[0].base_color = [1.0, 0.0, 0.0, 1.0];
    doc.scene.textures[0].source = ImageSource::Embedded {
        bytes: png_bytes(),
        mime_type: "image/png".into(),
    };
    let dir = tempfile::tempdir().expect("temp dir");
    for ext in ["glb", "gltf"] {
        let (back, _, json) = write_read(&doc, dir.path(), &format!("a.{ext}"));
        assert_eq!(back.scene.materials, doc.scene.materials, "{ext}");
        assert_eq!(
            json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"],
            json!([1.0, 0.0, 0.0, 1.0])
        );
        assert_eq!(back.scene.textures.len(), 3);
        for (a, b) in doc.scene.textures.iter().zip(&back.scene.textures) {
            assert_eq!(
                gltf_support::image_bytes(&a.source),
                gltf_support::image_bytes(&b.source)
            );
        }
    }
}

#[test]
fn a_changed_scene_graph_is_written_from_the_scene_with_a_warning() {
    let Some(c) = corpus("a_changed_scene_graph_is_written_from_the_scene_with_a_warning") else {
        return;
    };
    let mut doc = read(c.join("textured/CesiumMilkTruck.glb")).unwrap_or_else(|e| panic!("{e}"));
    doc.scene.nodes[0].matrix[12] = 3.0;
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, warnings, _) = write_read(&doc, dir.path(), "moved.glb");
    assert!(
        warnings.iter().any(|w| w.contains("scene graph")),
        "{warnings:?}"
    );
    assert_eq!(back.scene.nodes, doc.scene.nodes);
    assert_eq!(back.scene.materials, doc.scene.materials);
    assert!(back.scene.animations.is_empty());
    for (a, b) in doc.scene.meshes.iter().zip(&back.scene.meshes) {
        assert_same_mesh("truck", a, b);
    }
}

#[test]
fn non_standard_attribute_names_are_read_as_custom_and_written_with_an_underscore() {
    let mut b = triangle();
    let ids = b.floats(&[1.0, 2.0, 3.0], "SCALAR");
    b.json["meshes"][0]["primitives"][0]["attributes"]["BATCHID"] = json!(ids);
    let doc = read_bytes("c.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    assert!(doc.warnings.iter().any(|w| w.contains("BATCHID")));
    let a = doc.scene.meshes[0]
        .attribute(&Semantic::Custom("BATCHID".into()))
        .expect("custom");
    assert_eq!(a.values, vec![1.0, 2.0, 3.0]);
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, _, json) = write_read(&doc, dir.path(), "c.glb");
    assert!(json["meshes"][0]["primitives"][0]["attributes"]
        .get("_BATCHID")
        .is_some());
}

#[test]
fn primitives_sharing_vertex_accessors_share_vertices() {
    // Two primitives over the same four vertices with different indices
    // and materials (a common exporter layout).
    let mut b = Builder::new();
    let pos = b.floats(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
        "VEC3",
    );
    let i0 = b.indices(&[0, 1, 2]);
    let i1 = b.indices(&[2, 1, 3]);
    b.json["materials"] = json!([{}, {}]);
    b.mesh(json!([
        {"attributes": {"POSITION": pos}, "indices": i0, "material": 0},
        {"attributes": {"POSITION": pos}, "indices": i1, "material": 1}
    ]));
    let doc = read_bytes("s.glb", &b.glb()).unwrap_or_else(|e| panic!("{e}"));
    let m = &doc.scene.meshes[0];
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.faces.indices, vec![0, 1, 2, 2, 1, 3]);
    assert_eq!(m.face_parts, vec![0, 1]);
}

#[test]
fn outputs_are_byte_identical_across_runs() {
    let Some(c) = corpus("outputs_are_byte_identical_across_runs") else {
        return;
    };
    let doc = read(c.join("skinned/CesiumMan.glb")).unwrap_or_else(|e| panic!("{e}"));
    let dir = tempfile::tempdir().expect("temp dir");
    let mut outs: Vec<Vec<u8>> = Vec::new();
    for i in 0..2 {
        let p: PathBuf = dir.path().join(format!("{i}.glb"));
        write(&doc, &p, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        outs.push(std::fs::read(&p).expect("read"));
    }
    assert!(outs[0] == outs[1]);
}

/// The triangle with a material whose base color texture is `image`.
fn textured_triangle(image: Value) -> Builder {
    let mut b = triangle();
    b.json["images"] = json!([image]);
    b.json["textures"] = json!([{"source": 0}]);
    b.json["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    b.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    b
}

#[test]
fn data_uri_images_are_embedded_in_glb_and_kept_in_gltf() {
    use base64::Engine;
    let uri = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png_bytes())
    );
    let b = textured_triangle(json!({ "uri": uri }));
    let doc = read_bytes("d.gltf", &b.gltf_embedded()).unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(&doc.scene.textures[0].source,
        ImageSource::Embedded { bytes, mime_type } if *bytes == png_bytes() && mime_type == "image/png"));
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, _, json) = write_read(&doc, dir.path(), "d.glb");
    assert_eq!(json["images"][0]["mimeType"], "image/png");
    assert!(json["images"][0].get("uri").is_none());
    assert_eq!(back.scene.textures, doc.scene.textures);
    let (back, _, json) = write_read(&doc, dir.path(), "d.gltf");
    assert_eq!(json["images"][0]["uri"], json!(uri));
    assert_eq!(back.scene.textures, doc.scene.textures);
}

#[test]
fn a_missing_image_file_is_a_warning_and_its_uri_is_kept() {
    let b = textured_triangle(json!({"uri": "gone.png"}));
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("t.gltf"), b.gltf_embedded()).expect("write");
    let doc = read(dir.path().join("t.gltf")).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        doc.warnings
            .iter()
            .any(|w| w.contains("image 0") && w.contains("gone.png")),
        "{:?}",
        doc.warnings
    );
    let out = tempfile::tempdir().expect("temp dir");
    for ext in ["glb", "gltf"] {
        let p = out.path().join(format!("t.{ext}"));
        let warnings = write(&doc, &p, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            warnings.iter().any(|w| w.contains("gone.png")),
            "{warnings:?}"
        );
        let json = check_written(&p);
        assert_eq!(json["images"][0]["uri"], "gone.png");
    }
}

#[test]
fn animations_of_a_scene_built_in_code_are_written_from_their_tracks() {
    use wildlod_mesh::{Animation, Interpolation, Node, Track, TrackPath, IDENTITY};
    // A cube under a node moved by (0, 2, 0) that turns 90° about y in
    // three keys, and slides in two keys of the same times' first and last.
    let mut scene = Scene::from_mesh(shapes::cube());
    let mut moved = IDENTITY;
    moved[13] = 2.0;
    scene.nodes.push(Node {
        name: "spinner".into(),
        matrix: moved,
        children: vec![0],
        ..Node::default()
    });
    scene.roots = vec![1];
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let s = (std::f32::consts::PI / 8.0).sin();
    let c = (std::f32::consts::PI / 8.0).cos();
    scene.animations.push(Animation {
        name: "spin".into(),
        channels: 2,
        duration: 1.0,
        tracks: vec![
            Track {
                node: 1,
                path: TrackPath::Rotation,
                interpolation: Interpolation::Linear,
                times: vec![0.0, 0.5, 1.0],
                values: vec![0.0, 0.0, 0.0, 1.0, 0.0, s, 0.0, c, 0.0, h, 0.0, h],
            },
            Track {
                node: 1,
                path: TrackPath::Translation,
                interpolation: Interpolation::Step,
                times: vec![0.0, 1.0],
                values: vec![0.0, 2.0, 0.0, 1.0, 2.0, 0.0],
            },
        ],
    });
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, warnings, json) =
        write_read(&Document::from_scene(scene.clone()), dir.path(), "spin.glb");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(back.scene.animations, scene.animations);
    assert_eq!(back.scene.nodes, scene.nodes);
    // The animated node is written as TRS (glTF forbids a matrix there).
    let node = &json["nodes"][1];
    assert!(node.get("matrix").is_none(), "{node}");
    assert_eq!(node["translation"], json!([0.0, 2.0, 0.0]));
    // Key times are bounded, as glTF requires of animation inputs.
    let input = json["animations"][0]["samplers"][0]["input"]
        .as_u64()
        .expect("input");
    assert_eq!(json["accessors"][input as usize]["max"], json!([1.0]));
}

#[test]
fn tracks_gltf_cannot_hold_are_left_out_with_a_warning() {
    use wildlod_mesh::{Animation, Interpolation, Track, TrackPath};
    let mut scene = Scene::from_mesh(shapes::cube());
    scene.animations.push(Animation {
        name: "broken".into(),
        channels: 1,
        duration: 1.0,
        tracks: vec![Track {
            node: 0,
            path: TrackPath::Scale,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 1.0],
            values: vec![1.0; 5],
        }],
    });
    let dir = tempfile::tempdir().expect("temp dir");
    let (back, warnings, _) = write_read(&Document::from_scene(scene), dir.path(), "b.glb");
    assert!(back.scene.animations.is_empty());
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("track 0") && w.contains("5 values")),
        "{warnings:?}"
    );
}

/// Signed area along +z of every triangle of `m` (whose faces are
/// triangles), by the triangle's corner positions.
fn areas_along_z(m: &Mesh) -> Vec<f64> {
    (0..m.faces.len())
        .map(|t| {
            let [a, b, c] =
                [0, 1, 2].map(|i| m.positions[m.faces.face(t)[i] as usize].map(f64::from));
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .collect()
}

/// Non-convex polygons (an L-shaped wall face from the corner that cannot
/// see the far arm, a letter-like star of 24 corners), as architecture and
/// CAD OBJ exports write them, facing +z. Written as glTF or STL, which
/// draw triangles, they must cover their outlines exactly: no triangle
/// turned over (the fan from the first corner folds both, drawing area
/// outside the outline), and the areas adding up to the outlines'.
#[test]
fn non_convex_polygons_are_written_as_triangles_covering_their_outline() {
    let l_shape = [
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 0.0],
    ];
    let star: Vec<[f32; 2]> = (0..24)
        .map(|i| {
            let a = i as f32 / 24.0 * std::f32::consts::TAU;
            let r = if i % 2 == 0 { 1.0 } else { 0.3 };
            [4.0 + r * a.cos(), r * a.sin()]
        })
        .collect();
    let mut positions = Vec::new();
    let mut faces = Faces::new();
    for poly in [&l_shape[..], &star[..]] {
        let base = positions.len() as u32;
        positions.extend(poly.iter().map(|p| [p[0], p[1], 0.0]));
        faces.push(&(base..base + poly.len() as u32).collect::<Vec<u32>>());
    }
    // L: 3; star: 24 corners, half of them at radius 1 around (4, 0).
    let outline = 3.0 + 24.0 * 0.5 * 1.0 * 0.3 * (std::f64::consts::TAU / 24.0).sin();
    let scene = Scene::from_mesh(Mesh::from_polygons(positions, faces));
    let dir = tempfile::tempdir().expect("temp dir");
    for ext in ["glb", "stl"] {
        let (back, _, _) = if ext == "glb" {
            write_read(
                &Document::from_scene(scene.clone()),
                dir.path(),
                "outline.glb",
            )
        } else {
            let out = dir.path().join("outline.stl");
            write(
                &Document::from_scene(scene.clone()),
                &out,
                &WriteOptions::default(),
            )
            .unwrap_or_else(|e| panic!("{e}"));
            (
                read(&out).unwrap_or_else(|e| panic!("{e}")),
                Vec::new(),
                Value::Null,
            )
        };
        let m = &back.scene.meshes[0];
        assert_eq!(m.triangle_count(), 4 + 22, "{ext}");
        let areas = areas_along_z(m);
        assert!(areas.iter().all(|&a| a >= 0.0), "{ext}: {areas:?}");
        let total: f64 = areas.iter().sum();
        assert!(
            (total - outline).abs() < 1e-5,
            "{ext}: {total} against {outline}"
        );
    }
}
