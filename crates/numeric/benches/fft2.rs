//! The 2-D FFT at the sizes the stages use: a 1024² real map there and back
//! (a correlation's transforms), a 2048² map convolved on its padded 4096²
//! grid (the BEM's free-surface operator, twice per solver iteration), and
//! a 1024² complex transform (phase correlation).
//!
//! Run: `cargo bench -p hypercontact-numeric --bench fft2`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_numeric::fft2::{Complex64, ComplexFft2, Direction, RealFft2};

fn map(rows: usize, cols: usize) -> Vec<f64> {
    (0..rows * cols)
        .map(|k| ((k * 7919) % 101) as f64)
        .collect()
}

fn fft2(c: &mut Criterion) {
    let mut group = c.benchmark_group("fft2");
    group.sample_size(10);

    let n = 1024;
    let fft = RealFft2::new(n, n).unwrap();
    let values = map(n, n);
    let mut spectrum = vec![Complex64::ZERO; fft.spectrum_len()];
    let mut back = vec![0.0; n * n];
    let mut work = fft.workspace();
    let scale = 1.0 / (n * n) as f64;
    group.bench_function("real_1024_forward_inverse", |b| {
        b.iter(|| {
            fft.forward(black_box(&values), (n, n), &mut spectrum, &mut work)
                .unwrap();
            fft.inverse(&mut spectrum, (n, n), &mut back, scale)
                .unwrap();
        })
    });

    let (n, m) = (2048, 4096);
    let fft = RealFft2::new(m, m).unwrap();
    let kernel: Vec<f64> = map(m, m).iter().map(|v| v * 1e-3).collect();
    let mut kernel_spectrum = vec![Complex64::ZERO; fft.spectrum_len()];
    let mut work = fft.workspace();
    fft.forward(&kernel, (m, m), &mut kernel_spectrum, &mut work)
        .unwrap();
    drop(kernel);
    let real_kernel: Vec<f64> = kernel_spectrum.iter().map(|c| c.re).collect();
    drop(kernel_spectrum);
    let pressure = map(n, n);
    let mut displacement = vec![0.0; n * n];
    group.bench_function("real_2048_on_4096_convolution", |b| {
        b.iter(|| {
            fft.convolve(
                black_box(&pressure),
                (n, n),
                &mut displacement,
                1.0,
                &mut work,
                |offset, strip| {
                    for (c, &k) in strip.iter_mut().zip(&real_kernel[offset..]) {
                        *c *= k;
                    }
                },
            )
            .unwrap()
        })
    });

    let n = 1024;
    let fft = ComplexFft2::new(n, n).unwrap();
    let mut data: Vec<Complex64> = map(n, n).iter().map(|&v| Complex64::new(v, 0.0)).collect();
    group.bench_function("complex_1024_forward", |b| {
        b.iter(|| {
            fft.process(black_box(&mut data), Direction::Forward)
                .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, fft2);
criterion_main!(benches);
