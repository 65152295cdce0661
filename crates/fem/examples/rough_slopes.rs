//! Issue #48's Newton targets on self-affine patches of a chosen rms slope:
//! a 20 × 20 sample surface (20 µm pixels, H = 0.8), 10 layers, neo-Hookean
//! μ = 1 MPa, κ = 5000 μ, mirror faces, 20 steps aimed at A/A0 up to 0.72
//! with the stage's first step (the bearing approach of 0.72 / 20). Prints
//! per run the wall time, the Newton iterations per step and the area
//! reached; OUT (optional) receives every step's approach, area and load
//! and its contact mask, one line each, for comparing two versions.
//!
//! Run: `cargo run --release -p hypercontact-fem --example rough_slopes --
//! [0.3] [0.6] [finite|small] [OUT=file]`.

use std::io::Write;
use std::time::Instant;

use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    AreaSteps, ContactProblem, Curve, HeightMap, Lateral, Law, Mesh, MeshOptions, NewtonOptions,
    bearing_approach_m, solve_area_steps,
};

type Failure = Box<dyn std::error::Error>;

const PIXEL_M: f64 = 20e-6;

/// The sample surface scaled to rms slope `slope`
/// ([`hypercontact_fem::sample::rms_slope`]).
fn surface(n: usize, slope: f64, modes: usize, seed: u64) -> Vec<f64> {
    SampleSurface {
        nx: n,
        ny: n,
        pixel_m: PIXEL_M,
        rms_m: 1e-6,
        hurst: 0.8,
        modes,
        seed,
    }
    .with_rms_slope(slope)
    .heights_m()
}

fn run(
    heights_m: &[f64],
    (n, layers, cut_damping): (usize, usize, f64),
    law: Law,
) -> Result<Curve, Failure> {
    let map = HeightMap {
        heights_m,
        nx: n,
        ny: n,
        dx_m: PIXEL_M,
        dy_m: PIXEL_M,
    };
    let mesh_options = MeshOptions {
        layers,
        ..MeshOptions::default()
    };
    let mesh = Mesh::new(&map, &mesh_options)?;
    let newton = NewtonOptions {
        cut_damping,
        ..NewtonOptions::default()
    };
    let mut problem = ContactProblem::new(mesh, law, Lateral::Mirror, newton)?;
    let (lo, hi) = heights_m
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let (steps, max_area_fraction) = (20, 0.72);
    let options = AreaSteps {
        steps,
        max_area_fraction,
        first_approach_m: bearing_approach_m(heights_m, max_area_fraction / steps as f64)
            .max(1e-3 * (hi - lo)),
        snapshot_area_fractions: vec![],
        max_steps: 4 * steps + 10,
    };
    let mut on_step = |step: &hypercontact_fem::Step| {
        eprintln!(
            "  approach {:.4e} m: {} iterations, A/A0 {:.4}, load {:.6e} N",
            step.approach_m, step.iterations, step.area_fraction, step.load_n
        );
    };
    Ok(solve_area_steps(&mut problem, &options, &mut on_step)?)
}

fn main() -> Result<(), Failure> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut slopes: Vec<f64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let modes: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("modes="))
        .map_or(Ok(5), str::parse)?;
    let n: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("n="))
        .map_or(Ok(20), str::parse)?;
    let layers: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("layers="))
        .map_or(Ok(10), str::parse)?;
    let cut_damping: f64 = args
        .iter()
        .find_map(|a| a.strip_prefix("cut="))
        .map_or(Ok(0.25), str::parse)?;
    let seed: u64 = args
        .iter()
        .find_map(|a| a.strip_prefix("seed="))
        .map_or(Ok(3), str::parse)?;
    if slopes.is_empty() {
        slopes = vec![0.3, 0.6];
    }
    let strains: Vec<&str> = ["finite", "small"]
        .into_iter()
        .filter(|s| {
            args.iter().all(|a| a != "finite" && a != "small") || args.contains(&s.to_string())
        })
        .collect();
    let mut out = args
        .iter()
        .find_map(|a| a.strip_prefix("OUT="))
        .map(std::fs::File::create)
        .transpose()?;
    let finite = Law::hyperelastic(&hypercontact_material::NeoHookean::new(0.5e6)?, 5000.0)?;
    let small = Law::linear_elastic(finite.shear_modulus_pa(), 5000.0)?;
    for slope in slopes {
        let heights_m = surface(n, slope, modes, seed);
        for strain in &strains {
            let law = if *strain == "finite" { &finite } else { &small };
            let started = Instant::now();
            let result = run(&heights_m, (n, layers, cut_damping), law.clone());
            let seconds = started.elapsed().as_secs_f64();
            match result {
                Ok(curve) => {
                    let per_step: Vec<usize> = curve.steps.iter().map(|s| s.iterations).collect();
                    let total: usize = per_step.iter().sum();
                    println!(
                        "slope {slope} {strain}: {seconds:.2} s, {total} iterations over {} steps \
                         ({:.1} per step) {per_step:?}, A/A0 {:.4}",
                        per_step.len(),
                        total as f64 / per_step.len() as f64,
                        curve.steps.last().map_or(0.0, |s| s.area_fraction)
                    );
                    if let Some(out) = out.as_mut() {
                        for s in &curve.steps {
                            writeln!(
                                out,
                                "{slope} {strain} {:.17e} {:.17e} {:.17e}",
                                s.approach_m, s.area_fraction, s.load_n
                            )?;
                        }
                    }
                }
                Err(e) => println!("slope {slope} {strain}: failed after {seconds:.2} s: {e}"),
            }
        }
    }
    Ok(())
}
