//! The 5–95 % bootstrap band of a contact model's curve on one sample
//! (e.g. icm's `bands` output): how far the tensile tests' scatter and the fit's
//! freedom move F/(E0* A0) and E_t*/E0* at each contact area fraction.
//! Drawn under the curves of Figs. 7 and 8 and read at the summary's area
//! fractions.

use hypercontact_core::contact::BandTable;

use crate::ReportError;
use crate::interp::interpolate;

/// A band sorted by A/A0. A percentile is NaN on a row no replicate
/// reached (its law gave out earlier), and such rows are not drawn.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Band {
    /// A/A0, ascending.
    pub area_fraction: Vec<f64>,
    /// 5th and 95th percentiles of F/(E0* A0), on the axes of the main
    /// fit's response (its E0* A0).
    pub load_norm_p05: Vec<f64>,
    pub load_norm_p95: Vec<f64>,
    /// 5th and 95th percentiles of E_t*/E0*, each replicate over its own E0*.
    pub tangent_ratio_p05: Vec<f64>,
    pub tangent_ratio_p95: Vec<f64>,
}

impl Band {
    /// Reads input `input`'s table; `None` for a table without rows (the
    /// ICM had no replicates wired). A non-finite area fraction, or a 5th
    /// percentile above the 95th, is an error naming column and row.
    pub fn read(input: &str, table: BandTable) -> Result<Option<Self>, ReportError> {
        if table.area_fraction.is_empty() {
            return Ok(None);
        }
        if let Some(row) = table.area_fraction.iter().position(|a| !a.is_finite()) {
            return Err(ReportError::input(
                input,
                format!(
                    "column `area_fraction` row {row} is {}",
                    table.area_fraction[row]
                ),
            ));
        }
        for (name, low, high) in [
            ("load_norm", &table.load_norm_p05, &table.load_norm_p95),
            (
                "tangent_ratio",
                &table.tangent_ratio_p05,
                &table.tangent_ratio_p95,
            ),
        ] {
            if let Some(row) = (0..low.len()).find(|&i| low[i] > high[i]) {
                return Err(ReportError::input(
                    input,
                    format!(
                        "row {row}: `{name}_p05` = {} is above `{name}_p95` = {}",
                        low[row], high[row]
                    ),
                ));
            }
        }
        let mut order: Vec<usize> = (0..table.area_fraction.len()).collect();
        order.sort_by(|&a, &b| table.area_fraction[a].total_cmp(&table.area_fraction[b]));
        let pick = |v: &[f64]| order.iter().map(|&i| v[i]).collect::<Vec<_>>();
        Ok(Some(Band {
            area_fraction: pick(&table.area_fraction),
            load_norm_p05: pick(&table.load_norm_p05),
            load_norm_p95: pick(&table.load_norm_p95),
            tangent_ratio_p05: pick(&table.tangent_ratio_p05),
            tangent_ratio_p95: pick(&table.tangent_ratio_p95),
        }))
    }

    /// (p05, p95) of F/(E0* A0) at area fraction `a`, each linearly
    /// interpolated in A/A0 as the summary reads the curves; `None` outside
    /// the band or next to a row no replicate reached.
    pub fn load_norm_at(&self, a: f64) -> (Option<f64>, Option<f64>) {
        let at = |v: &[f64]| interpolate(&self.area_fraction, v, a).filter(|v| v.is_finite());
        (at(&self.load_norm_p05), at(&self.load_norm_p95))
    }
}

/// One stretch of a band without gaps, in chart coordinates: its lower and
/// upper edges over the same abscissae, at least two points each.
#[derive(Clone, Debug, PartialEq)]
pub struct BandRun {
    pub lower: Vec<(f64, f64)>,
    pub upper: Vec<(f64, f64)>,
}

