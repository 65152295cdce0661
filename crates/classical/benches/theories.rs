//! The two theories on a realistic spectrum: the radial PSD of a 453² map at
//! 20 µm (the paper pipeline's stitched, filtered T1 size), 200 rows each.
//! `cargo bench -p hypercontact-classical --bench theories`

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_classical::curve::{log_grid, unit_pressure_at};
use hypercontact_classical::gw::Asperities;
use hypercontact_classical::persson::{Persson, Variant};
use hypercontact_classical::spectrum::Spectrum;
use hypercontact_surface::psd::{Window, psd_radial};
use hypercontact_synth::surface::self_affine::SelfAffine;

fn spectrum() -> Spectrum {
    let map = SelfAffine {
        hurst: 0.7,
        rms_m: 14e-6,
        lambda_min_m: 40e-6,
        lambda_max_m: 2e-3,
    }
    .non_periodic(453, 453, 20e-6, 1);
    let psd = psd_radial(&map, 20e-6, 20e-6, Window::Hann, 10);
    Spectrum::from_surface_topography(&psd.q_per_m, &psd.c).unwrap()
}

fn bench(c: &mut Criterion) {
    let s = spectrum();
    let slope = s.moments().rms_slope();
    for (name, variant) in [
        (
            "persson original, 200 rows with separation",
            Variant::Original,
        ),
        (
            "persson yang-persson, 200 rows with separation",
            Variant::YangPersson { gamma: 0.45 },
        ),
    ] {
        c.bench_function(name, |b| {
            b.iter(|| {
                let theory = Persson::new(&s, variant);
                let lo = unit_pressure_at(&theory, 1e-3, slope).unwrap();
                let hi = unit_pressure_at(&theory, 0.95, slope).unwrap();
                theory.curve(&log_grid(lo, hi, 200))
            })
        });
    }
    c.bench_function("greenwood-williamson, 200 rows", |b| {
        b.iter(|| {
            let gw = Asperities::from_moments(s.moments()).unwrap();
            let lo = unit_pressure_at(&gw, 1e-3, slope).unwrap();
            let hi = unit_pressure_at(&gw, 0.95, slope).unwrap();
            log_grid(lo, hi, 200)
                .iter()
                .map(|&p| gw.at_separation(gw.separation_at_unit_pressure(p)))
                .collect::<Vec<_>>()
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
