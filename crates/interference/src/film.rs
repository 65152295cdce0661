//! Reflectance of the glass – gap – rubber stack at normal incidence, the
//! paper's Fig. 3 rig (SPEC, "Interference images").
//!
//! Light comes through the glass; the gap (air, thickness g) is a thin film
//! between two half-spaces. Summing the multiply reflected waves (Airy):
//!
//! R(g, λ) = |(r1 + r2 e^{iδ}) / (1 + r1 r2 e^{iδ})|²,  δ = 4π n_gap g / λ,
//!
//! with the Fresnel amplitude coefficients r1 = (n_glass − n_gap)/(n_glass + n_gap)
//! (glass → gap) and r2 = (n_gap − n_rubber)/(n_gap + n_rubber) (gap → rubber,
//! negative: the half-wave loss). Expanding the moduli,
//!
//! R = (r1² + r2² + 2 r1 r2 cos δ) / (1 + r1² r2² + 2 r1 r2 cos δ),
//!
//! which is what is evaluated (the sign convention of r is the one of Born &
//! Wolf, *Principles of Optics*, §1.6 and §7.6.1). At g = 0 the film
//! vanishes and R is the glass–rubber interface's ((n_glass − n_rubber) /
//! (n_glass + n_rubber))²; averaged over δ it is the incoherent sum
//! (r1² + r2² − 2 r1² r2²) / (1 − r1² r2²). The spectral average over a
//! source is in [`SpectralAverage`].

use crate::error::{InterferenceError, positive};
use crate::spectrum::Spectrum;

/// Width of the taper that brings S to zero at the band's ends, nm.
pub const EDGE_TAPER_NM: f64 = 20.0;
/// Harmonics of R(δ) smaller than this may alias on the wavelength grid.
pub const ALIAS_FLOOR: f64 = 1e-9;
/// The coarsest wavelength grid [`SpectralAverage::resolving`] picks, nm.
pub const MAX_STEP_NM: f64 = 0.5;

/// Refractive indices of the stack (dispersion neglected: quartz varies by
/// ~1 % over the visible band).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Indices {
    /// the window, fused quartz
    pub n_glass: f64,
    /// the gap, air
    pub n_gap: f64,
    /// the rubber sample
    pub n_rubber: f64,
}

impl Default for Indices {
    fn default() -> Self {
        Self {
            n_glass: 1.458,
            n_gap: 1.0,
            n_rubber: 1.50,
        }
    }
}

impl Indices {
    /// Every index finite and at least 1 (no medium here is optically thinner
    /// than vacuum).
    pub fn check(&self) -> Result<(), InterferenceError> {
        for (param, n) in [
            ("n_glass", self.n_glass),
            ("n_gap", self.n_gap),
            ("n_rubber", self.n_rubber),
        ] {
            if !(n.is_finite() && n >= 1.0) {
                return Err(InterferenceError::param(
                    param,
                    n,
                    "a refractive index must be finite and at least 1",
                ));
            }
        }
        Ok(())
    }
}

/// The stack with its Fresnel coefficients, from checked [`Indices`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stack {
    indices: Indices,
    /// glass → gap amplitude coefficient r1
    r1: f64,
    /// gap → rubber amplitude coefficient r2
    r2: f64,
}

impl Stack {
    pub fn new(indices: Indices) -> Result<Self, InterferenceError> {
        indices.check()?;
        let Indices {
            n_glass,
            n_gap,
            n_rubber,
        } = indices;
        Ok(Self {
            indices,
            r1: (n_glass - n_gap) / (n_glass + n_gap),
            r2: (n_gap - n_rubber) / (n_gap + n_rubber),
        })
    }

    pub fn indices(&self) -> Indices {
        self.indices
    }

    /// r1, the glass → gap amplitude reflection coefficient.
    pub fn r_glass_gap(&self) -> f64 {
        self.r1
    }

    /// r2, the gap → rubber amplitude reflection coefficient (negative when
    /// the rubber is optically denser than the gap).
    pub fn r_gap_rubber(&self) -> f64 {
        self.r2
    }

    /// R at g = 0: the glass–rubber interface alone.
    pub fn contact_reflectance(&self) -> f64 {
        let Indices {
            n_glass, n_rubber, ..
        } = self.indices;
        let r = (n_glass - n_rubber) / (n_glass + n_rubber);
        r * r
    }

