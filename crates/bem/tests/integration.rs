//! The integration tests of `hypercontact-bem` as one test binary: one link instead of
//! 5, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod analytic;
mod iterations;
mod material_law;
mod methods;
mod mirrored;
mod stage;
