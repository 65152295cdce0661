//! The isotropic height spectrum the theories integrate, in Persson's
//! normalisation, with the integrals ∫ q^k C(q) dq they need.
//!
//! Conventions:
//! - Input: the radial PSD of stage `surface` (SurfaceTopography's
//!   normalisation, C_ST = |Δx Δy FFT2(h)|² / (Lx Ly), so that
//!   ⟨h²⟩ = (1/(2π)²) ∫ C_ST d²q).
//! - Here: Persson's, C(q) = (1/(2π)²) ∫ ⟨h(x) h(0)⟩ e^{−iq·x} d²x, so that
//!   ⟨h²⟩ = ∫ C d²q = 2π ∫ q C dq (Persson, J. Chem. Phys. 115, 3840, 2001).
//!   Hence C = C_ST / (2π)².
//! - Between tabulated points C is a power law in q (straight in log–log),
//!   so each piece integrates in closed form and a pure power law is
//!   integrated exactly; a piece with C = 0 at an end is linear in q.
//! - Profile moments of the isotropic surface (Nayak 1971):
//!   m0 = 2π ∫ q C dq, m2 = π ∫ q³ C dq, m4 = (3π/4) ∫ q⁵ C dq;
//!   h_rms² = m0 and h'rms² = ⟨|∇h|²⟩ = 2 m2.

use std::f64::consts::{PI, TAU};

pub use crate::gw::Moments;

/// Why a spectrum cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    #[error("the spectrum has {0} point(s) with q > 0; at least 2 are needed")]
    TooShort(usize),
    #[error("point {index}: q = {q_per_m} rad/m, C = {c} is not a finite q > 0 with C ≥ 0")]
    Invalid { index: usize, q_per_m: f64, c: f64 },
    #[error("point {index}: q = {q_per_m} rad/m does not rise above the previous point's")]
    NotAscending { index: usize, q_per_m: f64 },
    #[error(
        "the range q = {lo:.6e} … {hi:.6e} rad/m leaves no part of the spectrum \
         ({first:.6e} … {last:.6e} rad/m)"
    )]
    EmptyRange {
        lo: f64,
        hi: f64,
        first: f64,
        last: f64,
    },
    #[error("the spectrum holds no power (every C is 0) over q = {lo:.6e} … {hi:.6e} rad/m")]
    NoPower { lo: f64, hi: f64 },
}

/// An isotropic spectrum C(q) in Persson's normalisation, q ascending (rad/m), C in m⁴.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrum {
    q_per_m: Vec<f64>,
    c_m4: Vec<f64>,
}

impl Spectrum {
    /// From points in Persson's normalisation.
    pub fn new(q_per_m: Vec<f64>, c_m4: Vec<f64>) -> Result<Self, SpectrumError> {
        assert_eq!(q_per_m.len(), c_m4.len());
        for (index, (&q, &c)) in q_per_m.iter().zip(&c_m4).enumerate() {
            if !(q.is_finite() && q > 0.0 && c.is_finite() && c >= 0.0) {
                return Err(SpectrumError::Invalid {
                    index,
                    q_per_m: q,
                    c,
                });
            }
            if index > 0 && q <= q_per_m[index - 1] {
                return Err(SpectrumError::NotAscending { index, q_per_m: q });
            }
        }
        if q_per_m.len() < 2 {
            return Err(SpectrumError::TooShort(q_per_m.len()));
        }
        let s = Self { q_per_m, c_m4 };
        if s.c_m4.iter().all(|&c| c == 0.0) {
            return Err(SpectrumError::NoPower {
                lo: s.q_min(),
                hi: s.q_max(),
            });
        }
        Ok(s)
    }

    /// From a radial PSD in SurfaceTopography's normalisation (stage
    /// `surface`'s `psd` rows with direction `radial`): C = C_ST / (2π)².
    /// A q = 0 point (the mean) is left out.
    pub fn from_surface_topography(
        q_per_m: &[f64],
        c_st_m4: &[f64],
    ) -> Result<Self, SpectrumError> {
        let (q, c): (Vec<f64>, Vec<f64>) = q_per_m
            .iter()
            .zip(c_st_m4)
            .filter(|(q, _)| **q != 0.0)
            .map(|(&q, &c)| (q, c / (TAU * TAU)))
            .unzip();
        Self::new(q, c)
    }

    pub fn q_per_m(&self) -> &[f64] {
        &self.q_per_m
    }

    pub fn c_m4(&self) -> &[f64] {
        &self.c_m4
    }

    pub fn q_min(&self) -> f64 {
        self.q_per_m[0]
    }

    pub fn q_max(&self) -> f64 {
        self.q_per_m[self.q_per_m.len() - 1]
    }

