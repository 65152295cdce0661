//! The `icm` stage on materials given by their constants (stage `material`)
//! and under both tangents: a linear material is E* = E/(1 − ν²) whatever
//! the law says; the uniaxial tangent meets the linear curve at zero load,
//! the paper's equibiaxial one starts at twice it.

use std::f64::consts::PI;

use hypercontact_core::{Context, Inputs, Params, Product, Stage, Table};
use hypercontact_icm::stage::{Icm, IcmParams};
use hypercontact_material::constants_stage::{MaterialConstants, MaterialParams};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use serde_json::json;

/// Punch radius, m.
const A_M: f64 = 1e-4;

/// A flat punch of radius A_M in a 1 mm² map, indented by `depths_m`
/// (first 0): F = 2 E* a d exactly for a constant modulus (Sneddon).
fn punch(depths_m: &[f64]) -> Table {
    let area = PI * A_M * A_M;
    let n = depths_m.len();
    Table::new()
        .with("z_m", depths_m.iter().map(|d| 1e-5 - d).collect::<Vec<_>>())
        .with(
            "z_over_sigma",
            depths_m.iter().map(|d| 1.0 - d).collect::<Vec<_>>(),
        )
        .with("area_fraction", vec![area / 1e-6; n])
        .with("patches", vec![1_i64; n])
        .with("radius_m", vec![A_M; n])
        .with("area_m2", vec![area; n])
}

/// The `material` stage's table for these parameters.
fn material(params: serde_json::Value) -> Table {
    let p: MaterialParams = serde_json::from_value(params).unwrap();
    let out = MaterialConstants
        .run(
            &p.check().unwrap(),
            &Inputs::new(),
            &Context::new("material"),
        )
        .unwrap();
    match out.get("material") {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no material table"),
    }
}

/// The response's columns `load_n` and `tangent_ratio`, and the notes.
fn icm(law: serde_json::Value, material: &Table, profile: &Table) -> (Table, Vec<String>) {
    let p: IcmParams = serde_json::from_value(law).unwrap();
    let inputs = Inputs::new()
        .with("profile", Product::Table(profile.clone()))
        .with("material", Product::Table(material.clone()));
    let ctx = Context::new("icm");
    let out = Icm.run(&p.check().unwrap(), &inputs, &ctx).unwrap();
    match out.get("response") {
        Some(Product::Table(t)) => (t.clone(), ctx.notes()),
        _ => panic!("no response"),
    }
}

#[test]
fn a_linear_material_gives_the_linear_curve_with_its_own_composite_modulus() {
    let (e_pa, nu) = (2e6, 0.49);
    let e0_star = e_pa / (1.0 - nu * nu);
    let linear = material(json!({"family": "linear", "e_pa": e_pa, "poisson": nu}));
    let profile = punch(&[0.0, 5e-6, 1e-5]);
    let (reference, notes) = icm(json!({"model": "linear", "poisson": nu}), &linear, &profile);
    assert!(notes.is_empty(), "{notes:?}");
    let loads = reference.f64("load_n").unwrap();
    for (d, load) in [0.0, 5e-6, 1e-5].iter().zip(loads) {
        let sneddon = 2.0 * e0_star * A_M * d;
        assert!(
            (load - sneddon).abs() <= 1e-12 * sneddon,
            "{load} vs {sneddon}"
        );
    }
    // The hyperelastic model, either tangent, any ν: the same loads, noted.
    for law in [
        json!({"model": "hyperelastic"}),
        json!({"model": "hyperelastic", "tangent": "uniaxial", "poisson": 0.3}),
        json!({"model": "linear", "scheme": "heun"}),
    ] {
        let (response, notes) = icm(law.clone(), &linear, &profile);
        assert_eq!(response.f64("load_n").unwrap(), loads, "{law}");
        assert_eq!(response.f64("tangent_ratio").unwrap(), [1.0; 3], "{law}");
        assert_eq!(
            response.f64("load_norm").unwrap(),
            reference.f64("load_norm").unwrap()
        );
        assert_eq!(notes.len(), 1, "{law}: {notes:?}");
        assert!(
            notes[0].contains("linear elastic") && notes[0].contains("not used"),
            "{notes:?}"
        );
    }
}

#[test]
fn the_uniaxial_tangent_meets_the_linear_curve_at_zero_load_the_equibiaxial_twice_it() {
    // Depths of nanometres: the mean stress stays below 1e-4 E0*.
    let depths: Vec<f64> = (0..6).map(|k| k as f64 * 1e-9).collect();
    let profile = punch(&depths);
    let materials = [
        to_table(&paper_epdm()),
        material(json!({"family": "neo-hookean", "mu_pa": 6e5})),
    ];
    for m in &materials {
        let (linear, _) = icm(json!({"model": "linear"}), m, &profile);
        let (uniaxial, _) = icm(json!({"tangent": "uniaxial"}), m, &profile);
        let (equibiaxial, _) = icm(json!({}), m, &profile);
        let explicit = icm(json!({"tangent": "equibiaxial"}), m, &profile).0;
        assert_eq!(explicit, equibiaxial, "the default is the paper's tangent");
        let ratio =
            |t: &Table, k: usize| t.f64("load_n").unwrap()[k] / linear.f64("load_n").unwrap()[k];
        for k in 1..depths.len() {
            assert!(
                (ratio(&uniaxial, k) - 1.0).abs() < 1e-3,
                "step {k}: {}",
                ratio(&uniaxial, k)
            );
            assert!(
                (ratio(&equibiaxial, k) - 2.0).abs() < 2e-3,
                "step {k}: {}",
                ratio(&equibiaxial, k)
            );
        }
        let first = |t: &Table| t.f64("tangent_ratio").unwrap()[0];
        assert!(
            (first(&uniaxial) - 1.0).abs() < 1e-9,
            "{}",
            first(&uniaxial)
        );
        assert!(
            (first(&equibiaxial) - 2.0).abs() < 1e-9,
            "{}",
            first(&equibiaxial)
        );
    }
}

#[test]
fn a_stress_beyond_the_uniaxial_range_names_the_plane_and_the_curve() {
    // A tiny area under a stiff punch: S far beyond either curve's range.
    let profile = Table::new()
        .with("z_m", vec![1e-5, 0.0])
        .with("z_over_sigma", vec![1.0, 0.0])
        .with("area_fraction", vec![1.0, 1.0])
        .with("patches", vec![1_i64, 1])
        .with("radius_m", vec![1.0, 1.0])
        .with("area_m2", vec![1e-12, 1e-12]);
    let inputs = Inputs::new()
        .with("profile", Product::Table(profile))
        .with("material", Product::Table(to_table(&paper_epdm())));
    for (tangent, label) in [
        ("uniaxial", "the UT nominal stress"),
        ("equibiaxial", "the BT nominal stress"),
    ] {
        let p: IcmParams = serde_json::from_value(json!({"tangent": tangent})).unwrap();
        let e = Icm
            .run(&p.check().unwrap(), &inputs, &Context::new("icm"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("level 1") && e.contains(label), "{tangent}: {e}");
    }
}
