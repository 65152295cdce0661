//! What a parameter's type must tell: its description, its own checks, and
//! the input paths inside it. Every method is required, so a type holding an
//! [`InputPath`] cannot forget to show it to the runner.

use std::collections::BTreeMap;

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::{ChoiceDoc, InputPath, ParamError, ParamSpec, join};

/// A type a parameter may have. Implemented here for numbers, text, bools,
/// paths and containers of them, by [`macro@crate::params`] for parameter
/// structs and by [`crate::Choice`] for choices.
pub trait ParamValue:
    Serialize + DeserializeOwned + Clone + std::fmt::Debug + Send + Sync + 'static
{
    /// How `hypercontact stages` names the type.
    fn type_doc() -> TypeDoc;

    /// Checks inside the value (a nested parameter struct's own checks);
    /// errors name the parameter by `prefix` and the path below it.
    fn validate_at(&self, prefix: &str) -> Result<(), ParamError>;

    /// Calls `visit` with every input path inside the value and its
    /// parameter path.
    fn visit_paths(&mut self, prefix: &str, visit: &mut dyn FnMut(&str, &mut InputPath));
}

/// A parameter's type, as `hypercontact stages` describes it.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", content = "of", rename_all = "lowercase")]
pub enum TypeDoc {
    Number,
    Integer,
    Bool,
    Text,
    Path,
    Choice(&'static [ChoiceDoc]),
    Optional(Box<TypeDoc>),
    List(Box<TypeDoc>),
    Array(usize, Box<TypeDoc>),
    Struct(Vec<ParamSpec>),
    /// Labelled values, `{ label: value, ... }`.
    Map(Box<TypeDoc>),
    /// A type with its own spelling (`levels`: an integer or `all`).
    Custom(String),
}

/// `ParamValue` for a type with its own serde form and no paths inside
/// (`levels: 1000 | all`), described by `$doc` in `hypercontact stages`.
#[macro_export]
macro_rules! leaf_param_value {
    ($t:ty, $doc:expr) => {
        impl $crate::ParamValue for $t {
            fn type_doc() -> $crate::param::TypeDoc {
                $crate::param::TypeDoc::Custom(::std::string::ToString::to_string(&$doc))
            }

            fn validate_at(&self, _prefix: &str) -> ::core::result::Result<(), $crate::ParamError> {
                ::core::result::Result::Ok(())
            }

            fn visit_paths(
                &mut self,
                _prefix: &str,
                _visit: &mut dyn ::core::ops::FnMut(&str, &mut $crate::InputPath),
            ) {
            }
        }
    };
}

macro_rules! leaf {
    ($doc:expr => $($t:ty),*) => {$(
        impl ParamValue for $t {
            fn type_doc() -> TypeDoc {
                $doc
            }

            fn validate_at(&self, _prefix: &str) -> Result<(), ParamError> {
                Ok(())
            }

            fn visit_paths(&mut self, _prefix: &str, _visit: &mut dyn FnMut(&str, &mut InputPath)) {}
        }
    )*};
}

leaf!(TypeDoc::Number => f64, f32);
leaf!(TypeDoc::Integer => u8, u16, u32, u64, usize, i32, i64);
leaf!(TypeDoc::Bool => bool);
leaf!(TypeDoc::Text => String);

impl ParamValue for InputPath {
    fn type_doc() -> TypeDoc {
        TypeDoc::Path
    }

    fn validate_at(&self, prefix: &str) -> Result<(), ParamError> {
        if self.path().as_os_str().is_empty() {
            return Err(ParamError::new(prefix, "the path is empty"));
        }
        Ok(())
    }

    fn visit_paths(&mut self, prefix: &str, visit: &mut dyn FnMut(&str, &mut InputPath)) {
        visit(prefix, self);
    }
}

impl<T: ParamValue> ParamValue for Option<T> {
    fn type_doc() -> TypeDoc {
        TypeDoc::Optional(Box::new(T::type_doc()))
    }

    fn validate_at(&self, prefix: &str) -> Result<(), ParamError> {
        self.as_ref().map_or(Ok(()), |v| v.validate_at(prefix))
    }

    fn visit_paths(&mut self, prefix: &str, visit: &mut dyn FnMut(&str, &mut InputPath)) {
        if let Some(v) = self {
            v.visit_paths(prefix, visit);
        }
    }
}

/// Items of a list, each under its index (`files.2`).
fn validate_items<T: ParamValue>(items: &[T], prefix: &str) -> Result<(), ParamError> {
    items
        .iter()
        .enumerate()
        .try_for_each(|(i, v)| v.validate_at(&join(prefix, &i.to_string())))
}

fn visit_items<T: ParamValue>(
    items: &mut [T],
    prefix: &str,
    visit: &mut dyn FnMut(&str, &mut InputPath),
) {
    for (i, v) in items.iter_mut().enumerate() {
        v.visit_paths(&join(prefix, &i.to_string()), visit);
    }
}

impl<T: ParamValue> ParamValue for Vec<T> {
    fn type_doc() -> TypeDoc {
        TypeDoc::List(Box::new(T::type_doc()))
    }

    fn validate_at(&self, prefix: &str) -> Result<(), ParamError> {
        validate_items(self, prefix)
    }

    fn visit_paths(&mut self, prefix: &str, visit: &mut dyn FnMut(&str, &mut InputPath)) {
        visit_items(self, prefix, visit);
    }
}

impl<T: ParamValue, const N: usize> ParamValue for [T; N]
where
    [T; N]: Serialize + DeserializeOwned,
{
    fn type_doc() -> TypeDoc {
        TypeDoc::Array(N, Box::new(T::type_doc()))
    }

    fn validate_at(&self, prefix: &str) -> Result<(), ParamError> {
        validate_items(self, prefix)
    }

    fn visit_paths(&mut self, prefix: &str, visit: &mut dyn FnMut(&str, &mut InputPath)) {
        visit_items(self, prefix, visit);
    }
}

/// Labelled values (`{ T1: a, T2: b }`), in label order.
impl<T: ParamValue> ParamValue for BTreeMap<String, T> {
    fn type_doc() -> TypeDoc {
        TypeDoc::Map(Box::new(T::type_doc()))
    }

    fn validate_at(&self, prefix: &str) -> Result<(), ParamError> {
        self.iter()
            .try_for_each(|(k, v)| v.validate_at(&join(prefix, k)))
    }

    fn visit_paths(&mut self, prefix: &str, visit: &mut dyn FnMut(&str, &mut InputPath)) {
        for (k, v) in self.iter_mut() {
            v.visit_paths(&join(prefix, k), visit);
        }
    }
}
