//! Errors that name the file and the element.

use std::path::{Path, PathBuf};

use wildlod_mesh::ValidationErrors;

/// An error reading or writing a file: the file, and what is wrong with it.
#[derive(Debug, thiserror::Error)]
#[error("{}: {kind}", path.display())]
pub struct Error {
    /// The file the error is about.
    pub path: PathBuf,
    /// What went wrong.
    pub kind: ErrorKind,
}

impl Error {
    /// An error about `path`.
    pub fn new(path: &Path, kind: ErrorKind) -> Self {
        Error {
            path: path.to_path_buf(),
            kind,
        }
    }
}

/// What went wrong, with the element where it went wrong.
#[derive(Debug, thiserror::Error)]
pub enum ErrorKind {
    /// The operating system refused (missing file, permissions…).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The extension names no format we read or write.
    #[error("unsupported file extension {0:?}: expected .gltf, .glb, .obj, .ply, .stl or .off")]
    UnsupportedExtension(String),
    /// The file is empty.
    #[error("the file is empty")]
    EmptyFile,
    /// The file is larger than any mesh file we accept.
    #[error("the file is {bytes} bytes, larger than wildlod reads")]
    TooLarge {
        /// File size.
        bytes: u64,
    },
    /// A text format's syntax error at a line (1-based).
    #[error("line {line}: {message}")]
    Syntax {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A structural problem at a named element: "accessor 3", "PLY element
    /// 'face' 12", "STL triangle 5", "header"…
    #[error("{element}: {message}")]
    Malformed {
        /// Where.
        element: String,
        /// What is wrong.
        message: String,
    },
    /// A header declares more elements than the file's size allows; refused
    /// before allocating.
    #[error("{element} declares {count} items, but the file can hold at most {max}")]
    ImplausibleCount {
        /// Which header field.
        element: String,
        /// Declared count.
        count: u64,
        /// What the file size allows.
        max: u64,
    },
    /// The content read (or about to be written) breaks a mesh invariant.
    #[error("invalid mesh: {0}")]
    Invalid(ValidationErrors),
    /// Writing would replace an input file.
    /// (The library cannot know what its caller calls the permission: the
    /// `wildlod` binary adds "pass --overwrite to allow it".)
    #[error("refusing to overwrite the input file {} (WriteOptions::allow_overwrite_input allows it)", .0.display())]
    WouldOverwriteInput(PathBuf),
    /// A path to read is not a regular file (a FIFO, a device, a folder):
    /// refused before opening it, which could block forever.
    #[error("{} is {what}, not a regular file; refused without reading it", path.display())]
    NotAFile {
        /// The path (the input itself, or an MTL, buffer or image it names).
        path: PathBuf,
        /// What it is instead.
        what: &'static str,
    },
    /// The folder an output goes into cannot take a file (it does not
    /// exist, is not a folder, or is not writable).
    #[error("cannot write into the folder {}: {source}", folder.display())]
    OutputFolder {
        /// The folder.
        folder: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The content cannot be expressed in the output format.
    #[error("{0}")]
    Unsupported(String),
}

impl ErrorKind {
    /// A syntax error at a 1-based line.
    pub fn syntax(line: usize, message: impl Into<String>) -> Self {
        ErrorKind::Syntax {
            line,
            message: message.into(),
        }
    }

    /// A structural error at a named element.
    pub fn malformed(element: impl Into<String>, message: impl Into<String>) -> Self {
        ErrorKind::Malformed {
            element: element.into(),
            message: message.into(),
        }
    }
}
