//! Synthetic self-affine height maps by Fourier filtering, for tests,
//! benchmarks and the shipped sample (not used by the stage).
//!
//! White complex Gaussian noise is shaped by |ĥ(q)| ∝ q^(−1−H), so the 2-D
//! PSD falls as C(q) ∝ q^(−2−2H) (the radial convention of the SPEC), for
//! 2π/L ≤ |q| ≤ the Nyquist wave-vector; the mean (q = 0) is removed. The
//! real part of the inverse transform is kept (it has the same spectrum), and
//! the map is scaled to the requested rms height. The result is periodic.

use ndarray::Array2;
use rand::RngExt;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;

/// A self-affine map of `nx × ny` pixels of `pixel_m`, Hurst exponent
/// `hurst`, rms height `rms_m`, from a fixed `seed`. Axis 0 is x.
pub fn self_affine_map(
    nx: usize,
    ny: usize,
    pixel_m: f64,
    hurst: f64,
    rms_m: f64,
    seed: u64,
) -> Array2<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lx, ly) = (nx as f64 * pixel_m, ny as f64 * pixel_m);
    // Signed FFT frequency index: 0, 1, …, n/2, −(n/2 − 1), …, −1.
    let wave = |k: usize, n: usize, l: f64| {
        let signed = if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        };
        2.0 * std::f64::consts::PI * signed / l
    };
    let mut spectrum: Vec<Complex64> = Vec::with_capacity(nx * ny);
    for kx in 0..nx {
        let qx = wave(kx, nx, lx);
        for ky in 0..ny {
            let qy = wave(ky, ny, ly);
            let q = qx.hypot(qy);
            let noise = Complex64::new(rng.sample(StandardNormal), rng.sample(StandardNormal));
            spectrum.push(if q > 0.0 {
                noise * q.powf(-1.0 - hurst)
            } else {
                Complex64::new(0.0, 0.0)
            });
        }
    }
    inverse_fft_2d(&mut spectrum, nx, ny);

    let mut heights: Vec<f64> = spectrum.into_iter().map(|c| c.re).collect();
    let mean = heights.iter().sum::<f64>() / heights.len() as f64;
    let rms =
        (heights.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / heights.len() as f64).sqrt();
    let scale = if rms > 0.0 { rms_m / rms } else { 0.0 };
    for h in &mut heights {
        *h = (*h - mean) * scale;
    }
    Array2::from_shape_vec((nx, ny), heights).expect("nx · ny values")
}

/// In-place 2-D inverse FFT of a row-major `nx × ny` array (unnormalised:
/// the scale is fixed afterwards anyway).
fn inverse_fft_2d(data: &mut [Complex64], nx: usize, ny: usize) {
    let mut planner = FftPlanner::<f64>::new();
    // Rows (axis 1) are contiguous: one call transforms them all.
    planner.plan_fft_inverse(ny).process(data);
    // Columns (axis 0) go through a buffer, which keeps memory at one map.
    let column_fft = planner.plan_fft_inverse(nx);
    let mut column = vec![Complex64::new(0.0, 0.0); nx];
    for iy in 0..ny {
        for ix in 0..nx {
            column[ix] = data[ix * ny + iy];
        }
        column_fft.process(&mut column);
        for ix in 0..nx {
            data[ix * ny + iy] = column[ix];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_has_the_asked_rms_and_zero_mean() {
        let h = self_affine_map(64, 32, 1e-5, 0.8, 1e-5, 7);
        let n = h.len() as f64;
        let mean = h.sum() / n;
        let rms = (h.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
        assert!(mean.abs() < 1e-18, "mean {mean}");
        assert!((rms - 1e-5).abs() < 1e-15, "rms {rms}");
        assert_eq!(h, self_affine_map(64, 32, 1e-5, 0.8, 1e-5, 7), "seeded");
    }

    #[test]
    fn rms_of_differences_scales_with_the_hurst_exponent() {
        // For a self-affine profile the height difference over a lag δ grows
        // as δ^H; check the exponent from lags 2 and 8 pixels along x.
        let hurst = 0.8;
        let (nx, ny) = (512, 512);
        let h = self_affine_map(nx, ny, 1.0, hurst, 1.0, 11);
        let rms_diff = |lag: usize| {
            let mut s = 0.0;
            for ix in 0..nx - lag {
                for iy in 0..ny {
                    s += (h[[ix + lag, iy]] - h[[ix, iy]]).powi(2);
                }
            }
            (s / ((nx - lag) * ny) as f64).sqrt()
        };
        let slope = (rms_diff(8) / rms_diff(2)).ln() / 4.0_f64.ln();
        assert!((slope - hurst).abs() < 0.1, "fitted H = {slope}");
    }
}
