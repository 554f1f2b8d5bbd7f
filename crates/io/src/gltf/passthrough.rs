//! What a glTF file carries beyond the [`Scene`]: the original JSON and
//! buffers, so that the writer can put back, unchanged, everything the
//! simplifier did not touch (extensions and extras on every object,
//! cameras, lights, samplers, animation curves, morph weights and names…).

use std::fmt;
use std::path::PathBuf;

use serde_json::Value;
use wildlod_mesh::Scene;

/// How the parts of one [`wildlod_mesh::Mesh`] map back to the primitives
/// of the glTF mesh it was read from.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MeshSource {
    /// Source primitive of every part, in part order.
    pub part_primitives: Vec<usize>,
    /// Primitives the model cannot hold (points, lines), written back
    /// verbatim from the JSON.
    pub kept_primitives: Vec<usize>,
}

/// The glTF-only content of a [`crate::Document`].
#[derive(Clone, Default)]
pub(crate) struct Passthrough {
    /// The document's JSON, exactly as read.
    pub json: Value,
    /// Every buffer's bytes, `byteLength` long, in JSON order.
    pub buffers: Vec<Vec<u8>>,
    /// Absolute directory of the source file: relative URIs resolve here.
    pub source_dir: PathBuf,
    /// Files the source references (buffers, images), absolute: the
    /// writer must never overwrite them.
    pub external: Vec<PathBuf>,
    /// One entry per glTF mesh.
    pub meshes: Vec<MeshSource>,
    /// The scene as read, without mesh geometry: when the document's scene
    /// still matches it, the JSON is trusted for the parts it describes.
    pub read: Scene,
    /// Whether the source declared KHR_mesh_quantization, so that the
    /// writer may keep attributes in the encodings only it allows.
    pub quantization: bool,
}

impl fmt::Debug for Passthrough {
    // The buffers can be hundreds of megabytes: summarize them.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Passthrough")
            .field("source_dir", &self.source_dir)
            .field(
                "buffers",
                &self.buffers.iter().map(Vec::len).collect::<Vec<_>>(),
            )
            .field("external", &self.external)
            .field("meshes", &self.meshes)
            .field("quantization", &self.quantization)
            .finish_non_exhaustive()
    }
}
