//! Errors of the optics and camera cores; each names the parameter or input
//! at fault and the value it held.

/// Why an image cannot be formed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InterferenceError {
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
    /// An input with no values.
    #[error("{what} is empty ({detail})")]
    Empty { what: &'static str, detail: String },
    /// A value that is not allowed at that place of an input.
    #[error("{what}[{index}] = {value}: {message}")]
    Value {
        what: &'static str,
        index: usize,
        value: f64,
        message: &'static str,
    },
    /// The spectrum is so narrow that the fringes do not wash out within the
    /// gaps the lookup table may span.
    #[error(
        "the fringes still swing by {residual:.3e} (tolerance {tolerance:.1e}) at a gap of \
         {max_gap_m:.3e} m: the spectrum is too narrow for the incoherent limit there; raise \
         `max_gap_m` or the tolerance"
    )]
    Coherent {
        residual: f64,
        tolerance: f64,
        max_gap_m: f64,
    },
}

impl InterferenceError {
    pub(crate) fn param(
        param: &'static str,
        value: impl ToString,
        message: impl Into<String>,
    ) -> Self {
        InterferenceError::Param {
            param,
            value: value.to_string(),
            message: message.into(),
        }
    }
}

/// `Ok` when `value` is finite and strictly positive.
pub(crate) fn positive(param: &'static str, value: f64) -> Result<(), InterferenceError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(InterferenceError::param(
            param,
            value,
            "must be finite and greater than 0",
        ))
    }
}

/// `Ok` when `value` is finite and not negative.
pub(crate) fn non_negative(param: &'static str, value: f64) -> Result<(), InterferenceError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(InterferenceError::param(
            param,
            value,
            "must be finite and at least 0",
        ))
    }
}
