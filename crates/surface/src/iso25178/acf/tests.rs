use std::f64::consts::TAU;

use ndarray::Array2;

use super::*;
use crate::iso25178::ISO_DECAY_THRESHOLD;
use crate::iso25178::tests::{gaussian_noise, smoothed_noise};

/// The definition summed directly over every pair of measured points
/// (O(N²) per lag): the FFT's sums, overlap counts and normalisation.
#[test]
fn the_fft_acf_is_the_direct_sum_over_measured_pairs() {
    let mut h = gaussian_noise(9, 7, 3);
    h[[2, 3]] = f64::NAN;
    h[[8, 0]] = f64::NAN;
    h[[0, 6]] = f64::NAN;
    let acf = autocorrelation(&h, 1e-6, 2e-6).unwrap();
    assert_eq!(acf.max_lag(), (8, 6));
    let measured: Vec<f64> = h.iter().copied().filter(|v| !v.is_nan()).collect();
    let mean = measured.iter().sum::<f64>() / measured.len() as f64;
    let direct = |a: isize, b: isize| {
        let (mut n, mut s) = (0usize, 0.0);
        for i in 0..9isize {
            for j in 0..7isize {
                let (k, l) = (i + a, j + b);
                if !(0..9).contains(&k) || !(0..7).contains(&l) {
                    continue;
                }
                let (p, q) = (h[[i as usize, j as usize]], h[[k as usize, l as usize]]);
                if !p.is_nan() && !q.is_nan() {
                    n += 1;
                    s += (p - mean) * (q - mean);
                }
            }
        }
        if n == 0 { f64::NAN } else { s / n as f64 }
    };
    let variance = direct(0, 0);
    for a in -8..=8 {
        for b in -6..=6 {
            let (fast, slow) = (acf.at(a, b), direct(a, b) / variance);
            assert!(
                (fast.is_nan() && slow.is_nan()) || (fast - slow).abs() < 1e-12,
                "({a}, {b}): {fast} vs {slow}"
            );
        }
    }
    assert_eq!(acf.at(0, 0), 1.0);
    assert!(acf.at(9, 0).is_nan());
}

/// h = A sin(2πx/L), constant along y: f_ACF(τx, τy) = cos(2πτx/L) (up to
/// O(L/(n − τ)) on the finite map), decay to 0.2 first along x at τ = L·acos(0.2)/(2π), never
/// along y: Sal is that τ and Str is small.
#[test]
fn a_sinusoidal_ridge_texture_has_a_cosine_acf_and_a_small_str() {
    let (period, dx) = (32usize, 0.5e-6);
    let h = Array2::from_shape_fn((16 * period, 128), |(i, _)| {
        (TAU * i as f64 / period as f64).sin() * 1e-6
    });
    let acf = autocorrelation(&h, dx, dx).unwrap();
    for a in 0..40isize {
        let expected = (TAU * a as f64 / period as f64).cos();
        assert!((acf.at(a, 0) - expected).abs() < 0.02, "{a}");
        assert!((acf.at(a, 17) - expected).abs() < 0.02, "{a}");
    }
    let decay = acf.decay_lengths(ISO_DECAY_THRESHOLD).unwrap();
    let sal = period as f64 * dx * 0.2f64.acos() / TAU;
    assert!(
        (decay.sal_m() / sal - 1.0).abs() < 0.01,
        "{decay:?} vs {sal}"
    );
    assert!(decay.shortest_direction_deg < 1e-9);
    // Along y and within ~6° of it (where the ray's x lag stays under the
    // 7 px of the decay) f_ACF never falls to 0.2: those directions count
    // with the search ellipse's radius, 63 px along y (half of 128 columns)
    // and a little more off the axis (the ellipse reaches 255 px along x).
    assert!(!decay.all_decayed && (decay.longest_direction_deg - 90.0).abs() < 7.0);
    assert!(
        (decay.longest_m / (63.0 * dx) - 1.0).abs() < 0.01,
        "{decay:?}"
    );
    assert!(decay.str() < 0.12, "{decay:?}");
}

