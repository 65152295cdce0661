//! Errors of the `persson` and `greenwood-williamson` stages.

use hypercontact_core::StageError;

use crate::spectrum::SpectrumError;

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ClassicalError {
    #[error("{0}")]
    Input(String),
    #[error("{0}")]
    Param(String),
    #[error("input `{0}`: {1}")]
    Spectrum(&'static str, SpectrumError),
    #[error("input `material`: {0}")]
    Material(hypercontact_material::MaterialError),
    #[error("the load range: {0}")]
    Range(#[from] crate::curve::RangeError),
    #[error("the hyperelastic load, {0}")]
    Tangent(String),
}

impl From<ClassicalError> for StageError {
    fn from(e: ClassicalError) -> Self {
        StageError::other(e)
    }
}
