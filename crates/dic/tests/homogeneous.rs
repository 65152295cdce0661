//! Homogeneous stretch sequences through the real stages,
//! `synth-tensile → dic → material-fit`: the recovered stretch must follow
//! the truth within 2e-4 at every frame (UT to 2.5, PT to 2.0, BT to 1.5),
//! λ₂ must follow incompressibility in UT, the nominal stress must match the
//! generating material, and the Ogden fit of the DIC data must reproduce the
//! generating curves within 1 % RMS relative error per mode.

use crate::common;

use std::time::Instant;

use hypercontact_core::{Context, Inputs, Params, Product, Stage, Table};
use hypercontact_dic::{DicParams, Method};
use hypercontact_material::fit_stage::{MaterialFit, MaterialFitParams};
use hypercontact_material::{Mode, presets};
use hypercontact_synth::tensile::SynthTensileParams;

/// synth → dic for one mode, checked frame by frame against the truth.
fn recovered(mode: &str) -> Table {
    let start = Instant::now();
    let (files, truth) = common::synth(&SynthTensileParams {
        mode: Mode::from_label(mode).unwrap(),
        seed: 11,
        ..Default::default()
    });
    let synth_s = start.elapsed().as_secs_f64();
    let table = common::dic(&files, &DicParams::default()).unwrap();
    let stretch = table.f64("stretch").unwrap();
    let stretch_2 = table.f64("stretch_2").unwrap();
    let true_stretch = truth.f64("stretch").unwrap();
    let true_stretch_2 = truth.f64("stretch_2").unwrap();
    let valid = table.f64("valid_fraction").unwrap();
    let mut worst: f64 = 0.0;
    for k in 0..stretch.len() {
        let e1 = (stretch[k] - true_stretch[k]).abs();
        let e2 = (stretch_2[k] - true_stretch_2[k]).abs();
        worst = worst.max(e1).max(e2);
        assert!(
            e1 < 2e-4,
            "{mode} frame {k}: stretch {} vs {}",
            stretch[k],
            true_stretch[k]
        );
        assert!(
            e2 < 2e-4,
            "{mode} frame {k}: stretch_2 {} vs {}",
            stretch_2[k],
            true_stretch_2[k]
        );
        assert!(
            valid[k] > 0.95,
            "{mode} frame {k}: valid fraction {}",
            valid[k]
        );
    }
    eprintln!(
        "{mode}: worst stretch error {worst:.2e} over {} frames (synth {synth_s:.1} s, dic {:.1} s)",
        stretch.len(),
        start.elapsed().as_secs_f64() - synth_s
    );

    // Nominal stress against the generating curve at the measured stretch:
    // force resolution and noise dominate near λ = 1, so relative to the
    // largest stress.
    let material = presets::preset("paper-epdm").unwrap();
    let m = Mode::from_label(mode).unwrap();
    let stress = table.f64("nominal_stress_pa").unwrap();
    let scale = stress.iter().fold(0.0_f64, |a, s| a.max(s.abs()));
    for k in 0..stress.len() {
        let expected = material.nominal_stress_pa(m, stretch[k]);
        assert!(
            (stress[k] - expected).abs() < 2e-3 * scale,
            "{mode} frame {k}: stress {} vs {expected}",
            stress[k]
        );
    }
    table
}

#[test]
fn synth_dic_and_fit_recover_the_generating_material() {
    let (ut, (pt, bt)) = rayon::join(
        || recovered("UT"),
        || rayon::join(|| recovered("PT"), || recovered("BT")),
    );
    let stretch = ut.f64("stretch").unwrap();
    let stretch_2 = ut.f64("stretch_2").unwrap();
    assert!((stretch.last().unwrap() - 2.5).abs() < 2e-4);
    for (l, l2) in stretch.iter().zip(stretch_2) {
        assert!((l2 - l.powf(-0.5)).abs() < 2e-4, "UT: λ = {l}, λ2 = {l2}");
    }

    let mut all = ut.clone();
    all.append(&pt).unwrap();
    all.append(&bt).unwrap();
    // The paper's plain least squares: the data are made from its Table 1,
    // whose cancelling μ_i no stable (μ_i ≥ 0) Ogden follows.
    let params = MaterialFitParams {
        compare: false,
        constraint: hypercontact_material::Constraint::Free,
        ..Default::default()
    }
    .check()
    .unwrap();
    let start = Instant::now();
    let out = MaterialFit
        .run(
            &params,
            &Inputs::new().with("tensile", Product::Table(all)),
            &Context::new("fit"),
        )
        .unwrap();
    let Some(Product::Table(quality)) = out.get("quality") else {
        panic!("no quality table")
    };
    eprintln!("fit {:.1} s", start.elapsed().as_secs_f64());
    let modes = quality.str("mode").unwrap();
    let rms = quality.f64("rms_rel_err").unwrap();
    for (mode, rms) in modes.iter().zip(rms) {
        eprintln!("{mode}: RMS relative error {:.3} %", 100.0 * rms);
        assert!(*rms < 0.01, "{mode}: RMS relative error {rms}");
    }
}

#[test]
fn markers_and_subsets_agree() {
    let (files, _) = common::synth(&SynthTensileParams {
        mode: Mode::Uniaxial,
        max_stretch: Some(2.0),
        frames: 12,
        seed: 5,
        ..Default::default()
    });
    let subset = common::dic(&files, &DicParams::default()).unwrap();
    let markers = common::dic(
        &files,
        &DicParams {
            method: Method::Markers,
            ..Default::default()
        },
    )
    .unwrap();
    let (a, b) = (
        subset.f64("stretch").unwrap(),
        markers.f64("stretch").unwrap(),
    );
    for k in 0..a.len() {
        assert!(
            (a[k] - b[k]).abs() < 1e-3,
            "frame {k}: subset {} markers {}",
            a[k],
            b[k]
        );
    }
    assert_eq!(markers.f64("valid_fraction").unwrap().last(), Some(&1.0));
}
