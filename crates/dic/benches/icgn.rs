//! IC-GN throughput: subset 31 px, first-order shape function, bicubic
//! B-spline interpolation, on a 2048 × 2048 frame pair (the paper's
//! camera), one thread. The target: ≥ 20 000 POI/s per core.
//!
//! Precomputed once per frame, outside the timed loop, as the subset tracker
//! does once per target frame or reference update: the target's B-spline
//! coefficients and the `ReferenceFrame` (the reference spline's gradient at
//! every pixel). Timed per POI, as the tracker does per POI and frame: the
//! reference subset (mean, norm, Σ J̃ f̃, Σ J̃, the 6 × 6 Hessian and its
//! Cholesky factor, gathered from the gradient images) and IC-GN from a
//! guess about one pixel off, as a propagated guess is. The per-frame
//! preparations are timed separately (`*_2048px`, all threads).
//!
//! Run: `cargo bench -p hypercontact-dic --bench icgn`.

use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hypercontact_dic::GrayImage;
use hypercontact_dic::bspline::BSplineImage;
use hypercontact_dic::icgn::{IcgnSettings, ReferenceFrame, Warp};
use hypercontact_synth::tensile::render::{AxisMap, render};
use hypercontact_synth::tensile::speckle::SpecklePattern;

const SIZE: usize = 2048;

fn frame(pattern: &SpecklePattern, map: &AxisMap) -> GrayImage {
    GrayImage::new(SIZE, SIZE, render(pattern, map, SIZE, SIZE, 1)).unwrap()
}

fn icgn_2048(c: &mut Criterion) {
    let centre = [(SIZE as f64 - 1.0) / 2.0; 2];
    let pattern = SpecklePattern::random([-40.0, -40.0, 2090.0, 2090.0], 2.5, 0.5, Vec::new(), 9);
    let reference = frame(&pattern, &AxisMap::identity(centre));
    let map = AxisMap {
        centre,
        stretch: [1.05, 1.05f64.powf(-0.5)],
        shift: [0.4, -0.3],
    };
    let target_image = frame(&pattern, &map);
    let target = BSplineImage::new(&target_image);
    let reference_spline = BSplineImage::new(&reference);
    let reference = ReferenceFrame::with_spline(reference, &reference_spline);
    let settings = IcgnSettings {
        subset_px: 31,
        max_iterations: 30,
        convergence_px: 1e-3,
    };
    // 2 500 POIs at step 16 in the centre of the frame.
    let pois: Vec<(usize, usize)> = (0..50)
        .flat_map(|j| (0..50).map(move |i| (624 + 16 * i, 624 + 16 * j)))
        .collect();
    let guesses: Vec<Warp> = pois
        .iter()
        .map(|&(x, y)| {
            let u = map.to_image(0, x as f64) - x as f64;
            let v = map.to_image(1, y as f64) - y as f64;
            Warp::from_gradient(
                (u + 0.7).round(),
                (v - 0.6).round(),
                [[map.stretch[0], 0.0], [0.0, map.stretch[1]]],
            )
        })
        .collect();

    // Check once that the benchmark measures working matches.
    let mut iterations = 0;
    for (&(x, y), guess) in pois.iter().zip(&guesses) {
        let subset = reference.subset(x, y, 15).unwrap();
        let m = subset.solve(&target, *guess, &settings);
        assert!(m.converged && m.zncc > 0.99);
        iterations += m.iterations;
    }
    eprintln!(
        "mean IC-GN iterations per POI: {:.2}",
        iterations as f64 / pois.len() as f64
    );

    // The same work timed on the thread's own CPU clock as well, since the
    // wall clock of a shared machine also counts other processes' turns.
    let passes = 5;
    let (wall, cpu) = (Instant::now(), thread_cpu_s());
    let mut zncc_sum = 0.0;
    for _ in 0..passes {
        for (&(x, y), guess) in pois.iter().zip(&guesses) {
            let subset = reference.subset(x, y, 15).unwrap();
            zncc_sum += subset.solve(&target, *guess, &settings).zncc;
        }
    }
    let poi_count = (passes * pois.len()) as f64;
    if let (Some(start), Some(end)) = (cpu, thread_cpu_s()) {
        eprintln!(
            "{:.0} POI/s on this thread's CPU time, {:.0} POI/s wall (Σ ZNCC {zncc_sum:.1})",
            poi_count / (end - start),
            poi_count / wall.elapsed().as_secs_f64()
        );
    }

    let mut group = c.benchmark_group("icgn");
    group.sample_size(10);
    group.throughput(Throughput::Elements(pois.len() as u64));
    group.bench_function("subset31_first_order_2048px_one_thread", |b| {
        b.iter(|| {
            let mut zncc_sum = 0.0;
            for (&(x, y), guess) in pois.iter().zip(&guesses) {
                let subset = reference.subset(x, y, 15).unwrap();
                zncc_sum += subset.solve(&target, *guess, &settings).zncc;
            }
            zncc_sum
        })
    });
    group.finish();

    let mut group = c.benchmark_group("frame_setup");
    group.sample_size(10);
    group.bench_function("bspline_prefilter_2048px", |b| {
        b.iter(|| BSplineImage::new(&target_image))
    });
    group.bench_function("reference_gradients_2048px", |b| {
        b.iter(|| ReferenceFrame::with_spline(target_image.clone(), &target))
    });
    group.finish();
}

/// On-CPU time of the calling thread, seconds, from Linux's
/// `/proc/thread-self/schedstat` (None where it does not exist).
fn thread_cpu_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

criterion_group!(benches, icgn_2048);
criterion_main!(benches);
