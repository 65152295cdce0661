//! The `bem` stage on a material given by its constants (stage `material`)
//! and under both tangents: a linear material is E* = E/(1 − ν²) whatever
//! the law says; the uniaxial tangent meets the linear curve at zero load,
//! the paper's equibiaxial one starts at twice it.

use hypercontact_bem::stage::Bem;
use hypercontact_core::{Context, DynStage, Field, Inputs, Product, Table};
use hypercontact_material::constants_stage::MaterialConstants;
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_material::{Hyperelastic, composite_modulus_pa};
use serde_json::json;

/// A small non-periodic self-affine map, heights of `rms_m`.
fn map(rms_m: f64) -> Field {
    let values = hypercontact_synth::surface::SelfAffine {
        hurst: 0.8,
        rms_m,
        lambda_min_m: 4e-5,
        lambda_max_m: 1e-3,
    }
    .non_periodic(32, 32, 2e-5, 7);
    Field::new(values, 2e-5, 2e-5).unwrap()
}

fn bem(law: serde_json::Value, surface: &Field, material: &Table) -> (Table, Vec<String>) {
    let mut params = json!({"steps": 4, "max_area_fraction": 0.2, "map_fractions": [0.2]});
    let extra = law.as_object().unwrap().clone();
    params.as_object_mut().unwrap().extend(extra);
    let p = Bem
        .params_from_json(params, std::path::Path::new("."))
        .unwrap();
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface.clone()))
        .with("material", Product::Table(material.clone()));
    let ctx = Context::new("bem");
    let out = Bem.run_dyn(p.as_ref(), &inputs, &ctx).unwrap();
    match out.get("response") {
        Some(Product::Table(t)) => (t.clone(), ctx.notes()),
        _ => panic!("no response"),
    }
}

fn material(params: serde_json::Value) -> Table {
    let p = (MaterialConstants)
        .params_from_json(params, std::path::Path::new("."))
        .unwrap();
    let out = (MaterialConstants)
        .run_dyn(p.as_ref(), &Inputs::new(), &Context::new("m"))
        .unwrap();
    match out.get("material") {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no material"),
    }
}

#[test]
fn a_linear_material_gives_the_linear_curve_with_its_own_composite_modulus() {
    let (e_pa, nu) = (2e6, 0.49);
    let e0_star = e_pa / (1.0 - nu * nu);
    let surface = map(1e-5);
    let linear = material(json!({"family": "linear", "e_pa": e_pa, "poisson": nu}));
    let (reference, notes) = bem(json!({"model": "linear", "poisson": nu}), &surface, &linear);
    assert!(
        notes.iter().all(|n| !n.contains("linear elastic")),
        "{notes:?}"
    );
    let loads = reference.f64("load_n").unwrap();
    // The linear contact scales with E*: the paper's EPDM, linear, times the
    // ratio of the composite moduli.
    let epdm_e0_star = composite_modulus_pa(paper_epdm().shear_modulus_pa(), 0.5);
    let (epdm, _) = bem(
        json!({"model": "linear"}),
        &surface,
        &to_table(&paper_epdm()),
    );
    for (load, other) in loads.iter().zip(epdm.f64("load_n").unwrap()) {
        let expected = other * e0_star / epdm_e0_star;
        assert!(
            (load - expected).abs() <= 1e-12 * expected,
            "{load} vs {expected}"
        );
    }
    for law in [
        json!({"model": "hyperelastic"}),
        json!({"model": "hyperelastic", "tangent": "uniaxial", "poisson": 0.3}),
    ] {
        let (response, notes) = bem(law.clone(), &surface, &linear);
        assert_eq!(response.f64("load_n").unwrap(), loads, "{law}");
        assert_eq!(
            response.f64("load_norm").unwrap(),
            reference.f64("load_norm").unwrap()
        );
        assert!(
            response
                .f64("tangent_ratio")
                .unwrap()
                .iter()
                .all(|&r| r == 1.0)
        );
        let noted = notes
            .iter()
            .filter(|n| n.contains("linear elastic"))
            .count();
        assert_eq!(noted, 1, "{law}: {notes:?}");
    }
}

#[test]
fn the_uniaxial_tangent_meets_the_linear_curve_at_zero_load_the_equibiaxial_twice_it() {
    // Slopes of about 1e-4: the mean contact stress, about E* h'rms / κ,
    // stays near 1e-4 E0*, so the loads show the zero-load tangent.
    let surface = map(1e-9);
    let epdm = to_table(&paper_epdm());
    let (linear, _) = bem(json!({"model": "linear"}), &surface, &epdm);
    let (uniaxial, _) = bem(json!({"tangent": "uniaxial"}), &surface, &epdm);
    let (equibiaxial, _) = bem(json!({}), &surface, &epdm);
    let loads = |t: &Table| t.f64("load_n").unwrap().to_vec();
    let (linear, uniaxial, equibiaxial) = (loads(&linear), loads(&uniaxial), loads(&equibiaxial));
    assert_eq!(linear[0], 0.0, "first contact");
    for k in 1..linear.len() {
        let (u, e) = (uniaxial[k] / linear[k], equibiaxial[k] / linear[k]);
        assert!((u - 1.0).abs() < 1e-3, "step {k}: uniaxial/linear = {u}");
        assert!(
            (e / 2.0 - 1.0).abs() < 1e-3,
            "step {k}: equibiaxial/linear = {e}"
        );
    }
}
