//! The glTF attribute names of the mesh model's semantics, for reading
//! and for encoding.

use wildlod_mesh::{MorphChannel, Semantic};

/// The glTF attribute name of a non-custom, non-morph semantic.
pub(crate) fn semantic_key(s: &Semantic) -> String {
    match s {
        Semantic::TexCoord(n) => format!("TEXCOORD_{n}"),
        Semantic::Normal => "NORMAL".into(),
        Semantic::Tangent => "TANGENT".into(),
        Semantic::Color(n) => format!("COLOR_{n}"),
        Semantic::Custom(n) => n.clone(),
        Semantic::Morph { channel, .. } => morph_key(*channel).into(),
    }
}

/// The glTF key of a morph target channel.
pub(crate) fn morph_key(c: MorphChannel) -> &'static str {
    match c {
        MorphChannel::Position => "POSITION",
        MorphChannel::Normal => "NORMAL",
        MorphChannel::Tangent => "TANGENT",
    }
}
