//! Hyperelastic materials for hypercontact.
//!
//! - [`model`]: the [`Hyperelastic`] trait (strain energy, nominal stress and
//!   its slope in UT, PT and BT) and its implementations;
//! - [`contact`]: the paper's Eq. (2) φ(ε), its inverse and Eq. (6) E_t,
//!   which the incremental contact model evaluates;
//! - [`table`]: the `material` table that carries a model between stages.

pub mod contact;
pub mod model;
pub mod ogden;
pub mod presets;
pub mod table;

pub use contact::{ContactLaw, MonotonicRange};
pub use model::{Hyperelastic, Mode};
pub use ogden::Ogden;

/// Errors of the material crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialError {
    #[error(
        "stress {stress_pa:.6e} Pa lies outside the range where φ is monotonic and invertible \
         ({min_pa:.6e} … {max_pa:.6e} Pa, strain {eps_min:.4} … {eps_max:.4})"
    )]
    OutsideMonotonicRange {
        stress_pa: f64,
        min_pa: f64,
        max_pa: f64,
        eps_min: f64,
        eps_max: f64,
    },
    #[error("material table: {0}")]
    Table(String),
    #[error("unknown material preset `{name}` (known: {known})")]
    UnknownPreset { name: String, known: String },
    #[error("invalid material: {0}")]
    Invalid(String),
}

/// Registers this crate's stage kinds.
pub fn register(_registry: &mut hypercontact_core::Registry) {}
