//! Reading each instrument file shipped in `data/reference/topography/`
//! (0.3–0.4 M points each), bytes already in memory: the cost `height-map`
//! adds over the disk read.
//!
//! Run: `cargo bench -p hypercontact-formats --bench read`

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};

const FILES: [&str; 5] = [
    "x3p-2.x3p",
    "sur-2.sur",
    "plu-1.plu",
    "metropro-1.dat",
    "opd-1.opd",
];

fn read_each(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/reference/topography");
    let mut group = c.benchmark_group("read");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    for name in FILES {
        let path = dir.join(name);
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        group.bench_function(name, |b| {
            b.iter(|| hypercontact_formats::read_bytes(black_box(&bytes), Some(&path)).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, read_each);
criterion_main!(benches);
