//! Node and unknown counts, the tangent's pattern, the element entry table
//! and the Cholesky factor (nested-dissection order) of the paper's mesh
//! (8 layers graded 8 : 1, depth = lateral size, mirror faces) on n × n
//! patches, with and without lateral coarsening (issue #48).
//!
//! Run: `cargo run --release -p hypercontact-fem --example mesh_sizes --
//! [N …] [on|off]` (default 48 96, both meshes). The peak resident memory
//! printed is the process's so far (VmHWM): run one size and one mesh per
//! process to read it.

use std::time::Instant;

use hypercontact_fem::assembly::Pattern;
use hypercontact_fem::dofs::Dofs;
use hypercontact_fem::linear_solver::LinearSolver;
use hypercontact_fem::ordering::nested_dissection;
use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::{Lateral, Mesh, MeshOptions};

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
    let sizes: Vec<usize> = (args.iter())
        .filter(|a| *a != "on" && *a != "off")
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
        }
    }
    Ok(())
}
