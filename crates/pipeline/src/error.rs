//! Errors of the pipelines, naming the file, the mesh or the setting.

use std::path::PathBuf;

/// Why a pipeline could not run. Not reaching a target is no error: the
/// reports say how far each mesh got.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or writing a file failed (the error names the file).
    #[error(transparent)]
    Io(#[from] wildlod_io::Error),
    /// The simplifier refused a mesh of a file.
    #[error("{}: simplifying {mesh}", file.display())]
    Simplify {
        /// The file the mesh came from.
        file: PathBuf,
        /// The mesh, as messages name it ([`crate::mesh_name`]).
        mesh: String,
        /// Why.
        #[source]
        source: wildlod_simplify::Error,
    },
    /// A mesh of a file could not be re-baked.
    #[error("{}: re-baking {mesh}", file.display())]
    Bake {
        /// The file the mesh came from.
        file: PathBuf,
        /// The mesh, as messages name it ([`crate::mesh_name`]).
        mesh: String,
        /// Why.
        #[source]
        source: wildlod_bake::BakeError,
    },
    /// A level of a chain could not be made.
    #[error("level of detail {level}")]
    Level {
        /// 1 for the first level below the input.
        level: usize,
        /// Why.
        #[source]
        source: Box<Error>,
    },
    /// A setting out of its range; `name` is the [`crate::Tuning`] field
    /// or target name (the CLI shows it as `--name-with-dashes`).
    #[error("{name} must be {expected}, got {value}")]
    Setting {
        /// The setting's name, in snake case.
        name: &'static str,
        /// What it must be.
        expected: &'static str,
        /// What it was.
        value: String,
    },
    /// Settings that do not fit together (level lists, targets).
    #[error("{0}")]
    Usage(String),
    /// A report could not be serialized.
    #[error("serializing the report")]
    Json(#[from] serde_json::Error),
    /// The worker threads of a batch could not start.
    #[error("starting the worker threads")]
    Threads(#[from] rayon::ThreadPoolBuildError),
}

impl Error {
    /// A [`Error::Setting`] for a number.
    pub(crate) fn setting(name: &'static str, expected: &'static str, value: f64) -> Self {
        Error::Setting {
            name,
            expected,
            value: value.to_string(),
        }
    }

    /// Whether the operating system refused a read or write (a missing
    /// file, permissions…), as opposed to content or settings refused.
    pub fn is_os_error(&self) -> bool {
        match self {
            Error::Io(e) => matches!(e.kind, wildlod_io::ErrorKind::Io(_)),
            Error::Level { source, .. } => source.is_os_error(),
            _ => false,
        }
    }
}

/// An error with its causes, `: `-separated (as `anyhow`'s `{:#}` shows it).
pub(crate) fn error_chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        s.push_str(": ");
        s.push_str(&c.to_string());
        cause = c.source();
    }
    s
}
