//! Reads whatever upstream products are wired into typed, checked series.
//!
//! Every input is optional here; which figures and tables can be drawn is
//! decided from what is present (see `plan.rs`). A table that is wired but
//! malformed (missing column, NaN in a plotted column) is an error that names
//! the input, the column and the row: a report silently missing a curve would
//! look like a result.

use std::collections::BTreeMap;

use hypercontact_core::{Field, Inputs, Product, Table};

use crate::ReportError;

/// One tensile mode's measured and fitted nominal stress (Fig. 2).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeCurve {
    /// `UT`, `PT` or `BT`, as in the `curves` table.
    pub mode: String,
    /// Stretch λ, ascending.
    pub stretch: Vec<f64>,
    pub measured_pa: Vec<f64>,
    pub fitted_pa: Vec<f64>,
}

/// The Drucker-stable stretch range of the fitted model in one mode.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityRange {
    pub mode: String,
    pub lambda_min: f64,
    pub lambda_max: f64,
}

/// A 1-D series sorted by its abscissa.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// The surface statistics row of one sample (non-finite = not available).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceStats {
    pub sigma_m: f64,
    pub rms_slope: f64,
    pub hurst_x: f64,
    pub hurst_y: f64,
    pub hurst_radial: f64,
}

/// An ICM response: the area fraction and the two normalised quantities.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Response {
    /// A/A0, ascending.
    pub area_fraction: Vec<f64>,
    /// F/(E0* A0).
    pub load_norm: Vec<f64>,
    /// E_t*/E0*.
    pub tangent_ratio: Vec<f64>,
}

/// Everything the report knows about one sample.
#[derive(Clone, Debug, Default)]
pub struct Sample<'a> {
    pub label: String,
    pub height: Option<&'a Field>,
    /// C(q) along x and y (q in 1/m, C in m³), q > 0 and C > 0 only.
    pub psd_x: Option<Series>,
    pub psd_y: Option<Series>,
    pub stats: Option<SurfaceStats>,
    /// A/A0 against z/σ.
    pub profile: Option<Series>,
    pub response: Option<Response>,
    pub response_linear: Option<Response>,
}

/// The fitted material as the `material` table holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSummary {
    pub model: String,
    /// (parameter name, value in SI) in table order.
    pub parameters: Vec<(String, f64)>,
    pub mu0_pa: f64,
    pub e0_pa: f64,
    /// E0* = E0 / (1 − ν²), ν = ½ (incompressible).
    pub e0_star_pa: f64,
}

/// The wired inputs, read and checked.
#[derive(Clone, Debug, Default)]
pub struct ReportData<'a> {
    pub curves: Option<Vec<ModeCurve>>,
    pub quality: Option<&'a Table>,
    /// R² per mode label, from `quality`.
    pub r2_by_mode: BTreeMap<String, f64>,
    pub params: Option<&'a Table>,
    pub stability: Option<Vec<StabilityRange>>,
    pub comparison: Option<&'a Table>,
    pub material: Option<MaterialSummary>,
    /// Samples in label order (T1, T2, ...), each with what is wired for it.
    pub samples: Vec<Sample<'a>>,
}

/// The input names of the per-sample many-inputs.
pub const SAMPLE_INPUTS: [&str; 6] = [
    "heights",
    "psd",
    "stats",
    "profiles",
    "responses",
    "responses_linear",
];

impl<'a> ReportData<'a> {
    /// Reads every wired input; absent inputs stay `None`.
    pub fn gather(inputs: &'a Inputs) -> Result<Self, ReportError> {
        let mut data = ReportData {
            curves: optional_table(inputs, "curves")?
                .map(read_curves)
                .transpose()?,
            quality: optional_table(inputs, "quality")?,
            params: optional_table(inputs, "params")?,
            stability: optional_table(inputs, "stability")?
                .map(read_stability)
                .transpose()?,
            comparison: optional_table(inputs, "comparison")?,
            material: optional_table(inputs, "material")?
                .map(read_material)
                .transpose()?,
            ..Default::default()
        };
        if let Some(q) = data.quality {
            let modes = q
                .str("mode")
                .map_err(|e| ReportError::table("quality", e))?;
            let r2 = q
                .to_f64("r2")
                .map_err(|e| ReportError::table("quality", e))?;
            data.r2_by_mode = modes.iter().cloned().zip(r2).collect();
        }
        data.samples = read_samples(inputs)?;
        Ok(data)
    }
}

