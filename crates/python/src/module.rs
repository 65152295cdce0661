//! The PyO3 module `hypercontact._hypercontact`: the registry's kinds, their
//! declarations and a generic stage call. Products cross as tagged tuples,
//! which `python/hypercontact/__init__.py` turns into DataFrames and
//! `Field`s: `("table", parquet_bytes)`, `("field", heights, dx_m, dy_m)`
//! (a float64 numpy array, axis 0 = x), `("files", {name: bytes},
//! index_parquet_bytes | None)`. Every error is a `ValueError` carrying the
//! message the CLI prints.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use hypercontact_core::{Field, Files, Inputs, Product, Registry};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};

use crate::bridge::{self, BridgeError, Crossing, Show};
use crate::lines::Writer;
use crate::runs::{self, RunRequest};

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

/// The Python name of a kind in `hypercontact.stages` (hyphens as
/// underscores), as the type stub names it.
#[pyfunction]
fn attribute(kind: &str) -> String {
    crate::stubs::attribute(kind)
}

/// The docstring of `hypercontact.stages.<kind>`, from its declaration.
#[pyfunction]
fn docstring(kind: &str) -> PyResult<String> {
    let stage = bridge::stage(registry(), kind).map_err(value_error)?;
    Ok(crate::stubs::docstring(stage.as_ref()))
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

fn crossing_to_python<'py>(py: Python<'py>, crossing: Crossing) -> PyResult<Bound<'py, PyAny>> {
    let tuple = match crossing {
        Crossing::Table(bytes) => ("table", PyBytes::new(py, &bytes)).into_pyobject(py)?,
        Crossing::Field(field) => {
            // The array moves to numpy without a copy.
            let heights = PyArray2::from_owned_array(py, field.values);
            ("field", heights, field.dx_m, field.dy_m).into_pyobject(py)?
        }
        Crossing::Files(files, index) => {
            let dict = PyDict::new(py);
            for (file, bytes) in &files {
                dict.set_item(file, PyBytes::new(py, bytes))?;
            }
            let index = index.map(|bytes| PyBytes::new(py, &bytes));
            ("files", dict, index).into_pyobject(py)?
        }
    };
    Ok(tuple.into_any())
}

/// Runs `kind` on `inputs` ({name: product tuple}; labelled inputs as
/// `name.label`) with `params_json` (a JSON object, the YAML `with:` block);
/// returns ({output: product tuple}, [notes]). Relative paths in parameters
/// resolve against `base_dir` (default the current directory). The GIL is
/// released while the stage runs.
#[pyfunction]
#[pyo3(signature = (kind, inputs, params_json, progress=None, base_dir=None))]
fn run_stage<'py>(
    py: Python<'py>,
    kind: &str,
    inputs: &Bound<'py, PyDict>,
    params_json: &str,
    progress: Option<Bound<'py, PyAny>>,
    base_dir: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyDict>, Vec<String>)> {
    let mut products = Inputs::new();
    for (name, item) in inputs.iter() {
        let name: String = name.extract()?;
        let product = product_from_python(&name, &item)?;
        products = products.with(&name, product);
    }
    let dir = match base_dir {
        Some(dir) => dir,
        None => std::env::current_dir().map_err(value_error)?,
    };
    let show = show(progress)?;
    let crossed: Result<_, BridgeError> = py.detach(|| {
        let run = bridge::run_stage(registry(), kind, &products, params_json, &dir, show)?;
        let stage = bridge::stage(registry(), kind)?;
        Ok((
            bridge::encode_outputs(stage.as_ref(), run.outputs)?,
            run.notes,
        ))
    });
    let (outputs, notes) = crossed.map_err(value_error)?;
    let dict = PyDict::new(py);
    for (name, crossing) in outputs {
        dict.set_item(&name, crossing_to_python(py, crossing)?)?;
    }
    Ok((dict, notes))
}

/// `progress` as Python gives it: None or False for nothing, True for the
/// runner's bars on the process's stderr, or a callable taking a line of
/// text (what a notebook shows: `sys.stderr.write`), called with the GIL
/// taken back from the worker thread that reports.
fn show(progress: Option<Bound<'_, PyAny>>) -> PyResult<Show> {
    let Some(progress) = progress else {
        return Ok(Show::Quiet);
    };
    if progress.is_callable() {
        let callback: Py<PyAny> = progress.unbind();
        let writer: Writer = Arc::new(move |line: &str| {
            Python::attach(|py| {
                // A failing writer must not stop the stage: the line is lost.
                let _ = callback.call1(py, (line,));
            });
        });
        return Ok(Show::Lines(writer));
    }
    Ok(if progress.is_truthy()? {
        Show::Terminal
    } else {
        Show::Quiet
    })
}

