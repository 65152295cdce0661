//! The stage interface of hypercontact and the types stages exchange.
//!
//! A stage is a pure computation: checked parameters and named input products
//! in, named output products out. Everything around it (reading the pipeline,
//! caching, timing, progress, file formats) belongs to the runner. Stage
//! crates depend on this crate only, so they build and test in seconds.
//!
//! A stage declares each fact once: its parameters with [`macro@params`]
//! (type, default, unit, doc, range), its choices with [`Choice`], its tables
//! with [`Schema`]; the checks, the `hypercontact stages` text, the serde
//! shape and the cache key's file hashes all follow from those declarations.

// The derives name this crate `::hypercontact_core`, also inside it.
extern crate self as hypercontact_core;

pub mod contact;
pub mod context;
pub mod csv_table;
pub mod error;
pub mod field;
pub mod mode;
pub mod param;
pub mod png;
pub mod product;
pub mod registry;
pub mod robust;
pub mod schema;
pub mod sequence;
pub mod source;
pub mod stage;
pub mod table;

pub use context::{Context, ProductReader, Progress};
pub use error::StageError;
pub use field::Field;
pub use hypercontact_derive::{Choice, Schema, params};
pub use mode::Mode;
pub use param::{Checked, InputPath, ParamError, ParamSpec, ParamValue, Params, check_range, join};
pub use product::{Files, Inputs, Outputs, Product, ProductKind};
pub use registry::{AnyParams, DynStage, ParamsError, Registry};
pub use schema::Schema;
pub use source::FileSource;
pub use stage::{Arity, ColumnSpec, InputSpec, OutputSpec, Resources, Stage, StageInfo};
pub use table::{ColumnData, DType, NotANumber, Table, TableError};

/// What the derives' generated code names; not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use serde;
    pub use serde_json;
}
