//! Declared ranges: checked before any run, and shown by `hypercontact stages`.

use std::fmt;
use std::ops::Bound;

use crate::ParamError;

/// The interval a number parameter must lie in (floats must also be finite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamRange {
    pub lo: Bound<f64>,
    pub hi: Bound<f64>,
}

impl ParamRange {
    /// `> 0`.
    pub const POSITIVE: ParamRange = ParamRange {
        lo: Bound::Excluded(0.0),
        hi: Bound::Unbounded,
    };

    pub fn contains(&self, v: f64) -> bool {
        let above = match self.lo {
            Bound::Included(lo) => v >= lo,
            Bound::Excluded(lo) => v > lo,
            Bound::Unbounded => !v.is_nan(),
        };
        let below = match self.hi {
            Bound::Included(hi) => v <= hi,
            Bound::Excluded(hi) => v < hi,
            Bound::Unbounded => !v.is_nan(),
        };
        above && below && v.is_finite()
    }
}

/// A short, exact spelling of a bound: `0.5`, `1000`, `2e-5`.
pub(crate) fn number(v: f64) -> String {
    let plain = format!("{v}");
    if v.fract() == 0.0 && v.abs() < 1e15 {
        return plain;
    }
    let sci = format!("{v:e}");
    if sci.len() < plain.len() { sci } else { plain }
}

impl fmt::Display for ParamRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use Bound::*;
        match (self.lo, self.hi) {
            (Unbounded, Unbounded) => f.write_str("finite"),
            (Included(lo), Unbounded) => write!(f, "≥ {}", number(lo)),
            (Excluded(lo), Unbounded) => write!(f, "> {}", number(lo)),
            (Unbounded, Included(hi)) => write!(f, "≤ {}", number(hi)),
            (Unbounded, Excluded(hi)) => write!(f, "< {}", number(hi)),
            (lo, hi) => {
                let (open, lo) = match lo {
                    Included(v) => ('[', v),
                    Excluded(v) => ('(', v),
                    Unbounded => unreachable!("handled above"),
                };
                let (close, hi) = match hi {
                    Included(v) => (']', v),
                    Excluded(v) => (')', v),
                    Unbounded => unreachable!("handled above"),
                };
                write!(f, "{open}{}, {}{close}", number(lo), number(hi))
            }
        }
    }
}

pub(crate) fn serialize_optional<S: serde::Serializer>(
    range: &Option<ParamRange>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match range {
        Some(r) => s.serialize_str(&r.to_string()),
        None => s.serialize_none(),
    }
}

/// Values a declared range can bound: numbers, and optional numbers and
/// lists of numbers (every element given is checked).
pub trait RangeCheck {
    fn check_in(&self, path: &str, range: &ParamRange) -> Result<(), ParamError>;
}

macro_rules! range_check_number {
    ($($t:ty),*) => {$(
        impl RangeCheck for $t {
            fn check_in(&self, path: &str, range: &ParamRange) -> Result<(), ParamError> {
                #[allow(clippy::cast_precision_loss, clippy::unnecessary_cast)]
                let v = *self as f64;
                if range.contains(v) {
                    Ok(())
                } else {
                    let shown = if v.is_finite() { number(v) } else { format!("{v}") };
                    Err(ParamError::new(path, match (range.lo, range.hi) {
                        (Bound::Unbounded, Bound::Unbounded) => format!("must be finite, got {shown}"),
                        (_, Bound::Unbounded) | (Bound::Unbounded, _) => format!("must be {range}, got {shown}"),
                        _ => format!("must lie in {range}, got {shown}"),
                    }))
                }
            }
        }
    )*};
}

range_check_number!(f64, f32, u8, u16, u32, u64, usize, i32, i64);

impl<T: RangeCheck> RangeCheck for Option<T> {
    fn check_in(&self, path: &str, range: &ParamRange) -> Result<(), ParamError> {
        match self {
            Some(v) => v.check_in(path, range),
            None => Ok(()),
        }
    }
}

impl<T: RangeCheck> RangeCheck for Vec<T> {
    fn check_in(&self, path: &str, range: &ParamRange) -> Result<(), ParamError> {
        self.iter()
            .enumerate()
            .try_for_each(|(i, v)| v.check_in(&super::join(path, &i.to_string()), range))
    }
}

impl<T: RangeCheck, const N: usize> RangeCheck for [T; N] {
    fn check_in(&self, path: &str, range: &ParamRange) -> Result<(), ParamError> {
        self.iter()
            .enumerate()
            .try_for_each(|(i, v)| v.check_in(&super::join(path, &i.to_string()), range))
    }
}

/// What the generated checks call for a declared `range` or `positive`.
pub fn check_range<T: RangeCheck>(
    path: &str,
    value: &T,
    range: &ParamRange,
) -> Result<(), ParamError> {
    value.check_in(path, range)
}
