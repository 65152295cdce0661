//! The height parameters of ISO 25178-2 §4.1 of the measured points, about
//! their mean z̄ (z = h − z̄):
//!
//! Sa = ⟨|z|⟩, Sq = ⟨z²⟩^½, Ssk = ⟨z³⟩/Sq³, Sku = ⟨z⁴⟩/Sq⁴,
//! Sp = max z, Sv = |min z| = −min z, Sz = Sp + Sv,
//!
//! with ⟨·⟩ the mean over the measured points (the standard's integrals over
//! the definition area, sampled on the grid).

use ndarray::Array2;

use super::{checked_heights, measured_mean};
use crate::SurfaceError;

/// The height parameters of a map, heights in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightParameters {
    /// The mean plane's height z̄ the others are measured from, m.
    pub mean_m: f64,
    pub sa_m: f64,
    pub sq_m: f64,
    /// NaN for a flat map (Sq = 0).
    pub ssk: f64,
    /// NaN for a flat map (Sq = 0).
    pub sku: f64,
    pub sp_m: f64,
    pub sv_m: f64,
    pub sz_m: f64,
    /// The measured points they come from.
    pub measured: usize,
}

/// Sa, Sq, Ssk, Sku, Sp, Sv, Sz of the measured points of `h` (a map the
/// caller has levelled); an error for fewer than four measured points, a
/// ±∞ height, or heights so large that ⟨z⁴⟩ overflows.
pub fn height_parameters(h: &Array2<f64>) -> Result<HeightParameters, SurfaceError> {
    const QUANTITY: &str = "the height parameters (Sa, Sq, Ssk, Sku, Sp, Sv, Sz)";
    let heights = checked_heights(h, QUANTITY)?;
    let values = &heights.values[..];
    let mean_m = measured_mean(values);
    let [abs, square, cube, fourth] = hypercontact_numeric::reduce::sums(values.len(), |i| {
        let z = values[i] - mean_m;
        if z.is_nan() {
            [0.0; 4]
        } else {
            let z2 = z * z;
            [z.abs(), z2, z2 * z, z2 * z2]
        }
    });
    if !fourth.is_finite() {
        return Err(SurfaceError::Areal {
            quantity: QUANTITY,
            message: "the fourth power of the heights overflows f64 (is the map in metres?)".into(),
        });
    }
    let (min, max) = values
        .iter()
        .filter(|v| !v.is_nan())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let n = heights.measured as f64;
    let sq_m = (square / n).sqrt();
    let (ssk, sku) = if sq_m > 0.0 {
        (cube / n / sq_m.powi(3), fourth / n / sq_m.powi(4))
    } else {
        (f64::NAN, f64::NAN)
    };
    let (sp_m, sv_m) = (max - mean_m, mean_m - min);
    Ok(HeightParameters {
        mean_m,
        sa_m: abs / n,
        sq_m,
        ssk,
        sku,
        sp_m,
        sv_m,
        sz_m: sp_m + sv_m,
        measured: heights.measured,
    })
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{PI, SQRT_2, TAU};

    use super::*;

    /// h = A sin(2πx/L) over whole periods: Sq = A/√2, Sa = 2A/π, Ssk = 0,
    /// Sku = 3/2, Sp = Sv = A (the sampled extremes of 64 points per period).
    #[test]
    fn a_sinusoid_has_its_analytic_moments() {
        let (amplitude, period) = (2e-6, 64);
        let h = Array2::from_shape_fn((4 * period, 9), |(i, _)| {
            amplitude * (TAU * i as f64 / period as f64).sin() + 5e-6
        });
        let p = height_parameters(&h).unwrap();
        assert!((p.mean_m - 5e-6).abs() < 1e-18);
        assert!((p.sq_m / (amplitude / SQRT_2) - 1.0).abs() < 1e-12, "{p:?}");
        // The mean of |sin(2πi/N)| over N samples of a period is
        // 2·cot(π/N)/N (Σ of sines over half a period), → 2/π for large N.
        let n = period as f64;
        let sampled = 2.0 / (PI / n).tan() / n;
        assert!(
            (p.sa_m / (amplitude * sampled) - 1.0).abs() < 1e-12,
            "{p:?}"
        );
        assert!(
            (p.sa_m / (2.0 * amplitude / PI) - 1.0).abs() < 1e-3,
            "{p:?}"
        );
        assert!(p.ssk.abs() < 1e-9 && (p.sku - 1.5).abs() < 1e-12, "{p:?}");
        assert!((p.sp_m - amplitude).abs() < 1e-18 && (p.sv_m - amplitude).abs() < 1e-18);
        assert!((p.sz_m - 2.0 * amplitude).abs() < 1e-18);
    }

    /// Heights −1 (three times) and +3 (once): mean 0, Sa = 1.5, Sq = √3,
    /// Ssk = (3·(−1) + 27)/4 / 3^{3/2} = 2/√3, Sku = (3 + 81)/4 / 9 = 7/3;
    /// the NaN points are left out.
    #[test]
    fn a_two_level_map_with_gaps() {
        let mut h = Array2::from_elem((3, 3), f64::NAN);
        h[[0, 0]] = -1.0;
        h[[1, 2]] = -1.0;
        h[[2, 1]] = -1.0;
        h[[2, 2]] = 3.0;
        let p = height_parameters(&h).unwrap();
        assert_eq!(p.measured, 4);
        assert!(p.mean_m.abs() < 1e-15 && (p.sa_m - 1.5).abs() < 1e-15);
        assert!((p.sq_m - 3f64.sqrt()).abs() < 1e-15);
        assert!((p.ssk - 2.0 / 3f64.sqrt()).abs() < 1e-14);
        assert!((p.sku - 7.0 / 3.0).abs() < 1e-14);
        assert_eq!((p.sp_m, p.sv_m, p.sz_m), (3.0, 1.0, 4.0));
    }

    #[test]
    fn a_flat_map_has_no_skewness_and_bad_maps_are_refused() {
        let p = height_parameters(&Array2::from_elem((3, 3), 2.0)).unwrap();
        assert_eq!((p.sa_m, p.sq_m, p.sz_m), (0.0, 0.0, 0.0));
        assert!(p.ssk.is_nan() && p.sku.is_nan());
        let mut h = Array2::from_elem((3, 3), f64::NAN);
        h[[0, 0]] = 1.0;
        let e = height_parameters(&h).unwrap_err().to_string();
        assert!(
            e.contains("at least 4 measured points, the map has 1 of 9"),
            "{e}"
        );
        assert!(height_parameters(&Array2::zeros((0, 3))).is_err());
        h.fill(1.0);
        h[[1, 1]] = f64::INFINITY;
        let e = height_parameters(&h).unwrap_err().to_string();
        assert!(e.contains("height of inf m"), "{e}");
        h[[1, 1]] = 1e300;
        assert!(height_parameters(&h).is_err());
    }
}
