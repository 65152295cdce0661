//! The error a stage returns. The runner adds the stage name and the file.

use std::path::PathBuf;

use crate::{ProductKind, TableError};

#[derive(Debug, thiserror::Error)]
pub enum StageError {
    #[error("input `{0}` is missing")]
    MissingInput(String),
    #[error("input `{name}` is a {found}, expected a {expected}")]
    InputKind {
        name: String,
        expected: ProductKind,
        found: ProductKind,
    },
    // The cause is in the message, so it is not also the error's source:
    // a printed chain would say it twice.
    #[error("input `{input}`: {cause}")]
    InputTable { input: String, cause: TableError },
    #[error("input `{0}` comes without an index of its files (wire an output that hands one on)")]
    NoIndex(String),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
    #[error("{0}")]
    Invalid(String),
    /// A stage that needs a 2-D height map was given a line scan.
    #[error(
        "{kind}: input `{input}` is a line scan ({nx} × {ny} points, a profile): {kind} needs \
         a 2-D height map (a line scan goes through `surface` for its profile PSD, Hurst \
         exponent and roughness, and no further)"
    )]
    LineScan {
        kind: &'static str,
        input: String,
        nx: usize,
        ny: usize,
    },
    #[error(transparent)]
    Other(Box<dyn std::error::Error + Send + Sync>),
}

impl StageError {
    /// Wraps a stage crate's own error type.
    pub fn other(e: impl std::error::Error + Send + Sync + 'static) -> Self {
        StageError::Other(Box::new(e))
    }

    pub fn invalid(message: impl Into<String>) -> Self {
        StageError::Invalid(message.into())
    }

    pub fn file(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        StageError::File {
            path: path.into(),
            message: message.into(),
        }
    }
}
