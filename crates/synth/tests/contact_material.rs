//! Stage `synth-contact` on a material given by its constants (stage
//! `material`): a linear material's force is E* = E/(1 − ν²) of its own ν
//! times the linear contact, whatever `model` and `poisson` say.

use hypercontact_core::{Context, DynStage, Field, Inputs, Product, Schema, Table};
use hypercontact_material::constants_stage::MaterialConstants;
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_material::{Hyperelastic, composite_modulus_pa};
use hypercontact_synth::contact::{ContactTruthTable, SynthContact};
use ndarray::Array2;
use serde_json::json;

/// A paraboloid cap (R = 20 mm) on a 0.6 mm square map of 10 µm.
fn cap() -> Field {
    let (n, d, radius) = (61, 1e-5, 2e-2);
    let h = Array2::from_shape_fn((n, n), |(i, j)| {
        let x = (i as f64 - 30.0) * d;
        let y = (j as f64 - 30.0) * d;
        -(x * x + y * y) / (2.0 * radius)
    });
    Field::new(h, d, d).unwrap()
}

/// The true force of every frame, and the notes.
fn forces(law: serde_json::Value, material: &Table) -> (Vec<f64>, Vec<String>) {
    let mut params = json!({"width_px": 48, "height_px": 40, "resolution_m": 1e-5,
        "magnification": 1.3, "max_area_fraction": 0.3, "shift_x_m": 0, "shift_y_m": 0,
        "frames": 5});
    params
        .as_object_mut()
        .unwrap()
        .extend(law.as_object().unwrap().clone());
    let p = SynthContact
        .params_from_json(params, std::path::Path::new("."))
        .unwrap();
    let inputs = Inputs::new()
        .with("surface", Product::Field(cap()))
        .with("material", Product::Table(material.clone()));
    let ctx = Context::new("synth-contact");
    let out = SynthContact.run_dyn(p.as_ref(), &inputs, &ctx).unwrap();
    let truth = ContactTruthTable::from_table(out.get_table("truth").unwrap()).unwrap();
    (truth.force_n, ctx.notes())
}

#[test]
fn a_linear_material_gives_the_linear_force_with_its_own_composite_modulus() {
    let (e_pa, nu) = (2e6, 0.49);
    let p = MaterialConstants
        .params_from_json(
            json!({"family": "linear", "e_pa": e_pa, "poisson": nu}),
            std::path::Path::new("."),
        )
        .unwrap();
    let out = MaterialConstants
        .run_dyn(p.as_ref(), &Inputs::new(), &Context::new("m"))
        .unwrap();
    let linear = out.get_table("material").unwrap().clone();
    let (reference, _) = forces(json!({"model": "linear", "poisson": nu}), &linear);
    let (hyperelastic, notes) = forces(json!({"model": "hyperelastic"}), &linear);
    assert_eq!(hyperelastic, reference);
    let (uniaxial, _) = forces(json!({"tangent": "uniaxial"}), &linear);
    assert_eq!(uniaxial, reference);
    assert_eq!(
        notes
            .iter()
            .filter(|n| n.contains("linear elastic"))
            .count(),
        1,
        "{notes:?}"
    );
    // The paper's EPDM, linear, scaled by the ratio of the composite moduli.
    let (epdm, _) = forces(json!({"model": "linear"}), &to_table(&paper_epdm()));
    let scale = e_pa / (1.0 - nu * nu) / composite_modulus_pa(paper_epdm().shear_modulus_pa(), 0.5);
    assert!(reference.iter().any(|&f| f > 0.0));
    for (f, g) in reference.iter().zip(&epdm) {
        assert!(
            (f - g * scale).abs() <= 1e-12 * f.abs().max(1e-300),
            "{f} vs {}",
            g * scale
        );
    }
}

#[test]
fn the_uniaxial_tangent_starts_at_the_linear_force_the_equibiaxial_at_twice_it() {
    // On a 20 mm cap the mean contact stress stays below 1 % of E0*.
    let epdm = to_table(&paper_epdm());
    let (linear, _) = forces(json!({"model": "linear"}), &epdm);
    let (uniaxial, _) = forces(json!({"tangent": "uniaxial"}), &epdm);
    let (equibiaxial, _) = forces(json!({}), &epdm);
    let first = linear.iter().position(|&f| f > 0.0).unwrap();
    let (u, e) = (
        uniaxial[first] / linear[first],
        equibiaxial[first] / linear[first],
    );
    assert!((u - 1.0).abs() < 1e-2, "uniaxial/linear = {u}");
    assert!((e / 2.0 - 1.0).abs() < 1e-2, "equibiaxial/linear = {e}");
    // Both stiffen as the load grows.
    let last = linear.len() - 1;
    assert!(uniaxial[last] / linear[last] > u && equibiaxial[last] / linear[last] > e);
}
