//! Wavefront OBJ + MTL. (Being written: see the foundation issue.)

use std::path::Path;

use wildlod_mesh::Scene;

use crate::{Document, ErrorKind, OutputFiles};

pub(crate) fn read(
    _path: &Path,
    _data: &[u8],
    _warnings: &mut Vec<String>,
) -> Result<Scene, ErrorKind> {
    Err(ErrorKind::Unsupported(
        "OBJ reading is not built yet".into(),
    ))
}

pub(crate) fn write(
    _doc: &Document,
    _path: &Path,
    _files: &mut OutputFiles,
) -> Result<(), ErrorKind> {
    Err(ErrorKind::Unsupported(
        "OBJ writing is not built yet".into(),
    ))
}
