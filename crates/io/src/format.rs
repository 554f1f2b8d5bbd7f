//! File formats, chosen by extension.

use std::path::Path;

use crate::error::ErrorKind;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// glTF 2.0 JSON (`.gltf`) with external or data-URI buffers.
    Gltf,
    /// Binary glTF (`.glb`).
    Glb,
    /// Wavefront OBJ (`.obj`) with MTL materials.
    Obj,
    /// Stanford PLY (`.ply`), ASCII or binary.
    Ply,
    /// STL (`.stl`), ASCII or binary.
    Stl,
    /// OFF (`.off`): OFF, COFF, NOFF, STOFF and their combinations, text.
    Off,
}

impl Format {
    /// The format named by a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format, ErrorKind> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        Ok(match ext.as_str() {
            "gltf" => Format::Gltf,
            "glb" => Format::Glb,
            "obj" => Format::Obj,
            "ply" => Format::Ply,
            "stl" => Format::Stl,
            "off" => Format::Off,
            _ => return Err(ErrorKind::UnsupportedExtension(ext)),
        })
    }

    /// Whether the format stores polygons as such (quads and n-gons are
    /// triangulated when written to the others).
    pub fn keeps_polygons(self) -> bool {
        matches!(self, Format::Obj | Format::Ply | Format::Off)
    }

    /// Whether a file of this format must hold a face to be read (OBJ, PLY
    /// and STL readers refuse a file with none).
    pub fn needs_faces(self) -> bool {
        matches!(self, Format::Obj | Format::Ply | Format::Stl | Format::Off)
    }

    /// The usual extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Gltf => "gltf",
            Format::Glb => "glb",
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Stl => "stl",
            Format::Off => "off",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extension_picks_format_case_insensitively() {
        assert_eq!(
            Format::from_path(Path::new("a/B.GLB")).ok(),
            Some(Format::Glb)
        );
        assert_eq!(
            Format::from_path(Path::new("x.obj")).ok(),
            Some(Format::Obj)
        );
        assert!(matches!(
            Format::from_path(Path::new("x.fbx")),
            Err(ErrorKind::UnsupportedExtension(e)) if e == "fbx"
        ));
        assert!(Format::from_path(Path::new("noext")).is_err());
    }
}
