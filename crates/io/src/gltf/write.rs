use crate::{Document, ErrorKind, Format, OutputFiles};
use std::path::Path;
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
