//! Hostile input and the rough edges a new user hit (issue 13): inputs that
//! are not regular files, inputs that used to take minutes, and messages
//! that named the wrong thing. Every test here failed before the fix.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::{shapes, Faces, Mesh, Node, Scene};

/// Runs wildlod, killing it after `limit`: `None` when it had to be killed.
/// The limits are far above what the runs take (they are not timings, see
/// `crates/bench/benches/hostile.rs` for those) and far below "forever".
fn wildlod_within(args: &[&str], limit: Duration) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_wildlod"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run wildlod");
    let start = Instant::now();
    loop {
        if child.try_wait().expect("poll wildlod").is_some() {
            return Some(child.wait_with_output().expect("collect output"));
        }
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn wildlod(args: &[&str]) -> Output {
    wildlod_within(args, Duration::from_secs(120))
        .unwrap_or_else(|| panic!("wildlod {args:?} did not finish in 120 s"))
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn write_scene(scene: Scene, path: &Path) {
    wildlod_io::write(&Document::from_scene(scene), path, &WriteOptions::default()).unwrap();
}

fn cube_obj(dir: &Path) -> PathBuf {
    let path = dir.join("cube.obj");
    write_scene(
        Scene::from_mesh(shapes::box_grid([0.0; 3], [1.0; 3], 4)),
        &path,
    );
    path
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
    assert!(ok, "mkfifo {}", path.display());
}

/// Files in `dir` other than `keep`.
fn files_besides(dir: &Path, keep: &[&Path]) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| !keep.contains(&p.as_path()))
        .collect()
}

#[cfg(unix)]
#[test]
fn fifo_input_is_refused_at_once_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.obj");
    mkfifo(&fifo);
    let out = dir.path().join("out.glb");
    for args in [
        vec!["info", s(&fifo)],
        vec!["simplify", s(&fifo), "-o", s(&out)],
    ] {
        let o = wildlod_within(&args, Duration::from_secs(20))
            .unwrap_or_else(|| panic!("wildlod {args:?} blocked on the FIFO"));
        assert_eq!(o.status.code(), Some(1));
        let e = stderr(&o);
        assert!(e.contains("pipe.obj") && e.contains("FIFO"), "{e}");
    }
    assert!(!out.exists());
}

#[cfg(unix)]
#[test]
fn mtllib_naming_a_fifo_is_refused_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    mkfifo(&dir.path().join("m.mtl"));
    let obj = dir.path().join("a.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
    )
    .unwrap();
    let o = wildlod_within(&["info", s(&obj)], Duration::from_secs(20))
        .expect("wildlod blocked on the FIFO named by mtllib");
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("m.mtl") && e.contains("FIFO"), "{e}");
}

#[cfg(unix)]
#[test]
fn texture_naming_a_fifo_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    mkfifo(&dir.path().join("tex.png"));
    std::fs::write(dir.path().join("m.mtl"), "newmtl x\nmap_Kd tex.png\n").unwrap();
    let obj = dir.path().join("a.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl x\nf 1/1 2/1 3/1\n",
    )
    .unwrap();
    let out = dir.path().join("out.glb");
    let o = wildlod_within(
        &["simplify", s(&obj), "-o", s(&out)],
        Duration::from_secs(20),
    )
    .expect("wildlod blocked on a texture that is a FIFO");
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("tex.png") && e.contains("FIFO"), "{e}");
    assert!(!out.exists());
}

#[cfg(unix)]
#[test]
fn gltf_buffer_that_is_a_fifo_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let gltf = dir.path().join("a.gltf");
    write_scene(Scene::from_mesh(shapes::cube()), &gltf);
    let bin = dir.path().join("a.bin");
    std::fs::remove_file(&bin).unwrap();
    mkfifo(&bin);
    let o = wildlod_within(&["info", s(&gltf)], Duration::from_secs(20))
        .expect("wildlod blocked on a buffer that is a FIFO");
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("a.bin") && e.contains("FIFO"), "{e}");
}

