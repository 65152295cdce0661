//! The table every contact-model stage emits (`icm` today; boundary
//! elements, Persson and Greenwood–Williamson next), declared here once so
//! that one word in a pipeline swaps the model and every reader of the table
//! (the report, the comparison with experiment) reads all of them alike.

use crate::{ParamError, Schema};

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

/// Refuses `map_fractions[i]` when an earlier entry has the same
/// [`area_fraction_label`]: both would write the same file names. Stages
/// call it for each index in order, beside their own checks of the entry.
pub fn check_map_fraction(fractions: &[f64], i: usize) -> Result<(), ParamError> {
    let f = fractions[i];
    match fractions[..i]
        .iter()
        .position(|&g| area_fraction_label(g) == area_fraction_label(f))
    {
        Some(j) => Err(ParamError::new(
            &format!("map_fractions.{i}"),
            format!("{f} gives the same file names as map_fractions.{j}"),
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fraction_with_an_earlier_fractions_file_names_is_refused() {
        let fractions = [0.1, 0.5, 0.1004, 0.9];
        assert!(check_map_fraction(&fractions, 0).is_ok());
        assert!(check_map_fraction(&fractions, 1).is_ok());
        let e = check_map_fraction(&fractions, 2).unwrap_err().to_string();
        assert!(
            e.contains("map_fractions.2") && e.contains("same file names as map_fractions.0"),
            "{e}"
        );
        assert!(check_map_fraction(&fractions, 3).is_ok());
    }
}
