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
    let s = simplify_polygons_with_progress(&mesh.positions, &mesh.faces, options, progress)?;
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
