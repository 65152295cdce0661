//! 1-D (along x and y) and radial PSDs of a 4096 × 4096 map, 10 bins per
//! decade, with a Hann window (non-periodic treatment) and without
//! (periodic). Issue #4's target: faster than SurfaceTopography's
//! `power_spectrum_from_profile` / `power_spectrum_from_area` on the same map.
//!
//! Run: `cargo bench -p hypercontact-surface --bench psd`

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_surface::psd::{Window, psd_radial, psd_x, psd_y};
use hypercontact_synth::surface::SelfAffine;

const N: usize = 4096;
const PIXEL_M: f64 = 1e-6;
const PER_DECADE: usize = 10;

fn psd_4096(c: &mut Criterion) {
    let h = SelfAffine::MICRON.periodic(N, N, PIXEL_M, 4);
    let mut group = c.benchmark_group("psd_4096x4096");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(8));
    for (name, window) in [("hann", Window::Hann), ("periodic", Window::None)] {
        group.bench_function(format!("x/{name}"), |b| {
            b.iter(|| psd_x(black_box(&h), PIXEL_M, window, PER_DECADE))
        });
        group.bench_function(format!("y/{name}"), |b| {
            b.iter(|| psd_y(black_box(&h), PIXEL_M, window, PER_DECADE))
        });
        group.bench_function(format!("radial/{name}"), |b| {
            b.iter(|| psd_radial(black_box(&h), PIXEL_M, PIXEL_M, window, PER_DECADE))
        });
    }
    group.finish();
}

criterion_group!(benches, psd_4096);
criterion_main!(benches);
