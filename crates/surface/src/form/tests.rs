//! Tests of form removal against exact shapes, analytic residuals and an
//! independent dense QR.

use hypercontact_fuzz::on_threads;
use nalgebra::{DMatrix, DVector};
use ndarray::Array2;

use super::*;

/// Uniform values in [−1, 1) from a fixed seed (splitmix64), so tests draw
/// the same "noise" everywhere.
struct Draws(u64);

impl Draws {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// NaN holes at fixed scattered points and one block.
fn with_holes(mut h: Array2<f64>) -> Array2<f64> {
    let (nx, ny) = h.dim();
    for ((i, j), v) in h.indexed_iter_mut() {
        if (7 * i + 3 * j) % 23 == 0 || (i > nx / 3 && i < nx / 2 && j > ny / 4 && j < ny / 3) {
            *v = f64::NAN;
        }
    }
    h
}

fn relative_max_difference(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    let scale = b
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| {
            assert_eq!(x.is_nan(), y.is_nan());
            if x.is_nan() { 0.0 } else { (x - y).abs() }
        })
        .fold(0.0f64, f64::max);
    diff / scale
}

/// A polynomial of total degree `degree` in monomials of x/X, y/Y (not the
/// fit's centred Legendre basis), plus `noise` made orthogonal to every such
/// polynomial over the measured points by a dense QR of the monomial design
/// matrix (an independent least-squares solver): fitting `degree` must
/// return that noise exactly as its residual.
#[test]
fn a_polynomial_plus_orthogonal_noise_leaves_the_noise() {
    let (nx, ny, dx_m, dy_m) = (37, 29, 1e-6, 2e-6);
    for degree in 0..=polynomial::MAX_DEGREE {
        let mut draws = Draws(degree as u64 + 1);
        let exps = polynomial::exponents(degree);
        let coefficients: Vec<f64> = exps.iter().map(|_| 1e-6 * draws.next()).collect();
        let monomials = |i: usize, j: usize| -> Vec<f64> {
            let (s, t) = (i as f64 / 40.0, j as f64 / 30.0);
            exps.iter()
                .map(|&(a, b)| s.powi(a as i32) * t.powi(b as i32))
                .collect()
        };
        let shape = with_holes(Array2::zeros((nx, ny)));
        let measured: Vec<(usize, usize)> = shape
            .indexed_iter()
            .filter(|(_, v)| !v.is_nan())
            .map(|(p, _)| p)
            .collect();
        let design = DMatrix::from_fn(measured.len(), exps.len(), |r, k| {
            monomials(measured[r].0, measured[r].1)[k]
        });
        let noise = DVector::from_fn(measured.len(), |_, _| 1e-8 * draws.next());
        let q = design.qr().q();
        let orthogonal = &noise - &q * (q.transpose() * &noise);
        let mut form = Array2::from_elem((nx, ny), f64::NAN);
        let mut expected = Array2::from_elem((nx, ny), f64::NAN);
        for (r, &(i, j)) in measured.iter().enumerate() {
            form[[i, j]] = monomials(i, j)
                .iter()
                .zip(&coefficients)
                .map(|(m, c)| m * c)
                .sum();
            expected[[i, j]] = orthogonal[r];
        }
        let h = &form + &expected;
        let fit = remove_polynomial(&h, dx_m, dy_m, degree).unwrap();
        let error = relative_max_difference(&fit.residual_m, &expected);
        assert!(
            error < 1e-10,
            "degree {degree}: residual off the noise by {error:e}"
        );
        assert_eq!(fit.points, measured.len());
        // What was removed is the polynomial: its rms about its mean.
        let values: Vec<f64> = measured.iter().map(|&p| form[p]).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let rms =
            (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt();
        if degree > 0 {
            assert!(
                (fit.removed_rms_m - rms).abs() < 1e-9 * rms,
                "degree {degree}"
            );
        }
        // The polynomial's own evaluation agrees with the map's.
        let (i, j) = measured[measured.len() / 2];
        let at = fit.form.at(i as f64 * dx_m, j as f64 * dy_m);
        assert!(
            (at - form[[i, j]]).abs() < 1e-9 * rms.max(1e-12),
            "degree {degree}"
        );
    }
}

/// One degree lower leaves a residual known by symmetry: on a full grid
/// symmetric about its centre, u² is orthogonal to 1's complement (u, v) and
/// u³ to (1, v, u², uv, v²), so a linear fit to u² leaves u² − mean(u²),
/// with mean(u²) = (n + 1)/(3(n − 1)) in closed form, and a quadratic fit
/// to u³ leaves u³ − β u with β = Σu⁴/Σu² (1-D sums).
#[test]
fn one_degree_lower_leaves_the_known_residual() {
    let (nx, ny) = (41, 33);
    let u = |i: usize| (i as f64 - 20.0) / 20.0;
    let square = Array2::from_shape_fn((nx, ny), |(i, _)| u(i).powi(2));
    let fit = remove_polynomial(&square, 0.5, 0.3, 1).unwrap();
    let mean = (nx as f64 + 1.0) / (3.0 * (nx as f64 - 1.0));
    for ((i, _), r) in fit.residual_m.indexed_iter() {
        assert!((r - (u(i).powi(2) - mean)).abs() < 1e-13, "{i}");
    }
    let cube = Array2::from_shape_fn((nx, ny), |(i, _)| u(i).powi(3));
    let fit = remove_polynomial(&cube, 0.5, 0.3, 2).unwrap();
    let beta =
        (0..nx).map(|i| u(i).powi(4)).sum::<f64>() / (0..nx).map(|i| u(i).powi(2)).sum::<f64>();
    for ((i, _), r) in fit.residual_m.indexed_iter() {
        assert!((r - (u(i).powi(3) - beta * u(i))).abs() < 1e-13, "{i}");
    }
    // Degree 3 removes it entirely.
    let fit = remove_polynomial(&cube, 0.5, 0.3, 3).unwrap();
    assert!(fit.residual_m.iter().all(|r| r.abs() < 1e-13));
}

#[test]
fn polynomial_inputs_that_cannot_be_fitted_are_refused() {
    let h = Array2::from_elem((5, 6), 1.0);
    assert_eq!(
        remove_polynomial(&h, 1.0, 1.0, 7).unwrap_err(),
        FormError::Degree { degree: 7 }
    );
    assert!(matches!(
        remove_polynomial(&h, f64::NAN, 1.0, 1),
        Err(FormError::Spacing { name: "dx_m", .. })
    ));
    let mut inf = h.clone();
    inf[[2, 3]] = f64::INFINITY;
    assert!(matches!(
        remove_polynomial(&inf, 1.0, 1.0, 1),
        Err(FormError::NotFinite { i: 2, j: 3, .. })
    ));
    // One column measured: points on a line cannot fix the terms in y.
    let line = Array2::from_shape_fn((5, 6), |(i, j)| if j == 2 { i as f64 } else { f64::NAN });
    let e = remove_polynomial(&line, 1.0, 1.0, 1).unwrap_err();
    assert!(e.to_string().contains("on a line"), "{e}");
    let few = Array2::from_shape_fn((5, 6), |(i, j)| if i + j < 2 { 1.0 } else { f64::NAN });
    assert!(matches!(
        remove_polynomial(&few, 1.0, 1.0, 2),
        Err(FormError::TooFewPoints {
            needed: 6,
            found: 3,
            ..
        })
    ));
    assert!(matches!(
        remove_polynomial(&Array2::zeros((1, 6)), 1.0, 1.0, 0),
        Err(FormError::TooSmall { nx: 1, ny: 6 })
    ));
}

/// A sphere of radius R centred at (x0, y0, zc) sampled on the map's grid;
/// cap up (z above the centre) or down.
fn sphere_map(
    (nx, ny, dx_m, dy_m): (usize, usize, f64, f64),
    radius_m: f64,
    (x0_m, y0_m, zc_m): (f64, f64, f64),
    cap: Cap,
) -> Array2<f64> {
    let sign = if cap == Cap::Up { 1.0 } else { -1.0 };
    Array2::from_shape_fn((nx, ny), |(i, j)| {
        let q = (i as f64 * dx_m - x0_m).powi(2) + (j as f64 * dy_m - y0_m).powi(2);
        zc_m + sign * (radius_m * radius_m - q).sqrt()
    })
}

const GRID: (usize, usize, f64, f64) = (60, 45, 20e-6, 25e-6);

#[test]
fn a_sphere_cap_with_holes_is_recovered() {
    // (R, centre, cap): a shallow dome centred inside the map, a bowl
    // centred outside it, and a deep cap (the map's corners at 54° from the
    // pole), whose Kåsa start is exact.
    let cases = [
        (12e-3, (0.4e-3, 0.7e-3, -12e-3 + 3e-6), Cap::Up),
        (5e-3, (-0.3e-3, 0.5e-3, 5e-3 - 1e-6), Cap::Down),
        (1e-3, (0.59e-3, 0.55e-3, -1e-3), Cap::Up),
    ];
    for (radius_m, centre, cap) in cases {
        let h = with_holes(sphere_map(GRID, radius_m, centre, cap));
        let fit = remove_sphere(&h, GRID.2, GRID.3).unwrap();
        let s = &fit.form;
        assert_eq!(s.cap, cap);
        assert!(
            (s.radius_m - radius_m).abs() < 1e-9 * radius_m,
            "R {:e} vs {radius_m:e}",
            s.radius_m
        );
        for (found, expected) in [
            (s.centre_x_m, centre.0),
            (s.centre_y_m, centre.1),
            (s.centre_z_m, centre.2),
        ] {
            assert!(
                (found - expected).abs() < 1e-9 * radius_m,
                "centre {found:e} vs {expected:e}"
            );
        }
        let sign = if cap == Cap::Up { 1.0 } else { -1.0 };
        assert!((s.apex_z_m - (centre.2 + sign * radius_m)).abs() < 1e-9 * radius_m);
        assert!(
            fit.residual_rms_m < 1e-12 * fit.removed_rms_m,
            "{:e}",
            fit.residual_rms_m
        );
        assert!(fit.residual_m[[0, 0]].is_nan() && !fit.residual_m[[0, 1]].is_nan());
    }
}

/// Linearised least squares: near its apex a sphere is z ≈ a + b x + c y +
/// e ρ² with e = −1/(2R), and noise of standard deviation σ on N points
/// gives e a standard deviation σ/√(N var ρ²) (ρ² is uncorrelated with x
/// and y on a grid centred on the map), so R = −1/(2e) one of
/// 2R²σ/√(N var ρ²). The fit must land within 5 of those.
#[test]
fn a_noisy_sphere_is_recovered_within_its_statistical_error() {
    let (nx, ny, dx_m, dy_m) = GRID;
    let radius_m = 12e-3;
    let amplitude_m = 20e-9;
    let mut draws = Draws(7);
    let clean = with_holes(sphere_map(
        GRID,
        radius_m,
        (0.6e-3, 0.55e-3, -radius_m),
        Cap::Up,
    ));
    let h = clean.mapv(|z| z + amplitude_m * draws.next());
    let fit = remove_sphere(&h, dx_m, dy_m).unwrap();
    let rho2: Vec<f64> = clean
        .indexed_iter()
        .filter(|(_, z)| !z.is_nan())
        .map(|((i, j), _)| {
            (i as f64 * dx_m - (nx - 1) as f64 * dx_m / 2.0).powi(2)
                + (j as f64 * dy_m - (ny - 1) as f64 * dy_m / 2.0).powi(2)
        })
        .collect();
    let n = rho2.len() as f64;
    let mean = rho2.iter().sum::<f64>() / n;
    let var = rho2.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let sigma_m = amplitude_m / 3f64.sqrt();
    let sd_radius_m = 2.0 * radius_m * radius_m * sigma_m / (n * var).sqrt();
    let error = (fit.form.radius_m - radius_m).abs();
    assert!(
        error < 5.0 * sd_radius_m,
        "R off by {error:e} m, σ_R = {sd_radius_m:e} m"
    );
    // The residual is the noise: its rms is σ to a few per cent.
    assert!(
        (fit.residual_rms_m / sigma_m - 1.0).abs() < 0.05,
        "{:e}",
        fit.residual_rms_m
    );
    let note = fit.description();
    assert!(
        note.starts_with("form: sphere R = 12.0 mm removed, "),
        "{note}"
    );
}

#[test]
fn a_sphere_needs_curvature() {
    let plane = Array2::from_shape_fn((10, 12), |(i, j)| 1e-6 * (i as f64 - 0.5 * j as f64));
    let e = remove_sphere(&plane, 1e-6, 1e-6).unwrap_err();
    assert!(matches!(e, FormError::Degenerate { .. }), "{e}");
}

/// A cylinder of radius R whose axis, at `angle` to x, passes over (x0, y0)
/// at height zc (crest above it for a cap).
fn cylinder_map(
    radius_m: f64,
    angle: f64,
    (x0_m, y0_m, zc_m): (f64, f64, f64),
    cap: Cap,
) -> Array2<f64> {
    let (nx, ny, dx_m, dy_m) = GRID;
    let sign = if cap == Cap::Up { 1.0 } else { -1.0 };
    let (sin, cos) = f64::sin_cos(angle);
    Array2::from_shape_fn((nx, ny), |(i, j)| {
        let d = -(i as f64 * dx_m - x0_m) * sin + (j as f64 * dy_m - y0_m) * cos;
        zc_m + sign * (radius_m * radius_m - d * d).sqrt()
    })
}

#[test]
fn a_cylinder_with_holes_is_recovered_along_x_along_y_and_at_a_fitted_angle() {
    let pi = std::f64::consts::PI;
    // (axis, true angle, R, a point of the axis and the axis height, cap)
    let cases = [
        (
            CylinderAxis::X,
            0.0,
            8e-3,
            (0.2e-3, 0.3e-3, -8e-3 + 2e-6),
            Cap::Up,
        ),
        (
            CylinderAxis::Y,
            pi / 2.0,
            3e-3,
            (0.7e-3, 0.1e-3, 3e-3),
            Cap::Down,
        ),
        (
            CylinderAxis::Fitted,
            pi / 6.0,
            8e-3,
            (0.5e-3, 0.4e-3, -8e-3),
            Cap::Up,
        ),
        (
            CylinderAxis::Fitted,
            -1.2,
            2e-3,
            (0.6e-3, 0.5e-3, 2e-3 + 1e-6),
            Cap::Down,
        ),
    ];
    for (axis, angle, radius_m, (x0, y0, zc), cap) in cases {
        let h = with_holes(cylinder_map(radius_m, angle, (x0, y0, zc), cap));
        let fit = remove_cylinder(&h, GRID.2, GRID.3, axis).unwrap();
        let c = &fit.form;
        assert_eq!(c.cap, cap, "{axis:?}");
        assert!(
            (c.radius_m - radius_m).abs() < 1e-9 * radius_m,
            "{axis:?}: R {:e}",
            c.radius_m
        );
        assert!(
            (c.axis_angle_rad - angle).abs() < 1e-9,
            "{axis:?}: angle {}",
            c.axis_angle_rad
        );
        // The reported axis point lies on the true axis.
        let (sin, cos) = angle.sin_cos();
        let off_axis = -(c.axis_x_m - x0) * sin + (c.axis_y_m - y0) * cos;
        assert!(
            off_axis.abs() < 1e-9 * radius_m,
            "{axis:?}: {off_axis:e} {c:?} {}",
            fit.residual_rms_m
        );
        let sign = if cap == Cap::Up { 1.0 } else { -1.0 };
        assert!(
            (c.apex_z_m - (zc + sign * radius_m)).abs() < 1e-9 * radius_m,
            "{axis:?}"
        );
        assert!(fit.residual_rms_m < 1e-12 * fit.removed_rms_m, "{axis:?}");
    }
}

/// As for the sphere, linearised: across the axis z ≈ a + b d + e d², e =
/// −1/(2R), σ_e = σ/√(N var d²) when d² is uncorrelated with d (axis through
/// the map's centre), so σ_R = 2R²σ/√(N var d²).
#[test]
fn a_noisy_cylinder_is_recovered_within_its_statistical_error() {
    let (nx, _, dx_m, _) = GRID;
    let radius_m = 6e-3;
    let amplitude_m = 20e-9;
    let centre_x_m = (nx - 1) as f64 * dx_m / 2.0;
    let clean = with_holes(cylinder_map(
        radius_m,
        pi_half(),
        (centre_x_m, 0.0, -radius_m),
        Cap::Up,
    ));
    let mut draws = Draws(11);
    let h = clean.mapv(|z| z + amplitude_m * draws.next());
    let fit = remove_cylinder(&h, GRID.2, GRID.3, CylinderAxis::Y).unwrap();
    let d2: Vec<f64> = clean
        .indexed_iter()
        .filter(|(_, z)| !z.is_nan())
        .map(|((i, _), _)| (i as f64 * dx_m - centre_x_m).powi(2))
        .collect();
    let n = d2.len() as f64;
    let mean = d2.iter().sum::<f64>() / n;
    let var = d2.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let sd_radius_m = 2.0 * radius_m * radius_m * (amplitude_m / 3f64.sqrt()) / (n * var).sqrt();
    let error = (fit.form.radius_m - radius_m).abs();
    assert!(
        error < 5.0 * sd_radius_m,
        "R off by {error:e} m, σ_R = {sd_radius_m:e} m"
    );
    // A fitted angle finds the y axis within the noise too.
    let free = remove_cylinder(&h, GRID.2, GRID.3, CylinderAxis::Fitted).unwrap();
    assert!(
        (free.form.axis_angle_rad.abs() - pi_half()).abs() < 1e-3,
        "{}",
        free.form.axis_angle_rad
    );
    assert!((free.form.radius_m - radius_m).abs() < 5.0 * sd_radius_m + error);
}

fn pi_half() -> f64 {
    std::f64::consts::FRAC_PI_2
}

#[test]
fn form_removal_gives_the_same_bits_on_any_number_of_threads() {
    let h = with_holes(sphere_map(GRID, 5e-3, (0.3e-3, 0.6e-3, -5e-3), Cap::Up));
    let mut draws = Draws(3);
    let h = h.mapv(|z| z + 1e-8 * draws.next());
    let run = || {
        let p = remove_polynomial(&h, GRID.2, GRID.3, 4).unwrap();
        let s = remove_sphere(&h, GRID.2, GRID.3).unwrap();
        (p.residual_m, s.residual_m, s.form.radius_m)
    };
    let one = on_threads(1, run);
    let three = on_threads(3, run);
    let bits = |a: &Array2<f64>| a.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one.0), bits(&three.0));
    assert_eq!(bits(&one.1), bits(&three.1));
    assert_eq!(one.2.to_bits(), three.2.to_bits());
}

