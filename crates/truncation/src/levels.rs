//! Where the truncating planes go (`levels`) and which pixels count as
//! neighbours (`connectivity`), with the YAML spellings users write.

use std::fmt;

use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The planes at which the profile is read off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Levels {
    /// `levels: 1000`: planes z_k = z_max (levels − k) / levels, k = 0 … levels.
    Count(u32),
    /// `levels: all`: one plane at every distinct measured height.
    All,
}

impl Default for Levels {
    fn default() -> Self {
        Levels::Count(1000)
    }
}

impl Levels {
    /// The plane heights above the lowest point, top down. `sorted_desc` holds
    /// the measured heights (above the lowest point) in descending order.
    pub fn planes_m(self, sorted_desc: impl Iterator<Item = f64>, z_max_m: f64) -> Vec<f64> {
        match self {
            Levels::Count(n) => {
                let n = u64::from(n);
                // z_max·(n−k)/n rather than z_max − k·Δz, so the ends are
                // exactly z_max and 0 whatever the rounding.
                (0..=n)
                    .map(|k| z_max_m * (n - k) as f64 / n as f64)
                    .collect()
            }
            Levels::All => {
                let mut planes: Vec<f64> = Vec::new();
                for h in sorted_desc {
                    if planes.last() != Some(&h) {
                        planes.push(h);
                    }
                }
                planes
            }
        }
    }
}

impl Serialize for Levels {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Levels::Count(n) => s.serialize_u32(*n),
            Levels::All => s.serialize_str("all"),
        }
    }
}

impl<'de> Deserialize<'de> for Levels {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(LevelsVisitor)
    }
}

struct LevelsVisitor;

impl LevelsVisitor {
    fn count<E: de::Error>(n: u64) -> Result<Levels, E> {
        match u32::try_from(n) {
            Ok(n) if n >= 1 => Ok(Levels::Count(n)),
            _ => Err(E::custom(format!(
                "levels must be a whole number from 1 to {}, or `all`; got {n}",
                u32::MAX
            ))),
        }
    }
}

impl Visitor<'_> for LevelsVisitor {
    type Value = Levels;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a positive whole number of levels, or `all`")
    }

    fn visit_u64<E: de::Error>(self, n: u64) -> Result<Levels, E> {
        Self::count(n)
    }

    fn visit_i64<E: de::Error>(self, n: i64) -> Result<Levels, E> {
        match u64::try_from(n) {
            Ok(n) => Self::count(n),
            Err(_) => Err(E::custom(format!(
                "levels must be positive or `all`, got {n}"
            ))),
        }
    }

    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Levels, E> {
        if x.fract() == 0.0 && x >= 1.0 && x <= f64::from(u32::MAX) {
            Self::count(x as u64)
        } else {
            Err(E::custom(format!(
                "levels must be a whole number or `all`, got {x}"
            )))
        }
    }

    fn visit_str<E: de::Error>(self, s: &str) -> Result<Levels, E> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("all") {
            return Ok(Levels::All);
        }
        // `levels: "10"` is text in YAML: refused, not read as the number
        // (`--set trunc.levels=10` is read as YAML, so it arrives as 10).
        match hypercontact_core::param::quoted_number_advice(s) {
            Some(advice) => Err(E::custom(format!(
                "levels must be a number or `all`; {advice}"
            ))),
            None => Err(E::custom(format!(
                "levels must be a whole number or `all`, got `{s}`"
            ))),
        }
    }
}

hypercontact_core::leaf_param_value!(Levels, "a whole number of planes ≥ 1, or `all`");

/// Which pixels touch: the 4 edge neighbours, or the 8 edge and corner ones.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "u8", into = "u8")]
pub enum Connectivity {
    Four,
    /// MATLAB's `bwlabel` default, which the paper's labelling used.
    #[default]
    Eight,
}

impl Connectivity {
    /// Neighbour offsets (dx, dy) to examine when a pixel is added. All of
    /// them, since any touched neighbour, earlier or later in memory, joins.
    pub fn offsets(self) -> &'static [(isize, isize)] {
        const FOUR: [(isize, isize); 4] = [(-1, 0), (1, 0), (0, -1), (0, 1)];
        const EIGHT: [(isize, isize); 8] = [
            (-1, -1),
            (-1, 0),
            (-1, 1),
            (0, -1),
            (0, 1),
            (1, -1),
            (1, 0),
            (1, 1),
        ];
        match self {
            Connectivity::Four => &FOUR,
            Connectivity::Eight => &EIGHT,
        }
    }
}

hypercontact_core::leaf_param_value!(Connectivity, "4 | 8");

impl TryFrom<u8> for Connectivity {
    type Error = String;

    fn try_from(n: u8) -> Result<Self, String> {
        match n {
            4 => Ok(Connectivity::Four),
            8 => Ok(Connectivity::Eight),
            other => Err(format!("connectivity must be 4 or 8, got {other}")),
        }
    }
}

impl From<Connectivity> for u8 {
    fn from(c: Connectivity) -> u8 {
        match c {
            Connectivity::Four => 4,
            Connectivity::Eight => 8,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_accept_numbers_and_all() {
        let l: Levels = serde_json::from_str("250").unwrap();
        assert_eq!(l, Levels::Count(250));
        let l: Levels = serde_json::from_str("\"all\"").unwrap();
        assert_eq!(l, Levels::All);
        // A quoted number is text (#31, 11): refused, saying how to write it.
        let e = serde_json::from_str::<Levels>("\"64\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("write 64, not \"64\""), "{e}");
        assert_eq!(serde_json::to_string(&Levels::All).unwrap(), "\"all\"");
        assert_eq!(serde_json::to_string(&Levels::Count(7)).unwrap(), "7");
        for bad in ["0", "-3", "2.5", "\"some\""] {
            let e = serde_json::from_str::<Levels>(bad).unwrap_err().to_string();
            assert!(e.contains("levels"), "{bad}: {e}");
        }
    }

    #[test]
    fn connectivity_is_4_or_8() {
        let c: Connectivity = serde_json::from_str("4").unwrap();
        assert_eq!(c, Connectivity::Four);
        assert_eq!(serde_json::to_string(&Connectivity::Eight).unwrap(), "8");
        let e = serde_json::from_str::<Connectivity>("6")
            .unwrap_err()
            .to_string();
        assert!(e.contains("4 or 8"), "{e}");
    }

    #[test]
    fn planes_run_from_the_top_to_exactly_zero() {
        let z = Levels::Count(3).planes_m(std::iter::empty(), 0.3);
        assert_eq!(z.len(), 4);
        assert_eq!((z[0], z[3]), (0.3, 0.0));
        assert!((z[1] - 0.2).abs() < 1e-15);
        let z = Levels::All.planes_m([3.0, 2.0, 2.0, 0.5, 0.0].into_iter(), 3.0);
        assert_eq!(z, [3.0, 2.0, 0.5, 0.0]);
    }
}
