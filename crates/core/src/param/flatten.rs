//! Parameter blocks declared once and spliced into several stages' parameters
//! (`#[param(flatten)]`): the contact law every contact model takes, the
//! spectrum route Persson's and Greenwood–Williamson's theories share.
//!
//! serde's own `#[serde(flatten)]` cannot refuse unknown keys
//! (`deny_unknown_fields` does not combine with it) and loses the path of an
//! error inside the flattened block, so `#[params]` reads a struct with
//! flattened blocks key by key itself: each key goes to the field or block
//! that declares it, read from the same map, so a wrong value is still
//! reported at its own key (`parameter `poisson`: ...`) and an unknown key
//! with serde's own message listing every key the stage takes.

use serde::de::{Error, MapAccess};

/// Implemented by [`macro@crate::params`] for every parameter struct, so any
/// of them can be flattened into another. Not meant to be implemented by
/// hand.
pub trait Flatten: Sized {
    /// One slot per parameter, filled as its key is read.
    type Slots: Default;

    /// Every key the struct takes, flattened blocks' keys in their place.
    const FIELDS: &'static [&'static str];

    /// Reads the value of `key` into its slot if this struct (or a block
    /// flattened into it) declares the key; `Ok(false)` if it does not.
    fn take<'de, A: MapAccess<'de>>(
        slots: &mut Self::Slots,
        key: &str,
        map: &mut A,
    ) -> Result<bool, A::Error>;

    /// The struct from its slots: defaults for absent keys, an error for an
    /// absent required one.
    fn finish<E: Error>(slots: Self::Slots) -> Result<Self, E>;
}

/// The value of a key this struct declares, refusing it a second time.
#[doc(hidden)]
pub fn fill<'de, T: serde::Deserialize<'de>, A: MapAccess<'de>>(
    slot: &mut Option<T>,
    key: &'static str,
    map: &mut A,
) -> Result<bool, A::Error> {
    if slot.is_some() {
        return Err(A::Error::duplicate_field(key));
    }
    *slot = Some(map.next_value()?);
    Ok(true)
}

/// Reads a key and refuses one not in `0` from inside the key's own
/// deserialisation, as serde's derive does: so serde_path_to_error places
/// the error at the unknown key (`parameter `poison`: unknown field ...`).
#[doc(hidden)]
#[derive(Clone, Copy)]
pub struct Key(pub &'static [&'static str]);

impl<'de> serde::de::DeserializeSeed<'de> for Key {
    type Value = String;

    fn deserialize<D: serde::Deserializer<'de>>(self, deserializer: D) -> Result<String, D::Error> {
        let key = <String as serde::Deserialize>::deserialize(deserializer)?;
        if self.0.contains(&key.as_str()) {
            Ok(key)
        } else {
            Err(D::Error::unknown_field(&key, self.0))
        }
    }
}
