//! One planner for the process, so a length is planned once whoever asks.
//!
//! rustfft's planners keep every plan they made (keyed by length and
//! direction) and choose the algorithm from the length and the CPU alone,
//! so a cached plan computes the same bits as a fresh one: caching saves
//! the planning (twiddle tables, SIMD detection) and nothing else changes.

use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

/// The two directions of a transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// X_k = Σ_n x_n e^{−2πi nk/N}
    Forward,
    /// x_n = Σ_k X_k e^{+2πi nk/N}, not divided by N
    Inverse,
}

fn complex_planner() -> &'static Mutex<FftPlanner<f64>> {
    static PLANNER: OnceLock<Mutex<FftPlanner<f64>>> = OnceLock::new();
    PLANNER.get_or_init(|| Mutex::new(FftPlanner::new()))
}

fn real_planner() -> &'static Mutex<RealFftPlanner<f64>> {
    static PLANNER: OnceLock<Mutex<RealFftPlanner<f64>>> = OnceLock::new();
    PLANNER.get_or_init(|| Mutex::new(RealFftPlanner::new()))
}

/// The complex transform of `len` points (`len` ≥ 1).
pub(crate) fn complex(len: usize, direction: Direction) -> Arc<dyn Fft<f64>> {
    // A poisoned lock only means another thread panicked while planning;
    // the planner's cache holds finished plans only.
    let mut planner = complex_planner()
        .lock()
        .unwrap_or_else(PoisonError::into_inner);
    match direction {
        Direction::Forward => planner.plan_fft_forward(len),
        Direction::Inverse => planner.plan_fft_inverse(len),
    }
}

/// The real-to-complex transform of `len` points and its inverse.
pub(crate) fn real(len: usize) -> (Arc<dyn RealToComplex<f64>>, Arc<dyn ComplexToReal<f64>>) {
    let mut planner = real_planner()
        .lock()
        .unwrap_or_else(PoisonError::into_inner);
    (planner.plan_fft_forward(len), planner.plan_fft_inverse(len))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rustfft::num_complex::Complex64;

    #[test]
    fn a_cached_plan_computes_what_a_fresh_one_does() {
        for len in [1, 2, 7, 60, 97, 250, 1024] {
            let signal: Vec<Complex64> = (0..len)
                .map(|k| Complex64::new((k as f64 * 0.37).sin(), (k as f64 * 1.3).cos()))
                .collect();
            let fresh = FftPlanner::<f64>::new().plan_fft_forward(len);
            let (mut a, mut b) = (signal.clone(), signal);
            fresh.process(&mut a);
            // twice through the cache: the second is the stored plan
            complex(len, Direction::Forward);
            complex(len, Direction::Forward).process(&mut b);
            assert_eq!(a, b, "{len}");
        }
    }
}
