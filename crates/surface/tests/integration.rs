//! The integration tests of `hypercontact-surface` as one test binary: one link instead of
//! 6, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod common;
mod fuzz_positions;
mod hurst_quality;
mod inputs;
mod level_rows;
mod missing_points;
mod spectra;
mod stitching;
mod tip_cutoff;
