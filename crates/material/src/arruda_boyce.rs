//! The Arruda–Boyce eight-chain solid in the five-term series form that
//! Abaqus uses (Abaqus Theory Guide, "Hyperelastic behavior of rubberlike
//! materials"; Arruda & Boyce 1993, J. Mech. Phys. Solids 41, 389):
//!
//! W = μ Σ_{i=1..5} C_i / λm^(2i−2) (I1^i − 3^i),
//! C = (1/2, 1/20, 11/1050, 19/7000, 519/673750),
//!
//! the first five terms of the inverse-Langevin expansion, not the exact
//! inverse Langevin function. Its initial shear modulus is
//! μ0 = μ (1 + 3/(5λm²) + 99/(175λm⁴) + 513/(875λm⁶) + 42039/(67375λm⁸)).

use crate::invariants::{InvariantEnergy, InvariantSlopes};
use crate::{MaterialError, Parameter};

/// The series coefficients C_i (Abaqus Theory Guide, "Hyperelastic behavior
/// of rubberlike materials"); the finite-element energy uses them too.
pub const SERIES: [f64; 5] = [
    1.0 / 2.0,
    1.0 / 20.0,
    11.0 / 1050.0,
    19.0 / 7000.0,
    519.0 / 673_750.0,
];

#[derive(Clone, Debug, PartialEq)]
pub struct ArrudaBoyce {
    /// μ, Pa (μ0 differs from μ by the series factor above).
    pub mu_pa: f64,
    /// Locking stretch λm, > 0.
    pub lambda_m: f64,
}

impl ArrudaBoyce {
    pub fn new(mu_pa: f64, lambda_m: f64) -> Result<Self, MaterialError> {
        if !(mu_pa.is_finite() && lambda_m > 0.0 && lambda_m.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "Arruda–Boyce needs a finite μ and a positive finite λm, got μ = {mu_pa}, \
                 λm = {lambda_m}"
            )));
        }
        Ok(Self { mu_pa, lambda_m })
    }

    /// μ C_i / λm^(2i−2) for i = 1…5: the coefficient of I1^i.
    fn coefficients(&self) -> [f64; 5] {
        let beta = 1.0 / (self.lambda_m * self.lambda_m);
        let mut k = [0.0; 5];
        let mut power = 1.0;
        for (ki, ci) in k.iter_mut().zip(SERIES) {
            *ki = self.mu_pa * ci * power;
            power *= beta;
        }
        k
    }
}

impl InvariantEnergy for ArrudaBoyce {
    fn energy_at(&self, i1: f64, _: f64) -> f64 {
        self.coefficients()
            .iter()
            .zip(1..)
            .map(|(k, i)| k * (i1.powi(i) - 3f64.powi(i)))
            .sum()
    }

    fn slopes_at(&self, i1: f64, _: f64) -> InvariantSlopes {
        let k = self.coefficients();
        let mut s = InvariantSlopes::default();
        for (ki, i) in k.iter().zip(1..) {
            let fi = f64::from(i);
            s.w1 += ki * fi * i1.powi(i - 1);
            if i >= 2 {
                s.w11 += ki * fi * (fi - 1.0) * i1.powi(i - 2);
            }
        }
        s
    }

    fn family_name(&self) -> &'static str {
        "arruda-boyce"
    }
    fn initial_shear_modulus_pa(&self) -> f64 {
        2.0 * self.slopes_at(3.0, 3.0).w1
    }
    fn named_parameters(&self) -> Vec<Parameter> {
        vec![
            Parameter::modulus("mu", self.mu_pa),
            Parameter::number("lambda_m", self.lambda_m),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::invariants::tests::{check_against_energy, check_small_strain};
    use crate::{Hyperelastic, Mode};

    #[test]
    fn stresses_follow_the_energy_and_the_small_strain_limit() {
        let m = ArrudaBoyce::new(0.3e6, 2.5).unwrap();
        check_against_energy(&m);
        check_small_strain(&m);
    }

    #[test]
    fn initial_shear_modulus_matches_the_published_series() {
        let (mu, lm) = (0.3e6, 2.5_f64);
        let m = ArrudaBoyce::new(mu, lm).unwrap();
        let b = lm.powi(-2);
        let expected = mu
            * (1.0
                + 3.0 / 5.0 * b
                + 99.0 / 175.0 * b * b
                + 513.0 / 875.0 * b.powi(3)
                + 42039.0 / 67375.0 * b.powi(4));
        assert!((m.shear_modulus_pa() / expected - 1.0).abs() < 1e-12);
        // A long chain (λm → ∞) is neo-Hookean with C10 = μ/2.
        let long = ArrudaBoyce::new(mu, 1e6).unwrap();
        let nh = crate::NeoHookean::new(mu / 2.0).unwrap();
        let (a, b) = (
            long.nominal_stress_pa(Mode::Uniaxial, 2.0),
            nh.nominal_stress_pa(Mode::Uniaxial, 2.0),
        );
        assert!((a / b - 1.0).abs() < 1e-9, "{a} vs {b}");
        assert!(ArrudaBoyce::new(mu, 0.0).is_err());
    }
}