    /// The mean of R over the phase δ: the two interfaces' intensities added
    /// with all their multiple reflections, no interference.
    pub fn incoherent_reflectance(&self) -> f64 {
        let (p1, p2) = (self.r1 * self.r1, self.r2 * self.r2);
        (p1 + p2 - 2.0 * p1 * p2) / (1.0 - p1 * p2)
    }

    /// a_m of the Fourier series R(δ) = R_inc + Σ_{m≥1} a_m cos(m δ):
    /// a_m = −2 (1 − r1²)(1 − r2²) / (1 − q²) · (−q)^m with q = r1 r2 (from
    /// R = 1 − (1 − r1²)(1 − r2²) / |1 + q e^{iδ}|² and the Poisson-kernel
    /// series of 1 / |1 + q e^{iδ}|²). Harmonic m of the spectral average is
    /// the source's coherence at m times the gap, so these say how many
    /// harmonics a wavelength grid must resolve.
    pub fn harmonic(&self, m: u32) -> f64 {
        let (p1, p2, q) = (self.r1 * self.r1, self.r2 * self.r2, self.r1 * self.r2);
        let m = m.min(i32::MAX as u32) as i32;
        -2.0 * (1.0 - p1) * (1.0 - p2) / (1.0 - q * q) * (-q).powi(m)
    }

    /// R as a function of cos δ: (a + b cos δ) / (c + b cos δ).
    #[inline]
    pub(crate) fn airy_coefficients(&self) -> AiryCoefficients {
        let (r1, r2) = (self.r1, self.r2);
        AiryCoefficients {
            a: r1 * r1 + r2 * r2,
            b: 2.0 * r1 * r2,
            c: 1.0 + r1 * r1 * r2 * r2,
        }
    }

    /// Monochromatic reflectance at a gap of `gap_m` for the vacuum
    /// wavelength `wavelength_m`. NaN in, NaN out; a negative gap is taken as
    /// a film of that (unphysical) thickness, the formula being even in g.
    pub fn reflectance(&self, gap_m: f64, wavelength_m: f64) -> f64 {
        let delta = 4.0 * std::f64::consts::PI * self.indices.n_gap * gap_m / wavelength_m;
        self.airy_coefficients().at(delta.cos())
    }
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct AiryCoefficients {
    a: f64,
    b: f64,
    c: f64,
}

impl AiryCoefficients {
    #[inline(always)]
    pub(crate) fn at(&self, cos_delta: f64) -> f64 {
        (self.a + self.b * cos_delta) / (self.c + self.b * cos_delta)
    }
}

/// The stack under a broadband source: R̄(g) = ∫ S(λ) R(g, λ) dλ / ∫ S(λ) dλ,
/// by the trapezoidal rule on an even wavelength grid over the spectrum's
/// band.
///
/// S is tapered to zero over the outer [`EDGE_TAPER_NM`] of the band (a
/// raised cosine; a tenth of the band if that is narrower). A spectrum cut
/// where it is not yet zero rings as a fringe that decays only like 1/g (a
/// Gaussian band cut at 1e-3 of its peak still swings by ~1e-6 at 10 µm);
/// the taper turns that into 1/g³, and the built-in spectrum is below 2e-6
/// of its peak at both ends anyway. With S and S' zero at the ends the
/// rule's error is O(h⁴) (Euler–Maclaurin) as long as the grid resolves the
/// phase: harmonic m of R(δ) (see [`Stack::harmonic`]) turns by
/// m · 4π n g h / λ² per step, and a harmonic sampled near 2π per step
/// aliases to a slow fringe that never washes out
/// ([`SpectralAverage::resolving`] picks h accordingly).
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralAverage {
    stack: Stack,
    /// quadrature nodes, m
    wavelength_m: Vec<f64>,
    /// S(λ) × trapezoid weight, normalised to sum 1
    weight: Vec<f64>,
}

impl SpectralAverage {
    /// `step_nm`: the wavelength grid's step (see the tests for how far
    /// 0.5 nm is converged).
    pub fn new(stack: Stack, spectrum: &Spectrum, step_nm: f64) -> Result<Self, InterferenceError> {
        spectrum.check()?;
        positive("step_nm", step_nm)?;
        let (min_nm, max_nm) = spectrum.band_nm();
        let intervals = ((max_nm - min_nm) / step_nm).ceil();
        if intervals > 1e6 {
            return Err(InterferenceError::param(
                "step_nm",
                step_nm,
                format!(
                    "gives {intervals} wavelength steps over {min_nm}–{max_nm} nm (at most 1e6)"
                ),
            ));
        }
        let intervals = (intervals as usize).max(1);
        let h_nm = (max_nm - min_nm) / intervals as f64;
        let taper_nm = EDGE_TAPER_NM.min(0.1 * (max_nm - min_nm));
        let taper = |lambda_nm: f64| {
            let edge = (lambda_nm - min_nm).min(max_nm - lambda_nm) / taper_nm;
            if edge >= 1.0 {
                1.0
            } else if edge <= 0.0 {
                0.0
            } else {
                0.5 * (1.0 - (std::f64::consts::PI * edge).cos())
            }
        };
        let mut wavelength_m = Vec::with_capacity(intervals + 1);
        let mut weight = Vec::with_capacity(intervals + 1);
        for k in 0..=intervals {
            let lambda_nm = min_nm + h_nm * k as f64;
            let end = if k == 0 || k == intervals { 0.5 } else { 1.0 };
            wavelength_m.push(lambda_nm * 1e-9);
            weight.push(end * taper(lambda_nm) * spectrum.power(lambda_nm));
        }
        let total: f64 = weight.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return Err(InterferenceError::param(
                "spectrum",
                total,
                "carries no power on the wavelength grid",
            ));
        }
        weight.iter_mut().for_each(|w| *w /= total);
        Ok(Self {
            stack,
            wavelength_m,
            weight,
        })
    }

