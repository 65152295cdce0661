//! The speed targets: a 32 × 32 patch with 8 layers and 20
//! approach steps (under 20 s on 2 cores), and a 64 × 64 patch (under
//! 3 min), on the deterministic sample surface (20 µm pixels, rms slope
//! ≈ 0.2, the paper's EPDM), up to ~30 % contact; and the 96 × 96 patch of
//! issue #48, with and without lateral coarsening.
//!
//! Run: `cargo bench -p hypercontact-fem --bench patch` (`-- 64` or `-- 96`
//! for the larger patches, `-- neo` for the neo-Hookean solid of the felupe
//! timing, `-- small` for small-strain linear elasticity with the EPDM's
//! μ0, `-- coarsen` for the laterally coarsened mesh; RAYON_NUM_THREADS=1
//! for one thread). Peak memory: run the bench binary under
//! `/usr/bin/time -v`.

use std::time::Instant;

use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    ContactProblem, CurveOptions, HeightMap, Lateral, Law, Mesh, MeshOptions, NewtonOptions,
    solve_curve,
};

/// The solid of a run.
#[derive(Clone, Copy, PartialEq)]
enum Solid {
    PaperEpdm,
    NeoHookean,
    /// Small-strain linear elasticity with the EPDM's μ0, K = 5000 μ0.
    Small,
}

impl Solid {
    fn law(self) -> Law {
        let epdm =
            || Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap();
        match self {
            Solid::PaperEpdm => epdm(),
            // μ = 1 MPa: the felupe comparison's solid.
            Solid::NeoHookean => Law::hyperelastic(
                &hypercontact_material::NeoHookean::new(0.5e6).unwrap(),
                5000.0,
            )
            .unwrap(),
            Solid::Small => Law::linear_elastic(epdm().shear_modulus_pa(), 5000.0).unwrap(),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Solid::PaperEpdm => "paper EPDM",
            Solid::NeoHookean => "neo-Hookean μ = 1 MPa",
            Solid::Small => "small strain (EPDM μ0)",
        }
    }
}

/// The process's CPU time (user + system, all threads) from /proc, s (0
/// where /proc is missing): on a shared machine it varies less than the
/// wall time.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let ticks: f64 = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|v| v.parse::<f64>().ok())
        .sum();
    ticks / 100.0
}

fn run(n: usize, steps: usize, solid: Solid, lateral_coarsening: bool) {
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
    let (started, cpu_started_s) = (Instant::now(), cpu_s());
    let map = HeightMap {
        heights_m: &heights,
        nx: n,
        ny: n,
        dx_m: pixel_m,
        dy_m: pixel_m,
    };
    let options = MeshOptions {
        lateral_coarsening,
        ..MeshOptions::default()
    };
    let mesh = Mesh::new(&map, &options).unwrap();
    let nodes = mesh.node_count();
    let mut problem =
        ContactProblem::new(mesh, solid.law(), Lateral::Mirror, NewtonOptions::default()).unwrap();
    let setup = started.elapsed();
    let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mean = heights.iter().sum::<f64>() / heights.len() as f64;
    let options = CurveOptions::uniform(0.9 * (top - mean), steps);
    let curve = solve_curve(&mut problem, &options).unwrap();
    let total = started.elapsed();
    let cpu = cpu_s() - cpu_started_s;
    let iterations: usize = curve.steps.iter().map(|s| s.iterations).sum();
    let last = curve.steps.last().unwrap();
    println!(
        "{n} × {n} × 8{}, {}, {steps} steps, {} threads: {total:.2?} (set-up {setup:.2?}), \
         {cpu:.2} s CPU, {nodes} nodes, {} unknowns, {} factorisations, {iterations} Newton \
         iterations, final area fraction {:.3}, load {:.4e} N",
        if lateral_coarsening { " coarsened" } else { "" },
        solid.name(),
        rayon::current_num_threads(),
        problem.dofs.count,
        problem.factorizations(),
        last.area_fraction,
        last.load_n
    );
}

fn main() {
    let which: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let has = |name: &str| which.iter().any(|a| a == name);
    let solid = if has("neo") {
        Solid::NeoHookean
    } else if has("small") {
        Solid::Small
    } else {
        Solid::PaperEpdm
    };
    let coarsen = has("coarsen");
    let larger = has("64") || has("96");
    if !larger || has("32") {
        run(32, 20, solid, coarsen);
    }
    for n in [64, 96] {
        if has(&n.to_string()) {
            run(n, 20, solid, coarsen);
        }
    }
}
