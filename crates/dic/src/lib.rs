//! Digital image correlation of tensile speckle sequences: the `dic` stage.
//!
//! - [`bspline`], [`icgn`], [`zncc_fft`]: subset matching (bicubic B-spline
//!   interpolation, IC-GN, FFT ZNCC integer guess); `vector_isa` runs
//!   IC-GN's loops on the CPU's widest vector instructions;
//! - [`subset_tracking`]: POIs through a sequence (reliability-guided
//!   propagation, incremental reference updating);
//! - [`markers`]: centroid tracking of painted dots;
//! - [`strain`]: deformation gradient, principal stretches, Green–Lagrange;
//! - [`region`]: the analysed pixels (rectangle, polygon, mask);
//! - [`gray`]: frames as fractions of the camera's full scale;
//! - [`sequence`]: the raw files; [`stage`]: the stage, computed by
//!   [`analysis`].

pub mod analysis;
pub mod bspline;
pub mod error;
pub mod gray;
pub mod icgn;
pub mod markers;
pub mod poi_grid;
pub mod region;
pub mod sequence;
pub mod stage;
pub mod strain;
pub mod subset_tracking;
mod vector_isa;
pub mod zncc_fft;

pub use error::DicError;
pub use gray::GrayImage;
pub use stage::{Dic, DicFieldTable, DicParams, DicTensileTable, LoadingAxis, Method};

use hypercontact_core::Registry;

/// Registers this crate's stage kinds.
pub fn register(registry: &mut Registry) {
    registry.add(stage::Dic);
}