#[test]
fn lengths_read_in_the_unit_that_fits() {
    assert_eq!(length(12.3e-3), "12.3 mm");
    assert_eq!(length(4.1e-6), "4.10 um");
    assert_eq!(length(0.5e-9), "0.50 nm");
    assert_eq!(length(250e-9), "250 nm");
    assert_eq!(length(2.0), "2.00 m");
}

/// Timing on 2048² (run with `--ignored --nocapture`): polynomials of
/// degree 3 and 6, a sphere and the 3 × 3 spike rule, on a map with NaN
/// holes.
#[test]
#[ignore = "timing, not a check: run by hand"]
fn form_removal_on_2048_squared_timing() {
    let n = 2048;
    let mut draws = Draws(5);
    let h = with_holes(Array2::from_shape_fn((n, n), |(i, j)| {
        let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
        1e-6 * (x * x * y - 0.3 * y * y + x) + 1e-9 * draws.next()
    }));
    let time = |what: &str, run: &dyn Fn() -> String| {
        for _ in 0..3 {
            let start = std::time::Instant::now();
            let note = run();
            println!(
                "{what} on {n}²: {:.3} s ({note})",
                start.elapsed().as_secs_f64()
            );
        }
    };
    time("degree 3", &|| {
        remove_polynomial(&h, 1e-6, 1e-6, 3).unwrap().description()
    });
    time("degree 6", &|| {
        remove_polynomial(&h, 1e-6, 1e-6, 6).unwrap().description()
    });
    let cap = with_holes(sphere_map(
        (n, n, 0.5e-6, 0.5e-6),
        12e-3,
        (0.3e-3, 0.6e-3, -12e-3),
        Cap::Up,
    ));
    let cap = cap.mapv(|z| z + 1e-9 * draws.next());
    time("sphere", &|| {
        remove_sphere(&cap, 0.5e-6, 0.5e-6).unwrap().description()
    });
    let rule = crate::spikes::LocalRule::default();
    time("spikes (3 × 3)", &|| {
        crate::spikes::remove_spikes(&h, &rule).unwrap().description
    });
}
