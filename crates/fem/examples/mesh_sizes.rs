//! Node and unknown counts, the tangent's pattern, the element entry table
//! and the Cholesky factor (nested-dissection order) of the paper's mesh
//! (8 layers graded 8 : 1, depth = lateral size, mirror faces) on n × n
//! patches, with and without lateral coarsening (issue #48).
//!
//! Run: `cargo run --release -p hypercontact-fem --example mesh_sizes --
//! [N …] [on|off] [time]` (default 48 96, both meshes; `time`: assembly
//! times too). The peak resident memory printed is the process's so far
//! (VmHWM): run one size and one mesh per process to read it.

use std::time::Instant;

use hypercontact_fem::assembly::{self, Pattern};
use hypercontact_fem::dofs::Dofs;
use hypercontact_fem::linear_solver::LinearSolver;
use hypercontact_fem::ordering::nested_dissection;
use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{Lateral, Law, Mesh, MeshOptions};

type Failure = Box<dyn std::error::Error>;

/// The process's peak resident memory so far (VmHWM of /proc/self/status),
/// MB; NaN where /proc is missing.
fn peak_rss_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    (status.lines())
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn main() -> Result<(), Failure> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let meshes: Vec<bool> = match args.iter().find(|a| *a == "on" || *a == "off") {
        Some(which) => vec![which == "on"],
        None => vec![false, true],
    };
    let time = args.iter().any(|a| a == "time");
    let sizes: Vec<usize> = (args.iter())
        .filter(|a| !["on", "off", "time"].contains(&a.as_str()))
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let sizes = if sizes.is_empty() {
        vec![48, 96]
    } else {
        sizes
    };
    for n in sizes {
        let surface = SampleSurface {
            nx: n,
            ny: n,
            pixel_m: 20e-6,
            rms_m: 3e-6 * n as f64 / 32.0,
            hurst: 0.8,
            modes: 8,
            seed: 1,
        };
        let heights = surface.heights_m();
        for &lateral_coarsening in &meshes {
            let options = MeshOptions {
                lateral_coarsening,
                ..MeshOptions::default()
            };
            let mesh = Mesh::new(&surface.on_grid(&heights), &options)?;
            let dofs = Dofs::new(&mesh, Lateral::Mirror);
            let started = Instant::now();
            let pattern = Pattern::new(&mesh, &dofs);
            let pattern_s = started.elapsed().as_secs_f64();
            let pattern_peak_mb = peak_rss_mb();
            let order = nested_dissection(&mesh, &dofs);
            let solver = LinearSolver::new(&pattern, Some(&order))?;
            println!(
                "{n}² × {}, coarsening {}: steps {:?}, {} nodes ({} hanging), {} elements, {} \
                 unknowns, pattern {} values (built in {pattern_s:.2} s), element entries {:.1} MB, \
                 Cholesky factor {} values ({:.0} B per node); peak RSS {pattern_peak_mb:.0} MB \
                 after the pattern, {:.0} MB after the symbolic factorisation",
                mesh.layers,
                if lateral_coarsening { "on " } else { "off" },
                mesh.layer_steps,
                mesh.node_count(),
                mesh.hanging.len(),
                mesh.elements.len(),
                dofs.count,
                pattern.row_idx.len(),
                pattern.entry_bytes() as f64 / 1e6,
                solver.factor_len(),
                8.0 * solver.factor_len() as f64 / mesh.node_count() as f64,
                peak_rss_mb(),
            );
            if time {
                println!("  assembly: {}", assembly_times(&mesh, &dofs, &pattern));
            }
        }
    }
    Ok(())
}

/// The process's CPU time (user + system, all threads) from /proc, s (0
/// where /proc is missing): on a shared machine it varies less than the
/// wall time.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let ticks: f64 = (rest.split_whitespace().skip(11).take(2))
        .filter_map(|v| v.parse::<f64>().ok())
        .sum();
    ticks / 100.0
}

/// The mean CPU time of one assembly over ten, residual alone and with the
/// tangent, for the paper's EPDM and its small-strain twin at a small
/// displacement, s (run with RAYON_NUM_THREADS=1).
fn assembly_times(mesh: &Mesh, dofs: &Dofs, pattern: &Pattern) -> String {
    let epdm = Law::hyperelastic(&hypercontact_material::presets::paper_epdm(), 5000.0).unwrap();
    let small = Law::linear_elastic(epdm.shear_modulus_pa(), 5000.0).unwrap();
    let x: Vec<f64> = (0..dofs.count)
        .map(|k| 1e-8 * (((k * 37) % 11) as f64 - 5.0))
        .collect();
    let mut times = Vec::new();
    for (name, law) in [("small strain", &small), ("EPDM", &epdm)] {
        for (what, tangent) in [("residual", None), ("tangent", Some(pattern))] {
            let started = cpu_s();
            for _ in 0..10 {
                let e = assembly::evaluate(mesh, dofs, law, tangent, &x);
                std::hint::black_box(e.is_ok());
            }
            times.push(format!("{name} {what} {:.3} s", (cpu_s() - started) / 10.0));
        }
    }
    times.join(", ")
}
