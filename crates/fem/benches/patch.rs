//! The speed targets: a 32 × 32 patch with 8 layers and 20
//! approach steps (under 20 s on 2 cores), and a 64 × 64 patch (under
//! 3 min), on the deterministic sample surface (20 µm pixels, rms slope
//! ≈ 0.2, the paper's EPDM), up to ~30 % contact.
//!
//! Run: `cargo bench -p hypercontact-fem --bench patch` (`-- 64` for the
//! larger patch, `-- neo` for the neo-Hookean solid of the felupe timing;
//! RAYON_NUM_THREADS=1 for one thread).

use std::time::Instant;

use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    ContactProblem, CurveOptions, HeightMap, Lateral, Law, Mesh, MeshOptions, NewtonOptions,
    solve_curve,
};

fn run(n: usize, steps: usize, neo_hookean: bool) {
    let pixel_m = 20e-6;
    let surface = SampleSurface {
        nx: n,
        ny: n,
        pixel_m,
        rms_m: 3e-6 * n as f64 / 32.0,
        hurst: 0.8,
        modes: 8,
        seed: 1,
    };
    let heights = surface.heights_m();
    let started = Instant::now();
    let map = HeightMap {
        heights_m: &heights,
        nx: n,
        ny: n,
        dx_m: pixel_m,
        dy_m: pixel_m,
    };
    let mesh = Mesh::new(&map, &MeshOptions::default()).unwrap();
    let law = if neo_hookean {
        // μ = 1 MPa: the felupe comparison's solid.
        Law::hyperelastic(
            &hypercontact_material::NeoHookean::new(0.5e6).unwrap(),
            5000.0,
        )
        .unwrap()
    } else {
        Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap()
    };
    let mut problem =
        ContactProblem::new(mesh, law, Lateral::Mirror, NewtonOptions::default()).unwrap();
    let setup = started.elapsed();
    let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mean = heights.iter().sum::<f64>() / heights.len() as f64;
    let options = CurveOptions::uniform(0.9 * (top - mean), steps);
    let curve = solve_curve(&mut problem, &options).unwrap();
    let total = started.elapsed();
    let iterations: usize = curve.steps.iter().map(|s| s.iterations).sum();
    let last = curve.steps.last().unwrap();
    println!(
        "{n} × {n} × 8, {}, {steps} steps, {} threads: {total:.2?} (set-up {setup:.2?}), {iterations} \
         Newton iterations, final area fraction {:.3}, load {:.4e} N",
        if neo_hookean {
            "neo-Hookean μ = 1 MPa"
        } else {
            "paper EPDM"
        },
        rayon::current_num_threads(),
        last.area_fraction,
        last.load_n
    );
}

fn main() {
    let which: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let neo_hookean = which.iter().any(|a| a == "neo");
    if which.iter().all(|a| a != "64") || which.iter().any(|a| a == "32") {
        run(32, 20, neo_hookean);
    }
    if which.iter().any(|a| a == "64") {
        run(64, 20, neo_hookean);
    }
}
