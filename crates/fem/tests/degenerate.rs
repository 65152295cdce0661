//! Issue #50, item 2: tiny inputs are refused or fail fast with their
//! likely cause, instead of hanging or failing slowly as "Newton did not
//! converge".

use std::time::Instant;

use hypercontact_core::{Context, Field, Inputs, Params, Product, Stage};
use hypercontact_fem::MAX_FLATNESS;
use hypercontact_fem::stage::{Fem, FemParams};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use ndarray::Array2;

const PIXEL_M: f64 = 20e-6;

/// The stage's error on `heights` (n × n) with parameters `json`.
fn refusal(heights: Array2<f64>, json: &str) -> String {
    let p = serde_json::from_str::<FemParams>(json)
        .unwrap()
        .check()
        .unwrap();
    let surface = Field::new(heights, PIXEL_M, PIXEL_M).unwrap();
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface))
        .with("material", Product::Table(to_table(&paper_epdm())));
    Fem.run(&p, &inputs, &Context::new("fem"))
        .map(|_| ())
        .expect_err("the stage should fail")
        .to_string()
}

/// A gentle bump: every point at a different height.
fn bumpy(n: usize) -> Array2<f64> {
    Array2::from_shape_fn((n, n), |(i, j)| {
        1e-6 * ((i as f64 * 0.9).sin() + (j as f64 * 1.3).cos())
    })
}

/// A 4 × 4 window with 256 layers: its top layer is 0.0035 pixels thick.
/// It ran for minutes; now it is refused before meshing, naming the ratio,
/// the bound and the parameters to change.
#[test]
fn a_tiny_window_with_many_layers_is_refused_at_once() {
    let started = Instant::now();
    let said = refusal(bumpy(4), r#"{"layers": 256}"#);
    let took_s = started.elapsed().as_secs_f64();
    assert!(took_s < 0.5, "{took_s} s");
    assert!(
        said.contains("degenerate elements: layer 256 of 256"),
        "{said}"
    );
    assert!(
        said.contains(&format!(
            "above the bound {MAX_FLATNESS} (width / thickness)"
        )),
        "{said}"
    );
    assert!(
        said.contains("fewer `layers`, a smaller `grading`, a larger `depth_m`"),
        "{said}"
    );
    let ratio: f64 = said
        .split("aspect ratio ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((280.0..300.0).contains(&ratio), "{ratio}");
    // 32 layers (a ratio of 36) failed Newton after 10–45 s.
    let said = refusal(bumpy(4), r#"{"layers": 32}"#);
    assert!(said.contains("degenerate elements"), "{said}");
}

/// A single spike on a flat map: the contact stays one node while the
/// approach grows, whatever `steps` say; the failure says so.
#[test]
fn a_lone_spike_on_a_flat_map_names_the_saturated_area() {
    let mut heights = Array2::zeros((8, 8));
    heights[[4, 4]] = 5e-6;
    let said = refusal(
        heights,
        r#"{"steps": 20, "max_area_fraction": 0.3, "map_fractions": [0.3], "layers": 4}"#,
    );
    assert!(
        said.contains("likely cause: the contact area stalled at A/A0 = 0.0156 from approach"),
        "{said}"
    );
    assert!(said.contains("(10 steps), then jumped to 0.1406"), "{said}");
    assert!(said.contains("max_area_fraction = 0.3"), "{said}");
}
