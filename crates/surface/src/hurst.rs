//! Hurst exponent from the power-law slope of a PSD: C ∝ q^(−1−2H) for 1-D
//! PSDs and C ∝ q^(−2−2H) for the radial 2-D PSD (Persson et al., J. Phys.:
//! Condens. Matter 17, R1, 2005), fitted by least squares in log–log over the
//! bins whose q lies in a given range.

use crate::psd::Spectrum;

/// Which PSD the slope comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// 1-D profile PSD: slope = −1 − 2H.
    Profile,
    /// Radial 2-D PSD: slope = −2 − 2H.
    Areal,
}

/// A power-law fit C = prefactor · q^slope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerLaw {
    pub slope: f64,
    pub prefactor: f64,
    /// Number of PSD points used.
    pub points: usize,
}

impl PowerLaw {
    pub fn hurst(&self, dimension: Dimension) -> f64 {
        match dimension {
            Dimension::Profile => (-self.slope - 1.0) / 2.0,
            Dimension::Areal => (-self.slope - 2.0) / 2.0,
        }
    }
}

/// Least-squares line through (ln q, ln C) for q_min ≤ q ≤ q_max and C > 0;
/// None with fewer than three such points.
pub fn fit_power_law(spectrum: &Spectrum, q_min: f64, q_max: f64) -> Option<PowerLaw> {
    let points: Vec<(f64, f64)> = spectrum
        .q_per_m
        .iter()
        .zip(&spectrum.c)
        .filter(|&(&q, &c)| q >= q_min && q <= q_max && c > 0.0 && c.is_finite())
        .map(|(q, c)| (q.ln(), c.ln()))
        .collect();
    if points.len() < 3 {
        return None;
    }
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    Some(PowerLaw {
        slope,
        prefactor: (my - slope * mx).exp(),
        points: points.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_power_laws_give_their_exponent() {
        let q: Vec<f64> = (1..50).map(|k| 1e3 * 1.2f64.powi(k)).collect();
        let profile = Spectrum {
            c: q.iter().map(|q| 2e-20 * q.powf(-1.0 - 2.0 * 0.7)).collect(),
            q_per_m: q.clone(),
        };
        let fit = fit_power_law(&profile, 0.0, f64::INFINITY).unwrap();
        assert!((fit.hurst(Dimension::Profile) - 0.7).abs() < 1e-12);
        assert!((fit.prefactor / 2e-20 - 1.0).abs() < 1e-9);
        let areal = Spectrum {
            c: q.iter().map(|q| q.powf(-2.0 - 2.0 * 0.35)).collect(),
            q_per_m: q,
        };
        let fit = fit_power_law(&areal, 2e3, 1e5).unwrap();
        assert!((fit.hurst(Dimension::Areal) - 0.35).abs() < 1e-12);
        assert!(fit.points < 49);
    }

    #[test]
    fn too_few_points_is_none() {
        let s = Spectrum {
            q_per_m: vec![1.0, 2.0, 3.0],
            c: vec![1.0, 0.5, 0.2],
        };
        assert!(fit_power_law(&s, 1.5, 10.0).is_none());
    }
}
