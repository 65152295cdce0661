//! Contact theories from the height spectrum (issue #16): the two classical
//! alternatives the paper sets its incremental model against.
//!
//! - [`spectrum`]: the isotropic spectrum in Persson's normalisation and the
//!   integrals ∫ q^k C dq (moments m0, m2, m4);
//! - [`persson`]: Persson's theory (2001) and Yang & Persson's correction
//!   (2008), with the mean separation of Persson (2007);
//! - [`gw`]: Greenwood–Williamson's asperity model, its summits from the
//!   moments (Nayak 1971, McCool 1986);
//! - [`curve`]: the load rows and the paper's tangent modulus on them;
//! - [`stage`]: the `persson` and `greenwood-williamson` stages.
pub mod curve;
pub mod error;
pub mod gw;
pub mod persson;
mod source;
pub mod spectrum;
pub mod stage;

pub use error::ClassicalError;

/// Adds this crate's stages to the registry.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::PerssonStage);
    registry.add(stage::GreenwoodWilliamson);
}