/// Runs `work` on a thread of its own while the interpreter's thread
/// waits without the GIL, taking it back every [`POLL`] to run Python's
/// signal handlers: Ctrl-C raises `KeyboardInterrupt` within a second
/// (the CLI is ended by the signal itself; a Python process goes on). The
/// run is then told to start no further stage (`cancel`); the stage under
/// way finishes on its thread and writes its entry whole, as every entry
/// is written, so the cache stays sound.
fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    cancel: &AtomicBool,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    const POLL: Duration = Duration::from_millis(100);
    // How long an interrupted run gets to stop between stages before the
    // interpreter goes on without it.
    const GRACE: Duration = Duration::from_millis(500);
    let (sender, receiver) = mpsc::channel();
    std::thread::Builder::new()
        .name("hypercontact-run".into())
        .spawn(move || {
            // The caller may have gone on after an interruption.
            let _ = sender.send(work());
        })
        .map_err(value_error)?;
    let mut receiver = receiver;
    loop {
        // The receiver moves to the detached closure and back: it is Send,
        // not Sync.
        let (waited, back) = py.detach(move || (receiver.recv_timeout(POLL), receiver));
        receiver = back;
        match waited {
            Ok(result) => return Ok(result),
            Err(RecvTimeoutError::Disconnected) => {
                return Err(value_error(
                    "the run ended without a result (its thread panicked)",
                ));
            }
            Err(RecvTimeoutError::Timeout) => {}
        }
        if let Err(signal) = py.check_signals() {
            cancel.store(true, Ordering::SeqCst);
            let _ = py.detach(move || receiver.recv_timeout(GRACE).is_ok());
            return Err(signal);
        }
    }
}

/// Refuses an array that cannot be a field's values in the words the
/// CLI's `.npy` reader uses: `descr` is the type descriptor as a `.npy`
/// header writes it (`'<i8'`), `shape` the array's.
#[pyfunction]
fn check_field_values(descr: &str, shape: Vec<usize>) -> PyResult<()> {
    hypercontact_core::field::value_bytes(descr)
        .and_then(|_| hypercontact_core::field::check_2d(&shape))
        .map_err(value_error)
}

/// Why a float cannot be a parameter, in the words a YAML value gets.
#[pyfunction]
fn not_finite(value: f64) -> String {
    hypercontact_runner::yaml::not_finite(value)
}

/// Runs a pipeline file as `hypercontact run` does (`sets` are `--set`
/// assignments, in order); returns (run folder, summary, computed, cached).
/// The GIL is released while it runs; an error is a `ValueError` with the
/// CLI's message.
#[pyfunction]
#[pyo3(signature = (pipeline, out=None, cache=None, sets=Vec::new(), force=Vec::new(), only=None, progress=false))]
#[allow(clippy::too_many_arguments)] // the CLI's flags, one by one
fn run_pipeline(
    py: Python<'_>,
    pipeline: PathBuf,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
    sets: Vec<String>,
    force: Vec<String>,
    only: Option<String>,
    progress: bool,
) -> PyResult<(PathBuf, String, usize, usize)> {
    let request = RunRequest {
        pipeline,
        out,
        cache,
        sets,
        force,
        only,
        progress,
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let outcome = interruptible(py, &cancel, move || {
        runs::run_pipeline(registry(), &request, Some(flag))
    })?
    .map_err(PyValueError::new_err)?;
    Ok((
        outcome.out_dir,
        outcome.summary,
        outcome.computed,
        outcome.cached,
    ))
}

/// Runs a pipeline's `study:` sweep as `hypercontact study` does; returns
/// (study folder, [(stage.output, gathered table file)]).
#[pyfunction]
#[pyo3(signature = (pipeline, out=None, cache=None, sets=Vec::new(), progress=false))]
fn run_study(
    py: Python<'_>,
    pipeline: PathBuf,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
    sets: Vec<String>,
    progress: bool,
) -> PyResult<(PathBuf, Vec<(String, PathBuf)>)> {
    let request = RunRequest {
        pipeline,
        out,
        cache,
        sets,
        progress,
        ..RunRequest::default()
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let outcome = interruptible(py, &cancel, move || {
        runs::run_study(registry(), &request, Some(flag))
    })?
    .map_err(PyValueError::new_err)?;
    Ok((outcome.out_dir, outcome.tables))
}

/// A pipeline's folder and its stages as (name, kind, parameters as given,
/// JSON), `sets` applied: what a replay of one stage needs.
#[pyfunction]
#[pyo3(signature = (pipeline, sets=Vec::new()))]
fn pipeline_stages(
    pipeline: PathBuf,
    sets: Vec<String>,
) -> PyResult<(PathBuf, Vec<runs::DeclaredStage>)> {
    runs::pipeline_stages(registry(), &pipeline, &sets).map_err(PyValueError::new_err)
}

/// Reads a field as the runner stored it (`.npy` beside `.grid.json`);
/// returns (values, dx_m, dy_m).
#[pyfunction]
fn read_field<'py>(
    py: Python<'py>,
    npy: PathBuf,
    grid: PathBuf,
) -> PyResult<(Bound<'py, PyArray2<f64>>, f64, f64)> {
    let field = hypercontact_runner::store::read_field(&npy, &grid).map_err(value_error)?;
    Ok((
        PyArray2::from_owned_array(py, field.values),
        field.dx_m,
        field.dy_m,
    ))
}

#[pymodule]
fn _hypercontact(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(kinds, m)?)?;
    m.add_function(wrap_pyfunction!(describe, m)?)?;
    m.add_function(wrap_pyfunction!(docstring, m)?)?;
    m.add_function(wrap_pyfunction!(attribute, m)?)?;
    m.add_function(wrap_pyfunction!(run_stage, m)?)?;
    m.add_function(wrap_pyfunction!(run_pipeline, m)?)?;
    m.add_function(wrap_pyfunction!(run_study, m)?)?;
    m.add_function(wrap_pyfunction!(read_field, m)?)?;
    m.add_function(wrap_pyfunction!(pipeline_stages, m)?)?;
    m.add_function(wrap_pyfunction!(check_field_values, m)?)?;
    m.add_function(wrap_pyfunction!(not_finite, m)?)?;
    Ok(())
}
