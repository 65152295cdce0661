//! The composite modulus the ICM integrates with: E_t*(S) of the paper's
//! Eqs. (5)–(6) for the hyperelastic model, or the constant E0* of Wang's
//! original (linear) model.
//!
//! Conventions (SPEC, "Ogden model" and "Incremental contact model"):
//! - E0 = 2 μ0 (1 + ν), E0* = E0 / (1 − ν²)
//!   ([`hypercontact_material::composite_modulus_pa`]).
//! - Hyperelastic: E_t* = E_t(φ⁻¹(S)) / (1 − ν²) with φ a nominal stress
//!   curve (Eq. 2) and E_t = dφ/dε (Eq. 6), at the compressive S = −F/A ≤ 0,
//!   so ε ≤ 0. Which curve is the [`Tangent`] choice:
//!   - `equibiaxial` (the paper's): the material under a contact patch is
//!     stretched equally in its plane. E_t(0) = 6 μ0 = 2 E0, hence
//!     E_t*/E0* = 3 / (1 + ν) at first contact: a factor 2 for ν = ½, so the
//!     hyperelastic curve starts at twice the linear one and does not reduce
//!     to linear elasticity at vanishing load.
//!   - `uniaxial`: compression along the load axis with free lateral
//!     expansion, the small-strain limit of Hertz's and Boussinesq's
//!     solutions. E_t(0) = 3 μ0 = E0, E_t*/E0* = 3 / (2 (1 + ν)) at first
//!     contact: 1 for ν = ½, where the curve meets the linear one.
//! - For ν < ½ the material law stays the incompressible one (the Ogden
//!   form has no bulk term); only E0 and the 1/(1 − ν²) factor use ν.
//! - A linear-elastic material ([`hypercontact_material::LinearElastic`])
//!   has E* = E / (1 − ν²) with its own ν at every stress, whatever the
//!   model, tangent and ν of the stage.

use std::sync::Arc;

use hypercontact_core::Choice;
use hypercontact_material::{
    ContactLaw, Hyperelastic, LinearElastic, Material, MaterialError, Mode, composite_modulus_pa,
};

use crate::tangent_table::TangentTable;

/// Which contact law the ICM uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum Model {
    /// the paper's: tangent modulus at the mean contact stress
    #[default]
    Hyperelastic,
    /// Wang's original ICM: the initial modulus E0* throughout
    Linear,
}

/// Which nominal stress curve the tangent modulus E_t = dφ/dε is taken from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum Tangent {
    /// the paper's: the equibiaxial curve (patch stretched equally in-plane); E_t(0) = 2 E0
    #[default]
    Equibiaxial,
    /// the uniaxial curve in compression (free lateral expansion, Hertz's small-strain limit); E_t(0) = E0
    Uniaxial,
}

impl Tangent {
    /// The test mode whose nominal stress is φ.
    pub fn mode(self) -> Mode {
        match self {
            Tangent::Equibiaxial => Mode::Equibiaxial,
            Tangent::Uniaxial => Mode::Uniaxial,
        }
    }
}

/// E_t*(S) for one material, model, tangent and Poisson ratio.
#[derive(Clone, Debug)]
pub struct CompositeModulus {
    model: Model,
    /// The hyperelastic law; None for a linear-elastic material.
    law: Option<ContactLaw>,
    /// The compressive branch of E_t(S), for speed; None for `linear`.
    table: Option<TangentTable>,
    poisson: f64,
    e0_star_pa: f64,
}

impl CompositeModulus {
    /// The paper's law: the equibiaxial tangent ([`Tangent::Equibiaxial`]).
    pub fn new(
        material: Arc<dyn Hyperelastic>,
        model: Model,
        poisson: f64,
    ) -> Result<Self, MaterialError> {
        Self::with_tangent(material, model, Tangent::Equibiaxial, poisson)
    }

