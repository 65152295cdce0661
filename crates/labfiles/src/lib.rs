//! Reading a lab's files: what a loader stage is pointed at, kept out of
//! hypercontact-core so that a stage crate which only computes does not
//! build image, TIFF and CSV decoders.
//!
//! - [`sequence`]: an image sequence with its frame list and force log, the
//!   one layout the tensile test's DIC and the contact experiment read;
//! - [`csv_table`]: CSV tables whose rows keep their file lines, so errors
//!   name them;
//! - [`png`]: the one PNG encoder stages write frames and figures with;
//! - [`source`]: a stage's raw files, from a `Files` product or a folder;
//! - [`LabReader`]: core's `ProductReader` for CSV tables and `.npy` fields,
//!   which the runner's Parquet reader composes.

pub mod csv_table;
pub mod png;
pub mod reader;
pub mod sequence;
pub mod source;

pub use reader::LabReader;
pub use source::FileSource;
