//! Small stage kinds for exercising the runner without real physics.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use hypercontact_core::param::NoParams;
use hypercontact_core::product::ProductKind;
use hypercontact_core::stage::Arity;
use hypercontact_core::{
    Checked, ColumnSpec, Context, Field, Files, InputPath, InputSpec, Inputs, OutputSpec, Outputs,
    Registry, Schema, Stage, StageError, StageInfo, Table, params,
};

/// How often `scale` computed, across threads.
pub static SCALE_RUNS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// How often the runner asked `scale` to let go, on this thread.
    pub static SCALE_LET_GOS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Parameters of the test `source`.
#[params]
pub struct SourceParams {
    /// step between values
    #[param(default = 0.0, unit = "m")]
    pub value: f64,
    /// number of values
    #[param(default = 0, range = ..=1_000_000)]
    pub n: u32,
    /// a CSV whose `x` column is appended
    pub path: Option<InputPath>,
    /// a free label
    #[param(default = String::new())]
    pub label: String,
}

pub struct Source;
static SOURCE: StageInfo = StageInfo {
    kind: "source",
    version: 1,
    summary: "test source",
    doc: "",
    inputs: &[],
    outputs: &[OutputSpec {
        name: "t",
        kind: ProductKind::Table,
        columns: &[ColumnSpec::f64("x", "m", "")],
        doc: "",
    }],
};

impl Stage for Source {
    type Params = SourceParams;
    fn info(&self) -> &'static StageInfo {
        &SOURCE
    }
    fn run(
        &self,
        p: &Checked<SourceParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let mut x: Vec<f64> = (0..p.n).map(|i| p.value * i as f64).collect();
        if let Some(path) = &p.path {
            x.extend(ctx.read_table(path)?.to_f64("x")?);
        }
        Ok(Outputs::new().table("t", Table::new().with("x", x)))
    }
}

/// Parameters of the test `scale`.
#[params]
pub struct ScaleParams {
    /// multiplies x
    #[param(default = 1.0)]
    pub factor: f64,
    /// sleeps this long first
    #[param(default = 0, unit = "ms")]
    pub sleep_ms: u64,
}

pub struct Scale;
static SCALE: StageInfo = StageInfo {
    kind: "scale",
    version: 1,
    summary: "test scale",
    doc: "",
    inputs: &[InputSpec {
        name: "t",
        kind: ProductKind::Table,
        arity: Arity::One,
        columns: &[ColumnSpec::f64("x", "m", "")],
        doc: "a table with x",
    }],
    outputs: &[
        OutputSpec {
            name: "t",
            kind: ProductKind::Table,
            columns: &[ColumnSpec::f64("x", "m", "")],
            doc: "",
        },
        OutputSpec {
            name: "map",
            kind: ProductKind::Field,
            columns: &[],
            doc: "",
        },
        OutputSpec {
            name: "figs",
            kind: ProductKind::Files,
            columns: &[],
            doc: "",
        },
    ],
};

impl Stage for Scale {
    type Params = ScaleParams;
    fn info(&self) -> &'static StageInfo {
        &SCALE
    }
    fn let_go(&self) {
        SCALE_LET_GOS.with(|n| n.set(n.get() + 1));
    }
    fn run(
        &self,
        p: &Checked<ScaleParams>,
        inputs: &Inputs,
        _: &Context,
    ) -> Result<Outputs, StageError> {
        SCALE_RUNS.fetch_add(1, Ordering::SeqCst);
        std::thread::sleep(std::time::Duration::from_millis(p.sleep_ms));
        let x: Vec<f64> = inputs
            .table("t")?
            .f64("x")?
            .iter()
            .map(|v| v * p.factor)
            .collect();
        let n = x.len().max(1);
        let map = Field::new(ndarray::Array2::from_elem((n, 2), p.factor), 1e-5, 1e-5)
            .map_err(StageError::other)?;
        Ok(Outputs::new()
            .table("t", Table::new().with("x", x))
            .field("map", map)
            .files(
                "figs",
                Files::new().with("note.txt", format!("factor {}", p.factor).into_bytes()),
            ))
    }
}

/// Gathers many tables: sums their rows.
pub struct Gather;
static GATHER: StageInfo = StageInfo {
    kind: "gather",
    version: 1,
    summary: "test many-input",
    doc: "",
    inputs: &[InputSpec {
        name: "parts",
        kind: ProductKind::Table,
        arity: Arity::Many,
        columns: &[],
        doc: "",
    }],
    outputs: &[OutputSpec {
        name: "rows",
        kind: ProductKind::Table,
        columns: &[ColumnSpec::str("label", ""), ColumnSpec::i64("n", "", "")],
        doc: "",
    }],
};

