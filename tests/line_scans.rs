//! Line scans (issue #36, item 5): `surface` analyses a profile, and every
//! stage that needs a 2-D height map refuses one with an error naming the
//! stage and saying its input is a line scan, rather than panicking or
//! giving a number for a surface that was never measured.

use std::path::Path;

use hypercontact_core::{Context, Field, Inputs, Product, StageError};
use ndarray::Array2;
use serde_json::{Value, json};

/// A rough profile of n points along x (a sum of incommensurate waves).
fn profile(n: usize) -> Field {
    let h = Array2::from_shape_fn((n, 1), |(i, _)| {
        let x = i as f64;
        1e-6 * ((0.05 * x).sin() + 0.3 * (0.31 * x).sin() + 0.1 * (1.7 * x).cos())
    });
    Field::new(h, 1e-6, 1e-6).unwrap()
}

/// Runs `kind` with parameters `params` (JSON, as a pipeline gives them)
/// on `inputs`.
fn run(
    kind: &str,
    params: Value,
    inputs: &Inputs,
) -> Result<hypercontact_core::Outputs, StageError> {
    let registry = hypercontact::registry();
    let stage = registry
        .get(kind)
        .unwrap_or_else(|| panic!("no kind {kind}"));
    let params = stage
        .params_from_json(params, Path::new("."))
        .unwrap_or_else(|e| panic!("{kind}: {e}"));
    stage.run_dyn(params.as_ref(), inputs, &Context::new(kind))
}

/// The parameters each refusing kind needs to get as far as its input
/// (those of tests/guard/pipeline.yaml where it has required ones).
fn params_of(kind: &str) -> Value {
    match kind {
        "crop" => json!({ "x0": 0, "y0": 0, "nx": 24, "ny": 24 }),
        "synth-contact" => json!({ "width_px": 96, "height_px": 96, "magnification": 2.0,
            "frames": 8, "shift_x_m": 0.0, "shift_y_m": 0.0 }),
        _ => json!({}),
    }
}

#[test]
fn stages_that_need_an_area_refuse_a_line_scan_naming_themselves() {
    for (n, shape) in [(4000, (4000, 1)), (4000, (1, 4000))] {
        let line = profile(n);
        let values = line.values.into_shape_with_order(shape).unwrap();
        let line = Field::new(values, 1e-6, 1e-6).unwrap();
        let inputs = Inputs::new().with("surface", Product::Field(line));
        for kind in [
            "bem",
            "fem",
            "truncation",
            "crop",
            "synth-contact",
            "persson",
            "greenwood-williamson",
            "contact-compare",
        ] {
            let e = run(kind, params_of(kind), &inputs)
                .err()
                .unwrap_or_else(|| panic!("{kind} ran on a line scan"))
                .to_string();
            let said = format!(
                "{kind}: input `surface` is a line scan ({} × {} points, a profile): {kind} \
                 needs a 2-D height map",
                shape.0, shape.1
            );
            assert!(e.starts_with(&said), "{kind}: {e}");
        }
    }
}

// The contact theories from surface's tables of a line: refused from the
// stats (the PSD has no radial rows), naming the stage.
#[test]
fn theories_refuse_the_tables_of_a_line_scan() {
    let inputs = Inputs::new().with("height", Product::Field(profile(4000)));
    let out = run("surface", json!({}), &inputs).unwrap();
    let psd = out.get("psd").unwrap().clone();
    let stats = out.get("stats").unwrap().clone();
    for kind in ["persson", "greenwood-williamson"] {
        let inputs = Inputs::new()
            .with("psd", psd.clone())
            .with("stats", stats.clone());
        let e = run(kind, json!({}), &inputs).err().unwrap().to_string();
        assert!(
            e.starts_with(&format!(
                "{kind}: input `psd` is a line scan (4000 × 1 points, a profile)"
            )),
            "{kind}: {e}"
        );
        // Without stats the missing radial rows say why.
        let inputs = Inputs::new().with("psd", psd.clone());
        let e = run(kind, json!({ "nominal_area_m2": 1e-6 }), &inputs)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("gives none for a line scan"), "{kind}: {e}");
    }
}
