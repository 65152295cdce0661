//! One 2048² 16-bit frame rendered from a 512² gap field on two threads
//! (resampling + table lookup + camera), its three parts, and the table's
//! construction (once per sequence).
//!
//! Run: `cargo bench -p hypercontact-interference --bench render`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_interference::{
    Camera, CameraGrid, CameraParams, GapMap, OpticsParams, Placement, render_frame, resample,
};
use ndarray::Array2;

/// A wavy surface pressed onto the glass: contact patches, fringes around
/// them, far gaps, and an unmeasured corner.
fn gap_field(n: usize, dx_m: f64) -> Array2<f64> {
    Array2::from_shape_fn((n, n), |(i, j)| {
        if i + j < n / 16 {
            return f64::NAN;
        }
        let (x, y) = (i as f64 * dx_m, j as f64 * dx_m);
        let h =
            2e-6 * ((x / 3e-4).sin() * (y / 4e-4).cos() + 0.5 * (x / 1.1e-4 + y / 1.7e-4).sin());
        (h + 1.5e-6).max(0.0)
    })
}

fn render(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let (n, dx_m) = (512, 20e-6);
    let field = gap_field(n, dx_m);
    let gap = GapMap::square(field.view(), dx_m);
    let grid = CameraGrid::square(2048, 5e-6);
    let placement = Placement {
        angle_rad: 0.05,
        shift_x_m: 1e-4,
        shift_y_m: -2e-4,
    };
    let optics = OpticsParams::default();
    let mut group = c.benchmark_group("render");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(6));
    group.bench_function("table", |b| {
        b.iter(|| pool.install(|| optics.build().unwrap()))
    });
    let table = pool.install(|| optics.build().unwrap());
    let camera = Camera::new(CameraParams::default(), table.max_reflectance()).unwrap();
    group.bench_function("frame_2048_from_512", |b| {
        b.iter(|| {
            pool.install(|| {
                render_frame(black_box(&gap), &placement, &grid, &table, &camera, 7).unwrap()
            })
        })
    });
    group.bench_function("resample", |b| {
        b.iter(|| pool.install(|| resample(black_box(&gap), &placement, &grid).unwrap()))
    });
    let mut gaps = resample(&gap, &placement, &grid).unwrap();
    group.bench_function("lookup", |b| {
        b.iter(|| {
            let mut g = gaps.clone();
            pool.install(|| table.apply(black_box(&mut g)));
            g
        })
    });
    table.apply(&mut gaps);
    group.bench_function("camera", |b| {
        b.iter(|| pool.install(|| camera.capture(black_box(&gaps), 2048, 2048, 7).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