fn optional_table<'a>(inputs: &'a Inputs, name: &str) -> Result<Option<&'a Table>, ReportError> {
    match inputs.get(name) {
        None => Ok(None),
        Some(Product::Table(t)) => Ok(Some(t)),
        Some(other) => Err(ReportError::input(
            name,
            format!("is a {}, expected a table", other.kind()),
        )),
    }
}

/// A numeric column whose every value must be finite.
pub fn finite_column(input: &str, table: &Table, column: &str) -> Result<Vec<f64>, ReportError> {
    let values = table
        .to_f64(column)
        .map_err(|e| ReportError::table(input, e))?;
    if let Some(row) = values.iter().position(|v| !v.is_finite()) {
        return Err(ReportError::input(
            input,
            format!("column `{column}` row {row} is {}", values[row]),
        ));
    }
    Ok(values)
}

/// Sorts parallel columns by the first one (stable, so ties keep row order).
fn sort_by_first(mut columns: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let mut order: Vec<usize> = (0..columns[0].len()).collect();
    order.sort_by(|&a, &b| columns[0][a].total_cmp(&columns[0][b]));
    for c in &mut columns {
        *c = order.iter().map(|&i| c[i]).collect();
    }
    columns
}

fn read_curves(table: &Table) -> Result<Vec<ModeCurve>, ReportError> {
    let input = "curves";
    let modes = table
        .str("mode")
        .map_err(|e| ReportError::table(input, e))?;
    let stretch = finite_column(input, table, "stretch")?;
    let measured = finite_column(input, table, "measured_pa")?;
    let fitted = finite_column(input, table, "fitted_pa")?;
    let mut labels: Vec<&String> = Vec::new();
    for m in modes {
        if !labels.contains(&m) {
            labels.push(m);
        }
    }
    // Paper order UT, PT, BT first, anything else after.
    labels.sort_by_key(|m| ["UT", "PT", "BT"].iter().position(|k| k == m).unwrap_or(3));
    Ok(labels
        .into_iter()
        .map(|label| {
            let rows: Vec<usize> = (0..modes.len()).filter(|&i| &modes[i] == label).collect();
            let pick = |v: &[f64]| rows.iter().map(|&i| v[i]).collect::<Vec<_>>();
            let sorted = sort_by_first(vec![pick(&stretch), pick(&measured), pick(&fitted)]);
            let [s, m, f]: [Vec<f64>; 3] = sorted.try_into().expect("three columns in, three out");
            ModeCurve {
                mode: label.clone(),
                stretch: s,
                measured_pa: m,
                fitted_pa: f,
            }
        })
        .collect())
}

fn read_stability(table: &Table) -> Result<Vec<StabilityRange>, ReportError> {
    let input = "stability";
    let modes = table
        .str("mode")
        .map_err(|e| ReportError::table(input, e))?;
    // Unbounded limits may be stored as ±inf; NaN is not meaningful.
    let lo = table
        .to_f64("lambda_min")
        .map_err(|e| ReportError::table(input, e))?;
    let hi = table
        .to_f64("lambda_max")
        .map_err(|e| ReportError::table(input, e))?;
    if let Some(row) = lo.iter().chain(&hi).position(|v| v.is_nan()) {
        return Err(ReportError::input(
            input,
            format!("row {} holds a NaN limit", row % lo.len().max(1)),
        ));
    }
    Ok(modes
        .iter()
        .zip(lo.iter().zip(&hi))
        .map(|(m, (&l, &h))| StabilityRange {
            mode: m.clone(),
            lambda_min: l,
            lambda_max: h,
        })
        .collect())
}

fn read_material(table: &Table) -> Result<MaterialSummary, ReportError> {
    let model = hypercontact_material::table::from_table(table)
        .map_err(|e| ReportError::Material(e.to_string()))?;
    let mu0_pa = model.shear_modulus_pa();
    let nu = 0.5;
    Ok(MaterialSummary {
        model: model.family().to_owned(),
        parameters: model
            .parameters()
            .into_iter()
            .map(|p| (p.name(), p.value))
            .collect(),
        mu0_pa,
        e0_pa: hypercontact_material::youngs_modulus_pa(mu0_pa, nu),
        e0_star_pa: hypercontact_material::composite_modulus_pa(mu0_pa, nu),
    })
}

