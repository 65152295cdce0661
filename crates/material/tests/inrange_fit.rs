//! The `in-range` constraint end to end: the paper's Table 1 recovered
//! from its synthetic tests, Treloar's data against an independent bounded
//! search, bad windows refused, and every fitted model checked by the
//! stability module alone (independently of the constraint code).

use std::time::Instant;

use hypercontact_material::bootstrap::{Bootstrap, replicates};
use hypercontact_material::drucker_windows::DruckerWindows;
use hypercontact_material::quality::quality;
use hypercontact_material::sample::paper_sample;
use hypercontact_material::stability::stability_range;
use hypercontact_material::{Constraint, Family, FitOptions, Hyperelastic, Mode, TensileData, fit};

fn in_range() -> FitOptions {
    FitOptions {
        constraint: Constraint::InRange,
        ..FitOptions::default()
    }
}

fn treloar() -> TensileData {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/reference/treloar_1944.csv");
    let table = hypercontact_labfiles::csv_table::read_csv(&path).unwrap();
    TensileData::from_table(&table, "treloar_1944.csv").unwrap()
}

/// The model is Drucker-stable on every window, by the stability module's
/// own scan.
fn assert_stable_on(model: &dyn Hyperelastic, windows: &DruckerWindows) {
    for mode in Mode::ALL {
        let Some((lo, hi)) = windows.get(mode) else {
            continue;
        };
        let r = stability_range(model, mode);
        assert!(
            r.stable_at_rest && r.lambda_min <= lo && r.lambda_max >= hi,
            "{mode} window {lo}–{hi}: {r:?}"
        );
    }
}

#[test]
fn six_term_ogden_in_range_recovers_the_papers_table_1_from_its_sample() {
    let data = paper_sample();
    let started = Instant::now();
    let r = fit(&data, Family::Ogden(6), &in_range()).unwrap();
    // Measured: 2.5 s in release on one core of the build machine.
    eprintln!("paper sample, ogden-6 in-range: {:?}", started.elapsed());
    let mu0 = r.model.shear_modulus_pa();
    assert!((mu0 / 1.79e6 - 1.0).abs() < 0.01, "μ0 = {mu0}");
    let qualities = quality(r.model.as_ref(), &data);
    assert_eq!(qualities.len(), 4);
    for q in &qualities {
        assert!(q.rms_rel_err <= 0.01, "{q:?}");
    }
    let windows = r.windows.as_ref().unwrap();
    // The default windows: each mode's data from λ = 1, BT down to 0.6.
    assert_eq!(windows.get(Mode::Equibiaxial).unwrap().0, 0.6);
    assert_eq!(windows.get(Mode::Uniaxial).unwrap().0, 1.0);
    assert_stable_on(r.model.as_ref(), windows);
    // The paper's own Table 1 fails below λ ≈ 0.56 in BT: 0.6 binds
    // nothing it needs, so the fit keeps the noise-level error.
    assert!(qualities[3].rms_rel_err < 0.0055, "{:?}", qualities[3]);
}

#[test]
fn in_range_ogden_on_treloar_is_within_two_percent_of_an_independent_constrained_search() {
    // Reference: crates/material/tests/reference/treloar_inrange.py, scipy
    // 1.17.1 / numpy 2.4.6 SLSQP (ftol 1e-14, maxiter 2000) on the full
    // problem in (μ_i, α_i), the same relative residuals with the 1 %
    // floor and unit weights, under det H ≥ 0 and trace H ≥ 0 (expanded
    // Ogden form) at 120 geometric stretches per default window (UT 1–7.6,
    // PT 1–4.97, BT 0.6–4.45); 100 random starts (α ∈ U(−6, 8), μ by NNLS),
    // bounds |α_i| ≤ 30 and |μ_i| ≤ 1000 × the largest measured stress;
    // best ½ Σ r² kept (2026-11-26).
    // Each start is polished by SLSQP twice, from the draw and from scipy's
    // bounded trust-region least-squares (trf) optimum of the draw.
    // ogden-3: 0.143559100 (μ = 401028, 7951, 2717 Pa; α = 1.2523,
    // −2.1431, 5.1183: all μ_i ≥ 0, the `stable` optimum too). Ours: equal
    // to 1e-11.
    check_treloar(3, 0.143_559_100, 0.98 * 0.143_559_100);
    // ogden-4: 0.118897945 (μ = 386738, 5e-7, 3464, 20907 Pa: the μ_i ≥ 0
    // optimum, one term dead). Ours: equal to
    // 1e-10.
    check_treloar(4, 0.118_897_945, 0.98 * 0.118_897_945);
    // ogden-6: 0.109093914 (197 of 200 polished starts feasible; next best
    // 0.109137; μ = −222, 0.0118, 329, 140, 76, −323 MPa, α = 3.95, −1.96,
    // 3.71, 3.28, 4.09, 3.45). Ours is 0.25 % lower (0.108824), with
    // moduli of ±5e12 Pa that the bound (±6.3e9 Pa) keeps the reference
    // from: so ours is also held from below by the best unconstrained
    // objective known (0.1088148, fit.rs), which no stable model can beat,
    // and its stability on the windows is checked by the stability
    // module's own scan. (SLSQP from the draws alone stopped at
    // 0.111056.)
    check_treloar(6, 0.109_093_914, 0.108_814_8 * (1.0 - 1e-6));
}