    /// The part over q_lo … q_hi (either None: the spectrum's own end), with
    /// C at a cut interpolated as the piece it falls in.
    pub fn clip(&self, q_lo: Option<f64>, q_hi: Option<f64>) -> Result<Self, SpectrumError> {
        let lo = q_lo.unwrap_or(self.q_min()).max(self.q_min());
        let hi = q_hi.unwrap_or(self.q_max()).min(self.q_max());
        if lo >= hi || lo.is_nan() || hi.is_nan() {
            return Err(SpectrumError::EmptyRange {
                lo: q_lo.unwrap_or(self.q_min()),
                hi: q_hi.unwrap_or(self.q_max()),
                first: self.q_min(),
                last: self.q_max(),
            });
        }
        let mut q = vec![lo];
        let mut c = vec![self.value_at(lo)];
        for (&qi, &ci) in self.q_per_m.iter().zip(&self.c_m4) {
            if qi > lo && qi < hi {
                q.push(qi);
                c.push(ci);
            }
        }
        q.push(hi);
        c.push(self.value_at(hi));
        Self::new(q, c)
    }

    /// C(q) inside the range (piecewise power law), 0 outside.
    pub fn value_at(&self, q: f64) -> f64 {
        if !(q >= self.q_min() && q <= self.q_max()) {
            return 0.0;
        }
        let i = self.piece(q);
        Piece::new(self, i).value(q)
    }

    /// ∫ q^k C(q) dq over the whole range.
    pub fn integral(&self, k: f64) -> f64 {
        self.integral_between(k, self.q_min(), self.q_max())
    }

    /// ∫_a^b q^k C(q) dq for q_min ≤ a ≤ b ≤ q_max, pieces added in order of q.
    pub fn integral_between(&self, k: f64, a: f64, b: f64) -> f64 {
        let a = a.max(self.q_min());
        let b = b.min(self.q_max());
        if a >= b || a.is_nan() || b.is_nan() {
            return 0.0;
        }
        let mut sum = 0.0;
        let mut i = self.piece(a);
        let mut lo = a;
        loop {
            let piece = Piece::new(self, i);
            let hi = b.min(piece.q1);
            sum += piece.integral(k, lo, hi);
            if hi >= b || i + 2 >= self.q_per_m.len() {
                break;
            }
            lo = hi;
            i += 1;
        }
        sum
    }

    /// Nayak's profile moments over the range.
    pub fn moments(&self) -> Moments {
        Moments {
            m0: TAU * self.integral(1.0),
            m2: PI * self.integral(3.0),
            m4: 0.75 * PI * self.integral(5.0),
        }
    }

    /// The index i of the piece [q_i, q_{i+1}] holding q (the last piece for q_max).
    fn piece(&self, q: f64) -> usize {
        let n = self.q_per_m.len();
        self.q_per_m
            .partition_point(|&qi| qi <= q)
            .saturating_sub(1)
            .min(n - 2)
    }
}

impl Moments {
    /// h_rms = √m0, m.
    pub fn rms_height_m(&self) -> f64 {
        self.m0.sqrt()
    }

    /// h'rms = √⟨|∇h|²⟩ = √(2 m2).
    pub fn rms_slope(&self) -> f64 {
        (2.0 * self.m2).sqrt()
    }
}

/// One piece of the spectrum between two tabulated points.
struct Piece {
    q0: f64,
    q1: f64,
    c0: f64,
    c1: f64,
}

impl Piece {
    fn new(s: &Spectrum, i: usize) -> Self {
        Self {
            q0: s.q_per_m[i],
            q1: s.q_per_m[i + 1],
            c0: s.c_m4[i],
            c1: s.c_m4[i + 1],
        }
    }

    fn power_law(&self) -> bool {
        self.c0 > 0.0 && self.c1 > 0.0
    }

    /// The log–log slope of the piece.
    fn slope(&self) -> f64 {
        (self.c1 / self.c0).ln() / (self.q1 / self.q0).ln()
    }

    fn value(&self, q: f64) -> f64 {
        if self.power_law() {
            self.c0 * (q / self.q0).powf(self.slope())
        } else {
            self.c0 + (self.c1 - self.c0) * (q - self.q0) / (self.q1 - self.q0)
        }
    }

