//! Errors of the report stage; each names the input, column and row, or the
//! figure, that went wrong.

use hypercontact_core::{StageError, TableError};

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// An input table lacks a column or holds the wrong type.
    #[error("input `{input}`: {cause}")]
    Table { input: String, cause: TableError },
    /// An input holds a value the report cannot draw (NaN, wrong label, ...).
    #[error("input `{input}`: {message}")]
    Input { input: String, message: String },
    /// A parameter naming something the inputs do not hold (a model label
    /// not wired).
    #[error("parameter `{param}`: {message}")]
    Param { param: String, message: String },
    /// The `material` table cannot be decoded into a model.
    #[error("input `material`: {0}")]
    Material(String),
    /// Plotting failed (a backend or layout error).
    #[error("figure `{figure}`: {message}")]
    Plot { figure: String, message: String },
    /// Encoding a PNG failed.
    #[error("encoding `{name}`: {message}")]
    Encode { name: String, message: String },
}

impl ReportError {
    pub fn input(input: &str, message: impl Into<String>) -> Self {
        ReportError::Input {
            input: input.to_owned(),
            message: message.into(),
        }
    }

    pub fn table(input: &str, cause: TableError) -> Self {
        ReportError::Table {
            input: input.to_owned(),
            cause,
        }
    }

    pub fn plot(figure: &str, message: impl std::fmt::Display) -> Self {
        ReportError::Plot {
            figure: figure.to_owned(),
            message: message.to_string(),
        }
    }
}

impl From<ReportError> for StageError {
    fn from(e: ReportError) -> Self {
        match e {
            ReportError::Table { input, cause } => StageError::InputTable { input, cause },
            other => StageError::other(other),
        }
    }
}
