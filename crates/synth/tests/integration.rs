//! The integration tests of `hypercontact-synth` as one test binary: one link instead of
//! 2, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod contact;
mod contact_material;
