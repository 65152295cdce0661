//! The power law C(q) = A q^(−1−2H) of a self-affine 1-D PSD, as drawn over
//! the measured C(q) in Fig. 4 (convention of the spec: 1-D PSD slope
//! −1 − 2H, as in the SurfaceTopography package).

/// A straight line in log10–log10 axes: log10 C = intercept + slope log10 q.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerLaw {
    pub intercept: f64,
    pub slope: f64,
}

impl PowerLaw {
    /// The Hurst exponent of a 1-D PSD with this slope.
    pub fn hurst(&self) -> f64 {
        (-self.slope - 1.0) / 2.0
    }

    pub fn eval(&self, q: f64) -> f64 {
        10f64.powf(self.intercept + self.slope * q.log10())
    }

    /// Least-squares line through (log q, log C). With `hurst` given (the
    /// upstream's estimate), only the prefactor is fitted, so the line drawn
    /// has exactly the slope the statistics table reports. None when fewer
    /// than two points (one with a known slope) are usable.
    pub fn fit(q: &[f64], c: &[f64], hurst: Option<f64>) -> Option<PowerLaw> {
        let points: Vec<(f64, f64)> = q
            .iter()
            .zip(c)
            .filter(|&(&q, &c)| q > 0.0 && c > 0.0 && q.is_finite() && c.is_finite())
            .map(|(&q, &c)| (q.log10(), c.log10()))
            .collect();
        let n = points.len() as f64;
        let mean_x = points.iter().map(|p| p.0).sum::<f64>() / n;
        let mean_y = points.iter().map(|p| p.1).sum::<f64>() / n;
        match hurst.filter(|h| h.is_finite()) {
            Some(h) if !points.is_empty() => {
                let slope = -1.0 - 2.0 * h;
                Some(PowerLaw {
                    intercept: mean_y - slope * mean_x,
                    slope,
                })
            }
            _ if points.len() >= 2 => {
                let sxx: f64 = points.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
                if sxx == 0.0 {
                    return None;
                }
                let sxy: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
                let slope = sxy / sxx;
                Some(PowerLaw {
                    intercept: mean_y - slope * mean_x,
                    slope,
                })
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact_psd(h: f64) -> (Vec<f64>, Vec<f64>) {
        let q: Vec<f64> = (0..40).map(|i| 1e3 * 1.2f64.powi(i)).collect();
        let c = q.iter().map(|q| 3e-20 * q.powf(-1.0 - 2.0 * h)).collect();
        (q, c)
    }

    #[test]
    fn recovers_the_hurst_exponent_of_an_exact_power_law() {
        let (q, c) = exact_psd(0.75);
        let fit = PowerLaw::fit(&q, &c, None).unwrap();
        assert!((fit.hurst() - 0.75).abs() < 1e-10, "{fit:?}");
        assert!((fit.eval(1e4) / (3e-20 * 1e4f64.powf(-2.5)) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_given_hurst_fixes_the_slope_and_fits_the_prefactor() {
        let (q, c) = exact_psd(0.6);
        let fit = PowerLaw::fit(&q, &c, Some(0.6)).unwrap();
        assert_eq!(fit.slope, -2.2);
        assert!((fit.eval(5e3) / (3e-20 * 5e3f64.powf(-2.2)) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn too_few_points_give_none() {
        assert_eq!(PowerLaw::fit(&[1.0], &[1.0], None), None);
        assert_eq!(PowerLaw::fit(&[], &[], Some(0.5)), None);
        assert_eq!(PowerLaw::fit(&[1.0, 1.0], &[1.0, 2.0], None), None);
    }
}
