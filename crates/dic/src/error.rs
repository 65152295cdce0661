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
