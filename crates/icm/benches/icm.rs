//! ICM over 100 000 planes (target: under 0.1 s), per model and scheme.
//!
//! Run: `cargo bench -p hypercontact-icm --bench icm`

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_icm::{CompositeModulus, Model, ProfileSlices, Scheme, solve};
use hypercontact_material::presets::paper_epdm;
use hypercontact_synth::surface::SelfAffine;
use hypercontact_truncation::{Levels, TruncationOptions, truncate};

fn icm_100k_levels(c: &mut Criterion) {
    // H = 0.8, rms 10 µm, power from the map's side down to two pixels.
    let h = SelfAffine::whole_band(512, 2e-5).periodic(512, 512, 2e-5, 2024);
    let options = TruncationOptions {
        levels: Levels::Count(100_000),
        ..Default::default()
    };
    let p = truncate(h.view(), 2e-5, 2e-5, &options, &mut |_| {}).unwrap();
    let patches: Vec<f64> = p.patches.iter().map(|&n| n as f64).collect();
    let slices = ProfileSlices {
        z_m: &p.z_m,
        area_m2: &p.area_m2,
        patches: &patches,
        radius_m: &p.radius_m,
    };
    let mut group = c.benchmark_group("icm_100001_planes");
    group.sample_size(10);
    for model in [Model::Linear, Model::Hyperelastic] {
        let modulus = CompositeModulus::new(Arc::new(paper_epdm()), model, 0.5).unwrap();
        for scheme in [Scheme::Euler, Scheme::Heun] {
            group.bench_function(format!("{model:?}/{scheme:?}"), |b| {
                b.iter(|| {
                    solve(black_box(slices), scheme, &mut |s| {
                        modulus.at_stress_pa(s).map_err(|e| e.to_string())
                    })
                    .unwrap()
                })
            });
        }
    }
    // The whole hyperelastic computation as the stage does it: the material
    // law and its tangent table built, then the Heun integration.
    group.bench_function("Hyperelastic/Heun+setup", |b| {
        b.iter(|| {
            let modulus =
                CompositeModulus::new(Arc::new(paper_epdm()), Model::Hyperelastic, 0.5).unwrap();
            solve(black_box(slices), Scheme::Heun, &mut |s| {
                modulus.at_stress_pa(s).map_err(|e| e.to_string())
            })
            .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, icm_100k_levels);
criterion_main!(benches);
