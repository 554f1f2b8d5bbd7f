//! Appearance on the corpus's textured and skinned glTF files at 50%, 10%
//! and 1%: no new UV islands (as `wildlod info` counts them, a chart that
//! meets itself across its own seam counting once), one influence
//! set per position in every skinned output, and the Khronos glTF validator
//! finds no error in an output whose input had none, nor a new kind of
//! error in the others.
#![allow(clippy::unwrap_used, clippy::expect_used)] // test code

mod support;

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::process::Command;

use wildlod_mesh::{Attribute, Mesh, Semantic, ABSENT};
use wildlod_testkit::{corpus, mesh_files, short};

const RATIOS: [f64; 3] = [0.5, 0.1, 0.01];

fn wildlod(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_wildlod"))
        .args(args)
        .output()
        .expect("run wildlod")
}

fn gltf_files(root: &Path) -> Vec<PathBuf> {
    ["textured", "skinned"]
        .iter()
        .flat_map(|c| mesh_files(root, c))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("gltf" | "glb")))
        .collect()
}

fn islands(path: &Path) -> Option<u64> {
    let o = wildlod(&["info", path.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    v["uv_islands"].as_u64()
}

fn simplify(input: &Path, out: &Path, r: f64) {
    simplify_with(input, out, r, &[]);
}

fn simplify_with(input: &Path, out: &Path, r: f64, extra: &[&str]) {
    let ratio = r.to_string();
    let mut args = vec![
        "simplify",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--ratio",
        &ratio,
        "-q",
    ];
    args.extend_from_slice(extra);
    let o = wildlod(&args);
    assert!(
        o.status.success(),
        "{}: {}",
        input.display(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// UV islands of `m` as `wildlod info` counts them, one id per face
/// (`usize::MAX`: no UV), and their count.
fn island_ids(m: &Mesh) -> (Vec<usize>, usize) {
    match wildlod_mesh::stats::uv_island_ids(m) {
        Some((ids, n)) => (
            ids.into_iter()
                .map(|i| if i == ABSENT { usize::MAX } else { i as usize })
                .collect(),
            n,
        ),
        None => (vec![usize::MAX; m.faces.len()], 0),
    }
}

/// A corner's position and UV, bit for bit.
fn corner_key(m: &Mesh, uv: &Attribute, c: usize) -> Option<([u32; 3], [u32; 2])> {
    let i = *uv.indices.get(c)?;
    if i == ABSENT || i as usize >= uv.value_count() {
        return None;
    }
    let v = uv.value(i);
    let p = m.positions[m.faces.indices[c] as usize];
    Some((p.map(f32::to_bits), [v[0].to_bits(), v[1].to_bits()]))
}

/// The squared distance from `p` to the UV triangle `t`.
fn uv_triangle_distance2(p: [f64; 2], t: [[f64; 2]; 3]) -> f64 {
    let cross = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let (d0, d1, d2) = (
        cross(t[0], t[1], p),
        cross(t[1], t[2], p),
        cross(t[2], t[0], p),
    );
    if (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0) {
        return 0.0;
    }
    (0..3)
        .map(|k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l2 = dx * dx + dy * dy;
            let u = if l2 > 0.0 {
                (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (x, y) = (a[0] + u * dx - p[0], a[1] + u * dy - p[1]);
            x * x + y * y
        })
        .fold(f64::INFINITY, f64::min)
}

/// The pieces `output`'s mesh (a level of detail of `input`'s mesh) cuts
/// the input's UV islands into: output faces are one piece where they
/// share a corner's position and UV (as `wildlod info` counts islands),
/// and also where they share an edge and their UVs lie in the same input
/// island (nearest to each face's UV centroid). A chart that wraps around
/// a part (a cup's ring, a handle) meets itself across its own seam; cut
/// down to a few triangles it may meet itself only there, two islands by
/// `wildlod info` with no new seam between them. Returns (the input's
/// islands, the output's pieces).
fn pieces_of_islands(input: &Mesh, output: &Mesh) -> (usize, usize) {
    let (ids_in, n_in) = island_ids(input);
    let (ids_out, n_out) = island_ids(output);
    let (Some(uv_in), Some(uv_out)) = (
        input.attribute(&Semantic::TexCoord(0)),
        output.attribute(&Semantic::TexCoord(0)),
    ) else {
        return (n_in, n_out);
    };
    let uv_at = |_: &Mesh, uv: &Attribute, c: usize| {
        let v = uv.value(uv.indices[c]);
        [f64::from(v[0]), f64::from(v[1])]
    };
    // The input's UV triangles (fans), each with its island.
    let mut tris: Vec<([[f64; 2]; 3], usize)> = Vec::new();
    for (f, &island) in ids_in.iter().enumerate() {
        if island == usize::MAX {
            continue;
        }
        let r: Vec<usize> = input.faces.corner_range(f).collect();
        if r.iter().any(|&c| corner_key(input, uv_in, c).is_none()) {
            continue;
        }
        for k in 1..r.len().saturating_sub(1) {
            let t = [r[0], r[k], r[k + 1]].map(|c| uv_at(input, uv_in, c));
            tris.push((t, island));
        }
    }
    let island_of = |f: usize| {
        let r: Vec<usize> = output.faces.corner_range(f).collect();
        let n = r.len() as f64;
        let c = r.iter().fold([0.0, 0.0], |acc, &c| {
            let t = uv_at(output, uv_out, c);
            [acc[0] + t[0] / n, acc[1] + t[1] / n]
        });
        tris.iter()
            .map(|(t, i)| (uv_triangle_distance2(c, *t), *i))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|x| x.1)
    };
    let home: Vec<Option<usize>> = (0..output.faces.len())
        .map(|f| (ids_out[f] != usize::MAX).then(|| island_of(f)).flatten())
        .collect();
    let mut parent: Vec<usize> = (0..n_out).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut sides: HashMap<[[u32; 3]; 2], Vec<usize>> = HashMap::new();
    for f in 0..output.faces.len() {
        let face = output.faces.face(f);
        for k in 0..face.len() {
            let (a, b) = (
                output.positions[face[k] as usize].map(f32::to_bits),
                output.positions[face[(k + 1) % face.len()] as usize].map(f32::to_bits),
            );
            sides
                .entry(if a <= b { [a, b] } else { [b, a] })
                .or_default()
                .push(f);
        }
    }
    for faces in sides.values() {
        for (i, &f) in faces.iter().enumerate() {
            for &g in &faces[i + 1..] {
                if home[f].is_some() && home[f] == home[g] {
                    let (a, b) = (find(&mut parent, ids_out[f]), find(&mut parent, ids_out[g]));
                    parent[b] = a;
                }
            }
        }
    }
    let pieces = (0..n_out).filter(|&x| find(&mut parent, x) == x).count();
    (n_in, pieces)
}

/// A mesh of triangles over `positions` with one UV per corner.
fn uv_mesh(positions: Vec<[f32; 3]>, tris: &[u32], uvs: &[[f32; 2]]) -> Mesh {
    let mut m = Mesh::from_triangles(positions, tris);
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uvs.iter().flatten().copied().collect(),
        indices: (0..tris.len() as u32).collect(),
        format: wildlod_mesh::ComponentFormat::F32,
    });
    m
}

#[test]
fn a_chart_meeting_itself_across_its_seam_is_one_piece_a_torn_one_two() {
    // The input: one chart, a strip of four triangles along x (u = x).
    let p: Vec<[f32; 3]> = (0..3)
        .flat_map(|i| [[i as f32, 0.0, 0.0], [i as f32, 1.0, 0.0]])
        .collect();
    let tris = [0, 2, 1, 1, 2, 3, 2, 4, 3, 3, 4, 5];
    let uv = |v: u32| [p[v as usize][0] / 2.0, p[v as usize][1]];
    let input = uv_mesh(p.clone(), &tris, &tris.map(uv));
    assert_eq!(island_ids(&input).1, 1);
    // Two triangles sharing the edge 1-2 whose UVs jump across it (as
    // across a wrapped chart's seam): two islands as `info` counts them,
    // one piece of the input's one.
    let (a, b) = ([0u32, 2, 1], [1u32, 2, 3]);
    let mut jumped: Vec<[f32; 2]> = a.map(uv).to_vec();
    jumped.extend(b.map(|v| {
        let t = uv(v);
        [t[0] + if v == 1 || v == 2 { 0.25 } else { 0.0 }, t[1]]
    }));
    let wrapped = uv_mesh(p.clone(), &[0, 2, 1, 1, 2, 3], &jumped);
    assert_eq!(island_ids(&wrapped).1, 2);
    assert_eq!(pieces_of_islands(&input, &wrapped), (1, 1));
    // The two end triangles alone, apart: the chart is torn in two.
    let torn = uv_mesh(p.clone(), &[0, 2, 1, 3, 4, 5], &[0, 2, 1, 3, 4, 5].map(uv));
    assert_eq!(pieces_of_islands(&input, &torn), (1, 2));
}

/// Keeping the UVs keeps the input's islands: no new seam is cut (a
/// re-baked LOD, which the default writes where it measures better, gets
/// an atlas of its own by design). Islands are counted as `wildlod info`
/// counts them, except that a chart meeting itself across its own seam is
/// one piece (see [`pieces_of_islands`]: at 1% the tea set's ring chart,
/// 576 triangles around a cup, became two triangles that share only the
/// ring's seam edge).
#[test]
fn levels_of_detail_add_no_uv_island() {
    let Some(root) = corpus("levels_of_detail_add_no_uv_island") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for input in gltf_files(&root) {
        let Some(before) = islands(&input) else {
            continue;
        };
        for r in RATIOS {
            let out = dir.path().join(format!("lod_{r}.glb"));
            simplify_with(&input, &out, r, &["--textures", "keep"]);
            let a = wildlod_io::read(&input).unwrap().scene;
            let b = wildlod_io::read(&out).unwrap().scene;
            assert_eq!(a.meshes.len(), b.meshes.len(), "{}", short(&root, &input));
            let (mut total_in, mut after) = (0, 0);
            for (m, n) in a.meshes.iter().zip(&b.meshes) {
                let (i, o) = pieces_of_islands(m, n);
                total_in += i;
                after += o;
            }
            // The per-mesh count agrees with `wildlod info` on the input.
            assert_eq!(total_in as u64, before, "{}", short(&root, &input));
            assert!(
                after <= total_in,
                "{} at {r}: {before} UV islands became {after}",
                short(&root, &input)
            );
            checked += 1;
        }
    }
    assert!(
        checked >= 18,
        "only {checked} runs: is the corpus complete?"
    );
}

#[test]
fn skinned_levels_of_detail_keep_one_influence_set_per_position() {
    let Some(root) = corpus("skinned_levels_of_detail_keep_one_influence_set_per_position") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut skinned = 0;
    for input in gltf_files(&root) {
        for r in RATIOS {
            let out = dir.path().join(format!("lod_{r}.glb"));
            simplify(&input, &out, r);
            let doc = wildlod_io::read(&out).unwrap();
            for mesh in &doc.scene.meshes {
                let Some(s) = &mesh.skinning else {
                    continue;
                };
                skinned += 1;
                let mut sets: BTreeMap<[u32; 3], Vec<(u16, u32)>> = BTreeMap::new();
                for (corner, &v) in mesh.faces.indices.iter().enumerate() {
                    let (js, ws) = s.entry(s.indices[corner]);
                    let mut set: Vec<(u16, u32)> = js
                        .iter()
                        .zip(ws)
                        .filter(|(_, &w)| w > 0.0)
                        .map(|(&j, &w)| (j, w.to_bits()))
                        .collect();
                    set.sort_unstable();
                    let key = mesh.positions[v as usize].map(f32::to_bits);
                    let seen = sets.entry(key).or_insert_with(|| set.clone());
                    assert_eq!(
                        *seen,
                        set,
                        "{} at {r}: copies of one position carry different influences",
                        short(&root, &input)
                    );
                }
            }
        }
    }
    assert!(skinned >= 12, "only {skinned} skinned outputs checked");
}

/// `node tools/gltf-validator/validate.js`, installing the validator from
/// the npm registry the first time; `None` (with a message) where Node.js
/// is absent, a failure under `CI=true`.
fn validator() -> Option<PathBuf> {
    support::npm_tool("gltf-validator", "gltf-validator").map(|dir| dir.join("validate.js"))
}

/// The error codes the validator reports for a file, with counts.
fn validation_errors(script: &Path, file: &Path) -> BTreeMap<String, u64> {
    let o = Command::new("node").arg(script).arg(file).output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("validator output for {}: {e}", file.display()));
    v["codes"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, n)| (k.clone(), n.as_u64().unwrap()))
        .collect()
}

#[test]
fn the_khronos_validator_finds_no_new_error_in_levels_of_detail() {
    let Some(root) = corpus("the_khronos_validator_finds_no_new_error_in_levels_of_detail") else {
        return;
    };
    let Some(script) = validator() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for input in gltf_files(&root) {
        let before = validation_errors(&script, &input);
        for r in RATIOS {
            let out = dir.path().join(format!("lod_{r}.glb"));
            simplify(&input, &out, r);
            let after = validation_errors(&script, &out);
            let new: Vec<&String> = after.keys().filter(|k| !before.contains_key(*k)).collect();
            assert!(
                new.is_empty(),
                "{} at {r}: new kinds of error {new:?} (input had {before:?})",
                short(&root, &input)
            );
            assert!(
                !before.is_empty() || after.is_empty(),
                "{} at {r}: {after:?} in the output of a valid input",
                short(&root, &input)
            );
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} runs");
}
