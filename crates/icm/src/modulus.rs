//! The composite modulus the ICM integrates with: E_t*(S) of the paper's
//! Eqs. (5)–(6) for the hyperelastic model, or the constant E0* of Wang's
//! original (linear) model.
//!
//! Conventions (SPEC, "Ogden model" and "Incremental contact model"):
//! - E0 = 2 μ0 (1 + ν), E0* = E0 / (1 − ν²)
//!   ([`hypercontact_material::composite_modulus_pa`]).
//! - Hyperelastic: E_t* = E_t(φ⁻¹(S)) / (1 − ν²) with φ the equibiaxial
//!   nominal stress (Eq. 2) and E_t = dφ/dε (Eq. 6), at the compressive
//!   S = −F/A ≤ 0, so ε ≤ 0. E_t(0) = 6 μ0, hence E_t*/E0* = 3 / (1 + ν)
//!   at first contact: 2 for ν = ½.
//! - For ν < ½ the material law stays the incompressible one (the Ogden
//!   form has no bulk term); only E0 and the 1/(1 − ν²) factor use ν.

use std::sync::Arc;

use hypercontact_core::Choice;
use hypercontact_material::{ContactLaw, Hyperelastic, MaterialError, composite_modulus_pa};

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

/// E_t*(S) for one material, model and Poisson ratio.
#[derive(Clone, Debug)]
pub struct CompositeModulus {
    model: Model,
    law: ContactLaw,
    /// The compressive branch of E_t(S), for speed; None for `linear`.
    table: Option<TangentTable>,
    poisson: f64,
    e0_star_pa: f64,
}

impl CompositeModulus {
    pub fn new(
        material: Arc<dyn Hyperelastic>,
        model: Model,
        poisson: f64,
    ) -> Result<Self, MaterialError> {
        let e0_star_pa = composite_modulus_pa(material.shear_modulus_pa(), poisson);
        if !(e0_star_pa > 0.0 && e0_star_pa.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "the initial composite modulus E0* is {e0_star_pa} Pa"
            )));
        }
        let law = ContactLaw::new(material)?;
        let table = (model == Model::Hyperelastic).then(|| TangentTable::new(&law));
        Ok(Self {
            model,
            law,
            table,
            poisson,
            e0_star_pa,
        })
    }

    /// E0* = E0 / (1 − ν²), Pa.
    pub fn e0_star_pa(&self) -> f64 {
        self.e0_star_pa
    }

    /// E_t* at the compressive stress S (≤ 0), Pa.
    pub fn at_stress_pa(&self, stress_pa: f64) -> Result<f64, MaterialError> {
        match self.model {
            Model::Linear => Ok(self.e0_star_pa),
            Model::Hyperelastic => {
                let tabulated = self.table.as_ref().and_then(|t| t.get(stress_pa));
                let e_t = match tabulated {
                    Some(e_t) => e_t,
                    // Outside the table: the exact inversion, or its error.
                    None => self.law.tangent_at_stress_pa(stress_pa)?,
                };
                Ok(e_t / (1.0 - self.poisson * self.poisson))
            }
        }
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
}
