//! The measurement harness of issue #35: the `bem` stage's default curve
//! (free boundary, 40 steps to A/A0 = 0.9, tolerance 1e-8, 2000 iterations
//! per solve) on a real instrument map, timed, with where the iterations go
//! and fingerprints of the bits.
//!
//! Run: `cargo run --release -p hypercontact-bem --example plu_curve --
//! [MAP] [--dump DIR]` (MAP defaults to data/reference/topography/plu-1.plu,
//! read with `hypercontact_formats` as the `height-map` stage reads vendor
//! files). Prints per step the solves, the iterations of the accepted solve
//! and of the trials, then the totals, wall and CPU time and BLAKE3 hashes
//! of the rows and of the pressures. `--dump DIR` also writes the rows
//! (rows.txt, exact bits) and each step's contact mask (mask_K.bin, one bit
//! per pixel) and the last pressure (pressure_last.bin, f64 little-endian);
//! `--pressures` also writes every step's pressure (pressure_K.bin).
//! `--at DIR` solves at the approaches of an earlier dump's rows instead of
//! choosing them (each solve warm-started from the previous two, as the
//! curve does), so two solvers can be compared at the same approaches (a
//! curve chooses its next approach from the areas it found, and a pixel
//! more or less moves every later step). `compare DIR_A DIR_B` then
//! reports the largest relative changes in load, area and approach per step
//! and the pixels whose contact differs, with (when both dumps hold the
//! pressures) the largest pressure at such a pixel over the step's mean
//! contact pressure.
//!
//! Issue #48's before/after (main's solver built into this example by
//! checking out its `crates/bem/src/polonsky_keer.rs`, then this branch's):
//! `plu_curve --dump B --pressures` with each binary, one after the other,
//! then `plu_curve --at B --dump C --pressures` and `plu_curve compare B C`
//! for the products at the same approaches. Measured 2026-12-07 on 2 cores
//! at load ~10: 2 166 → 1 151 iterations, CPU 86.2 → 63.7 s, wall 167.3 →
//! 152.1 s; at main's approaches loads within 1.2e-8, at most 2 pixels of
//! a step's contact set differ, under 1.1e-6 of the mean contact pressure.

use std::path::{Path, PathBuf};
use std::time::Instant;

use hypercontact_bem::curve::warm_start;
use hypercontact_bem::{
    Boundary, Control, CurveOptions, Influence, Problem, Solution, SolverOptions, Step, solve_curve,
};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("compare") {
        let [_, a, b] = args.as_slice() else {
            panic!("usage: compare DIR_A DIR_B");
        };
        compare(Path::new(a), Path::new(b));
        return;
    }
    let mut run = Run {
        map: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/reference/topography/plu-1.plu"),
        dump: None,
        pressures: false,
        at: None,
    };
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--dump" => run.dump = Some(PathBuf::from(rest.next().expect("--dump DIR"))),
            "--at" => run.at = Some(PathBuf::from(rest.next().expect("--at DIR"))),
            "--pressures" => run.pressures = true,
            _ => run.map = PathBuf::from(arg),
        }
    }
    run.run();
}

/// What to run: the map, where to dump, and whether at a dump's approaches.
struct Run {
    map: PathBuf,
    dump: Option<PathBuf>,
    /// every step's pressure into the dump
    pressures: bool,
    /// the dump whose approaches to solve at
    at: Option<PathBuf>,
}

/// CPU seconds of the whole process (every thread), user + system, from
/// /proc/self/stat (fields 14 and 15, in USER_HZ = 100 ticks per second).
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat");
    // The command name (field 2) may hold spaces: count from after its ')'.
    let after = &stat[stat.rfind(')').expect("a stat line") + 2..];
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks: f64 = fields[11].parse::<f64>().unwrap() + fields[12].parse::<f64>().unwrap();
    ticks / 100.0
}

