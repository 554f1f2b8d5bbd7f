//! Stanford PLY. (Being written: see the foundation issue.)

use std::path::Path;

use wildlod_mesh::Scene;

use crate::{ErrorKind, OutputFiles};

pub(crate) fn read(_data: &[u8]) -> Result<Scene, ErrorKind> {
    Err(ErrorKind::Unsupported(
        "PLY reading is not built yet".into(),
    ))
}

pub(crate) fn write(
    _scene: &Scene,
    _path: &Path,
    _files: &mut OutputFiles,
) -> Result<(), ErrorKind> {
    Err(ErrorKind::Unsupported(
        "PLY writing is not built yet".into(),
    ))
}
