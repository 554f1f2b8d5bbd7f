//! Attributes through simplification (Hoppe 1999; Knodt 2024 §3): values
//! are fitted at the new positions, seams stay where they were, skins keep
//! one influence set per position.
#![allow(clippy::unwrap_used)] // test code

mod common;

use common::ratio;
use wildlod_eval::{compare, CompareOptions, EvalMesh};
use wildlod_mesh::{
    shapes, Attribute, ComponentFormat, Faces, Image, ImageSource, Material, Mesh, Scene, Semantic,
    Skinning, Texture, TextureRef, ABSENT,
};
use wildlod_simplify::{simplify_mesh, simplify_polygons, Options, Partition, SeamPolicy};

/// A linear UV field on the plane z = 0.
fn field(p: [f32; 3]) -> [f32; 2] {
    [0.3 * p[0] + 0.1 * p[1] + 0.2, -0.2 * p[0] + 0.5 * p[1]]
}

/// An `n × n` triangle grid on [0, 1]², UVs from `uv` per vertex.
fn grid(n: usize, uv: impl Fn([f32; 3]) -> [f32; 2]) -> Mesh {
    let mut m = shapes::triangulate(&shapes::quad_grid(n, n));
    let uvs: Vec<f32> = m.positions.iter().flat_map(|&p| uv(p)).collect();
    let indices = m.faces.indices.clone();
    m.attributes = vec![Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uvs,
        indices,
        format: ComponentFormat::F32,
    }];
    m
}

fn uv_of(m: &Mesh, corner: usize) -> [f32; 2] {
    let v = m
        .attribute(&Semantic::TexCoord(0))
        .unwrap()
        .corner_value(corner)
        .unwrap();
    [v[0], v[1]]
}

#[test]
fn a_linear_uv_field_survives_simplification_exactly() {
    let input = grid(40, field);
    let (out, report) = simplify_mesh(&input, &ratio(0.05)).unwrap();
    assert!(report.output_triangles.abs_diff(report.target_triangles) <= 1);
    assert!(out.vertices_moved_from(&input));
    for (corner, &v) in out.faces.indices.iter().enumerate() {
        let (got, want) = (uv_of(&out, corner), field(out.positions[v as usize]));
        for k in 0..2 {
            assert!(
                (got[k] - want[k]).abs() <= 1e-5,
                "corner {corner}: {got:?} vs the field's {want:?}"
            );
        }
    }
}

/// Helper trait: the output has vertices that are not input vertices
/// (otherwise copying values would pass the test above).
trait Moved {
    fn vertices_moved_from(&self, input: &Mesh) -> bool;
}

impl Moved for Mesh {
    fn vertices_moved_from(&self, input: &Mesh) -> bool {
        self.positions.iter().any(|p| !input.positions.contains(p))
    }
}