impl Run {
    fn run(&self) {
        let map = &self.map;
        let bytes = std::fs::read(map).expect("read the map");
        let topo = hypercontact_formats::read_bytes(&bytes, Some(map)).expect("a height map");
        let (nx, ny) = topo.heights_m.dim();
        let heights: Vec<f64> = topo.heights_m.iter().copied().collect();
        let missing = heights.iter().filter(|h| h.is_nan()).count();
        println!(
            "{}: {nx} × {ny} at {:.4} × {:.4} µm, {missing} missing; {} threads",
            map.display(),
            topo.dx_m * 1e6,
            topo.dy_m * 1e6,
            rayon::current_num_threads()
        );
        let (wall, cpu) = (Instant::now(), cpu_seconds());
        let influence = Influence::new(nx, ny, topo.dx_m, topo.dy_m, Boundary::Free);
        let problem = Problem::new(&influence, &heights).expect("a contact problem");
        let setup = wall.elapsed();
        // The `bem` stage's defaults.
        let options = CurveOptions {
            steps: 40,
            max_area_fraction: 0.9,
            solver: SolverOptions {
                tolerance: 1e-8,
                max_iterations: 2000,
                ..SolverOptions::default()
            },
        };
        let mut seen = Seen::default();
        let rows = match &self.at {
            None => solve_curve(&problem, options, &mut |_, _, s| {
                seen.add(s, self.pressures)
            })
            .expect("the curve"),
            Some(dir) => {
                let approaches: Vec<f64> = read_rows(dir).iter().map(|r| r.0).collect();
                solve_at(&problem, &approaches, options.solver, &mut |s| {
                    seen.add(s, self.pressures)
                })
            }
        };
        let (wall, cpu) = (wall.elapsed(), cpu_seconds() - cpu);
        report(&rows);
        println!(
            "wall {:.2} s (set-up {:.2} s), CPU {:.2} s",
            wall.as_secs_f64(),
            setup.as_secs_f64(),
            cpu
        );
        seen.report(&rows);
        if let Some(dir) = &self.dump {
            seen.dump(dir, &rows);
        }
    }
}

/// What the run keeps of each step: fingerprints, masks and pressures.
#[derive(Default)]
struct Seen {
    pressures: Vec<Vec<f64>>,
    hash: blake3::Hasher,
    last_pressure: Vec<f64>,
    masks: Vec<Vec<u8>>,
}

impl Seen {
    fn add(&mut self, s: &Solution, keep: bool) {
        for p in &s.pressure {
            self.hash.update(&p.to_le_bytes());
        }
        self.masks.push(pack_mask(&s.pressure));
        self.last_pressure.clone_from(&s.pressure);
        if keep {
            self.pressures.push(s.pressure.clone());
        }
    }

    fn report(&self, rows: &[Step]) {
        let mut row_hash = blake3::Hasher::new();
        for r in rows {
            row_hash.update(row_line(r).as_bytes());
        }
        let mut last_hash = blake3::Hasher::new();
        for p in &self.last_pressure {
            last_hash.update(&p.to_le_bytes());
        }
        println!("blake3 rows      {}", row_hash.finalize());
        println!("blake3 pressures {}", self.hash.finalize());
        println!("blake3 last p    {}", last_hash.finalize());
    }

    fn dump(&self, dir: &Path, rows: &[Step]) {
        std::fs::create_dir_all(dir).expect("create the dump directory");
        let text: String = rows.iter().map(row_line).collect();
        std::fs::write(dir.join("rows.txt"), text).expect("write rows.txt");
        for (k, mask) in self.masks.iter().enumerate() {
            std::fs::write(dir.join(format!("mask_{}.bin", k + 1)), mask).expect("write a mask");
        }
        let bytes = |p: &[f64]| -> Vec<u8> { p.iter().flat_map(|p| p.to_le_bytes()).collect() };
        std::fs::write(dir.join("pressure_last.bin"), bytes(&self.last_pressure))
            .expect("write the pressure");
        for (k, p) in self.pressures.iter().enumerate() {
            std::fs::write(dir.join(format!("pressure_{}.bin", k + 1)), bytes(p))
                .expect("write a pressure");
        }
    }
}