#[cfg(unix)]
#[test]
fn mtllib_that_is_a_symlink_loop_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink(dir.path().join("l2"), dir.path().join("loop.mtl")).unwrap();
    std::os::unix::fs::symlink(dir.path().join("loop.mtl"), dir.path().join("l2")).unwrap();
    let obj = dir.path().join("a.obj");
    std::fs::write(
        &obj,
        "mtllib loop.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
    )
    .unwrap();
    let o = wildlod(&["info", s(&obj)]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    let e = stderr(&o);
    assert!(e.contains("a.obj") && e.contains("loop.mtl"), "{e}");
}

#[test]
fn ratio_zero_keeps_the_smallest_valid_result_not_an_empty_file() {
    let dir = tempfile::tempdir().unwrap();
    // Two meshes under two nodes.
    let input = dir.path().join("two.glb");
    let mut scene = Scene::from_mesh(shapes::box_grid([0.0; 3], [1.0; 3], 4));
    scene.meshes.push(shapes::torus(12, 8, 1.0, 0.3));
    scene.nodes.push(Node {
        mesh: Some(1),
        ..Node::default()
    });
    scene.roots.push(1);
    write_scene(scene, &input);
    for (flag, value) in [("--ratio", "0"), ("--faces", "0")] {
        // One budget for the file: the file keeps geometry (a mesh may
        // go), and no node shows an empty mesh.
        let out = dir.path().join(format!("lod{}.glb", &flag[2..]));
        let o = wildlod(&["simplify", s(&input), "-o", s(&out), flag, value]);
        assert!(o.status.success(), "{}", stderr(&o));
        let doc = wildlod_io::read(&out).unwrap();
        let total: usize = doc.scene.meshes.iter().map(|m| m.triangle_count()).sum();
        assert!(
            (1..=4).contains(&total),
            "{flag} {value}: {total} triangles"
        );
        for n in &doc.scene.nodes {
            if let Some(m) = n.mesh {
                assert!(!doc.scene.meshes[m as usize].faces.is_empty());
            }
        }
        // Per mesh: each mesh keeps geometry.
        let out = dir.path().join(format!("per_mesh{}.glb", &flag[2..]));
        let o = wildlod(&[
            "simplify",
            s(&input),
            "-o",
            s(&out),
            flag,
            value,
            "--per-mesh",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let doc = wildlod_io::read(&out).unwrap();
        assert_eq!(doc.scene.meshes.len(), 2);
        for m in &doc.scene.meshes {
            let t = m.triangle_count();
            assert!(
                (1..=2).contains(&t),
                "{flag} {value} --per-mesh: a mesh kept {t} triangles"
            );
        }
    }
}

#[test]
fn missing_output_folder_is_named_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let input = cube_obj(dir.path());
    let out = dir.path().join("no_such_folder").join("lod.obj");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(
        e.contains("no_such_folder") && e.contains("does not exist") && !e.contains(".wildlod-"),
        "{e}"
    );
    // The summary line is printed after simplifying: there is none.
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
}

#[test]
fn unsupported_output_extension_fails_before_simplifying() {
    let dir = tempfile::tempdir().unwrap();
    let input = cube_obj(dir.path());
    let out = dir.path().join("lod.fbx");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("unsupported file extension"),
        "{}",
        stderr(&o)
    );
    assert!(stdout(&o).is_empty(), "simplified first: {}", stdout(&o));
}

#[test]
fn negative_ratio_gets_the_range_error_not_clap_advice() {
    let dir = tempfile::tempdir().unwrap();
    let input = cube_obj(dir.path());
    let out = dir.path().join("lod.obj");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out), "--ratio", "-1"]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("--ratio must be between 0 and 1, got -1"), "{e}");
    assert!(!e.contains("-- -1"), "{e}");
    let o = wildlod(&["simplify", s(&input), "-o", s(&out), "--error", "-0.5"]);
    assert!(stderr(&o).contains("--error must be"), "{}", stderr(&o));
}

