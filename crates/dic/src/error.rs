//! Errors of the DIC crate; each names the file, frame or parameter at fault.

/// Why a DIC run cannot proceed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DicError {
    #[error("{file}: {message}")]
    File { file: String, message: String },
    #[error("parameter `{param}`: {message}")]
    Param { param: String, message: String },
    #[error("frame {frame} ({file}) is {width} × {height} pixels, frame 0 is {width0} × {height0}")]
    SizeMismatch {
        frame: usize,
        file: String,
        width: usize,
        height: usize,
        width0: usize,
        height0: usize,
    },
    #[error("no point of interest could be correlated in frame {frame} ({file}): {reason}")]
    Lost {
        frame: usize,
        file: String,
        reason: String,
    },
    #[error("{0}")]
    Invalid(String),
}

impl DicError {
    /// A core reader's error as the crate's: a file error keeps its file.
    pub fn from_stage(e: hypercontact_core::StageError) -> Self {
        match e {
            hypercontact_core::StageError::File { path, message } => DicError::File {
                file: path.display().to_string(),
                message,
            },
            other => DicError::Invalid(other.to_string()),
        }
    }

    pub fn file(file: &str, message: impl Into<String>) -> Self {
        DicError::File {
            file: file.to_owned(),
            message: message.into(),
        }
    }

    pub fn param(param: &str, message: impl Into<String>) -> Self {
        DicError::Param {
            param: param.to_owned(),
            message: message.into(),
        }
    }
}