/// The curve's steps at given approaches (row 0, first contact, included
/// in `approaches` and skipped): each solve warm-started from the previous
/// two as [`solve_curve`] does, one solve per step.
fn solve_at(
    problem: &Problem,
    approaches: &[f64],
    solver: SolverOptions,
    on_step: &mut dyn FnMut(&Solution),
) -> Vec<Step> {
    let measured = problem.measured() as f64;
    let mut rows = vec![Step {
        approach_m: 0.0,
        area_fraction: 0.0,
        contact_pixels: 0,
        mean_pressure: 0.0,
        iterations: 0,
        solves: 0,
        accepted_iterations: 0,
        residual: 0.0,
    }];
    let mut recent: Vec<(f64, Vec<f64>)> = Vec::new();
    for &approach_m in &approaches[1..] {
        let warm = warm_start(&recent, approach_m);
        let s = problem
            .solve(Control::Approach(approach_m), solver, warm.as_deref())
            .expect("a solve");
        on_step(&s);
        rows.push(Step {
            approach_m,
            area_fraction: s.contact_pixels as f64 / measured,
            contact_pixels: s.contact_pixels,
            mean_pressure: s.mean_pressure,
            iterations: s.iterations,
            solves: 1,
            accepted_iterations: s.iterations,
            residual: s.residual,
        });
        if recent.len() == 2 {
            recent.remove(0);
        }
        recent.push((approach_m, s.pressure));
    }
    rows
}

/// Per step: the solves, the accepted solve's iterations and the trials';
/// then the totals.
fn report(rows: &[Step]) {
    println!(" k  A/A0     approach_m    p/E*          solves  accepted  trials");
    let (mut accepted, mut trials, mut solves) = (0, 0, 0);
    for (k, r) in rows.iter().enumerate().skip(1) {
        let trial = r.iterations - r.accepted_iterations;
        println!(
            "{k:2}  {:.5}  {:.6e}  {:.6e}  {:6}  {:8}  {:6}",
            r.area_fraction, r.approach_m, r.mean_pressure, r.solves, r.accepted_iterations, trial
        );
        accepted += r.accepted_iterations;
        trials += trial;
        solves += r.solves;
    }
    println!(
        "solves {solves}; iterations {} (accepted {accepted}, trials {trials})",
        accepted + trials
    );
}

/// One row as exact bits (hex) then readable values: approach, area
/// fraction, contact pixels, mean pressure, residual, iterations.
fn row_line(r: &Step) -> String {
    format!(
        "{:016x} {:016x} {:016x} {:016x} {} {} | {:.9e} {:.9e} {:.9e} {:.3e}\n",
        r.approach_m.to_bits(),
        r.area_fraction.to_bits(),
        r.mean_pressure.to_bits(),
        r.residual.to_bits(),
        r.contact_pixels,
        r.iterations,
        r.approach_m,
        r.area_fraction,
        r.mean_pressure,
        r.residual
    )
}

/// p > 0 as one bit per pixel, least significant first.
fn pack_mask(pressure: &[f64]) -> Vec<u8> {
    pressure
        .chunks(8)
        .map(|c| {
            c.iter()
                .enumerate()
                .fold(0u8, |b, (i, &p)| b | (u8::from(p > 0.0) << i))
        })
        .collect()
}

/// The rows of a dump: (approach, area fraction, contact pixels, mean
/// pressure) from the exact bits.
fn read_rows(dir: &Path) -> Vec<(f64, f64, usize, f64)> {
    let text = std::fs::read_to_string(dir.join("rows.txt")).expect("read rows.txt");
    text.lines()
        .map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            let bits = |s: &str| f64::from_bits(u64::from_str_radix(s, 16).expect("hex bits"));
            (
                bits(f[0]),
                bits(f[1]),
                f[4].parse().expect("pixels"),
                bits(f[2]),
            )
        })
        .collect()
}