/// A grid cut at x = ½ into two UV charts: the left half maps to
/// `(x, y)`, the right half to `(x + 2, y)`. The seam's vertices are stored
/// twice, once per chart, as glTF does.
///
/// ```text
///   y=1 ┌────────┬┬────────┐
///       │ chart A ││ chart B│   uv = (x, y) | uv = (x + 2, y)
///   y=0 └────────┴┴────────┘
///       x=0     x=½      x=1
/// ```
fn two_charts(n: usize) -> Mesh {
    let mut positions = Vec::new();
    let mut uv = Vec::new();
    let mut faces = Faces::with_capacity(2 * n * n, 6 * n * n);
    let half = n / 2;
    for (side, cols) in [(0.0f32, 0..half), (2.0, half..n)] {
        let base = positions.len() as u32;
        let width = cols.len() + 1;
        for j in 0..=n {
            for i in cols.start..=cols.end {
                let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
                positions.push([x, y, 0.0]);
                uv.extend_from_slice(&[x + side, y]);
            }
        }
        let id = |i: usize, j: usize| base + (j * width + i) as u32;
        for j in 0..n {
            for i in 0..width - 1 {
                faces.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                faces.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    let mut m = Mesh::from_polygons(positions, faces);
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices,
        format: ComponentFormat::F32,
    });
    m
}

fn check_two_charts(out: &Mesh) {
    let mut seam_positions = 0;
    for f in 0..out.faces.len() {
        let corners = out.faces.corner_range(f);
        let side = if uv_of(out, corners.start)[0] > 1.5 {
            2.0
        } else {
            0.0
        };
        for c in corners {
            let p = out.positions[out.faces.indices[c] as usize];
            let uv = uv_of(out, c);
            // Every corner of a face is in one chart, with its field.
            assert!(
                (uv[0] - (p[0] + side)).abs() <= 1e-5 && (uv[1] - p[1]).abs() <= 1e-5,
                "face {f} corner {c} at {p:?}: uv {uv:?}, chart offset {side}"
            );
        }
    }
    // Positions that carry both charts' values lie on the straight seam.
    for (v, p) in out.positions.iter().enumerate() {
        let charts: Vec<bool> = (0..out.faces.indices.len())
            .filter(|&c| out.positions[out.faces.indices[c] as usize] == *p)
            .map(|c| uv_of(out, c)[0] > 1.5)
            .collect();
        if charts.contains(&true) && charts.contains(&false) {
            seam_positions += 1;
            // Within the pull of the regularizer (1e-4 of a vertex's area,
            // against seam planes of 0.05 per squared edge: about 1e-3 of
            // the distance to merged off-seam vertices, an edge or so).
            assert!(
                (p[0] - 0.5).abs() <= 1e-3,
                "seam vertex {v} left the seam: {p:?}"
            );
        }
    }
    assert!(seam_positions >= 2, "the seam survives");
    assert_eq!(wildlod_mesh::stats::topology(out).uv_islands, Some(2));
}

#[test]
fn a_straight_uv_seam_stays_straight_and_both_charts_keep_their_fields() {
    let input = two_charts(40);
    for seams in [SeamPolicy::Penalize, SeamPolicy::Keep] {
        let mut options = ratio(0.05);
        options.attributes.seams = seams;
        let (out, report) = simplify_mesh(&input, &options).unwrap();
        assert!(
            report.output_triangles <= report.target_triangles + 1,
            "{seams:?}: {report:?}"
        );
        check_two_charts(&out);
    }
}

#[test]
fn ignoring_seams_lets_them_move() {
    // The control for the test above: without the seam rules and planes,
    // collapses slide seam vertices off the seam's line.
    let input = two_charts(40);
    let mut options = ratio(0.05);
    options.attributes.seams = SeamPolicy::Ignore;
    let (out, _) = simplify_mesh(&input, &options).unwrap();
    let moved = out.positions.iter().any(|p| {
        let charts: Vec<bool> = (0..out.faces.indices.len())
            .filter(|&c| out.positions[out.faces.indices[c] as usize] == *p)
            .map(|c| uv_of(&out, c)[0] > 1.5)
            .collect();
        charts.contains(&true) && charts.contains(&false) && (p[0] - 0.5).abs() > 1e-3
    });
    assert!(
        moved,
        "ignoring seams kept them too: the seam test proves nothing"
    );
}

/// A rippled tube along z of `nu × nv` quads (triangulated), stored with its UV
/// seam split (the column at u = 0 and u = 1 are different vertices at the
/// same positions), skinned to joint 0 at the bottom blending into joint 3
/// at the top.
fn skinned_tube(nu: usize, nv: usize) -> Mesh {
    let mut positions = Vec::new();
    let mut uv = Vec::new();
    let mut weights = Vec::new();
    let mut joints = Vec::new();
    for j in 0..=nv {
        for i in 0..=nu {
            // i = nu is the seam copy of i = 0: the same position bits.
            let a = std::f32::consts::TAU * (i % nu) as f32 / nu as f32;
            let z = j as f32 / nv as f32 * 4.0;
            // Ripples, so that collapses have a cost and an order.
            let r = 1.0 + 0.05 * (5.0 * a).sin() * (3.0 * z).sin();
            positions.push([r * a.cos(), r * a.sin(), z]);
            uv.extend_from_slice(&[i as f32 / nu as f32, j as f32 / nv as f32]);
            let t = (z / 4.0).clamp(0.0, 1.0);
            joints.extend_from_slice(&[0u16, 3, 7, 0]);
            weights.extend_from_slice(&[1.0 - t, t * 0.8, t * 0.2, 0.0]);
        }
    }
    let id = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            idx.extend_from_slice(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            idx.extend_from_slice(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut m = Mesh::from_triangles(positions, &idx);
    m.attributes.push(Attribute {
        semantic: Semantic::TexCoord(0),
        components: 2,
        values: uv,
        indices: idx.clone(),
        format: ComponentFormat::F32,
    });
    m.skinning = Some(Skinning {
        influences: 4,
        joints,
        weights,
        indices: idx,
        weight_format: ComponentFormat::U8Norm,
        joint_format: ComponentFormat::U8,
    });
    m
}

/// Joints and weight bits of one skin entry, sorted.
type InfluenceSet = Vec<(u16, u32)>;

/// `o` and the same with the parallel phase forced on a small test mesh
/// (chunks of 1024 faces).
fn with_and_without_chunks(o: Options) -> [Options; 2] {
    let mut chunked = o.clone();
    chunked.partition = Partition {
        min_triangles: 0,
        chunk_faces: 1024,
        handoff: 0.02,
    };
    [o, chunked]
}

#[test]
fn skins_keep_one_normalized_influence_set_per_position() {
    let input = skinned_tube(96, 100);
    for o in [0.5, 0.1]
        .into_iter()
        .flat_map(|r| with_and_without_chunks(ratio(r)))
    {
        let (out, rep) = simplify_mesh(&input, &o).unwrap();
        assert!(
            o.partition.min_triangles > 0 || rep.parallel_collapses > 0,
            "{rep:?}"
        );
        out.validate().unwrap();
        let s = out.skinning.as_ref().unwrap();
        assert_eq!(s.influences, 4);
        let mut by_position: Vec<([f32; 3], InfluenceSet)> = Vec::new();
        for (corner, &v) in out.faces.indices.iter().enumerate() {
            let e = s.indices[corner];
            assert_ne!(e, ABSENT);
            let (js, ws) = s.entry(e);
            let sum: f32 = ws.iter().sum();
            assert!((sum - 1.0).abs() <= 1e-6, "weights sum to {sum}");
            assert!(ws.iter().filter(|&&w| w > 0.0).count() <= 4);
            let mut set: InfluenceSet = js
                .iter()
                .zip(ws)
                .filter(|(_, &w)| w > 0.0)
                .map(|(&j, &w)| (j, w.to_bits()))
                .collect();
            set.sort_unstable();
            let p = out.positions[v as usize];
            match by_position.iter().find(|(q, _)| *q == p) {
                Some((_, other)) => assert_eq!(other, &set, "copies of {p:?} differ"),
                None => by_position.push((p, set)),
            }
        }
        // The UV seam survives (a position whose corners carry two UVs,
        // which a glTF writer stores as two vertices), so the check above
        // compared real copies.
        let uv = out.attribute(&Semantic::TexCoord(0)).unwrap();
        let split = (0..out.positions.len()).any(|v| {
            let mut values: Vec<u32> = (0..out.faces.indices.len())
                .filter(|&c| out.faces.indices[c] as usize == v)
                .map(|c| uv.indices[c])
                .collect();
            values.sort_unstable();
            values.dedup();
            values.len() > 1
        });
        assert!(split, "no seam copies left");
    }
}

#[test]
fn fitted_skin_weights_follow_the_blend_at_the_new_positions() {
    // Along the tube, joint 3 weighs 0.8·z/4 and joint 7 0.2·z/4: a linear
    // blend, which the fit reproduces wherever vertices move.
    for o in with_and_without_chunks(ratio(0.2)) {
        let (out, rep) = simplify_mesh(&skinned_tube(96, 100), &o).unwrap();
        assert!(
            o.partition.min_triangles > 0 || rep.parallel_collapses > 0,
            "{rep:?}"
        );
        let s = out.skinning.as_ref().unwrap();
        for (corner, &v) in out.faces.indices.iter().enumerate() {
            let t = (out.positions[v as usize][2] / 4.0).clamp(0.0, 1.0);
            let (js, ws) = s.entry(s.indices[corner]);
            let w = |j: u16| -> f32 {
                js.iter()
                    .zip(ws)
                    .filter(|(&k, _)| k == j)
                    .map(|(_, &w)| w)
                    .sum()
            };
            assert!(
                (w(0) - (1.0 - t)).abs() < 1e-4,
                "joint 0 at z {}: {}",
                4.0 * t,
                w(0)
            );
            assert!((w(3) - 0.8 * t).abs() < 1e-4 && (w(7) - 0.2 * t).abs() < 1e-4);
        }
    }
}

/// A checkerboard of `k × k` squares, black and white.
fn checkerboard(size: u32, k: u32) -> Image {
    let mut img = Image::filled(size, size, [0.0, 0.0, 0.0, 1.0]);
    for y in 0..size {
        for x in 0..size {
            if (x * k / size + y * k / size) % 2 == 0 {
                img.pixels[(y * size + x) as usize] = [1.0, 1.0, 1.0, 1.0];
            }
        }
    }
    img
}

fn textured(mesh: Mesh) -> Scene {
    let mut mesh = mesh;
    mesh.parts[0].material = Some(0);
    let mut s = Scene::from_mesh(mesh);
    s.materials.push(Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
        }),
        ..Material::default()
    });
    s.textures.push(Texture {
        name: "checker".into(),
        source: ImageSource::Path("checker.png".into()),
        sampler: Default::default(),
    });
    s
}

