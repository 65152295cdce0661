//! One-shot timings too long for criterion's ten samples: a load step on a
//! 2048² free map (the comparison with tamaas 2.9, which needs
//! 100–340 s per load on one thread), and the 40-step curve of a ~450² map
//! like a paper-pipeline sample, run through the stage.
//!
//! Run: `RAYON_NUM_THREADS=1 cargo bench -p hypercontact-bem --bench load_step`
//! (and without the variable for all cores). `-- 2048` or `-- 450` runs one.

use std::time::Instant;

use hypercontact_bem::{
    Boundary, Control, CurveOptions, Influence, Problem, SolverOptions, solve_curve,
};
use hypercontact_synth::surface::SelfAffine;

/// A non-periodic n × n crop of a 2n × 2n self-affine surface at 20 µm:
/// H = 0.65, rms 15 µm, power from 5 mm down to 40 µm (T1 filtered at 20 µm).
fn map(n: usize) -> Vec<f64> {
    let surface = SelfAffine::T1_LIKE.non_periodic(n, n, 20e-6, 101);
    surface.iter().copied().collect()
}

fn load_step_2048() {
    let n = 2048;
    let heights = map(n);
    let started = Instant::now();
    let influence = Influence::new(n, n, 20e-6, 20e-6, Boundary::Free);
    let setup = started.elapsed();
    let problem = Problem::new(&influence, &heights).unwrap();
    let mut u = vec![0.0; n * n];
    let mut work = influence.workspace();
    let started = Instant::now();
    let rounds = 3;
    for _ in 0..rounds {
        influence.apply(&heights, &mut u, &mut work);
    }
    let convolution = started.elapsed() / rounds;
    println!(
        "2048² free (transform {:?}), {} threads: kernel set-up {setup:.2?}, one convolution \
         {convolution:.3?}",
        influence.transform_size(),
        rayon::current_num_threads()
    );
    // Warm-started steps, as the stage runs them.
    let options = CurveOptions {
        steps: 4,
        max_area_fraction: 0.2,
        solver: SolverOptions {
            tolerance: 1e-8,
            max_iterations: 5000,
            ..SolverOptions::default()
        },
    };
    let started = Instant::now();
    let mut last = started;
    let rows = solve_curve(&problem, options, &mut |k, row, _| {
        println!(
            "  step {k}: A/A0 = {:.4}, {} iterations, {:.2?}",
            row.area_fraction,
            row.iterations,
            last.elapsed()
        );
        last = Instant::now();
    })
    .unwrap();
    println!(
        "  4 warm-started steps to A/A0 = 0.2: {:.2?}",
        started.elapsed()
    );
    // One load alone, from nothing (tamaas' figure is per load).
    let approach_m = rows[1].approach_m;
    for tolerance in [1e-8, 1e-10] {
        let options = SolverOptions {
            tolerance,
            max_iterations: 5000,
            ..SolverOptions::default()
        };
        let started = Instant::now();
        let s = problem
            .solve(Control::Approach(approach_m), options, None)
            .unwrap();
        let cold = started.elapsed();
        println!(
            "  cold solve at A/A0 = {:.4}, tolerance {tolerance:.0e}: {cold:.2?} ({} iterations, \
             {:.3?}/iteration)",
            s.contact_pixels as f64 / (n * n) as f64,
            s.iterations,
            cold / s.iterations.max(1) as u32,
        );
    }
}

/// The stage as a pipeline runs it (defaults: free, 40 steps to A/A0 = 0.9,
/// tolerance 1e-8, hyperelastic, maps at 0.1/0.5/0.9), on a 453² map (the size
/// of the paper pipeline's stitched T1 at 20 µm).
fn curve_450() {
    use hypercontact_bem::stage::{Bem, BemParams};
    use hypercontact_core::{Context, Field, Inputs, Params, Product, Stage, Table};

    let n = 453;
    let heights = ndarray::Array2::from_shape_vec((n, n), map(n)).unwrap();
    let inputs = Inputs::new()
        .with(
            "surface",
            Product::Field(Field::new(heights, 20e-6, 20e-6).unwrap()),
        )
        .with(
            "material",
            Product::Table(hypercontact_material::table::to_table(
                &hypercontact_material::presets::paper_epdm(),
            )),
        );
    let params = BemParams::default().check().unwrap();
    let started = Instant::now();
    let out = Bem.run(&params, &inputs, &Context::new("bem")).unwrap();
    let elapsed = started.elapsed();
    let Some(Product::Table(response)) = out.get("response") else {
        panic!("no response")
    };
    let response: &Table = response;
    let iterations: i64 = response.i64("iterations").unwrap().iter().sum();
    let fractions = response.f64("area_fraction").unwrap();
    println!(
        "stage bem on 453² (free, 40 steps to A/A0 = {:.3}): {elapsed:.2?} ({iterations} \
         iterations, {} threads)",
        fractions[fractions.len() - 1],
        rayon::current_num_threads()
    );
}

fn main() {
    let which: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let wants = |name: &str| which.is_empty() || which.iter().any(|w| w == name);
    if wants("450") {
        curve_450();
    }
    if wants("2048") {
        load_step_2048();
    }
}
