//! The paper pipeline's eight `fem` runs (issue #35) without the binary:
//! the four 48 × 48 patches (t1-fem … t4-fem of pipelines/paper.yaml) at
//! finite and small strain, with the stage's defaults (8 layers, grading 8,
//! mirror faces, 20 steps to A/A0 = 0.3, maps at 0.05, 0.1, 0.2, 0.3).
//! Prints per run the wall time, the Newton iterations per step and a
//! fingerprint of the products (the bits of every step's load_n and area
//! fractions and of the snapshots' pressures and masks), so a change of
//! speed can be told apart from a change of results.
//!
//! Run: `cargo run --release -p hypercontact-fem --example paper_patches --
//! DIR [OUT]` with DIR holding tN-patch-height.npy, .grid.json and
//! fit-material.json; OUT (optional) receives every step's load_n and every
//! snapshot's mask, one line each, for comparing two versions. Arguments
//! `t1` … `t4`, `finite`, `small` pick runs (default all); `coarsen` meshes
//! with lateral coarsening (issue #48); `compare` solves each run on the
//! coarsened mesh too, at the uniform run's approaches, and prints the
//! load ratio at every step.

use std::collections::hash_map::DefaultHasher;
use std::hash::Hasher;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use hypercontact_fem::{
    AreaSteps, ContactProblem, Curve, CurveOptions, HeightMap, Lateral, Law, Mesh, MeshOptions,
    NewtonOptions, bearing_approach_m, solve_area_steps, solve_curve,
};
use hypercontact_material::Ogden;

type Failure = Box<dyn std::error::Error>;

fn main() -> Result<(), Failure> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(
        args.first()
            .ok_or("usage: paper_patches DIR [OUT] [t1..t4] [finite|small]")?,
    );
    let out_path = args.get(1).filter(|a| !is_pick(a)).map(PathBuf::from);
    let picks: Vec<&String> = args.iter().skip(1).filter(|a| is_pick(a)).collect();
    let wanted = |name: &str| {
        // A sample is picked among the samples, a strain among the strains.
        let sample = |p: &str| p.starts_with('t');
        let family: Vec<_> = picks
            .iter()
            .filter(|p| {
                sample(p) == sample(name) && !matches!(p.as_str(), "direct" | "coarsen" | "compare")
            })
            .collect();
        family.is_empty() || family.iter().any(|p| p.as_str() == name)
    };
    let (finite_law, small_law) = laws(&dir)?;
    let coarsen = picks.iter().any(|p| p.as_str() == "coarsen");
    let compare_meshes = picks.iter().any(|p| p.as_str() == "compare");
    let mut out = out_path.map(std::fs::File::create).transpose()?;
    let (mut total_s, mut total_cpu_s) = (0.0, 0.0);
    for sample in ["t1", "t2", "t3", "t4"].into_iter().filter(|s| wanted(s)) {
        let (heights_m, nx, ny, pixel_m) = patch(&dir, sample)?;
        for (strain, law) in [("finite", &finite_law), ("small", &small_law)] {
            if !wanted(strain) {
                continue;
            }
            let (started, cpu_started_s) = (Instant::now(), cpu_s());
            let direct = picks.iter().any(|p| p.as_str() == "direct");
            let grid = (nx, ny, pixel_m);
            let (curve, solves) = run(&heights_m, grid, law.clone(), (coarsen, direct))?;
            let seconds = started.elapsed().as_secs_f64();
            let cpu_seconds = cpu_s() - cpu_started_s;
            total_s += seconds;
            total_cpu_s += cpu_seconds;
            let per_step: Vec<usize> = curve.steps.iter().map(|s| s.iterations).collect();
            println!(
                "{sample}-{strain}: {seconds:.2} s ({cpu_seconds:.2} s CPU), {} iterations {per_step:?}, {solves}, fingerprint {:016x}",
                per_step.iter().sum::<usize>(),
                fingerprint(&curve)
            );
            if let Some(out) = out.as_mut() {
                write_products(out, &format!("{sample}-{strain}"), &curve)?;
            }
            if compare_meshes {
                compare(&heights_m, grid, law, &curve)?;
            }
        }
    }
    println!(
        "total {total_s:.2} s ({total_cpu_s:.2} s CPU) on {} rayon threads",
        rayon::current_num_threads()
    );
    Ok(())
}

