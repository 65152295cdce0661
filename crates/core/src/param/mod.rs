//! Stage parameters: YAML → typed struct → [`Checked`], before any work.
//!
//! A parameter struct is declared once with [`macro@crate::params`]: each field
//! carries its doc comment, default, unit and range. From that declaration
//! come the serde shape, the checks, the `hypercontact stages` description and
//! the walk over input paths (whose content the runner hashes into the cache
//! key). A stage's `run` takes only [`Checked`] parameters, and the only way
//! to one is [`Params::check`], in the spirit of linfa's `ParamGuard`.

mod choice;
pub mod flatten;
mod path;
mod quoted;
mod range;
mod value;

use std::fmt;
use std::ops::Deref;

use serde::Serialize;

pub use choice::{Choice, ChoiceDoc, UnknownChoice, deserialize_choice, parse_choice};
pub use flatten::Flatten;
pub use path::InputPath;
pub use quoted::{explain_quoted_number, quoted_number_advice};
pub use range::{ParamRange, RangeCheck, check_range};
pub use value::{ParamValue, TypeDoc};

/// The parameters of one stage kind. Implemented by [`macro@crate::params`];
/// not meant to be implemented by hand.
pub trait Params: ParamValue {
    /// Every parameter as declared: name, unit, doc, type, default, range.
    fn spec() -> Vec<ParamSpec>;

    /// The parameters, checked: the only way to a [`Checked`] value.
    fn check(self) -> Result<Checked<Self>, ParamError> {
        self.validate_at("")?;
        Ok(Checked(self))
    }
}

/// Parameters that passed their checks. A stage's `run` accepts nothing
/// else, so no library user or test can hand it `poisson: 7.0`; the field is
/// private, so a `Checked` comes only from [`Params::check`]
/// (`tests/compile_fail/` pins both with the compiler's own errors).
#[derive(Clone, Debug, PartialEq)]
pub struct Checked<P>(P);

impl<P> Deref for Checked<P> {
    type Target = P;

    fn deref(&self) -> &P {
        &self.0
    }
}

impl<P> Checked<P> {
    /// The plain parameters, e.g. to change one and check them again.
    pub fn into_inner(self) -> P {
        self.0
    }
}

impl<P: Serialize> Serialize for Checked<P> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(serializer)
    }
}

/// One parameter, as declared.
#[derive(Clone, Debug, Serialize)]
pub struct ParamSpec {
    /// The key in YAML.
    pub name: &'static str,
    /// SI unit, or "" for dimensionless values, counts and choices.
    pub unit: &'static str,
    /// The field's doc comment.
    pub doc: &'static str,
    #[serde(rename = "type")]
    pub ty: TypeDoc,
    /// The default in its YAML/JSON form; `None` when the parameter is
    /// required or optional without a default.
    pub default: Option<serde_json::Value>,
    pub required: bool,
    /// The declared range, checked before any run.
    #[serde(serialize_with = "range::serialize_optional")]
    pub range: Option<ParamRange>,
    /// Whether a further check (a function named in the declaration) applies.
    pub custom_check: bool,
}

/// A parameter value that fails its check, naming the parameter by its path
/// (`poisson`, `weights.UT`, `files.2`).
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

    /// The same error for a parameter nested under `prefix`.
    pub fn under(mut self, prefix: &str) -> Self {
        self.param = join(prefix, &self.param);
        self
    }
}

/// `prefix.name`, or `name` at the top.
pub fn join(prefix: &str, name: &str) -> String {
    match (prefix.is_empty(), name.is_empty()) {
        (true, _) => name.to_owned(),
        (_, true) => prefix.to_owned(),
        _ => format!("{prefix}.{name}"),
    }
}

impl fmt::Display for TypeDoc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TypeDoc::Number => f.write_str("number"),
            TypeDoc::Integer => f.write_str("integer"),
            TypeDoc::Bool => f.write_str("bool"),
            TypeDoc::Text => f.write_str("text"),
            TypeDoc::Path => f.write_str("path"),
            TypeDoc::Choice(variants) => {
                let names: Vec<&str> = variants.iter().map(|v| v.name).collect();
                f.write_str(&names.join(" | "))
            }
            TypeDoc::Optional(inner) => write!(f, "{inner} (optional)"),
            TypeDoc::List(inner) => write!(f, "list of {inner}"),
            TypeDoc::Array(n, inner) => write!(f, "{n} × {inner}"),
            TypeDoc::Struct(fields) => {
                let names: Vec<&str> = fields.iter().map(|p| p.name).collect();
                write!(f, "{{{}}}", names.join(", "))
            }
            TypeDoc::Map(inner) => write!(f, "map of {inner}"),
            TypeDoc::Custom(text) => f.write_str(text),
        }
    }
}

/// Parameters of a stage that takes none.
#[crate::params]
pub struct NoParams {}

#[cfg(test)]
mod tests;
