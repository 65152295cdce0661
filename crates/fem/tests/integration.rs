//! The integration tests of `hypercontact-fem` as one test binary: one link instead of
//! 6, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod coarsening;
mod common;
mod degenerate;
mod felupe;
mod homogeneous;
mod newton;
mod rough_patch;
mod stage;
mod tangent;
mod westergaard;
