//! The measurements of issue #48: a rough patch of n × n surface nodes and
//! `layers` element layers, pressed in aimed steps to A/A0 = 0.3 as the
//! `fem` stage steps it, at finite or small strain, with the wall time, the
//! CPU time, the peak resident memory and its share per node, the Newton
//! iterations per step and the factorisations.
//!
//! The surface is the deterministic sample surface (20 µm pixels, H = 0.8,
//! 8 modes, rms ≈ 3 µm per 32 pixels, rms slope ≈ 0.2); the material the
//! paper's EPDM (or, with `neo`, a neo-Hookean μ = 1 MPa, the felupe
//! comparison's solid), κ = 5000 μ, mirror faces, 8 layers graded 8 : 1.
//!
//! Run: `cargo bench -p hypercontact-fem --bench patch -- [N ...] [small]
//! [neo] [coarsen] [direct] [layers=L] [steps=S]` (default: 32 and 48,
//! finite strain, 20 steps; `coarsen` meshes with lateral coarsening,
//! `direct` turns off the conjugate gradients on the kept factor). Each N runs in a process of its own (the bench re-executes
//! itself), so the peak memory is that run's alone. RAYON_NUM_THREADS=1
//! for one thread.

use std::time::Instant;

use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{
    AreaSteps, ContactProblem, HeightMap, Lateral, Law, Mesh, MeshOptions, NewtonOptions,
    bearing_approach_m, solve_area_steps,
};

/// One run's set-up.
struct Run {
    n: usize,
    layers: usize,
    steps: usize,
    finite: bool,
    neo_hookean: bool,
    lateral_coarsening: bool,
    krylov: bool,
}

/// The process's CPU time (user + system, all threads) from /proc, s.
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

/// The process's peak resident memory (VmHWM), bytes.
fn peak_rss_bytes() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|kb| kb.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb * 1024.0)
}

fn law(run: &Run) -> Law {
    let hyperelastic = if run.neo_hookean {
        Law::hyperelastic(
            &hypercontact_material::NeoHookean::new(0.5e6).unwrap(),
            5000.0,
        )
    } else {
        Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0)
    }
    .unwrap();
    if run.finite {
        hyperelastic
    } else {
        Law::linear_elastic(hyperelastic.shear_modulus_pa(), 5000.0).unwrap()
    }
}

fn measure(run: &Run) {
    let pixel_m = 20e-6;
    let n = run.n;
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
    let (started, cpu_started) = (Instant::now(), cpu_s());
    let map = HeightMap {
        heights_m: &heights,
        nx: n,
        ny: n,
        dx_m: pixel_m,
        dy_m: pixel_m,
    };
    let options = MeshOptions {
        layers: run.layers,
        lateral_coarsening: run.lateral_coarsening,
        ..MeshOptions::default()
    };
    let mesh = Mesh::new(&map, &options).unwrap();
    let nodes = mesh.node_count();
    let mut problem =
        ContactProblem::new(mesh, law(run), Lateral::Mirror, NewtonOptions::default()).unwrap();
    if !run.krylov {
        problem.set_krylov(false);
    }
    let estimate = problem.memory_estimate_bytes() as f64;
    let (lo, hi) = heights
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    // The stage's stepping (stage.rs, `solve`).
    let max_area_fraction = 0.3;
    let steps = AreaSteps {
        steps: run.steps,
        max_area_fraction,
        first_approach_m: bearing_approach_m(&heights, max_area_fraction / run.steps as f64)
            .max(1e-3 * (hi - lo)),
        snapshot_area_fractions: Vec::new(),
        max_steps: 4 * run.steps + 10,
    };
    let curve = solve_area_steps(&mut problem, &steps, &mut |_| {}).unwrap();
    let (wall_s, cpu) = (started.elapsed().as_secs_f64(), cpu_s() - cpu_started);
    let per_step: Vec<usize> = curve.steps.iter().map(|s| s.iterations).collect();
    let newton: usize = per_step.iter().sum();
    let peak = peak_rss_bytes();
    let last = curve.steps.last().unwrap();
    println!(
        "{n}² × {}{}, {}, {}: {} nodes, {wall_s:.1} s wall, {cpu:.1} s CPU, {} threads; peak RSS \
         {:.0} MB ({:.1} kB per node; estimated {:.0} MB); {} steps, {newton} Newton iterations ({:.1} per step) \
         {per_step:?}; {} factorisations, {} CG iterations; A/A0 {:.3}, load {:.5e} N",
        run.layers,
        if run.lateral_coarsening {
            " coarsened"
        } else {
            ""
        },
        if run.finite { "finite" } else { "small" },
        if run.neo_hookean {
            "neo-Hookean"
        } else {
            "paper EPDM"
        },
        nodes,
        rayon::current_num_threads(),
        peak / 1e6,
        peak / nodes as f64 / 1e3,
        estimate / 1e6,
        curve.steps.len(),
        newton as f64 / curve.steps.len() as f64,
        problem.factorizations(),
        problem.krylov_iterations(),
        last.area_fraction,
        last.load_n
    );
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let value = |key: &str, default: usize| {
        args.iter()
            .find_map(|a| a.strip_prefix(key)?.strip_prefix('=')?.parse().ok())
            .unwrap_or(default)
    };
    let sizes: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let run = |n| Run {
        n,
        layers: value("layers", 8),
        steps: value("steps", 20),
        finite: !args.iter().any(|a| a == "small"),
        neo_hookean: args.iter().any(|a| a == "neo"),
        lateral_coarsening: args.iter().any(|a| a == "coarsen"),
        krylov: !args.iter().any(|a| a == "direct"),
    };
    if std::env::var_os("HYPERCONTACT_BENCH_CHILD").is_some() || sizes.len() == 1 {
        for &n in &sizes {
            measure(&run(n));
        }
        return;
    }
    let sizes = if sizes.is_empty() {
        vec![32, 48]
    } else {
        sizes
    };
    // One process per size, so each peak RSS is its run's own.
    let exe = std::env::current_exe().unwrap();
    for n in sizes {
        let mut child_args: Vec<String> = args
            .iter()
            .filter(|a| a.parse::<usize>().is_err())
            .cloned()
            .collect();
        child_args.push(n.to_string());
        let status = std::process::Command::new(&exe)
            .args(&child_args)
            .env("HYPERCONTACT_BENCH_CHILD", "1")
            .status()
            .unwrap();
        assert!(status.success(), "the {n}² run failed");
    }
}
