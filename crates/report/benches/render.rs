//! Time to render the full report for four samples at realistic sizes:
//! 500 × 500 height maps, 1000-level truncation and ICM responses.
//! `cargo bench -p hypercontact-report --bench render`

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_report::{ReportOptions, render_report};

fn full_report(c: &mut Criterion) {
    let inputs = common::inputs(common::ALL, 500, 1000);
    let options = ReportOptions::default();
    let mut group = c.benchmark_group("report");
    group.sample_size(10);
    group.bench_function("full_4_samples_500x500_1000_levels", |b| {
        b.iter(|| render_report(&inputs, &options, None).expect("renders"))
    });
    group.finish();
}

criterion_group!(benches, full_report);
criterion_main!(benches);
