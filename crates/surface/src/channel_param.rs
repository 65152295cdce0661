//! `height-map`'s `channel`: which image of a multi-channel instrument file
//! (an AFM's height, deflection and phase, trace and retrace) is read,
//! spelled as YAML users write it: `channel: 2` or `channel: Height`.

use std::fmt;

use hypercontact_formats::Channel;
use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A channel by its position in the file's list, or by its name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ChannelParam {
    /// `channel: 2`: the third channel the note lists
    Index(usize),
    /// `channel: Height`: the first of that name, case ignored
    Name(String),
}

impl ChannelParam {
    /// The formats crate's choice.
    pub fn to_channel(&self) -> Channel {
        match self {
            ChannelParam::Index(index) => Channel::Index(*index),
            ChannelParam::Name(name) => Channel::Name(name.clone()),
        }
    }
}

impl Serialize for ChannelParam {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            ChannelParam::Index(index) => s.serialize_u64(*index as u64),
            ChannelParam::Name(name) => s.serialize_str(name),
        }
    }
}

impl<'de> Deserialize<'de> for ChannelParam {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ChannelVisitor)
    }
}

struct ChannelVisitor;

impl Visitor<'_> for ChannelVisitor {
    type Value = ChannelParam;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a channel's position (0, 1, ...) or its name")
    }

    fn visit_u64<E: de::Error>(self, n: u64) -> Result<ChannelParam, E> {
        usize::try_from(n)
            .map(ChannelParam::Index)
            .map_err(|_| E::custom(format!("channel {n} is beyond any file's channels")))
    }

    fn visit_i64<E: de::Error>(self, n: i64) -> Result<ChannelParam, E> {
        match u64::try_from(n) {
            Ok(n) => self.visit_u64(n),
            Err(_) => Err(E::custom(format!(
                "channel must be a position from 0 or a name, got {n}"
            ))),
        }
    }

    fn visit_f64<E: de::Error>(self, x: f64) -> Result<ChannelParam, E> {
        if x.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&x) {
            Ok(ChannelParam::Index(x as usize))
        } else {
            Err(E::custom(format!(
                "channel must be a whole position from 0 or a name, got {x}"
            )))
        }
    }

    fn visit_str<E: de::Error>(self, s: &str) -> Result<ChannelParam, E> {
        let name = s.trim();
        if name.is_empty() {
            return Err(E::custom(
                "channel is empty: give a position (0, 1, ...) or a name",
            ));
        }
        Ok(ChannelParam::Name(name.to_string()))
    }
}

hypercontact_core::leaf_param_value!(
    ChannelParam,
    "a channel's position from 0, or its name (case ignored)"
);

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn positions_and_names_are_read_and_written_as_given() {
        let read = |v| serde_json::from_value::<ChannelParam>(v);
        assert_eq!(read(json!(2)).unwrap(), ChannelParam::Index(2));
        assert_eq!(read(json!(3.0)).unwrap(), ChannelParam::Index(3));
        assert_eq!(
            read(json!(" Height ")).unwrap(),
            ChannelParam::Name("Height".into())
        );
        for bad in [json!(-1), json!(1.5), json!(""), json!(true), json!([0])] {
            assert!(read(bad.clone()).is_err(), "{bad}");
        }
        for p in [ChannelParam::Index(1), ChannelParam::Name("Phase".into())] {
            let back = read(serde_json::to_value(&p).unwrap()).unwrap();
            assert_eq!(back, p);
        }
        assert_eq!(ChannelParam::Index(1).to_channel(), Channel::Index(1));
    }
}
