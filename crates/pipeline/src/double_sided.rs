//! Reversed twin faces written once, with a double-sided material (issue
//! 31, decision 5).
//!
//! Exporters make a sheet double-sided by writing every face twice, once
//! each way (SketchUp and many CAD exports do it for whole models). The
//! simplifier keeps both copies of a visible sheet together (a twin rides
//! along with its face) and drops the copies nobody can see, but the
//! copies it keeps still cost twice their triangles, in the budget and on
//! the GPU. glTF says what the exporter meant directly: one face and a
//! material with `doubleSided`. So before simplifying for a glTF output,
//! every pair of faces that are the same cycle of positions walked both
//! ways round, in the same material, becomes one face in a part whose
//! material is a double-sided clone of it (the material itself where it
//! already is double-sided). A renderer lights the back of a double-sided
//! face with its normal reversed, which is what the reversed copy carried.
//!
//! Formats without a double-sided flag (OBJ, PLY, STL) keep both faces:
//! callers only merge for glTF.

use std::collections::HashMap;

use wildlod_mesh::{Material, Mesh, Scene, Semantic, ABSENT};

/// What merging the twins of a scene did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MergedTwins {
    /// Face pairs written once.
    pub pairs: usize,
    /// Triangles the scene draws fewer (every instance counted).
    pub triangles: usize,
}

/// What `simplify` does before simplifying for an output at `output`: a
/// glTF says "double-sided" directly, so its visible twins are merged
/// ([`merge_twins_double_sided`]) and a ratio in `targets` becomes a count
/// of what the input drew (the budget stays of the file as it was); other
/// formats keep both faces. Returns the twins merged and the targets to
/// simplify to.
pub fn merge_twins_for_output(
    scene: &mut Scene,
    output: &std::path::Path,
    targets: &crate::FileTargets,
) -> (MergedTwins, crate::FileTargets) {
    let gltf = matches!(
        wildlod_io::Format::from_path(output),
        Ok(wildlod_io::Format::Gltf | wildlod_io::Format::Glb)
    );
    let mut t = *targets;
    if !gltf {
        return (MergedTwins::default(), t);
    }
    let drawn = crate::drawn_triangles(scene);
    let twins = merge_twins_double_sided(scene);
    if let (Some(r), true) = (t.ratio, twins.triangles > 0) {
        let of_input = (r * drawn as f64).round() as usize;
        t.faces = Some(t.faces.map_or(of_input, |n| n.min(of_input)));
        t.ratio = None;
    }
    (twins, t)
}

/// Merges every reversed twin pair of `scene` that shares a material (see
/// the module documentation). Faces with a repeated position are left
/// alone (no cycle to compare).
pub fn merge_twins_double_sided(scene: &mut Scene) -> MergedTwins {
    let instances = scene.instance_counts();
    let mut clones: HashMap<Option<u32>, u32> = HashMap::new();
    let mut merged = MergedTwins::default();
    for (m, mesh) in scene.meshes.iter_mut().enumerate() {
        let pairs = twin_pairs(mesh, |part| {
            mesh.parts.get(part as usize).and_then(|p| p.material)
        });
        if pairs.is_empty() {
            continue;
        }
        let mut keep = vec![true; mesh.faces.len()];
        // Kept faces move to a part of the double-sided clone, one new part
        // per (old part) that has any.
        let mut new_part: HashMap<u32, u32> = HashMap::new();
        for &(kept, dropped) in &pairs {
            keep[dropped as usize] = false;
            let part = mesh.face_parts[kept as usize];
            let material = mesh.parts[part as usize].material;
            let already = material
                .and_then(|i| scene.materials.get(i as usize))
                .is_some_and(|mat| mat.double_sided);
            if already {
                continue;
            }
            let target = *new_part.entry(part).or_insert_with(|| {
                let clone = *clones.entry(material).or_insert_with(|| {
                    let mut mat = material
                        .and_then(|i| scene.materials.get(i as usize))
                        .cloned()
                        .unwrap_or_else(|| Material {
                            name: "double_sided".into(),
                            ..Material::default()
                        });
                    mat.double_sided = true;
                    if material.is_some() {
                        mat.name = format!("{}_double_sided", mat.name);
                    }
                    scene.materials.push(mat);
                    (scene.materials.len() - 1) as u32
                });
                let mut p = mesh.parts[part as usize].clone();
                p.material = Some(clone);
                mesh.parts.push(p);
                (mesh.parts.len() - 1) as u32
            });
            mesh.face_parts[kept as usize] = target;
        }
        let triangles: usize = pairs
            .iter()
            .map(|&(_, d)| mesh.faces.arity(d as usize).saturating_sub(2))
            .sum();
        merged.pairs += pairs.len();
        merged.triangles += triangles * instances.get(m).copied().unwrap_or(1).max(1);
        mesh.retain_faces(&keep);
    }
    merged
}

