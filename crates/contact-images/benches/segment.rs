//! Segmenting and labelling one 2048 × 2048 16-bit contact frame on one
//! thread (issue #14's target: under 0.1 s each). The crate uses no thread
//! pool; `RAYON_NUM_THREADS=1` only pins anything a dependency might start.
//!
//! The frame: 3000 dark disks (radius 1–16 px, ~20 % contact) on a vignetted
//! background with a dark offset, shot and read noise; a no-contact reference
//! of the same illumination.
//!
//! Run: `RAYON_NUM_THREADS=1 cargo bench -p hypercontact-contact-images --bench segment`

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_contact_images::{
    Calibrated, Frame, Level, MultiOtsu, label, multi_otsu, otsu, segment_calibrated,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

const N: usize = 2048;
const OFFSET: f64 = 100.0;

fn frames() -> (Frame, Frame) {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let mut contact = vec![false; N * N];
    for _ in 0..3000 {
        let (cx, cy) = (
            rng.random_range(0.0..N as f64),
            rng.random_range(0.0..N as f64),
        );
        let r: f64 = rng.random_range(1.0..16.0);
        let (x0, x1) = ((cx - r).max(0.0) as usize, ((cx + r) as usize + 1).min(N));
        let (y0, y1) = ((cy - r).max(0.0) as usize, ((cy + r) as usize + 1).min(N));
        for y in y0..y1 {
            for x in x0..x1 {
                if (x as f64 - cx).hypot(y as f64 - cy) <= r {
                    contact[y * N + x] = true;
                }
            }
        }
    }
    let mut noisy = |mean: f64| {
        let noise: f64 = StandardNormal.sample(&mut rng);
        let sigma = (30.0_f64 * 30.0 + 20.0 * mean).sqrt();
        (OFFSET + mean + sigma * noise).clamp(0.0, 65535.0) as u16
    };
    let mut frame = Vec::with_capacity(N * N);
    let mut reference = Vec::with_capacity(N * N);
    for y in 0..N {
        for x in 0..N {
            let (dx, dy) = (x as f64 / N as f64 - 0.5, y as f64 / N as f64 - 0.5);
            let lit = 40000.0 * (1.0 - 1.2 * (dx * dx + dy * dy));
            let signal = if contact[y * N + x] { 0.02 * lit } else { lit };
            frame.push(noisy(signal));
            reference.push(noisy(lit));
        }
    }
    (
        Frame::new(N, N, 16, frame).unwrap(),
        Frame::new(N, N, 16, reference).unwrap(),
    )
}

fn segment(c: &mut Criterion) {
    let (frame, reference) = frames();
    let mut group = c.benchmark_group("contact_frame_2048x2048_16bit");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));

    group.bench_function("histogram", |b| b.iter(|| black_box(&frame).histogram()));
    group.bench_function("otsu_histogram_threshold_mask", |b| {
        b.iter(|| {
            let t = otsu(&black_box(&frame).histogram()).unwrap().threshold;
            frame.dark_mask(t)
        })
    });
    let options = MultiOtsu::default();
    group.bench_function("multi_otsu_3_classes_256_bins_mask", |b| {
        b.iter(|| {
            let r = multi_otsu(&black_box(&frame).histogram(), &options).unwrap();
            frame.dark_mask(r.contact_threshold())
        })
    });
    let params = Calibrated {
        dark_level: OFFSET,
        ..Calibrated::default()
    };
    group.bench_function("calibrated_with_patches", |b| {
        b.iter(|| segment_calibrated(black_box(&frame), &reference, &params).unwrap())
    });
    let given = Calibrated {
        contact_level: Level::Given(0.02),
        background_level: Level::Given(1.0),
        ..params
    };
    group.bench_function("calibrated_given_levels_with_patches", |b| {
        b.iter(|| segment_calibrated(black_box(&frame), &reference, &given).unwrap())
    });
    let mask = frame.dark_mask(otsu(&frame.histogram()).unwrap().threshold);
    group.bench_function("label_otsu_mask", |b| b.iter(|| label(black_box(&mask))));
    group.finish();

    let calibrated = segment_calibrated(&frame, &reference, &params).unwrap();
    println!(
        "otsu: {} patches, A/A0 = {:.4}; calibrated: {} patches, A/A0 = {:.4}",
        label(&mask).count(),
        mask.area_fraction(),
        calibrated.patches.count(),
        calibrated.mask.area_fraction()
    );
}

criterion_group!(benches, segment);
criterion_main!(benches);
