//! The table every contact-model stage emits (`icm` today; boundary
//! elements, Persson and Greenwood–Williamson next), declared here once so
//! that one word in a pipeline swaps the model and every reader of the table
//! (the report, the comparison with experiment) reads all of them alike.

use crate::Schema;

/// The `response` table: load against contact area, one row per step.
/// Each stage documents what its `z_m` is (for `icm`, the truncation plane).
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ResponseTable {
    /// separation coordinate of the step (the stage says which)
    #[column(unit = "m")]
    pub z_m: Vec<f64>,
    /// A / A0
    pub area_fraction: Vec<f64>,
    /// total contact load F
    #[column(unit = "N")]
    pub load_n: Vec<f64>,
    /// F / (E0* A0)
    pub load_norm: Vec<f64>,
    /// F / A (magnitude; the law is evaluated at S = −F/A)
    #[column(unit = "Pa")]
    pub mean_stress_pa: Vec<f64>,
    /// E_t*(S) / E0*; 1 for a linear model
    pub tangent_ratio: Vec<f64>,
}

/// `a0.100` for A/A0 = 0.1: how a contact model or the experiment names the
/// map it keeps at a requested area fraction (`pressure_a0.100.npy`,
/// `mask_a0.100.png`), so the comparison finds them alike.
pub fn area_fraction_label(fraction: f64) -> String {
    format!("a{fraction:.3}")
}
