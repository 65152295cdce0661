//! The half-space operator (two of these per conjugate-gradient iteration)
//! at the sizes that matter: a paper-pipeline map (~450², free: 900²
//! transforms) and the 2048² comparison map (free: 4096²).
//!
//! Run: `cargo bench -p hypercontact-bem --bench bem` (RAYON_NUM_THREADS=1
//! for one thread). The whole curve and a 2048² load step are timed by the
//! `load_step` bench.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_bem::{Boundary, Influence};

fn operator(c: &mut Criterion) {
    let mut group = c.benchmark_group("operator");
    group.sample_size(10);
    for (n, boundary) in [
        (450, Boundary::Free),
        (450, Boundary::Periodic),
        (512, Boundary::Free),
        (2048, Boundary::Free),
    ] {
        let influence = Influence::new(n, n, 1e-5, 1e-5, boundary);
        let pressure: Vec<f64> = (0..n * n).map(|k| ((k * 7919) % 101) as f64).collect();
        let mut u = vec![0.0; n * n];
        let mut work = influence.workspace();
        group.bench_function(format!("{boundary:?}/{n}"), |b| {
            b.iter(|| influence.apply(black_box(&pressure), &mut u, &mut work))
        });
    }
    group.finish();
}

criterion_group!(benches, operator);
criterion_main!(benches);