/// The drawable runs of a band between `lower` and `upper` over `x`, split
/// wherever `y` cannot map an edge (NaN, or ≤ 0 on a log axis) so that no
/// shading bridges a gap.
pub fn runs(
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
    y: impl Fn(f64) -> Option<f64>,
) -> Vec<BandRun> {
    let mut out = Vec::new();
    let (mut low, mut high) = (Vec::new(), Vec::new());
    let n = x.len().min(lower.len()).min(upper.len());
    for i in 0..=n {
        let point = (i < n)
            .then(|| Some((y(lower[i])?, y(upper[i])?)))
            .flatten();
        match point {
            Some((l, h)) => {
                low.push((x[i], l));
                high.push((x[i], h));
            }
            None => {
                if low.len() >= 2 {
                    out.push(BandRun {
                        lower: std::mem::take(&mut low),
                        upper: std::mem::take(&mut high),
                    });
                } else {
                    low.clear();
                    high.clear();
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(a: Vec<f64>, p05: Vec<f64>, p95: Vec<f64>) -> BandTable {
        let n = a.len();
        BandTable {
            area_fraction: a,
            load_norm_p50: p05.iter().zip(&p95).map(|(l, h)| 0.5 * (l + h)).collect(),
            load_norm_p05: p05,
            load_norm_p95: p95,
            tangent_ratio_p05: vec![2.0; n],
            tangent_ratio_p50: vec![2.5; n],
            tangent_ratio_p95: vec![3.0; n],
            replicates: vec![100; n],
        }
    }

    #[test]
    fn a_band_is_sorted_and_read_by_linear_interpolation() {
        let band = Band::read(
            "bands.T1",
            table(
                vec![0.5, 0.0, 1.0],
                vec![2.0, 0.0, 4.0],
                vec![3.0, 0.0, 8.0],
            ),
        )
        .unwrap()
        .unwrap();
        assert_eq!(band.area_fraction, [0.0, 0.5, 1.0]);
        assert_eq!(band.load_norm_p95, [0.0, 3.0, 8.0]);
        // Halfway between rows 0.5 and 1.0: (2 + 4)/2 and (3 + 8)/2.
        assert_eq!(band.load_norm_at(0.75), (Some(3.0), Some(5.5)));
        assert_eq!(band.load_norm_at(0.25), (Some(1.0), Some(1.5)));
        assert_eq!(band.load_norm_at(1.5), (None, None));
    }

    #[test]
    fn rows_no_replicate_reached_read_as_none() {
        let nan = f64::NAN;
        let band = Band::read(
            "bands.T1",
            table(
                vec![0.1, 0.2, 0.3],
                vec![1.0, 2.0, nan],
                vec![1.5, 2.5, nan],
            ),
        )
        .unwrap()
        .unwrap();
        assert_eq!(band.load_norm_at(0.15), (Some(1.5), Some(2.0)));
        assert_eq!(band.load_norm_at(0.25), (None, None));
    }

    #[test]
    fn an_empty_table_is_no_band_and_bad_rows_are_named() {
        assert_eq!(
            Band::read("bands.T1", table(vec![], vec![], vec![])).unwrap(),
            None
        );
        let e = Band::read(
            "bands.T2",
            table(vec![0.1, 0.2], vec![1.0, 3.0], vec![2.0, 2.5]),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("bands.T2") && e.contains("row 1") && e.contains("load_norm_p05"),
            "{e}"
        );
        let e = Band::read(
            "bands.T2",
            table(vec![0.1, f64::INFINITY], vec![1.0, 1.0], vec![2.0, 2.0]),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("area_fraction") && e.contains("row 1"), "{e}");
    }

    #[test]
    fn runs_split_where_an_edge_cannot_be_drawn() {
        let positive = |v: f64| (v > 0.0).then(|| v.log10());
        let x = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6];
        let lower = [0.0, 1.0, 10.0, f64::NAN, 1.0, 1.0, 1.0];
        let upper = [1.0, 10.0, 100.0, 1.0, 10.0, -1.0, 10.0];
        let r = runs(&x, &lower, &upper, positive);
        // Rows 1–2 only: row 0's lower edge is 0, row 3 NaN, row 4 alone
        // between two gaps, row 5's upper edge negative, row 6 alone.
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].lower, [(0.1, 0.0), (0.2, 1.0)]);
        assert_eq!(r[0].upper, [(0.1, 1.0), (0.2, 2.0)]);
    }
}
