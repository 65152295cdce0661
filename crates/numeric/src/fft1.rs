//! 1-D transforms from the process's one planner (the plans the 2-D
//! transforms use), for the profile spectra that transform each line of a
//! map on its own. Crates outside this one reach rustfft and realfft only
//! through here and [`crate::fft2`].

use std::sync::Arc;

pub use realfft::{ComplexToReal, RealToComplex};
pub use rustfft::Fft;

pub use crate::fft2::{Complex64, Direction};

/// The complex transform of `len` points (`len` ≥ 1), in `direction`.
pub fn complex(len: usize, direction: Direction) -> Arc<dyn Fft<f64>> {
    crate::fft2::plans::complex(len, direction)
}

/// The real-to-complex transform of `len` points (`len` ≥ 1).
pub fn real_forward(len: usize) -> Arc<dyn RealToComplex<f64>> {
    crate::fft2::plans::real(len).0
}
