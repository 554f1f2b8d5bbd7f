//! MikkTSpace tangents per corner, as glTF expects them.
//!
//! glTF 2.0 says a renderer without stored tangents computes MikkTSpace
//! tangents from positions, normals and the normal texture's UVs, and that
//! the bitangent is `cross(normal, tangent.xyz) * tangent.w`, with the normal
//! map's +Y pointing *up* the image. Our UVs follow glTF (`v = 0` is the top
//! row), while MikkTSpace measures `v` upwards like OpenGL; so `v` is flipped
//! before MikkTSpace sees it (Blender's importer does the same). On a plane
//! mapped without mirroring this gives `w = +1` and a bitangent pointing to
//! the top of the image, which is what normal maps authored for glTF expect.
//!
//! Re-baked normal maps (W §4.3) must be expressed in exactly the frame the
//! renderer will rebuild, so the baker and any writer that stores tangents
//! use this one function.

use std::collections::HashMap;

use crate::attribute::{Attribute, ComponentFormat, Semantic, ABSENT};
use crate::mesh::Mesh;

/// Why tangents could not be generated.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TangentError {
    /// The mesh has no normal stream.
    #[error("the mesh has no normals")]
    NoNormals,
    /// The mesh has no stream for the requested UV set.
    #[error("the mesh has no UV set {0}")]
    NoUvs(u32),
    /// MikkTSpace refused the geometry (for instance, no faces).
    #[error("MikkTSpace could not generate tangents")]
    Failed,
}

/// MikkTSpace tangents (xyz + handedness `w` = ±1) for every corner of
/// `mesh`, from its normals and UV set `uv_set`, as a
/// [`Semantic::Tangent`] stream whose equal values are shared.
///
/// Triangles and quads go to MikkTSpace as they are; larger polygons as
/// fans, each corner taking the tangent of the first fan triangle it is in.
/// Corners without a normal or a UV get [`ABSENT`].
///
/// # Errors
/// [`TangentError`] when the mesh lacks normals or that UV set, or when
/// MikkTSpace rejects the geometry.
pub fn generate_tangents(mesh: &Mesh, uv_set: u32) -> Result<Attribute, TangentError> {
    let normals = mesh
        .attribute(&Semantic::Normal)
        .ok_or(TangentError::NoNormals)?;
    let uvs = mesh
        .attribute(&Semantic::TexCoord(uv_set))
        .ok_or(TangentError::NoUvs(uv_set))?;
    // MikkTSpace takes faces of 3 or 4 corners: polygons become fans, each
    // (face, vertex) of the fan naming a corner of the mesh.
    let mut fans: Vec<[u32; 4]> = Vec::with_capacity(mesh.faces.len());
    let mut arity: Vec<u8> = Vec::with_capacity(mesh.faces.len());
    for f in 0..mesh.faces.len() {
        let start = mesh.faces.offsets[f];
        let n = mesh.faces.offsets[f + 1] - start;
        if n <= 4 {
            let mut c = [start; 4];
            for (k, slot) in c.iter_mut().enumerate().take(n as usize) {
                *slot = start + k as u32;
            }
            fans.push(c);
            arity.push(n as u8);
        } else {
            for k in 1..n - 1 {
                fans.push([start, start + k, start + k + 1, start]);
                arity.push(3);
            }
        }
    }
    let mut geometry = Geometry {
        mesh,
        normals,
        uvs,
        fans: &fans,
        arity: &arity,
        tangents: vec![None; mesh.faces.corner_count()],
    };
    if !mikktspace::generate_tangents(&mut geometry) {
        return Err(TangentError::Failed);
    }
    Ok(shared_stream(&geometry.tangents))
}

/// The stream of per-corner tangents, one pool value per distinct tangent.
fn shared_stream(tangents: &[Option<[f32; 4]>]) -> Attribute {
    let mut values = Vec::new();
    let mut indices = Vec::with_capacity(tangents.len());
    let mut seen: HashMap<[u32; 4], u32> = HashMap::new();
    for t in tangents {
        let Some(t) = t else {
            indices.push(ABSENT);
            continue;
        };
        let key = t.map(f32::to_bits);
        let next = seen.len() as u32;
        let i = *seen.entry(key).or_insert_with(|| {
            values.extend_from_slice(t);
            next
        });
        indices.push(i);
    }
    Attribute {
        semantic: Semantic::Tangent,
        components: 4,
        values,
        indices,
        format: ComponentFormat::F32,
    }
}

struct Geometry<'a> {
    mesh: &'a Mesh,
    normals: &'a Attribute,
    uvs: &'a Attribute,
    fans: &'a [[u32; 4]],
    arity: &'a [u8],
    tangents: Vec<Option<[f32; 4]>>,
}

