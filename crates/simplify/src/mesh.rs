//! Simplifying a [`Mesh`]: its faces through [`simplify_polygons`], its
//! parts, attribute streams and skin influences carried along per corner.

use wildlod_mesh::Mesh;

use crate::error::Error;
use crate::options::Options;
use crate::report::Report;
use crate::simplify::simplify_polygons_with_progress;

/// Simplifies a mesh and carries everything per corner: each surviving
/// corner keeps the attribute values (UVs, normals, colors, morph deltas,
/// skin influences) it had in the input, and each face its part. Attribute
/// seams cannot tear the surface: positions are welded before simplifying.
/// Values no corner uses any more are dropped.
pub fn simplify_mesh(mesh: &Mesh, options: &Options) -> Result<(Mesh, Report), Error> {
    simplify_mesh_with_progress(mesh, options, &|_| {})
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
    let s = if joints.is_empty() || !options.vertex_joints.is_empty() {
        simplify_polygons_with_progress(&mesh.positions, &mesh.faces, options, progress)?
    } else {
        let options = Options {
            vertex_joints: joints,
            ..options.clone()
        };
        simplify_polygons_with_progress(&mesh.positions, &mesh.faces, &options, progress)?
    };
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
        skinning: mesh.skinning.clone(),
    };
    for a in &mut out.attributes {
        a.indices = s
            .corner_origin
            .iter()
            .map(|&c| a.indices[c as usize])
            .collect();
    }
    if let Some(sk) = &mut out.skinning {
        sk.indices = s
            .corner_origin
            .iter()
            .map(|&c| sk.indices[c as usize])
            .collect();
    }
    out.compact();
    Ok((out, s.report))
}

/// Joint influences per vertex from the mesh's skinning (each vertex takes
/// the entry of its first corner); empty when the mesh is not skinned.
fn vertex_joints(mesh: &Mesh) -> Vec<Vec<(u32, f32)>> {
    let Some(s) = &mesh.skinning else {
        return Vec::new();
    };
    let mut out: Vec<Vec<(u32, f32)>> = vec![Vec::new(); mesh.positions.len()];
    let mut seen = vec![false; mesh.positions.len()];
    for (corner, &v) in mesh.faces.indices.iter().enumerate() {
        let (v, entry) = (v as usize, s.indices[corner]);
        if seen[v] || entry == wildlod_mesh::ABSENT {
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