#[test]
fn a_checkerboard_keeps_its_squares_at_ten_percent() {
    // A gently curved sheet (z = 0.1·sin(πx)), 8×8 checker squares mapped
    // by UV = (x, y). The bound: two samplings of one textured surface
    // differ only where a sample and its nearest neighbour on the other
    // side straddle a square's edge. That sampling term is measured here as
    // the texture Chamfer distance between the input and the same surface
    // tessellated twice as finely (samples land elsewhere; geometry and
    // texture agree to the chords' sag, 1e-4 of the diagonal); a level
    // of detail whose UVs follow the surface adds its own geometric error,
    // so it may exceed the term by a margin of half again (measured: 1.02×).
    // The control: the same collapses with copied UVs (every surviving
    // corner keeping an input corner's value, as wildlod did before
    // fitting) must break it (measured: 7×).
    let n = 48;
    let bend = |m: &mut Mesh| {
        for p in &mut m.positions {
            p[2] = 0.1 * (std::f32::consts::PI * p[0]).sin();
        }
    };
    let mut input = grid(n, |p| [p[0], p[1]]);
    bend(&mut input);
    // The same surface, tessellated finer: its samples fall elsewhere.
    let mut finer = grid(2 * n + 1, |p| [p[0], p[1]]);
    bend(&mut finer);
    let images = [Some(checkerboard(256, 8))];
    let tc = |m: &Mesh| {
        let (r, c) = (textured(input.clone()), textured(m.clone()));
        compare(
            &EvalMesh::from_scene(&r, &images),
            &EvalMesh::from_scene(&c, &images),
            &CompareOptions {
                samples: 1_000,
                texture_samples: 40_000,
                ..CompareOptions::default()
            },
        )
        .texture_chamfer
        .unwrap()
    };
    let sampling = tc(&finer);
    let (lod, _) = simplify_mesh(&input, &ratio(0.1)).unwrap();
    let got = tc(&lod);
    assert!(sampling > 0.0);
    assert!(
        got <= 1.5 * sampling,
        "texture Chamfer {got} against the sampling term {sampling}"
    );
    let plain = simplify_polygons(&input.positions, &input.faces, &ratio(0.1)).unwrap();
    let mut copied = Mesh::from_polygons(plain.positions, plain.faces);
    let uv_in = &input.attributes[0];
    copied.attributes.push(Attribute {
        indices: plain
            .corner_origin
            .iter()
            .map(|&c| uv_in.indices[c as usize])
            .collect(),
        ..uv_in.clone()
    });
    let control = tc(&copied);
    assert!(
        control > 1.5 * sampling,
        "copied UVs pass too ({control} against {sampling}): the bound proves nothing"
    );
}

