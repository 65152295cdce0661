//! The incompressible neo-Hookean solid, W = C10 (I1 − 3), μ0 = 2 C10
//! (Abaqus' parameter name C10; Treloar's Gaussian-network energy).

use crate::invariants::{InvariantEnergy, InvariantSlopes};
use crate::{MaterialError, Parameter};

#[derive(Clone, Debug, PartialEq)]
pub struct NeoHookean {
    /// C10 = μ0 / 2, Pa.
    pub c10_pa: f64,
}

impl NeoHookean {
    pub fn new(c10_pa: f64) -> Result<Self, MaterialError> {
        if !c10_pa.is_finite() {
            return Err(MaterialError::Invalid(format!(
                "neo-Hookean C10 is not finite ({c10_pa})"
            )));
        }
        Ok(Self { c10_pa })
    }
}

impl InvariantEnergy for NeoHookean {
    fn energy_at(&self, i1: f64, _: f64) -> f64 {
        self.c10_pa * (i1 - 3.0)
    }

    fn slopes_at(&self, _: f64, _: f64) -> InvariantSlopes {
        InvariantSlopes {
            w1: self.c10_pa,
            ..Default::default()
        }
    }

    fn family_name(&self) -> &'static str {
        "neo-hookean"
    }
    fn initial_shear_modulus_pa(&self) -> f64 {
        2.0 * self.c10_pa
    }
    fn named_parameters(&self) -> Vec<Parameter> {
        vec![Parameter::modulus("c10", self.c10_pa)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::invariants::tests::{check_against_energy, check_small_strain};
    use crate::{Hyperelastic, Mode};

    #[test]
    fn stresses_follow_the_energy_and_the_small_strain_limit() {
        let m = NeoHookean::new(0.2e6).unwrap();
        check_against_energy(&m);
        check_small_strain(&m);
    }

    #[test]
    fn closed_forms() {
        // T = 2 C10 (λ − λ^-2), 2 C10 (λ − λ^-3), 2 C10 (λ − λ^-5)
        // (e.g. Treloar, The Physics of Rubber Elasticity, ch. 5).
        let c10 = 0.35e6;
        let m = NeoHookean::new(c10).unwrap();
        for l in [0.5, 1.2, 2.0, 4.0_f64] {
            let cases = [
                (Mode::Uniaxial, 2.0 * c10 * (l - l.powi(-2))),
                (Mode::Planar, 2.0 * c10 * (l - l.powi(-3))),
                (Mode::Equibiaxial, 2.0 * c10 * (l - l.powi(-5))),
            ];
            for (mode, expected) in cases {
                let t = m.nominal_stress_pa(mode, l);
                assert!(
                    (t - expected).abs() < 1e-9 * c10,
                    "{mode} λ={l}: {t} vs {expected}"
                );
            }
        }
        assert!(NeoHookean::new(f64::NAN).is_err());
    }
}
