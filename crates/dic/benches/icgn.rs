//! IC-GN throughput: subset 31 px, first-order shape function, bicubic
//! B-spline interpolation, on a 2048 × 2048 frame pair (the paper's
//! camera), one thread. Each POI builds its reference subset (gradients,
//! Hessian) and iterates from a guess one pixel off, as a propagated guess
//! is. The target: ≥ 20 000 POI/s per core.
//!
//! Run: `cargo bench -p hypercontact-dic --bench icgn`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hypercontact_dic::GrayImage;
use hypercontact_dic::bspline::BSplineImage;
use hypercontact_dic::icgn::{IcgnSettings, ReferenceSubset, Warp};
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
    let target = BSplineImage::new(&frame(&pattern, &map));
    let reference_spline = BSplineImage::new(&reference);
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
        let subset = ReferenceSubset::new(&reference, &reference_spline, x, y, 15).unwrap();
        let m = subset.solve(&target, *guess, &settings);
        assert!(m.converged && m.zncc > 0.99);
        iterations += m.iterations;
    }
    eprintln!(
        "mean IC-GN iterations per POI: {:.2}",
        iterations as f64 / pois.len() as f64
    );

    let mut group = c.benchmark_group("icgn");
    group.sample_size(10);
    group.throughput(Throughput::Elements(pois.len() as u64));
    group.bench_function("subset31_first_order_2048px_one_thread", |b| {
        b.iter(|| {
            let mut zncc_sum = 0.0;
            for (&(x, y), guess) in pois.iter().zip(&guesses) {
                let subset = ReferenceSubset::new(&reference, &reference_spline, x, y, 15).unwrap();
                zncc_sum += subset.solve(&target, *guess, &settings).zncc;
            }
            zncc_sum
        })
    });
    group.finish();
}

criterion_group!(benches, icgn_2048);
criterion_main!(benches);
