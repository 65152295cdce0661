//! The plain-Rust half of the Python module: any registered stage run on
//! products handed over from another language, with the runner's parameter
//! path (`params_from_json`, then `check()`), so a parameter is refused with
//! the message a pipeline's YAML gets. Tables cross as Parquet bytes written
//! and read by hypercontact-io (the format of the runner's cache), so a
//! table seen from Python holds the same values as the CLI's file.

use std::path::Path;
use std::sync::Arc;

use hypercontact_core::progress::ProgressSink;
use hypercontact_core::{
    ColumnSpec, Context, DType, DynStage, Inputs, Outputs, ParamsError, Product, ProductKind,
    Registry, StageError, Table,
};
use hypercontact_io::{IoError, RunnerReader};
use hypercontact_runner::progress::TerminalProgress;

use crate::lines::LineProgress;
use indicatif::MultiProgress;

/// Why a call from Python failed; each message names the kind, the
/// parameter, the input or the stage's own complaint.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    #[error("unknown stage kind `{kind}` (known: {known})")]
    UnknownKind { kind: String, known: String },
    #[error("{kind}: {source}")]
    Params { kind: String, source: ParamsError },
    #[error("{kind}: parameters are not a JSON object: {message}")]
    ParamsJson { kind: String, message: String },
    #[error("{kind}: no input `{input}` (declared: {declared})")]
    UnknownInput {
        kind: String,
        input: String,
        declared: String,
    },
    #[error("{kind}: input `{input}` is a {expected}, got a {got}")]
    InputKind {
        kind: String,
        input: String,
        expected: ProductKind,
        got: ProductKind,
    },
    #[error("{kind}: input `{input}`: no column `{column}` (required: {required})")]
    MissingColumn {
        kind: String,
        input: String,
        column: String,
        required: String,
    },
    #[error("{kind}: input `{input}`: column `{column}` holds {got}, the stage reads {expected}")]
    ColumnType {
        kind: String,
        input: String,
        column: String,
        expected: hypercontact_core::DType,
        got: hypercontact_core::DType,
    },
    #[error("{kind}: {source}")]
    Stage { kind: String, source: StageError },
    #[error("table `{name}`: {source}")]
    Table { name: String, source: IoError },
}

/// The stage of `kind`, or the list of kinds that exist.
pub fn stage<'a>(registry: &'a Registry, kind: &str) -> Result<&'a Arc<dyn DynStage>, BridgeError> {
    registry.get(kind).ok_or_else(|| BridgeError::UnknownKind {
        kind: kind.to_owned(),
        known: registry.kinds().collect::<Vec<_>>().join(", "),
    })
}

/// A table as Parquet bytes, written as the runner stores it: its
/// declared columns' units and descriptions in the file (zstd, statistics).
pub fn table_to_parquet(
    name: &str,
    table: &Table,
    columns: &[ColumnSpec],
) -> Result<Vec<u8>, BridgeError> {
    let mut bytes = Vec::new();
    hypercontact_io::write_parquet_described(table, columns, &mut bytes).map_err(|source| {
        BridgeError::Table {
            name: name.to_owned(),
            source,
        }
    })?;
    Ok(bytes)
}

/// An output as it crosses to another language: tables as the runner's
/// Parquet bytes, fields as they are, files with their index's bytes.
pub enum Crossing {
    Table(Vec<u8>),
    Field(hypercontact_core::Field),
    Files(std::collections::BTreeMap<String, Vec<u8>>, Option<Vec<u8>>),
}

/// Every output of `kind` ready to cross, in output-name order; each table
/// carries the columns its output declares, so its bytes are the file the
/// CLI exports.
pub fn encode_outputs(
    stage: &dyn DynStage,
    outputs: Outputs,
) -> Result<Vec<(String, Crossing)>, BridgeError> {
    let info = stage.info();
    let mut crossing = Vec::new();
    for (name, product) in outputs.into_inner() {
        let columns = info.output(&name).map(|o| o.columns).unwrap_or(&[]);
        let encoded = match product {
            Product::Table(table) => Crossing::Table(table_to_parquet(&name, &table, columns)?),
            Product::Field(field) => Crossing::Field(field),
            Product::Files(files) => {
                let index = files
                    .index
                    .as_ref()
                    .map(|table| table_to_parquet(&name, table, columns))
                    .transpose()?;
                Crossing::Files(files.files, index)
            }
        };
        crossing.push((name, encoded));
    }
    Ok(crossing)
}

