//! glTF 2.0 and GLB. (Being written: see the foundation issue.)

use std::path::Path;

use wildlod_mesh::Scene;

use crate::{Document, ErrorKind, Format, OutputFiles};

/// What a glTF file carries beyond the [`Scene`], kept for writing back.
#[derive(Clone, Debug, Default)]
pub(crate) struct Passthrough {}

pub(crate) fn read(
    _path: &Path,
    _data: &[u8],
    _warnings: &mut Vec<String>,
) -> Result<(Scene, Passthrough), ErrorKind> {
    Err(ErrorKind::Unsupported(
        "glTF reading is not built yet".into(),
    ))
}

pub(crate) fn write(
    _doc: &Document,
    _path: &Path,
    _format: Format,
    _files: &mut OutputFiles,
) -> Result<(), ErrorKind> {
    Err(ErrorKind::Unsupported(
        "glTF writing is not built yet".into(),
    ))
}
