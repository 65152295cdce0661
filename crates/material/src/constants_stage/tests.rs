use super::*;
use hypercontact_core::{DynStage, Mode, Params, Product, Schema, Table};
use serde_json::json;

use crate::table::{from_table, material_from_table};
use crate::{ArrudaBoyce, Hyperelastic, MooneyRivlin, NeoHookean, Ogden, Yeoh};

fn run(params: serde_json::Value) -> Table {
    run_noted(params).0
}

fn run_noted(params: serde_json::Value) -> (Table, Vec<String>) {
    let p: MaterialParams = serde_json::from_value(params).unwrap();
    let ctx = Context::new("t");
    let out = MaterialConstants
        .run(&p.check().unwrap(), &Inputs::new(), &ctx)
        .unwrap();
    let Some(Product::Table(t)) = out.get("material") else {
        panic!("no material table")
    };
    t.conform(MaterialTable::COLUMNS).unwrap();
    (t.clone(), ctx.notes())
}

fn param_error(params: serde_json::Value) -> (String, String) {
    let e = MaterialConstants
        .params_from_json(params, std::path::Path::new("."))
        .unwrap_err();
    (e.param, e.message)
}

#[test]
fn every_family_round_trips_through_the_table() {
    let cases: Vec<(serde_json::Value, Box<dyn Hyperelastic>)> = vec![
        (
            json!({"family": "neo-hookean", "mu_pa": 6e5}),
            Box::new(NeoHookean::new(3e5).unwrap()),
        ),
        (
            json!({"family": "mooney-rivlin", "c10_pa": 2e5, "c01_pa": 5e4}),
            Box::new(MooneyRivlin::new(2e5, 5e4).unwrap()),
        ),
        (
            json!({"family": "yeoh", "c10_pa": 2e5, "c20_pa": -1e4, "c30_pa": 1e3}),
            Box::new(Yeoh::new(2e5, -1e4, 1e3).unwrap()),
        ),
        (
            json!({"family": "arruda-boyce", "mu_pa": 3e5, "lambda_m": 2.7}),
            Box::new(ArrudaBoyce::new(3e5, 2.7).unwrap()),
        ),
        (
            json!({"family": "ogden", "mu_pa": [7e5, -1e5, 2e3], "alpha": [1.3, -2.0, 5.0]}),
            Box::new(Ogden::new(vec![7e5, -1e5, 2e3], vec![1.3, -2.0, 5.0]).unwrap()),
        ),
        (
            json!({"family": "ogden", "mu_pa": 4e5, "alpha": 2.0}),
            Box::new(Ogden::new(vec![4e5], vec![2.0]).unwrap()),
        ),
    ];
    for (params, expected) in cases {
        let table = run(params.clone());
        let Material::Hyperelastic(back) = material_from_table(&table).unwrap() else {
            panic!("{params} is hyperelastic")
        };
        assert_eq!(back.family(), expected.family(), "{params}");
        assert_eq!(back.parameters(), expected.parameters(), "{params}");
        // The hyperelastic-only reader gives the same model.
        assert_eq!(
            from_table(&table).unwrap().parameters(),
            expected.parameters()
        );
        for mode in Mode::ALL {
            for l in [0.5, 0.9, 1.0, 1.3, 2.0] {
                assert_eq!(
                    back.nominal_stress_pa(mode, l),
                    expected.nominal_stress_pa(mode, l),
                    "{params} {mode:?} λ = {l}"
                );
            }
        }
    }
    let table = run(json!({"family": "linear", "e_pa": 2e6, "poisson": 0.49}));
    let Material::Linear(solid) = material_from_table(&table).unwrap() else {
        panic!("linear")
    };
    assert_eq!((solid.e_pa, solid.poisson), (2e6, 0.49));
    let Material::Linear(solid) =
        material_from_table(&run(json!({"family": "linear", "e_pa": 2e6}))).unwrap()
    else {
        panic!("linear")
    };
    assert_eq!(solid.poisson, 0.5);
}

#[test]
fn a_linear_table_is_refused_where_a_strain_energy_is_needed() {
    let table = run(json!({"family": "linear", "e_pa": 2e6, "poisson": 0.49}));
    let e = from_table(&table).unwrap_err().to_string();
    assert!(
        e.contains("linear solid") && e.contains("E = 2e6 Pa") && e.contains("strain energy"),
        "{e}"
    );
}