/// The process's CPU time (user + system, all threads) from /proc, s: the
/// measure that a machine shared with other jobs disturbs least (0 where
/// /proc is missing).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command's closing parenthesis: utime and stime are
    // the 12th and 13th, in clock ticks (100 per second on Linux).
    let rest = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let ticks: f64 = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|v| v.parse::<f64>().ok())
        .sum();
    ticks / 100.0
}

fn is_pick(arg: &str) -> bool {
    matches!(
        arg,
        "t1" | "t2" | "t3" | "t4" | "finite" | "small" | "direct" | "coarsen" | "compare"
    )
}

fn problem(
    heights_m: &[f64],
    (nx, ny, pixel_m): (usize, usize, f64),
    law: Law,
    lateral_coarsening: bool,
) -> Result<ContactProblem, Failure> {
    let map = HeightMap {
        heights_m,
        nx,
        ny,
        dx_m: pixel_m,
        dy_m: pixel_m,
    };
    let options = MeshOptions {
        lateral_coarsening,
        ..MeshOptions::default()
    };
    let mesh = Mesh::new(&map, &options)?;
    Ok(ContactProblem::new(
        mesh,
        law,
        Lateral::Mirror,
        NewtonOptions::default(),
    )?)
}

/// The coarsened mesh at the approaches of `uniform` (a curve on the
/// uniform mesh): load and A/A0 ratios per step.
fn compare(
    heights_m: &[f64],
    grid: (usize, usize, f64),
    law: &Law,
    uniform: &Curve,
) -> Result<(), Failure> {
    let mut coarse = problem(heights_m, grid, law.clone(), true)?;
    let options = CurveOptions {
        approaches_m: uniform.steps.iter().map(|s| s.approach_m).collect(),
        ..Default::default()
    };
    let (started, cpu_started_s) = (Instant::now(), cpu_s());
    let curve = solve_curve(&mut coarse, &options)?;
    let mut worst: f64 = 0.0;
    for (u, c) in uniform.steps.iter().zip(&curve.steps) {
        let change = c.load_n / u.load_n - 1.0;
        worst = worst.max(change.abs());
        println!(
            "  approach {:.4e} m: A/A0 {:.4} uniform, {:.4} coarsened; load {:.6e} N, {:.6e} N \
             ({change:+.3e})",
            u.approach_m, u.area_fraction, c.area_fraction, u.load_n, c.load_n
        );
    }
    println!(
        "  coarsened: {} nodes, {} unknowns, {:.2} s ({:.2} s CPU); largest load change {worst:.3e}",
        coarse.mesh.node_count(),
        coarse.dofs.count,
        started.elapsed().as_secs_f64(),
        cpu_s() - cpu_started_s
    );
    Ok(())
}

/// The fitted Ogden-6 at finite strain (bulk ratio 5000) and its small-strain
/// twin (μ0 and the same K), as the stage's `law_of` builds them.
fn laws(dir: &Path) -> Result<(Law, Law), Failure> {
    let text = std::fs::read_to_string(dir.join("fit-material.json"))?;
    let json: serde_json::Value = serde_json::from_str(&text)?;
    let numbers = |key: &str| -> Result<Vec<f64>, Failure> {
        json[key]
            .as_array()
            .ok_or(format!("fit-material.json: no array `{key}`"))?
            .iter()
            .map(|v| {
                v.as_f64()
                    .ok_or_else(|| format!("{key}: {v} is no number").into())
            })
            .collect()
    };
    let model = Ogden::new(numbers("mu_pa")?, numbers("alpha")?)?;
    let finite = Law::hyperelastic(&model, 5000.0)?;
    let small = Law::linear_elastic(finite.shear_modulus_pa(), 5000.0)?;
    Ok((finite, small))
}

