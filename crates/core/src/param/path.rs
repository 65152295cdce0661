//! Input paths: files and folders a stage reads, hashed into its cache key.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// A file or folder a stage reads. Declaring a parameter of this type (alone,
/// in an `Option`, a list or a nested struct) is all it takes: the runner
/// resolves it against the pipeline's folder and puts the hash of its
/// content in the stage's cache key, so editing the file reruns the stage.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct InputPath(PathBuf);

impl InputPath {
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self(path.into())
    }

    pub fn path(&self) -> &Path {
        &self.0
    }

    /// Makes a relative path relative to `dir` instead (the pipeline's folder).
    pub fn resolve_against(&mut self, dir: &Path) {
        if !self.0.as_os_str().is_empty() && self.0.is_relative() {
            self.0 = dir.join(&self.0);
        }
    }
}

impl AsRef<Path> for InputPath {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl std::ops::Deref for InputPath {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl From<&str> for InputPath {
    fn from(s: &str) -> Self {
        Self(s.into())
    }
}

impl From<PathBuf> for InputPath {
    fn from(p: PathBuf) -> Self {
        Self(p)
    }
}

impl From<&Path> for InputPath {
    fn from(p: &Path) -> Self {
        Self(p.to_owned())
    }
}

impl fmt::Display for InputPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.display().fmt(f)
    }
}

impl From<&InputPath> for PathBuf {
    fn from(p: &InputPath) -> PathBuf {
        p.0.clone()
    }
}
