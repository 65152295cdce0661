//! Truncates a large synthetic map once, for measuring time and peak memory:
//!
//! `cargo build -p hypercontact-truncation --release --example peak_rss`
//! `/usr/bin/time -v $CARGO_TARGET_DIR/release/examples/peak_rss 8192 1000`
//!
//! Prints the peak resident memory after generating the map (the FFT
//! buffers, freed before the truncation) and after the truncation.

use std::time::Instant;

use hypercontact_synth::surface::SelfAffine;
use hypercontact_truncation::{Levels, TruncationOptions, truncate};

fn peak_rss() -> String {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM"))
                .map(str::to_owned)
        })
        .unwrap_or_else(|| "VmHWM: unknown".into())
}

/// User + system CPU seconds of this process so far (from /proc, 100 Hz
/// ticks), a figure less disturbed than wall time on a busy machine.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the parenthesised command name; utime and stime are the
    // 14th and 15th fields of the whole line.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(8192);
    let levels: u32 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(1000);
    let start = Instant::now();
    let h = SelfAffine::whole_band(n, 2e-5).periodic(n, n, 2e-5, 8192);
    println!(
        "generated {n} × {n} in {:.2} s; {}",
        start.elapsed().as_secs_f64(),
        peak_rss()
    );
    let (start, cpu_start) = (Instant::now(), cpu_s());
    let options = TruncationOptions {
        levels: Levels::Count(levels),
        ..Default::default()
    };
    let p = truncate(h.view(), 2e-5, 2e-5, &options, &mut |_| {}).expect("a self-affine map");
    let mid = p.area_fraction.iter().position(|&f| f >= 0.5).unwrap_or(0);
    println!(
        "truncated at {} planes in {:.2} s wall, {:.2} s CPU; N = {} at A/A0 = {:.3}; {}",
        p.z_m.len(),
        start.elapsed().as_secs_f64(),
        cpu_s() - cpu_start,
        p.patches[mid],
        p.area_fraction[mid],
        peak_rss()
    );
}