/// The in-range Ogden fit with `terms` terms on Treloar's data: its
/// objective at most 2 % above `reference` and not below `floor`, and its
/// model stable on the windows.
fn check_treloar(terms: usize, reference: f64, floor: f64) {
    let r = fit(&treloar(), Family::Ogden(terms), &in_range()).unwrap();
    assert!(
        r.cost <= 1.02 * reference,
        "ogden-{terms}: {} vs scipy {reference}",
        r.cost
    );
    assert!(r.cost >= floor, "ogden-{terms}: {} below {floor}", r.cost);
    assert_stable_on(r.model.as_ref(), r.windows.as_ref().unwrap());
}

#[test]
fn bad_windows_are_refused_naming_the_model_and_the_window() {
    let options = FitOptions {
        windows: Some(
            DruckerWindows::from_data(&paper_sample(), [1.0; 3], 0.6)
                .with(Mode::Planar, (0.05, 2.0)),
        ),
        ..in_range()
    };
    let e = fit(&paper_sample(), Family::Ogden(2), &options)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`ogden-2`") && e.contains("PT window [0.05, 2]"),
        "{e}"
    );
}

#[test]
fn a_fit_that_finds_no_stable_optimum_names_the_model_and_the_windows() {
    // Out of budget from every start: the error says where stability was
    // imposed.
    let options = FitOptions {
        patience: 1,
        ..in_range()
    };
    let e = fit(&paper_sample(), Family::Ogden(4), &options)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`ogden-4`") && e.contains("Drucker stability imposed on UT 1.0000–2.5000"),
        "{e}"
    );
}

#[test]
fn every_family_fits_in_range_and_is_stable_on_the_windows() {
    let data = paper_sample();
    for family in Family::all() {
        let r = fit(&data, family, &in_range()).unwrap();
        let free = fit(
            &data,
            family,
            &FitOptions {
                constraint: Constraint::Free,
                ..FitOptions::default()
            },
        )
        .unwrap();
        let stable = fit(&data, family, &FitOptions::default()).unwrap();
        assert_stable_on(r.model.as_ref(), r.windows.as_ref().unwrap());
        // Between the free optimum and the μ ≥ 0 one (μ ≥ 0 is stable on
        // any window). Separate non-convex searches: the free search may
        // stop a little above the best free optimum (ogden-5: 1.5e-4
        // relative above the in-range one), hence 1 % below.
        assert!(
            r.cost >= free.cost * 0.99 && r.cost <= stable.cost * (1.0 + 1e-6),
            "{}: {} not in [{}, {}]",
            family.name(),
            r.cost,
            free.cost,
            stable.cost
        );
    }
}

#[test]
fn in_range_bootstrap_is_the_same_on_one_and_two_threads() {
    let data = paper_sample();
    let best = fit(&data, Family::Ogden(3), &in_range()).unwrap();
    // Replicates are judged on the full data's windows.
    let options = FitOptions {
        windows: best.windows.clone(),
        ..in_range()
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let plan = Bootstrap {
                    count: 4,
                    seed: 3,
                    starts: 2,
                };
                replicates(&data, &best, &options, plan, &|| ())
                    .into_iter()
                    .map(|m| {
                        let m = m.unwrap();
                        assert_stable_on(m.as_ref(), best.windows.as_ref().unwrap());
                        m.parameters()
                            .iter()
                            .map(|p| p.value.to_bits())
                            .collect::<Vec<u64>>()
                    })
                    .collect::<Vec<_>>()
            })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_ne!(one[0], one[1]);
}

