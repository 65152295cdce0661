use std::f64::consts::{PI, SQRT_2, TAU};

use hypercontact_core::{Context, Field, Params};
use ndarray::Array2;

use super::*;
use crate::analysis::analyse;
use crate::surface_stage::SurfaceParams;

/// A deterministic uniform sequence in [0, 1) (a 64-bit LCG).
fn uniforms(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A self-affine profile of n points by random-phase Fourier synthesis:
/// amplitude |ĥ_k| ∝ q_k^(−(1+2H)/2) for k = 1 … n/2 − 1, so the periodogram
/// is exactly C ∝ q^(−1−2H); periodic, rms about 1 µm.
fn self_affine(n: usize, hurst: f64, seed: u64) -> Vec<f64> {
    let mut next = uniforms(seed);
    let modes: Vec<(f64, f64)> = (1..n / 2)
        .map(|k| ((k as f64).powf(-(1.0 + 2.0 * hurst) / 2.0), TAU * next()))
        .collect();
    let mut h: Vec<f64> = (0..n)
        .map(|i| {
            modes
                .iter()
                .enumerate()
                .map(|(m, (a, phase))| {
                    let k = (m + 1) as f64;
                    a * (TAU * k * i as f64 / n as f64 + phase).cos()
                })
                .sum()
        })
        .collect();
    let rms = (h.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    h.iter_mut().for_each(|v| *v *= 1e-6 / rms);
    h
}

fn params(f: impl FnOnce(&mut SurfaceParams)) -> hypercontact_core::Checked<SurfaceParams> {
    let mut p = SurfaceParams::default();
    f(&mut p);
    p.check().unwrap()
}

fn line(values: &[f64], dx_m: f64) -> Field {
    Field::new(
        Array2::from_shape_vec((values.len(), 1), values.to_vec()).unwrap(),
        dx_m,
        dx_m,
    )
    .unwrap()
}

/// The rows of one direction of a PSD table.
fn rows(psd: &PsdTable, direction: &str) -> (Vec<f64>, Vec<f64>) {
    psd.direction
        .iter()
        .zip(psd.q_per_m.iter().zip(&psd.c))
        .filter(|(d, _)| d.as_str() == direction)
        .map(|(_, (q, c))| (*q, *c))
        .unzip()
}

#[test]
fn gaps_are_filled_linearly_and_ends_held() {
    let nan = f64::NAN;
    let mut h = [nan, 1.0, nan, nan, 4.0, nan];
    assert_eq!(fill_linear(&mut h, false), 4);
    assert_eq!(h, [1.0, 1.0, 2.0, 3.0, 4.0, 4.0]);
    // Periodic: from h[4] = 4 across the wrap to h[1] = 1, three steps.
    let mut h = [nan, 1.0, nan, nan, 4.0, nan];
    assert_eq!(fill_linear(&mut h, true), 4);
    assert_eq!(h, [2.0, 1.0, 2.0, 3.0, 4.0, 3.0]);
    let mut h = [nan, nan];
    assert_eq!(fill_linear(&mut h, false), 0);
    assert!(h.iter().all(|v| v.is_nan()));
}

// A straight tilted line (with gaps) detrends to zero; the stage then
// refuses it as flat rather than give a PSD of rounding noise.
#[test]
fn a_tilted_straight_line_detrends_to_zero() {
    let mut h: Vec<f64> = (0..100).map(|i| 3e-3 + 2e-6 * i as f64).collect();
    h[7] = f64::NAN;
    h[50] = f64::NAN;
    remove_line(&mut h).unwrap();
    let worst = h
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(worst < 1e-12 * 3.2e-3, "{worst}");
    assert!(h[7].is_nan());
    let mut one = [1.0, f64::NAN];
    assert!(remove_line(&mut one).is_err());
    let straight: Vec<f64> = (0..64).map(|i| 1e-6 * i as f64).collect();
    let e = analyse(line(&straight, 1e-6), &params(|_| {}), &Context::new("t"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("flat"), "{e}");
}

// h = A sin(2π i/P) over whole periods, P = 64 samples: σ = Rq = A/√2,
// Ra = A·2cot(π/P)/P (the mean |sin| over a period's samples), Rsk = 0,
// Rku = 3/2, Rp = Rv = A; the rms slope of the n − 1 forward differences
// (A/dx)·2 sin(θ/2) cos(θ(i + ½)), θ = 2π/P, is
// (2A/dx) sin(θ/2) √((n/2 − cos²(θ/2))/(n − 1)) (Σ cos² over whole periods
// is n/2, less the missing last term cos²(θ(n − ½)) = cos²(θ/2)); periodic,
// the PSD peaks at k0 = n/P with C = A²L/4.
#[test]
fn a_sinusoid_has_its_hand_values() {
    let (a_m, period, n, dx_m) = (2e-6, 64usize, 1024usize, 0.5e-6);
    let theta = TAU / period as f64;
    let h: Vec<f64> = (0..n).map(|i| a_m * (theta * i as f64).sin()).collect();
    let p = params(|p| {
        p.detrend = Detrend::Mean;
        p.periodic = true;
        p.reference = ReferenceKind::Percentile;
        p.reference_percent = 50.0;
        // one wavevector a bin: the peak's bin is k0 alone
        p.bins_per_decade = 100;
    });
    let ctx = Context::new("sine");
    let a = analyse(line(&h, dx_m), &p, &ctx).unwrap();
    let close = |x: f64, y: f64, what: &str| {
        assert!((x / y - 1.0).abs() < 1e-12, "{what}: {x} against {y}");
    };
    close(a.stats.sigma_m[0], a_m / SQRT_2, "σ");
    close(a.areal.sq_m[0], a_m / SQRT_2, "Rq");
    let ra = a_m * 2.0 / (PI / period as f64).tan() / period as f64;
    close(a.areal.sa_m[0], ra, "Ra");
    assert!(a.areal.ssk[0].abs() < 1e-9, "Rsk {}", a.areal.ssk[0]);
    close(a.areal.sku[0], 1.5, "Rku");
    close(a.areal.sp_m[0], a_m, "Rp");
    close(a.areal.sv_m[0], a_m, "Rv");
    let half = theta / 2.0;
    let nf = n as f64;
    let slope =
        2.0 * a_m / dx_m * half.sin() * ((nf / 2.0 - half.cos().powi(2)) / (nf - 1.0)).sqrt();
    close(a.stats.rms_slope[0], slope, "rms slope");
    close(a.areal.sdq[0], slope, "Rdq");
    let (q, c) = rows(&a.psd, "x");
    let peak = (0..c.len()).max_by(|&i, &j| c[i].total_cmp(&c[j])).unwrap();
    let l_m = nf * dx_m;
    let k0 = (n / period) as f64;
    close(q[peak], TAU * k0 / l_m, "peak q");
    close(c[peak], a_m * a_m * l_m / 4.0, "peak C");
    assert!(a.areal.sdr_percent[0].is_nan() && a.areal.str[0].is_nan());
    assert!(ctx.notes()[0].starts_with("line scan: a profile of 1024 points along x"));
}

/// The Hurst exponent of the synthesised profile, and its fit's R².
fn fitted_hurst(periodic: bool, seed: u64) -> (f64, f64) {
    let h = self_affine(4096, 0.7, seed);
    let p = params(|p| p.periodic = periodic);
    let a = analyse(line(&h, 1e-6), &p, &Context::new("t")).unwrap();
    (a.stats.hurst_x[0], a.stats.hurst_x_r2[0])
}

// Random-phase synthesis with C ∝ q^(−1−2H), H = 0.7, fitted over the
// stage's default range (4·dx … L/4): periodic (no window) the periodogram
// is the exact power law and only the bin averaging moves H (< 0.01).
// With the default Hann window a single profile's low-q bins, a few
// wavevectors each, mix neighbouring modes through the window's leakage
// (H = 0.645, R² = 0.958 for seed 3): the mean over eight profiles is
// within 0.03.
#[test]
fn a_self_affine_profile_gives_its_hurst_exponent_back() {
    let (periodic, r2) = fitted_hurst(true, 3);
    assert!(
        (periodic - 0.7).abs() < 0.01 && r2 > 0.999,
        "{periodic} {r2}"
    );
    let windowed: Vec<f64> = (1..=8).map(|seed| fitted_hurst(false, seed).0).collect();
    let mean = windowed.iter().sum::<f64>() / 8.0;
    assert!((mean - 0.7).abs() < 0.03, "{mean}: {windowed:?}");
    assert!(
        windowed.iter().all(|h| (h - 0.7).abs() < 0.1),
        "{windowed:?}"
    );
}

// The independent check: a line's PSD, Hurst exponent, σ and slope equal
// the x PSD and statistics the existing 2-D code gives for a map made of
// identical copies of the line (detrended plane = the line's trend; the
// y PSD of the copies is zero), with and without the filter to
// resolution_m (the 2-D Gaussian on copies is the profile Gaussian).
#[test]
fn a_line_matches_a_map_of_its_copies() {
    let mut h = self_affine(2000, 0.8, 11);
    for (i, v) in h.iter_mut().enumerate() {
        *v += 3e-9 * i as f64;
    }
    for resolution_m in [0.0, 3e-6] {
        let p = params(|p| p.resolution_m = resolution_m);
        let one = analyse(line(&h, 1e-6), &p, &Context::new("line")).unwrap();
        let copies = Array2::from_shape_fn((h.len(), 400), |(i, _)| h[i]);
        let copies = Field::new(copies, 1e-6, 1e-6).unwrap();
        let map = analyse(copies, &p, &Context::new("map")).unwrap();
        let (q1, c1) = rows(&one.psd, "x");
        let (q2, c2) = rows(&map.psd, "x");
        assert_eq!(q1.len(), q2.len());
        for k in 0..q1.len() {
            assert!((q1[k] / q2[k] - 1.0).abs() < 1e-12, "q, bin {k}");
            assert!(
                (c1[k] / c2[k] - 1.0).abs() < 1e-12,
                "C, bin {k}: {} vs {}",
                c1[k],
                c2[k]
            );
        }
        let same = |x: f64, y: f64, what: &str| {
            assert!((x / y - 1.0).abs() < 1e-12, "{what}: {x} vs {y}");
        };
        same(one.stats.hurst_x[0], map.stats.hurst_x[0], "H");
        same(one.stats.sigma_m[0], map.stats.sigma_m[0], "σ");
        same(one.stats.rms_slope[0], map.stats.rms_slope[0], "slope");
        same(one.areal.sq_m[0], map.areal.sq_m[0], "Rq = Sq");
        same(one.areal.sa_m[0], map.areal.sa_m[0], "Ra = Sa");
        assert_eq!(one.stats.nx, map.stats.nx);
        assert_eq!(one.height.values.dim(), (map.stats.nx[0] as usize, 1));
        // The autocorrelation along the line is the map's along x; the
        // height histogram has the map's densities (a copy's counts);
        // the slope, curvature and scale-dependent statistics are areal.
        let along: Vec<usize> = (0..map.acf.direction.len())
            .filter(|&i| map.acf.direction[i] == "x")
            .collect();
        assert!(one.acf.direction.iter().all(|d| d == "x"));
        assert_eq!(one.acf.lag_m.len(), along.len());
        for (k, &i) in along.iter().enumerate() {
            same(
                one.acf.lag_m[k].max(1e-300),
                map.acf.lag_m[i].max(1e-300),
                "lag",
            );
            assert!(
                (one.acf.acf[k] - map.acf.acf[i]).abs() < 1e-12,
                "ACF at lag {k}"
            );
        }
        assert!(one.distributions.quantity.iter().all(|q| q == "height"));
        let heights = map
            .distributions
            .quantity
            .iter()
            .filter(|q| *q == "height")
            .count();
        assert_eq!(one.distributions.count.len(), heights);
        let copies_kept = map.stats.ny[0]; // 400, or fewer once filtered
        for k in 0..heights {
            assert_eq!(
                copies_kept * one.distributions.count[k],
                map.distributions.count[k]
            );
            assert!(
                (one.distributions.density[k] - map.distributions.density[k]).abs()
                    <= 1e-12 * map.distributions.density[k].abs()
            );
        }
        assert!(one.scale_dependent.scale_m.is_empty());
    }
}

// The tables of a line: PSD rows along the line only, the other Hurst
// columns NaN and flagged, Sdr and Str NaN; a 1 × n map is the same
// profile along y.
#[test]
fn a_line_has_its_direction_only() {
    let h = self_affine(512, 0.6, 5);
    let p = params(|_| {});
    let along_x = analyse(line(&h, 1e-6), &p, &Context::new("x")).unwrap();
    assert!(along_x.psd.direction.iter().all(|d| d == "x"));
    let s = &along_x.stats;
    assert!(s.hurst_x[0].is_finite() && s.hurst_y[0].is_nan() && s.hurst_radial[0].is_nan());
    assert_eq!(s.hurst_y_flag[0], NOT_DEFINED);
    assert_eq!(s.hurst_radial_flag[0], NOT_DEFINED);
    assert_eq!((s.nx[0], s.ny[0]), (512, 1));
    let row = Array2::from_shape_vec((1, 512), h.clone()).unwrap();
    let along_y = analyse(Field::new(row, 2e-6, 1e-6).unwrap(), &p, &Context::new("y")).unwrap();
    assert!(along_y.psd.direction.iter().all(|d| d == "y"));
    assert_eq!(along_y.psd.c, along_x.psd.c);
    let t = &along_y.stats;
    assert_eq!(
        (t.hurst_y[0], t.hurst_x_flag[0].as_str()),
        (s.hurst_x[0], NOT_DEFINED)
    );
    assert_eq!(
        (t.nx[0], t.ny[0], t.dx_m[0], t.dy_m[0]),
        (1, 512, 2e-6, 1e-6)
    );
    assert_eq!(along_y.height.values.dim(), (1, 512));
    assert_eq!(
        along_y.height.values.iter().collect::<Vec<_>>(),
        along_x.height.values.iter().collect::<Vec<_>>()
    );
}

// Sal (to 0.2) and the correlation length (to 1/e) of a line against the
// profile's autocorrelation summed directly over the pairs of each lag
// (mean removed, normalised by the overlap count), the first crossing
// interpolated linearly between whole lags.
#[test]
fn a_profiles_autocorrelation_lengths_match_direct_sums() {
    let n = 300;
    let mut next = uniforms(9);
    // A moving average of white noise: correlated over ~6 points.
    let noise: Vec<f64> = (0..n + 12).map(|_| next() - 0.5).collect();
    let h: Vec<f64> = (0..n).map(|i| noise[i..i + 12].iter().sum()).collect();
    let mean = h.iter().sum::<f64>() / n as f64;
    let z: Vec<f64> = h.iter().map(|v| v - mean).collect();
    let acf = |lag: usize| {
        let sum: f64 = (0..n - lag).map(|i| z[i] * z[i + lag]).sum();
        sum / (n - lag) as f64
    };
    let crossing = |threshold: f64| {
        let f0 = acf(0);
        let k = (1..n).find(|&k| acf(k) / f0 <= threshold).unwrap();
        let (a, b) = (acf(k - 1) / f0, acf(k) / f0);
        (k - 1) as f64 + (a - threshold) / (a - b)
    };
    let dx_m = 1e-6;
    let profile = Array2::from_shape_vec((n, 1), h.clone()).unwrap();
    let (parameters, _) = profile_parameters(&profile, dx_m).unwrap();
    let sal = crossing(0.2) * dx_m;
    assert!(
        (parameters.sal_m / sal - 1.0).abs() < 1e-9,
        "{} vs {sal}",
        parameters.sal_m
    );
    let xi = crossing((-1.0f64).exp()) * dx_m;
    assert!(
        (parameters.correlation_length_m / xi - 1.0).abs() < 1e-9,
        "{} vs {xi}",
        parameters.correlation_length_m
    );
}

// Missing points of a line: the stage fills them (a note says so), and the
// share limit applies.
#[test]
fn missing_points_are_filled_and_limited() {
    let mut h = self_affine(512, 0.7, 2);
    for v in &mut h[100..110] {
        *v = f64::NAN;
    }
    let ctx = Context::new("gaps");
    let a = analyse(line(&h, 1e-6), &params(|_| {}), &ctx).unwrap();
    assert_eq!(a.stats.filled_points[0], 10);
    assert!(
        ctx.notes()
            .iter()
            .any(|n| n.starts_with("10 missing points") && n.contains("linearly")),
        "{:?}",
        ctx.notes()
    );
    for v in &mut h[..100] {
        *v = f64::NAN;
    }
    let e = analyse(line(&h, 1e-6), &params(|_| {}), &Context::new("t"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("max_missing_fraction"), "{e}");
    let short = analyse(line(&h[..7], 1e-6), &params(|_| {}), &Context::new("t"));
    let e = short.err().unwrap().to_string();
    assert!(e.contains("line scan has only 7 points"), "{e}");
}
