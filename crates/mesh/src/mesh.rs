//! The [`Mesh`]: one stored mesh of a file (a glTF mesh with all its
//! primitives, an OBJ file's faces, a PLY or STL body).

use crate::attribute::{Attribute, Semantic, Skinning};
use crate::faces::Faces;

/// A group of faces that share a material and a source grouping: a glTF
/// primitive, or a run of OBJ faces under one `o`/`g`/`usemtl`.
///
/// Writers emit one primitive (glTF) or one group (OBJ) per part; the
/// simplifier keeps every surviving face in its part.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Part {
    /// Object or group name (OBJ `o`/`g`), empty when the source had none.
    pub name: String,
    /// Material index into [`crate::Scene::materials`].
    pub material: Option<u32>,
}

/// One mesh: positions, polygon faces, per-corner attribute streams,
/// optional skin influences, and the part of every face.
///
/// Positions are the file's vertices as stored: a glTF vertex split at a UV
/// seam appears twice with the same position, an STL soup has three
/// positions per triangle. Algorithms that need connectivity weld equal
/// positions first ([`crate::weld`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Name of the mesh (glTF mesh name, OBJ file stem…).
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Polygon faces indexing `positions`.
    pub faces: Faces,
    /// Part of every face, indexing `parts`.
    pub face_parts: Vec<u32>,
    /// The parts (at least one when there are faces).
    pub parts: Vec<Part>,
    /// Per-corner attribute streams.
    pub attributes: Vec<Attribute>,
    /// Per-corner skin influences, when the mesh is skinned.
    pub skinning: Option<Skinning>,
}

impl Mesh {
    /// A mesh of polygons with one part and no attribute.
    pub fn from_polygons(positions: Vec<[f32; 3]>, faces: Faces) -> Self {
        let n = faces.len();
        Mesh {
            name: String::new(),
            positions,
            faces,
            face_parts: vec![0; n],
            parts: vec![Part::default()],
            attributes: Vec::new(),
            skinning: None,
        }
    }

