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

/// The bytes of one source buffer that a write may copy, at their offsets
/// in the buffer: the spans of the views it copies (see
/// `rewrite::copied_views`). The rest — the triangle primitives' data,
/// rebuilt from the scene — is not kept, so a large mesh is not held twice
/// (once decoded, once as bytes) while it is simplified.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SourceBuffer {
    /// (start, bytes), sorted by start, disjoint and not touching.
    spans: Vec<(usize, Vec<u8>)>,
}

impl SourceBuffer {
    /// Keeps the ranges `(start, length)` of `bytes` (overlapping ranges
    /// merge; ranges reaching past the end are cut at it).
    pub fn keep(bytes: &[u8], ranges: impl IntoIterator<Item = (usize, usize)>) -> SourceBuffer {
        let mut r: Vec<(usize, usize)> = ranges
            .into_iter()
            .filter_map(|(start, len)| {
                let end = start.saturating_add(len).min(bytes.len());
                (start < end).then_some((start, end))
            })
            .collect();
        r.sort_unstable();
        let mut merged: Vec<(usize, usize)> = Vec::with_capacity(r.len());
        for (start, end) in r {
            match merged.last_mut() {
                Some(last) if start <= last.1 => last.1 = last.1.max(end),
                _ => merged.push((start, end)),
            }
        }
        SourceBuffer {
            spans: merged
                .into_iter()
                .map(|(start, end)| (start, bytes[start..end].to_vec()))
                .collect(),
        }
    }

    /// The `len` bytes at `start`, if kept.
    pub fn get(&self, start: usize, len: usize) -> Option<&[u8]> {
        let k = self
            .spans
            .partition_point(|(s, _)| *s <= start)
            .checked_sub(1)?;
        let (s, bytes) = &self.spans[k];
        let from = start - s;
        bytes.get(from..from.checked_add(len)?)
    }

    /// How many bytes are kept.
    pub fn kept_bytes(&self) -> usize {
        self.spans.iter().map(|(_, b)| b.len()).sum()
    }
}

/// The glTF-only content of a [`crate::Document`].
#[derive(Clone, Default)]
pub(crate) struct Passthrough {
    /// The document's JSON, exactly as read.
    pub json: Value,
    /// Every buffer's bytes the writer may copy (see [`SourceBuffer`]), in
    /// JSON order.
    pub buffers: Vec<SourceBuffer>,
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
                &self
                    .buffers
                    .iter()
                    .map(SourceBuffer::kept_bytes)
                    .collect::<Vec<_>>(),
            )
            .field("external", &self.external)
            .field("meshes", &self.meshes)
            .field("quantization", &self.quantization)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::SourceBuffer;

    #[test]
    fn a_source_buffer_keeps_only_the_spans_asked_for() {
        let bytes: Vec<u8> = (0..100).collect();
        // [10, 20) and [15, 30) merge; [20, 25) touches; [90, 120) is cut
        // at the end; an empty range keeps nothing.
        let b = SourceBuffer::keep(&bytes, [(15, 15), (10, 10), (90, 30), (20, 5), (50, 0)]);
        assert_eq!(b.kept_bytes(), 20 + 10);
        assert_eq!(b.get(10, 20), Some(&bytes[10..30]));
        assert_eq!(b.get(12, 3), Some(&bytes[12..15]));
        assert_eq!(b.get(95, 5), Some(&bytes[95..100]));
        // Not kept, or reaching out of a span.
        assert_eq!(b.get(0, 1), None);
        assert_eq!(b.get(40, 1), None);
        assert_eq!(b.get(25, 10), None);
        assert_eq!(b.get(95, 6), None);
        assert_eq!(b.get(usize::MAX, 2), None);
        assert_eq!(SourceBuffer::keep(&bytes, []).kept_bytes(), 0);
    }
}
