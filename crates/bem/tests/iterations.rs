//! The solver's iterations over a curve (issue #48): on a map rough down to
//! the pixel, whose contact set is ragged, the preconditioner corrected on
//! the set (`complement`) with Polak–Ribière conjugation takes at most 60 %
//! of the iterations the plain FFT preconditioner with Fletcher–Reeves' β
//! took (223 against 386; on the 768 × 576 instrument map of the
//! `plu_curve` example 1 151 against 2 166), and its warm-started steps are
//! the contacts a cold solve by PK as published finds.

use hypercontact_bem::{
    Boundary, Control, CurveOptions, Influence, Problem, Solution, SolverOptions, solve_curve,
};
use hypercontact_synth::surface::SelfAffine;

/// A 96 × 80 crop of a self-affine surface with power down to two pixels.
fn rough_map() -> (Vec<f64>, (usize, usize, f64)) {
    let (nx, ny, pixel_m) = (96, 80, 2e-6);
    let surface = SelfAffine {
        hurst: 0.8,
        rms_m: 2e-6,
        lambda_min_m: 2.0 * pixel_m,
        lambda_max_m: 100.0 * pixel_m,
    }
    .non_periodic(nx, ny, pixel_m, 48);
    (surface.iter().copied().collect(), (nx, ny, pixel_m))
}

const OPTIONS: CurveOptions = CurveOptions {
    steps: 12,
    max_area_fraction: 0.6,
    solver: SolverOptions {
        tolerance: 1e-8,
        max_iterations: 1000,
        preconditioned: true,
    },
};

/// Iterations of this curve by the solver before the correction (main at
/// 25aa63c: FFT preconditioner on the set, Fletcher–Reeves' β).
const ITERATIONS_BEFORE: usize = 386;

#[test]
fn a_rough_maps_curve_takes_at_most_sixty_percent_of_the_iterations() {
    let (heights, (nx, ny, pixel_m)) = rough_map();
    let influence = Influence::new(nx, ny, pixel_m, pixel_m, Boundary::Free);
    let problem = Problem::new(&influence, &heights).unwrap();
    let rows = solve_curve(&problem, OPTIONS, &mut |_, _, _| {}).unwrap();
    let iterations: usize = rows.iter().map(|r| r.iterations).sum();
    eprintln!("{iterations} iterations (before: {ITERATIONS_BEFORE})");
    assert!(rows.last().unwrap().area_fraction >= 0.6);
    assert!(
        5 * iterations <= 3 * ITERATIONS_BEFORE,
        "{iterations} iterations, before {ITERATIONS_BEFORE}"
    );
}

#[test]
fn warm_started_steps_are_the_contacts_of_cold_published_solves() {
    let (heights, (nx, ny, pixel_m)) = rough_map();
    let influence = Influence::new(nx, ny, pixel_m, pixel_m, Boundary::Free);
    let problem = Problem::new(&influence, &heights).unwrap();
    let mut steps: Vec<Solution> = Vec::new();
    solve_curve(&problem, OPTIONS, &mut |k, _, s| {
        if k % 4 == 0 {
            steps.push(s.clone())
        }
    })
    .unwrap();
    let published = SolverOptions {
        preconditioned: false,
        max_iterations: 20_000,
        ..OPTIONS.solver
    };
    for warm in &steps {
        let cold = problem
            .solve(Control::Approach(warm.approach_m), published, None)
            .unwrap();
        let load_change = (warm.mean_pressure / cold.mean_pressure - 1.0).abs();
        let mean_contact =
            cold.mean_pressure * problem.measured() as f64 / cold.contact_pixels as f64;
        let (mut differing, mut largest) = (0, 0f64);
        for (&p, &q) in warm.pressure.iter().zip(&cold.pressure) {
            if (p > 0.0) != (q > 0.0) {
                differing += 1;
                largest = largest.max(p.max(q) / mean_contact);
            }
        }
        eprintln!(
            "A/A0 {:.3}: load {load_change:.2e}, {differing} pixels differ, their pressure up \
             to {largest:.2e} of the mean; {} vs {} iterations",
            warm.contact_pixels as f64 / problem.measured() as f64,
            warm.iterations,
            cold.iterations
        );
        assert!(load_change < 1e-7, "{load_change}");
        assert!(differing <= 2 && largest < 1e-4, "{differing} {largest}");
    }
}
