//! Stand-in materials for the tests of contact models (not fitted to any
//! rubber, not offered as presets).

use crate::{Hyperelastic, Mode, Parameter};

/// A material whose nominal stress is 6 μ (λ − 1) in every mode, so its
/// equibiaxial tangent is the constant 6 μ = E_t(0) of any material with
/// shear modulus μ: a tangent-modulus contact model must then give the
/// linear model at E* = E_t*. It has no strain energy (0); only the contact
/// law may use it.
#[derive(Debug)]
pub struct ConstantTangent {
    pub mu_pa: f64,
}

impl Hyperelastic for ConstantTangent {
    fn family(&self) -> &'static str {
        "constant-tangent"
    }
    fn shear_modulus_pa(&self) -> f64 {
        self.mu_pa
    }
    fn energy_pa(&self, _: [f64; 3]) -> f64 {
        0.0
    }
    fn nominal_stress_pa(&self, _: Mode, stretch: f64) -> f64 {
        6.0 * self.mu_pa * (stretch - 1.0)
    }
    fn nominal_stress_slope_pa(&self, _: Mode, _: f64) -> f64 {
        6.0 * self.mu_pa
    }
    fn parameters(&self) -> Vec<Parameter> {
        Vec::new()
    }
}
