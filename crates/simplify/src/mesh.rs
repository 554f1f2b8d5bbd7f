//! Simplifying a [`Mesh`]: its faces and every per-corner stream through
//! [`simplify_with_attributes`], each stream weighted by its meaning
//! ([`crate::AttributeOptions`]), and the result put back into a mesh.

use glam::DVec3;
use wildlod_mesh::{Mesh, Semantic, Skinning, ABSENT};

use crate::attributes::{AttributeInput, AttributeStream, SkinStream, StreamKind};
use crate::error::Error;
use crate::options::{NormalMode, Options};
use crate::report::Report;
use crate::simplify::simplify_with_attributes_and_progress;

/// Simplifies a mesh with its attributes fitted, not copied (Hoppe 1999;
/// Knodt 2024 §3): every UV set, normal, tangent, color and morph delta is
/// evaluated at the simplified positions from the linear functionals of the
/// faces merged into it, seams are kept (see [`crate::SeamPolicy`]), and
/// skin weights end as one influence set per position. Faces keep their
/// part. Values no corner uses any more are dropped.
pub fn simplify_mesh(mesh: &Mesh, options: &Options) -> Result<(Mesh, Report), Error> {
    simplify_mesh_with_progress(mesh, options, &|_| {})
}

/// The stream settings a semantic gets: weight, seams, kind.
fn stream_settings(semantic: &Semantic, options: &Options) -> (f64, bool, StreamKind) {
    let a = &options.attributes;
    match semantic {
        Semantic::TexCoord(_) => (a.tex_coord_weight, true, StreamKind::TexCoord),
        Semantic::Normal => (a.normal_weight, true, StreamKind::Direction),
        // Tangents follow the UV layout's seams and are not steered by:
        // they follow from the UVs and normals.
        Semantic::Tangent => (0.0, true, StreamKind::Direction),
        Semantic::Color(_) => (a.color_weight, true, StreamKind::Color),
        // Deltas follow the same fit as positions; a morph target is no
        // reason to keep or move a vertex.
        Semantic::Morph { .. } => (0.0, false, StreamKind::Generic),
        Semantic::Custom(_) => (0.0, false, StreamKind::Carried),
    }
}

/// [`simplify_mesh`] with a progress callback (see
/// [`crate::simplify_polygons_with_progress`]).
pub fn simplify_mesh_with_progress(
    mesh: &Mesh,
    options: &Options,
    progress: &dyn Fn(f64),
) -> Result<(Mesh, Report), Error> {
    mesh.validate()
        .map_err(|e| Error::InvalidMesh(e.to_string()))?;
    let joints = vertex_joints(mesh);
    let see_through = see_through_faces(mesh, options);
    let with_joints;
    let options =
        if (joints.is_empty() || !options.vertex_joints.is_empty()) && see_through.is_empty() {
            options
        } else {
            with_joints = Options {
                vertex_joints: if options.vertex_joints.is_empty() {
                    joints
                } else {
                    options.vertex_joints.clone()
                },
                see_through_faces: if see_through.is_empty() {
                    options.see_through_faces.clone()
                } else {
                    see_through
                },
                ..options.clone()
            };
            &with_joints
        };
    let streams: Vec<AttributeStream<'_>> = mesh
        .attributes
        .iter()
        .map(|a| {
            let (weight, seams, kind) = stream_settings(&a.semantic, options);
            AttributeStream {
                components: a.components as usize,
                values: &a.values,
                indices: &a.indices,
                weight,
                seams,
                kind,
            }
        })
        .collect();
    let skin = mesh.skinning.as_ref().map(|s| SkinStream {
        influences: s.influences as usize,
        joints: &s.joints,
        weights: &s.weights,
        indices: &s.indices,
        weight: options.attributes.skin_weight,
    });
    let groups = material_groups(mesh);
    let input = AttributeInput {
        streams,
        skin,
        face_groups: &groups,
    };
    let s = simplify_with_attributes_and_progress(
        &mesh.positions,
        &mesh.faces,
        &input,
        options,
        progress,
    )?;
    let mut out = Mesh {
        name: mesh.name.clone(),
        positions: s.positions,
        faces: s.faces,
        face_parts: s
            .face_origin
            .iter()
            .map(|&f| mesh.face_parts[f as usize])
            .collect(),
        parts: mesh.parts.clone(),
        attributes: mesh.attributes.clone(),
        skinning: None,
    };
    for (a, fitted) in out.attributes.iter_mut().zip(s.attributes) {
        a.values = fitted.values;
        a.indices = fitted.indices;
        if a.semantic == Semantic::Tangent && a.components == 4 {
            // The handedness is a sign, not a quantity to average.
            for w in a.values.chunks_exact_mut(4) {
                w[3] = if w[3] < 0.0 { -1.0 } else { 1.0 };
            }
        }
    }
    if options.attributes.normals == NormalMode::Recompute {
        for a in &mut out.attributes {
            if a.semantic == Semantic::Normal && a.components == 3 {
                recompute_normals(&out.positions, &out.faces, a);
            }
        }
    }
    if let Some(k) = out
        .attributes
        .iter()
        .position(|a| a.semantic == Semantic::Tangent)
    {
        // Tangents follow from normals and UVs: a renderer (or a normal map
        // baked for this mesh) rebuilds them with MikkTSpace, so they are
        // regenerated that way rather than fitted. UV set 0 is the one
        // normal maps use unless a material says otherwise; where MikkTSpace
        // cannot run (no normals), the fitted tangents stay.
        if let Ok(t) = wildlod_mesh::tangents::generate_tangents(&out, 0) {
            let a = &mut out.attributes[k];
            a.values = t.values;
            a.indices = t.indices;
        }
    }
    if let (Some(src), Some(fitted)) = (&mesh.skinning, s.skin) {
        out.skinning = Some(Skinning {
            influences: src.influences,
            joints: fitted.joints,
            weights: fitted.weights,
            // One influence set per output vertex, shared by its corners.
            indices: out.faces.indices.clone(),
            weight_format: src.weight_format,
            joint_format: src.joint_format,
        });
    }
    out.compact();
    Ok((out, s.report))
}