fn labelled_tables<'a>(
    inputs: &'a Inputs,
    name: &str,
) -> Result<Vec<(&'a str, &'a Table)>, ReportError> {
    inputs
        .labelled(name)
        .into_iter()
        .map(|(label, p)| match p {
            Product::Table(t) => Ok((label, t)),
            other => Err(ReportError::input(
                &format!("{name}.{label}"),
                format!("is a {}, expected a table", other.kind()),
            )),
        })
        .collect()
}

fn read_samples(inputs: &Inputs) -> Result<Vec<Sample<'_>>, ReportError> {
    let mut map: BTreeMap<String, Sample<'_>> = BTreeMap::new();
    fn slot<'m, 'a>(map: &'m mut BTreeMap<String, Sample<'a>>, label: &str) -> &'m mut Sample<'a> {
        map.entry(label.to_owned()).or_insert_with(|| Sample {
            label: label.to_owned(),
            ..Default::default()
        })
    }
    for (label, p) in inputs.labelled("heights") {
        match p {
            Product::Field(f) => slot(&mut map, label).height = Some(f),
            other => {
                return Err(ReportError::input(
                    &format!("heights.{label}"),
                    format!("is a {}, expected a field", other.kind()),
                ));
            }
        }
    }
    for (label, t) in labelled_tables(inputs, "psd")? {
        let (x, y) = read_psd(&format!("psd.{label}"), t)?;
        let s = slot(&mut map, label);
        s.psd_x = x;
        s.psd_y = y;
    }
    for (label, t) in labelled_tables(inputs, "stats")? {
        slot(&mut map, label).stats = Some(read_stats(&format!("stats.{label}"), t)?);
    }
    for (label, t) in labelled_tables(inputs, "profiles")? {
        slot(&mut map, label).profile = Some(read_profile(&format!("profiles.{label}"), t)?);
    }
    for (label, t) in labelled_tables(inputs, "responses")? {
        slot(&mut map, label).response = Some(read_response(&format!("responses.{label}"), t)?);
    }
    for (label, t) in labelled_tables(inputs, "responses_linear")? {
        slot(&mut map, label).response_linear =
            Some(read_response(&format!("responses_linear.{label}"), t)?);
    }
    let mut samples: Vec<Sample<'_>> = map.into_values().collect();
    samples.sort_by_key(|s| natural_key(&s.label));
    Ok(samples)
}

/// Orders `T2` before `T10`: the text before the trailing number, then the number.
fn natural_key(label: &str) -> (String, u64, String) {
    let digits = label.len() - label.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (head, tail) = label.split_at(label.len() - digits);
    (head.to_owned(), tail.parse().unwrap_or(0), label.to_owned())
}

fn read_psd(input: &str, table: &Table) -> Result<(Option<Series>, Option<Series>), ReportError> {
    let direction = table
        .str("direction")
        .map_err(|e| ReportError::table(input, e))?;
    let q = finite_column(input, table, "q_per_m")?;
    let c = finite_column(input, table, "c")?;
    // Log–log axes: q = 0 (the mean) and C = 0 cannot be drawn and carry no slope.
    let series = |dir: &str| -> Option<Series> {
        let rows: Vec<usize> = (0..q.len())
            .filter(|&i| direction[i].eq_ignore_ascii_case(dir) && q[i] > 0.0 && c[i] > 0.0)
            .collect();
        if rows.is_empty() {
            return None;
        }
        let sorted = sort_by_first(vec![
            rows.iter().map(|&i| q[i]).collect(),
            rows.iter().map(|&i| c[i]).collect(),
        ]);
        let [x, y]: [Vec<f64>; 2] = sorted.try_into().expect("two columns in, two out");
        Some(Series { x, y })
    };
    Ok((series("x"), series("y")))
}

fn read_stats(input: &str, table: &Table) -> Result<SurfaceStats, ReportError> {
    if table.n_rows() == 0 {
        return Err(ReportError::input(input, "the statistics table has no row"));
    }
    // A statistic the upstream could not estimate may be NaN: it is shown as
    // "n/a" and written as null, never as a number.
    let first = |column: &str| -> Result<f64, ReportError> {
        table
            .to_f64(column)
            .map(|v| v[0])
            .map_err(|e| ReportError::table(input, e))
    };
    Ok(SurfaceStats {
        sigma_m: first("sigma_m")?,
        rms_slope: first("rms_slope")?,
        hurst_x: first("hurst_x")?,
        hurst_y: first("hurst_y")?,
        hurst_radial: first("hurst_radial")?,
    })
}

