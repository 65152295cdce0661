//! The solver against closed-form contacts: Hertz and Sneddon on the free
//! half-space, Westergaard's wavy surface on the periodic one. E* = 1
//! throughout (the solver's units), so loads are F/E*.

use std::f64::consts::PI;

use hypercontact_bem::{Boundary, Control, Influence, Problem, SolverOptions};

/// Both methods: the FFT-preconditioned default and PK as published.
const METHODS: [SolverOptions; 2] = [
    SolverOptions {
        tolerance: 1e-10,
        max_iterations: 2000,
        preconditioned: true,
    },
    SolverOptions {
        tolerance: 1e-10,
        max_iterations: 2000,
        preconditioned: false,
    },
];

/// An n × n map of pixel `d` with heights h(r) about the centre pixel.
fn radial_map(n: usize, d: f64, h: impl Fn(f64) -> f64) -> Vec<f64> {
    let c = (n / 2) as f64;
    (0..n * n)
        .map(|k| {
            let (x, y) = (((k / n) as f64 - c) * d, ((k % n) as f64 - c) * d);
            h(x.hypot(y))
        })
        .collect()
}

struct HertzErrors {
    radius: f64,
    load: f64,
}

/// A paraboloid of radius R pressed to δ = a²/R with a = `a_px` pixels:
/// a = √(Rδ), F = (4/3) E* √R δ^{3/2} (Hertz), solved at the given
/// approach and, separately, at the given load (which must return δ).
fn hertz(a_px: usize, options: SolverOptions) -> HertzErrors {
    let (radius_m, a_m) = (1.0, 1e-3);
    let d = a_m / a_px as f64;
    let n = 4 * a_px;
    let heights = radial_map(n, d, |r| -r * r / (2.0 * radius_m));
    let influence = Influence::new(n, n, d, d, Boundary::Free);
    let problem = Problem::new(&influence, &heights).unwrap();
    let delta = a_m * a_m / radius_m;
    let load_exact = 4.0 / 3.0 * radius_m.sqrt() * delta.powf(1.5);

    let by_approach = problem
        .solve(Control::Approach(delta), options, None)
        .unwrap();
    let load = by_approach.pressure.iter().sum::<f64>() * d * d;
    let radius = (by_approach.contact_pixels as f64 * d * d / PI).sqrt();

    let mean = load_exact / (n * n) as f64 / (d * d);
    let by_load = problem
        .solve(Control::MeanPressure(mean), options, None)
        .unwrap();
    assert!(by_load.residual <= options.tolerance);
    assert!((by_load.mean_pressure / mean - 1.0).abs() < 1e-12);
    // Under load control the approach is the solver's output: Hertz's
    // δ = (3F / (4 E* √R))^{2/3}, within the same discretisation error.
    let approach_error = (by_load.approach_m / delta - 1.0).abs();
    let load_error = (load / load_exact - 1.0).abs();
    assert!(
        approach_error < 1.0 * load_error + 0.01,
        "approach {approach_error:.2e} vs load {load_error:.2e}"
    );
    // Hertz's pressure at the centre, p0 = 2 a E* / (π R).
    let centre = (n / 2) * n + n / 2;
    let p0 = 2.0 * a_m / (PI * radius_m);
    assert!(
        (by_approach.pressure[centre] / p0 - 1.0).abs() < 0.02,
        "p0 {} vs {p0}",
        by_approach.pressure[centre]
    );
    eprintln!(
        "Hertz a = {a_px} px: radius error {:.3e}, load error {load_error:.3e}, approach error \
         {approach_error:.3e}, {} + {} iterations",
        radius / a_m - 1.0,
        by_approach.iterations,
        by_load.iterations
    );
    HertzErrors {
        radius: (radius / a_m - 1.0).abs(),
        load: load_error,
    }
}

#[test]
fn hertz_radius_and_load_converge_under_refinement() {
    for options in METHODS {
        let coarse = hertz(8, options);
        let fine = hertz(16, options);
        let finer = hertz(32, options);
        assert!(
            finer.radius < 0.01 && finer.load < 1e-3,
            "{:.3e} {:.3e}",
            finer.radius,
            finer.load
        );
        assert!(fine.load < coarse.load && finer.load < fine.load);
        assert!(fine.radius < coarse.radius && finer.radius < fine.radius);
    }
}

