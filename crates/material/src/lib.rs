//! Hyperelastic materials for hypercontact.
//!
//! - [`model`]: the [`Hyperelastic`] trait (strain energy, nominal stress and
//!   its slope in UT, PT and BT, typed [`Parameter`]s) and its
//!   implementations;
//! - [`contact`]: the paper's Eq. (2) φ(ε), its inverse and Eq. (6) E_t,
//!   which the incremental contact model evaluates;
//! - [`mod@material`]: what a material table holds, a hyperelastic model or a
//!   linear solid ([`Material`]);
//! - [`table`]: the `material` table that carries a material between stages;
//! - [`tensile`], [`mod@fit`], [`stability`]: tensile data, the simultaneous
//!   UT/PT/BT least-squares fit and the Drucker stability check, behind the
//!   stages `tensile-table`, `material-fit` and `material-preset`;
//! - [`constants`], [`constants_file`]: any material by its constants,
//!   behind the stage `material`.

pub mod arruda_boyce;
pub mod bootstrap;
mod compensated_sum;
pub mod constants;
pub mod constants_file;
pub mod constants_stage;
pub mod contact;
pub mod drucker_windows;
pub mod family;
pub mod fit;
pub mod fit_stage;
mod fit_tables;
pub mod invariants;
pub mod lsi;
pub mod material;
pub mod model;
pub mod mooney_rivlin;
pub mod neo_hookean;
pub mod nnls;
pub mod ogden;
pub mod parameter;
pub mod preset_stage;
pub mod presets;
pub mod quality;
pub mod sample;
pub mod stability;
pub mod table;
pub mod tensile;
pub mod tensile_stage;
pub mod testing;
pub mod yeoh;

use hypercontact_core::RowPlace;

pub use arruda_boyce::ArrudaBoyce;
pub use contact::{ContactLaw, MonotonicRange};
pub use family::Family;
pub use fit::{Conditioning, Constraint, FitOptions, FitResult, Residual, fit};
pub use material::{LinearElastic, Material};
pub use model::{Hyperelastic, Mode, Poisson, composite_modulus_pa, youngs_modulus_pa};
pub use mooney_rivlin::MooneyRivlin;
pub use neo_hookean::NeoHookean;
pub use ogden::Ogden;
pub use parameter::{ParamUnit, Parameter};
pub use tensile::TensileData;
pub use yeoh::Yeoh;

/// Errors of the material crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialError {
    #[error(
        "stress {stress_pa:.6e} Pa lies outside the range where φ, the {mode} nominal stress, is \
         monotonic and invertible ({min_pa:.6e} … {max_pa:.6e} Pa, strain {eps_min:.4} … \
         {eps_max:.4})"
    )]
    OutsideMonotonicRange {
        /// The test mode of φ: `BT` (the paper's) or `UT`.
        mode: &'static str,
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
    /// A tensile table that cannot be fitted; `origin` is the file or input.
    #[error("{origin}: {}column `{column}`: {message}", place.map(|p| format!("{p}, ")).unwrap_or_default())]
    Tensile {
        origin: String,
        /// The file line of the row (CSV), or its 1-based row in a table
        /// without lines.
        place: Option<RowPlace>,
        column: String,
        message: String,
    },
    #[error("fit of model `{model}`: {message}")]
    Fit { model: String, message: String },
    #[error("unknown model `{name}` (known: {known})")]
    UnknownModel { name: String, known: String },
}

/// Registers this crate's stage kinds.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry
        .add(tensile_stage::TensileTable)
        .add(fit_stage::MaterialFit)
        .add(preset_stage::MaterialPreset)
        .add(constants_stage::MaterialConstants);
}
