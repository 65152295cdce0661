//! What every contact model shares, declared once: the `response` table
//! each emits (icm, bem, persson, greenwood-williamson; a model's own
//! columns follow by `#[column(flatten)]`), the function that derives its
//! normalised columns, the bootstrap `bands`, and the indexes of the contact
//! maps handed to the comparison with experiment. One word in a pipeline
//! swaps the model, and every reader of these (the report, the comparison)
//! reads all of them alike.

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

impl ResponseTable {
    /// The response from a model's curve: the load `load_n` (N) at contact
    /// area `area_m2` (m²; A/A0 `area_fraction`) and separation `z_m`, with
    /// the tangent modulus `modulus_pa` (Pa) each row was integrated with
    /// (E0* for a linear model), normalised by E0* `e0_star_pa` and the
    /// nominal area `a0_m2`. The one place the derived columns are formed:
    /// load_norm = F/(E0* A0), mean_stress_pa = F/A (0 without contact),
    /// tangent_ratio = E_t*/E0*.
    pub fn from_curve(curve: Curve, e0_star_pa: f64, a0_m2: f64) -> Self {
        let Curve {
            z_m,
            area_fraction,
            area_m2,
            load_n,
            modulus_pa,
        } = curve;
        ResponseTable {
            load_norm: load_n.iter().map(|f| f / (e0_star_pa * a0_m2)).collect(),
            mean_stress_pa: load_n
                .iter()
                .zip(&area_m2)
                .map(|(f, a)| if *a > 0.0 { f / a } else { 0.0 })
                .collect(),
            tangent_ratio: modulus_pa.iter().map(|e| e / e0_star_pa).collect(),
            z_m,
            area_fraction,
            load_n,
        }
    }

    /// κ = (A/A0) / (p̄/(E0* h'rms)) per row, p̄ = F/A0, from the table's own
    /// columns (= A/A0 · h'rms / load_norm): the dimensionless slope of the
    /// area against the load that the theories predict (√(8/π) for
    /// Persson's, about 2 for boundary elements at small load). NaN where
    /// there is no load.
    pub fn kappa(&self, rms_slope: f64) -> Vec<f64> {
        self.area_fraction
            .iter()
            .zip(&self.load_norm)
            .map(|(a, l)| {
                if *l > 0.0 {
                    a * rms_slope / l
                } else {
                    f64::NAN
                }
            })
            .collect()
    }
}

/// A contact model's curve before normalisation: what
/// [`ResponseTable::from_curve`] is given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Curve {
    pub z_m: Vec<f64>,
    pub area_fraction: Vec<f64>,
    /// True contact area A, m².
    pub area_m2: Vec<f64>,
    /// Load F, N.
    pub load_n: Vec<f64>,
    /// The tangent modulus E_t* of each row (E0* for a linear law), Pa.
    pub modulus_pa: Vec<f64>,
}

/// The index of a contact model's `contact_maps`: one row per kept map,
/// the model's contact pressure on the height map's grid. The comparison
/// reads any model's maps through it (contact where the pressure is
/// positive).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ModelMapIndex {
    /// the A/A0 asked for (the stage's map_fractions)
    pub requested_area_fraction: Vec<f64>,
    /// A/A0 of the step kept (the nearest)
    pub area_fraction: Vec<f64>,
    /// load of that step
    #[column(unit = "N")]
    pub load_n: Vec<f64>,
    /// the pressure map (.npy, Pa, axis 0 = x as in the height map; NaN where not measured)
    pub pressure_file: Vec<String>,
    /// its spacing along x
    #[column(unit = "m")]
    pub dx_m: Vec<f64>,
    /// its spacing along y
    #[column(unit = "m")]
    pub dy_m: Vec<f64>,
}

/// The index of observed contact maps on a camera's pixels (the contact
/// experiment's, or the synthetic lab's true contact): one row per kept
/// frame.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ObservedMapIndex {
    /// the A/A0 asked for (the stage's map_fractions)
    pub requested_area_fraction: Vec<f64>,
    /// A/A0 of the frame kept (the nearest)
    pub area_fraction: Vec<f64>,
    /// the frame's number
    pub frame: Vec<i64>,
    /// the mask (8-bit PNG: 255 = contact, 0 = none)
    pub file: Vec<String>,
    /// the camera pixel on the sample
    #[column(unit = "m")]
    pub pixel_m: Vec<f64>,
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

/// Refuses a `map_fractions` entry above the curve's `max_area_fraction`
/// (no step would reach it) or with the file names of an earlier one: the
/// check of every contact model that keeps maps along its curve.
pub fn check_maps_within_curve(
    map_fractions: &[f64],
    max_area_fraction: f64,
) -> Result<(), ParamError> {
    for (i, &f) in map_fractions.iter().enumerate() {
        if f > max_area_fraction {
            return Err(ParamError::new(
                &format!("map_fractions.{i}"),
                format!("{f} lies above max_area_fraction ({max_area_fraction})"),
            ));
        }
        check_map_fraction(map_fractions, i)?;
    }
    Ok(())
}

/// The `.npy` bytes (with its grid) of a model map given row-major on the
/// height map's `nx × ny` grid of spacing `dx_m × dy_m` (axis 0 = x).
pub fn map_npy(
    values: Vec<f64>,
    (nx, ny): (usize, usize),
    dx_m: f64,
    dy_m: f64,
) -> Result<Vec<u8>, crate::StageError> {
    let array =
        ndarray::Array2::from_shape_vec((nx, ny), values).map_err(crate::StageError::other)?;
    let mut bytes = Vec::new();
    crate::Field::new(array, dx_m, dy_m)
        .and_then(|f| f.write_npy(&mut bytes))
        .map_err(crate::StageError::other)?;
    Ok(bytes)
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
