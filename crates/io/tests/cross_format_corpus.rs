//! The cross-format matrix over the shared corpus: every mesh file except
//! `large/` (a 15 MB scan, too slow here; `gltf_corpus.rs` round-trips it
//! through glTF) is read, written as glb, gltf, obj, ply and stl into a
//! temporary directory, read back, and checked for what the output format
//! can hold. The corpus has no PLY file, so the PLY copy of every file is
//! put through the same matrix as an input. Everything is compared on bit
//! patterns, in world space (every instance moved by its node transforms),
//! as sorted multisets, so that vertex splitting and face reordering by a
//! writer do not matter:
//!
//! | check | glb / gltf | obj | ply | stl |
//! |---|---|---|---|---|
//! | triangles per instance | = | = | = | = |
//! | triangles' corner positions | = | = | = | = |
//! | the same, per stored mesh; node matrices | = from glTF | – | – | – |
//! | polygons (arities kept) | all triangles | = | = | all triangles |
//! | UV set 0 per triangle corner | = ¹ | = ² | = ¹ | none |
//! | normals per triangle corner | = ¹ ³ | = ² | = ¹ | none |
//! | vertex count | [`expected_vertices`] | = | [`expected_vertices`] | 3 per triangle |
//! | part name and material per face | = | = | none | none |
//! | skins, animations, materials | = from glTF | none | none | none |
//! | warnings | [`expected_warnings`] | ditto | ditto | ditto |
//!
//! "none" is a documented loss: the read-back file must not have it, and
//! the write must have warned about it ([`expected_warnings`]: exactly one
//! warning per kind of content dropped, and no other). OBJ keeps materials
//! (MTL) and part names (`g`); PLY and STL keep neither.
//!
//! ¹ A vertex needs a value in every stream it has: a corner without one
//! gets the writer's default (glTF: +z normal, zero UV; PLY: zeros) where
//! other corners of its primitive (glTF) or file (PLY) have one. ² OBJ
//! writes a face's `vt`/`vn` only when all its corners have one. ³ glTF
//! requires unit normals: a zero normal becomes +z, with a warning (the
//! writer also renormalizes normals more than 1e-4 off unit length; no
//! corpus file has any, so this test would flag one). All are the writers'
//! documented behaviour, applied to the expectation by [`as_written`].

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use wildlod_io::{read, write, Document, Format, WriteOptions};
use wildlod_mesh::shapes::triangulate;
use wildlod_mesh::transform::transformed;
use wildlod_mesh::{Attribute, ComponentFormat, Mesh, Scene, Semantic, ABSENT};
use wildlod_testkit::{corpus, mesh_files, short};

/// Bit pattern of a position.
type Bits3 = [u32; 3];
/// A triangle's corner positions, in winding order.
type Triangle = [Bits3; 3];
/// A corner: its position and its value in one stream (`None`: no value).
type Corner = (Bits3, Option<Vec<u32>>);

fn bits(p: &[f32; 3]) -> Bits3 {
    p.map(f32::to_bits)
}

/// Every corpus mesh file except `large/`.
fn corpus_files(root: &Path) -> Vec<PathBuf> {
    mesh_files(root, "")
        .into_iter()
        .filter(|p| !p.starts_with(root.join("large")))
        .collect()
}

/// Every mesh instance moved into world space, one mesh per instance.
fn world(scene: &Scene) -> Vec<Mesh> {
    scene
        .instances()
        .iter()
        .map(|(m, matrix)| transformed(&scene.meshes[*m as usize], matrix))
        .collect()
}

fn triangle_total(meshes: &[Mesh]) -> usize {
    meshes.iter().map(Mesh::triangle_count).sum()
}

fn vertex_total(meshes: &[Mesh]) -> usize {
    meshes.iter().map(|m| m.positions.len()).sum()
}

/// The fan-triangulated corner positions of every face, sorted.
fn triangles(meshes: &[Mesh]) -> Vec<Triangle> {
    let mut out = Vec::new();
    for m in meshes {
        let t = triangulate(m);
        out.extend(
            t.faces
                .iter()
                .map(|f| [0, 1, 2].map(|k| bits(&t.positions[f[k] as usize]))),
        );
    }
    out.sort_unstable();
    out
}

