//! The generated scenes: each is valid, deterministic, survives a `.glb`
//! round trip through `wildlod_io`, passes the Khronos validator where it
//! can run, and has the property it is documented to have.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::process::Command;

use glam::DVec3;
use wildlod_io::{Document, WriteOptions};
use wildlod_mesh::disjoint_sets::DisjointSets;
use wildlod_mesh::{Mesh, Scene, Semantic, ABSENT};
use wildlod_testkit::scenes::{self, OUTLIER_HEIGHT, TUBE_LENGTH};

fn all() -> Vec<(&'static str, Scene)> {
    vec![
        ("house", scenes::house(false)),
        ("house_textured", scenes::house(true)),
        ("filleted_block", scenes::filleted_block()),
        ("flat_tiling", scenes::flat_tiling(7)),
        ("city_block", scenes::city_block()),
        ("bent_tube", scenes::bent_tube()),
        ("outlier_terrain", scenes::outlier_terrain(64, 3)),
        ("uv_fold_mesh", scenes::uv_fold_mesh()),
        ("double_sided_sheet", scenes::double_sided_sheet()),
        ("morph_sphere", scenes::morph_sphere(16, 5)),
        ("foliage_tree", scenes::foliage_tree(200)),
        ("chain_link_fence", scenes::chain_link_fence()),
        ("decal_wall", scenes::decal_wall()),
    ]
}

#[test]
fn the_decals_are_separate_grids_two_millimetres_in_front_of_the_wall() {
    let s = scenes::decal_wall();
    let m = &s.meshes[0];
    let mut sets = DisjointSets::new(m.positions.len());
    for f in m.faces.iter() {
        for w in f.windows(2) {
            sets.union(w[0], w[1]);
        }
    }
    let roots: HashSet<u32> = m.faces.iter().map(|f| sets.find(f[0])).collect();
    assert_eq!(roots.len(), 1 + 24, "the wall and one component per decal");
    assert_eq!(m.parts.len(), 2);
    let mut decal_vertices = 0;
    for (f, ids) in m.faces.iter().enumerate() {
        let lift = if m.face_parts[f] == 1 {
            decal_vertices += ids.len();
            scenes::DECAL_GAP
        } else {
            0.0
        };
        for &v in ids {
            let p = m.positions[v as usize].map(f64::from);
            let z = scenes::decal_wall_height(p[0], p[1]) + lift;
            assert!((p[2] - z).abs() < 1e-6, "{p:?} against {z}");
        }
    }
    assert!(decal_vertices > 24 * 4 * 9);
}

#[test]
fn the_fence_is_an_opaque_wire_mesh_over_transparent_texels() {
    use wildlod_mesh::AlphaMode;
    let s = scenes::chain_link_fence();
    assert_eq!(s.meshes[0].faces.len(), 2 * 96 * 16);
    let m = &s.materials[0];
    assert_eq!((m.alpha_mode, m.alpha_cutoff), (AlphaMode::Mask, 0.5));
    let wildlod_mesh::ImageSource::Embedded { bytes, .. } = &s.textures[0].source else {
        panic!("embedded image");
    };
    let img = image::load_from_memory(bytes).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (1024, 256));
    // Alpha is 0 or 255; wires 3 texels of every 24 along both
    // diagonals. x + y and x − y have one parity: on even diagonals 2 of
    // 12 residues are wire in each family, on odd ones 1 of 12, so
    // 1 − ((10/12)² + (11/12)²) / 2 = 67/288 of the texels are opaque.
    let opaque = img.pixels().filter(|p| p[3] == 255).count();
    assert!(img.pixels().all(|p| p[3] == 0 || p[3] == 255));
    let expected = 67.0 / 288.0;
    let got = opaque as f64 / (1024.0 * 256.0);
    assert!((got - expected).abs() < 1e-3, "{got} {expected}");
}

