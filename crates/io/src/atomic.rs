//! All-or-nothing output: every file of one write (a `.gltf` and its `.bin`,
//! an `.obj` and its `.mtl`, copied images) goes to a temporary file in the
//! destination directory first and is renamed into place only when all of
//! them were written.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::ErrorKind;

/// The files one [`crate::write`] call produces, committed together.
#[derive(Debug)]
pub struct OutputFiles {
    files: Vec<(PathBuf, Vec<u8>)>,
    warnings: Vec<String>,
    protected: Vec<PathBuf>,
    allow_overwrite: bool,
}

impl OutputFiles {
    /// Collects outputs; `source` (the input file) is protected from being
    /// overwritten unless `allow_overwrite` is set.
    pub fn new(source: Option<&Path>, allow_overwrite: bool) -> Self {
        let mut o = OutputFiles {
            files: Vec::new(),
            warnings: Vec::new(),
            protected: Vec::new(),
            allow_overwrite,
        };
        if let Some(s) = source {
            o.protect(s);
        }
        o
    }

    /// Marks another input (a `.bin` or image the source references) as not
    /// to be overwritten.
    pub fn protect(&mut self, path: &Path) {
        self.protected.push(normalize(path));
    }

    /// Adds a file to write. Fails at once if it would replace a protected
    /// input, or if two outputs of the same write share a path.
    pub fn add(&mut self, path: &Path, bytes: Vec<u8>) -> Result<(), ErrorKind> {
        let n = normalize(path);
        if !self.allow_overwrite && self.protected.contains(&n) {
            return Err(ErrorKind::WouldOverwriteInput(path.to_path_buf()));
        }
        if self.files.iter().any(|(p, _)| normalize(p) == n) {
            return Err(ErrorKind::Unsupported(format!(
                "two outputs of one write would share the path {}",
                path.display()
            )));
        }
        self.files.push((path.to_path_buf(), bytes));
        Ok(())
    }

    /// Notes something the output format cannot hold; returned by
    /// [`crate::write`] after a successful commit.
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }

    /// The files collected so far.
    pub fn files(&self) -> &[(PathBuf, Vec<u8>)] {
        &self.files
    }

    /// Writes every file to a temporary sibling, then renames them all into
    /// place, and returns the warnings. On error nothing is renamed and the
    /// temporaries are removed.
    pub fn commit(self) -> Result<Vec<String>, ErrorKind> {
        let mut staged = Vec::with_capacity(self.files.len());
        for (path, bytes) in &self.files {
            let dir = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                _ => PathBuf::from("."),
            };
            let mut builder = tempfile::Builder::new();
            builder.prefix(".wildlod-").suffix(".tmp");
            #[cfg(unix)]
            builder.permissions(output_permissions(path));
            let mut tmp = builder
                .tempfile_in(&dir)
                .map_err(|source| ErrorKind::OutputFolder {
                    folder: dir.clone(),
                    source,
                })?;
            tmp.write_all(bytes)?;
            tmp.as_file().sync_all()?;
            staged.push((tmp, path));
        }
        // The main file is added first by writers; rename it last so a
        // reader never sees it before its sidecars.
        for (tmp, path) in staged.into_iter().rev() {
            tmp.persist(path).map_err(|e| ErrorKind::Io(e.error))?;
        }
        Ok(self.warnings)
    }
}

/// Permissions for an output: those of the file it replaces, else what a
/// plain create gives (0666 minus the umask, applied by the OS) rather than
/// the temporary file's private 0600. (Elsewhere than unix, temporary files
/// already get ordinary permissions.)
#[cfg(unix)]
fn output_permissions(path: &Path) -> std::fs::Permissions {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path)
        .map(|m| m.permissions())
        .unwrap_or_else(|_| std::fs::Permissions::from_mode(0o666))
}

/// An absolute, `.`/`..`-free form of a path for comparison; symlinks and
/// existing files are resolved through the filesystem when possible.
fn normalize(path: &Path) -> PathBuf {
    if let Ok(c) = path.canonicalize() {
        return c;
    }
    // The file may not exist yet: canonicalize its directory instead.
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .map(|d| d.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    };
    match (abs.parent(), abs.file_name()) {
        (Some(dir), Some(name)) => dir
            .canonicalize()
            .map(|d| d.join(name))
            .unwrap_or(abs.clone()),
        _ => abs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_to_overwrite_source_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let src = dir.path().join("in.obj");
        std::fs::write(&src, b"original").unwrap();
        let mut o = OutputFiles::new(Some(&src), false);
        assert!(matches!(
            o.add(&dir.path().join("./in.obj"), b"x".to_vec()),
            Err(ErrorKind::WouldOverwriteInput(_))
        ));
        assert_eq!(std::fs::read(&src).unwrap(), b"original");
    }

    #[test]
    fn commit_writes_all_files_and_leaves_no_temporaries() {
        let dir = tempfile::tempdir().unwrap();
        let mut o = OutputFiles::new(None, false);
        o.add(&dir.path().join("a.gltf"), b"{}".to_vec()).unwrap();
        o.add(&dir.path().join("a.bin"), vec![1, 2, 3]).unwrap();
        o.commit().unwrap();
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, vec!["a.bin", "a.gltf"]);
    }

    #[cfg(unix)]
    #[test]
    fn outputs_get_ordinary_permissions_not_the_temporary_ones() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mut o = OutputFiles::new(None, false);
        o.add(&dir.path().join("a.obj"), b"v 0 0 0".to_vec())
            .unwrap();
        o.commit().unwrap();
        let mode = std::fs::metadata(dir.path().join("a.obj"))
            .unwrap()
            .permissions()
            .mode();
        // Readable by others unless the umask forbids it; never 0600 only
        // because of the temporary file.
        assert_ne!(mode & 0o777, 0o600);
    }

    #[test]
    fn commit_into_missing_directory_fails_without_partial_output() {
        let dir = tempfile::tempdir().unwrap();
        let mut o = OutputFiles::new(None, false);
        o.add(&dir.path().join("ok.obj"), b"v 0 0 0".to_vec())
            .unwrap();
        o.add(&dir.path().join("missing/x.mtl"), b"".to_vec())
            .unwrap();
        assert!(o.commit().is_err());
        assert!(!dir.path().join("ok.obj").exists());
    }
}
