//! The bridge the Python module stands on, without an interpreter: a BEM
//! curve through `run_stage` equals the stage called directly with the same
//! checked parameters, a refused parameter carries the YAML message, and
//! tables survive the Parquet crossing bit for bit. The load pinned here is
//! the one `tests/test_stages.py` expects from Python on the same map.

use std::path::Path;

use _hypercontact::bridge::{self, BridgeError};
use hypercontact_core::{Context, Field, Inputs, Product};
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

const BEM_PARAMS: &str = r#"{"boundary": "periodic", "model": "linear", "steps": 5,
    "max_area_fraction": 0.1, "map_fractions": [0.1]}"#;

fn material() -> Product {
    let registry = hypercontact::registry();
    let outputs = bridge::run_stage(
        &registry,
        "material-preset",
        &Inputs::new(),
        "{}",
        Path::new("."),
    )
    .unwrap();
    outputs.get("material").unwrap().clone()
}

fn bem_load_n(inputs: &Inputs) -> Vec<f64> {
    let registry = hypercontact::registry();
    let outputs = bridge::run_stage(&registry, "bem", inputs, BEM_PARAMS, Path::new(".")).unwrap();
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
const PINNED_LAST_LOAD_N: f64 = 8.66976748034176e-06;

#[test]
fn parquet_crossing_keeps_every_bit() {
    let Product::Table(table) = material() else {
        panic!("material-preset's material is a table")
    };
    let bytes = bridge::table_to_parquet("material", &table).unwrap();
    assert_eq!(
        bridge::table_from_parquet("material", bytes).unwrap(),
        table
    );
}

#[test]
fn a_refused_parameter_carries_the_yaml_message() {
    let registry = hypercontact::registry();
    let e = bridge::run_stage(
        &registry,
        "bem",
        &Inputs::new(),
        r#"{"steps": 0}"#,
        Path::new("."),
    )
    .unwrap_err();
    let BridgeError::Params { source, .. } = &e else {
        panic!("expected a parameter error, got {e}")
    };
    assert_eq!(source.param, "steps");
    assert!(e.to_string().contains("parameter `steps`"), "{e}");
}

#[test]
fn an_unknown_kind_or_input_is_named() {
    let registry = hypercontact::registry();
    let e = bridge::run_stage(&registry, "nope", &Inputs::new(), "{}", Path::new(".")).unwrap_err();
    assert!(
        e.to_string().contains("`nope`") && e.to_string().contains("bem"),
        "{e}"
    );
    let inputs = Inputs::new().with("surfce", Product::Field(surface()));
    let e = bridge::run_stage(&registry, "bem", &inputs, "{}", Path::new(".")).unwrap_err();
    assert!(e.to_string().contains("`surfce`"), "{e}");
}