/// The corner positions of every polygon as stored, sorted.
fn polygons(meshes: &[Mesh]) -> Vec<Vec<Bits3>> {
    let mut out: Vec<Vec<Bits3>> = meshes
        .iter()
        .flat_map(|m| {
            m.faces
                .iter()
                .map(|f| f.iter().map(|&v| bits(&m.positions[v as usize])).collect())
        })
        .collect();
    out.sort_unstable();
    out
}

/// Every triangle as (position, value in stream `s`) per corner, sorted.
fn corner_triangles(meshes: &[Mesh], s: &Semantic) -> Vec<[Corner; 3]> {
    let mut out = Vec::new();
    for m in meshes {
        let t = triangulate(m);
        let stream = t.attribute(s);
        for f in 0..t.faces.len() {
            let r = t.faces.corner_range(f);
            out.push([0, 1, 2].map(|k| {
                let c = r.start + k;
                let value = stream
                    .and_then(|a| a.corner_value(c))
                    .map(|v| v.iter().map(|x| x.to_bits()).collect());
                (bits(&t.positions[t.faces.indices[c] as usize]), value)
            }));
        }
    }
    out.sort_unstable();
    out
}

/// Every triangle with its face's part name.
fn part_triangles(scene: &Scene) -> Vec<(Triangle, String)> {
    let mut out = Vec::new();
    for m in world(scene) {
        let t = triangulate(&m);
        for (f, face) in t.faces.iter().enumerate() {
            let tri = [0, 1, 2].map(|k| bits(&t.positions[face[k] as usize]));
            out.push((tri, t.parts[t.face_parts[f] as usize].name.clone()));
        }
    }
    out.sort_unstable();
    out
}

/// What is compared of a face's material: its base color (RGB bits) and
/// whether it has a base color texture.
type MaterialKey = ([u32; 3], bool);

/// Every triangle with its face's material, if any.
fn material_triangles(scene: &Scene) -> Vec<(Triangle, Option<MaterialKey>)> {
    let mut out = Vec::new();
    for m in world(scene) {
        let t = triangulate(&m);
        for (f, face) in t.faces.iter().enumerate() {
            let color = t.parts[t.face_parts[f] as usize]
                .material
                .map(|i| &scene.materials[i as usize])
                .map(|m| {
                    let c = m.base_color;
                    (
                        [c[0].to_bits(), c[1].to_bits(), c[2].to_bits()],
                        m.base_color_texture.is_some(),
                    )
                });
            let tri = [0, 1, 2].map(|k| bits(&t.positions[face[k] as usize]));
            out.push((tri, color));
        }
    }
    out.sort_unstable();
    out
}

/// The streams compared per corner, with their component counts.
const STREAMS: [(Semantic, u8); 2] = [(Semantic::TexCoord(0), 2), (Semantic::Normal, 3)];

/// The input's world meshes with UV set 0 and normals as `out` writes them
/// (see the notes at the top); other streams are dropped, they are not
/// compared here.
fn as_written(meshes: &[Mesh], out: Format) -> Vec<Mesh> {
    let mut meshes = meshes.to_vec();
    for m in &mut meshes {
        m.attributes.retain(|a| {
            STREAMS
                .iter()
                .any(|(s, k)| *s == a.semantic && a.components == *k)
        });
    }
    match out {
        // Not in this matrix yet: tests/off.rs checks OFF's round trips.
        Format::Off => {}
        Format::Stl => {
            for m in &mut meshes {
                m.attributes.clear();
            }
        }
        Format::Obj => {
            for m in &mut meshes {
                for f in 0..m.faces.len() {
                    let r = m.faces.corner_range(f);
                    for a in &mut m.attributes {
                        if a.indices[r.clone()].contains(&ABSENT) {
                            a.indices[r.clone()].fill(ABSENT);
                        }
                    }
                }
            }
        }
        Format::Ply => {
            for (s, k) in &STREAMS {
                if !meshes.iter().any(|m| m.attribute(s).is_some()) {
                    continue;
                }
                for m in &mut meshes {
                    let zero = vec![0.0; *k as usize];
                    let a = stream_or_empty(m, s, *k);
                    fill_absent(a, 0..a.indices.len(), &zero);
                }
            }
        }
        Format::Gltf | Format::Glb => {
            for m in &mut meshes {
                let corners_of_part = |m: &Mesh, p: u32| -> Vec<usize> {
                    (0..m.faces.len())
                        .filter(|&f| m.face_parts[f] == p)
                        .flat_map(|f| m.faces.corner_range(f))
                        .collect()
                };
                for p in 0..m.parts.len() as u32 {
                    let corners = corners_of_part(m, p);
                    for a in &mut m.attributes {
                        if corners.iter().all(|&c| a.indices[c] == ABSENT) {
                            continue;
                        }
                        let default: &[f32] = match a.semantic {
                            Semantic::Normal => &[0.0, 0.0, 1.0],
                            _ => &[0.0, 0.0],
                        };
                        fill_absent(a, corners.iter().copied(), default);
                    }
                }
                // glTF requires unit normals: a zero one becomes +z (and
                // the writer warns).
                for a in &mut m.attributes {
                    if a.semantic == Semantic::Normal {
                        for v in a.values.chunks_exact_mut(3) {
                            if v.iter().all(|&x| x == 0.0) {
                                v.copy_from_slice(&[0.0, 0.0, 1.0]);
                            }
                        }
                    }
                }
            }
        }
    }
    meshes
}

