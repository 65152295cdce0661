//! Typed stage parameters: YAML → typed struct → checked, before any work.

use std::fmt;
use std::path::PathBuf;

use serde::Serialize;
use serde::de::DeserializeOwned;

/// The parameters of one stage kind.
///
/// Implementors derive `Deserialize` with `#[serde(deny_unknown_fields,
/// default)]`, so a typo is an error and an omitted key takes its default.
/// The serialised form (with defaults filled in) is what enters the cache
/// key, so key order and float spelling in the YAML do not matter.
pub trait Params:
    Serialize + DeserializeOwned + Default + Clone + fmt::Debug + Send + Sync + 'static
{
    /// Rejects values no run could use, naming the parameter (in the spirit
    /// of linfa's `ParamGuard`): a stage's `run` never sees them.
    fn check(&self) -> Result<(), ParamError> {
        Ok(())
    }

    /// The file and folder paths among the parameters. The runner resolves
    /// relative ones against the pipeline's folder and hashes their content
    /// into the cache key, so editing an input file reruns the stage.
    fn paths_mut(&mut self) -> Vec<&mut PathBuf> {
        Vec::new()
    }
}

/// A parameter value that fails its check.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("parameter `{param}`: {message}")]
pub struct ParamError {
    pub param: String,
    pub message: String,
}

impl ParamError {
    pub fn new(param: &str, message: impl Into<String>) -> Self {
        Self {
            param: param.to_owned(),
            message: message.into(),
        }
    }
}

/// Checks `value > 0` and finite.
pub fn positive(param: &str, value: f64) -> Result<(), ParamError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(ParamError::new(
            param,
            format!("must be positive and finite, got {value}"),
        ))
    }
}

/// Checks `lo <= value <= hi`.
pub fn in_range(param: &str, value: f64, lo: f64, hi: f64) -> Result<(), ParamError> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(ParamError::new(
            param,
            format!("must lie in [{lo}, {hi}], got {value}"),
        ))
    }
}

/// Parameters of a stage that takes none.
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoParams {}

impl Params for NoParams {}
