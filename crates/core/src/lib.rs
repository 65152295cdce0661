//! The stage interface of hypercontact and the types stages exchange.
//!
//! A stage is a pure computation: checked parameters and named input products
//! in, named output products out. Everything around it (reading the pipeline,
//! caching, timing, progress, file formats) belongs to the runner. A stage
//! crate depends on this crate, on hypercontact-numeric or -labfiles where it
//! computes transforms or reads a lab's files, and on the stage crates whose
//! tables or physics it reuses; never on the runner or the Parquet edge
//! (hypercontact-io), so it builds and tests without polars.
//!
//! A stage declares each fact once: its parameters with [`macro@params`]
//! (type, default, unit, doc, range), its choices with [`Choice`], its tables
//! with [`Schema`]; the checks, the `hypercontact stages` text, the serde
//! shape and the cache key's file hashes all follow from those declarations.
//!
//! Architecture invariant: core reads no lab files and draws nothing. Every
//! stage crate builds core, so whatever core depends on, every stage crate
//! builds. Image and TIFF decoding, the CSV parser and file-name sorting live
//! in hypercontact-labfiles, which only the crates that read a lab's files
//! depend on; terminal progress bars (indicatif) live in hypercontact-runner,
//! behind [`ProgressSink`]. What stays is what the stage interface itself
//! needs: tables, fields and their `.npy` format, parameters, errors.
//! `tests/lean.rs` fails if image, tiff, csv, alphanumeric-sort or
//! indicatif reappear in core's dependency tree.

// The derives name this crate `::hypercontact_core`, also inside it.
extern crate self as hypercontact_core;

pub mod const_concat;
pub mod contact;
pub mod context;
pub mod error;
pub mod field;
pub mod mode;
pub mod param;
pub mod product;
pub mod progress;
pub mod registry;
pub mod regular_file;
pub mod robust;
pub mod row_lines;
pub mod schema;
pub mod shown;
pub mod stage;
pub mod table;

pub use context::{Context, FieldReader, ProductReader};
pub use error::StageError;
pub use field::Field;
pub use hypercontact_derive::{Choice, Schema, params};
pub use mode::Mode;
pub use param::{Checked, InputPath, ParamError, ParamSpec, ParamValue, Params, check_range, join};
pub use product::{Files, Inputs, Outputs, Product, ProductKind};
pub use progress::{Progress, ProgressSink};
pub use registry::{AnyParams, DynStage, ParamsError, Registry};
pub use row_lines::{RowLines, RowPlace};
pub use schema::Schema;
pub use stage::{Arity, ColumnSpec, InputSpec, OutputSpec, Resources, Stage, StageInfo};
pub use table::{ColumnData, DType, NotANumber, Table, TableError};

/// What the derives' generated code names; not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use serde;
    pub use serde_json;
}