/// A table from Parquet bytes, read as the runner reads its cache.
pub fn table_from_parquet(name: &str, bytes: Vec<u8>) -> Result<Table, BridgeError> {
    hypercontact_io::read_parquet(std::io::Cursor::new(bytes)).map_err(|source| {
        BridgeError::Table {
            name: name.to_owned(),
            source,
        }
    })
}

/// Refuses an input the kind does not declare, or one of the wrong kind,
/// before the stage sees it. Labelled inputs arrive as `name.label`.
fn check_inputs(stage: &dyn DynStage, inputs: &Inputs) -> Result<(), BridgeError> {
    let info = stage.info();
    for name in inputs.names() {
        let declared_name = name.split('.').next().unwrap_or(name);
        let Some(spec) = info.input(declared_name) else {
            return Err(BridgeError::UnknownInput {
                kind: info.kind.to_owned(),
                input: name.to_owned(),
                declared: info
                    .inputs
                    .iter()
                    .map(|i| i.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        };
        let got = inputs.get(name).map(Product::kind).unwrap_or(spec.kind);
        if got != spec.kind {
            return Err(BridgeError::InputKind {
                kind: info.kind.to_owned(),
                input: name.to_owned(),
                expected: spec.kind,
                got,
            });
        }
        if let Some(Product::Table(table)) = inputs.get(name) {
            check_columns(info.kind, name, spec.columns, table)?;
        }
    }
    Ok(())
}

/// A table handed over from Python has no upstream declaration the plan
/// could have checked, so its required columns are checked here, by name
/// and type, before the stage reads it.
fn check_columns(
    kind: &str,
    input: &str,
    required: &[ColumnSpec],
    table: &Table,
) -> Result<(), BridgeError> {
    for spec in required {
        let Some(column) = table.columns().iter().find(|c| c.name == spec.name) else {
            return Err(BridgeError::MissingColumn {
                kind: kind.to_owned(),
                input: input.to_owned(),
                column: spec.name.to_owned(),
                required: required
                    .iter()
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        };
        // An integer column where floats are read is widened by the
        // stage's own reader, as for a Parquet file; anything else is not.
        let got = column.data.dtype();
        let widened = got == DType::I64 && spec.dtype == DType::F64;
        if got != spec.dtype && !widened {
            return Err(BridgeError::ColumnType {
                kind: kind.to_owned(),
                input: input.to_owned(),
                column: spec.name.to_owned(),
                expected: spec.dtype,
                got,
            });
        }
    }
    Ok(())
}

/// What a stage called from another language gave: its outputs and the
/// notes it said (warnings start with `warning:`).
pub struct StageRun {
    pub outputs: Outputs,
    pub notes: Vec<String>,
}

/// How a stage called from another language shows its progress.
pub enum Show {
    /// Nothing (the notes are still returned).
    Quiet,
    /// The runner's bars on stderr, as `hypercontact run` draws them.
    Terminal,
    /// Text lines through a writer (a notebook).
    Lines(crate::lines::Writer),
}

/// Runs `kind` on `inputs` with parameters given as a JSON object (the
/// pipeline's `with:` block), file paths resolved against `dir`; files are
/// read as the runner reads them.
pub fn run_stage(
    registry: &Registry,
    kind: &str,
    inputs: &Inputs,
    params_json: &str,
    dir: &Path,
    show: Show,
) -> Result<StageRun, BridgeError> {
    let stage = stage(registry, kind)?;
    let value: serde_json::Value =
        serde_json::from_str(params_json).map_err(|e| BridgeError::ParamsJson {
            kind: kind.to_owned(),
            message: e.to_string(),
        })?;
    let params = stage
        .params_from_json(value, dir)
        .map_err(|source| BridgeError::Params {
            kind: kind.to_owned(),
            source,
        })?;
    check_inputs(stage.as_ref(), inputs)?;
    let reader = RunnerReader;
    let bars = MultiProgress::new();
    let sink: Option<Box<dyn ProgressSink + '_>> = match show {
        Show::Quiet => None,
        Show::Terminal => Some(Box::new(TerminalProgress::new(&bars))),
        // Lines every two seconds: enough to see a long stage move.
        Show::Lines(writer) => Some(Box::new(LineProgress::new(
            writer,
            std::time::Duration::from_secs(2),
        ))),
    };
    let ctx = Context::with(kind, sink.as_deref(), &reader);
    let outputs = stage
        .run_dyn(params.as_ref(), inputs, &ctx)
        .map_err(|source| BridgeError::Stage {
            kind: kind.to_owned(),
            source,
        })?;
    Ok(StageRun {
        outputs,
        notes: ctx.notes(),
    })
}
