//! The stage interface: what a stage declares and what it computes.

use crate::{Checked, Context, DType, Inputs, Outputs, Params, ProductKind, Schema, StageError};

/// One column of a table schema.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ColumnSpec {
    pub name: &'static str,
    pub dtype: DType,
    pub unit: &'static str,
    pub doc: &'static str,
}

impl ColumnSpec {
    pub const fn f64(name: &'static str, unit: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            dtype: DType::F64,
            unit,
            doc,
        }
    }

    pub const fn i64(name: &'static str, unit: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            dtype: DType::I64,
            unit,
            doc,
        }
    }

    pub const fn str(name: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            dtype: DType::Str,
            unit: "",
            doc,
        }
    }
}

/// How many upstream products an input takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Arity {
    /// Exactly one: `inputs: { surface: surf }`.
    One,
    /// Zero or one.
    Optional,
    /// Any number, labelled: `inputs: { responses: { T1: icm1, T2: icm2 } }`;
    /// the stage sees them as `responses.T1`, `responses.T2`.
    Many,
    /// At least one: a single product (`tensile: csv`) or labelled ones as
    /// for [`Arity::Many`]; the plan refuses none.
    OneOrMore,
    /// Any number, labelled twice, by sample and then by model:
    /// `inputs: { responses: { T1: { icm: a, bem: b } } }`; the stage sees
    /// them as `responses.T1.icm`, `responses.T1.bem` ([`crate::Inputs::nested`]).
    /// How a consumer of a role (the report) takes every producer of it.
    Nested,
}

impl Arity {
    /// How many labels a product of this input carries: none, one (sample
    /// or model) or two (sample, then model); `None` where both none and one
    /// are accepted ([`Arity::OneOrMore`]).
    pub fn depth(self) -> Option<usize> {
        match self {
            Arity::One | Arity::Optional => Some(0),
            Arity::Many => Some(1),
            Arity::OneOrMore => None,
            Arity::Nested => Some(2),
        }
    }
}

/// A declared input.
#[derive(Clone, Copy, Debug)]
pub struct InputSpec {
    pub name: &'static str,
    pub kind: ProductKind,
    pub arity: Arity,
    /// Required columns when `kind` is a table (others are allowed).
    pub columns: &'static [ColumnSpec],
    pub doc: &'static str,
}

impl InputSpec {
    /// A table input whose required columns are those of schema `S`.
    pub const fn table<S: Schema>(name: &'static str, arity: Arity, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Table,
            arity,
            columns: S::COLUMNS,
            doc,
        }
    }

    /// A field input (a height map).
    pub const fn field(name: &'static str, arity: Arity, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Field,
            arity,
            columns: &[],
            doc,
        }
    }

    /// A files input (an image sequence, a folder's worth of files).
    pub const fn files(name: &'static str, arity: Arity, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Files,
            arity,
            columns: &[],
            doc,
        }
    }

    /// A files input whose producer must hand on an index with (at least)
    /// the columns of schema `S`: which file holds what. The plan refuses
    /// wiring from an output without such an index.
    pub const fn files_indexed<S: Schema>(
        name: &'static str,
        arity: Arity,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            kind: ProductKind::Files,
            arity,
            columns: S::COLUMNS,
            doc,
        }
    }
}

/// A declared output.
#[derive(Clone, Copy, Debug)]
pub struct OutputSpec {
    pub name: &'static str,
    pub kind: ProductKind,
    /// The columns a table output always has, in order; for files, those
    /// of their index (none: the files come without one).
    pub columns: &'static [ColumnSpec],
    pub doc: &'static str,
}

impl OutputSpec {
    /// A table output with the columns of schema `S`.
    pub const fn table<S: Schema>(name: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Table,
            columns: S::COLUMNS,
            doc,
        }
    }

    pub const fn field(name: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Field,
            columns: &[],
            doc,
        }
    }

    pub const fn files(name: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Files,
            columns: &[],
            doc,
        }
    }

    /// Files with an index of schema `S` ([`crate::Files::with_index`]),
    /// stored and exported beside them as the table `<name>.parquet`.
    pub const fn files_indexed<S: Schema>(name: &'static str, doc: &'static str) -> Self {
        Self {
            name,
            kind: ProductKind::Files,
            columns: S::COLUMNS,
            doc,
        }
    }
}

