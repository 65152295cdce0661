//! The `report` stage of hypercontact: the paper's figures (Figs. 2, 4, 7
//! and 8 as PNG and SVG), its Table 1, the model comparison and a
//! per-sample summary, in one self-contained HTML page plus `summary.json`.
//!
//! - [`gather`]: reads and checks whatever inputs are wired, with the
//!   upstream stages' own table schemas;
//! - [`roster`]: the contact models wired, by label: their order, colours
//!   and laws (no model is known by name);
//! - [`band`]: the bootstrap band of a model's curve;
//! - [`material`]: Table 1's moduli at the report's ν, held to the E0* of
//!   the responses;
//! - [`table1`]: Table 1 as HTML, with the bootstrap intervals and the
//!   fit's constraint;
//! - [`figures`]: one file per figure, shared plotting helpers;
//! - [`surface_stats`]: the surface stage's areal parameters, ACF,
//!   distributions and scale-dependent statistics, and their table;
//! - [`refinement`]: the convergence study of fem against bem over
//!   refine factors, its table and Fig. 11;
//! - [`findings`]: the opening "What this rerun finds", in words and numbers;
//! - [`summary`], [`html`]: the numbers and the page;
//! - [`report`]: decides what can be drawn and assembles the files;
//! - [`stage`]: the `report` stage kind.
//!
//! Library users who hold the run's provenance call
//! [`report::render_report`] with it; the stage passes none yet.

pub mod band;
pub mod error;
pub mod experiment;
pub mod figures;
pub mod findings;
pub mod finite_strain;
pub mod gather;
pub mod html;
pub mod interp;
pub mod material;
pub mod models;
pub mod powerlaw;
pub mod refinement;
pub mod report;
pub mod roster;
pub mod stage;
pub mod summary;
pub mod surface_stats;
pub mod table1;

pub use error::ReportError;
pub use html::provenance_section;
pub use report::{ReportOptions, build_report, render_report};
pub use stage::{Report, ReportParams};

/// Registers this crate's stage kinds.
pub fn register(registry: &mut hypercontact_core::Registry) {
    registry.add(stage::Report);
}

#[cfg(test)]
mod tests {
    #[test]
    fn registers_the_report_kind() {
        let mut registry = hypercontact_core::Registry::new();
        super::register(&mut registry);
        assert_eq!(registry.kinds().collect::<Vec<_>>(), ["report"]);
        let info = registry.get("report").unwrap().info();
        assert_eq!(info.outputs[0].name, "report");
    }
}
