//! Polygon faces stored flat: `offsets` (one more than the face count) and
//! `indices` (the corners of every face, in order).

/// Polygon faces of any arity, stored flat like a CSR matrix.
///
/// Face `f` uses `indices[offsets[f]..offsets[f + 1]]`. A *corner* is one
/// entry of `indices`; per-corner attribute streams are indexed by corner.
/// Invariants (checked by [`crate::Mesh::validate`]): `offsets[0] == 0`,
/// offsets strictly increase by at least 3, and `offsets.last() ==
/// indices.len()`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Faces {
    /// Start of each face in `indices`, plus one final entry: the corner count.
    pub offsets: Vec<u32>,
    /// Vertex (position) index of every corner.
    pub indices: Vec<u32>,
}

impl Default for Faces {
    fn default() -> Self {
        Self::new()
    }
}

impl Faces {
    /// No faces.
    pub fn new() -> Self {
        Faces {
            offsets: vec![0],
            indices: Vec::new(),
        }
    }

    /// Room for `faces` faces with `corners` corners in all.
    pub fn with_capacity(faces: usize, corners: usize) -> Self {
        let mut offsets = Vec::with_capacity(faces + 1);
        offsets.push(0);
        Faces {
            offsets,
            indices: Vec::with_capacity(corners),
        }
    }

    /// Triangles from a flat index list (three indices per triangle).
    ///
    /// A trailing incomplete triangle is ignored; callers that must report it
    /// check `indices.len() % 3` first.
    pub fn from_triangles(indices: &[u32]) -> Self {
        let n = indices.len() / 3;
        Faces {
            offsets: (0..=n as u32).map(|f| 3 * f).collect(),
            indices: indices[..3 * n].to_vec(),
        }
    }

    /// Appends one face. The caller guarantees at least three corners.
    pub fn push(&mut self, corners: &[u32]) {
        self.indices.extend_from_slice(corners);
        self.offsets.push(self.indices.len() as u32);
    }

    /// Number of faces.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// True when there is no face.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of corners (sum of arities).
    pub fn corner_count(&self) -> usize {
        self.indices.len()
    }

    /// The corners (vertex indices) of face `f`.
    #[inline]
    pub fn face(&self, f: usize) -> &[u32] {
        &self.indices[self.offsets[f] as usize..self.offsets[f + 1] as usize]
    }

    /// The range of corner ids of face `f`.
    #[inline]
    pub fn corner_range(&self, f: usize) -> std::ops::Range<usize> {
        self.offsets[f] as usize..self.offsets[f + 1] as usize
    }

    /// Number of corners of face `f`.
    #[inline]
    pub fn arity(&self, f: usize) -> usize {
        (self.offsets[f + 1] - self.offsets[f]) as usize
    }

    /// Iterates over faces as corner slices.
    pub fn iter(&self) -> FaceIter<'_> {
        FaceIter { faces: self, f: 0 }
    }

    /// Triangle count of the fan-triangulated faces: a triangle counts 1, a
    /// quad 2, an n-gon n − 2. This is the count every target refers to.
    pub fn triangulated_count(&self) -> usize {
        self.iter().map(|f| f.len().saturating_sub(2)).sum()
    }

    /// Counts faces by arity: (triangles, quads, n-gons with n ≥ 5).
    pub fn arity_counts(&self) -> (usize, usize, usize) {
        let (mut t, mut q, mut n) = (0, 0, 0);
        for f in self.iter() {
            match f.len() {
                3 => t += 1,
                4 => q += 1,
                _ => n += 1,
            }
        }
        (t, q, n)
    }
}

/// Iterator over the faces of a [`Faces`], yielding corner slices.
pub struct FaceIter<'a> {
    faces: &'a Faces,
    f: usize,
}

impl<'a> Iterator for FaceIter<'a> {
    type Item = &'a [u32];
    fn next(&mut self) -> Option<&'a [u32]> {
        if self.f >= self.faces.len() {
            return None;
        }
        let s = self.faces.face(self.f);
        self.f += 1;
        Some(s)
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.faces.len() - self.f;
        (n, Some(n))
    }
}

impl ExactSizeIterator for FaceIter<'_> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_counts_as_two_triangles_and_pentagon_as_three() {
        let mut f = Faces::new();
        f.push(&[0, 1, 2]);
        f.push(&[0, 1, 2, 3]);
        f.push(&[0, 1, 2, 3, 4]);
        assert_eq!(f.len(), 3);
        assert_eq!(f.triangulated_count(), 1 + 2 + 3);
        assert_eq!(f.arity_counts(), (1, 1, 1));
        assert_eq!(f.face(1), &[0, 1, 2, 3]);
        assert_eq!(f.corner_range(2), 7..12);
    }

    #[test]
    fn from_triangles_drops_incomplete_tail() {
        let f = Faces::from_triangles(&[0, 1, 2, 2, 1, 3, 9]);
        assert_eq!(f.len(), 2);
        assert_eq!(f.offsets, vec![0, 3, 6]);
    }
}
