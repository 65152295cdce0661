//! The integration tests of `hypercontact-compare` as one test binary: one link instead of
//! 3, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod common;
mod fuzz_inputs;
mod register;
mod synthetic_lab;
