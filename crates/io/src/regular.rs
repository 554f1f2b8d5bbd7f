//! Every file wildlod reads — a mesh, an MTL library, a glTF buffer, an
//! image — must be a regular file, checked before it is opened.
//!
//! Opening a FIFO blocks until something writes to it, and a character
//! device such as `/dev/zero` never ends: a mesh path, or an `mtllib` or
//! image URI inside a file someone sent, would hang wildlod instead of
//! failing. The check follows symlinks (a link to a mesh is a mesh); a link
//! loop fails with the operating system's error, which names it.

use std::path::Path;

use crate::error::ErrorKind;

/// What a path is, when it is not a regular file.
pub(crate) fn not_regular(path: &Path) -> Result<(), ErrorKind> {
    let meta = std::fs::metadata(path).map_err(ErrorKind::Io)?;
    let ft = meta.file_type();
    if ft.is_file() {
        return Ok(());
    }
    Err(ErrorKind::NotAFile {
        path: path.to_path_buf(),
        what: describe(&ft),
    })
}

fn describe(ft: &std::fs::FileType) -> &'static str {
    if ft.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if ft.is_char_device() {
            return "a character device";
        }
        if ft.is_block_device() {
            return "a block device";
        }
        if ft.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// Reads a regular file of at most `max` bytes; anything else is refused
/// before a byte is read.
pub(crate) fn read(path: &Path, max: u64) -> Result<Vec<u8>, ErrorKind> {
    not_regular(path)?;
    let len = std::fs::metadata(path).map_err(ErrorKind::Io)?.len();
    if len > max {
        return Err(ErrorKind::TooLarge { bytes: len });
    }
    std::fs::read(path).map_err(ErrorKind::Io)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn fifo_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe.obj");
        let status = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(status.success());
        // Opening it would block this test forever; the check must not.
        let e = read(&fifo, 1 << 20).unwrap_err();
        assert!(e.to_string().contains("FIFO"), "{e}");
    }

    #[test]
    fn folder_and_device_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        assert!(read(dir.path(), 1 << 20)
            .unwrap_err()
            .to_string()
            .contains("folder"));
        assert!(read(Path::new("/dev/zero"), 1 << 20)
            .unwrap_err()
            .to_string()
            .contains("character device"));
    }

    #[test]
    fn symlink_to_a_file_reads_and_a_loop_fails() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.obj");
        std::fs::write(&file, b"v 0 0 0").unwrap();
        let link = dir.path().join("b.obj");
        std::os::unix::fs::symlink(&file, &link).unwrap();
        assert_eq!(read(&link, 100).unwrap(), b"v 0 0 0");
        let l1 = dir.path().join("l1");
        let l2 = dir.path().join("l2");
        std::os::unix::fs::symlink(&l2, &l1).unwrap();
        std::os::unix::fs::symlink(&l1, &l2).unwrap();
        assert!(read(&l1, 100).is_err());
    }
}