/// The faces of [`Options::see_through_materials`], when the caller named
/// some and gave no per-face flags; empty otherwise.
fn see_through_faces(mesh: &Mesh, options: &Options) -> Vec<bool> {
    if options.see_through_materials.is_empty() || !options.see_through_faces.is_empty() {
        return Vec::new();
    }
    let part_sees: Vec<bool> = mesh
        .parts
        .iter()
        .map(|p| {
            p.material
                .is_some_and(|m| options.see_through_materials.contains(&m))
        })
        .collect();
    if !part_sees.contains(&true) {
        return Vec::new();
    }
    mesh.face_parts
        .iter()
        .map(|&p| part_sees.get(p as usize).copied().unwrap_or(false))
        .collect()
}

/// A material id per face when the mesh has faces of at least two
/// materials (their borders are kept like seams); empty otherwise.
fn material_groups(mesh: &Mesh) -> Vec<u32> {
    let material = |f: usize| {
        mesh.parts
            .get(mesh.face_parts[f] as usize)
            .and_then(|p| p.material)
            .unwrap_or(u32::MAX)
    };
    let n = mesh.faces.len();
    if n == 0 || (1..n).all(|f| material(f) == material(0)) {
        return Vec::new();
    }
    (0..n).map(material).collect()
}

/// Normals from the simplified faces: every corner takes the area-weighted
/// sum of the face normals of the corners that share its value (its wedge),
/// so corners that kept one normal wedge are smooth and hard edges stay
/// hard.
fn recompute_normals(
    positions: &[[f32; 3]],
    faces: &wildlod_mesh::Faces,
    normals: &mut wildlod_mesh::Attribute,
) {
    let count = normals.value_count();
    let mut sum = vec![DVec3::ZERO; count];
    let p = |v: u32| DVec3::from(positions[v as usize].map(f64::from));
    let mut corner = 0usize;
    for face in faces.iter() {
        let mut n = DVec3::ZERO;
        for k in 0..face.len() {
            n += p(face[k]).cross(p(face[(k + 1) % face.len()]));
        }
        for _ in face {
            let i = normals.indices[corner];
            if i != ABSENT {
                sum[i as usize] += n;
            }
            corner += 1;
        }
    }
    for (i, s) in sum.iter().enumerate() {
        let len = s.length();
        if len > 0.0 && len.is_finite() {
            let n = *s / len;
            normals.values[3 * i..3 * i + 3].copy_from_slice(&[n.x as f32, n.y as f32, n.z as f32]);
        }
    }
}

/// Joint influences per vertex from the mesh's skinning (each vertex takes
/// the entry of its first corner); empty when the mesh is not skinned. The
/// input of Knodt's joint-difference term (Knodt 2024 Eq. 3,
/// [`crate::Options::vertex_joints`]).
pub fn vertex_joints(mesh: &Mesh) -> Vec<Vec<(u32, f32)>> {
    let Some(s) = &mesh.skinning else {
        return Vec::new();
    };
    let mut out: Vec<Vec<(u32, f32)>> = vec![Vec::new(); mesh.positions.len()];
    let mut seen = vec![false; mesh.positions.len()];
    for (corner, &v) in mesh.faces.indices.iter().enumerate() {
        let (v, entry) = (v as usize, s.indices[corner]);
        if seen[v] || entry == ABSENT {
            continue;
        }
        seen[v] = true;
        let (joints, weights) = s.entry(entry);
        out[v] = joints
            .iter()
            .zip(weights)
            .filter(|(_, &w)| w > 0.0)
            .map(|(&j, &w)| (j as u32, w))
            .collect();
    }
    out
}