impl Stage for Gather {
    type Params = NoParams;
    fn info(&self) -> &'static StageInfo {
        &GATHER
    }
    fn run(
        &self,
        _: &Checked<NoParams>,
        inputs: &Inputs,
        _: &Context,
    ) -> Result<Outputs, StageError> {
        let parts = inputs.labelled("parts");
        let labels: Vec<String> = parts.iter().map(|(l, _)| l.to_string()).collect();
        let n: Vec<i64> = parts
            .iter()
            .map(|(_, p)| match p {
                hypercontact_core::Product::Table(t) => t.n_rows() as i64,
                _ => -1,
            })
            .collect();
        Ok(Outputs::new().table("rows", Table::new().with("label", labels).with("n", n)))
    }
}

/// Takes tables labelled by sample and then by model (a role's consumer):
/// one row per product, its two labels.
pub struct Nest;
static NEST: StageInfo = StageInfo {
    kind: "collect-nested",
    version: 1,
    summary: "test nested input",
    doc: "",
    inputs: &[InputSpec {
        name: "parts",
        kind: ProductKind::Table,
        arity: Arity::Nested,
        columns: &[],
        doc: "",
    }],
    outputs: &[OutputSpec {
        name: "rows",
        kind: ProductKind::Table,
        columns: &[ColumnSpec::str("sample", ""), ColumnSpec::str("model", "")],
        doc: "",
    }],
};

impl Stage for Nest {
    type Params = NoParams;
    fn info(&self) -> &'static StageInfo {
        &NEST
    }
    fn run(
        &self,
        _: &Checked<NoParams>,
        inputs: &Inputs,
        _: &Context,
    ) -> Result<Outputs, StageError> {
        let (samples, models): (Vec<String>, Vec<String>) = inputs
            .nested("parts")
            .into_iter()
            .map(|(s, m, _)| (s.to_owned(), m.to_owned()))
            .unzip();
        Ok(Outputs::new().table(
            "rows",
            Table::new().with("sample", samples).with("model", models),
        ))
    }
}

/// Reads files that must come with an index holding a `file` column.
pub struct IndexReader;
static INDEX_READER: StageInfo = StageInfo {
    kind: "files-indexed",
    version: 1,
    summary: "test indexed files input",
    doc: "",
    inputs: &[InputSpec {
        name: "maps",
        kind: ProductKind::Files,
        arity: Arity::One,
        columns: &[ColumnSpec::str("file", "")],
        doc: "",
    }],
    outputs: &[],
};

impl Stage for IndexReader {
    type Params = NoParams;
    fn info(&self) -> &'static StageInfo {
        &INDEX_READER
    }
    fn run(&self, _: &Checked<NoParams>, _: &Inputs, _: &Context) -> Result<Outputs, StageError> {
        Ok(Outputs::new())
    }
}

pub fn registry() -> Registry {
    let mut r = Registry::new();
    r.add(Source)
        .add(Scale)
        .add(Gather)
        .add(Nest)
        .add(IndexReader);
    r
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

pub const BASIC: &str = "\
name: basic
stages:
  src:
    uses: source
    with: { value: 2.0e-5, n: 5 }
  double:
    uses: scale
    inputs: { t: src }
    with: { factor: 2 }
";

// ---- a throwaway stage whose file parameters sit in a list and in a nested
// struct: nothing but the declaration tells the runner about them ----

/// A nested block with one file.
#[params]
pub struct Lookup {
    /// a lookup table
    pub table: InputPath,
}

/// Parameters of `count-lines`.
#[params]
pub struct CountParams {
    /// any number of files
    #[param(default = Vec::new())]
    pub extra: Vec<InputPath>,
    /// a nested file
    pub lookup: Lookup,
}

/// Lines per file.
#[derive(Schema)]
pub struct Counts {
    /// lines in the file
    pub lines: Vec<i64>,
}

pub struct CountLines;

static INFO: StageInfo = StageInfo {
    kind: "count-lines",
    version: 1,
    summary: "counts the lines of its files",
    doc: "",
    inputs: &[],
    outputs: &[OutputSpec::table::<Counts>("counts", "one row per file")],
};

impl Stage for CountLines {
    type Params = CountParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<CountParams>,
        _: &Inputs,
        _: &Context,
    ) -> Result<Outputs, StageError> {
        let mut lines = Vec::new();
        for path in p.extra.iter().chain([&p.lookup.table]) {
            let text =
                std::fs::read_to_string(path).map_err(|e| StageError::file(path, e.to_string()))?;
            lines.push(text.lines().count() as i64);
        }
        let table: Table = Counts { lines }.into_table();
        Ok(Outputs::new().table("counts", table))
    }
}