#[test]
fn the_tree_is_a_trunk_and_branches_and_one_card_per_leaf_all_on_one_image() {
    use wildlod_mesh::AlphaMode;
    let s = scenes::foliage_tree(200);
    let m = &s.meshes[0];
    // Trunk and four branches, then two triangles per card.
    let bark = 16 * 2 * (12 + 4 * 6);
    assert_eq!(m.faces.len(), bark + 2 * 200);
    let mut sets = DisjointSets::new(m.positions.len());
    for f in m.faces.iter() {
        for w in f.windows(2) {
            sets.union(w[0], w[1]);
        }
    }
    let roots: HashSet<u32> = (0..m.positions.len() as u32)
        .map(|v| sets.find(v))
        .collect();
    assert_eq!(roots.len(), 5 + 200, "one component per limb and card");
    // Every card's UVs span the whole image once: the image repeats.
    let uv = m.attribute(&Semantic::TexCoord(0)).unwrap();
    for f in bark..m.faces.len() {
        let start = m.faces.offsets[f] as usize;
        let us: Vec<&[f32]> = (start..start + 3)
            .map(|c| uv.corner_value(c).unwrap())
            .collect();
        let span = |k: usize| {
            let lo = us.iter().map(|u| u[k]).fold(f32::INFINITY, f32::min);
            let hi = us.iter().map(|u| u[k]).fold(f32::NEG_INFINITY, f32::max);
            hi - lo
        };
        assert_eq!((span(0), span(1)), (1.0, 1.0));
    }
    assert_eq!(s.textures.len(), 1);
    let leaves = &s.materials[1];
    assert_eq!(leaves.alpha_mode, AlphaMode::Mask);
    assert!(leaves.double_sided && leaves.base_color_texture.is_some());
}

