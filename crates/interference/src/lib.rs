//! The contact experiment's optics and camera (issue #14, `synth-contact`):
//! what a camera sees of a rubber sample pressed against quartz glass, from
//! the gap field between them (gap 0 = contact, dark by the half-wave loss).
//!
//! - [`film`]: the glass–gap–rubber stack's reflectance (Airy), and its
//!   average over a source spectrum;
//! - [`spectrum`]: the white LED (a sum of Gaussians) or a measured spectrum;
//! - [`lookup`]: the spectral average tabulated for rendering, with the
//!   incoherent limit beyond a coherence cutoff;
//! - [`geometry`]: the camera's placement on the sample and bilinear
//!   resampling of the gap field onto its pixels;
//! - [`camera`]: vignetting, shot and read noise, gain, quantisation;
//! - [`render`]: the chain for one frame.

pub mod camera;
pub mod error;
pub mod film;
pub mod geometry;
pub mod lookup;
pub mod render;
pub mod spectrum;

pub use camera::{Camera, CameraParams, Frame};
pub use error::InterferenceError;
pub use film::{Indices, SpectralAverage, Stack};
pub use geometry::{CameraGrid, GapMap, Placement, Similarity, resample};
pub use lookup::{ReflectanceTable, TableParams};
pub use render::{OpticsParams, expose, render_frame};
pub use spectrum::{GaussianLine, Spectrum};