/// A face's material and its cycle of positions, rotated canonically.
type CycleKey = (Option<u32>, Vec<[u32; 3]>);

/// Pairs (kept, dropped) of faces of `mesh` that are one cycle of
/// positions walked both ways round in the same material (`material` of
/// a part), each face in one pair at most; the earlier face is kept.
fn twin_pairs(mesh: &Mesh, material: impl Fn(u32) -> Option<u32>) -> Vec<(u32, u32)> {
    // Positions by value (-0 and +0 alike), so twins with vertices of their
    // own (split normals) still match.
    let key = |v: u32| {
        mesh.positions
            .get(v as usize)
            .map(|p| p.map(|x| (if x == 0.0 { 0.0f32 } else { x }).to_bits()))
    };
    let key = &key;
    let mut open: HashMap<CycleKey, Vec<u32>> = HashMap::new();
    let mut pairs = Vec::new();
    for f in 0..mesh.faces.len() {
        let Some(cycle) = mesh
            .faces
            .face(f)
            .iter()
            .map(|&v| key(v))
            .collect::<Option<Vec<[u32; 3]>>>()
        else {
            continue;
        };
        let mut sorted = cycle.clone();
        sorted.sort_unstable();
        if cycle.len() < 3 || sorted.windows(2).any(|w| w[0] == w[1]) {
            continue;
        }
        let mat = mesh.face_parts.get(f).and_then(|&p| material(p));
        let forward = canonical(cycle.iter().copied());
        let backward = canonical(cycle.iter().rev().copied());
        // A waiting face walked the other way round is this one's twin.
        if let Some(waiting) = open.get_mut(&(mat, backward)) {
            if let Some(k) = waiting
                .iter()
                .rposition(|&g| same_look(mesh, g as usize, f, &key))
            {
                pairs.push((waiting.remove(k), f as u32));
                continue;
            }
        }
        open.entry((mat, forward)).or_default().push(f as u32);
    }
    // Deterministic regardless of hashing: pairs were made in face order.
    pairs
}

/// Whether faces `a` and `b` (one cycle of positions both ways round) show
/// the same where they share a position: equal texture coordinates and
/// colors at every position (normals differ by their sign, as a renderer
/// makes them for a back face). A back with UVs of its own (a flag whose
/// back is mirrored to read the right way round) would show otherwise as
/// a double-sided face, so it keeps its faces.
fn same_look(mesh: &Mesh, a: usize, b: usize, key: &dyn Fn(u32) -> Option<[u32; 3]>) -> bool {
    let corners_b: Vec<(Option<[u32; 3]>, usize)> = mesh
        .faces
        .corner_range(b)
        .map(|c| (key(mesh.faces.indices[c]), c))
        .collect();
    mesh.faces.corner_range(a).all(|ca| {
        let k = key(mesh.faces.indices[ca]);
        let Some(&(_, cb)) = corners_b.iter().find(|(kb, _)| *kb == k) else {
            return false;
        };
        mesh.attributes
            .iter()
            .filter(|s| matches!(s.semantic, Semantic::TexCoord(_) | Semantic::Color(_)))
            .all(|s| {
                let value = |c: usize| {
                    s.indices
                        .get(c)
                        .filter(|&&i| i != ABSENT)
                        .map(|&i| s.value(i).to_vec())
                };
                value(ca) == value(cb)
            })
    })
}

