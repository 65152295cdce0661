//! What a `material` table holds: a hyperelastic model (a preset, a fit or
//! constants) or a linear-elastic solid given by Young's modulus E and
//! Poisson's ratio ν.
//!
//! A linear solid is not a hyperelastic model: it has no strain energy of
//! finite strain, no nominal stress curves and no tangent modulus beyond its
//! constant one. Its composite (plane-strain) modulus is the usual
//! E* = E / (1 − ν²) (Johnson, Contact Mechanics, Eq. 4.22 for two bodies
//! of which one is rigid), with its own ν.

use std::sync::Arc;

use crate::{Hyperelastic, MaterialError, Parameter};

/// A linear-elastic solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearElastic {
    /// Young's modulus E, Pa (> 0).
    pub e_pa: f64,
    /// Poisson's ratio ν, 0 ≤ ν ≤ ½.
    pub poisson: f64,
}

impl LinearElastic {
    /// The `model` name of a linear solid in the `material` table.
    pub const FAMILY: &'static str = "linear";

    pub fn new(e_pa: f64, poisson: f64) -> Result<Self, MaterialError> {
        if !(e_pa > 0.0 && e_pa.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "a linear solid needs a positive finite Young's modulus, got E = {e_pa} Pa"
            )));
        }
        if !(0.0..=0.5).contains(&poisson) {
            return Err(MaterialError::Invalid(format!(
                "a linear solid needs 0 ≤ ν ≤ 0.5, got ν = {poisson}"
            )));
        }
        Ok(Self { e_pa, poisson })
    }

    /// E* = E / (1 − ν²), Pa.
    pub fn composite_modulus_pa(&self) -> f64 {
        self.e_pa / (1.0 - self.poisson * self.poisson)
    }

    /// Its rows of the `material` table: `e` (Pa) and `poisson` (1).
    pub fn parameters(&self) -> Vec<Parameter> {
        vec![
            Parameter::modulus("e", self.e_pa),
            Parameter::number("poisson", self.poisson),
        ]
    }
}

/// What a `material` table holds.
#[derive(Clone, Debug)]
pub enum Material {
    /// Young's modulus and Poisson's ratio: E* the same at every stress.
    Linear(LinearElastic),
    /// A strain energy: the contact stages' tangent modulus follows it.
    Hyperelastic(Arc<dyn Hyperelastic>),
}

impl Material {
    /// The family's name in the `material` table.
    pub fn family(&self) -> &'static str {
        match self {
            Material::Linear(_) => LinearElastic::FAMILY,
            Material::Hyperelastic(model) => model.family(),
        }
    }

    /// The parameters in SI units, in the order of the `material` table.
    pub fn parameters(&self) -> Vec<Parameter> {
        match self {
            Material::Linear(solid) => solid.parameters(),
            Material::Hyperelastic(model) => model.parameters(),
        }
    }

    /// The hyperelastic model, or None for a linear solid.
    pub fn hyperelastic(&self) -> Option<&Arc<dyn Hyperelastic>> {
        match self {
            Material::Linear(_) => None,
            Material::Hyperelastic(model) => Some(model),
        }
    }
}

impl From<Box<dyn Hyperelastic>> for Material {
    fn from(model: Box<dyn Hyperelastic>) -> Self {
        Material::Hyperelastic(Arc::from(model))
    }
}

impl From<LinearElastic> for Material {
    fn from(solid: LinearElastic) -> Self {
        Material::Linear(solid)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_composite_modulus_is_e_over_one_minus_nu_squared() {
        let solid = LinearElastic::new(2e6, 0.49).unwrap();
        assert_eq!(solid.composite_modulus_pa(), 2e6 / (1.0 - 0.49 * 0.49));
        let names: Vec<String> = solid.parameters().iter().map(Parameter::name).collect();
        assert_eq!(names, ["e", "poisson"]);
        assert_eq!(Material::from(solid).family(), "linear");
    }

    #[test]
    fn bad_constants_are_refused_with_their_value() {
        let e = LinearElastic::new(-1.0, 0.3).unwrap_err().to_string();
        assert!(e.contains("E = -1 Pa"), "{e}");
        let e = LinearElastic::new(1e6, 0.6).unwrap_err().to_string();
        assert!(e.contains("ν = 0.6"), "{e}");
        assert!(LinearElastic::new(f64::NAN, 0.3).is_err());
        assert!(LinearElastic::new(1e6, f64::NAN).is_err());
    }
}
