//! The bridge the Python module stands on, without an interpreter: a BEM
//! curve through `run_stage` equals the stage called directly with the same
//! checked parameters, a refused parameter carries the YAML message, and
//! tables survive the Parquet crossing bit for bit. The load pinned here is
//! the one `tests/test_stages.py` expects from Python on the same map.

use std::path::Path;

use _hypercontact::bridge::{self, BridgeError, Show};
use hypercontact_core::{Context, Field, Inputs, Outputs, Product, Table};
use ndarray::Array2;

/// A rough periodic map whose every height is an exact IEEE product, so
/// numpy builds the same bits (`surface_m` in `tests/test_stages.py`).
fn surface() -> Field {
    let n = 32;
    let heights = Array2::from_shape_fn((n, n), |(ix, iy)| {
        ((3 * ix * ix + 5 * iy + ix * iy) % 23) as f64 * 1e-8
    });
    Field::new(heights, 1e-6, 1e-6).unwrap()
}

/// The bridge as Python calls it, without progress; the outputs only.
fn call(kind: &str, inputs: &Inputs, params_json: &str) -> Result<Outputs, BridgeError> {
    let registry = hypercontact::registry();
    bridge::run_stage(
        &registry,
        kind,
        inputs,
        params_json,
        Path::new("."),
        Show::Quiet,
    )
    .map(|run| run.outputs)
}

const BEM_PARAMS: &str = r#"{"boundary": "periodic", "model": "linear", "steps": 5,
    "max_area_fraction": 0.1, "map_fractions": [0.1]}"#;

fn material() -> Product {
    let outputs = call("material-preset", &Inputs::new(), "{}").unwrap();
    outputs.get("material").unwrap().clone()
}

fn bem_load_n(inputs: &Inputs) -> Vec<f64> {
    let outputs = call("bem", inputs, BEM_PARAMS).unwrap();
    outputs
        .get_table("response")
        .unwrap()
        .f64("load_n")
        .unwrap()
        .to_vec()
}

#[test]
fn bem_through_the_bridge_equals_the_stage_called_directly() {
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface()))
        .with("material", material());
    let through_bridge = bem_load_n(&inputs);

    let registry = hypercontact::registry();
    let bem = registry.get("bem").unwrap();
    let params = bem
        .params_from_json(serde_json::from_str(BEM_PARAMS).unwrap(), Path::new("."))
        .unwrap();
    let direct = bem
        .run_dyn(params.as_ref(), &inputs, &Context::new("bem"))
        .unwrap();
    let direct_load_n = direct.get_table("response").unwrap().f64("load_n").unwrap();
    assert_eq!(through_bridge, direct_load_n);
    assert_eq!(through_bridge.len(), 6, "first contact and 5 steps");
    // The number tests/test_stages.py compares Python's curve with.
    assert_eq!(
        through_bridge[5], PINNED_LAST_LOAD_N,
        "{:e}",
        through_bridge[5]
    );
}

/// bem's last load on `surface()`, printed by this test when recorded.
const PINNED_LAST_LOAD_N: f64 = 8.66976747881934e-06;

#[test]
fn parquet_crossing_keeps_every_bit() {
    let Product::Table(table) = material() else {
        panic!("material-preset's material is a table")
    };
    let registry = hypercontact::registry();
    let preset = registry.get("material-preset").unwrap();
    let columns = preset.info().output("material").unwrap().columns;
    let bytes = bridge::table_to_parquet("material", &table, columns).unwrap();
    // The units travel: the declaration comes back from the bytes.
    let meta = hypercontact_io::parquet_columns_meta(std::io::Cursor::new(bytes.clone())).unwrap();
    let names: Vec<&str> = meta.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["model", "param", "value"]);
    assert_eq!(
        bridge::table_from_parquet("material", bytes).unwrap(),
        table
    );
}

#[test]
fn a_refused_parameter_carries_the_yaml_message() {
    let e = call("bem", &Inputs::new(), r#"{"steps": 0}"#).unwrap_err();
    let BridgeError::Params { source, .. } = &e else {
        panic!("expected a parameter error, got {e}")
    };
    assert_eq!(source.param, "steps");
    assert!(e.to_string().contains("parameter `steps`"), "{e}");
}

#[test]
fn a_table_without_a_required_column_is_refused_naming_it() {
    let Product::Table(material) = material() else {
        panic!("material-preset gives a table")
    };
    let mut cut = Table::new();
    for column in material.columns().iter().filter(|c| c.name != "value") {
        cut.push(&column.name, column.data.clone());
    }
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface()))
        .with("material", Product::Table(cut));
    let e = call("bem", &inputs, BEM_PARAMS).unwrap_err();
    assert_eq!(
        e.to_string(),
        "bem: input `material`: no column `value` (required: model, param, value)"
    );
}

#[test]
fn an_unknown_kind_or_input_is_named() {
    let e = call("nope", &Inputs::new(), "{}").unwrap_err();
    assert!(
        e.to_string().contains("`nope`") && e.to_string().contains("bem"),
        "{e}"
    );
    let inputs = Inputs::new().with("surfce", Product::Field(surface()));
    let e = call("bem", &inputs, "{}").unwrap_err();
    assert!(e.to_string().contains("`surfce`"), "{e}");
}