/// Everything the runner and `hypercontact stages` need to know about a kind.
#[derive(Clone, Copy, Debug)]
pub struct StageInfo {
    /// The name used after `uses:` in a pipeline.
    pub kind: &'static str,
    /// Bumped whenever the implementation's results may change; it is part of
    /// the cache key, so a new version reruns the stage and its dependents.
    pub version: u32,
    pub summary: &'static str,
    /// Conventions and references, shown by `hypercontact stages KIND`.
    pub doc: &'static str,
    pub inputs: &'static [InputSpec],
    pub outputs: &'static [OutputSpec],
}

impl StageInfo {
    pub fn output(&self, name: &str) -> Option<&'static OutputSpec> {
        self.outputs.iter().find(|o| o.name == name)
    }

    pub fn input(&self, name: &str) -> Option<&'static InputSpec> {
        self.inputs.iter().find(|i| i.name == name)
    }
}

/// What one computation of a stage kind asks of a cluster node: the
/// defaults of a Slurm job (`--cpus-per-task`, `--mem`, `--time`) when the
/// pipeline runs with `--executor slurm`. A pipeline's `slurm:` keys
/// override them; they never change a result, so they are not part of any
/// cache key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resources {
    pub cpus: u32,
    pub mem_mb: u64,
    pub time_min: u64,
}

impl Resources {
    /// A light stage: one core, 2 GiB, 30 minutes.
    pub const LIGHT: Resources = Resources {
        cpus: 1,
        mem_mb: 2048,
        time_min: 30,
    };

    /// A stage whose work is parallel (rayon) over maps or replicates.
    pub const PARALLEL: Resources = Resources {
        cpus: 4,
        mem_mb: 8192,
        time_min: 120,
    };
}

impl Default for Resources {
    fn default() -> Self {
        Self::LIGHT
    }
}

/// A pipeline stage: a pure function of its parameters and inputs.
///
/// Its parameters are declared by its `Params` type (see
/// [`macro@crate::params`]); `run` receives them only after their checks
/// passed, so a stage never sees a value outside its declared range (a call
/// with unchecked parameters does not compile: `tests/compile_fail/`). The
/// check is where `poisson: 7.0` is refused:
///
/// ```
/// # use hypercontact_core::{Checked, Context, Inputs, Outputs, Params, Stage, StageError, StageInfo};
/// # #[hypercontact_core::params]
/// # struct P { #[param(default = 0.5, range = 0.0..=0.5)] poisson: f64 }
/// # struct S;
/// # static INFO: StageInfo = StageInfo { kind: "s", version: 1, summary: "", doc: "", inputs: &[], outputs: &[] };
/// # impl Stage for S {
/// #     type Params = P;
/// #     fn info(&self) -> &'static StageInfo { &INFO }
/// #     fn run(&self, _: &Checked<P>, _: &Inputs, _: &Context) -> Result<Outputs, StageError> { Ok(Outputs::new()) }
/// # }
/// assert!(P { poisson: 7.0 }.check().is_err());
/// let checked = P { poisson: 0.3 }.check().unwrap();
/// S.run(&checked, &Inputs::new(), &Context::new("s")).unwrap();
/// ```
pub trait Stage: Send + Sync + 'static {
    type Params: Params;

    fn info(&self) -> &'static StageInfo;

    /// What a cluster job of this kind asks for by default: a kind whose
    /// work is parallel says `const RESOURCES: Resources = Resources::PARALLEL;`.
    const RESOURCES: Resources = Resources::LIGHT;

    fn run(
        &self,
        params: &Checked<Self::Params>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError>;

    /// Drops what this kind keeps on the calling thread for the next stage
    /// of its kind (a solved curve a second `bem` replays). The runner
    /// calls it on the thread that ran the stage when the next stage in the
    /// plan is of another kind, so nothing is held through the stages
    /// between (#48). Keeps nothing by default.
    fn let_go(&self) {}
}