#[test]
fn flat_punch_stiffness_is_sneddons() {
    // A cylinder of radius a, the rest far below: F = 2 E* a δ for the
    // punch's discrete area (a = √(A/π)).
    let (a_px, d) = (24, 1e-5);
    let n = 4 * a_px;
    let a_m = a_px as f64 * d;
    let heights = radial_map(n, d, |r| if r <= a_m { 0.0 } else { -1.0 });
    let influence = Influence::new(n, n, d, d, Boundary::Free);
    let problem = Problem::new(&influence, &heights).unwrap();
    let delta = 1e-6;
    for options in METHODS {
        let s = problem
            .solve(Control::Approach(delta), options, None)
            .unwrap();
        let punch_pixels = heights.iter().filter(|&&h| h == 0.0).count();
        assert_eq!(s.contact_pixels, punch_pixels);
        let a_eff = (punch_pixels as f64 * d * d / PI).sqrt();
        let load = s.pressure.iter().sum::<f64>() * d * d;
        let error = load / (2.0 * a_eff * delta) - 1.0;
        eprintln!(
            "Sneddon: load error {error:.3e} in {} iterations",
            s.iterations
        );
        assert!(error.abs() < 0.01, "{error}");
        // The gap under the punch is closed, everywhere else open.
        for (g, h) in s.gap_m.iter().zip(&heights) {
            if *h == 0.0 {
                assert!(g.abs() <= 1e-8 * delta);
            } else {
                assert!(*g > 0.5);
            }
        }
    }
}

#[test]
fn westergaard_wavy_contact_profile_and_width() {
    // h = Δ cos(2πx/λ) on a periodic map, uniform in y. Full contact at
    // p* = π E* Δ / λ; below it the contact half-width a obeys
    // p̄ = p* sin²(πa/λ) and p(x) = 2 p̄ cos(πx/λ) √(sin²(πa/λ) − sin²(πx/λ))
    // / sin²(πa/λ) (Westergaard 1939; Johnson, Contact Mechanics, §13.2).
    let (nx, ny, d, amplitude) = (512, 4, 1e-6, 1e-7);
    let wavelength = nx as f64 * d;
    let x = |i: usize| i as f64 * d;
    let heights: Vec<f64> = (0..nx * ny)
        .map(|k| amplitude * (2.0 * PI * x(k / ny) / wavelength).cos())
        .collect();
    let influence = Influence::new(nx, ny, d, d, Boundary::Periodic);
    let problem = Problem::new(&influence, &heights).unwrap();
    let p_full = PI * amplitude / wavelength;
    for (options, a_over_lambda) in METHODS
        .into_iter()
        .flat_map(|o| [0.1, 0.25, 0.4].map(|a| (o, a)))
    {
        let s2 = (PI * a_over_lambda).sin().powi(2);
        let mean = p_full * s2;
        let s = problem
            .solve(Control::MeanPressure(mean), options, None)
            .unwrap();
        let exact = |x: f64| {
            let x = if x > wavelength / 2.0 {
                x - wavelength
            } else {
                x
            };
            let inside = s2 - (PI * x / wavelength).sin().powi(2);
            if inside > 0.0 {
                2.0 * mean * (PI * x / wavelength).cos() * inside.sqrt() / s2
            } else {
                0.0
            }
        };
        let peak = exact(0.0);
        let mut worst: f64 = 0.0;
        for i in 0..nx {
            for j in 0..ny {
                worst = worst.max((s.pressure[i * ny + j] - exact(x(i))).abs());
            }
        }
        let width = (s.contact_pixels / ny) as f64 * d;
        let width_error = width / (2.0 * a_over_lambda * wavelength) - 1.0;
        eprintln!(
            "Westergaard a/λ = {a_over_lambda}: worst pressure error {:.3e} of p(0), width error \
             {width_error:.3e}, {} iterations",
            worst / peak,
            s.iterations
        );
        assert!(worst / peak < 0.02, "{}", worst / peak);
        assert!(
            width_error.abs() < 2.0 / (2.0 * a_over_lambda * nx as f64) + 1e-3,
            "{width_error}"
        );
        // Each row alike: the y direction is uniform.
        assert_eq!(s.contact_pixels % ny, 0);
    }
}
