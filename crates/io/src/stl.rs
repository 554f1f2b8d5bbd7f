//! STL. (Being written: see the foundation issue.)

use std::path::Path;

use wildlod_mesh::Scene;

use crate::{ErrorKind, OutputFiles};

pub(crate) fn read(_path: &Path, _data: &[u8]) -> Result<Scene, ErrorKind> {
    Err(ErrorKind::Unsupported(
        "STL reading is not built yet".into(),
    ))
}

pub(crate) fn write(
    _scene: &Scene,
    _path: &Path,
    _files: &mut OutputFiles,
) -> Result<(), ErrorKind> {
    Err(ErrorKind::Unsupported(
        "STL writing is not built yet".into(),
    ))
}
