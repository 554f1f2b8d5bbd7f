//! Wavefront OBJ with MTL materials: polygons kept as polygons, streams
//! kept as the file indexes them (`v/vt/vn`), groups and materials as parts.

mod mtl;
mod read;
pub(crate) mod text;
mod write;

use std::path::{Component, Path, PathBuf};

pub(crate) use read::read;
pub(crate) use write::write;

/// The directory of `file` as an absolute, `.`/`..`-free path (lexically:
/// symlinks are kept, so that paths stay the ones the user gave).
pub(crate) fn absolute_dir(file: &Path) -> PathBuf {
    let dir = file.parent().unwrap_or(Path::new(""));
    let abs = if dir.is_absolute() {
        dir.to_path_buf()
    } else {
        std::env::current_dir()
            .map(|d| d.join(dir))
            .unwrap_or_else(|_| dir.to_path_buf())
    };
    clean(&abs)
}

/// A path named inside a file (`mtllib`, `map_Kd`), resolved against the
/// directory of that file. Windows separators are accepted everywhere:
/// assets made on Windows write `.\textures\a.png`.
pub(crate) fn resolve_path(dir: &Path, raw: &str) -> PathBuf {
    let unix = raw.trim().replace('\\', "/");
    clean(&dir.join(unix))
}

/// Removes `.` and resolves `..` lexically.
pub(crate) fn clean(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if matches!(out.components().next_back(), Some(Component::Normal(_))) {
                    out.pop();
                } else {
                    out.push("..");
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_relative_path_resolves_against_the_library_directory() {
        assert_eq!(
            resolve_path(Path::new("/a/b"), ".\\tex\\wal.jpg"),
            PathBuf::from("/a/b/tex/wal.jpg")
        );
        assert_eq!(
            resolve_path(Path::new("/a/b"), "../c.png"),
            PathBuf::from("/a/c.png")
        );
        assert_eq!(
            resolve_path(Path::new("/a/b"), "/abs/c.png"),
            PathBuf::from("/abs/c.png")
        );
    }
}