#[test]
fn overwrite_refusal_names_the_flag_and_comes_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let input = cube_obj(dir.path());
    let before = std::fs::read(&input).unwrap();
    let o = wildlod(&["simplify", s(&input), "-o", s(&input)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("pass --overwrite"), "{}", stderr(&o));
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
    assert_eq!(std::fs::read(&input).unwrap(), before);
    // A sidecar of the input (its MTL) is protected too, with the same words.
    let mut m = shapes::quad_grid(2, 2);
    m.parts[0].material = Some(0);
    let mut scene = Scene::from_mesh(m);
    scene.materials.push(wildlod_mesh::Material {
        name: "red".into(),
        ..Default::default()
    });
    let a = dir.path().join("a.obj");
    write_scene(scene, &a);
    let mtl_before = std::fs::read(dir.path().join("a.mtl")).unwrap();
    // b.obj uses a.mtl; writing a.obj from b.obj would replace a.mtl.
    let b = dir.path().join("b.obj");
    std::fs::copy(&a, &b).unwrap();
    let o = wildlod(&["simplify", s(&b), "-o", s(&a)]);
    let e = stderr(&o);
    assert!(
        o.status.code() == Some(1) && e.contains("a.mtl") && e.contains("pass --overwrite"),
        "{e}"
    );
    assert_eq!(std::fs::read(dir.path().join("a.mtl")).unwrap(), mtl_before);
}

#[test]
fn glb_named_gltf_is_read_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("real.glb");
    write_scene(Scene::from_mesh(shapes::cube()), &glb);
    let misnamed = dir.path().join("misnamed.gltf");
    std::fs::rename(&glb, &misnamed).unwrap();
    let o = wildlod(&["info", s(&misnamed)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = stdout(&o) + &stderr(&o);
    assert!(all.contains("binary glTF (GLB) but named .gltf"), "{all}");
}

#[test]
fn simplify_help_prints_each_example_on_its_own_line() {
    let h = stdout(&wildlod(&["simplify", "--help"]));
    for example in [
        "wildlod simplify bunny.obj -o bunny_lod.obj --ratio 0.1",
        "wildlod simplify truck.glb -o truck_lod.glb --faces 2000",
        "wildlod simplify scan.ply -o scan_lod.stl --error 0.001",
    ] {
        assert!(
            h.lines().any(|l| l.trim() == example),
            "no line holds just `{example}`:\n{h}"
        );
    }
}

#[test]
fn demo_output_folder_is_git_ignored() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let ignore = std::fs::read_to_string(root.join(".gitignore")).unwrap();
    let default = "wildlod-demo";
    assert!(
        ignore.lines().any(|l| l.trim_matches('/') == default),
        ".gitignore does not ignore {default}/:\n{ignore}"
    );
    let h = stdout(&wildlod(&["demo", "--help"]));
    assert!(h.contains(default), "the default folder changed: {h}");
}

