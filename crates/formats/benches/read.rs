//! Reading each instrument file, bytes already in memory: the cost
//! `height-map` adds over the disk read. The first five are shipped in
//! `data/reference/topography/` (0.3–0.4 M points each); the instruments
//! of issue 36 are read from `shared/reference/topography/more/` (the same
//! files the reader tests compare with SurfaceTopography).
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

/// One file of each format of issue 36.
const MORE: [&str; 12] = [
    "al3d-1.al3d",
    "di-1.di",
    "frt-1.frt",
    "mnt-1.mnt",
    "nid-1.nid",
    "spot_1-1000nm.ibw",
    "mi-1.mi",
    "tmd-1.tmd",
    "nc-1.nc",
    "matrix-2.txt",
    "gwyddion-export-english.txt",
    "dektak-1.csv",
];

fn read_each(c: &mut Criterion) {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shipped = manifest.join("../../data/reference/topography");
    let more = manifest.join("../../../shared/reference/topography/more");
    let mut group = c.benchmark_group("read");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    let paths = FILES
        .iter()
        .map(|name| shipped.join(name))
        .chain(MORE.iter().map(|name| more.join(name)));
    for path in paths {
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        group.bench_function(name, |b| {
            b.iter(|| hypercontact_formats::read_bytes(black_box(&bytes), Some(&path)).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, read_each);
criterion_main!(benches);
