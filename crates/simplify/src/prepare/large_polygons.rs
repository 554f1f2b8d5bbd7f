//! Large polygons are split into pieces before simplifying.
//!
//! The complex keeps faces as polygons (Knodt 2024: output faces are input
//! faces with merged vertices), and much of the per-collapse work is linear
//! in the arity of the faces around the collapse: the boundary area term
//! walks the boundary edges of the one-ring, normalizing a face scans it,
//! the guards triangulate it. On a k-gon every edge sees the whole face, so
//! one collapse costs O(k) per edge re-evaluated and O(k) edges change:
//! a 20,000-corner CAD cap never finished. Split into pieces of at most
//! [`MAX_POLYGON_CORNERS`] corners (`wildlod_mesh::polygon::split_polygon`,
//! O(k log k), balanced so no vertex gets a fan's valence), the cap costs
//! what its triangles cost.
//!
//! Decision: the pieces stay in the output, each mapped to the input face
//! it came from (`face_origin`, `corner_origin`), so attributes and parts
//! ride along. Keeping the polygon whole would need a face representation
//! whose collapses cost O(log k); no mesh of the corpus has a face above 16
//! corners, so the limit changes nothing there.

use wildlod_mesh::polygon::split_polygon;
use wildlod_mesh::{Faces, ABSENT};

use crate::input::{AttributeInput, SkinStream};

/// Polygons with more corners than this are split into pieces of at most
/// this many before simplifying. 32: twice the corpus's largest polygon,
/// and small enough that a piece costs about what its triangles cost.
pub const MAX_POLYGON_CORNERS: usize = 32;

/// Faces with the large polygons split, and the way back to the input.
pub(crate) struct Split {
    /// The faces the simplifier works on.
    pub faces: Faces,
    /// For every face of `faces`, the input face it is (a piece of).
    face_origin: Vec<u32>,
    /// For every corner of `faces`, the input corner it is.
    corner_origin: Vec<u32>,
    /// How many input polygons were split.
    pub polygons: usize,
}

/// Splits the faces above [`MAX_POLYGON_CORNERS`]; `None` when there is
/// none (the common case costs one pass over the offsets), or when the
/// attribute input does not match the faces (its own check reports that,
/// on the faces as given).
pub(crate) fn split_large(
    positions: &[[f32; 3]],
    faces: &Faces,
    attributes: &AttributeInput<'_>,
) -> Option<Split> {
    if (0..faces.len()).all(|f| faces.arity(f) <= MAX_POLYGON_CORNERS) {
        return None;
    }
    let corners = faces.corner_count();
    let mismatched = attributes
        .streams
        .iter()
        .any(|s| s.indices.len() != corners)
        || attributes.skin.is_some_and(|s| s.indices.len() != corners)
        || !(attributes.face_groups.is_empty() || attributes.face_groups.len() == faces.len());
    if mismatched {
        return None;
    }
    let mut out = Split {
        faces: Faces::with_capacity(faces.len(), faces.corner_count()),
        face_origin: Vec::with_capacity(faces.len()),
        corner_origin: Vec::with_capacity(faces.corner_count()),
        polygons: 0,
    };
    let mut pieces = Faces::new();
    let mut points = Vec::new();
    for f in 0..faces.len() {
        let r = faces.corner_range(f);
        if r.len() <= MAX_POLYGON_CORNERS {
            out.faces.push(&faces.indices[r.clone()]);
            out.face_origin.push(f as u32);
            out.corner_origin.extend(r.map(|c| c as u32));
            continue;
        }
        out.polygons += 1;
        points.clear();
        // Indices were checked against `positions` before this runs.
        points.extend(
            faces.indices[r.clone()]
                .iter()
                .map(|&v| positions.get(v as usize).copied().unwrap_or([0.0; 3])),
        );
        pieces.offsets.truncate(1);
        pieces.indices.clear();
        split_polygon(&points, MAX_POLYGON_CORNERS, &mut pieces);
        let mut corners = Vec::new();
        for piece in pieces.iter() {
            corners.clear();
            corners.extend(piece.iter().map(|&k| faces.indices[r.start + k as usize]));
            out.faces.push(&corners);
            out.face_origin.push(f as u32);
            out.corner_origin
                .extend(piece.iter().map(|&k| (r.start + k as usize) as u32));
        }
    }
    Some(out)
}

/// The per-corner and per-face parts of an [`AttributeInput`], re-indexed
/// for the split faces (values stay borrowed from the input).
pub(crate) struct SplitAttributes {
    streams: Vec<Vec<u32>>,
    skin: Option<Vec<u32>>,
    face_groups: Vec<u32>,
}

impl SplitAttributes {
    /// The input with its indices replaced by the split ones.
    pub fn input<'s>(&'s self, original: &AttributeInput<'s>) -> AttributeInput<'s> {
        let mut out = original.clone();
        for (s, indices) in out.streams.iter_mut().zip(&self.streams) {
            s.indices = indices;
        }
        if let (Some(skin), Some(indices)) = (&mut out.skin, &self.skin) {
            *skin = SkinStream { indices, ..*skin };
        }
        out.face_groups = &self.face_groups;
        out
    }
}

impl Split {
    /// The attribute input's indices for the split faces: each split corner
    /// takes its input corner's value, each piece its face's group.
    pub fn attributes(&self, input: &AttributeInput<'_>) -> SplitAttributes {
        let per_corner = |indices: &[u32]| -> Vec<u32> {
            self.corner_origin
                .iter()
                .map(|&c| indices.get(c as usize).copied().unwrap_or(ABSENT))
                .collect()
        };
        SplitAttributes {
            streams: input
                .streams
                .iter()
                .map(|s| per_corner(s.indices))
                .collect(),
            skin: input.skin.map(|s| per_corner(s.indices)),
            face_groups: if input.face_groups.is_empty() {
                Vec::new()
            } else {
                self.face_origin
                    .iter()
                    .map(|&f| input.face_groups.get(f as usize).copied().unwrap_or(0))
                    .collect()
            },
        }
    }

    /// The input face a piece comes from.
    pub fn input_face(&self, piece: u32) -> u32 {
        self.face_origin[piece as usize]
    }

    /// The input corner a piece's corner comes from.
    pub fn input_corner(&self, corner: u32) -> u32 {
        self.corner_origin[corner as usize]
    }
}
