//! Registration of the paper's camera (2048² pixels of 3.25 µm) onto a
//! 453² scan at 20 µm over ±10° (target: under 2 s on 2 cores), and of the
//! quick pipeline's 512² camera at 4.33 µm.
//!
//! Run: `cargo bench -p hypercontact-compare --bench register`

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use common::{Spec, build};
use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_compare::register::{RegisterSettings, register};

fn registration(c: &mut Criterion) {
    let mut group = c.benchmark_group("register");
    group.sample_size(10);
    for (name, spec) in [
        ("2048px_3.25um_vs_453_scan", Spec::paper()),
        ("512px_4.33um_vs_450_scan", Spec::quick()),
    ] {
        let scene = build(&spec);
        let (predicted, observed) = (scene.predicted_map(), scene.observed_mask());
        let settings = RegisterSettings::default();
        group.bench_function(name, |b| {
            b.iter(|| register(black_box(&predicted), black_box(&observed), &settings).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, registration);
criterion_main!(benches);