    /// The grid that resolves every harmonic of R(δ) above
    /// [`ALIAS_FLOOR`] up to gaps of `max_gap_m`: harmonic m at gap g turns
    /// by m · 4π n g h / λ² per step h, which must stay within π (Nyquist)
    /// at the band's shortest wavelength; at most 0.5 nm.
    pub fn resolving(
        stack: Stack,
        spectrum: &Spectrum,
        max_gap_m: f64,
    ) -> Result<Self, InterferenceError> {
        spectrum.check()?;
        positive("max_gap_m", max_gap_m)?;
        let harmonics = (1..=64u32)
            .take_while(|&m| stack.harmonic(m).abs() >= ALIAS_FLOOR)
            .last()
            .unwrap_or(1) as f64;
        let lambda_min_nm = spectrum.band_nm().0;
        let step_nm = lambda_min_nm * lambda_min_nm
            / (4.0 * stack.indices.n_gap * harmonics * max_gap_m * 1e9);
        Self::new(stack, spectrum, step_nm.min(MAX_STEP_NM))
    }

    /// The wavelength grid's step, nm.
    pub fn step_nm(&self) -> f64 {
        match self.wavelength_m.as_slice() {
            [first, second, ..] => (second - first) * 1e9,
            _ => 0.0,
        }
    }

    pub fn stack(&self) -> &Stack {
        &self.stack
    }

    /// The quadrature: nodes (m) and normalised weights.
    pub fn nodes(&self) -> (&[f64], &[f64]) {
        (&self.wavelength_m, &self.weight)
    }

    /// R̄(g), the direct sum over the wavelength grid.
    pub fn reflectance(&self, gap_m: f64) -> f64 {
        let airy = self.stack.airy_coefficients();
        let phase_per_inverse_m = 4.0 * std::f64::consts::PI * self.stack.indices.n_gap * gap_m;
        self.wavelength_m
            .iter()
            .zip(&self.weight)
            .map(|(&lambda, &w)| w * airy.at((phase_per_inverse_m / lambda).cos()))
            .sum()
    }

