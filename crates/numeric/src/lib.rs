//! The numeric plumbing the stages share, each in one place and each giving
//! the same bits on any number of threads:
//!
//! - [`fft2`]: the 2-D FFT (real-to-complex and complex, any size, plans
//!   cached) and the fast transform sizes;
//! - [`reduce`]: the fixed-order parallel reduction (sums whose order of
//!   additions depends on the data's size only);
//! - [`zncc`]: the masked zero-normalised cross-correlation of a template
//!   against every placement in an image, by FFT and summed-area tables.
//!
//! This crate knows nothing of stages, tables or units: it computes on
//! slices, so any stage crate can use it without the core's types.

mod error;
pub mod fft1;
pub mod fft2;
pub mod reduce;
pub mod zncc;

pub use error::NumericError;
