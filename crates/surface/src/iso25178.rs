//! Areal surface texture parameters of ISO 25178-2 (and the functional
//! parameters of ISO 13565-2 it adopts) of a height map that the caller has
//! already levelled (form removed): the reference plane is the mean of the
//! measured points, as ISO 25178-2 §3.1.9 takes the mean plane after form
//! removal.
//!
//! Conventions shared by every function here: array axis 0 is x (spacing
//! `dx_m`), axis 1 is y (`dy_m`); NaN marks a point that was not measured and
//! is left out of every sum (a difference or cell counts only when all its
//! points are measured); heights are in metres; sums go through
//! [`hypercontact_numeric::reduce`], so results do not depend on the number
//! of threads.
//!
//! - [`height`]: Sa, Sq, Ssk, Sku, Sp, Sv, Sz;
//! - [`hybrid`]: Sdq (rms gradient) and Sdr (developed interfacial area ratio);
//! - [`acf`]: the areal autocorrelation function, Sal, Str and the
//!   correlation length;
//! - [`material_ratio`]: the Abbott–Firestone curve Smr(c), its inverse
//!   Smc(mr) and Sk, Spk, Svk, Smr1, Smr2;
//! - [`distributions`]: histograms of height, slope and curvature, and the
//!   scale-dependent rms slope and curvature of SurfaceTopography.
//!
//! [`areal_parameters`] computes every scalar at once.

pub mod acf;
pub mod distributions;
pub mod height;
pub mod hybrid;
pub mod material_ratio;
#[cfg(test)]
mod tests;

use std::borrow::Cow;

use ndarray::Array2;

use crate::SurfaceError;

pub use acf::{Autocorrelation, Axis, DecayLengths, autocorrelation};
pub use distributions::{
    Histogram, ScaleSeries, curvature_histogram, height_histogram, lag_ladder,
    scale_dependent_curvature, scale_dependent_slope, slope_and_curvature_histograms,
    slope_histogram,
};
pub use height::{HeightParameters, height_parameters};
pub use hybrid::{sdq, sdr_percent};
pub use material_ratio::{FunctionalParameters, MaterialRatio};

/// ISO 25178-2's default threshold s of Sal and Str: the autocorrelation has
/// decayed at the lag where it first falls to 0.2.
pub const ISO_DECAY_THRESHOLD: f64 = 0.2;

/// The fewest measured points any parameter here is computed from (the
/// kurtosis needs four).
pub const MIN_MEASURED: usize = 4;

/// Every scalar areal parameter of a levelled map. A parameter that a map
/// does not define is NaN: Ssk, Sku, Sal, Str and the correlation length of
/// a flat map (Sq = 0), Sal and the correlation length when the
/// autocorrelation does not decay far enough within half the map's extent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArealParameters {
    /// Arithmetical mean height ⟨|z|⟩, m.
    pub sa_m: f64,
    /// Root mean square height ⟨z²⟩^½, m.
    pub sq_m: f64,
    /// Skewness ⟨z³⟩ / Sq³.
    pub ssk: f64,
    /// Kurtosis ⟨z⁴⟩ / Sq⁴ (3 for Gaussian heights).
    pub sku: f64,
    /// Maximum peak height, m.
    pub sp_m: f64,
    /// Maximum pit depth (positive), m.
    pub sv_m: f64,
    /// Maximum height Sp + Sv, m.
    pub sz_m: f64,
    /// Root mean square gradient (dimensionless), see [`sdq`].
    pub sdq: f64,
    /// Developed interfacial area ratio, %, see [`sdr_percent`].
    pub sdr_percent: f64,
    /// Autocorrelation length at s = 0.2, m, see [`DecayLengths`].
    pub sal_m: f64,
    /// Texture aspect ratio at s = 0.2 (0 … 1), see [`DecayLengths::str`].
    pub str: f64,
    /// Core height, m, see [`FunctionalParameters`].
    pub sk_m: f64,
    /// Reduced peak height, m.
    pub spk_m: f64,
    /// Reduced valley depth, m.
    pub svk_m: f64,
    /// Material ratio at the top of the core, %.
    pub smr1_percent: f64,
    /// Material ratio at the bottom of the core, %.
    pub smr2_percent: f64,
    /// Lag at which the radially averaged autocorrelation falls to 1/e, m,
    /// see [`Autocorrelation::correlation_length_m`].
    pub correlation_length_m: f64,
}

/// All scalar parameters of a levelled map `h` (NaN = not measured) with
/// spacings `dx_m`, `dy_m`. O(N log N) in the number of points N: the
/// autocorrelation's FFT and the material-ratio curve's sort.
pub fn areal_parameters(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
) -> Result<ArealParameters, SurfaceError> {
    areal_parameters_and_curve(h, dx_m, dy_m).map(|(parameters, _)| parameters)
}

