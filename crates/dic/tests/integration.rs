//! The integration tests of `hypercontact-dic` as one test binary: one link instead of
//! 7, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod common;
mod errors;
mod fuzz_sequence;
mod homogeneous;
mod markers;
mod real_sets;
mod sequence_timing;
mod translation;
