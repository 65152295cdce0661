//! The integration tests of `hypercontact-formats` as one test binary: one link instead of
//! 10, which keeps the cold build of the tests within budget (#35). Each module
//! is one file of this folder; run one with
//! `cargo test --workspace --release --test integration -- MODULE::`.

mod afm;
mod common;
mod datx;
mod metropro;
mod opd;
mod optical;
mod plu;
mod sur;
mod text;
mod x3p;
mod x3p_write;
