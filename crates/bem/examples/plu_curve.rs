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
//! `compare DIR_A DIR_B` then reports the largest relative changes in load,
//! area and approach per step and the pixels whose contact differs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use hypercontact_bem::{Boundary, CurveOptions, Influence, Problem, SolverOptions, solve_curve};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("compare") {
        let [_, a, b] = args.as_slice() else {
            panic!("usage: compare DIR_A DIR_B");
        };
        compare(Path::new(a), Path::new(b));
        return;
    }
    let mut dump = None;
    let mut map =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/reference/topography/plu-1.plu");
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        if arg == "--dump" {
            dump = Some(PathBuf::from(rest.next().expect("--dump DIR")));
        } else {
            map = PathBuf::from(arg);
        }
    }
    run(&map, dump.as_deref());
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

fn run(map: &Path, dump: Option<&Path>) {
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
    let mut pressures = blake3::Hasher::new();
    let mut last_pressure = Vec::new();
    let mut masks = Vec::new();
    let rows = solve_curve(&problem, options, &mut |_, _, s| {
        for p in &s.pressure {
            pressures.update(&p.to_le_bytes());
        }
        masks.push(pack_mask(&s.pressure));
        last_pressure.clone_from(&s.pressure);
    })
    .expect("the curve");
    let (wall, cpu) = (wall.elapsed(), cpu_seconds() - cpu);

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
    let mut row_hash = blake3::Hasher::new();
    for r in &rows {
        row_hash.update(row_line(r).as_bytes());
    }
    let mut last_hash = blake3::Hasher::new();
    for p in &last_pressure {
        last_hash.update(&p.to_le_bytes());
    }
    println!(
        "solves {solves}; iterations {} (accepted {accepted}, trials {trials})",
        accepted + trials
    );
    println!(
        "wall {:.2} s (set-up {:.2} s), CPU {:.2} s",
        wall.as_secs_f64(),
        setup.as_secs_f64(),
        cpu
    );
    println!("blake3 rows      {}", row_hash.finalize());
    println!("blake3 pressures {}", pressures.finalize());
    println!("blake3 last p    {}", last_hash.finalize());
    if let Some(dir) = dump {
        std::fs::create_dir_all(dir).expect("create the dump directory");
        let text: String = rows.iter().map(row_line).collect();
        std::fs::write(dir.join("rows.txt"), text).expect("write rows.txt");
        for (k, mask) in masks.iter().enumerate() {
            std::fs::write(dir.join(format!("mask_{}.bin", k + 1)), mask).expect("write a mask");
        }
        let bytes: Vec<u8> = last_pressure.iter().flat_map(|p| p.to_le_bytes()).collect();
        std::fs::write(dir.join("pressure_last.bin"), bytes).expect("write the pressure");
    }
}

/// One row as exact bits (hex) then readable values: approach, area
/// fraction, contact pixels, mean pressure, residual, iterations.
fn row_line(r: &hypercontact_bem::Step) -> String {
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
    let mut worst_pixels = 0;
    println!(" k  d(approach)  d(area)     d(load)     pixels differing (A only, B only)");
    for (k, (x, y)) in ra.iter().zip(&rb).enumerate().skip(1) {
        let (da, dr, dl) = (relative(x.0, y.0), relative(x.1, y.1), relative(x.3, y.3));
        let ma = std::fs::read(a.join(format!("mask_{k}.bin"))).expect("mask A");
        let mb = std::fs::read(b.join(format!("mask_{k}.bin"))).expect("mask B");
        let only = |p: &[u8], q: &[u8]| -> u32 {
            p.iter().zip(q).map(|(p, q)| (p & !q).count_ones()).sum()
        };
        let (only_a, only_b) = (only(&ma, &mb), only(&mb, &ma));
        println!(
            "{k:2}  {da:.3e}    {dr:.3e}   {dl:.3e}   {} ({only_a}, {only_b})",
            only_a + only_b
        );
        worst_approach = worst_approach.max(da);
        worst_area = worst_area.max(dr);
        worst_load = worst_load.max(dl);
        worst_pixels = worst_pixels.max(only_a + only_b);
    }
    println!(
        "largest relative change: approach {worst_approach:.3e}, area {worst_area:.3e}, load \
         {worst_load:.3e}; at most {worst_pixels} pixels differ in one step's contact set"
    );
}
