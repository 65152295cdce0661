//! The integration tests of `hypercontact-report` as one test binary: one link instead of
//! 3, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod bands;
mod common;
mod icm_normalisation;
mod render;
mod surface_statistics;
