//! hypercontact from Python (issue #34): every registered stage as a
//! function, generated from the stage declarations, so a new kind needs no
//! Python code. [`bridge`] is plain Rust (kinds, declarations, a stage run
//! on products with the YAML parameter path) and is what the workspace's
//! tests exercise; the PyO3 module on top of it is compiled only with the
//! `extension-module` feature, which maturin turns on.

pub mod bridge;
pub mod lines;
pub mod runs;
pub mod stubs;

#[cfg(feature = "extension-module")]
mod module;
