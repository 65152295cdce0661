//! The workspace's one 2-D FFT: real-to-complex ([`RealFft2`], with a fused
//! filter-and-return pass for convolutions and correlations) and complex
//! ([`ComplexFft2`]), on grids of any size, with the fast sizes
//! 2^a 3^b 5^c to pad to ([`fast_size`], [`fast_even_size`]).
//!
//! Both compute the DFT X[k, l] = Σ_m Σ_n x[m, n] e^{−2πi (km/R + ln/C)} of a
//! row-major R × C array by the row-column method (the 2-D DFT is a 1-D DFT
//! along every row followed by one down every column: Cooley, Lewis & Welch,
//! "The fast Fourier transform and its applications", IEEE Trans. Educ. 12,
//! 1969), the rows (contiguous) first. Plans come from one process-wide
//! cache (`plans.rs`). Rows and columns are spread over rayon's threads, each
//! transformed whole by one of them, and nothing is summed across threads:
//! the bits do not depend on the thread count. (Across machines, the SIMD
//! kernels rustfft picks for the CPU may move the last bits.)

mod complex;
#[cfg(test)]
mod direct;
pub(crate) mod plans;
mod real;
mod sizes;
mod transpose;

pub use complex::ComplexFft2;
pub use plans::Direction;
pub use real::{RealFft2, RealWorkspace};
pub use rustfft::num_complex::Complex64;
pub use sizes::{fast_even_size, fast_size};