/// The stream `s` of `m`, added with no value at any corner if missing.
fn stream_or_empty<'m>(m: &'m mut Mesh, s: &Semantic, components: u8) -> &'m mut Attribute {
    let i = match m.attributes.iter().position(|a| &a.semantic == s) {
        Some(i) => i,
        None => {
            m.attributes.push(Attribute {
                semantic: s.clone(),
                components,
                values: Vec::new(),
                indices: vec![ABSENT; m.faces.corner_count()],
                format: ComponentFormat::F32,
            });
            m.attributes.len() - 1
        }
    };
    &mut m.attributes[i]
}

/// Gives the corners without a value among `corners` the value `v`.
fn fill_absent(a: &mut Attribute, corners: impl IntoIterator<Item = usize>, v: &[f32]) {
    let index = a.value_count() as u32;
    let mut used = false;
    for c in corners {
        if a.indices[c] == ABSENT {
            a.indices[c] = index;
            used = true;
        }
    }
    if used {
        a.values.extend_from_slice(v);
    }
}

/// How many vertices the read-back output has, summed over instances:
///
/// - same format out as in, and OBJ out: equal to the input (OBJ writes its
///   `v`/`vt`/`vn` pools as stored, per instance);
/// - STL out: three per triangle, whatever the input shared. STL is a
///   triangle soup: the format forces the split, so the input's sharing
///   is not asserted, only that the reader keeps the soup as stored;
/// - PLY out: a vertex per distinct (position, UV, normal, color) value
///   combination of the corners, unless every stream is already indexed
///   like the positions (glTF, STL, OBJ without `vt`/`vn`): then equal;
/// - glTF out from OBJ/STL: a vertex per distinct (position, stream
///   indices) combination in each part; equal to the input when no
///   position is used by two parts or with two `vt`/`vn` index pairs, and
///   none is unused.
fn expected_vertices(input: &Scene, from: Format, to: Format) -> usize {
    let meshes = world(input);
    let same = |a: Format, b: Format| {
        a == b
            || matches!(
                (a, b),
                (Format::Gltf | Format::Glb, Format::Gltf | Format::Glb)
            )
    };
    if same(from, to) || to == Format::Obj {
        return vertex_total(&meshes);
    }
    match to {
        Format::Stl => 3 * triangle_total(&meshes),
        Format::Ply => meshes.iter().map(ply_vertices).sum(),
        _ => meshes.iter().map(gltf_vertices).sum(),
    }
}

/// The streams PLY writes.
fn ply_streams(m: &Mesh) -> Vec<&Attribute> {
    m.attributes
        .iter()
        .filter(|a| match a.semantic {
            Semantic::TexCoord(0) => a.components >= 2,
            Semantic::Normal => a.components == 3,
            Semantic::Color(0) => a.components >= 3,
            _ => false,
        })
        .collect()
}

fn ply_vertices(m: &Mesh) -> usize {
    let streams = ply_streams(m);
    let direct = streams
        .iter()
        .all(|a| a.value_count() >= m.positions.len() && a.indices == m.faces.indices);
    if direct {
        return m.positions.len();
    }
    let mut keys = std::collections::HashSet::new();
    for (c, &v) in m.faces.indices.iter().enumerate() {
        let mut key = vec![v];
        for a in &streams {
            match a.corner_value(c) {
                Some(val) => key.extend(val.iter().map(|x| x.to_bits())),
                None => key.push(ABSENT),
            }
        }
        keys.insert(key);
    }
    keys.len()
}

