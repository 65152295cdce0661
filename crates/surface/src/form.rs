//! Form removal: the least-squares fit of a nominal shape (a polynomial,
//! a sphere, a cylinder) to the measured points of a height map, and the
//! map with that shape subtracted (the residual), as ISO 25178-2 asks
//! before roughness parameters are computed (the "F operator").
//!
//! - [`polynomial`]: total degree 0..=6 in Legendre polynomials of
//!   coordinates scaled to [−1, 1], a linear least-squares problem;
//! - [`sag`]: a sphere, or a cylinder whose axis lies in the map's plane,
//!   fitted by Levenberg–Marquardt on the vertical residual, started from an
//!   algebraic (Kåsa) fit.
//!
//! Each returns a [`FormRemoval`]: the residual map (NaN where the input is
//! NaN), the fitted form's parameters in metres, and the rms of what was
//! removed, for a note such as `form: sphere R = 12.3 mm removed, 4.10 um
//! rms`. Sums over the map run in the fixed order of
//! `hypercontact_numeric::reduce`, so the results are the same bits on any
//! number of threads.

pub mod polynomial;
pub mod sag;

use hypercontact_core::StageError;
use hypercontact_numeric::reduce;
use ndarray::Array2;

pub use polynomial::{Polynomial, remove_polynomial};
pub use sag::{Cap, Cylinder, CylinderAxis, Sphere, remove_cylinder, remove_sphere};

/// Errors of form removal; each says what is wrong with the input.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FormError {
    #[error("{name} = {value}: the spacing must be finite and positive")]
    Spacing { name: &'static str, value: f64 },
    #[error("the map has {nx} × {ny} points: form removal needs at least 2 × 2")]
    TooSmall { nx: usize, ny: usize },
    #[error("height at point ({i}, {j}) is {value}: heights must be finite or NaN (not measured)")]
    NotFinite { i: usize, j: usize, value: f64 },
    #[error("degree = {degree}: the polynomial form's degree must be 0 to 6")]
    Degree { degree: usize },
    #[error("{form}: {found} measured points, fewer than the {needed} the fit needs")]
    TooFewPoints {
        form: String,
        needed: usize,
        found: usize,
    },
    #[error("{form}: {why}")]
    Degenerate { form: String, why: String },
    #[error(
        "{form}: the fit did not converge in {iterations} iterations (is the map this shape? \
         remove spikes first)"
    )]
    NoConvergence { form: String, iterations: usize },
}

impl From<FormError> for StageError {
    fn from(e: FormError) -> Self {
        StageError::other(e)
    }
}

/// A map with its form removed.
#[derive(Clone, Debug, PartialEq)]
pub struct FormRemoval<F> {
    /// Height minus the fitted form, metres; NaN where the input is NaN.
    pub residual_m: Array2<f64>,
    /// The fitted form.
    pub form: F,
    /// Measured (non-NaN) points the fit used.
    pub points: usize,
    /// Rms about its mean of the subtracted form over the measured points:
    /// how much shape was removed (its mean, a height offset, is not form).
    pub removed_rms_m: f64,
    /// Rms of the residual over the measured points (about zero).
    pub residual_rms_m: f64,
}

/// A fitted form that can name itself in a note.
pub trait Form {
    /// E.g. `sphere R = 12.3 mm`, `polynomial of degree 3`.
    fn name(&self) -> String;
}

impl<F: Form> FormRemoval<F> {
    /// One line for the stage's note: `form: sphere R = 12.3 mm removed,
    /// 4.10 um rms (residual 12.0 nm rms)`.
    pub fn description(&self) -> String {
        format!(
            "form: {} removed, {} rms (residual {} rms)",
            self.form.name(),
            length(self.removed_rms_m),
            length(self.residual_rms_m)
        )
    }
}

/// A length with 3 significant digits in m, mm, um or nm.
pub fn length(value_m: f64) -> String {
    let a = value_m.abs();
    let (scale, unit) = if a >= 1.0 || a == 0.0 || !a.is_finite() {
        (1.0, "m")
    } else if a >= 1e-3 {
        (1e3, "mm")
    } else if a >= 1e-6 {
        (1e6, "um")
    } else {
        (1e9, "nm")
    };
    let v = value_m * scale;
    let decimals = if v.abs() >= 100.0 {
        0
    } else if v.abs() >= 10.0 {
        1
    } else {
        2
    };
    format!("{v:.decimals$} {unit}")
}

/// Checks the spacings, the size and the heights of a map; returns the
/// number of measured points.
pub(crate) fn check_map(h: &Array2<f64>, dx_m: f64, dy_m: f64) -> Result<usize, FormError> {
    for (name, value) in [("dx_m", dx_m), ("dy_m", dy_m)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(FormError::Spacing { name, value });
        }
    }
    let (nx, ny) = h.dim();
    if nx < 2 || ny < 2 {
        return Err(FormError::TooSmall { nx, ny });
    }
    let mut measured = 0;
    for ((i, j), &value) in h.indexed_iter() {
        if value.is_infinite() {
            return Err(FormError::NotFinite { i, j, value });
        }
        measured += usize::from(!value.is_nan());
    }
    Ok(measured)
}

/// Subtracts `form(i, j)` from every measured point of `h` and returns the
/// residual map with [`FormRemoval`]'s statistics (points, removed rms,
/// residual rms). `shift` is a value near the form's mean, taken off before
/// squaring so the removed rms does not cancel against a large mean.
pub(crate) fn subtract<F: Fn(usize, usize) -> f64 + Sync>(
    h: &Array2<f64>,
    shift: f64,
    form: F,
) -> (Array2<f64>, usize, f64, f64) {
    let (nx, ny) = h.dim();
    let mut residual = vec![0.0; nx * ny];
    let [n, s1, s2, r2] = reduce::fill_sums(&mut residual, |k| {
        let (i, j) = (k / ny, k % ny);
        let z = h[[i, j]];
        if z.is_nan() {
            return (f64::NAN, [0.0; 4]);
        }
        let f = form(i, j);
        let (df, r) = (f - shift, z - f);
        (r, [1.0, df, df * df, r * r])
    });
    let residual = Array2::from_shape_vec((nx, ny), residual)
        .unwrap_or_else(|_| unreachable!("nx · ny values were filled"));
    let points = n as usize;
    let count = n.max(1.0);
    let mean = s1 / count;
    let removed_rms_m = (s2 / count - mean * mean).max(0.0).sqrt();
    (residual, points, removed_rms_m, (r2 / count).sqrt())
}

#[cfg(test)]
mod tests;
