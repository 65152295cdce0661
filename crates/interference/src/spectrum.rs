//! The illumination's spectrum, as the camera sees it (source × optics ×
//! sensor response; a monochrome sCMOS's quantum efficiency is flat to
//! ~±15 % over 450–650 nm and is left out of the built-in spectrum).
//!
//! The built-in white LED is a phosphor-converted one: a blue InGaN
//! emission line plus the broad yellow band of the Ce:YAG phosphor it pumps,
//! written as a sum of Gaussians on 380–780 nm (see [`Spectrum::white_led`]).
//! A measured spectrum is given as (λ, S) samples.

use crate::error::InterferenceError;

/// One Gaussian band of a model spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussianLine {
    pub centre_nm: f64,
    /// full width at half maximum
    pub fwhm_nm: f64,
    /// height at the centre (relative units)
    pub peak: f64,
}

impl GaussianLine {
    pub fn power(&self, wavelength_nm: f64) -> f64 {
        // FWHM = 2 √(2 ln 2) σ
        let sigma = self.fwhm_nm / (2.0 * (2.0 * std::f64::consts::LN_2).sqrt());
        let z = (wavelength_nm - self.centre_nm) / sigma;
        self.peak * (-0.5 * z * z).exp()
    }
}

/// The relative spectral power S(λ) of the light that forms the image.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// A sum of Gaussian bands, cut to `[min_nm, max_nm]`.
    Gaussians {
        lines: Vec<GaussianLine>,
        min_nm: f64,
        max_nm: f64,
    },
    /// Measured samples: wavelengths strictly increasing, powers ≥ 0;
    /// linear between samples, zero outside them.
    Sampled {
        wavelength_nm: Vec<f64>,
        relative_power: Vec<f64>,
    },
}

impl Default for Spectrum {
    fn default() -> Self {
        Self::white_led()
    }
}

impl Spectrum {
    /// A cool-white phosphor-converted LED on 380–780 nm, three Gaussians:
    /// - the blue pump: 450 nm, 20 nm FWHM, peak 1;
    /// - the phosphor band, skewed to the red as Ce:YAG's is, as two
    ///   Gaussians: 550 nm, 80 nm FWHM, peak 0.45, and 615 nm, 80 nm FWHM,
    ///   peak 0.25; together they peak at 558 nm, 0.50, about 150 nm wide.
    ///
    /// The blue line carries 26 % of the power. Round numbers in the range of
    /// LED data sheets (pump 445–455 nm, 18–25 nm wide; phosphor maximum
    /// 550–570 nm), not one product. The red tail is kept short, below 2e-6
    /// of the peak at 780 nm (real LEDs keep ~1 % there), so the band's ends
    /// create no slow edge fringes (see [`crate::film::SpectralAverage`]).
    pub fn white_led() -> Self {
        Self::Gaussians {
            lines: vec![
                GaussianLine {
                    centre_nm: 450.0,
                    fwhm_nm: 20.0,
                    peak: 1.0,
                },
                GaussianLine {
                    centre_nm: 550.0,
                    fwhm_nm: 80.0,
                    peak: 0.45,
                },
                GaussianLine {
                    centre_nm: 615.0,
                    fwhm_nm: 80.0,
                    peak: 0.25,
                },
            ],
            min_nm: 380.0,
            max_nm: 780.0,
        }
    }

    /// The band the spectrum is defined on, nm.
    pub fn band_nm(&self) -> (f64, f64) {
        match self {
            Self::Gaussians { min_nm, max_nm, .. } => (*min_nm, *max_nm),
            Self::Sampled { wavelength_nm, .. } => (
                wavelength_nm.first().copied().unwrap_or(f64::NAN),
                wavelength_nm.last().copied().unwrap_or(f64::NAN),
            ),
        }
    }

