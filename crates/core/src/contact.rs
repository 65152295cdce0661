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

/// The `bands` table: how far a response moves over a material's bootstrap
/// replicates (`material-fit`'s `replicates`), one row per row of the
/// response. Percentiles are taken over the replicates that reached the row
/// (linear between order statistics, Hyndman & Fan's type 7, numpy's
/// default). `load_norm` is every replicate's load over the *main* fit's
/// E0* A0, so the band lies on the response's axes and carries the
/// modulus's own uncertainty; `tangent_ratio` is each replicate's E_t*
/// over its own E0*: how much the material stiffens, whatever its modulus.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct BandTable {
    /// A / A0 of the response row
    pub area_fraction: Vec<f64>,
    /// 5th percentile of F / (E0* A0)
    pub load_norm_p05: Vec<f64>,
    /// median of F / (E0* A0)
    pub load_norm_p50: Vec<f64>,
    /// 95th percentile of F / (E0* A0)
    pub load_norm_p95: Vec<f64>,
    /// 5th percentile of E_t* / E0*
    pub tangent_ratio_p05: Vec<f64>,
    /// median of E_t* / E0*
    pub tangent_ratio_p50: Vec<f64>,
    /// 95th percentile of E_t* / E0*
    pub tangent_ratio_p95: Vec<f64>,
    /// replicates that reached this row
    pub replicates: Vec<i64>,
}

/// The q-quantile (0 ≤ q ≤ 1) of `values`, linear between order
/// statistics (Hyndman & Fan 1996, type 7; numpy's default). NaN for no
/// values; NaN values are left out.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let (lo, frac) = (h.floor() as usize, h - h.floor());
    match v.get(lo + 1) {
        Some(next) if frac > 0.0 => v[lo] + frac * (next - v[lo]),
        _ => v[lo],
    }
}

impl BandTable {
    /// Bands from per-replicate curves on the response's rows: `load_norm[r]`
    /// and `tangent_ratio[r]` are replicate r's values, as long as the rows
    /// it reached (a replicate whose law gave out part-way is shorter).
    pub fn from_replicates(
        area_fraction: &[f64],
        load_norm: &[Vec<f64>],
        tangent_ratio: &[Vec<f64>],
    ) -> Self {
        let column = |curves: &[Vec<f64>], row: usize| -> Vec<f64> {
            curves.iter().filter_map(|c| c.get(row).copied()).collect()
        };
        let mut t = BandTable {
            area_fraction: area_fraction.to_vec(),
            load_norm_p05: Vec::new(),
            load_norm_p50: Vec::new(),
            load_norm_p95: Vec::new(),
            tangent_ratio_p05: Vec::new(),
            tangent_ratio_p50: Vec::new(),
            tangent_ratio_p95: Vec::new(),
            replicates: Vec::new(),
        };
        for row in 0..area_fraction.len() {
            let (load, tangent) = (column(load_norm, row), column(tangent_ratio, row));
            t.load_norm_p05.push(quantile(&load, 0.05));
            t.load_norm_p50.push(quantile(&load, 0.5));
            t.load_norm_p95.push(quantile(&load, 0.95));
            t.tangent_ratio_p05.push(quantile(&tangent, 0.05));
            t.tangent_ratio_p50.push(quantile(&tangent, 0.5));
            t.tangent_ratio_p95.push(quantile(&tangent, 0.95));
            t.replicates.push(load.len() as i64);
        }
        t
    }
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
    fn quantiles_are_numpys_linear_ones() {
        // numpy.percentile([3, 1, 4, 1, 5, 9, 2, 6], [5, 50, 95]) =
        // [1.0, 3.5, 7.95] (type 7).
        let v = [3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0];
        assert_eq!(quantile(&v, 0.05), 1.0);
        assert_eq!(quantile(&v, 0.5), 3.5);
        assert!((quantile(&v, 0.95) - 7.95).abs() < 1e-12);
        assert_eq!(quantile(&[2.0], 0.95), 2.0);
        assert!(quantile(&[], 0.5).is_nan());
        assert_eq!(quantile(&[f64::NAN, 1.0, 3.0], 0.5), 2.0);
    }

    #[test]
    fn bands_count_the_replicates_that_reached_each_row() {
        let t = BandTable::from_replicates(
            &[0.1, 0.2],
            &[vec![1.0, 2.0], vec![3.0]],
            &[vec![2.0, 2.5], vec![2.2]],
        );
        assert_eq!(t.replicates, [2, 1]);
        assert_eq!(t.load_norm_p50, [2.0, 2.0]);
        assert!((t.load_norm_p05[0] - 1.1).abs() < 1e-12);
        assert!((t.tangent_ratio_p95[0] - 2.19).abs() < 1e-12);
    }

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
