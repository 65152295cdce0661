//! What the `surface` stage's tests share: tiles as `.npy` bytes, and the
//! stage run on given parameters.

#![allow(dead_code)]

use hypercontact_core::{Context, Field, Inputs, Outputs, Params, Stage, StageError};
use hypercontact_surface::surface_stage::{Surface, SurfaceParams};
use ndarray::Array2;

/// `values` as the bytes of a `.npy` file.
pub fn npy(values: &Array2<f64>) -> Vec<u8> {
    let mut bytes = Vec::new();
    Field::new(values.clone(), 1.0, 1.0)
        .unwrap()
        .write_npy(&mut bytes)
        .unwrap();
    bytes
}

/// Runs the stage with `params`, which must pass their checks.
pub fn run(params: &SurfaceParams, inputs: Inputs) -> Result<Outputs, StageError> {
    let params = params
        .clone()
        .check()
        .expect("the tests' parameters pass their checks");
    Surface.run(&params, &inputs, &Context::new("surface"))
}
