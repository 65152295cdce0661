//! Truncation of a 4096 × 4096 self-affine map at 1000 levels (target:
//! under 5 s) against the brute force of relabelling the map at each level,
//! and of a 2048 × 2048 one, the size at which issue #35 compares with
//! scipy's per-level labelling (`benches/scipy_per_level.py`, on the map
//! `examples/bench_map.rs` writes).
//!
//! The brute force is timed on 20 of the 1000 levels (every 50th, at the
//! middle of each block of 50, so the touched fractions span 0 … 1 evenly);
//! its full cost is that time × 50, an extrapolation, said as such.
//!
//! Run: `cargo bench -p hypercontact-truncation --bench truncation`
//!
//! Issue #35 (2048², shared 2-core machine, load 4–6): the sweep takes
//! 0.21–0.24 s (it runs on one thread with `levels: N`; the same with
//! RAYON_NUM_THREADS=1), scipy 15–17 s wall (12 s CPU): 64–80×. Before the
//! grouping by plane it took 0.46 s (32×).

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, criterion_group, criterion_main};
use hypercontact_synth::surface::SelfAffine;
use hypercontact_truncation::flood_fill::label_at;
use hypercontact_truncation::{Connectivity, Levels, TruncationOptions, truncate};

const LEVELS: u32 = 1000;

/// H = 0.8, rms 10 µm, power from the map's side down to two pixels.
fn self_affine(n: usize) -> ndarray::Array2<f64> {
    SelfAffine::whole_band(n, 2e-5).periodic(n, n, 2e-5, 4096)
}

/// The map of side `n` and its group, with the one-sweep truncation timed
/// in it (`samples` samples).
fn union_find_group(
    c: &mut Criterion,
    n: usize,
    samples: usize,
) -> (ndarray::Array2<f64>, BenchmarkGroup<'_, WallTime>) {
    let h = self_affine(n);
    let options = TruncationOptions {
        levels: Levels::Count(LEVELS),
        ..Default::default()
    };
    let mut group = c.benchmark_group(format!("truncation_{n}x{n}_1000_levels"));
    group.sample_size(samples);
    group.bench_function("union_find_one_sweep", |b| {
        b.iter(|| truncate(black_box(h.view()), 2e-5, 2e-5, &options, &mut |_| {}).unwrap())
    });
    (h, group)
}

fn truncation_2048(c: &mut Criterion) {
    union_find_group(c, 2048, 20).1.finish();
}

fn truncation_4096(c: &mut Criterion) {
    let (h, mut group) = union_find_group(c, 4096, 10);

    let h_min = h.iter().copied().fold(f64::INFINITY, f64::min);
    let above = h.mapv(|v| v - h_min);
    let z_max = above.iter().copied().fold(0.0, f64::max);
    let sampled: Vec<f64> = (0..LEVELS / 50)
        .map(|block| {
            let k = block * 50 + 25;
            z_max * f64::from(LEVELS - k) / f64::from(LEVELS)
        })
        .collect();
    group.bench_function("flood_fill_20_of_1000_levels", |b| {
        b.iter(|| {
            sampled
                .iter()
                .map(|&z| label_at(black_box(above.view()), z, Connectivity::Eight).1)
                .sum::<usize>()
        })
    });
    group.finish();
}

criterion_group!(benches, truncation_2048, truncation_4096);
criterion_main!(benches);
