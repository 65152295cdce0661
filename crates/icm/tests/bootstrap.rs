//! Bootstrap bands, end to end through the stages: synthetic tensile data
//! from a known material with known noise → `material-fit` with a
//! bootstrap → `icm` with the replicates → `bands`, checked against the
//! generating material's own curve.

use std::sync::Arc;

use crate::common;
use hypercontact_core::{Context, Inputs, Params, Product, Schema, Stage, Table};
use hypercontact_icm::stage::{Icm, IcmParams};

use hypercontact_icm::{Model, Scheme};
use hypercontact_material::fit_stage::{BootstrapParams, MaterialFit, MaterialFitParams};
use hypercontact_material::sample::synthetic_tensile;
use hypercontact_material::{Family, Ogden};
use hypercontact_synth::surface::SelfAffine;
use hypercontact_truncation::stage::profile_table;
use hypercontact_truncation::{Levels, Profile, TruncationOptions, truncate};

/// A stable two-term Ogden (μ_i ≥ 0): the family the fit uses can
/// represent it, so the bands are about noise, not misfit.
fn truth() -> Ogden {
    Ogden::new(vec![0.35e6, 0.02e6], vec![1.6, 5.0]).unwrap()
}

fn profile() -> Profile {
    let h = SelfAffine::whole_band(128, 2e-5).periodic(128, 128, 2e-5, 7);
    let options = TruncationOptions {
        levels: Levels::Count(200),
        ..Default::default()
    };
    truncate(h.view(), 2e-5, 2e-5, &options, &mut |_| {}).unwrap()
}

/// The row nearest A/A0 = 0.5.
fn mid_row(p: &Profile) -> usize {
    (0..p.area_fraction.len())
        .min_by(|&a, &b| {
            (p.area_fraction[a] - 0.5)
                .abs()
                .total_cmp(&(p.area_fraction[b] - 0.5).abs())
        })
        .unwrap()
}

/// The generating material's load and tangent modulus at every plane, Pa
/// and N, with its E0*.
fn truth_curve(p: &Profile) -> (Vec<f64>, Vec<f64>, f64) {
    let (s, e0_star) =
        common::solve_profile(p, Arc::new(truth()), Model::Hyperelastic, Scheme::Heun);
    (s.load_n, s.modulus_pa, e0_star)
}

struct Run {
    /// The fitted material's E0*.
    e0_star_pa: f64,
    bands: Table,
}

fn run(p: &Profile, noise: f64, seed: u64, count: usize) -> Run {
    let data = synthetic_tensile(&truth(), 50, noise, seed);
    let fit = MaterialFitParams {
        model: Family::Ogden(2),
        compare: false,
        starts: 8,
        bootstrap: BootstrapParams {
            count,
            seed,
            starts: 1,
        },
        ..Default::default()
    }
    .check()
    .unwrap();
    let ctx = Context::new("t");
    let fitted = MaterialFit
        .run(
            &fit,
            &Inputs::new().with("tensile", Product::Table(data.to_table())),
            &ctx,
        )
        .unwrap();
    let table = |name: &str| match fitted.get(name) {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no {name}"),
    };
    let material = table("material");
    let e0_star_pa = {
        let m = hypercontact_material::table::from_table(&material).unwrap();
        hypercontact_material::composite_modulus_pa(m.shear_modulus_pa(), 0.5)
    };
    let inputs = Inputs::new()
        .with("profile", Product::Table(profile_table(p).into_table()))
        .with("material", Product::Table(material))
        .with("replicates", Product::Table(table("replicates")));
    let out = Icm
        .run(&IcmParams::default().check().unwrap(), &inputs, &ctx)
        .unwrap();
    let Some(Product::Table(bands)) = out.get("bands") else {
        panic!("no bands");
    };
    Run {
        e0_star_pa,
        bands: bands.clone(),
    }
}

#[test]
fn bands_cover_the_generating_curve_at_about_the_nominal_rate() {
    let p = profile();
    let row = mid_row(&p);
    let a0_m2 = p.area_m2[row] / p.area_fraction[row];
    let (load_n, tangent_pa, e0_star_true) = truth_curve(&p);
    let seeds = 60;
    let (mut load_in, mut tangent_in) = (0, 0);
    for seed in 1..=seeds {
        let r = run(&p, 0.01, seed, 100);
        let col = |name: &str| r.bands.f64(name).unwrap()[row];
        // The bands' loads are over the fitted E0* A0: the true load on
        // the same axes.
        let truth_load = load_n[row] / (r.e0_star_pa * a0_m2);
        if (col("load_norm_p05")..=col("load_norm_p95")).contains(&truth_load) {
            load_in += 1;
        }
        let truth_tangent = tangent_pa[row] / e0_star_true;
        if (col("tangent_ratio_p05")..=col("tangent_ratio_p95")).contains(&truth_tangent) {
            tangent_in += 1;
        }
        assert_eq!(r.bands.i64("replicates").unwrap()[row], 100);
    }
    // Nominal 90 %; 60 seeds give a binomial spread of ±4 %.
    let rate = |n: i32| f64::from(n) / seeds as f64;
    eprintln!(
        "coverage at A/A0 = {:.3}: load {:.3}, tangent ratio {:.3}",
        p.area_fraction[row],
        rate(load_in),
        rate(tangent_in)
    );
    for (what, n) in [("load", load_in), ("tangent ratio", tangent_in)] {
        assert!(
            (0.75..=0.99).contains(&rate(n)),
            "{what}: {n} of {seeds} bands hold the truth"
        );
    }
}

#[test]
fn bands_shrink_with_the_tensile_noise() {
    let p = profile();
    let row = mid_row(&p);
    let width = |noise: f64| {
        let r = run(&p, noise, 3, 100);
        let col = |name: &str| r.bands.f64(name).unwrap()[row];
        (
            col("load_norm_p95") - col("load_norm_p05"),
            col("tangent_ratio_p95") - col("tangent_ratio_p05"),
        )
    };
    let (wide, narrow) = (width(0.02), width(0.005));
    // Standard errors scale with the noise: a quarter of the noise, about
    // a quarter of the width.
    assert!(narrow.0 < 0.4 * wide.0, "{narrow:?} vs {wide:?}");
    assert!(narrow.1 < 0.4 * wide.1, "{narrow:?} vs {wide:?}");
    assert!(narrow.0 > 0.0 && narrow.1 > 0.0);
}
