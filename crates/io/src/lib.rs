//! Readers and writers between files and the wildlod mesh model.
//!
//! [`read`] picks the format from the file extension and returns a
//! [`Document`]: the format-neutral [`Scene`] plus what the format carries
//! beyond it (glTF extensions, animation curves, samplers…), kept so that
//! [`write()`] can put it back unchanged. [`write()`] picks the output format
//! from the output extension, whatever the input was, and writes through
//! temporary files renamed into place: a failed write leaves nothing behind
//! and never a half-written file.

mod atomic;
mod error;
mod far;
mod format;
mod gltf;
mod image;
mod ktx2;
mod obj;
mod off;
mod ply;
mod regular;
mod stl;

use std::path::{Path, PathBuf};

pub use atomic::OutputFiles;
pub use error::{Error, ErrorKind};
pub use format::Format;
pub use image::{decode_image, decode_image_rgba8, encode_image, ImageEncoding};
use wildlod_mesh::{Mesh, Scene};

/// Files larger than this are refused before reading: every format we read
/// stores a mesh in far less, and a bogus path to a disk image should fail
/// fast instead of exhausting memory.
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// A file's content: the [`Scene`] and what only its format knows.
#[derive(Clone, Debug, Default)]
pub struct Document {
    /// The format-neutral content. Edit this; writers take it from here.
    pub scene: Scene,
    /// The file this was read from, if any. [`write()`] refuses to overwrite
    /// it unless [`WriteOptions::allow_overwrite_input`] is set.
    pub source: Option<PathBuf>,
    /// The format it was read from.
    pub format: Option<Format>,
    /// Non-fatal problems met while reading (a missing MTL file…).
    pub warnings: Vec<String>,
    /// glTF-only content kept for writing back unchanged.
    pub(crate) gltf: Option<gltf::Passthrough>,
}

impl Document {
    /// A document holding a scene built in memory.
    pub fn from_scene(scene: Scene) -> Self {
        Document {
            scene,
            ..Document::default()
        }
    }
}

/// Options of [`write()`].
#[derive(Clone, Debug, Default)]
pub struct WriteOptions {
    /// Allow the output to replace the document's source file (and files it
    /// references). Off by default: wildlod never overwrites an input unless
    /// told to.
    pub allow_overwrite_input: bool,
}

/// Reads a mesh file; the format follows the extension (`.gltf`, `.glb`,
/// `.obj`, `.ply`, `.stl`, `.off`, case-insensitive).
///
/// Every error names the file and, where it can, the element (line,
/// accessor, face). The returned scene passes [`Scene::validate`].
pub fn read(path: impl AsRef<Path>) -> Result<Document, Error> {
    let path = path.as_ref();
    let at = |kind| Error::new(path, kind);
    let format = Format::from_path(path).map_err(at)?;
    let data = regular::read(path, MAX_FILE_BYTES).map_err(at)?;
    if data.is_empty() {
        return Err(at(ErrorKind::EmptyFile));
    }
    let mut doc = Document {
        source: Some(path.to_path_buf()),
        format: Some(format),
        ..Document::default()
    };
    if let Some(w) = misnamed_gltf(format, &data) {
        doc.warnings.push(w);
    }
    match format {
        Format::Gltf | Format::Glb => {
            let (scene, pass) = gltf::read(path, &data, &mut doc.warnings).map_err(at)?;
            doc.scene = scene;
            doc.gltf = Some(pass);
        }
        Format::Obj => doc.scene = obj::read(path, &data, &mut doc.warnings).map_err(at)?,
        Format::Ply => doc.scene = ply::read(&data, &mut doc.warnings).map_err(at)?,
        Format::Stl => doc.scene = stl::read(path, &data).map_err(at)?,
        Format::Off => doc.scene = off::read(path, &data, &mut doc.warnings).map_err(at)?,
    }
    doc.scene
        .validate()
        .map_err(|e| at(ErrorKind::Invalid(e)))?;
    Ok(doc)
}

/// Whether a face's corners name at least three distinct vertices. Faces
/// with fewer (two-corner "faces", `f 1 2 1`) cover no area; real scene
/// exports carry them, so readers skip them with one counted warning
/// ([`skipped_faces_warning`]) instead of refusing the file. O(corners).
pub(crate) fn has_three_distinct(corners: &[u32]) -> bool {
    let Some(&a) = corners.first() else {
        return false;
    };
    let Some(&b) = corners.iter().find(|&&v| v != a) else {
        return false;
    };
    corners.iter().any(|&v| v != a && v != b)
}

/// The one warning for the faces a reader skipped.
pub(crate) fn skipped_faces_warning(n: usize) -> String {
    format!(
        "skipped {n} face{} with fewer than 3 distinct vertices",
        if n == 1 { "" } else { "s" }
    )
}

