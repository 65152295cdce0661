//! The stage interface of hypercontact and the types stages exchange.
//!
//! A stage is a pure computation: typed, validated parameters and named input
//! products in, named output products out. Everything around it (reading the
//! pipeline, caching, timing, progress, file formats) belongs to the runner.
//! Stage crates depend on this crate only, so they build and test in seconds.

pub mod context;
pub mod csv_table;
pub mod error;
pub mod field;
pub mod params;
pub mod product;
pub mod registry;
pub mod stage;
pub mod table;

pub use context::{Context, ProductReader, Progress};
pub use error::StageError;
pub use field::Field;
pub use params::{ParamError, Params};
pub use product::{Files, Inputs, Outputs, Product, ProductKind};
pub use registry::{AnyParams, DynStage, Registry};
pub use stage::{Arity, ColumnSpec, InputSpec, OutputSpec, ParamDoc, Stage, StageInfo};
pub use table::{ColumnData, DType, Table, TableError};