    /// R̄ at the gaps `first_gap_m + k · step_m`, k = 0 … out.len() − 1, into
    /// `out`: the phases advance by a rotation per step instead of a cosine
    /// per point (the rounding drift over a block of 4096 steps is ~1e-13).
    pub(crate) fn reflectance_run(&self, first_gap_m: f64, step_m: f64, out: &mut [f64]) {
        let airy = self.stack.airy_coefficients();
        let scale = 4.0 * std::f64::consts::PI * self.stack.indices.n_gap;
        out.iter_mut().for_each(|v| *v = 0.0);
        for (&lambda, &w) in self.wavelength_m.iter().zip(&self.weight) {
            let (mut sin, mut cos) = (scale * first_gap_m / lambda).sin_cos();
            let (sin_step, cos_step) = (scale * step_m / lambda).sin_cos();
            for v in out.iter_mut() {
                *v += w * airy.at(cos);
                (sin, cos) = (
                    sin * cos_step + cos * sin_step,
                    cos * cos_step - sin * sin_step,
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Complex numbers, enough to evaluate the Airy sum as written.
    #[derive(Clone, Copy)]
    struct C(f64, f64);
    impl C {
        fn add(self, o: C) -> C {
            C(self.0 + o.0, self.1 + o.1)
        }
        fn mul(self, o: C) -> C {
            C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
        }
        fn norm2(self) -> f64 {
            self.0 * self.0 + self.1 * self.1
        }
    }

    fn stack() -> Stack {
        Stack::new(Indices::default()).unwrap()
    }

    #[test]
    fn closed_form_equals_the_complex_airy_sum() {
        let s = stack();
        let (r1, r2) = (s.r_glass_gap(), s.r_gap_rubber());
        for k in 0..500 {
            let g = k as f64 * 3.7e-9;
            let lambda = 400e-9 + (k % 37) as f64 * 10e-9;
            let delta = 4.0 * std::f64::consts::PI * g / lambda;
            let e = C(delta.cos(), delta.sin());
            let num = C(r1, 0.0).add(C(r2, 0.0).mul(e)).norm2();
            let den = C(1.0, 0.0).add(C(r1 * r2, 0.0).mul(e)).norm2();
            assert!((s.reflectance(g, lambda) - num / den).abs() < 1e-15);
        }
    }

    #[test]
    fn contact_is_the_glass_rubber_interface() {
        let s = stack();
        let expected = ((1.458f64 - 1.50) / (1.458 + 1.50)).powi(2);
        assert!((expected - 2.0161e-4).abs() < 1e-8, "{expected}");
        assert!((s.contact_reflectance() - expected).abs() < 1e-18);
        for lambda in [380e-9, 450e-9, 633e-9, 780e-9] {
            assert!((s.reflectance(0.0, lambda) - expected).abs() < 1e-16);
        }
        // the half-wave loss: r2 < 0
        assert!(s.r_gap_rubber() < 0.0 && s.r_glass_gap() > 0.0);
    }

    #[test]
    fn monochromatic_minima_and_maxima_sit_at_the_fringe_orders() {
        for n_gap in [1.0, 1.33] {
            let s = Stack::new(Indices {
                n_gap,
                ..Indices::default()
            })
            .unwrap();
            let lambda = 546.1e-9;
            let period = lambda / (2.0 * n_gap);
            // brute-force search for the minima on a fine grid
            let dg = 0.01e-9;
            let values: Vec<f64> = (0..=(3.2 * period / dg) as usize)
                .map(|k| s.reflectance(k as f64 * dg, lambda))
                .collect();
            let minima: Vec<f64> = (1..values.len() - 1)
                .filter(|&k| values[k] < values[k - 1] && values[k] <= values[k + 1])
                .map(|k| k as f64 * dg)
                .collect();
            assert_eq!(minima.len(), 3, "{minima:?}");
            for (m, g) in minima.iter().enumerate() {
                assert!(
                    (g - (m + 1) as f64 * period).abs() <= dg,
                    "{g} vs {}",
                    (m + 1) as f64 * period
                );
                assert!((s.reflectance(*g, lambda) - s.contact_reflectance()).abs() < 1e-9);
            }
            // maxima half-way, at (m + ½) λ / 2n, with R = ((r1 − r2)/(1 − r1 r2))²
            let (r1, r2) = (s.r_glass_gap(), s.r_gap_rubber());
            let r_max = ((r1 - r2) / (1.0 - r1 * r2)).powi(2);
            for m in 0..3 {
                let g = (m as f64 + 0.5) * period;
                assert!((s.reflectance(g, lambda) - r_max).abs() < 1e-14);
                assert!(s.reflectance(g + 2e-9, lambda) < r_max);
                assert!(s.reflectance(g - 2e-9, lambda) < r_max);
            }
        }
    }

    #[test]
    fn phase_average_is_the_incoherent_sum() {
        let s = stack();
        let (r1, r2) = (s.r_glass_gap(), s.r_gap_rubber());
        let formula = (r1 * r1 + r2 * r2 - 2.0 * r1 * r1 * r2 * r2) / (1.0 - r1 * r1 * r2 * r2);
        assert!((s.incoherent_reflectance() - formula).abs() < 1e-16);
        // the trapezoidal rule is exact to rounding for a periodic analytic integrand
        let n = 1000;
        let lambda = 500e-9;
        let mean: f64 = (0..n)
            .map(|k| s.reflectance(k as f64 / n as f64 * lambda / 2.0, lambda))
            .sum::<f64>()
            / n as f64;
        assert!((mean - formula).abs() < 1e-14, "{mean} vs {formula}");
        assert!((formula - 0.07204).abs() < 1e-5, "{formula}");
    }

    #[test]
    fn harmonics_are_the_fourier_coefficients_of_r() {
        for indices in [
            Indices::default(),
            Indices {
                n_glass: 1.9,
                n_gap: 1.33,
                n_rubber: 2.4,
            },
        ] {
            let s = Stack::new(indices).unwrap();
            let n = 2048;
            let lambda = 500e-9;
            let period = lambda / (2.0 * indices.n_gap);
            for m in 0..6u32 {
                // the trapezoidal rule over one period is exact to rounding here
                let coefficient = (0..n)
                    .map(|k| {
                        let t = k as f64 / n as f64;
                        s.reflectance(t * period, lambda)
                            * (2.0 * std::f64::consts::PI * m as f64 * t).cos()
                    })
                    .sum::<f64>()
                    * if m == 0 { 1.0 } else { 2.0 }
                    / n as f64;
                let expected = if m == 0 {
                    s.incoherent_reflectance()
                } else {
                    s.harmonic(m)
                };
                assert!(
                    (coefficient - expected).abs() < 1e-15,
                    "m = {m}: {coefficient} vs {expected}"
                );
            }
        }
        // the default stack: a1 ≈ −0.069, then a factor |r1 r2| ≈ 0.037 per order
        let s = stack();
        assert!((s.harmonic(1) + 0.0692).abs() < 1e-4, "{}", s.harmonic(1));
        assert!((s.harmonic(2) / s.harmonic(1) + s.r_glass_gap() * s.r_gap_rubber()).abs() < 1e-15);
    }

    /// The SPEC's white-light facts, from the built-in LED spectrum.
    /// Measured: R̄ reaches half the background (R_inc) at 42.4 nm and half
    /// the first bright fringe (1.86 R_inc at 131 nm) at 62.1 nm; the second
    /// dark fringe sits at 263.3 nm at 0.31 of the background.
    #[test]
    fn white_light_fringes() {
        let s = stack();
        let avg = SpectralAverage::new(s, &Spectrum::white_led(), 0.25).unwrap();
        let (r0, background) = (s.contact_reflectance(), s.incoherent_reflectance());
        let dg = 0.05e-9;
        let values: Vec<f64> = (0..=8000).map(|k| avg.reflectance(k as f64 * dg)).collect();
        let first_above = |level: f64| values.iter().position(|&v| v >= level).unwrap() as f64 * dg;
        let first_max = (1..values.len() - 1)
            .find(|&k| values[k] > values[k - 1] && values[k] >= values[k + 1])
            .unwrap();
        let second_min = (first_max..values.len() - 1)
            .find(|&k| values[k] < values[k - 1] && values[k] <= values[k + 1])
            .unwrap();
        let (g_max, r_max) = (first_max as f64 * dg, values[first_max]);
        let (g_dark, r_dark) = (second_min as f64 * dg, values[second_min]);
        let half_background = first_above(0.5 * (r0 + background));
        let half_bright = first_above(0.5 * (r0 + r_max));
        println!(
            "half of R_inc at {:.1} nm, half of the bright fringe ({:.3} R_inc at {:.1} nm) at \
             {:.1} nm, second dark fringe at {:.1} nm, {:.3} of R_inc",
            half_background * 1e9,
            r_max / background,
            g_max * 1e9,
            half_bright * 1e9,
            g_dark * 1e9,
            (r_dark - r0) / (background - r0)
        );
        // "rises half-way to the background by g ≈ 60 nm": half of R_inc
        // is passed by 60 nm, half of the bright fringe at 60 ± 5 nm
        assert!(
            (35e-9..=60e-9).contains(&half_background),
            "{half_background}"
        );
        assert!((half_bright - 60e-9).abs() <= 5e-9, "{half_bright}");
        // the first bright fringe at ~λ/4: 120–150 nm, ~1.9 × the background
        assert!((120e-9..=150e-9).contains(&g_max) && r_max > 1.8 * background);
        // "the second dark fringe near 270 nm is nearly as dark as contact":
        // at 270 ± 10 nm, and below a third of the background (a sixth of
        // the bright fringe) — not black: the blue line's own minimum sits
        // at 225 nm and washes it out
        assert!((g_dark - 270e-9).abs() <= 10e-9, "{g_dark}");
        assert!((r_dark - r0) / (background - r0) < 0.33, "{r_dark}");
        assert!(r_dark < r_max / 5.0);
    }

    #[test]
    fn white_light_tends_to_the_incoherent_sum() {
        let s = stack();
        let (r1, r2) = (s.r_glass_gap(), s.r_gap_rubber());
        let incoherent = (r1 * r1 + r2 * r2 - 2.0 * r1 * r1 * r2 * r2) / (1.0 - r1 * r1 * r2 * r2);
        // a grid that resolves six harmonics out to 60 µm
        let avg = SpectralAverage::new(s, &Spectrum::white_led(), 0.1).unwrap();
        let swing = |from_m: f64| {
            (0..400)
                .map(|k| (avg.reflectance(from_m + k as f64 * 1.7e-9) - incoherent).abs())
                .fold(0.0, f64::max)
        };
        // the fringes die out with the blue line's coherence
        assert!(swing(2e-6) > 1e-3);
        assert!(swing(6e-6) > 1e-5);
        for from_m in [12e-6, 20e-6, 35e-6, 50e-6] {
            assert!(swing(from_m) < 5e-8, "{from_m}: {}", swing(from_m));
        }
    }

    #[test]
    fn bad_indices_are_refused() {
        for (bad, name) in [
            (
                Indices {
                    n_glass: f64::NAN,
                    ..Indices::default()
                },
                "n_glass",
            ),
            (
                Indices {
                    n_gap: 0.5,
                    ..Indices::default()
                },
                "n_gap",
            ),
            (
                Indices {
                    n_rubber: f64::INFINITY,
                    ..Indices::default()
                },
                "n_rubber",
            ),
        ] {
            match Stack::new(bad) {
                Err(InterferenceError::Param { param, .. }) => assert_eq!(param, name),
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn spectral_average_of_a_single_line_is_the_monochromatic_reflectance() {
        let s = stack();
        // a sampled spectrum that is a narrow triangle: the average tends to R(λ0)
        let spectrum = Spectrum::Sampled {
            wavelength_nm: vec![549.99, 550.0, 550.01],
            relative_power: vec![0.0, 1.0, 0.0],
        };
        let avg = SpectralAverage::new(s, &spectrum, 0.001).unwrap();
        for g in [0.0, 30e-9, 137.5e-9, 300e-9, 1e-6] {
            assert!((avg.reflectance(g) - s.reflectance(g, 550e-9)).abs() < 1e-7);
        }
    }

    #[test]
    fn rotation_run_equals_direct_cosines() {
        let avg = SpectralAverage::new(stack(), &Spectrum::white_led(), 0.5).unwrap();
        let mut out = vec![0.0; 4096];
        let (g0, h) = (7.3e-6, 0.2e-9);
        avg.reflectance_run(g0, h, &mut out);
        for k in (0..4096).step_by(97).chain([4095]) {
            let direct = avg.reflectance(g0 + k as f64 * h);
            assert!(
                (out[k] - direct).abs() < 1e-12,
                "{k}: {} vs {direct}",
                out[k]
            );
        }
    }

    #[test]
    fn quadrature_is_converged_at_half_a_nanometre_to_1e_10() {
        let coarse = SpectralAverage::new(stack(), &Spectrum::white_led(), 0.5).unwrap();
        let fine = SpectralAverage::new(stack(), &Spectrum::white_led(), 0.125).unwrap();
        for k in 0..=120 {
            let g = k as f64 * 0.1e-6 + 3.3e-9;
            assert!(
                (coarse.reflectance(g) - fine.reflectance(g)).abs() < 1e-10,
                "{g}"
            );
        }
    }
}