/// A glTF whose content disagrees with its extension: it still reads (the
/// glTF reader goes by content), but tools that trust the extension will
/// not, so the user should hear of it.
fn misnamed_gltf(format: Format, data: &[u8]) -> Option<String> {
    let binary = data.starts_with(b"glTF");
    let json = data
        .iter()
        .find(|b| !b.is_ascii_whitespace())
        .is_some_and(|&b| b == b'{');
    match format {
        Format::Gltf if binary => Some(
            "the file is binary glTF (GLB) but named .gltf; read as GLB (rename it to .glb)".into(),
        ),
        Format::Glb if json => Some(
            "the file is glTF JSON but named .glb; read as JSON glTF (rename it to .gltf)".into(),
        ),
        _ => None,
    }
}

/// Writes a document; the format follows the output extension.
///
/// Refuses an invalid scene, and refuses to replace the document's source
/// unless allowed. Sidecar files (`.bin`, `.mtl`, images) are written next
/// to the output; all files appear together or not at all. Returns warnings
/// about content the output format cannot hold (per-corner colors in OBJ…).
pub fn write(
    doc: &Document,
    path: impl AsRef<Path>,
    options: &WriteOptions,
) -> Result<Vec<String>, Error> {
    let path = path.as_ref();
    let at = |kind| Error::new(path, kind);
    let format = Format::from_path(path).map_err(at)?;
    doc.scene
        .validate()
        .map_err(|e| at(ErrorKind::Invalid(e)))?;
    // OBJ, PLY and STL readers refuse a file without faces (it is a point
    // cloud or not a mesh at all); writing one would make a file wildlod
    // itself cannot read back.
    if format.needs_faces() && doc.scene.meshes.iter().all(|m| m.faces.is_empty()) {
        return Err(at(ErrorKind::Unsupported(format!(
            "nothing to write: no mesh has a face, and a .{} file without faces is not a mesh",
            format.extension()
        ))));
    }
    let mut files = OutputFiles::new(doc.source.as_deref(), options.allow_overwrite_input);
    match format {
        Format::Gltf | Format::Glb => gltf::write(doc, path, format, &mut files),
        Format::Obj => obj::write(doc, path, &mut files),
        Format::Ply => ply::write(&doc.scene, path, &mut files),
        Format::Stl => stl::write(&doc.scene, path, &mut files),
        Format::Off => off::write(&doc.scene, path, &mut files),
    }
    .map_err(at)?;
    files.commit().map_err(at)
}

/// Lower levels of detail written with a document by [`write_lods`].
#[derive(Clone, Copy, Debug)]
pub struct LodLevels<'a> {
    /// One entry per lower level, coarsest last (LOD1, LOD2, …); each holds
    /// one mesh per mesh of the document's scene, in the same order, with
    /// the same parts (materials) and skin.
    pub levels: &'a [Vec<Mesh>],
    /// Per scene mesh, the `MSFT_screencoverage` hints of the nodes showing
    /// it: `levels.len() + 1` values, the screen fraction below which each
    /// level hands over to the next and, last, below which nothing is
    /// drawn. Empty: no hints.
    pub screen_coverage: &'a [Vec<f64>],
}

/// Writes a document with lower levels of detail in the same glTF file, as
/// the `MSFT_lod` extension on nodes: every node showing a mesh keeps it as
/// the highest level and lists one extra node per lower level (same
/// transform and skin, that level's mesh, in no scene), so a viewer that
/// ignores the extension shows the highest level. Meshes share the
/// document's materials and textures.
///
/// Only `.gltf` and `.glb` hold levels; other formats are refused (write
/// one file per level with [`write()`]). Written all-or-nothing like
/// [`write()`].
pub fn write_lods(
    doc: &Document,
    lods: &LodLevels<'_>,
    path: impl AsRef<Path>,
    options: &WriteOptions,
) -> Result<Vec<String>, Error> {
    let path = path.as_ref();
    let at = |kind| Error::new(path, kind);
    let format = Format::from_path(path).map_err(at)?;
    if !matches!(format, Format::Gltf | Format::Glb) {
        return Err(at(ErrorKind::Unsupported(format!(
            "levels of detail in one file need glTF (.gltf or .glb), not .{}; write one file per level",
            format.extension()
        ))));
    }
    doc.scene
        .validate()
        .map_err(|e| at(ErrorKind::Invalid(e)))?;
    let mut files = OutputFiles::new(doc.source.as_deref(), options.allow_overwrite_input);
    gltf::write_with_lods(doc, Some(lods), path, format, &mut files).map_err(at)?;
    files.commit().map_err(at)
}
