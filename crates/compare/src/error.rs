//! Errors of the comparison cores; each names the input or parameter at
//! fault and the value it held.

use hypercontact_interference::InterferenceError;

/// Why a comparison cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CompareError {
    /// A parameter outside its range.
    #[error("parameter `{param}` = {value}: {message}")]
    Param {
        param: &'static str,
        value: String,
        message: String,
    },
    /// An input array whose length does not match its stated size.
    #[error("{what} holds {got} values, {expected} expected")]
    Length {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    /// An input with no values, or too few to work with.
    #[error("{what} is empty ({detail})")]
    Empty { what: &'static str, detail: String },
    /// An input too small to work with.
    #[error("{what} is too small: {detail}")]
    TooSmall { what: &'static str, detail: String },
    /// A value that is not allowed at that place of an input.
    #[error("{what}[{index}] = {value}: {message}")]
    Value {
        what: &'static str,
        index: usize,
        value: f64,
        message: &'static str,
    },
    /// A map or mask with one value everywhere it is measured: nothing in it
    /// to register.
    #[error("{what} shows {state}: a registration needs both contact and no contact in it")]
    Uniform {
        what: &'static str,
        state: &'static str,
    },
    /// The camera's view does not fit inside the predicted map.
    #[error(
        "the camera's view ({view_x_mm:.3} × {view_y_mm:.3} mm) does not fit inside the predicted \
         map's measured area ({map_x_mm:.3} × {map_y_mm:.3} mm) at any angle searched, with at \
         least {min_overlap} of it on measured points: the view is larger than the map (check \
         `pixel_m` and the map's spacing) or the map is mostly unmeasured"
    )]
    ViewOutsideMap {
        view_x_mm: f64,
        view_y_mm: f64,
        map_x_mm: f64,
        map_y_mm: f64,
        min_overlap: f64,
    },
    /// A load–area curve that cannot be read as one.
    #[error("the load–area curve of {what}: {message}")]
    Curve { what: String, message: String },
    /// Two things to compare that share nothing to compare on.
    #[error("{message}")]
    NoOverlap { message: String },
    /// A step that cannot fail on checked inputs did (a bug to report).
    #[error("internal error: {0}")]
    Internal(String),
    /// Resampling the predicted map failed (an input the checks here let
    /// through).
    #[error(transparent)]
    Interference(#[from] InterferenceError),
}

impl CompareError {
    pub(crate) fn param(
        param: &'static str,
        value: impl ToString,
        message: impl Into<String>,
    ) -> Self {
        CompareError::Param {
            param,
            value: value.to_string(),
            message: message.into(),
        }
    }
}

/// `Ok` when `value` is finite and strictly positive.
pub(crate) fn positive(param: &'static str, value: f64) -> Result<(), CompareError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CompareError::param(
            param,
            value,
            "must be finite and greater than 0",
        ))
    }
}