    /// The law with E_t taken from the `tangent` curve.
    pub fn with_tangent(
        material: Arc<dyn Hyperelastic>,
        model: Model,
        tangent: Tangent,
        poisson: f64,
    ) -> Result<Self, MaterialError> {
        let e0_star_pa = composite_modulus_pa(material.shear_modulus_pa(), poisson);
        if !(e0_star_pa > 0.0 && e0_star_pa.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "the initial composite modulus E0* is {e0_star_pa} Pa"
            )));
        }
        let law = ContactLaw::in_mode(material, tangent.mode())?;
        let table = (model == Model::Hyperelastic).then(|| TangentTable::new(&law));
        Ok(Self {
            model,
            law: Some(law),
            table,
            poisson,
            e0_star_pa,
        })
    }

    /// A linear-elastic solid: E* = E / (1 − ν²) with its own ν, at every
    /// stress.
    pub fn linear_elastic(solid: LinearElastic) -> Self {
        Self {
            model: Model::Linear,
            law: None,
            table: None,
            poisson: solid.poisson,
            e0_star_pa: solid.composite_modulus_pa(),
        }
    }

    /// Any material: a hyperelastic one under `model`, `tangent` and
    /// `poisson`, a linear one at its own constant E*.
    pub fn of_material(
        material: &Material,
        model: Model,
        tangent: Tangent,
        poisson: f64,
    ) -> Result<Self, MaterialError> {
        match material {
            Material::Linear(solid) => Ok(Self::linear_elastic(*solid)),
            Material::Hyperelastic(m) => Self::with_tangent(m.clone(), model, tangent, poisson),
        }
    }

    /// E0* = E0 / (1 − ν²), Pa.
    pub fn e0_star_pa(&self) -> f64 {
        self.e0_star_pa
    }

    /// The Poisson ratio in E0* (a linear material's own).
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// The curve E_t is taken from; None when the modulus is constant (a
    /// linear material).
    pub fn tangent_mode(&self) -> Option<Mode> {
        self.law.as_ref().map(ContactLaw::mode)
    }

    /// E_t* at the compressive stress S (≤ 0), Pa.
    pub fn at_stress_pa(&self, stress_pa: f64) -> Result<f64, MaterialError> {
        let law = match (&self.law, self.model) {
            (Some(law), Model::Hyperelastic) => law,
            _ => return Ok(self.e0_star_pa),
        };
        let tabulated = self.table.as_ref().and_then(|t| t.get(stress_pa));
        let e_t = match tabulated {
            Some(e_t) => e_t,
            // Outside the table: the exact inversion, or its error.
            None => law.tangent_at_stress_pa(stress_pa)?,
        };
        Ok(e_t / (1.0 - self.poisson * self.poisson))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_material::presets::paper_epdm;

    #[test]
    fn paper_epdm_moduli_match_the_paper() {
        let m = CompositeModulus::new(Arc::new(paper_epdm()), Model::Hyperelastic, 0.5).unwrap();
        // Section 2: E0 = 5.37 MPa, E0* = 7.16 MPa (rounded in the paper).
        assert!(
            (m.e0_star_pa() / 7.16e6 - 1.0).abs() < 2e-3,
            "{}",
            m.e0_star_pa()
        );
        let ratio = m.at_stress_pa(0.0).unwrap() / m.e0_star_pa();
        assert!((ratio - 2.0).abs() < 1e-9, "E_t*(0)/E0* = {ratio}");
        let linear = CompositeModulus::new(Arc::new(paper_epdm()), Model::Linear, 0.5).unwrap();
        assert_eq!(linear.at_stress_pa(-3e6).unwrap(), linear.e0_star_pa());
    }

    #[test]
    fn other_poisson_ratios_use_e0_from_mu0() {
        let nu = 0.3;
        let m = CompositeModulus::new(Arc::new(paper_epdm()), Model::Hyperelastic, nu).unwrap();
        let mu0 = paper_epdm().shear_modulus_pa();
        let e0_star = 2.0 * mu0 * (1.0 + nu) / (1.0 - nu * nu);
        assert!((m.e0_star_pa() / e0_star - 1.0).abs() < 1e-12);
        let ratio = m.at_stress_pa(0.0).unwrap() / m.e0_star_pa();
        assert!((ratio - 3.0 / (1.0 + nu)).abs() < 1e-9, "{ratio}");
    }

    #[test]
    fn first_contact_ratio_is_two_equibiaxial_and_one_uniaxial() {
        let models: [Arc<dyn Hyperelastic>; 2] = [
            Arc::new(paper_epdm()),
            Arc::new(hypercontact_material::NeoHookean::new(0.3e6).unwrap()),
        ];
        for material in models {
            for (tangent, expected) in [(Tangent::Equibiaxial, 2.0), (Tangent::Uniaxial, 1.0)] {
                let m = CompositeModulus::with_tangent(
                    material.clone(),
                    Model::Hyperelastic,
                    tangent,
                    0.5,
                )
                .unwrap();
                assert_eq!(m.tangent_mode(), Some(tangent.mode()));
                let ratio = m.at_stress_pa(0.0).unwrap() / m.e0_star_pa();
                assert!(
                    (ratio - expected).abs() < 1e-9,
                    "{} {tangent:?}: E_t*(0)/E0* = {ratio}",
                    material.family()
                );
                // Compression stiffens both.
                assert!(m.at_stress_pa(-1e6).unwrap() > m.at_stress_pa(0.0).unwrap());
            }
        }
    }

    #[test]
    fn a_linear_material_is_constant_whatever_the_law_says() {
        let solid = LinearElastic::new(2e6, 0.49).unwrap();
        let analytic = 2e6 / (1.0 - 0.49 * 0.49);
        for tangent in [Tangent::Equibiaxial, Tangent::Uniaxial] {
            let m = CompositeModulus::of_material(
                &Material::Linear(solid),
                Model::Hyperelastic,
                tangent,
                0.5,
            )
            .unwrap();
            assert_eq!(m.e0_star_pa(), analytic);
            assert_eq!(m.poisson(), 0.49);
            assert_eq!(m.tangent_mode(), None);
            for s in [0.0, -1e5, -1e9] {
                assert_eq!(m.at_stress_pa(s).unwrap(), analytic);
            }
        }
    }
}
