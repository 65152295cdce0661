//! `persson` and `greenwood-williamson` on a material given by its
//! constants (stage `material`): a linear material gives the linear curve
//! with E0* = E/(1 − ν²) of its own ν, whatever `model`, `tangent` and
//! `poisson` say; and both tangents at small stress.

use hypercontact_classical::stage::{GreenwoodWilliamson, PerssonStage};
use hypercontact_core::{Context, DynStage, Field, Inputs, Product, Table};
use hypercontact_material::constants_stage::MaterialConstants;
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_material::{Hyperelastic, composite_modulus_pa};
use hypercontact_synth::surface::self_affine::SelfAffine;
use serde_json::json;

const N: usize = 64;
const PIXEL_M: f64 = 20e-6;

fn inputs(material: Table) -> Inputs {
    inputs_of(material, 10e-6)
}

/// A periodic self-affine map with heights of `rms_m`, and `material`.
fn inputs_of(material: Table, rms_m: f64) -> Inputs {
    let surface = SelfAffine {
        hurst: 0.8,
        rms_m,
        lambda_min_m: 4.0 * PIXEL_M,
        lambda_max_m: 0.5 * N as f64 * PIXEL_M,
    };
    let map = Field::new(surface.periodic(N, N, PIXEL_M, 3), PIXEL_M, PIXEL_M).unwrap();
    Inputs::new()
        .with("surface", Product::Field(map))
        .with("material", Product::Table(material))
}

/// A stage's `response` and `summary` tables and its notes.
fn run(
    stage: &dyn DynStage,
    params: serde_json::Value,
    inputs: &Inputs,
) -> (Table, Table, Vec<String>) {
    let p = stage
        .params_from_json(params, std::path::Path::new("."))
        .unwrap();
    let ctx = Context::new("t");
    let out = stage.run_dyn(p.as_ref(), inputs, &ctx).unwrap();
    let table = |name| match out.get(name) {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no {name}"),
    };
    (table("response"), table("summary"), ctx.notes())
}

fn linear_material(e_pa: f64, poisson: f64) -> Table {
    let p = MaterialConstants
        .params_from_json(
            json!({"family": "linear", "e_pa": e_pa, "poisson": poisson}),
            std::path::Path::new("."),
        )
        .unwrap();
    let out = MaterialConstants
        .run_dyn(p.as_ref(), &Inputs::new(), &Context::new("m"))
        .unwrap();
    match out.get("material") {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no material"),
    }
}

#[test]
fn a_linear_material_gives_linear_persson_and_gw_curves_with_its_own_e0_star() {
    let (e_pa, nu) = (2e6, 0.49);
    let e0_star = e_pa / (1.0 - nu * nu);
    let linear = inputs(linear_material(e_pa, nu));
    let epdm = inputs(to_table(&paper_epdm()));
    let epdm_e0_star = composite_modulus_pa(paper_epdm().shear_modulus_pa(), 0.5);
    let stages: [(&str, &dyn DynStage); 2] = [
        ("persson", &PerssonStage),
        ("greenwood-williamson", &GreenwoodWilliamson),
    ];
    for (name, stage) in stages {
        let base = json!({"periodic": true, "steps": 12});
        let with = |extra: serde_json::Value| {
            let mut p = base.clone();
            p.as_object_mut()
                .unwrap()
                .extend(extra.as_object().unwrap().clone());
            p
        };
        let (reference, summary, notes) = run(
            stage,
            with(json!({"model": "linear", "poisson": nu})),
            &linear,
        );
        assert!(
            notes.iter().all(|n| !n.contains("linear elastic")),
            "{name}: {notes:?}"
        );
        assert_eq!(summary.f64("e0_star_pa").unwrap(), [e0_star], "{name}");
        // The same theory on the paper's EPDM, linear: loads scale with E0*.
        let (scaled, _, _) = run(stage, with(json!({"model": "linear"})), &epdm);
        let loads = reference.f64("load_n").unwrap();
        for (load, other) in loads.iter().zip(scaled.f64("load_n").unwrap()) {
            let expected = other * e0_star / epdm_e0_star;
            assert!(
                (load / expected - 1.0).abs() < 1e-12,
                "{name}: {load} vs {expected}"
            );
        }
        for law in [
            json!({"model": "hyperelastic"}),
            json!({"model": "hyperelastic", "tangent": "uniaxial", "poisson": 0.2}),
        ] {
            let (response, summary, notes) = run(stage, with(law.clone()), &linear);
            assert_eq!(response.f64("load_n").unwrap(), loads, "{name} {law}");
            assert!(
                response
                    .f64("tangent_ratio")
                    .unwrap()
                    .iter()
                    .all(|&r| r == 1.0)
            );
            assert_eq!(summary.f64("e0_star_pa").unwrap(), [e0_star], "{name}");
            let noted = notes
                .iter()
                .filter(|n| n.contains("linear elastic"))
                .count();
            assert_eq!(noted, 1, "{name} {law}: {notes:?}");
        }
    }
}

#[test]
fn at_small_stress_the_uniaxial_tangent_gives_the_linear_load_the_equibiaxial_twice_it() {
    // Slopes of about 1e-4: the theories' mean contact stress, about
    // E* h'rms / κ, stays near 1e-4 E0* over the rows.
    let gentle = inputs_of(to_table(&paper_epdm()), 1e-9);
    let stages: [(&str, &dyn DynStage); 2] = [
        ("persson", &PerssonStage),
        ("greenwood-williamson", &GreenwoodWilliamson),
    ];
    for (name, stage) in stages {
        let law = |extra: serde_json::Value| {
            let mut p = json!({"periodic": true, "steps": 8, "max_area_fraction": 0.3});
            p.as_object_mut()
                .unwrap()
                .extend(extra.as_object().unwrap().clone());
            run(stage, p, &gentle).0
        };
        let linear = law(json!({"model": "linear"}));
        let uniaxial = law(json!({"tangent": "uniaxial"}));
        let equibiaxial = law(json!({"tangent": "equibiaxial"}));
        let loads = |t: &Table| t.f64("load_n").unwrap().to_vec();
        let (linear, uniaxial, equibiaxial) =
            (loads(&linear), loads(&uniaxial), loads(&equibiaxial));
        for k in 0..linear.len() {
            let (u, e) = (uniaxial[k] / linear[k], equibiaxial[k] / linear[k]);
            assert!(
                (u - 1.0).abs() < 1e-3,
                "{name} row {k}: uniaxial/linear = {u}"
            );
            assert!(
                (e / 2.0 - 1.0).abs() < 1e-3,
                "{name} row {k}: equibiaxial/linear = {e}"
            );
        }
    }
}
