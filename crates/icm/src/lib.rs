//! The incremental contact model (ICM) of Wang, extended to hyperelastic
//! solids with the tangent modulus (the paper's section 4, Eqs. 4–7).
//!
//! - [`solver`]: the integration over a truncation profile (pure, on slices);
//! - [`modulus`]: E_t*(S) of a material (hyperelastic) or E0* (linear);
//! - [`tangent`]: the tangent-modulus load over the steps of any linear contact
//!   model (boundary elements, Persson, Greenwood–Williamson);
//! - [`tangent_table`]: E_t(S) tabulated once, so each plane costs nanoseconds;
//! - [`bands`]: bootstrap bands of any tangent-modulus model over the fit's
//!   replicate materials;
//! - [`law_params`]: the contact-law parameters every contact model takes;
//! - [`stage`]: the `icm` stage.

pub mod bands;
pub mod law_params;
pub mod modulus;
pub mod solver;
pub mod stage;
pub mod tangent;
pub mod tangent_table;

pub use law_params::LawParams;
pub use modulus::{CompositeModulus, Model, Tangent};
pub use solver::{ProfileSlices, Scheme, Solution, SolveError, solve};

/// Errors of the ICM stage.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IcmError {
    #[error("input `profile`: {0}")]
    Profile(String),
    #[error("input `material`: {0}")]
    Material(hypercontact_material::MaterialError),
    #[error(transparent)]
    Solve(#[from] SolveError),
}

// Not `#[from]`: the message holds the cause, so it is not also the source.
impl From<hypercontact_material::MaterialError> for IcmError {
    fn from(e: hypercontact_material::MaterialError) -> Self {
        IcmError::Material(e)
    }
}

/// Registers this crate's stage kinds.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::Icm);
}