/// `grid` with a constant normal, a stream, and the value of `stream` at
/// every vertex.
fn with_stream(
    mut m: Mesh,
    semantic: Semantic,
    components: u8,
    value: impl Fn([f32; 3]) -> Vec<f32>,
) -> Mesh {
    let values: Vec<f32> = m.positions.iter().flat_map(|&p| value(p)).collect();
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic,
        components,
        values,
        indices,
        format: ComponentFormat::F32,
    });
    m
}

#[test]
fn tangents_are_regenerated_from_the_simplified_normals_and_uvs() {
    // Stored tangents are wrong on purpose (along +y); UVs run along +x, so
    // MikkTSpace's tangents for the output run along +x.
    let m = with_stream(grid(24, |p| [p[0], p[1]]), Semantic::Normal, 3, |_| {
        vec![0.0, 0.0, 1.0]
    });
    let m = with_stream(m, Semantic::Tangent, 4, |_| vec![0.0, 1.0, 0.0, 1.0]);
    let (out, _) = simplify_mesh(&m, &ratio(0.1)).unwrap();
    let t = out.attribute(&Semantic::Tangent).unwrap();
    for c in 0..out.faces.indices.len() {
        let v = t.corner_value(c).unwrap();
        assert!(
            (v[0] - 1.0).abs() < 1e-4 && v[1].abs() < 1e-4 && v[2].abs() < 1e-4,
            "{v:?}"
        );
        assert_eq!(v[3].abs(), 1.0);
    }
}