fn gltf_vertices(m: &Mesh) -> usize {
    let mut keys = std::collections::HashSet::new();
    let t = triangulate(m);
    for (f, face) in t.faces.iter().enumerate() {
        for (k, &v) in face.iter().enumerate() {
            let c = t.faces.offsets[f] as usize + k;
            let mut key = vec![t.face_parts[f], v];
            key.extend(t.attributes.iter().map(|a| a.indices[c]));
            keys.insert(key);
        }
    }
    keys.len()
}

/// The warnings `write` must return for `scene` written as `to`, each as a
/// phrase it contains: one per kind of content the format cannot hold
/// (the writers name it in their documentation), and no other.
fn expected_warnings(scene: &Scene, to: Format) -> Vec<&'static str> {
    let meshes = world(scene);
    let any_stream =
        |f: &dyn Fn(&Attribute) -> bool| meshes.iter().any(|m| m.attributes.iter().any(f));
    let skins = !scene.skins.is_empty();
    let animations = !scene.animations.is_empty();
    let skin_weights = meshes.iter().any(|m| m.skinning.is_some());
    let tangents = any_stream(&|a| a.semantic == Semantic::Tangent);
    let more_uv_sets = any_stream(&|a| matches!(a.semantic, Semantic::TexCoord(n) if n > 0));
    let zero_normals = meshes.iter().any(|m| {
        m.attribute(&Semantic::Normal).is_some_and(|a| {
            (0..m.faces.corner_count()).any(|c| {
                a.corner_value(c)
                    .is_some_and(|v| v.iter().all(|&x| x == 0.0))
            })
        })
    });
    let materials: Vec<u32> = meshes
        .iter()
        .flat_map(|m| m.face_parts.iter().map(|&p| &m.parts[p as usize]))
        .filter_map(|p| p.material)
        .collect();
    let parts_or_materials =
        meshes.iter().map(|m| m.parts.len()).sum::<usize>() > 1 || !materials.is_empty();
    let second_uv_textures = materials.iter().any(|&m| {
        scene.materials[m as usize]
            .texture_refs()
            .any(|t| t.tex_coord != 0)
    });
    // PLY: a vertex has every property of the file, so a corner without a
    // value of a stream that another corner has is written with zeros.
    let ply_filled = [Semantic::TexCoord(0), Semantic::Normal, Semantic::Color(0)]
        .iter()
        .any(|s| {
            let stream = |m| ply_streams(m).into_iter().find(|a| &a.semantic == s);
            meshes.iter().any(|m| stream(m).is_some())
                && meshes
                    .iter()
                    .any(|m| stream(m).map_or(true, |a| a.indices.contains(&ABSENT)))
        });
    let attributes = meshes
        .iter()
        .any(|m| !m.attributes.is_empty() || m.skinning.is_some());

    let mut expected = Vec::new();
    let mut expect = |when: bool, phrase: &'static str| {
        if when {
            expected.push(phrase);
        }
    };
    match to {
        // Not in this matrix yet: tests/off.rs checks OFF's round trips.
        Format::Off => {}
        Format::Gltf | Format::Glb => {
            expect(zero_normals, "zero-length normals");
        }
        Format::Obj => {
            expect(skins, "OBJ cannot hold skins;");
            expect(animations, "OBJ cannot hold animations;");
            expect(skin_weights, "OBJ cannot hold skin weights;");
            expect(tangents, "OBJ cannot hold tangents;");
            expect(more_uv_sets, "OBJ cannot hold UV sets beyond the first;");
            expect(
                second_uv_textures,
                "OBJ cannot hold texture references to UV sets beyond the first;",
            );
        }
        Format::Ply => {
            expect(skins, "PLY cannot hold skins;");
            expect(animations, "PLY cannot hold animations;");
            expect(skin_weights, "PLY cannot hold skin weights;");
            expect(tangents, "PLY cannot hold tangents;");
            expect(more_uv_sets, "PLY cannot hold UV sets beyond the first;");
            expect(parts_or_materials, "PLY cannot hold parts or materials;");
            expect(ply_filled, "PLY vertices need every attribute");
        }
        Format::Stl => {
            expect(skins || animations, "STL holds no skins or animations");
            expect(attributes, "STL holds no vertex attributes");
            expect(parts_or_materials, "binary STL holds no parts or materials");
        }
    }
    expected
}

