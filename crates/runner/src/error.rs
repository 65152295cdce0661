//! The error of a pipeline that cannot be read or planned: it names the file,
//! the line and column where known, and the stage.

use std::fmt;
use std::path::{Path, PathBuf};

use hypercontact_core::shown;

use crate::yaml::Location;

#[derive(Debug, Clone, PartialEq)]
pub struct PipelineError {
    pub file: PathBuf,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub stage: Option<String>,
    pub message: String,
}

impl fmt::Display for PipelineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        match (self.line, self.column) {
            (Some(l), Some(c)) => write!(f, ":{l}:{c}")?,
            (Some(l), None) => write!(f, ":{l}")?,
            _ => {}
        }
        write!(f, ": ")?;
        if let Some(stage) = &self.stage {
            write!(f, "stage `{stage}`: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for PipelineError {}

impl PipelineError {
    /// The error in `file`; every value the message quotes (between
    /// backticks or double quotes: a YAML string, a key, a stage name) is
    /// cut to [`shown::ECHO_MAX_CHARS`] characters.
    pub fn new(file: &Path, message: impl Into<String>) -> Self {
        Self {
            file: file.to_owned(),
            line: None,
            column: None,
            stage: None,
            message: shown::cut_quoted(&message.into()),
        }
    }

    pub fn at(mut self, line: Option<usize>, column: Option<usize>) -> Self {
        self.line = line;
        self.column = column;
        self
    }

    pub fn located(self, at: Option<Location>) -> Self {
        match at {
            Some(at) => self.at(Some(at.line), Some(at.column)),
            None => self,
        }
    }

    pub fn stage(mut self, stage: &str) -> Self {
        self.stage = Some(shown::cut(stage));
        self
    }
}

/// An error and its causes on one line, each text said once: a cause whose
/// text the line already holds (a wrapper that quotes its source and also
/// returns it as `source()`) is left out. How the CLI and the Python
/// package print a failed run.
pub fn said_once<I, S>(causes: I) -> String
where
    I: IntoIterator<Item = S>,
    S: fmt::Display,
{
    let mut text = String::new();
    for cause in causes {
        let said = cause.to_string();
        if text.contains(&said) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&said);
    }
    text
}

/// The chain of a plain error (itself, then each `source()`).
pub fn chain(error: &dyn std::error::Error) -> Vec<&dyn std::error::Error> {
    std::iter::successors(Some(error), |e| e.source()).collect()
}