#[test]
fn bad_parameters_are_named() {
    let (param, message) =
        param_error(json!({"family": "neo-hookean", "mu_pa": 6e5, "c01_pa": 1e4}));
    assert_eq!(param, "c01_pa");
    assert!(
        message.contains("`neo-hookean` does not take it"),
        "{message}"
    );
    let (param, _) = param_error(json!({"family": "linear", "e_pa": 2e6, "poisson": 0.7}));
    assert_eq!(param, "poisson");
    let (param, _) = param_error(json!({"family": "linear", "e_pa": -2e6}));
    assert_eq!(param, "e_pa");
    let (param, message) = param_error(json!({"e_pa": 2e6}));
    assert_eq!(param, "family");
    assert!(message.contains("`file`"), "{message}");
    let (param, message) =
        param_error(json!({"family": "ogden", "mu_pa": [1e5, 2e5], "alpha": [2.0]}));
    assert_eq!(param, "alpha");
    assert!(message.contains("one α_i per μ_i"), "{message}");
    let (param, _) = param_error(json!({"family": "yeoh", "c10_pa": 1e5, "c20_pa": 0.0}));
    assert_eq!(param, "c30_pa");
    let (param, message) = param_error(json!({"family": "linear", "file": "rubber.csv"}));
    assert_eq!(param, "family");
    assert!(message.contains("from the file"), "{message}");
    let (param, message) = param_error(json!({"family": "gent"}));
    assert_eq!(param, "family");
    assert!(message.contains("arruda-boyce"), "{message}");
    let (param, _) = param_error(json!({"family": "linear", "e_pa": 2e6, "shear_pa": 1.0}));
    assert_eq!(param, "shear_pa");
    let (param, message) = param_error(json!({"family": "neo-hookean", "mu_pa": "6e5"}));
    assert_eq!(param, "mu_pa");
    assert!(
        message.contains("a number or a list of numbers"),
        "{message}"
    );
    let (param, message) =
        param_error(json!({"family": "ogden", "mu_pa": [1e5, "x"], "alpha": [2, 3]}));
    assert_eq!(param, "mu_pa.1");
    assert!(message.contains("f64"), "{message}");
    // Integers are numbers too.
    let table = run(json!({"family": "ogden", "mu_pa": [600000], "alpha": 2}));
    let Material::Hyperelastic(m) = material_from_table(&table).unwrap() else {
        panic!("ogden")
    };
    assert_eq!(m.shear_modulus_pa(), 6e5);
}

#[test]
fn a_parameter_file_gives_the_same_table_as_the_parameters() {
    let dir = std::env::temp_dir().join(format!("hc-material-stage-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ogden.csv");
    std::fs::write(
        &path,
        "# two terms\nfamily, ogden\nmu_pa, 7e5, -1e5\nalpha, 1.3, -2\n",
    )
    .unwrap();
    let from_file = run(json!({"file": path}));
    let given = run(json!({"family": "ogden", "mu_pa": [7e5, -1e5], "alpha": [1.3, -2.0]}));
    assert_eq!(from_file, given);
    std::fs::write(&path, "family, ogden\nmu_pa, 7e5, -1e5\nalpha, 1.3\n").unwrap();
    let p: MaterialParams = serde_json::from_value(json!({"file": path})).unwrap();
    let e = MaterialConstants
        .run(&p.check().unwrap(), &Inputs::new(), &Context::new("t"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("ogden.csv: line 3") && e.contains("alpha"),
        "{e}"
    );
}

#[test]
fn the_note_gives_the_small_strain_moduli() {
    let (_, notes) = run_noted(json!({"family": "mooney-rivlin", "c10_pa": 2e5, "c01_pa": 5e4}));
    assert_eq!(
        notes,
        ["mooney-rivlin: μ0 = 5.000000e5 Pa, E0 = 3 μ0 = 1.500000e6 Pa (ν = ½)"]
    );
    let (_, notes) = run_noted(json!({"family": "linear", "e_pa": 2e6, "poisson": 0.5}));
    assert_eq!(
        notes,
        ["linear: E = 2.000000e6 Pa, ν = 0.5, E* = E/(1 − ν²) = 2.666667e6 Pa at every stress"]
    );
}
