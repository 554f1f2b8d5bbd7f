//! The attributes a caller hands to the simplifier as plain arrays (like
//! meshoptimizer's `simplifyWithAttributes`), and what it gets back.

/// Per-corner index meaning "this corner has no value in this stream".
pub use wildlod_mesh::ABSENT;

/// What a stream holds: how its error is measured against geometry (so
/// that one weight means the same on every asset) and how its fitted values
/// are finished. Positions are measured relative to the bounding-box
/// diagonal; each kind is brought to that scale:
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StreamKind {
    /// Anything continuous with no known scale (morph deltas, custom
    /// floats): values are divided by the stream's range (the largest
    /// extent of a component over the input). Fitted values are clamped to
    /// the input's range per component.
    #[default]
    Generic,
    /// Texture coordinates: a UV error is measured as the distance the
    /// texture slides on the surface, `|Δuv| · sqrt(surface area / UV
    /// area)`, so weight 1 makes a texture shift cost as much as moving the
    /// surface by the same distance, whatever the atlas or the units.
    /// Fitted values are clamped to the input's range.
    TexCoord,
    /// Unit vectors (normals; the xyz of tangents): a change of `θ`
    /// (radians, about `|Δn|`) is measured as the displacement it means one
    /// edge away, `θ` times the input's mean edge length: normals change
    /// with the distance a collapse spans, so measured raw they would
    /// outweigh geometry more the finer the mesh. Fitted, then normalized.
    Direction,
    /// Colors in [0, 1]: like directions, a change of `d` is measured as `d`
    /// times the input's mean edge length. Fitted values are clamped to the
    /// input's range.
    Color,
    /// Values that must not be blended (ids, custom data): every surviving
    /// corner keeps the value it had in the input. Never in the error, never
    /// a seam.
    Carried,
}

/// One per-corner attribute stream.
#[derive(Clone, Copy, Debug)]
pub struct AttributeStream<'a> {
    /// Components per value, 1 to 4.
    pub components: usize,
    /// The value pool, `components` floats per value.
    pub values: &'a [f32],
    /// For every corner of the input faces, the index of its value in the
    /// pool, or [`ABSENT`].
    pub indices: &'a [u32],
    /// Weight of the stream in the collapse error, on the scale its
    /// [`StreamKind`] sets: weight 1 makes an error of `d` in the stream
    /// cost as much as moving the surface by `d` times the bounding-box
    /// diagonal. 0: the stream is fitted through every collapse but does
    /// not steer them.
    pub weight: f64,
    /// A position whose corners carry different values lies on a seam of
    /// this stream (a UV seam, a hard normal edge, a color border). With
    /// `seams` on, seams are kept: see [`crate::SeamPolicy`]. Off: values
    /// are fitted across them like anywhere else.
    pub seams: bool,
    /// How the fitted values are finished.
    pub kind: StreamKind,
}

/// Skin influences per corner (joint, weight), fitted as Knodt 2024 §3
/// does: each joint's weight is an attribute of its own (Eq. 6), stored
/// sparsely. Copies of one position always share one influence set.
#[derive(Clone, Copy, Debug)]
pub struct SkinStream<'a> {
    /// Influence slots per entry.
    pub influences: usize,
    /// Joint of every slot, `influences` per entry.
    pub joints: &'a [u16],
    /// Weight of every slot (unused slots 0).
    pub weights: &'a [f32],
    /// Entry of every corner, or [`ABSENT`].
    pub indices: &'a [u32],
    /// Weight of joint influences in the collapse error, measured as they
    /// are (a weight error of `d` costs like moving the surface by `d · w`
    /// diagonals). 0: fitted only.
    pub weight: f64,
}

/// One morph target's deltas per corner (a blend shape's position, normal
/// or tangent deltas, three floats a value), fitted at the simplified
/// positions like any attribute but stored sparsely (a target moves a
/// small region), one value per position: see `terms/attributes/morph.rs`.
/// They never steer collapses; a target's shape does, as a pose
/// ([`crate::InputData::morph_targets`]).
#[derive(Clone, Copy, Debug)]
pub struct MorphStream<'a> {
    /// The delta pool, three floats per value.
    pub values: &'a [f32],
    /// For every corner of the input faces, the index of its delta in the
    /// pool, or [`ABSENT`] (no delta: zero).
    pub indices: &'a [u32],
}

/// Everything besides positions that rides along a simplification.
#[derive(Clone, Debug, Default)]
pub struct AttributeInput<'a> {
    /// The per-corner streams.
    pub streams: Vec<AttributeStream<'a>>,
    /// Skin influences, when the mesh is skinned.
    pub skin: Option<SkinStream<'a>>,
    /// Morph target deltas, any number; [`crate::Simplified::morphs`]
    /// gives them back per output vertex, in this order.
    pub morphs: Vec<MorphStream<'a>>,
    /// A material (or any group) id per face: where faces of different ids
    /// meet, the border is kept like a seam. Empty: no material borders.
    pub face_groups: &'a [u32],
}

impl AttributeInput<'_> {
    /// True when nothing but positions is given.
    pub fn is_empty(&self) -> bool {
        self.streams.is_empty()
            && self.skin.is_none()
            && self.morphs.is_empty()
            && self.face_groups.is_empty()
    }
}

/// A stream's values after simplification.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FittedStream {
    /// Components per value.
    pub components: usize,
    /// The value pool.
    pub values: Vec<f32>,
    /// For every output corner, its value index or [`ABSENT`].
    pub indices: Vec<u32>,
}

/// Skin influences after simplification: one set per output vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FittedSkin {
    /// Influence slots per vertex (the input's count).
    pub influences: usize,
    /// Joints, `influences` per output vertex (unused slots 0).
    pub joints: Vec<u16>,
    /// Weights, `influences` per output vertex, summing to 1 (unused
    /// slots 0; all 0 for a vertex no skinned corner reached).
    pub weights: Vec<f32>,
}

/// How attribute seams are treated (see `terms/attributes/seams.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SeamPolicy {
    /// Seams are crossed only where that costs less than what else is left
    /// (the default): a collapse that would move a seam pays for the
    /// distance through the seam's constraint planes; one that would give
    /// both sides of a seam one value pays the attribute error of the
    /// merged values, which for UVs of different charts is the distance
    /// between the charts on the surface. A level of detail always reaches
    /// its budget, and on the corpus this keeps more UV islands than keeping
    /// seams strictly until stuck, whose last collapses are forced ones.
    #[default]
    Penalize,
    /// Seams are always kept: seam vertices collapse only along their seam,
    /// a seam's corners and junctions stay; the run may stop short of its
    /// target (like meshoptimizer).
    Keep,
    /// Seams get no protection: they move and close like any other edge
    /// (each side still keeps its own value until a collapse merges them).
    /// For meshes whose textures are re-baked.
    Ignore,
}
