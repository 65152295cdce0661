//! The integration tests of `hypercontact-classical` as one test binary: one link instead of
//! 4, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod gw;
mod material_law;
mod persson;
mod stages;
