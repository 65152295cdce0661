//! Fit speed at the sizes issue 3 names: a 6-term Ogden fit to the
//! 150-point sample with the default 8 starts (target < 1 s), and the whole
//! `material-fit` stage with the model comparison over every family
//! (target < 5 s).
//!
//! cargo bench -p hypercontact-material --bench fit

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hypercontact_core::{Context, Inputs, Params, Product, Stage};
use hypercontact_material::fit_stage::{MaterialFit, MaterialFitParams};
use hypercontact_material::sample::paper_sample;
use hypercontact_material::{Family, FitOptions, fit};

fn ogden_6(c: &mut Criterion) {
    let data = paper_sample();
    let options = FitOptions::default();
    c.bench_function("ogden-6 fit, 150 points, 8 starts", |b| {
        b.iter(|| fit(black_box(&data), Family::Ogden(6), &options).unwrap())
    });
}

fn comparison(c: &mut Criterion) {
    let inputs = Inputs::new().with("tensile", Product::Table(paper_sample().to_table()));
    let params = MaterialFitParams::default().check().unwrap();
    let ctx = Context::new("bench");
    c.bench_function("material-fit stage with comparison (10 families)", |b| {
        b.iter(|| MaterialFit.run(&params, black_box(&inputs), &ctx).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = ogden_6, comparison
}
criterion_main!(benches);