#[test]
fn gltf_output_keeps_image_names_and_stores_a_shared_image_once() {
    let dir = tempfile::tempdir().unwrap();
    let png = wildlod_fuzz_png();
    std::fs::write(dir.path().join("shared.png"), png).unwrap();
    // Two image objects (two names) pointing at one file, as exporters
    // write for a color map reused as opacity.
    let gltf = dir.path().join("in.gltf");
    write_scene(Scene::from_mesh(shapes::quad_grid(2, 2)), &gltf);
    let mut json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&gltf).unwrap()).unwrap();
    json["images"] = serde_json::json!([
        {"name": "color", "uri": "shared.png"},
        {"name": "opacity", "uri": "shared.png"}
    ]);
    json["textures"] = serde_json::json!([{"source": 0}, {"source": 1}]);
    json["materials"] = serde_json::json!([
        {"name": "a", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
        {"name": "b", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}
    ]);
    json["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
    std::fs::write(&gltf, serde_json::to_vec(&json).unwrap()).unwrap();
    let out = dir.path().join("out.glb");
    let o = wildlod(&["simplify", s(&gltf), "-o", s(&out), "--ratio", "1", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let images = glb_json(&out)["images"].clone();
    let names: Vec<&str> = images
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|i| i["name"].as_str())
        .collect();
    assert_eq!(names, ["color", "opacity"]);
    assert_eq!(
        images[0]["bufferView"], images[1]["bufferView"],
        "one image stored twice: {images}"
    );
    // From OBJ: images are named after their files.
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl a\nmap_Kd shared.png\nnewmtl b\nmap_Kd shared.png\n",
    )
    .unwrap();
    let obj = dir.path().join("t.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nusemtl a\nf 1/1 2/1 3/1\nusemtl b\nf 2/1 4/1 3/1\n",
    )
    .unwrap();
    let out = dir.path().join("obj.glb");
    let o = wildlod(&["simplify", s(&obj), "-o", s(&out), "--ratio", "1", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = glb_json(&out);
    assert_eq!(j["images"].as_array().unwrap().len(), 1, "{}", j["images"]);
    assert_eq!(j["images"][0]["name"], "shared.png");
}

/// The JSON chunk of a GLB.
fn glb_json(path: &Path) -> serde_json::Value {
    let b = std::fs::read(path).unwrap();
    let n = u32::from_le_bytes(b[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&b[20..20 + n]).unwrap()
}

/// A 1×1 PNG.
fn wildlod_fuzz_png() -> &'static [u8] {
    &[
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
        0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90,
        0x77, 0x53, 0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x08, 0xd7, 0x63, 0xf8,
        0xcf, 0xc0, 0x00, 0x00, 0x03, 0x01, 0x01, 0x00, 0x18, 0xdd, 0x8d, 0xb0, 0x00, 0x00, 0x00,
        0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
    ]
}

/// A flat convex polygon of `k` corners as the only face of an OBJ.
fn ngon_obj(dir: &Path, k: usize) -> PathBuf {
    let mut faces = Faces::new();
    faces.push(&(0..k as u32).collect::<Vec<u32>>());
    let positions = (0..k)
        .map(|i| {
            let a = i as f32 / k as f32 * std::f32::consts::TAU;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let path = dir.join("cap.obj");
    write_scene(
        Scene::from_mesh(Mesh::from_polygons(positions, faces)),
        &path,
    );
    path
}

#[test]
fn one_polygon_of_twenty_thousand_corners_simplifies_and_compares() {
    // It never finished (killed after 240 s); it now takes well under a
    // second in release. The limit only tells "finishes" from "hangs".
    let dir = tempfile::tempdir().unwrap();
    let input = ngon_obj(dir.path(), 20_000);
    let limit = Duration::from_secs(90);
    for (out, ratio) in [("lod.obj", "0.5"), ("same.glb", "1")] {
        let out = dir.path().join(out);
        let o = wildlod_within(
            &["simplify", s(&input), "-o", s(&out), "--ratio", ratio],
            limit,
        )
        .expect("simplifying one large polygon did not finish");
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stdout(&o)
                .contains("1 polygon of more than 32 corners simplified and written as pieces"),
            "{}",
            stdout(&o)
        );
        let doc = wildlod_io::read(&out).unwrap();
        let tris = doc.scene.meshes[0].triangle_count();
        let want: usize = if ratio == "1" { 19_998 } else { 9_999 };
        assert!(tris.abs_diff(want) <= 1, "{tris} triangles");
    }
    // Comparing the polygon with its triangulation went through a fan of
    // slivers whose boxes all overlap: minutes. Now it is a few samples'
    // work.
    let same = dir.path().join("same.glb");
    let o = wildlod_within(
        &["compare", s(&input), s(&same), "--samples", "20000"],
        limit,
    )
    .expect("comparing a large polygon did not finish");
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn deep_node_chain_writes_as_obj_in_linear_time() {
    // 100,000 nodes, each the child of the one before and each showing a
    // triangle: 100,000 OBJ objects of one name. Writing took time ∝
    // depth² (20,000: 12 s; 100,000: never finished).
    let depth = 100_000;
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::from_mesh(Mesh::from_triangles(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[0, 1, 2],
    ));
    scene.meshes[0].name = "leaf".into();
    scene.nodes = (0..depth)
        .map(|i| {
            let mut matrix = wildlod_mesh::IDENTITY;
            matrix[12] = 1e-3;
            Node {
                matrix,
                mesh: Some(0),
                children: if i + 1 < depth {
                    vec![i as u32 + 1]
                } else {
                    vec![]
                },
                ..Node::default()
            }
        })
        .collect();
    let input = dir.path().join("chain.glb");
    write_scene(scene, &input);
    let out = dir.path().join("chain.obj");
    let o = wildlod_within(
        &["simplify", s(&input), "-o", s(&out), "--ratio", "1", "-q"],
        Duration::from_secs(90),
    )
    .expect("writing a deep node chain as OBJ did not finish");
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("o ")).count(), depth);
    assert!(files_besides(dir.path(), &[&input, &out]).is_empty());
}