    /// A mesh of triangles (three indices each) with one part.
    pub fn from_triangles(positions: Vec<[f32; 3]>, indices: &[u32]) -> Self {
        Self::from_polygons(positions, Faces::from_triangles(indices))
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Triangle count of the triangulated mesh (a quad counts 2).
    pub fn triangle_count(&self) -> usize {
        self.faces.triangulated_count()
    }

    /// The stream with the given semantic, if any.
    pub fn attribute(&self, semantic: &Semantic) -> Option<&Attribute> {
        self.attributes.iter().find(|a| &a.semantic == semantic)
    }

    /// Axis-aligned bounds of the positions used by faces, or `None` when
    /// no face exists. Non-finite positions are skipped.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut any = false;
        for &v in &self.faces.indices {
            let Some(p) = self.positions.get(v as usize) else {
                continue;
            };
            if !p.iter().all(|c| c.is_finite()) {
                continue;
            }
            any = true;
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        any.then_some((lo, hi))
    }

    /// Length of the diagonal of the box the bulk of the positions used by
    /// faces spans (0 for an empty mesh): [`Mesh::bounds`]' diagonal,
    /// except that vertices far from all the others (a height of -1e30 an
    /// exporter wrote) are left out by [`crate::bounds::robust_bounds`]'s
    /// rule. The size errors are relative to.
    pub fn diagonal(&self) -> f64 {
        let mut used = vec![false; self.positions.len()];
        for &v in &self.faces.indices {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
        let points = used
            .iter()
            .zip(&self.positions)
            .filter(|(&u, _)| u)
            .map(|(_, p)| p.map(f64::from));
        crate::bounds::robust_bounds(points, &Default::default()).diagonal()
    }

    /// Keeps the faces `keep` marks (a face past its end is kept), with
    /// their parts and their corners' attribute and skin indices, in
    /// order. Positions and values stay (see [`Mesh::compact`]).
    pub fn retain_faces(&mut self, keep: &[bool]) {
        let kept = |f: usize| keep.get(f).copied().unwrap_or(true);
        let mut faces = Faces::with_capacity(self.faces.len(), self.faces.corner_count());
        let mut corners: Vec<usize> = Vec::with_capacity(self.faces.corner_count());
        let mut face_parts = Vec::with_capacity(self.face_parts.len());
        for f in 0..self.faces.len() {
            if !kept(f) {
                continue;
            }
            faces.push(self.faces.face(f));
            corners.extend(self.faces.corner_range(f));
            if let Some(&p) = self.face_parts.get(f) {
                face_parts.push(p);
            }
        }
        let pick = |indices: &[u32]| -> Vec<u32> {
            corners
                .iter()
                .map(|&c| indices.get(c).copied().unwrap_or(crate::ABSENT))
                .collect()
        };
        for a in &mut self.attributes {
            a.indices = pick(&a.indices);
        }
        if let Some(s) = &mut self.skinning {
            s.indices = pick(&s.indices);
        }
        self.faces = faces;
        self.face_parts = face_parts;
    }

    /// Removes positions and attribute values no corner uses, keeping the
    /// order of the rest. Returns the old-to-new position map (`u32::MAX`
    /// for dropped positions).
    pub fn compact(&mut self) -> Vec<u32> {
        let map = compact_pool(&mut self.faces.indices, self.positions.len());
        self.positions = gather(&self.positions, &map, 1);
        for a in &mut self.attributes {
            let n = a.value_count();
            let amap = compact_pool(&mut a.indices, n);
            a.values = gather(&a.values, &amap, a.components as usize);
        }
        if let Some(s) = &mut self.skinning {
            let n = s.entry_count();
            let smap = compact_pool(&mut s.indices, n);
            let k = s.influences as usize;
            s.joints = gather(&s.joints, &smap, k);
            s.weights = gather(&s.weights, &smap, k);
        }
        map
    }
}

/// Renumbers the used entries of a pool of `n` items in order of first
/// index; rewrites `indices` and returns the old-to-new map.
fn compact_pool(indices: &mut [u32], n: usize) -> Vec<u32> {
    let mut used = vec![false; n];
    for &i in indices.iter() {
        if let Some(u) = used.get_mut(i as usize) {
            *u = true;
        }
    }
    let mut map = vec![u32::MAX; n];
    let mut next = 0u32;
    for (i, u) in used.iter().enumerate() {
        if *u {
            map[i] = next;
            next += 1;
        }
    }
    for i in indices.iter_mut() {
        if let Some(&m) = map.get(*i as usize) {
            *i = m;
        }
    }
    map
}

/// Keeps the items (of `stride` elements each) whose map entry is not
/// `u32::MAX`, in order.
fn gather<T: Copy>(data: &[T], map: &[u32], stride: usize) -> Vec<T> {
    let mut out = Vec::with_capacity(data.len());
    for (i, &m) in map.iter().enumerate() {
        if m != u32::MAX {
            out.extend_from_slice(&data[i * stride..(i + 1) * stride]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attribute::{ComponentFormat, ABSENT};

    #[test]
    fn compact_drops_unused_positions_and_values_in_order() {
        // 0 and 3 are unused; UV value 1 is unused.
        let mut m = Mesh::from_triangles(
            vec![
                [9.0; 3],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [7.0; 3],
                [0.0, 0.0, 1.0],
            ],
            &[1, 2, 4],
        );
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: vec![0.0, 0.0, 5.0, 5.0, 1.0, 1.0],
            indices: vec![0, 2, ABSENT],
            format: ComponentFormat::F32,
        });
        let map = m.compact();
        assert_eq!(map, vec![u32::MAX, 0, 1, u32::MAX, 2]);
        assert_eq!(m.faces.indices, vec![0, 1, 2]);
        assert_eq!(
            m.positions,
            vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        );
        assert_eq!(m.attributes[0].values, vec![0.0, 0.0, 1.0, 1.0]);
        assert_eq!(m.attributes[0].indices, vec![0, 1, ABSENT]);
    }

    #[test]
    fn retain_faces_keeps_the_marked_faces_with_their_parts_and_corner_indices() {
        let mut m = Mesh::from_polygons(
            vec![[0.0; 3]; 5],
            Faces {
                offsets: vec![0, 3, 7, 10],
                indices: vec![0, 1, 2, 0, 1, 3, 4, 2, 3, 4],
            },
        );
        m.parts.push(Part::default());
        m.face_parts = vec![0, 1, 0];
        m.attributes.push(Attribute {
            semantic: Semantic::TexCoord(0),
            components: 2,
            values: vec![0.0; 20],
            indices: (0..10).collect(),
            format: ComponentFormat::F32,
        });
        m.retain_faces(&[true, false, true]);
        assert_eq!(m.faces.offsets, vec![0, 3, 6]);
        assert_eq!(m.faces.indices, vec![0, 1, 2, 2, 3, 4]);
        assert_eq!(m.face_parts, vec![0, 0]);
        // The third face's corners were 7..10.
        assert_eq!(m.attributes[0].indices, vec![0, 1, 2, 7, 8, 9]);
    }

    #[test]
    fn diagonal_of_unit_cube_corner_triangle() {
        let m = Mesh::from_triangles(vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]], &[0, 1, 2]);
        assert!((m.diagonal() - 3f64.sqrt()).abs() < 1e-12);
    }
}
