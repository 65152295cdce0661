//! Issue #18's target: 200 bootstrap refits of a 6-term Ogden fit (stable
//! constraint, the shipped 150-point sample) plus their ICM solves for four
//! samples (1000-plane profiles of 453² maps at 20 µm, the paper's size)
//! in under 30 s on 2 cores.
//!
//! Run: `cargo bench -p hypercontact-icm --bench bootstrap`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_core::{Context, Inputs, Outputs, Params, Product, Schema, Stage, Table};
use hypercontact_icm::stage::{Icm, IcmParams};
use hypercontact_material::Family;
use hypercontact_material::fit_stage::{BootstrapParams, MaterialFit, MaterialFitParams};
use hypercontact_material::sample::paper_sample;
use hypercontact_synth::surface::SelfAffine;
use hypercontact_truncation::stage::profile_table;
use hypercontact_truncation::{Levels, TruncationOptions, truncate};

fn table(out: &Outputs, name: &str) -> Table {
    match out.get(name) {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no table {name}"),
    }
}

fn profiles() -> Vec<Table> {
    (1..=4)
        .map(|seed| {
            let h = SelfAffine::whole_band(453, 2e-5).periodic(453, 453, 2e-5, seed);
            let options = TruncationOptions {
                levels: Levels::Count(1000),
                ..Default::default()
            };
            let p = truncate(h.view(), 2e-5, 2e-5, &options, &mut |_| {}).unwrap();
            profile_table(&p).into_table()
        })
        .collect()
}

fn bootstrap_to_bands(c: &mut Criterion) {
    let tensile = Inputs::new().with("tensile", Product::Table(paper_sample().to_table()));
    let fit = MaterialFitParams {
        model: Family::Ogden(6),
        compare: false,
        bootstrap: BootstrapParams {
            count: 200,
            ..Default::default()
        },
        ..Default::default()
    }
    .check()
    .unwrap();
    let icm = IcmParams::default().check().unwrap();
    let profiles = profiles();
    let ctx = Context::new("bench");
    c.bench_function("200 ogden-6 refits + ICM bands for 4 samples", |b| {
        b.iter(|| {
            let fitted = MaterialFit.run(&fit, black_box(&tensile), &ctx).unwrap();
            for profile in &profiles {
                let inputs = Inputs::new()
                    .with("profile", Product::Table(profile.clone()))
                    .with("material", Product::Table(table(&fitted, "material")))
                    .with("replicates", Product::Table(table(&fitted, "replicates")));
                black_box(Icm.run(&icm, &inputs, &ctx).unwrap());
            }
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bootstrap_to_bands
}
criterion_main!(benches);
