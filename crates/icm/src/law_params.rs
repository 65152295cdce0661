//! The contact-law parameters every contact model takes (`icm`, `bem`,
//! `persson`, `greenwood-williamson`, and the synthetic experiment's
//! physics), declared once and flattened into each stage's parameters, so
//! their names, defaults, ranges and docs cannot drift apart; and the one
//! function through which each of them reads its material.

use std::sync::Arc;

use hypercontact_core::{Context, Table, params};
use hypercontact_material::table::material_from_table;
use hypercontact_material::{Hyperelastic, Material, MaterialError, Poisson};

use crate::{CompositeModulus, Model, Scheme, Tangent};

/// `model`, `tangent`, `scheme` and `poisson`.
#[params]
pub struct LawParams {
    /// contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
    #[param(default = Model::Hyperelastic)]
    pub model: Model,
    /// the curve E_t = dφ/dε comes from: `equibiaxial` (the paper's; E_t*(0) = 2 E0* at ν = ½) or `uniaxial` (compression with free lateral expansion; E_t*(0) = E0*)
    #[param(default = Tangent::Equibiaxial)]
    pub tangent: Tangent,
    /// integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
    #[param(default = Scheme::Heun)]
    pub scheme: Scheme,
    /// Poisson's ratio ν of the composite moduli (a linear material uses its own)
    #[param(default = Poisson::INCOMPRESSIBLE)]
    pub poisson: Poisson,
}

impl LawParams {
    /// E_t*(S) of a hyperelastic `material` under this law.
    pub fn modulus(
        &self,
        material: Arc<dyn Hyperelastic>,
    ) -> Result<CompositeModulus, MaterialError> {
        CompositeModulus::with_tangent(material, self.model, self.tangent, self.poisson.0)
    }

    /// E_t*(S) of whatever a `material` table holds: what every contact
    /// stage calls. A linear material has E* = E / (1 − ν²) with its own ν
    /// at every stress; when `model`, `tangent` or `poisson` would have said
    /// otherwise, a note in `ctx` says which value was used.
    pub fn modulus_from_table(
        &self,
        table: &Table,
        ctx: &Context,
    ) -> Result<CompositeModulus, MaterialError> {
        let material = material_from_table(table)?;
        if let Some(note) = self.linear_note(&material) {
            ctx.note(&note);
        }
        CompositeModulus::of_material(&material, self.model, self.tangent, self.poisson.0)
    }

    /// What a linear material overrides of these parameters, if anything.
    fn linear_note(&self, material: &Material) -> Option<String> {
        let Material::Linear(solid) = material else {
            return None;
        };
        let mut ignored = Vec::new();
        if self.model == Model::Hyperelastic {
            ignored.push("model: hyperelastic and its tangent (E* is constant)".to_owned());
        }
        if self.poisson.0 != solid.poisson {
            ignored.push(format!(
                "poisson: {} (its own ν is {})",
                self.poisson.0, solid.poisson
            ));
        }
        (!ignored.is_empty()).then(|| {
            format!(
                "the material is linear elastic: E* = E/(1 − ν²) = {:.6e} Pa at every stress, \
                 with E = {:e} Pa and ν = {}; not used: {}",
                solid.composite_modulus_pa(),
                solid.e_pa,
                solid.poisson,
                ignored.join("; ")
            )
        })
    }
}