impl Geometry<'_> {
    fn corner(&self, face: usize, vert: usize) -> usize {
        self.fans[face][vert] as usize
    }

    fn complete(&self, corner: usize) -> bool {
        self.normals.indices[corner] != ABSENT && self.uvs.indices[corner] != ABSENT
    }
}

impl mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.fans.len()
    }

    fn num_vertices_of_face(&self, face: usize) -> usize {
        self.arity[face] as usize
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        let c = self.corner(face, vert);
        self.mesh.positions[self.mesh.faces.indices[c] as usize]
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        match self.normals.corner_value(self.corner(face, vert)) {
            Some(n) if n.len() >= 3 => [n[0], n[1], n[2]],
            _ => [0.0, 0.0, 1.0],
        }
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        match self.uvs.corner_value(self.corner(face, vert)) {
            // glTF's v runs down the image, MikkTSpace's up (module docs).
            Some(uv) if uv.len() >= 2 => [uv[0], 1.0 - uv[1]],
            _ => [0.0, 0.0],
        }
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        let c = self.corner(face, vert);
        if self.tangents[c].is_none() && self.complete(c) {
            self.tangents[c] = Some(tangent);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::faces::Faces;

    /// A unit quad in the z = 0 plane facing +z, as two triangles:
    ///
    /// ```text
    ///  3 ─── 2     uv (0,0) at vertex 3 (top-left of the image),
    ///  │  ╱  │     u along +x, v down the image = along −y
    ///  0 ─── 1
    /// ```
    fn plane(u_sign: f32) -> Mesh {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mut m = Mesh::from_polygons(
            positions.clone(),
            Faces::from_triangles(&[0, 1, 2, 0, 2, 3]),
        );
        let uv: Vec<f32> = positions
            .iter()
            .flat_map(|p| [0.5 + u_sign * (p[0] - 0.5), 1.0 - p[1]])
            .collect();
        let idx = m.faces.indices.clone();
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: uv,
            indices: idx.clone(),
            format: ComponentFormat::F32,
        });
        m.attributes.push(Attribute {
            semantic: Semantic::Normal,
            components: 3,
            values: [0.0, 0.0, 1.0].repeat(4),
            indices: idx,
            format: ComponentFormat::F32,
        });
        m
    }

    fn close(a: &[f32], b: &[f32]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5)
    }

    #[test]
    fn plane_with_v_down_the_image_has_tangent_x_and_bitangent_up() {
        let t = generate_tangents(&plane(1.0), 0).expect("tangents");
        for c in 0..6 {
            let v = t.corner_value(c).expect("every corner has a tangent");
            // w = +1: cross(n, t) * w = cross(z, x) = +y, the image's up.
            assert!(close(v, &[1.0, 0.0, 0.0, 1.0]), "corner {c}: {v:?}");
        }
        // All six corners share one value.
        assert_eq!(t.value_count(), 1);
    }

    #[test]
    fn mirrored_uvs_flip_the_tangent_and_keep_the_bitangent_up() {
        // u runs along −x: tangent −x; the bitangent must still point +y,
        // so w = −1 (cross(z, −x) = −y, times −1).
        let t = generate_tangents(&plane(-1.0), 0).expect("tangents");
        let v = t.corner_value(0).expect("tangent");
        assert!(close(v, &[-1.0, 0.0, 0.0, -1.0]), "{v:?}");
    }

    #[test]
    fn pentagon_corners_all_get_tangents() {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.5, 0.8, 0.0],
            [0.5, 1.5, 0.0],
            [-0.5, 0.8, 0.0],
        ];
        let mut faces = Faces::new();
        faces.push(&[0, 1, 2, 3, 4]);
        let mut m = Mesh::from_polygons(positions.clone(), faces);
        let idx = m.faces.indices.clone();
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: positions.iter().flat_map(|p| [p[0], 1.0 - p[1]]).collect(),
            indices: idx.clone(),
            format: ComponentFormat::F32,
        });
        m.attributes.push(Attribute {
            semantic: Semantic::Normal,
            components: 3,
            values: [0.0, 0.0, 1.0].repeat(5),
            indices: idx,
            format: ComponentFormat::F32,
        });
        let t = generate_tangents(&m, 0).expect("tangents");
        for c in 0..5 {
            let v = t.corner_value(c).expect("tangent");
            assert!(close(v, &[1.0, 0.0, 0.0, 1.0]), "corner {c}: {v:?}");
        }
    }

    #[test]
    fn missing_streams_are_named() {
        let mut m = plane(1.0);
        m.attributes.retain(|a| a.semantic != Semantic::Normal);
        assert_eq!(generate_tangents(&m, 0), Err(TangentError::NoNormals));
        assert_eq!(
            generate_tangents(&plane(1.0), 1),
            Err(TangentError::NoUvs(1))
        );
    }
}
