//! The stage interface: what a stage declares and what it computes.

use crate::{Context, DType, Inputs, Outputs, Params, ProductKind, StageError};

/// One parameter's documentation; its default comes from `Params::default()`.
#[derive(Clone, Copy, Debug)]
pub struct ParamDoc {
    pub name: &'static str,
    /// SI unit, or "" for dimensionless values, counts and choices.
    pub unit: &'static str,
    pub doc: &'static str,
}

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

/// A declared output.
#[derive(Clone, Copy, Debug)]
pub struct OutputSpec {
    pub name: &'static str,
    pub kind: ProductKind,
    /// The columns a table output always has, in order.
    pub columns: &'static [ColumnSpec],
    pub doc: &'static str,
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
    pub params: &'static [ParamDoc],
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

/// A pipeline stage: a pure function of its parameters and inputs.
pub trait Stage: Send + Sync + 'static {
    type Params: Params;

    fn info(&self) -> &'static StageInfo;

    fn run(
        &self,
        params: &Self::Params,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError>;
}