    /// ∫_a^b q^k C dq inside the piece.
    fn integral(&self, k: f64, a: f64, b: f64) -> f64 {
        if self.power_law() {
            // C = C(a) (q/a)^s → C(a) a^(k+1) ((b/a)^e − 1)/e, e = k + s + 1;
            // expm1 keeps e → 0 (where it becomes ln(b/a)) exact.
            let e = k + self.slope() + 1.0;
            let log_ratio = (b / a).ln();
            let factor = if (e * log_ratio).abs() < 1e-12 {
                log_ratio
            } else {
                (e * log_ratio).exp_m1() / e
            };
            self.value(a) * a.powf(k + 1.0) * factor
        } else {
            // C linear in q: C = α + β q; ∫ q^k (α + β q) dq in closed form.
            let beta = (self.c1 - self.c0) / (self.q1 - self.q0);
            let alpha = self.c0 - beta * self.q0;
            let power = |m: f64| (b.powf(m) - a.powf(m)) / m;
            alpha * power(k + 1.0) + beta * power(k + 2.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// C = c0 q^−(2+2H) from q0 to q1, sampled at n log-spaced points.
    fn power_law(h: f64, q0: f64, q1: f64, n: usize) -> Spectrum {
        let q: Vec<f64> = (0..n)
            .map(|i| q0 * (q1 / q0).powf(i as f64 / (n - 1) as f64))
            .collect();
        let c = q.iter().map(|q| 1e-30 * q.powf(-2.0 - 2.0 * h)).collect();
        Spectrum::new(q, c).unwrap()
    }

    #[test]
    fn a_power_law_integrates_exactly() {
        let (h, q0, q1) = (0.7, 1e3, 1e6);
        let s = power_law(h, q0, q1, 7);
        for k in [1.0, 3.0, 5.0, 0.4] {
            let e = k - 1.0 - 2.0 * h;
            let exact = 1e-30 * (q1.powf(e) - q0.powf(e)) / e;
            let got = s.integral(k);
            assert!(
                (got / exact - 1.0).abs() < 1e-12,
                "k = {k}: {got} vs {exact}"
            );
        }
        // e = 0: ∫ q^(1+2H) q^−(2+2H) dq = ln(q1/q0).
        let got = s.integral(1.0 + 2.0 * h);
        assert!((got / (1e-30 * (q1 / q0).ln()) - 1.0).abs() < 1e-12);
        // A sub-range and a clip agree with the closed form.
        let (a, b): (f64, f64) = (2.5e3, 7.7e5);
        let e = 2.0 - 2.0 * h;
        let exact = 1e-30 * (b.powf(e) - a.powf(e)) / e;
        for got in [
            s.integral_between(3.0, a, b),
            s.clip(Some(a), Some(b)).unwrap().integral(3.0),
        ] {
            assert!((got / exact - 1.0).abs() < 1e-12, "{got} vs {exact}");
        }
    }

    #[test]
    fn moments_of_a_band_of_white_noise() {
        // C constant on q0…q1: m0 = 2πC (q1² − q0²)/2, m2 = πC (q1⁴ − q0⁴)/4,
        // m4 = (3π/4) C (q1⁶ − q0⁶)/6.
        let (c, q0, q1) = (2e-24, 1e4, 3e5);
        let s = Spectrum::new(vec![q0, 1e5, q1], vec![c, c, c]).unwrap();
        let m = s.moments();
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(rel(m.m0, PI * c * (q1 * q1 - q0 * q0)) < 1e-13);
        assert!(rel(m.m2, PI * c * (q1.powi(4) - q0.powi(4)) / 4.0) < 1e-13);
        assert!(rel(m.m4, 0.125 * PI * c * (q1.powi(6) - q0.powi(6))) < 1e-13);
        assert!(rel(m.rms_slope(), (2.0 * m.m2).sqrt()) < 1e-15);
    }

    #[test]
    fn zero_power_pieces_are_linear_and_the_normalisation_is_surface_topographys() {
        // C falls linearly to 0 on the last piece: ∫ q^0 C = ½ C Δq there.
        let s = Spectrum::new(vec![1.0, 2.0, 4.0], vec![3.0, 3.0, 0.0]).unwrap();
        assert!((s.integral_between(0.0, 2.0, 4.0) - 3.0).abs() < 1e-14);
        assert_eq!(s.value_at(3.0), 1.5);
        assert_eq!(s.value_at(5.0), 0.0);
        let st =
            Spectrum::from_surface_topography(&[0.0, 1.0, 2.0], &[9.0, TAU * TAU, 0.0]).unwrap();
        assert_eq!(st.q_per_m(), &[1.0, 2.0]);
        assert!((st.c_m4()[0] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn bad_spectra_are_refused_with_the_point() {
        let e = Spectrum::new(vec![1.0, 1.0], vec![1.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("point 1"), "{e}");
        let e = Spectrum::new(vec![1.0, 2.0], vec![1.0, f64::NAN]).unwrap_err();
        assert!(e.to_string().contains("point 1"), "{e}");
        assert!(matches!(
            Spectrum::new(vec![1.0], vec![1.0]),
            Err(SpectrumError::TooShort(1))
        ));
        let e = Spectrum::new(vec![1.0, 2.0], vec![0.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("no power"), "{e}");
        let s = Spectrum::new(vec![1.0, 2.0], vec![1.0, 1.0]).unwrap();
        let e = s.clip(Some(3.0), None).unwrap_err();
        assert!(e.to_string().contains("leaves no part"), "{e}");
    }
}