#[test]
fn the_morph_sphere_has_one_small_bump_per_target_and_shows_each_in_turn() {
    let s = scenes::morph_sphere(16, 5);
    let m = &s.meshes[0];
    let targets: Vec<_> = m
        .attributes
        .iter()
        .filter(|a| matches!(a.semantic, Semantic::Morph { .. }))
        .collect();
    assert_eq!(targets.len(), 5);
    for a in &targets {
        let moved = a
            .values
            .chunks_exact(3)
            .filter(|d| d.iter().any(|&x| x != 0.0))
            .count();
        // A 15° cap is 1.7% of the sphere: some vertices, not most.
        assert!(moved > 0 && moved < m.positions.len() / 10, "{moved}");
        let top = a
            .values
            .chunks_exact(3)
            .map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
            .fold(0.0f32, f32::max);
        assert!(top > 0.1 && top <= 0.2 + 1e-6, "{top}");
    }
    let track = &s.animations[0].tracks[0];
    assert_eq!(track.times, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    // Key k + 1 holds target k at 1 and every other at 0.
    for k in 0..5 {
        let key = &track.values[(k + 1) * 5..(k + 2) * 5];
        for (t, &w) in key.iter().enumerate() {
            assert_eq!(w, if t == k { 1.0 } else { 0.0 });
        }
    }
}

fn write(scene: &Scene, path: &Path) {
    let warnings = wildlod_io::write(
        &Document::from_scene(scene.clone()),
        path,
        &WriteOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(warnings.is_empty(), "{}: {warnings:?}", path.display());
}

fn p64(m: &Mesh, v: u32) -> DVec3 {
    DVec3::from(m.positions[v as usize].map(f64::from))
}

/// The (unnormalized) normal of a face: twice its area along its normal.
fn face_normal(m: &Mesh, f: usize) -> DVec3 {
    let c = m.faces.face(f);
    (1..c.len() - 1)
        .map(|k| (p64(m, c[k]) - p64(m, c[0])).cross(p64(m, c[k + 1]) - p64(m, c[0])))
        .sum()
}

/// Triangles (as drawn, a polygon as its fan) of every part.
fn part_triangles(m: &Mesh) -> Vec<usize> {
    let mut out = vec![0; m.parts.len()];
    for (f, &p) in m.face_parts.iter().enumerate() {
        out[p as usize] += m.faces.arity(f) - 2;
    }
    out
}

/// Undirected edges (by vertex index) and how often faces use them.
fn edge_uses(m: &Mesh) -> HashMap<(u32, u32), usize> {
    let mut uses = HashMap::new();
    for f in m.faces.iter() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// Connected groups of faces that share a value of `semantic` (UV
/// islands when it is the UV set).
fn islands(m: &Mesh, semantic: &Semantic) -> usize {
    let a = m.attribute(semantic).expect("stream");
    let mut sets = DisjointSets::new(a.value_count());
    for f in 0..m.face_count() {
        let r = m.faces.corner_range(f);
        for c in r.clone().skip(1) {
            sets.union(a.indices[r.start], a.indices[c]);
        }
    }
    let roots: HashSet<u32> = a.indices.iter().map(|&i| sets.find(i)).collect();
    roots.len()
}

#[test]
fn every_scene_is_valid_and_the_same_on_every_run() {
    for ((name, a), (_, b)) in all().into_iter().zip(all()) {
        a.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(a == b, "{name} differs between two runs");
    }
    assert!(
        scenes::flat_tiling(7) != scenes::flat_tiling(8),
        "the seed changes the tiling"
    );
}

#[test]
fn every_scene_writes_to_glb_and_reads_back_without_loss() {
    let dir = tempfile::tempdir().unwrap();
    for (name, s) in all() {
        let path = dir.path().join(format!("{name}.glb"));
        write(&s, &path);
        let bytes = std::fs::read(&path).unwrap();
        write(&s, &dir.path().join("again.glb"));
        assert!(
            bytes == std::fs::read(dir.path().join("again.glb")).unwrap(),
            "{name}: two writes differ"
        );
        let back = wildlod_io::read(&path)
            .unwrap_or_else(|e| panic!("{e}"))
            .scene;
        assert_eq!(back.meshes.len(), s.meshes.len(), "{name}");
        let (m, r) = (&s.meshes[0], &back.meshes[0]);
        assert_eq!(
            part_triangles(r),
            part_triangles(m),
            "{name}: triangles per part"
        );
        let materials = |m: &Mesh| m.parts.iter().map(|p| p.material).collect::<Vec<_>>();
        assert_eq!(materials(r), materials(m), "{name}: part materials");
        assert_eq!(back.materials, s.materials, "{name}");
        assert_eq!(back.textures.len(), s.textures.len(), "{name}");
        for (a, b) in s.textures.iter().zip(&back.textures) {
            let (a, b) = (
                wildlod_io::decode_image(&a.source).unwrap(),
                wildlod_io::decode_image(&b.source).unwrap(),
            );
            assert!(a == b, "{name}: texture changed");
        }
        assert_eq!(back.nodes, s.nodes, "{name}");
        assert_eq!(back.roots, s.roots, "{name}");
        assert_eq!(back.skins, s.skins, "{name}");
        assert_eq!(back.animations, s.animations, "{name}");
        for sem in [Semantic::TexCoord(0), Semantic::Normal] {
            assert_eq!(
                r.attribute(&sem).is_some(),
                m.attribute(&sem).is_some(),
                "{name}: {sem:?}"
            );
        }
        assert_eq!(r.skinning.is_some(), m.skinning.is_some(), "{name}");
    }
}

/// The Khronos validator's error and warning count for every scene, where
/// node and the validator (`tools/gltf-validator`, `npm ci` there) are
/// installed; a loud skip elsewhere, a failure under CI.
#[test]
fn every_scene_passes_the_khronos_validator() {
    let tool = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/gltf-validator");
    let ci = std::env::var("CI").is_ok_and(|v| v == "true");
    if !tool.join("node_modules/gltf-validator").exists() {
        assert!(
            !ci,
            "the glTF validator is not installed in {}",
            tool.display()
        );
        wildlod_testkit::skipped(&format!(
            "run `npm ci` in {} to validate the scenes",
            tool.display()
        ));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // Errors and warnings both count; infos (such as UV sets no material
    // reads, which the house has on purpose) do not.
    let js = dir.path().join("check.js");
    std::fs::write(
        &js,
        format!(
            "const v = require({:?});\n\
             const b = new Uint8Array(require('fs').readFileSync(process.argv[2]));\n\
             v.validateBytes(b).then(r => console.log(JSON.stringify(r.issues.messages\n\
               .filter(m => m.severity <= 1).map(m => m.code))));\n",
            tool.join("node_modules/gltf-validator")
                .display()
                .to_string()
        ),
    )
    .unwrap();
    for (name, s) in all() {
        let path = dir.path().join(format!("{name}.glb"));
        write(&s, &path);
        let out = Command::new("node").arg(&js).arg(&path).output();
        let Ok(out) = out else {
            assert!(!ci, "node is not installed");
            wildlod_testkit::skipped("node is not installed");
            return;
        };
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(
            text.trim(),
            "[]",
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn house_ground_is_two_triangles_and_the_largest_part_by_far() {
    for textured in [false, true] {
        let s = scenes::house(textured);
        let m = &s.meshes[0];
        assert_eq!(m.parts.len(), 31);
        assert_eq!(s.materials.len(), 12);
        let ground = m.parts.iter().position(|p| p.name == "ground").unwrap();
        let mut area = vec![0.0; m.parts.len()];
        for f in 0..m.face_count() {
            area[m.face_parts[f] as usize] += 0.5 * face_normal(m, f).length();
        }
        assert_eq!(part_triangles(m)[ground], 2);
        assert_eq!(
            m.faces.arity(
                m.face_parts
                    .iter()
                    .position(|&p| p as usize == ground)
                    .unwrap()
            ),
            3
        );
        let rest: f64 = area.iter().sum::<f64>() - area[ground];
        assert!((area[ground] - 3600.0).abs() < 1e-9, "{}", area[ground]);
        assert!(area[ground] > 6.0 * rest, "{} against {rest}", area[ground]);
        // The house's extent is a fraction of the ground's.
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for (f, &p) in m.face_parts.iter().enumerate() {
            if p as usize != ground {
                for &v in m.faces.face(f) {
                    lo = lo.min(p64(m, v));
                    hi = hi.max(p64(m, v));
                }
            }
        }
        assert!(hi.x - lo.x < 10.0 && hi.z - lo.z < 10.0, "{lo} {hi}");
        // Every corner has a UV, in world units: far outside [0, 1].
        let uv = m.attribute(&Semantic::TexCoord(0)).unwrap();
        assert!(uv.indices.iter().all(|&i| i != ABSENT));
        assert!(uv.values.iter().any(|&x| x.abs() > 20.0));
        let n = islands(m, &Semantic::TexCoord(0));
        assert!(n >= 50, "box mapping makes many islands: {n}");
        let textured_materials: Vec<&str> = s
            .materials
            .iter()
            .filter(|m| m.base_color_texture.is_some())
            .map(|m| m.name.as_str())
            .collect();
        if textured {
            assert_eq!(textured_materials, ["plaster"]);
            let img = wildlod_io::decode_image(&s.textures[0].source).unwrap();
            assert_eq!((img.width, img.height), (64, 64));
            let walls = m.parts.iter().filter(|p| p.material == Some(1)).count();
            assert_eq!(walls, 6, "four walls and two gables sample the bricks");
        } else {
            assert!(textured_materials.is_empty());
            assert!(s.textures.is_empty());
        }
    }
}

#[test]
fn house_walls_are_closed_solids_with_openings() {
    let s = scenes::house(false);
    let m = &s.meshes[0];
    for name in ["wall_front", "wall_back", "wall_east", "wall_west"] {
        let part = m.parts.iter().position(|p| p.name == name).unwrap() as u32;
        let mut sub = m.clone();
        let keep: Vec<usize> = (0..m.face_count())
            .filter(|&f| m.face_parts[f] == part)
            .collect();
        let mut faces = wildlod_mesh::Faces::new();
        for &f in &keep {
            faces.push(m.faces.face(f));
        }
        sub.faces = faces;
        let uses = edge_uses(&sub);
        assert!(uses.values().all(|&u| u == 2), "{name} is not closed");
        // Euler characteristic 2 − 2 genus: one handle per window (the
        // front door reaches the wall's foot: a notch, not a handle).
        let v: HashSet<u32> = sub.faces.indices.iter().copied().collect();
        let chi = v.len() as i64 - uses.len() as i64 + keep.len() as i64;
        let openings = if name == "wall_east" || name == "wall_west" {
            1
        } else {
            2
        };
        assert_eq!(chi, 2 - 2 * openings, "{name}");
    }
}

#[test]
fn filleted_block_is_watertight_with_normals_split_between_brep_faces() {
    let s = scenes::filleted_block();
    let m = &s.meshes[0];
    assert_eq!(m.triangle_count(), 7864);
    // Closed and consistently wound: every directed edge once, its
    // reverse once.
    let mut directed = HashSet::new();
    for f in m.faces.iter() {
        for k in 0..3 {
            assert!(
                directed.insert((f[k], f[(k + 1) % 3])),
                "edge used twice the same way"
            );
        }
    }
    assert!(
        directed.iter().all(|&(a, b)| directed.contains(&(b, a))),
        "a border edge"
    );
    // Genus 1 (the hole): V − E + F = 0.
    let chi = m.positions.len() as i64 - (directed.len() / 2) as i64 + m.face_count() as i64;
    assert_eq!(chi, 0);
    // Every point is on the rounded box: its distance to the inner box is
    // the fillet radius, except on the hole's wall (radius 0.5 about y).
    let inner = DVec3::new(1.625, 0.625, 1.125);
    for p in &m.positions {
        let p = DVec3::from(p.map(f64::from));
        let d = (p.abs() - inner).max(DVec3::ZERO).length();
        let hole = (p.x.hypot(p.z) - 0.5).abs() < 1e-6;
        assert!(hole || (d - 0.375).abs() < 1e-6, "{p} at {d}");
    }
    // Normals agree with their faces everywhere (within a fillet step),
    // flats carry exact axes, and B-rep edges split normals.
    let n = m.attribute(&Semantic::Normal).unwrap();
    let mut per_position: HashMap<u32, HashSet<u32>> = HashMap::new();
    let mut exact_axes = 0;
    for f in 0..m.face_count() {
        let fn_ = face_normal(m, f).normalize();
        for c in m.faces.corner_range(f) {
            let v = n.value(n.indices[c]);
            let cn = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
            assert!(
                cn.dot(fn_) > (5.0f64).to_radians().cos(),
                "face {f}: {cn} vs {fn_}"
            );
            if v.iter().filter(|x| x.abs() == 1.0).count() == 1 {
                exact_axes += 1;
            }
            per_position
                .entry(m.faces.indices[c])
                .or_default()
                .insert(n.indices[c]);
        }
    }
    assert!(exact_axes > 0);
    let split = per_position.values().filter(|s| s.len() > 1).count();
    // Along every B-rep edge: the 24 fillet/flat seams and the rims.
    assert!(split > 300, "{split} positions on normal seams");
    // The rims are sharp: a rim position has normals 90° apart.
    let rim = m
        .positions
        .iter()
        .position(|p| (p[0] - 0.5).abs() < 1e-7 && p[2] == 0.0 && p[1] == 1.0)
        .unwrap() as u32;
    let normals: Vec<&[f32]> = per_position[&rim].iter().map(|&i| n.value(i)).collect();
    assert!(normals.iter().any(|v| v[1] == 1.0) && normals.iter().any(|v| v[1].abs() < 1e-7));
}

#[test]
fn flat_tiling_is_exactly_planar_mixed_and_its_border_is_closed_and_axis_aligned() {
    let s = scenes::flat_tiling(7);
    let m = &s.meshes[0];
    assert!(m
        .positions
        .iter()
        .all(|p| p[2] == 0.0 && p[2].is_sign_positive()));
    let (tris, quads, ngons) = m.faces.arity_counts();
    assert!(tris > 2000 && quads > 1500 && ngons == 0, "{tris} {quads}");
    assert!(
        (8500..10500).contains(&m.triangle_count()),
        "{}",
        m.triangle_count()
    );
    // Every face faces +z.
    assert!((0..m.face_count()).all(|f| face_normal(m, f).z > 0.0));
    // Manifold: every edge in one or two faces, every border vertex in
    // exactly two border edges; the border is axis-aligned (border
    // vertices are not jittered).
    let uses = edge_uses(m);
    assert!(uses.values().all(|&u| u <= 2));
    let border = scenes::border_segments(m);
    assert_eq!(border.len(), uses.values().filter(|&&u| u == 1).count());
    let mut degree: HashMap<[u32; 3], usize> = HashMap::new();
    for [a, b] in &border {
        assert!(a[0] == b[0] || a[1] == b[1], "{a:?} {b:?}");
        *degree.entry(a.map(f32::to_bits)).or_default() += 1;
        *degree.entry(b.map(f32::to_bits)).or_default() += 1;
    }
    assert!(degree.values().all(|&d| d == 2), "a pinched border vertex");
    // The outline is ragged (longer than the 36-unit square) and there is
    // a hole: more than 36 + the hole's rim.
    let length: f64 = border
        .iter()
        .map(|[a, b]| DVec3::from(a.map(f64::from)).distance(DVec3::from(b.map(f64::from))))
        .sum();
    assert!(length > 36.0 + 6.0, "{length}");
    // Interior vertices are off the border; border vertices on it.
    let on = |p: [f32; 3]| scenes::distance_to_segments(p.map(f64::from), &border) == 0.0;
    let on_border = m.positions.iter().filter(|&&p| on(p)).count();
    assert_eq!(on_border, degree.len());
}

#[test]
fn distance_to_segments_of_a_hand_computed_case() {
    let segs = [
        [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        [[2.0, 0.0, 0.0], [2.0, 2.0, 0.0]],
    ];
    assert_eq!(scenes::distance_to_segments([1.0, 1.0, 0.0], &segs), 1.0);
    assert_eq!(
        scenes::distance_to_segments([3.0, 3.0, 0.0], &segs),
        2f64.sqrt()
    );
    assert_eq!(scenes::distance_to_segments([1.0, 0.0, 0.0], &segs), 0.0);
    assert_eq!(
        scenes::distance_to_segments([1.0, 0.0, 0.0], &[]),
        f64::INFINITY
    );
}

#[test]
fn city_block_has_recessed_windows_flat_normals_and_150_posts() {
    let s = scenes::city_block();
    let m = &s.meshes[0];
    assert_eq!(m.triangle_count(), 80_338);
    assert_eq!(m.parts.len(), 27);
    assert_eq!(s.materials.len(), 7);
    let part = |name: &str| m.parts.iter().position(|p| p.name == name).unwrap() as u32;
    // The posts: 150 separate components.
    let posts = part("lamp_posts");
    let mut sets = DisjointSets::new(m.positions.len());
    for f in (0..m.face_count()).filter(|&f| m.face_parts[f] == posts) {
        let c = m.faces.face(f);
        for &v in &c[1..] {
            sets.union(c[0], v);
        }
    }
    let roots: HashSet<u32> = (0..m.face_count())
        .filter(|&f| m.face_parts[f] == posts)
        .map(|f| sets.find(m.faces.face(f)[0]))
        .collect();
    assert_eq!(roots.len(), 150);
    // Buildings: every corner's normal is its face's plane normal.
    let n = m.attribute(&Semantic::Normal).unwrap();
    let buildings: HashSet<u32> = (0..12)
        .flat_map(|k| {
            [
                part(&format!("building_{k}")),
                part(&format!("windows_{k}")),
            ]
        })
        .collect();
    for f in (0..m.face_count()).filter(|f| buildings.contains(&m.face_parts[*f])) {
        let fn_ = face_normal(m, f).normalize();
        for c in m.faces.corner_range(f) {
            let v = n.value(n.indices[c]);
            assert!(
                fn_.dot(DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)) > 1.0 - 1e-9,
                "face {f}"
            );
        }
    }
    // Window panes lie 8 cm behind their facade: the south facade of
    // building 0 is its largest z, its panes at that z − 0.08.
    let (b0, w0) = (part("building_0"), part("windows_0"));
    let zs = |p: u32| -> Vec<f32> {
        (0..m.face_count())
            .filter(|&f| m.face_parts[f] == p)
            .flat_map(|f| m.faces.face(f).iter().map(|&v| m.positions[v as usize][2]))
            .collect()
    };
    let facade = zs(b0).into_iter().fold(f32::MIN, f32::max);
    let pane = zs(w0).into_iter().fold(f32::MIN, f32::max);
    assert!((facade - pane - 0.08).abs() < 1e-5, "{facade} {pane}");
}

#[test]
fn bent_tube_poses_to_a_right_angle_after_a_glb_round_trip() {
    let s = scenes::bent_tube();
    let m = &s.meshes[0];
    assert_eq!(m.triangle_count(), 2928);
    let skin = m.skinning.as_ref().unwrap();
    for e in 0..skin.entry_count() as u32 {
        let sum: f32 = skin.entry(e).1.iter().sum();
        assert!((sum - 1.0).abs() < 1e-6);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tube.glb");
    write(&s, &path);
    let back = wildlod_io::read(&path).unwrap().scene;
    let tip = |scene: &Scene, t: f32| {
        let posed = wildlod_eval::posed(scene, Some(0), t);
        let pm = &posed.meshes[0];
        // The end cap's center: the rest position (0, 6, 0) (glTF stores
        // vertices in its own order, so it is looked up in `scene`).
        let rest = &scene.meshes[0].positions;
        let i = rest
            .iter()
            .position(|p| *p == [0.0, TUBE_LENGTH, 0.0])
            .unwrap();
        DVec3::from(pm.positions[i].map(f64::from))
    };
    for scene in [&s, &back] {
        assert!(
            tip(scene, 0.0).distance(DVec3::new(0.0, 6.0, 0.0)) < 1e-5,
            "{}",
            tip(scene, 0.0)
        );
        // 90° about z at the elbow (0, 3, 0): the tip goes to (−3, 3, 0).
        assert!(
            tip(scene, 1.0).distance(DVec3::new(-3.0, 3.0, 0.0)) < 1e-5,
            "{}",
            tip(scene, 1.0)
        );
        // Halfway, 45°.
        let h = 3.0 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(tip(scene, 0.5).distance(DVec3::new(-h, 3.0 + h, 0.0)) < 1e-5);
    }
    // The base stays: weight 1 on the root below the blend.
    let posed = wildlod_eval::posed(&back, Some(0), 1.0);
    let base = m.positions.iter().position(|p| p[1] == 0.0).unwrap();
    assert_eq!(
        posed.meshes[0].positions[base],
        back.meshes[0].positions[base]
    );
}

#[test]
fn outlier_terrain_differs_from_the_clean_one_only_at_its_outliers() {
    let (dirty, clean) = (
        scenes::outlier_terrain(50, 4),
        scenes::outlier_terrain(50, 0),
    );
    let (d, c) = (&dirty.meshes[0], &clean.meshes[0]);
    assert_eq!(d.triangle_count(), 2 * 49 * 49);
    assert_eq!(d.faces, c.faces);
    let outliers = scenes::terrain_outliers(50, 4);
    assert_eq!(outliers.len(), 4);
    for (v, (p, q)) in d.positions.iter().zip(&c.positions).enumerate() {
        if outliers.contains(&(v as u32)) {
            assert_eq!(p[1], OUTLIER_HEIGHT);
            assert_eq!([p[0], p[2]], [q[0], q[2]]);
            // Interior: on no border.
            assert!(!(p[0] == 0.0 || p[0] == 100.0 || p[2] == 0.0 || p[2] == 100.0));
        } else {
            assert_eq!(p, q);
            assert!(p[1].abs() < 8.0);
        }
    }
    assert!(
        (0..c.face_count()).all(|f| face_normal(c, f).y > 0.0),
        "faces face up"
    );
}

#[test]
fn uv_fold_mesh_has_216_unfolded_islands_inside_their_slots() {
    let s = scenes::uv_fold_mesh();
    let m = &s.meshes[0];
    assert_eq!(m.triangle_count(), 27_648);
    assert_eq!(islands(m, &Semantic::TexCoord(0)), 216);
    // Closed: every edge in two faces.
    assert!(edge_uses(m).values().all(|&u| u == 2));
    let uv = m.attribute(&Semantic::TexCoord(0)).unwrap();
    let img = wildlod_io::decode_image(&s.textures[0].source).unwrap();
    let mut signs = [0; 2];
    // Winding of each island (keyed by the slot its first face is in).
    let mut island_sign: HashMap<(u32, u32), bool> = HashMap::new();
    for f in 0..m.face_count() {
        let r = m.faces.corner_range(f);
        let t: Vec<&[f32]> = r.map(|c| uv.value(uv.indices[c])).collect();
        let area =
            (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
        assert!(area.abs() > 1e-8, "face {f} has no UV area");
        signs[usize::from(area > 0.0)] += 1;
        let slot = ((t[0][0] * 15.0) as u32, (t[0][1] * 15.0) as u32);
        let first = *island_sign.entry(slot).or_insert(area > 0.0);
        assert_eq!(first, area > 0.0, "face {f} is folded in its island");
        // The face's UV centroid samples the island, never the gutter.
        let c = [
            (t[0][0] + t[1][0] + t[2][0]) / 3.0,
            (t[0][1] + t[1][1] + t[2][1]) / 3.0,
        ];
        let px = img.texel((c[0] * 512.0) as i64, (c[1] * 512.0) as i64);
        assert!(
            px[..3].iter().any(|&x| x > 0.1),
            "face {f} samples black at {c:?}"
        );
    }
    // UV charts are mirrored on half of the cube's faces, but never
    // folded within a chart (checked above).
    assert_eq!(island_sign.len(), 216);
    assert!(signs[0] > 0 && signs[1] > 0);
    // The gutter between slots is black.
    assert_eq!(img.texel(0, 0), [0.0, 0.0, 0.0, 1.0]);
}

#[test]
fn double_sided_sheet_is_every_face_and_its_mirrored_twin() {
    let s = scenes::double_sided_sheet();
    let m = &s.meshes[0];
    let half = m.face_count() / 2;
    assert_eq!(half, 4800);
    assert!(!s.materials[0].double_sided);
    let (uv, n) = (
        m.attribute(&Semantic::TexCoord(0)).unwrap(),
        m.attribute(&Semantic::Normal).unwrap(),
    );
    for f in 0..half {
        let (a, b) = (m.faces.face(f), m.faces.face(f + half));
        assert_eq!([a[0], a[2], a[1]], [b[0], b[1], b[2]], "face {f}");
        let (ra, rb) = (m.faces.corner_range(f), m.faces.corner_range(f + half));
        for (ca, cb) in ra.zip([rb.start, rb.start + 2, rb.start + 1]) {
            let (na, nb) = (n.value(n.indices[ca]), n.value(n.indices[cb]));
            assert_eq!([na[0], na[1], na[2]], [-nb[0], -nb[1], -nb[2]]);
            let (ua, ub) = (uv.value(uv.indices[ca]), uv.value(uv.indices[cb]));
            assert!((ua[0] - (1.0 - ub[0])).abs() < 1e-6 && ua[1] == ub[1]);
        }
        // Front normals agree with the front face's winding.
        let corner = n.value(n.indices[m.faces.corner_range(f).start]);
        let fnrm = face_normal(m, f);
        assert!(
            fnrm.dot(DVec3::new(
                corner[0] as f64,
                corner[1] as f64,
                corner[2] as f64
            )) > 0.0
        );
    }
    // Open and curved: border edges exist, and z varies.
    let uses = edge_uses(m);
    assert!(uses.values().all(|&u| u == 2 || u == 4));
    assert!(uses.values().any(|&u| u == 2));
    let z: Vec<f32> = m.positions.iter().map(|p| p[2]).collect();
    assert!(z.iter().fold(0.0f32, |a, &b| a.max(b.abs())) > 0.1);
}
