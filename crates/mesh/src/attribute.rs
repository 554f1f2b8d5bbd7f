//! Per-corner attribute streams and skin influences.

/// Per-corner index meaning "this corner has no value in this stream".
///
/// Used when the faces of one part (say, a glTF primitive without
/// `TEXCOORD_1`) lack a stream that other parts of the same mesh carry.
pub const ABSENT: u32 = u32::MAX;

/// What an attribute stream means. Writers map it back to format names
/// (`TEXCOORD_n`, `NORMAL`, `vt`, …).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Semantic {
    /// Texture coordinates of UV set `n` (glTF `TEXCOORD_n`, OBJ `vt` is set 0).
    TexCoord(u32),
    /// Vertex normal.
    Normal,
    /// Tangent, four components (xyz + handedness sign), as in glTF.
    Tangent,
    /// Vertex color set `n`, three or four components in [0, 1].
    Color(u32),
    /// A glTF morph target delta stream.
    Morph {
        /// Target index.
        target: u32,
        /// Which quantity the delta applies to.
        channel: MorphChannel,
    },
    /// An application-specific attribute (glTF `_NAME`), kept as is.
    Custom(String),
}

/// The quantity a morph target delta displaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MorphChannel {
    /// Position delta.
    Position,
    /// Normal delta.
    Normal,
    /// Tangent delta (three components in glTF).
    Tangent,
}

/// How a stream was encoded in its source file. Values are always held as
/// `f32` (quantized data is normalized at the I/O boundary); writers may use
/// this hint to encode them back the same way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ComponentFormat {
    /// 32-bit float.
    #[default]
    F32,
    /// Unsigned byte, normalized to [0, 1].
    U8Norm,
    /// Unsigned short, normalized to [0, 1].
    U16Norm,
    /// Signed byte, normalized to [-1, 1].
    I8Norm,
    /// Signed short, normalized to [-1, 1].
    I16Norm,
    /// Unsigned byte, not normalized (integer values held as floats).
    U8,
    /// Unsigned short, not normalized.
    U16,
    /// Signed byte, not normalized.
    I8,
    /// Signed short, not normalized.
    I16,
    /// Unsigned int, not normalized.
    U32,
}

/// One per-corner attribute stream: a pool of values and, for every corner
/// of the mesh, the index of its value (or [`ABSENT`]).
///
/// Corners that share a value index share the value: an OBJ `vt` used by
/// several faces, or a glTF vertex used by several triangles. A position
/// with several distinct values in a stream lies on a *seam* of that stream.
#[derive(Clone, Debug, PartialEq)]
pub struct Attribute {
    /// Meaning of the stream.
    pub semantic: Semantic,
    /// Components per value, 1 to 4.
    pub components: u8,
    /// Flat values, `components` floats per value.
    pub values: Vec<f32>,
    /// Value index of every corner of the mesh, or [`ABSENT`].
    pub indices: Vec<u32>,
    /// Source encoding, a hint for writers.
    pub format: ComponentFormat,
}

impl Attribute {
    /// Number of values in the pool.
    pub fn value_count(&self) -> usize {
        if self.components == 0 {
            0
        } else {
            self.values.len() / self.components as usize
        }
    }

    /// The value with index `i`.
    #[inline]
    pub fn value(&self, i: u32) -> &[f32] {
        let c = self.components as usize;
        &self.values[i as usize * c..(i as usize + 1) * c]
    }

    /// The value of corner `corner`, or `None` when it is [`ABSENT`].
    #[inline]
    pub fn corner_value(&self, corner: usize) -> Option<&[f32]> {
        match self.indices[corner] {
            ABSENT => None,
            i => Some(self.value(i)),
        }
    }
}

/// Skin influences: for every corner, an entry of up to `influences` (joint,
/// weight) pairs. Joints index the skin of the node that instances the mesh.
///
/// Weights are normalized floats whatever the file stored (u8/u16/f32); an
/// unused slot has weight 0. Entries are shared by corners like attribute
/// values, so a glTF vertex keeps one entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Skinning {
    /// Influence slots per entry: 4 per glTF `JOINTS_n`/`WEIGHTS_n` set.
    pub influences: u8,
    /// Joint of every slot, `influences` per entry.
    pub joints: Vec<u16>,
    /// Weight of every slot, `influences` per entry.
    pub weights: Vec<f32>,
    /// Entry index of every corner, or [`ABSENT`].
    pub indices: Vec<u32>,
    /// Source encoding of the weights (joints are integers).
    pub weight_format: ComponentFormat,
    /// Source encoding of the joints: [`ComponentFormat::U8`] or [`ComponentFormat::U16`].
    pub joint_format: ComponentFormat,
}

impl Skinning {
    /// Number of entries.
    pub fn entry_count(&self) -> usize {
        if self.influences == 0 {
            0
        } else {
            self.weights.len() / self.influences as usize
        }
    }

    /// Joints and weights of entry `i`.
    #[inline]
    pub fn entry(&self, i: u32) -> (&[u16], &[f32]) {
        let k = self.influences as usize;
        let r = i as usize * k..(i as usize + 1) * k;
        (&self.joints[r.clone()], &self.weights[r])
    }
}
