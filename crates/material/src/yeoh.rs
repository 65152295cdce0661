//! The Yeoh solid (Abaqus' reduced polynomial with N = 3):
//! W = C10 (I1 − 3) + C20 (I1 − 3)² + C30 (I1 − 3)³, μ0 = 2 C10.

use crate::invariants::{InvariantEnergy, InvariantSlopes};
use crate::{MaterialError, Parameter};

#[derive(Clone, Debug, PartialEq)]
pub struct Yeoh {
    pub c10_pa: f64,
    pub c20_pa: f64,
    pub c30_pa: f64,
}

impl Yeoh {
    pub fn new(c10_pa: f64, c20_pa: f64, c30_pa: f64) -> Result<Self, MaterialError> {
        if !(c10_pa.is_finite() && c20_pa.is_finite() && c30_pa.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "Yeoh C10 = {c10_pa}, C20 = {c20_pa}, C30 = {c30_pa} must be finite"
            )));
        }
        Ok(Self {
            c10_pa,
            c20_pa,
            c30_pa,
        })
    }
}

impl InvariantEnergy for Yeoh {
    fn energy_at(&self, i1: f64, _: f64) -> f64 {
        let x = i1 - 3.0;
        x * (self.c10_pa + x * (self.c20_pa + x * self.c30_pa))
    }

    fn slopes_at(&self, i1: f64, _: f64) -> InvariantSlopes {
        let x = i1 - 3.0;
        InvariantSlopes {
            w1: self.c10_pa + 2.0 * self.c20_pa * x + 3.0 * self.c30_pa * x * x,
            w11: 2.0 * self.c20_pa + 6.0 * self.c30_pa * x,
            ..Default::default()
        }
    }

    fn family_name(&self) -> &'static str {
        "yeoh"
    }
    fn initial_shear_modulus_pa(&self) -> f64 {
        2.0 * self.c10_pa
    }
    fn named_parameters(&self) -> Vec<Parameter> {
        vec![
            Parameter::modulus("c10", self.c10_pa),
            Parameter::modulus("c20", self.c20_pa),
            Parameter::modulus("c30", self.c30_pa),
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
        let m = Yeoh::new(0.2e6, -0.01e6, 0.002e6).unwrap();
        check_against_energy(&m);
        check_small_strain(&m);
    }

    #[test]
    fn uniaxial_closed_form() {
        // T = 2 (λ − λ^-2) W1(I1) in uniaxial tension (Yeoh 1993).
        let m = Yeoh::new(0.2e6, -0.01e6, 0.002e6).unwrap();
        for l in [0.6, 1.5, 3.0_f64] {
            let x = l * l + 2.0 / l - 3.0;
            let w1 = 0.2e6 - 0.02e6 * x + 0.006e6 * x * x;
            let expected = 2.0 * (l - l.powi(-2)) * w1;
            let t = m.nominal_stress_pa(Mode::Uniaxial, l);
            assert!(
                (t - expected).abs() < 1e-9 * 0.2e6,
                "λ={l}: {t} vs {expected}"
            );
        }
    }
}
