//! Choices: parameters that take one of a fixed set of names.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, Deserializer, Visitor};

/// A fieldless enum read and written by name; derive it with
/// [`crate::Choice`].
pub trait Choice: Sized + 'static {
    /// Every variant's name and doc, in declaration order.
    const VARIANTS: &'static [ChoiceDoc];
    fn name(&self) -> &'static str;
    fn from_name(name: &str) -> Option<Self>;
}

/// One variant of a choice, for `hypercontact stages`.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ChoiceDoc {
    pub name: &'static str,
    pub doc: &'static str,
}

/// A name that is none of a choice's variants.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("unknown value `{given}` (expected one of: {expected})")]
pub struct UnknownChoice {
    pub given: String,
    pub expected: String,
}

/// `FromStr` for a [`Choice`].
pub fn parse_choice<C: Choice>(s: &str) -> Result<C, UnknownChoice> {
    C::from_name(s).ok_or_else(|| UnknownChoice {
        given: s.to_owned(),
        expected: C::VARIANTS
            .iter()
            .map(|v| v.name)
            .collect::<Vec<_>>()
            .join(", "),
    })
}

/// `Deserialize` for a [`Choice`]: a string naming a variant, or serde's
/// "unknown variant" error listing them.
pub fn deserialize_choice<'de, D: Deserializer<'de>, C: Choice>(d: D) -> Result<C, D::Error> {
    struct ChoiceVisitor<C>(PhantomData<C>);

    impl<C: Choice> Visitor<'_> for ChoiceVisitor<C> {
        type Value = C;

        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            let names: Vec<&str> = C::VARIANTS.iter().map(|v| v.name).collect();
            write!(f, "one of {}", names.join(", "))
        }

        fn visit_str<E: de::Error>(self, v: &str) -> Result<C, E> {
            C::from_name(v).ok_or_else(|| {
                // serde's own wording for an unknown variant, so every choice
                // reads like the other enums.
                let names: Vec<String> = C::VARIANTS
                    .iter()
                    .map(|v| format!("`{}`", v.name))
                    .collect();
                let expected = match names.as_slice() {
                    [one] => one.clone(),
                    [a, b] => format!("{a} or {b}"),
                    _ => format!("one of {}", names.join(", ")),
                };
                E::custom(format_args!("unknown variant `{v}`, expected {expected}"))
            })
        }

        // `model: 3` or `model: true` in YAML is a name that is not a variant,
        // reported as such rather than as a type error.
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<C, E> {
            self.visit_str(&v.to_string())
        }

        fn visit_i64<E: de::Error>(self, v: i64) -> Result<C, E> {
            self.visit_str(&v.to_string())
        }

        fn visit_f64<E: de::Error>(self, v: f64) -> Result<C, E> {
            self.visit_str(&v.to_string())
        }

        fn visit_bool<E: de::Error>(self, v: bool) -> Result<C, E> {
            self.visit_str(&v.to_string())
        }
    }

    d.deserialize_any(ChoiceVisitor(PhantomData))
}
