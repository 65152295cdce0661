//! The PyO3 module `hypercontact._hypercontact`: the registry's kinds, their
//! declarations and a generic stage call. Products cross as tagged tuples,
//! which `python/hypercontact/__init__.py` turns into DataFrames and
//! `Field`s: `("table", parquet_bytes)`, `("field", heights, dx_m, dy_m)`
//! (a float64 numpy array, axis 0 = x), `("files", {name: bytes},
//! index_parquet_bytes | None)`. Every error is a `ValueError` carrying the
//! message the CLI prints.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use hypercontact_core::{Field, Files, Inputs, Outputs, Product, Registry};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};

use crate::bridge::{self, BridgeError};

/// One registry for the interpreter's life: building it is cheap, but the
/// kinds never change while it runs.
fn registry() -> &'static Registry {
    static REGISTRY: OnceLock<Registry> = OnceLock::new();
    REGISTRY.get_or_init(hypercontact::registry)
}

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Every kind as (kind, version, summary, doc), in name order.
#[pyfunction]
fn kinds() -> Vec<(String, u32, String, String)> {
    registry()
        .iter()
        .map(|s| {
            let info = s.info();
            (
                info.kind.to_owned(),
                info.version,
                info.summary.to_owned(),
                info.doc.to_owned(),
            )
        })
        .collect()
}

/// The kind's declaration as `hypercontact stages --json` prints it, as
/// JSON text (params with default, unit and doc; inputs; outputs).
#[pyfunction]
fn describe(kind: &str) -> PyResult<String> {
    let stage = bridge::stage(registry(), kind).map_err(value_error)?;
    Ok(hypercontact::describe_json(stage.as_ref()).to_string())
}

fn product_from_python(name: &str, item: &Bound<'_, PyAny>) -> PyResult<Product> {
    let tuple = item
        .cast::<PyTuple>()
        .map_err(|_| value_error(format!("input `{name}`: expected a (kind, ...) tuple")))?;
    let tag: String = tuple.get_item(0)?.extract()?;
    match (tag.as_str(), tuple.len()) {
        ("table", 2) => {
            let bytes: Vec<u8> = tuple.get_item(1)?.extract()?;
            Ok(Product::Table(
                bridge::table_from_parquet(name, bytes).map_err(value_error)?,
            ))
        }
        ("field", 4) => {
            let heights: PyReadonlyArray2<'_, f64> = tuple.get_item(1)?.extract()?;
            let dx_m: f64 = tuple.get_item(2)?.extract()?;
            let dy_m: f64 = tuple.get_item(3)?.extract()?;
            let field = Field::new(heights.as_array().to_owned(), dx_m, dy_m)
                .map_err(|e| value_error(format!("input `{name}`: {e}")))?;
            Ok(Product::Field(field))
        }
        ("files", 3) => {
            let files: BTreeMap<String, Vec<u8>> = tuple.get_item(1)?.extract()?;
            let index: Option<Vec<u8>> = tuple.get_item(2)?.extract()?;
            let index = index
                .map(|bytes| bridge::table_from_parquet(name, bytes))
                .transpose()
                .map_err(value_error)?;
            Ok(Product::Files(Files { files, index }))
        }
        _ => Err(value_error(format!(
            "input `{name}`: unknown product tuple `{tag}` of {} items",
            tuple.len()
        ))),
    }
}

fn product_to_python<'py>(
    py: Python<'py>,
    name: &str,
    product: Product,
) -> PyResult<Bound<'py, PyAny>> {
    let tuple = match product {
        Product::Table(table) => {
            let bytes = bridge::table_to_parquet(name, &table).map_err(value_error)?;
            ("table", PyBytes::new(py, &bytes)).into_pyobject(py)?
        }
        Product::Field(field) => {
            let heights = PyArray2::from_owned_array(py, field.values);
            ("field", heights, field.dx_m, field.dy_m).into_pyobject(py)?
        }
        Product::Files(files) => {
            let dict = PyDict::new(py);
            for (file, bytes) in &files.files {
                dict.set_item(file, PyBytes::new(py, bytes))?;
            }
            let index = match &files.index {
                Some(table) => Some(PyBytes::new(
                    py,
                    &bridge::table_to_parquet(name, table).map_err(value_error)?,
                )),
                None => None,
            };
            ("files", dict, index).into_pyobject(py)?
        }
    };
    Ok(tuple.into_any())
}

/// Runs `kind` on `inputs` ({name: product tuple}; labelled inputs as
/// `name.label`) with `params_json` (a JSON object, the YAML `with:` block);
/// returns {output: product tuple}. Relative paths in parameters resolve
/// against the current directory. The GIL is released while the stage runs.
#[pyfunction]
fn run_stage<'py>(
    py: Python<'py>,
    kind: &str,
    inputs: &Bound<'py, PyDict>,
    params_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let mut products = Inputs::new();
    for (name, item) in inputs.iter() {
        let name: String = name.extract()?;
        let product = product_from_python(&name, &item)?;
        products = products.with(&name, product);
    }
    let dir = std::env::current_dir().map_err(value_error)?;
    let outputs: Result<Outputs, BridgeError> =
        py.detach(|| bridge::run_stage(registry(), kind, &products, params_json, &dir));
    let outputs = outputs.map_err(value_error)?;
    let dict = PyDict::new(py);
    for (name, product) in outputs.into_inner() {
        dict.set_item(&name, product_to_python(py, &name, product)?)?;
    }
    Ok(dict)
}

#[pymodule]
fn _hypercontact(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(kinds, m)?)?;
    m.add_function(wrap_pyfunction!(describe, m)?)?;
    m.add_function(wrap_pyfunction!(run_stage, m)?)?;
    Ok(())
}