fn read_profile(input: &str, table: &Table) -> Result<Series, ReportError> {
    let z = finite_column(input, table, "z_over_sigma")?;
    let a = finite_column(input, table, "area_fraction")?;
    let sorted = sort_by_first(vec![z, a]);
    let [x, y]: [Vec<f64>; 2] = sorted.try_into().expect("two columns in, two out");
    Ok(Series { x, y })
}

fn read_response(input: &str, table: &Table) -> Result<Response, ReportError> {
    let a = finite_column(input, table, "area_fraction")?;
    let f = finite_column(input, table, "load_norm")?;
    let t = finite_column(input, table, "tangent_ratio")?;
    let sorted = sort_by_first(vec![a, f, t]);
    let [area_fraction, load_norm, tangent_ratio]: [Vec<f64>; 3] =
        sorted.try_into().expect("three columns in, three out");
    Ok(Response {
        area_fraction,
        load_norm,
        tangent_ratio,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Product;

    #[test]
    fn samples_come_in_natural_order() {
        let mut labels = vec!["T10", "T2", "T1", "A"];
        labels.sort_by_key(|l| natural_key(l));
        assert_eq!(labels, ["A", "T1", "T2", "T10"]);
    }

    #[test]
    fn curves_are_grouped_in_paper_order_and_sorted_by_stretch() {
        let t = Table::new()
            .with("mode", vec!["BT", "UT", "UT", "PT"])
            .with("stretch", vec![1.5, 2.0, 1.2, 1.1])
            .with("measured_pa", vec![3.0, 2.0, 1.0, 0.5])
            .with("fitted_pa", vec![3.1, 2.1, 1.1, 0.6]);
        let curves = read_curves(&t).unwrap();
        let modes: Vec<&str> = curves.iter().map(|c| c.mode.as_str()).collect();
        assert_eq!(modes, ["UT", "PT", "BT"]);
        assert_eq!(curves[0].stretch, [1.2, 2.0]);
        assert_eq!(curves[0].measured_pa, [1.0, 2.0]);
        assert_eq!(curves[0].fitted_pa, [1.1, 2.1]);
    }

    #[test]
    fn psd_keeps_positive_points_per_direction() {
        let t = Table::new()
            .with("direction", vec!["x", "x", "y", "radial", "x"])
            .with("q_per_m", vec![0.0, 2e3, 1e3, 1e3, 1e3])
            .with("c", vec![1.0, 1e-20, 2e-20, 3e-20, 0.0]);
        let (x, y) = read_psd("psd.T1", &t).unwrap();
        assert_eq!(x.unwrap().x, [2e3]);
        assert_eq!(y.unwrap().y, [2e-20]);
    }

    #[test]
    fn nan_limits_and_wrong_kinds_are_named() {
        let t = Table::new()
            .with("mode", vec!["UT"])
            .with("lambda_min", vec![f64::NAN])
            .with("lambda_max", vec![2.0]);
        let e = read_stability(&t).unwrap_err().to_string();
        assert!(e.contains("stability") && e.contains("NaN"), "{e}");
        let inputs = Inputs::new().with("heights.T1", Product::Table(Table::new()));
        let e = ReportData::gather(&inputs).unwrap_err().to_string();
        assert!(
            e.contains("heights.T1") && e.contains("expected a field"),
            "{e}"
        );
    }

    #[test]
    fn material_gives_the_initial_moduli() {
        let t = Table::new()
            .with("model", vec!["ogden"; 4])
            .with("param", vec!["mu_1", "alpha_1", "mu_2", "alpha_2"])
            .with("value", vec![1.0e6, 2.0, 0.5e6, -2.0]);
        let m = read_material(&t).unwrap();
        assert_eq!(m.mu0_pa, 1.5e6);
        assert!((m.e0_pa - 4.5e6).abs() < 1e-6);
        assert!((m.e0_star_pa - 6.0e6).abs() < 1e-6);
    }
}