#[test]
fn morph_deltas_follow_the_fit_and_stay_one_per_position() {
    // A target that lifts the sheet by 0.1·x, stored per corner with the
    // two-chart UV seam of `two_charts` (so the seam's copies carry it
    // twice).
    let mut m = two_charts(40);
    let deltas: Vec<f32> = m
        .positions
        .iter()
        .flat_map(|p| [0.0, 0.0, 0.1 * p[0]])
        .collect();
    let indices = m.faces.indices.clone();
    m.attributes.push(Attribute {
        semantic: Semantic::Morph {
            target: 0,
            channel: wildlod_mesh::MorphChannel::Position,
        },
        components: 3,
        values: deltas,
        indices,
        format: ComponentFormat::F32,
    });
    let (out, _) = simplify_mesh(&m, &ratio(0.05)).unwrap();
    assert!(out.vertices_moved_from(&m));
    let d = &out.attributes[1];
    for (c, &v) in out.faces.indices.iter().enumerate() {
        let p = out.positions[v as usize];
        let got = d.corner_value(c).unwrap();
        assert!(
            (got[2] - 0.1 * p[0]).abs() < 1e-5 && got[0] == 0.0,
            "{p:?}: {got:?}"
        );
    }
}

/// A triangulated torus with its exact normals, stored per corner: the
/// corners of faces with x > 0 have their own copy of every normal with
/// `noise` added to each component, as an exporter that splits vertices at
/// a UV seam writes the normal once per copy. Positions are shared, so the
/// meshes differ in their normals' seams only.
fn torus_with_split_normals(noise: f32) -> Mesh {
    let (big_r, r) = (1.0f32, 0.3f32);
    let mut m = shapes::triangulate(&shapes::torus(48, 24, big_r, r));
    let n = m.positions.len() as u32;
    let normal = |p: [f32; 3]| {
        let s = big_r / (p[0] * p[0] + p[1] * p[1]).sqrt();
        [(p[0] - s * p[0]) / r, (p[1] - s * p[1]) / r, p[2] / r]
    };
    let mut values: Vec<f32> = m.positions.iter().flat_map(|&p| normal(p)).collect();
    let copies: Vec<f32> = values.iter().map(|x| x + noise).collect();
    values.extend(copies);
    let mut indices = m.faces.indices.clone();
    for f in 0..m.faces.len() {
        let corners = m.faces.corner_range(f);
        let x: f32 = corners
            .clone()
            .map(|c| m.positions[m.faces.indices[c] as usize][0])
            .sum();
        if x > 0.0 {
            for c in corners {
                indices[c] += n;
            }
        }
    }
    m.attributes.push(Attribute {
        semantic: Semantic::Normal,
        components: 3,
        values,
        indices,
        format: ComponentFormat::F32,
    });
    m
}

#[test]
fn normals_split_by_rounding_noise_are_not_a_hard_edge() {
    // Exporters write a split vertex's normal twice a few ulps apart; that
    // is no hard edge to keep, so the output is the one of exactly equal
    // copies. A 3° split is one, and the control shows it changes the
    // result (or the test could not tell).
    let options = ratio(0.1);
    // Output positions whose corners carry more than one normal.
    let split = |m: &Mesh| {
        let a = m.attribute(&Semantic::Normal).unwrap();
        let mut seen: Vec<Option<u32>> = vec![None; m.positions.len()];
        let mut split = vec![false; m.positions.len()];
        for (c, &v) in m.faces.indices.iter().enumerate() {
            let i = a.indices[c];
            match seen[v as usize] {
                None => seen[v as usize] = Some(i),
                Some(j) if j != i => split[v as usize] = true,
                _ => {}
            }
        }
        split.iter().filter(|&&s| s).count()
    };
    let (exact, _) = simplify_mesh(&torus_with_split_normals(0.0), &options).unwrap();
    let (noisy, _) = simplify_mesh(&torus_with_split_normals(2e-6), &options).unwrap();
    let (hard, _) = simplify_mesh(&torus_with_split_normals(0.05), &options).unwrap();
    assert_eq!(split(&exact), 0);
    assert_eq!(split(&noisy), 0, "rounding noise kept as a hard edge");
    assert!(split(&hard) > 0, "a 3° hard edge was merged away");
}
