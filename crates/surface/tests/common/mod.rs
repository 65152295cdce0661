//! What the `surface` crate's tests share: tiles as `.npy` bytes, the
//! `surface` stage run on given parameters, and `height-map` run as a
//! pipeline runs it.

#![allow(dead_code)]

use std::path::Path;

use hypercontact_core::{
    Context, DynStage, Field, Inputs, Outputs, Params, Product, Stage, StageError,
};
use hypercontact_surface::height_map::HeightMap;
use hypercontact_surface::surface_stage::{Surface, SurfaceParams};
use ndarray::Array2;
use serde_json::{Value, json};

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

/// `height-map` on `path` with `params` as a pipeline gives them: the
/// height field and the notes, or the error as text.
pub fn height_map(path: &Path, mut params: Value) -> Result<(Field, Vec<String>), String> {
    params["path"] = json!(path);
    let checked = HeightMap
        .params_from_json(params, Path::new("."))
        .map_err(|e| format!("{}: {}", e.param, e.message))?;
    let ctx = Context::new("afm");
    let out = HeightMap
        .run_dyn(&*checked, &Inputs::new(), &ctx)
        .map_err(|e| e.to_string())?;
    let Some(Product::Field(h)) = out.get("height") else {
        panic!("no height output")
    };
    Ok((h.clone(), ctx.notes()))
}
