//! The 2-D DFT by its definition, O(N²) per point: the reference the fast
//! transforms are tested against (tests only).

use std::f64::consts::TAU;

use rustfft::num_complex::Complex64;

use super::Direction;

/// X[k, l] = Σ_m Σ_n x[m, n] e^{∓2πi (km/rows + ln/cols)} of a row-major
/// `rows × cols` array, unnormalised.
pub(crate) fn dft2(
    x: &[Complex64],
    rows: usize,
    cols: usize,
    direction: Direction,
) -> Vec<Complex64> {
    let sign = match direction {
        Direction::Forward => -1.0,
        Direction::Inverse => 1.0,
    };
    // Reduced products km mod rows keep the angles small and exact.
    let phase = |k: usize, m: usize, n: usize| TAU * ((k * m) % n) as f64 / n as f64;
    let mut out = vec![Complex64::ZERO; rows * cols];
    for k in 0..rows {
        for l in 0..cols {
            let mut sum = Complex64::ZERO;
            for m in 0..rows {
                for n in 0..cols {
                    let angle = phase(k, m, rows) + phase(l, n, cols);
                    sum += x[m * cols + n] * Complex64::from_polar(1.0, sign * angle);
                }
            }
            out[k * cols + l] = sum;
        }
    }
    out
}

/// `map_rows × map_cols` real values zero-extended to a `rows × cols`
/// complex array.
pub(crate) fn embed(
    map: &[f64],
    (map_rows, map_cols): (usize, usize),
    rows: usize,
    cols: usize,
) -> Vec<Complex64> {
    let mut out = vec![Complex64::ZERO; rows * cols];
    for i in 0..map_rows {
        for j in 0..map_cols {
            out[i * cols + j] = Complex64::new(map[i * map_cols + j], 0.0);
        }
    }
    out
}

/// The largest |a − b| over two arrays.
pub(crate) fn max_difference(a: &[Complex64], b: &[Complex64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max)
}
