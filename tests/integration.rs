//! The integration tests of `hypercontact` as one test binary: one link instead of
//! 5, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod cli;
mod common;
mod determinism;
mod export;
mod graph;
mod layout;
mod line_scans;
mod new_model;
mod version_guard;