/// A patch's heights (i * ny + j), its shape and its pixel, m.
fn patch(dir: &Path, sample: &str) -> Result<(Vec<f64>, usize, usize, f64), Failure> {
    let array: ndarray::Array2<f64> =
        ndarray_npy::read_npy(dir.join(format!("{sample}-patch-height.npy")))?;
    let grid: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(
        dir.join(format!("{sample}-patch-height.grid.json")),
    )?)?;
    let pixel_m = grid["dx_m"].as_f64().ok_or("grid.json: no dx_m")?;
    let (nx, ny) = array.dim();
    Ok((array.iter().copied().collect(), nx, ny, pixel_m))
}

/// The stage's `solve` on one patch: first step at the bearing approach of
/// A/A0 = 0.3 / 20 (at least 1e-3 of the height range), then aimed steps.
/// The curve, and the factorisations and conjugate-gradient iterations it
/// took (`direct`: a factorisation for every Newton direction, as before
/// the conjugate gradients).
fn run(
    heights_m: &[f64],
    grid: (usize, usize, f64),
    law: Law,
    (coarsen, direct): (bool, bool),
) -> Result<(Curve, String), Failure> {
    let mut problem = problem(heights_m, grid, law, coarsen)?;
    problem.set_krylov(!direct);
    let (lo, hi) = heights_m
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let (steps, max_area_fraction) = (20, 0.3);
    let options = AreaSteps {
        steps,
        max_area_fraction,
        first_approach_m: bearing_approach_m(heights_m, max_area_fraction / steps as f64)
            .max(1e-3 * (hi - lo)),
        snapshot_area_fractions: vec![0.05, 0.1, 0.2, 0.3],
        max_steps: 4 * steps + 10,
    };
    // Progress on stderr: a slow run shows where it spends its iterations.
    let mut taken = 0;
    let mut on_step = |step: &hypercontact_fem::Step| {
        taken += 1;
        eprintln!(
            "  step {taken}: {} iterations, A/A0 {:.4}",
            step.iterations, step.area_fraction
        );
    };
    let curve = solve_area_steps(&mut problem, &options, &mut on_step)?;
    let solves = format!(
        "{} factorisations, {} CG iterations",
        problem.factorizations(),
        problem.krylov_iterations()
    );
    Ok((curve, solves))
}

/// A hash of the bits of every product the stage writes from the curve.
fn fingerprint(curve: &Curve) -> u64 {
    let mut hasher = DefaultHasher::new();
    for s in &curve.steps {
        for v in [
            s.approach_m,
            s.load_n,
            s.area_fraction,
            s.area_fraction_current,
            s.mean_gap_m,
            s.largest_penetration_m,
        ] {
            hasher.write_u64(v.to_bits());
        }
    }
    for snapshot in &curve.snapshots {
        hasher.write_usize(snapshot.step);
        snapshot
            .pressure_pa
            .iter()
            .for_each(|p| hasher.write_u64(p.to_bits()));
        snapshot
            .contact
            .iter()
            .for_each(|c| hasher.write_u8(u8::from(*c)));
        snapshot
            .displacement_m
            .iter()
            .flatten()
            .for_each(|u| hasher.write_u64(u.to_bits()));
    }
    hasher.finish()
}

/// Every step's approach, A/A0 and load, and every snapshot's mask.
fn write_products(out: &mut impl Write, run: &str, curve: &Curve) -> std::io::Result<()> {
    for (k, s) in curve.steps.iter().enumerate() {
        writeln!(
            out,
            "{run} step {k} {:e} {:e} {:e}",
            s.approach_m, s.area_fraction, s.load_n
        )?;
    }
    for snapshot in &curve.snapshots {
        let mask: String = snapshot
            .contact
            .iter()
            .map(|c| if *c { '1' } else { '0' })
            .collect();
        writeln!(
            out,
            "{run} mask {} {} {mask}",
            snapshot.requested_area_fraction, snapshot.step
        )?;
    }
    Ok(())
}