#[test]
#[ignore = "timing: cargo test --workspace --release --test integration -- inrange_fit:: --ignored --nocapture"]
fn time_a_200_replicate_in_range_bootstrap() {
    let data = paper_sample();
    let best = fit(&data, Family::Ogden(6), &in_range()).unwrap();
    let options = FitOptions {
        windows: best.windows.clone(),
        ..in_range()
    };
    let plan = Bootstrap {
        count: 200,
        seed: 1,
        starts: 4,
    };
    let started = Instant::now();
    let fitted = replicates(&data, &best, &options, plan, &|| ());
    eprintln!(
        "200 replicates, ogden-6 in-range, 4 + 1 starts each: {:?} on {} threads",
        started.elapsed(),
        rayon::current_num_threads()
    );
    assert!(fitted.iter().all(Result::is_ok));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// Whatever the data, an in-range fit never panics; it fails naming
    /// the model, or its model is stable on the windows.
    #[test]
    fn any_data_fits_in_range_or_fails_naming_the_model(
        points in proptest::collection::vec(
            (0usize..3, 0.05f64..12.0, -1e7f64..1e7),
            4..30,
        ),
        ogden in proptest::bool::ANY,
    ) {
        let mut data = TensileData::default();
        for (mode, stretch, stress_pa) in points {
            let mode = Mode::ALL[mode];
            let curve = hypercontact_material::tensile::TensileCurve {
                mode,
                stretch: vec![stretch],
                stress_pa: vec![stress_pa],
            };
            data.extend(TensileData { curves: vec![curve] });
        }
        let family = if ogden { Family::Ogden(2) } else { Family::MooneyRivlin };
        let options = FitOptions { starts: 2, ..in_range() };
        match fit(&data, family, &options) {
            Ok(r) => assert_stable_on(r.model.as_ref(), r.windows.as_ref().unwrap()),
            Err(e) => proptest::prop_assert!(e.to_string().contains(&family.name()), "{}", e),
        }
    }
}

#[test]
#[ignore = "timing: cargo test --workspace --release --test integration -- inrange_fit:: --ignored --nocapture"]
fn time_the_stage_with_its_comparison_on_the_paper_sample() {
    use hypercontact_core::{Checked, Context, Inputs, Params, Product, Stage};
    use hypercontact_material::fit_stage::{MaterialFit, MaterialFitParams};
    let inputs = Inputs::new().with("tensile", Product::Table(paper_sample().to_table()));
    let p: Checked<MaterialFitParams> = MaterialFitParams {
        constraint: Constraint::InRange,
        ..Default::default()
    }
    .check()
    .unwrap();
    let started = Instant::now();
    let out = MaterialFit.run(&p, &inputs, &Context::new("fit")).unwrap();
    eprintln!(
        "material-fit, ogden-6 in-range with the comparison (10 families × 3 constraints): {:?}",
        started.elapsed()
    );
    let Some(Product::Table(c)) = out.get("comparison") else {
        panic!("no comparison");
    };
    assert!(c.str("status").unwrap().iter().all(|s| s == "ok"));
    let (models, constraints) = (c.str("model").unwrap(), c.str("constraint").unwrap());
    let rms = c.f64("rms_rel_err").unwrap();
    for row in 0..models.len() {
        eprintln!(
            "{} {}: {:.4} %",
            models[row],
            constraints[row],
            100.0 * rms[row]
        );
    }
}

#[test]
fn a_window_where_the_free_optimum_is_unstable_binds_the_fit() {
    // The paper's Table 1 fails in BT below λ ≈ 0.56; its noise-free data
    // fitted without constraint give it back, unstable there too. Asked to
    // be stable down to 0.45, the fit must give up a little accuracy.
    let data = hypercontact_material::sample::synthetic_tensile(
        &hypercontact_material::presets::paper_epdm(),
        50,
        0.0,
        1,
    );
    let free = fit(
        &data,
        Family::Ogden(6),
        &FitOptions {
            constraint: Constraint::Free,
            ..FitOptions::default()
        },
    )
    .unwrap();
    let free_bt = stability_range(free.model.as_ref(), Mode::Equibiaxial);
    assert!(free_bt.lambda_min > 0.5, "{free_bt:?}");
    let windows = DruckerWindows::from_data(&data, [1.0; 3], 0.45);
    let options = FitOptions {
        windows: Some(windows.clone()),
        ..in_range()
    };
    let bound = fit(&data, Family::Ogden(6), &options).unwrap();
    assert_stable_on(bound.model.as_ref(), &windows);
    assert!(bound.cost > free.cost, "{} vs {}", bound.cost, free.cost);
    // ... a little: measured 0.15 % RMS.
    let bound_rms = quality(bound.model.as_ref(), &data)
        .pop()
        .unwrap()
        .rms_rel_err;
    assert!(bound_rms < 0.005, "{bound_rms}");
    // Down to 0.6 the paper's material is stable: nothing binds, and the
    // fit is the free one's quality.
    let default = fit(&data, Family::Ogden(6), &in_range()).unwrap();
    let rms = quality(default.model.as_ref(), &data)
        .pop()
        .unwrap()
        .rms_rel_err;
    assert!(rms < 1e-3, "{rms}");
}