/// [`areal_parameters`] and the material ratio curve they were read from
/// (its heights sorted once for both).
pub fn areal_parameters_and_curve(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
) -> Result<(ArealParameters, MaterialRatio), SurfaceError> {
    areal_parameters_curve_and_acf(h, dx_m, dy_m).map(|(parameters, ratio, _)| (parameters, ratio))
}

/// [`areal_parameters_and_curve`] and the autocorrelation Sal, Str and the
/// correlation length were read from (its FFT computed once for all).
pub fn areal_parameters_curve_and_acf(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
) -> Result<(ArealParameters, MaterialRatio, Autocorrelation), SurfaceError> {
    let heights = height_parameters(h)?;
    let sdq = sdq(h, dx_m, dy_m)?;
    let sdr_percent = sdr_percent(h, dx_m, dy_m)?;
    let acf = autocorrelation(h, dx_m, dy_m)?;
    let decay = acf.decay_lengths(ISO_DECAY_THRESHOLD)?;
    let ratio = MaterialRatio::new(h)?;
    let parameters = ArealParameters::assemble(
        &heights,
        (sdq, sdr_percent),
        (decay.sal_m(), decay.str()),
        &ratio.functional(),
        acf.correlation_length_m(),
    );
    Ok((parameters, ratio, acf))
}

impl ArealParameters {
    /// The parameters from their groups: the height parameters, (Sdq,
    /// Sdr), (Sal, Str), the functional ones of the material ratio, and the
    /// correlation length (a profile's analysis passes NaN for what needs
    /// an area).
    pub(crate) fn assemble(
        heights: &HeightParameters,
        (sdq, sdr_percent): (f64, f64),
        (sal_m, str): (f64, f64),
        functional: &FunctionalParameters,
        correlation_length_m: f64,
    ) -> Self {
        Self {
            sa_m: heights.sa_m,
            sq_m: heights.sq_m,
            ssk: heights.ssk,
            sku: heights.sku,
            sp_m: heights.sp_m,
            sv_m: heights.sv_m,
            sz_m: heights.sz_m,
            sdq,
            sdr_percent,
            sal_m,
            str,
            sk_m: functional.sk_m,
            spk_m: functional.spk_m,
            svk_m: functional.svk_m,
            smr1_percent: functional.smr1_percent,
            smr2_percent: functional.smr2_percent,
            correlation_length_m,
        }
    }
}

/// A map's heights in row-major order (axis 1 contiguous), borrowed when
/// they are already, with the number of measured points; an error if the
/// map has a ±∞ height or fewer than [`MIN_MEASURED`] measured points.
pub(crate) struct Heights<'a> {
    pub values: Cow<'a, [f64]>,
    pub shape: (usize, usize),
    pub measured: usize,
}

pub(crate) fn checked_heights<'a>(
    h: &'a Array2<f64>,
    quantity: &'static str,
) -> Result<Heights<'a>, SurfaceError> {
    let values = match h.as_slice() {
        Some(values) => Cow::Borrowed(values),
        None => Cow::Owned(h.iter().copied().collect()),
    };
    if let Some(v) = values.iter().find(|v| v.is_infinite()) {
        return Err(SurfaceError::Areal {
            quantity,
            message: format!("the map has a height of {v} m; missing points must be NaN"),
        });
    }
    let measured = values.iter().filter(|v| !v.is_nan()).count();
    if measured < MIN_MEASURED {
        return Err(SurfaceError::TooFewPoints {
            quantity,
            found: measured,
            needed: MIN_MEASURED,
            points: values.len(),
        });
    }
    Ok(Heights {
        values,
        shape: h.dim(),
        measured,
    })
}

/// An error unless both spacings are finite and positive.
pub(crate) fn check_spacing(
    dx_m: f64,
    dy_m: f64,
    quantity: &'static str,
) -> Result<(), SurfaceError> {
    for (name, d) in [("dx_m", dx_m), ("dy_m", dy_m)] {
        if !(d.is_finite() && d > 0.0) {
            return Err(SurfaceError::Areal {
                quantity,
                message: format!("the spacing {name} = {d} must be finite and positive"),
            });
        }
    }
    Ok(())
}

/// The mean of the measured (non-NaN) values, in the fixed order of
/// [`hypercontact_numeric::reduce::sums`]. The sum runs over the
/// differences from the first measured value, so a constant map's mean is
/// that value exactly (and a map far from zero loses no digits).
pub(crate) fn measured_mean(values: &[f64]) -> f64 {
    let Some(&origin) = values.iter().find(|v| !v.is_nan()) else {
        return f64::NAN;
    };
    let [n, sum] = hypercontact_numeric::reduce::sums(values.len(), |i| {
        let v = values[i];
        if v.is_nan() {
            [0.0, 0.0]
        } else {
            [1.0, v - origin]
        }
    });
    origin + sum / n
}
