//! The preconditioned solver and PK as published agree on rough contacts,
//! free and periodic, under both controls, with unmeasured points and
//! rectangular pixels.

use hypercontact_bem::{Boundary, Control, Influence, Problem, SolverOptions};

fn rough_map(nx: usize, ny: usize, seed: u64) -> Vec<f64> {
    let surface = hypercontact_synth::surface::SelfAffine {
        hurst: 0.7,
        rms_m: 1e-5,
        lambda_min_m: 3e-5,
        lambda_max_m: 1e-3,
    }
    .periodic(nx, ny, 1e-5, seed);
    let mut heights: Vec<f64> = surface.iter().copied().collect();
    for k in (0..heights.len()).step_by(97) {
        heights[k] = f64::NAN;
    }
    heights
}

#[test]
fn both_methods_find_the_same_contact() {
    let (nx, ny, dx, dy) = (72, 48, 1e-5, 1.5e-5);
    let heights = rough_map(nx, ny, 11);
    let options = |preconditioned| SolverOptions {
        tolerance: 1e-11,
        max_iterations: 5000,
        preconditioned,
    };
    for boundary in [Boundary::Free, Boundary::Periodic] {
        let influence = Influence::new(nx, ny, dx, dy, boundary);
        let problem = Problem::new(&influence, &heights).unwrap();
        let sigma = problem.sigma_m();
        let controls = [
            Control::Approach(0.5 * sigma),
            Control::Approach(2.0 * sigma),
            Control::MeanPressure(0.01),
            Control::MeanPressure(0.1),
        ];
        for control in controls {
            let a = problem.solve(control, options(true), None).unwrap();
            let b = problem.solve(control, options(false), None).unwrap();
            let peak = b.pressure.iter().copied().fold(0.0, f64::max);
            assert!(a.contact_pixels > 0, "{boundary:?} {control:?}");
            for (k, (pa, pb)) in a.pressure.iter().zip(&b.pressure).enumerate() {
                assert_eq!(*pa > 0.0, *pb > 0.0, "{boundary:?} {control:?}: pixel {k}");
                assert!((pa - pb).abs() < 1e-8 * peak, "{boundary:?} {control:?}");
            }
            assert!((a.approach_m / b.approach_m - 1.0).abs() < 1e-9);
            assert!(a.gap_m[0].is_nan() && a.pressure[0] == 0.0);
            eprintln!(
                "{boundary:?} {control:?}: A/A0 {:.3}, {} vs {} iterations",
                a.contact_pixels as f64 / problem.measured() as f64,
                a.iterations,
                b.iterations
            );
        }
    }
}
