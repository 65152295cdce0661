//! IC-GN throughput: subset 31 px, first-order shape function, bicubic
//! B-spline interpolation, on a 2048 × 2048 frame pair (the paper's
//! camera), one thread. Issue #35's target: ≥ 30 000 POI/s per core.
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
//! The IC-GN group is measured twice: on the wall clock (criterion's
//! default, `icgn/…`) and on the calling thread's own CPU time
//! (`icgn_thread_cpu/…`), since on a shared machine the wall clock also
//! counts other processes' turns on the core.
//!
//! Run: `cargo bench -p hypercontact-dic --bench icgn`.

use std::sync::OnceLock;
use std::time::Instant;

use criterion::measurement::{Measurement, ValueFormatter};
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

/// The frame pair, its per-frame preparations and the POIs with guesses.
struct Setup {
    target_image: GrayImage,
    target: BSplineImage,
    reference: ReferenceFrame,
    settings: IcgnSettings,
    pois: Vec<(usize, usize)>,
    guesses: Vec<Warp>,
}

impl Setup {
    fn get() -> &'static Setup {
        static SETUP: OnceLock<Setup> = OnceLock::new();
        SETUP.get_or_init(Setup::new)
    }

    fn new() -> Setup {
        let centre = [(SIZE as f64 - 1.0) / 2.0; 2];
        let pattern =
            SpecklePattern::random([-40.0, -40.0, 2090.0, 2090.0], 2.5, 0.5, Vec::new(), 9);
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
        Setup {
            target_image,
            target,
            reference,
            settings,
            pois,
            guesses,
        }
    }

    /// One pass over the POIs as the tracker makes it: Σ ZNCC.
    fn match_all(&self) -> f64 {
        let mut zncc_sum = 0.0;
        for (&(x, y), guess) in self.pois.iter().zip(&self.guesses) {
            let subset = self.reference.subset(x, y, 15).unwrap();
            zncc_sum += subset.solve(&self.target, *guess, &self.settings).zncc;
        }
        zncc_sum
    }
}

fn icgn_2048(c: &mut Criterion) {
    let setup = Setup::get();
    // Check once that the benchmark measures working matches.
    let mut iterations = 0;
    for (&(x, y), guess) in setup.pois.iter().zip(&setup.guesses) {
        let subset = setup.reference.subset(x, y, 15).unwrap();
        let m = subset.solve(&setup.target, *guess, &setup.settings);
        assert!(m.converged && m.zncc > 0.99);
        iterations += m.iterations;
    }
    eprintln!(
        "mean IC-GN iterations per POI: {:.2}",
        iterations as f64 / setup.pois.len() as f64
    );

    // A quick figure of both clocks before criterion's samples.
    let passes = 5;
    let (wall, cpu) = (Instant::now(), thread_cpu_s());
    let zncc_sum: f64 = (0..passes).map(|_| setup.match_all()).sum();
    let poi_count = (passes * setup.pois.len()) as f64;
    if let (Some(start), Some(end)) = (cpu, thread_cpu_s()) {
        eprintln!(
            "{:.0} POI/s on this thread's CPU time, {:.0} POI/s wall (Σ ZNCC {zncc_sum:.1})",
            poi_count / (end - start),
            poi_count / wall.elapsed().as_secs_f64()
        );
    }

    let mut group = c.benchmark_group("icgn");
    group.sample_size(10);
    group.throughput(Throughput::Elements(setup.pois.len() as u64));
    group.bench_function("subset31_first_order_2048px_one_thread", |b| {
        b.iter(|| setup.match_all())
    });
    group.finish();

    let mut group = c.benchmark_group("frame_setup");
    group.sample_size(10);
    group.bench_function("bspline_prefilter_2048px", |b| {
        b.iter(|| BSplineImage::new(&setup.target_image))
    });
    group.bench_function("reference_gradients_2048px", |b| {
        b.iter(|| ReferenceFrame::with_spline(setup.target_image.clone(), &setup.target))
    });
    group.finish();
}

/// The IC-GN group again, on the thread's CPU time.
fn icgn_2048_thread_cpu(c: &mut Criterion<ThreadCpuTime>) {
    if thread_cpu_s().is_none() {
        return;
    }
    let setup = Setup::get();
    let mut group = c.benchmark_group("icgn_thread_cpu");
    group.sample_size(10);
    group.throughput(Throughput::Elements(setup.pois.len() as u64));
    group.bench_function("subset31_first_order_2048px_one_thread", |b| {
        b.iter(|| setup.match_all())
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

/// Criterion measurement: the benchmarking thread's CPU time, nanoseconds
/// (criterion runs the routine on the thread that starts and ends the
/// measurement). NaN where schedstat is missing; the group is then skipped.
struct ThreadCpuTime;

impl Measurement for ThreadCpuTime {
    type Intermediate = f64;
    type Value = f64;

    fn start(&self) -> f64 {
        thread_cpu_s().map_or(f64::NAN, |s| s * 1e9)
    }
    fn end(&self, start_ns: f64) -> f64 {
        self.start() - start_ns
    }
    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn to_f64(&self, ns: &f64) -> f64 {
        *ns
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

/// Milliseconds, and elements per second for throughputs (all this bench
/// reports on the CPU clock).
struct CpuFormatter;

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, _typical_ns: f64, values: &mut [f64]) -> &'static str {
        values.iter_mut().for_each(|v| *v *= 1e-6);
        "ms CPU"
    }
    fn scale_throughputs(
        &self,
        _typical_ns: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let elements = match *throughput {
            Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => n,
            _ => 1,
        };
        values
            .iter_mut()
            .for_each(|v| *v = elements as f64 * 1e9 / *v / 1e3);
        "Kelem/s CPU"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

criterion_group!(benches, icgn_2048);
criterion_group! {
    name = cpu_benches;
    config = Criterion::default().with_measurement(ThreadCpuTime);
    targets = icgn_2048_thread_cpu
}
criterion_main!(benches, cpu_benches);