/// Problems found in one file's round trip through one format.
struct Report<'a> {
    what: &'a str,
    problems: &'a mut Vec<String>,
}

impl Report<'_> {
    fn check(&mut self, ok: bool, msg: impl FnOnce() -> String) {
        if !ok {
            self.problems.push(format!("{}: {}", self.what, msg()));
        }
    }

    /// Compares two sorted multisets; reports the counts and the first
    /// difference.
    fn same<T: PartialEq + std::fmt::Debug>(&mut self, what: &str, a: &[T], b: &[T]) {
        if a != b {
            let first = a.iter().zip(b).position(|(x, y)| x != y);
            let detail = match first {
                Some(i) => format!("first difference at {i}: {:?} vs {:?}", a[i], b[i]),
                None => String::new(),
            };
            self.problems.push(format!(
                "{}: {what} differ ({} vs {}) {detail}",
                self.what,
                a.len(),
                b.len()
            ));
        }
    }
}

/// Writes `doc` (read from `source`) as `to`, reads it back and checks
/// everything the table at the top promises; adds what fails to `problems`.
fn round_trip(source: &str, doc: &Document, to: Format, problems: &mut Vec<String>) {
    let name = format!("{source} → .{}", to.extension());
    let mut r = Report {
        what: &name,
        problems,
    };
    let from = doc.format.unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join(format!("out.{}", to.extension()));
    let warnings = write(doc, &out, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let back: Document = read(&out).unwrap_or_else(|e| panic!("{name}: {e}"));
    let (a, b) = (&doc.scene, &back.scene);
    let (wa, wb) = (world(a), world(b));

    r.check(triangle_total(&wa) == triangle_total(&wb), || {
        format!(
            "triangles per instance {} → {}",
            triangle_total(&wa),
            triangle_total(&wb)
        )
    });
    r.same("world-space triangles", &triangles(&wa), &triangles(&wb));
    if to.keeps_polygons() {
        r.same("polygons", &polygons(&wa), &polygons(&wb));
    } else {
        r.check(
            wb.iter().all(|m| m.faces.iter().all(|f| f.len() == 3)),
            || "polygons left untriangulated".into(),
        );
    }
    let expected = as_written(&wa, to);
    for (s, _) in &STREAMS {
        r.same(
            &format!("{s:?} per corner"),
            &corner_triangles(&expected, s),
            &corner_triangles(&wb, s),
        );
    }
    let vertices = expected_vertices(a, from, to);
    r.check(vertex_total(&wb) == vertices, || {
        format!(
            "vertices {} → {}, expected {vertices}",
            vertex_total(&wa),
            vertex_total(&wb)
        )
    });

    let glb_like = |f: Format| matches!(f, Format::Gltf | Format::Glb);
    if glb_like(from) && glb_like(to) {
        // Stored space: the same meshes, instanced by the same nodes.
        r.check(a.meshes.len() == b.meshes.len(), || "mesh count".into());
        for (i, (ma, mb)) in a.meshes.iter().zip(&b.meshes).enumerate() {
            let (ma, mb) = (std::slice::from_ref(ma), std::slice::from_ref(mb));
            r.same(
                &format!("mesh {i} stored triangles"),
                &triangles(ma),
                &triangles(mb),
            );
            let expected = as_written(ma, to);
            for (s, _) in &STREAMS {
                r.same(
                    &format!("mesh {i} stored {s:?} per corner"),
                    &corner_triangles(&expected, s),
                    &corner_triangles(mb, s),
                );
            }
        }
        let matrices = |s: &Scene| -> Vec<[u32; 16]> {
            s.nodes.iter().map(|n| n.matrix.map(f32::to_bits)).collect()
        };
        r.same("node matrices", &matrices(a), &matrices(b));
        r.check(a.skins == b.skins, || "skins changed".into());
        r.check(a.animations == b.animations, || "animations changed".into());
        r.check(a.materials == b.materials, || "materials changed".into());
    } else if !glb_like(to) {
        r.check(b.skins.is_empty() && b.animations.is_empty(), || {
            "skins or animations in a format that has none".into()
        });
    }
    if matches!(to, Format::Ply | Format::Stl) {
        r.check(b.materials.is_empty() && b.textures.is_empty(), || {
            "materials in a format that has none".into()
        });
    }
    if matches!(to, Format::Obj | Format::Gltf | Format::Glb) {
        r.same(
            "per-face part names",
            &part_triangles(a),
            &part_triangles(b),
        );
        r.same(
            "per-face material colors",
            &material_triangles(a),
            &material_triangles(b),
        );
    }
    let expected = expected_warnings(a, to);
    r.check(
        warnings.len() == expected.len()
            && expected
                .iter()
                .all(|e| warnings.iter().filter(|w| w.contains(e)).count() == 1),
        || format!("warnings {warnings:?}, expected one containing each of {expected:?}"),
    );
}

/// Every corpus file (but `large/`) through `to`, all problems reported
/// together.
fn matrix_through(test: &str, to: Format) {
    let Some(root) = corpus(test) else {
        return;
    };
    let files = corpus_files(&root);
    assert!(files.len() >= 35, "found only {} files", files.len());
    let mut problems = Vec::new();
    for f in &files {
        let doc = read(f).unwrap_or_else(|e| panic!("{e}"));
        round_trip(&short(&root, f), &doc, to, &mut problems);
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_corpus_file_round_trips_through_glb() {
    matrix_through("every_corpus_file_round_trips_through_glb", Format::Glb);
}

#[test]
fn every_corpus_file_round_trips_through_gltf() {
    matrix_through("every_corpus_file_round_trips_through_gltf", Format::Gltf);
}

#[test]
fn every_corpus_file_round_trips_through_obj() {
    matrix_through("every_corpus_file_round_trips_through_obj", Format::Obj);
}

#[test]
fn every_corpus_file_round_trips_through_ply() {
    matrix_through("every_corpus_file_round_trips_through_ply", Format::Ply);
}

#[test]
fn every_corpus_file_round_trips_through_stl() {
    matrix_through("every_corpus_file_round_trips_through_stl", Format::Stl);
}

/// The corpus has no PLY file: PLY as an input is covered by the PLY copy
/// of every corpus file, itself checked by the test above.
#[test]
fn ply_copies_of_the_corpus_round_trip_through_every_format() {
    let Some(root) = corpus("ply_copies_of_the_corpus_round_trip_through_every_format") else {
        return;
    };
    let files = corpus_files(&root);
    let mut problems = Vec::new();
    for f in &files {
        let dir = tempfile::tempdir().unwrap();
        let ply = dir.path().join("copy.ply");
        write(&read(f).unwrap(), &ply, &WriteOptions::default()).unwrap();
        let doc = read(&ply).unwrap();
        let source = format!("{} → .ply", short(&root, f));
        for to in [
            Format::Glb,
            Format::Gltf,
            Format::Obj,
            Format::Ply,
            Format::Stl,
        ] {
            round_trip(&source, &doc, to, &mut problems);
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// PLY stores t = 1 − v. For a v read from OBJ text below 0.5, no 32-bit
/// t gives it back (1 − v rounds), so the writer uses a 64-bit t; a file
/// whose v all fit keeps 32-bit floats. Needs no corpus.
#[test]
fn texture_v_from_obj_text_survives_ply_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("0.876543", "property double t"),
        ("0.25", "property float t"),
    ];
    for (v, property) in cases {
        let obj = dir.path().join("in.obj");
        let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 {v}\nf 1/1 2/1 3/1\n");
        std::fs::write(&obj, text).unwrap();
        let doc = read(&obj).unwrap();
        let ply = dir.path().join("out.ply");
        let warnings = write(&doc, &ply, &WriteOptions::default()).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let bytes = std::fs::read(&ply).unwrap();
        let header = String::from_utf8_lossy(&bytes[..bytes.len().min(400)]).into_owned();
        assert!(header.contains(property), "vt v {v}: {header}");
        let uv = |d: &Document| {
            let a = d.scene.meshes[0]
                .attribute(&Semantic::TexCoord(0))
                .unwrap()
                .clone();
            (0..3)
                .map(|c| {
                    a.corner_value(c)
                        .unwrap()
                        .iter()
                        .map(|x| x.to_bits())
                        .collect()
                })
                .collect::<Vec<Vec<u32>>>()
        };
        assert_eq!(uv(&read(&ply).unwrap()), uv(&doc), "vt v {v}");
    }
}
