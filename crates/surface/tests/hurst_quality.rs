//! The Hurst fits' quality (issue #17): R², q range and a flag per
//! direction, on a self-affine surface (ok), white noise and a sinusoid
//! (flagged).

use std::f64::consts::TAU;

use hypercontact_core::{Context, Field, Params};
use hypercontact_surface::surface_stage::{StatsTable, SurfaceParams, analyse};
use hypercontact_synth::surface::SelfAffine;
use ndarray::Array2;

fn stats(h: Array2<f64>, pixel_m: f64, periodic: bool) -> StatsTable {
    let params = SurfaceParams {
        resolution_m: 0.0,
        periodic,
        ..Default::default()
    }
    .check()
    .unwrap();
    let field = Field::new(h, pixel_m, pixel_m).unwrap();
    analyse(field, &params, &Context::new("test"))
        .unwrap()
        .stats
}

/// (H, R², q_min, q_max, flag) per direction x, y, radial.
fn fits(s: &StatsTable) -> [(f64, f64, f64, f64, String); 3] {
    [
        (
            s.hurst_x[0],
            s.hurst_x_r2[0],
            s.hurst_x_q_min_per_m[0],
            s.hurst_x_q_max_per_m[0],
            s.hurst_x_flag[0].clone(),
        ),
        (
            s.hurst_y[0],
            s.hurst_y_r2[0],
            s.hurst_y_q_min_per_m[0],
            s.hurst_y_q_max_per_m[0],
            s.hurst_y_flag[0].clone(),
        ),
        (
            s.hurst_radial[0],
            s.hurst_radial_r2[0],
            s.hurst_radial_q_min_per_m[0],
            s.hurst_radial_q_max_per_m[0],
            s.hurst_radial_flag[0].clone(),
        ),
    ]
}

#[test]
fn a_self_affine_surface_fits_well_inside_the_default_range() {
    let (n, pixel_m, hurst) = (512, 1e-6, 0.7);
    let h = SelfAffine {
        hurst,
        lambda_min_m: 1e-6,
        ..SelfAffine::MICRON
    }
    .periodic(n, n, pixel_m, 8);
    let s = stats(h, pixel_m, true);
    let l = n as f64 * pixel_m;
    for (h, r2, q_min, q_max, flag) in fits(&s) {
        eprintln!("H {h:.3}, R² {r2:.4}, q {q_min:.3e} … {q_max:.3e}, {flag}");
        assert!((h - hurst).abs() < 0.05, "{h}");
        assert!(r2 > 0.98 && r2 <= 1.0, "{r2}");
        assert_eq!(flag, "ok");
        // Default range: wavelengths 4·dx … L/4, the bins' mean q inside.
        assert!(q_min >= TAU / (l / 4.0) && q_min < 2.0 * TAU / (l / 4.0));
        assert!(q_max <= TAU / (4.0 * pixel_m) && q_max > 0.5 * TAU / (4.0 * pixel_m));
    }
}

#[test]
fn white_noise_is_flagged() {
    // A flat PSD: slope 0, H = −0.5 along profiles and −1 radially, and no
    // trend for a line to explain.
    let n = 256;
    let mut state = 5u64;
    let h = Array2::from_shape_fn((n, n), |_| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        1e-6 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
    });
    for (h, r2, _, _, flag) in fits(&stats(h, 1e-6, false)) {
        eprintln!("white noise: H {h:.3}, R² {r2:.3}, {flag}");
        assert_ne!(flag, "ok");
        assert!(h < 0.0);
    }
}

#[test]
fn a_sinusoid_is_a_poor_power_law() {
    // 13.7 periods across the map, with the Hann window's leakage falling
    // on both sides of the peak, which sits mid-range of the default fit.
    let (n, pixel_m) = (256, 1e-6);
    let k = 13.7;
    let h = Array2::from_shape_fn((n, n), |(i, j)| {
        1e-6 * ((TAU * k * i as f64 / n as f64).sin() + (TAU * k * j as f64 / n as f64).cos())
    });
    for (h, r2, _, _, flag) in fits(&stats(h, pixel_m, false)) {
        eprintln!("sinusoid: H {h:.3}, R² {r2:.3}, {flag}");
        assert_eq!(flag, "poor power law (R² < 0.9)");
        assert!(r2 < 0.9);
    }
}

#[test]
fn an_exponent_above_one_is_flagged_outside_the_unit_range() {
    // A clean power law (R² high) whose slope is steeper than a
    // self-affine surface's.
    let (n, pixel_m) = (256, 1e-6);
    let h = SelfAffine {
        hurst: 1.3,
        lambda_min_m: 1e-6,
        ..SelfAffine::MICRON
    }
    .periodic(n, n, pixel_m, 9);
    for (h, r2, _, _, flag) in fits(&stats(h, pixel_m, true)) {
        eprintln!("H = 1.3: H {h:.3}, R² {r2:.4}, {flag}");
        assert!((h - 1.3).abs() < 0.1 && r2 > 0.98, "{h} {r2}");
        assert_eq!(flag, "outside 0…1");
    }
}