/// A cycle rotated to start at its smallest element.
fn canonical(cycle: impl Iterator<Item = [u32; 3]>) -> Vec<[u32; 3]> {
    let c: Vec<[u32; 3]> = cycle.collect();
    let start = (0..c.len()).min_by_key(|&k| c[k]).unwrap_or(0);
    c[start..].iter().chain(&c[..start]).copied().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use wildlod_mesh::{Faces, Part};

    /// Two triangles of a square, each written both ways round with
    /// vertices of their own (as exporters split normals), plus one face
    /// only one way.
    fn sheet() -> Scene {
        let p = |x: f32, y: f32| [x, y, 0.0];
        let positions = vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0),
            p(0.0, 1.0),
            // The back's own copies.
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0),
            p(0.0, 1.0),
            p(2.0, 0.0),
        ];
        let faces = Faces::from_triangles(&[
            0, 1, 2, // front
            0, 2, 3, // front
            6, 5, 4, // back of the first, rotated
            4, 7, 6, // back of the second
            1, 8, 2, // single-sided
        ]);
        let mut mesh = Mesh::from_polygons(positions, faces);
        mesh.parts = vec![Part {
            name: "sheet".into(),
            material: Some(0),
        }];
        let mut scene = Scene::from_mesh(mesh);
        scene.materials.push(Material {
            name: "paper".into(),
            ..Material::default()
        });
        scene
    }

    #[test]
    fn twins_become_one_face_of_a_double_sided_clone() {
        let mut scene = sheet();
        let merged = merge_twins_double_sided(&mut scene);
        assert_eq!(
            merged,
            MergedTwins {
                pairs: 2,
                triangles: 2
            }
        );
        let mesh = &scene.meshes[0];
        assert_eq!(mesh.faces.len(), 3);
        // The fronts are kept, in the clone's part; the single face stays.
        assert_eq!(mesh.faces.face(0), &[0, 1, 2]);
        assert_eq!(mesh.faces.face(1), &[0, 2, 3]);
        assert_eq!(mesh.faces.face(2), &[1, 8, 2]);
        let material = |f: usize| mesh.parts[mesh.face_parts[f] as usize].material.unwrap();
        assert_eq!(material(2), 0);
        let clone = &scene.materials[material(0) as usize];
        assert!(clone.double_sided && clone.name == "paper_double_sided");
        assert_eq!(material(1), material(0));
        assert!(!scene.materials[0].double_sided);
    }

    #[test]
    fn different_materials_or_one_way_round_are_not_twins() {
        let mut scene = sheet();
        // The backs in another material.
        let mesh = &mut scene.meshes[0];
        mesh.parts.push(Part {
            name: "back".into(),
            material: Some(1),
        });
        mesh.face_parts[2] = 1;
        mesh.face_parts[3] = 1;
        scene.materials.push(Material::default());
        assert_eq!(merge_twins_double_sided(&mut scene).pairs, 0);
        assert_eq!(scene.meshes[0].faces.len(), 5);
        // The same face twice the same way round is a duplicate, not a twin.
        let mut dup = Scene::from_mesh(Mesh::from_triangles(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2, 1, 2, 0],
        ));
        assert_eq!(merge_twins_double_sided(&mut dup).pairs, 0);
    }

    #[test]
    fn a_double_sided_material_is_used_as_it_is() {
        let mut scene = sheet();
        scene.materials[0].double_sided = true;
        assert_eq!(merge_twins_double_sided(&mut scene).pairs, 2);
        assert_eq!(scene.materials.len(), 1);
        assert!(scene.meshes[0].face_parts.iter().all(|&p| p == 0));
    }
}
