//! The contact-law parameters every contact model takes (`icm`, `bem`,
//! `persson`, `greenwood-williamson`, and the synthetic experiment's
//! physics), declared once and flattened into each stage's parameters, so
//! their names, defaults, ranges and docs cannot drift apart.

use std::sync::Arc;

use hypercontact_core::params;
use hypercontact_material::{Hyperelastic, MaterialError, Poisson};

use crate::{CompositeModulus, Model, Scheme};

/// `model`, `scheme` and `poisson`.
#[params]
pub struct LawParams {
    /// contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
    #[param(default = Model::Hyperelastic)]
    pub model: Model,
    /// integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
    #[param(default = Scheme::Heun)]
    pub scheme: Scheme,
    /// Poisson's ratio ν of the composite moduli
    #[param(default = Poisson::INCOMPRESSIBLE)]
    pub poisson: Poisson,
}

impl LawParams {
    /// E_t*(S) of `material` under this law.
    pub fn modulus(
        &self,
        material: Arc<dyn Hyperelastic>,
    ) -> Result<CompositeModulus, MaterialError> {
        CompositeModulus::new(material, self.model, self.poisson.0)
    }
}