/// Uncorrelated heights: f_ACF is 1 at the origin and ≈ 0 at every other
/// lag, so the bilinear reading falls to 0.2 within one pixel in every
/// direction (at 0.8 px along the axes, (1 − √0.2)·√2 = 0.78 px along the
/// diagonals): Sal ≈ 0.78 px, Str ≈ 0.97; the radial average is 1 then ≈ 0,
/// so the correlation length is below one pixel.
#[test]
fn white_noise_decays_within_a_pixel() {
    let dx = 1e-6;
    let h = gaussian_noise(256, 256, 11);
    let acf = autocorrelation(&h, dx, dx).unwrap();
    let decay = acf.decay_lengths(ISO_DECAY_THRESHOLD).unwrap();
    assert!(decay.all_decayed);
    assert!(
        (decay.sal_m() / (0.78 * dx) - 1.0).abs() < 0.05,
        "{decay:?}"
    );
    assert!(decay.str() > 0.9 && decay.str() <= 1.0, "{decay:?}");
    let xi = acf.correlation_length_m();
    assert!(xi > 0.3 * dx && xi < dx, "{xi}");
}

/// Noise smoothed by a Gaussian kernel exp(−x²/(2wx²) − y²/(2wy²)) has
/// f_ACF = exp(−τx²/(4wx²) − τy²/(4wy²)): it decays to s = 0.2 at
/// τ = 2w·√ln 5, fastest along x, slowest along y, so Sal = 2wx·√ln 5 and
/// Str = wx/wy; isotropic, the radial average falls to 1/e at 2w.
#[test]
fn gaussian_correlated_noise_has_its_analytic_sal_str_and_length() {
    let dx = 1e-6;
    let (wx, wy) = (2.0, 4.0);
    let h = smoothed_noise(512, 512, wx, wy, 5);
    let decay = autocorrelation(&h, dx, dx)
        .unwrap()
        .decay_lengths(ISO_DECAY_THRESHOLD)
        .unwrap();
    let root = 5f64.ln().sqrt();
    assert!(
        (decay.sal_m() / (2.0 * wx * root * dx) - 1.0).abs() < 0.05,
        "{decay:?}"
    );
    assert!(
        (decay.longest_m / (2.0 * wy * root * dx) - 1.0).abs() < 0.05,
        "{decay:?}"
    );
    assert!((decay.str() - wx / wy).abs() < 0.04, "{decay:?}");
    assert!(decay.shortest_direction_deg < 10.0 || decay.shortest_direction_deg > 170.0);
    assert!(
        (decay.longest_direction_deg - 90.0).abs() < 10.0,
        "{decay:?}"
    );
    let w = 3.0;
    let h = smoothed_noise(512, 512, w, w, 6);
    let xi = autocorrelation(&h, dx, dx).unwrap().correlation_length_m();
    assert!((xi / (2.0 * w * dx) - 1.0).abs() < 0.05, "{xi}");
    // The same pixels 1000 times further apart along x: the decay length
    // along y is unchanged, along x a thousand times longer.
    let acf = autocorrelation(&h, 1000.0 * dx, dx).unwrap();
    let decay = acf.decay_lengths(ISO_DECAY_THRESHOLD).unwrap();
    let expected = 2.0 * w * root * dx;
    assert!((decay.sal_m() / expected - 1.0).abs() < 0.05, "{decay:?}");
    assert!(
        (decay.shortest_direction_deg - 90.0).abs() < 1e-9,
        "{decay:?}"
    );
    assert!(
        (decay.longest_m / (1000.0 * expected) - 1.0).abs() < 0.05,
        "{decay:?}"
    );
    assert!(acf.correlation_length_m().is_finite());
}

#[test]
fn bad_thresholds_and_flat_maps() {
    let h = gaussian_noise(8, 8, 1);
    let acf = autocorrelation(&h, 1e-6, 1e-6).unwrap();
    assert!(acf.decay_lengths(1.0).is_err() && acf.decay_lengths(-0.1).is_err());
    let flat = autocorrelation(&Array2::from_elem((8, 8), 1e-6), 1e-6, 1e-6).unwrap();
    assert!(flat.values.iter().all(|v| v.is_nan()));
    let decay = flat.decay_lengths(ISO_DECAY_THRESHOLD).unwrap();
    assert!(decay.sal_m().is_nan() && decay.str().is_nan());
    assert!(flat.correlation_length_m().is_nan());
    // one row: nothing to search across x, but no panic
    let row = autocorrelation(&gaussian_noise(1, 16, 2), 1e-6, 1e-6).unwrap();
    assert!(row.decay_lengths(ISO_DECAY_THRESHOLD).is_ok());
    assert!(autocorrelation(&h, -1.0, 1e-6).is_err());
}