    /// S(λ); 0 outside the band (and for samples [`Spectrum::check`] refuses).
    pub fn power(&self, wavelength_nm: f64) -> f64 {
        let (min_nm, max_nm) = self.band_nm();
        if !(wavelength_nm >= min_nm && wavelength_nm <= max_nm) {
            return 0.0;
        }
        match self {
            Self::Gaussians { lines, .. } => lines.iter().map(|l| l.power(wavelength_nm)).sum(),
            Self::Sampled {
                wavelength_nm: x,
                relative_power: y,
            } => {
                if x.len() != y.len() {
                    return 0.0;
                }
                // the first sample at or above λ
                let k = x.partition_point(|&xk| xk < wavelength_nm).min(x.len() - 1);
                if k == 0 {
                    return y[0];
                }
                let t = (wavelength_nm - x[k - 1]) / (x[k] - x[k - 1]);
                y[k - 1] + t * (y[k] - y[k - 1])
            }
        }
    }

    /// A band inside (0, 100 µm), finite non-negative powers, some power.
    pub fn check(&self) -> Result<(), InterferenceError> {
        let band_ok = |min_nm: f64, max_nm: f64| min_nm > 0.0 && max_nm > min_nm && max_nm < 1e5;
        match self {
            Self::Gaussians {
                lines,
                min_nm,
                max_nm,
            } => {
                if !band_ok(*min_nm, *max_nm) {
                    return Err(InterferenceError::param(
                        "spectrum.min_nm/max_nm",
                        format!("{min_nm}/{max_nm}"),
                        "the band must satisfy 0 < min_nm < max_nm < 1e5",
                    ));
                }
                if lines.is_empty() {
                    return Err(InterferenceError::Empty {
                        what: "spectrum.lines",
                        detail: "no Gaussian band".into(),
                    });
                }
                for line in lines {
                    let ok = line.centre_nm.is_finite()
                        && line.centre_nm > 0.0
                        && line.fwhm_nm.is_finite()
                        && line.fwhm_nm > 0.0
                        && line.peak.is_finite()
                        && line.peak >= 0.0;
                    if !ok {
                        return Err(InterferenceError::param(
                            "spectrum.lines",
                            format!("{line:?}"),
                            "a band needs a positive centre and width and a finite peak ≥ 0",
                        ));
                    }
                }
                if lines.iter().all(|l| l.peak == 0.0) {
                    return Err(InterferenceError::param(
                        "spectrum.lines",
                        "all peaks 0",
                        "the spectrum carries no power",
                    ));
                }
            }
            Self::Sampled {
                wavelength_nm,
                relative_power,
            } => {
                if wavelength_nm.len() < 2 {
                    return Err(InterferenceError::Empty {
                        what: "spectrum.wavelength_nm",
                        detail: format!("{} samples, at least 2 needed", wavelength_nm.len()),
                    });
                }
                if relative_power.len() != wavelength_nm.len() {
                    return Err(InterferenceError::Length {
                        what: "spectrum.relative_power",
                        expected: wavelength_nm.len(),
                        got: relative_power.len(),
                    });
                }
                for (index, &w) in wavelength_nm.iter().enumerate() {
                    let increasing = index == 0 || w > wavelength_nm[index - 1];
                    if !(w.is_finite() && w > 0.0 && w < 1e5 && increasing) {
                        return Err(InterferenceError::Value {
                            what: "spectrum.wavelength_nm",
                            index,
                            value: w,
                            message: "wavelengths must be in (0, 1e5) nm and strictly increasing",
                        });
                    }
                }
                for (index, &p) in relative_power.iter().enumerate() {
                    if !(p.is_finite() && p >= 0.0) {
                        return Err(InterferenceError::Value {
                            what: "spectrum.relative_power",
                            index,
                            value: p,
                            message: "a spectral power must be finite and at least 0",
                        });
                    }
                }
                if relative_power.iter().all(|&p| p == 0.0) {
                    return Err(InterferenceError::param(
                        "spectrum.relative_power",
                        "all 0",
                        "the spectrum carries no power",
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_led_shape() {
        let s = Spectrum::white_led();
        s.check().unwrap();
        let line = |centre_nm, fwhm_nm, peak| GaussianLine {
            centre_nm,
            fwhm_nm,
            peak,
        };
        let lines = [
            line(450.0, 20.0, 1.0),
            line(550.0, 80.0, 0.45),
            line(615.0, 80.0, 0.25),
        ];
        for w in [380.0, 450.0, 500.0, 555.5, 700.0, 780.0] {
            let sum: f64 = lines.iter().map(|l| l.power(w)).sum();
            assert!((s.power(w) - sum).abs() < 1e-15, "{w}");
        }
        // half maximum 10 nm from the blue line's centre
        assert!((lines[0].power(460.0) - 0.5).abs() < 1e-12);
        // the phosphor band's maximum lies in 550–570 nm
        let (mut best_nm, mut best) = (0.0, 0.0);
        for k in 0..3000 {
            let w = 480.0 + 0.1 * k as f64;
            if s.power(w) > best {
                (best_nm, best) = (w, s.power(w));
            }
        }
        assert!((550.0..=570.0).contains(&best_nm), "{best_nm}");
        // a dip between the blue line and the phosphor
        assert!(s.power(485.0) < 0.5 * best);
        // negligible at the band's ends (no edge ringing), zero outside
        assert!(s.power(380.0) < 2e-6 && s.power(780.0) < 2e-6);
        assert_eq!(s.power(379.0), 0.0);
        assert_eq!(s.power(781.0), 0.0);
    }

    #[test]
    fn sampled_spectrum_is_piecewise_linear() {
        let s = Spectrum::Sampled {
            wavelength_nm: vec![400.0, 500.0, 600.0],
            relative_power: vec![0.0, 2.0, 1.0],
        };
        s.check().unwrap();
        assert_eq!(s.band_nm(), (400.0, 600.0));
        for (w, p) in [
            (400.0, 0.0),
            (450.0, 1.0),
            (500.0, 2.0),
            (575.0, 1.25),
            (600.0, 1.0),
        ] {
            assert!((s.power(w) - p).abs() < 1e-12, "{w}");
        }
        assert_eq!(s.power(399.0), 0.0);
        assert_eq!(s.power(f64::NAN), 0.0);
        let unchecked = Spectrum::Sampled {
            wavelength_nm: vec![500.0],
            relative_power: vec![],
        };
        assert_eq!(unchecked.power(500.0), 0.0);
    }

    #[test]
    fn bad_spectra_are_refused() {
        let sampled = |w: Vec<f64>, p: Vec<f64>| Spectrum::Sampled {
            wavelength_nm: w,
            relative_power: p,
        };
        let bad = [
            sampled(vec![500.0], vec![1.0]),
            sampled(vec![500.0, 600.0], vec![1.0]),
            sampled(vec![500.0, 500.0], vec![1.0, 1.0]),
            sampled(vec![500.0, f64::NAN], vec![1.0, 1.0]),
            sampled(vec![500.0, 600.0], vec![1.0, -1.0]),
            sampled(vec![500.0, 600.0], vec![0.0, 0.0]),
            Spectrum::Gaussians {
                lines: vec![],
                min_nm: 380.0,
                max_nm: 780.0,
            },
            Spectrum::Gaussians {
                lines: vec![GaussianLine {
                    centre_nm: 500.0,
                    fwhm_nm: 0.0,
                    peak: 1.0,
                }],
                min_nm: 380.0,
                max_nm: 780.0,
            },
            Spectrum::Gaussians {
                lines: vec![GaussianLine {
                    centre_nm: 500.0,
                    fwhm_nm: 10.0,
                    peak: 1.0,
                }],
                min_nm: 780.0,
                max_nm: 380.0,
            },
        ];
        for s in bad {
            assert!(s.check().is_err(), "{s:?}");
        }
    }
}