fn compare(a: &Path, b: &Path) {
    let (ra, rb) = (read_rows(a), read_rows(b));
    assert_eq!(ra.len(), rb.len(), "the dumps have different step counts");
    let relative = |x: f64, y: f64| {
        if x == y {
            0.0
        } else {
            (x - y).abs() / x.abs().max(y.abs())
        }
    };
    let (mut worst_load, mut worst_area, mut worst_approach) = (0f64, 0f64, 0f64);
    let (mut worst_pixels, mut worst_edge, mut worst_dp) = (0, 0f64, 0f64);
    println!(
        " k  d(approach)  d(area)     d(load)     pixels differing (A only, B only)  \
         max p there / mean p  max |dp| / max p"
    );
    for (k, (x, y)) in ra.iter().zip(&rb).enumerate().skip(1) {
        let (da, dr, dl) = (relative(x.0, y.0), relative(x.1, y.1), relative(x.3, y.3));
        let ma = std::fs::read(a.join(format!("mask_{k}.bin"))).expect("mask A");
        let mb = std::fs::read(b.join(format!("mask_{k}.bin"))).expect("mask B");
        let only = |p: &[u8], q: &[u8]| -> u32 {
            p.iter().zip(q).map(|(p, q)| (p & !q).count_ones()).sum()
        };
        let (only_a, only_b) = (only(&ma, &mb), only(&mb, &ma));
        let pressures = pressure_differences(a, b, k);
        println!(
            "{k:2}  {da:.3e}    {dr:.3e}   {dl:.3e}   {} ({only_a}, {only_b}){}",
            only_a + only_b,
            pressures.map_or(String::new(), |(edge, dp)| format!(
                "   {edge:.3e}   {dp:.3e}"
            ))
        );
        worst_approach = worst_approach.max(da);
        worst_area = worst_area.max(dr);
        worst_load = worst_load.max(dl);
        worst_pixels = worst_pixels.max(only_a + only_b);
        if let Some((edge, dp)) = pressures {
            worst_edge = worst_edge.max(edge);
            worst_dp = worst_dp.max(dp);
        }
    }
    println!(
        "largest relative change: approach {worst_approach:.3e}, area {worst_area:.3e}, load \
         {worst_load:.3e}; at most {worst_pixels} pixels differ in one step's contact set, \
         their pressure at most {worst_edge:.3e} of the mean contact pressure; pressures differ \
         by at most {worst_dp:.3e} of the peak"
    );
}

/// With both dumps' pressures of step k: the largest pressure at a pixel in
/// contact in one only, over the mean contact pressure (of the dump where
/// it is in contact), and the largest |p_A − p_B| over the peak pressure.
fn pressure_differences(a: &Path, b: &Path, k: usize) -> Option<(f64, f64)> {
    let read = |dir: &Path| -> Option<Vec<f64>> {
        let bytes = std::fs::read(dir.join(format!("pressure_{k}.bin"))).ok()?;
        let values = bytes.chunks_exact(8);
        Some(
            values
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect(),
        )
    };
    let (pa, pb) = (read(a)?, read(b)?);
    let mean_contact = |p: &[f64]| {
        let contact = p.iter().filter(|&&p| p > 0.0).count().max(1);
        p.iter().sum::<f64>() / contact as f64
    };
    let (mean_a, mean_b) = (mean_contact(&pa), mean_contact(&pb));
    let peak = pa.iter().chain(&pb).copied().fold(0.0, f64::max);
    let (mut edge, mut dp) = (0f64, 0f64);
    for (&x, &y) in pa.iter().zip(&pb) {
        if (x > 0.0) != (y > 0.0) {
            edge = edge.max(x / mean_a).max(y / mean_b);
        }
        dp = dp.max((x - y).abs() / peak);
    }
    Some((edge, dp))
}
