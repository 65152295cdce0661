//! The incompressible Mooney–Rivlin solid, W = C10 (I1 − 3) + C01 (I2 − 3),
//! μ0 = 2 (C10 + C01) (Abaqus' parameter names).

use crate::invariants::{InvariantEnergy, InvariantSlopes};
use crate::{MaterialError, Parameter};

#[derive(Clone, Debug, PartialEq)]
pub struct MooneyRivlin {
    pub c10_pa: f64,
    pub c01_pa: f64,
}

impl MooneyRivlin {
    pub fn new(c10_pa: f64, c01_pa: f64) -> Result<Self, MaterialError> {
        if !(c10_pa.is_finite() && c01_pa.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "Mooney–Rivlin C10 = {c10_pa}, C01 = {c01_pa} must be finite"
            )));
        }
        Ok(Self { c10_pa, c01_pa })
    }
}

impl InvariantEnergy for MooneyRivlin {
    fn energy_at(&self, i1: f64, i2: f64) -> f64 {
        self.c10_pa * (i1 - 3.0) + self.c01_pa * (i2 - 3.0)
    }

    fn slopes_at(&self, _: f64, _: f64) -> InvariantSlopes {
        InvariantSlopes {
            w1: self.c10_pa,
            w2: self.c01_pa,
            ..Default::default()
        }
    }

    fn family_name(&self) -> &'static str {
        "mooney-rivlin"
    }
    fn initial_shear_modulus_pa(&self) -> f64 {
        2.0 * (self.c10_pa + self.c01_pa)
    }
    fn named_parameters(&self) -> Vec<Parameter> {
        vec![
            Parameter::modulus("c10", self.c10_pa),
            Parameter::modulus("c01", self.c01_pa),
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
        let m = MooneyRivlin::new(0.18e6, 0.02e6).unwrap();
        check_against_energy(&m);
        check_small_strain(&m);
    }

    #[test]
    fn closed_forms() {
        // UT: T = 2 (λ − λ^-2)(C10 + C01/λ); PT: 2 (λ − λ^-3)(C10 + C01);
        // BT: 2 (λ − λ^-5)(C10 + λ² C01) (Rivlin & Saunders 1951 forms).
        let (c10, c01) = (0.18e6, 0.05e6);
        let m = MooneyRivlin::new(c10, c01).unwrap();
        for l in [0.5, 1.2, 2.0, 4.0_f64] {
            let cases = [
                (Mode::Uniaxial, 2.0 * (l - l.powi(-2)) * (c10 + c01 / l)),
                (Mode::Planar, 2.0 * (l - l.powi(-3)) * (c10 + c01)),
                (
                    Mode::Equibiaxial,
                    2.0 * (l - l.powi(-5)) * (c10 + l * l * c01),
                ),
            ];
            for (mode, expected) in cases {
                let t = m.nominal_stress_pa(mode, l);
                assert!(
                    (t - expected).abs() < 1e-9 * c10,
                    "{mode} λ={l}: {t} vs {expected}"
                );
            }
        }
    }
}
