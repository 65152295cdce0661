//! Reads whatever upstream products are wired into typed, checked series.
//!
//! Every input is optional here; which figures and tables can be drawn is
//! decided from what is present (see `report.rs`). Tables are read with the
//! schemas their own stages declare, so no column is named twice. A table
//! that is wired but malformed (missing column, NaN in a plotted column) is
//! an error that names the input, the column and the row: a report silently
//! missing a curve would look like a result.

use std::collections::BTreeMap;

use hypercontact_compare::stage::{AgreementTable, FigureIndex, LoadRatioTable, TransformTable};
use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::{BandTable, ResponseTable};
use hypercontact_core::{Field, Files, Inputs, Mode, Product, Schema, Table};
use hypercontact_material::fit_stage::{
    ComparisonTable, CurvesTable, ParamsTable, QualityTable, StabilityTable,
};
use hypercontact_surface::surface_stage::{PsdTable, StatsTable};
use hypercontact_truncation::stage::ProfileTable;

use crate::ReportError;
use crate::band::Band;
use crate::material::{FitChoice, MaterialSummary};
use crate::roster::Roster;

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
    /// The limit is the search range's edge, not a found instability.
    pub min_at_edge: bool,
    pub max_at_edge: bool,
    /// The window the fit imposed stability on (`in-range`), else NaN.
    pub window: (f64, f64),
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

/// A contact model's response: the area fraction and the two normalised
/// quantities.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Response {
    /// A/A0, ascending.
    pub area_fraction: Vec<f64>,
    /// F/(E0* A0).
    pub load_norm: Vec<f64>,
    /// E_t*/E0*.
    pub tangent_ratio: Vec<f64>,
    /// The E0* that `load_norm` was divided by; `None` when no row carries
    /// load.
    pub e0_star_pa: Option<f64>,
    /// 1/(E0* A0): `load_norm` per newton of load, to put a measured force
    /// on the same axis; `None` when no row carries load.
    pub per_newton: Option<f64>,
}

/// The contact experiment's measured curve (contact-images' `contact`
/// table), in frame order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Experiment {
    pub area_fraction: Vec<f64>,
    pub force_n: Vec<f64>,
}

/// One contact model's curve on one sample, labelled as wired
/// (`responses: { T1: { <label>: ... } }`).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelResponse {
    pub label: String,
    pub response: Response,
}

/// Everything the report knows about one sample.
#[derive(Clone, Debug, Default)]
pub struct Sample<'a> {
    pub label: String,
    pub height: Option<&'a Field>,
    /// C(q) along x and y as the `psd` table holds them, q > 0 and C > 0 only.
    pub psd_x: Option<Series>,
    pub psd_y: Option<Series>,
    pub stats: Option<SurfaceStats>,
    /// A/A0 against z/σ.
    pub profile: Option<Series>,
    /// The areal parameters, ACF, distributions and scale-dependent
    /// statistics of the surface stage (each absent when not wired).
    pub extras: crate::surface_stats::SurfaceExtras,
    /// Every contact model's response, in the roster's order.
    pub models: Vec<ModelResponse>,
    /// Each model's 5–95 % bootstrap band by label (tables without rows
    /// are no band).
    pub bands: BTreeMap<String, Band>,
    /// What each model was given (its one-row summary table), by label.
    pub model_summaries: BTreeMap<String, &'a Table>,
    /// The contact experiment and its comparison with the models
    /// (contact-images, contact-compare).
    pub experiment: Option<Experiment>,
    pub agreement: Option<AgreementTable>,
    pub load_ratio: Option<LoadRatioTable>,
    pub transform: Option<TransformTable>,
    /// contact-compare's figures and their index.
    pub compare_figures: Option<(&'a Files, FigureIndex)>,
}

impl Sample<'_> {
    /// `load_norm` per newton for this sample's measured forces: that of
    /// its first response carrying load.
    pub fn per_newton(&self) -> Option<f64> {
        self.models.iter().find_map(|m| m.response.per_newton)
    }

    /// Model `label`'s response on this sample, if wired.
    pub fn response(&self, label: &str) -> Option<&Response> {
        self.models
            .iter()
            .find(|m| m.label == label)
            .map(|m| &m.response)
    }
}

/// The wired inputs, read and checked.
#[derive(Clone, Debug, Default)]
pub struct ReportData<'a> {
    pub curves: Option<Vec<ModeCurve>>,
    /// Shown as is (checked against its schema).
    pub quality: Option<&'a Table>,
    /// R² per mode label, from `quality`.
    pub r2_by_mode: BTreeMap<String, f64>,
    /// Shown as is (checked against its schema and against `material`).
    pub params: Option<&'a Table>,
    pub stability: Option<Vec<StabilityRange>>,
    /// Shown as is (checked against its schema).
    pub comparison: Option<&'a Table>,
    /// The chosen fit and the same family under the other constraint, from
    /// `comparison` (`None` when it is not wired or selects no row).
    pub fit_choice: Option<FitChoice>,
    pub material: Option<MaterialSummary>,
    /// Samples in label order (T1, T2, ...), each with what is wired for it.
    pub samples: Vec<Sample<'a>>,
    /// The contact models wired, in order, with their colours and lines.
    pub roster: Roster,
    /// The finite-strain comparison on one patch per sample (input
    /// `finite_strain`), samples in label order, curves in label order.
    pub finite_strain: Vec<PatchCurves>,
    /// The refinement study's levels (input `refinement`), ascending k.
    pub refinement: Vec<crate::refinement::RefinementLevel>,
}

/// The curves of one sample's patch: the finite-strain reference and the
/// models on the same window, by label.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchCurves {
    pub sample: String,
    pub curves: Vec<(String, PatchCurve)>,
}

/// A load–area curve as the finite-strain comparison reads it: A/A0
/// ascending and F/(E0* A0) (a finite-element response has no tangent
/// ratio, so none is read).
#[derive(Clone, Debug, PartialEq)]
pub struct PatchCurve {
    pub area_fraction: Vec<f64>,
    pub load_norm: Vec<f64>,
}

impl<'a> ReportData<'a> {
    /// Reads every wired input; absent inputs stay `None`. Table 1's moduli
    /// are taken at Poisson's ratio `poisson`, and every wired response must
    /// have been normalised by that E0*. The models come in the order
    /// `model_order` gives (labels not in it after, in label order).
    pub fn gather(
        inputs: &'a Inputs,
        poisson: f64,
        model_order: &[String],
    ) -> Result<Self, ReportError> {
        let quality = optional_table(inputs, "quality")?;
        let params = optional_table(inputs, "params")?;
        let comparison = optional_table(inputs, "comparison")?;
        let fit_params = params
            .map(|t| read::<ParamsTable>("params", t))
            .transpose()?;
        let fit_choice = comparison
            .map(|t| read::<ComparisonTable>("comparison", t))
            .transpose()?
            .and_then(|c| FitChoice::read(&c));
        let mut samples = read_samples(inputs)?;
        let roster = Roster::new(model_order, &samples);
        for s in &mut samples {
            s.models.sort_by_key(|m| roster.position(&m.label));
        }
        let data = ReportData {
            curves: read_optional::<CurvesTable>(inputs, "curves")?
                .map(read_curves)
                .transpose()?,
            quality,
            r2_by_mode: match quality {
                Some(t) => {
                    let q: QualityTable = read("quality", t)?;
                    q.mode.into_iter().zip(q.r2).collect()
                }
                None => BTreeMap::new(),
            },
            params,
            stability: read_optional::<StabilityTable>(inputs, "stability")?
                .map(read_stability)
                .transpose()?,
            comparison,
            fit_choice,
            material: optional_table(inputs, "material")?
                .map(|t| MaterialSummary::read(t, poisson, fit_params.as_ref()))
                .transpose()?,
            samples,
            roster,
            finite_strain: read_patches(inputs)?,
            refinement: crate::refinement::read(inputs)?,
        };
        if let Some(material) = &data.material {
            for s in &data.samples {
                for m in &s.models {
                    let input = format!("responses.{}.{}", s.label, m.label);
                    material.check_normalisation(&input, &m.response)?;
                }
            }
        }
        Ok(data)
    }
}

/// The product of input `input` as a table; anything else is an error
/// naming the input.
fn as_table<'a>(input: &str, product: &'a Product) -> Result<&'a Table, ReportError> {
    match product {
        Product::Table(t) => Ok(t),
        other => Err(ReportError::input(
            input,
            format!("is a {}, expected a table", other.kind()),
        )),
    }
}

fn optional_table<'a>(inputs: &'a Inputs, name: &str) -> Result<Option<&'a Table>, ReportError> {
    inputs.get(name).map(|p| as_table(name, p)).transpose()
}

/// Input `input`'s table read into schema `S`; a missing or mistyped column
/// is an error naming the input.
fn read<S: Schema>(input: &str, table: &Table) -> Result<S, ReportError> {
    S::from_table(table).map_err(|e| ReportError::table(input, e))
}

fn read_optional<S: Schema>(inputs: &Inputs, name: &str) -> Result<Option<S>, ReportError> {
    optional_table(inputs, name)?
        .map(|t| read(name, t))
        .transpose()
}

/// Checks that every value of a plotted column is finite; the error names
/// the column by its schema field, which is its name in the table.
macro_rules! finite {
    ($input:expr, $table:ident . $column:ident) => {
        check_finite($input, stringify!($column), &$table.$column)
    };
}

pub(crate) fn check_finite(input: &str, column: &str, values: &[f64]) -> Result<(), ReportError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(row) => Err(ReportError::input(
            input,
            format!("column `{column}` row {row} is {}", values[row]),
        )),
        None => Ok(()),
    }
}

/// Sorts parallel columns by the first one (stable, so ties keep row order).
pub(crate) fn sort_by_first<const N: usize>(columns: [&[f64]; N]) -> [Vec<f64>; N] {
    let mut order: Vec<usize> = (0..columns[0].len()).collect();
    order.sort_by(|&a, &b| columns[0][a].total_cmp(&columns[0][b]));
    columns.map(|c| order.iter().map(|&i| c[i]).collect())
}

fn read_curves(table: CurvesTable) -> Result<Vec<ModeCurve>, ReportError> {
    let input = "curves";
    finite!(input, table.stretch)?;
    finite!(input, table.measured_pa)?;
    finite!(input, table.fitted_pa)?;
    let modes = &table.mode;
    let mut labels: Vec<&String> = Vec::new();
    for m in modes {
        if !labels.contains(&m) {
            labels.push(m);
        }
    }
    // Paper order UT, PT, BT first, anything else after.
    labels.sort_by_key(|m| Mode::from_label(m).map_or(Mode::ALL.len(), |m| m as usize));
    Ok(labels
        .into_iter()
        .map(|label| {
            let rows: Vec<usize> = (0..modes.len()).filter(|&i| &modes[i] == label).collect();
            let pick = |v: &[f64]| rows.iter().map(|&i| v[i]).collect::<Vec<_>>();
            let [stretch, measured_pa, fitted_pa] = sort_by_first([
                &pick(&table.stretch),
                &pick(&table.measured_pa),
                &pick(&table.fitted_pa),
            ]);
            ModeCurve {
                mode: label.clone(),
                stretch,
                measured_pa,
                fitted_pa,
            }
        })
        .collect())
}

fn read_stability(table: StabilityTable) -> Result<Vec<StabilityRange>, ReportError> {
    // Unbounded limits may be stored as ±inf; NaN is not meaningful.
    let (lo, hi) = (&table.lambda_min, &table.lambda_max);
    if let Some(row) = lo.iter().chain(hi).position(|v| v.is_nan()) {
        return Err(ReportError::input(
            "stability",
            format!("row {} holds a NaN limit", row % lo.len().max(1)),
        ));
    }
    Ok(table
        .mode
        .iter()
        .enumerate()
        .map(|(i, mode)| StabilityRange {
            mode: mode.clone(),
            lambda_min: lo[i],
            lambda_max: hi[i],
            min_at_edge: table.lambda_min_at_edge[i] == 1,
            max_at_edge: table.lambda_max_at_edge[i] == 1,
            window: (table.window_min[i], table.window_max[i]),
        })
        .collect())
}

/// The products of a many-input by label, each read by `read` under its
/// input name (`psd.T1`).
pub(crate) fn labelled<'a, T>(
    inputs: &'a Inputs,
    name: &str,
    read: impl Fn(&str, &'a Product) -> Result<T, ReportError>,
) -> Result<Vec<(&'a str, T)>, ReportError> {
    inputs
        .labelled(name)
        .into_iter()
        .map(|(label, p)| Ok((label, read(&format!("{name}.{label}"), p)?)))
        .collect()
}

/// A per-sample table read into schema `S`.
pub(crate) fn sample_table<S: Schema>(input: &str, product: &Product) -> Result<S, ReportError> {
    read(input, as_table(input, product)?)
}

/// The products of a nested input by (sample, model), each read by `read`
/// under its input name (`responses.T1.icm`).
pub(crate) fn nested<'a, T>(
    inputs: &'a Inputs,
    name: &str,
    read: impl Fn(&str, &'a Product) -> Result<T, ReportError>,
) -> Result<Vec<(&'a str, &'a str, T)>, ReportError> {
    inputs
        .nested(name)
        .into_iter()
        .map(|(sample, model, p)| {
            Ok((sample, model, read(&format!("{name}.{sample}.{model}"), p)?))
        })
        .collect()
}

/// The samples by label while they are gathered.
pub(crate) type Slots<'a> = BTreeMap<String, Sample<'a>>;

pub(crate) fn slot<'m, 'a>(map: &'m mut Slots<'a>, label: &str) -> &'m mut Sample<'a> {
    map.entry(label.to_owned()).or_insert_with(|| Sample {
        label: label.to_owned(),
        ..Default::default()
    })
}

fn read_samples(inputs: &Inputs) -> Result<Vec<Sample<'_>>, ReportError> {
    let mut map = Slots::new();
    read_surfaces(inputs, &mut map)?;
    read_models(inputs, &mut map)?;
    read_comparisons(inputs, &mut map)?;
    let mut samples: Vec<Sample<'_>> = map.into_values().collect();
    samples.sort_by_key(|s| natural_key(&s.label));
    Ok(samples)
}

/// Height maps, spectra, statistics and truncation profiles.
fn read_surfaces<'a>(inputs: &'a Inputs, map: &mut Slots<'a>) -> Result<(), ReportError> {
    let heights = labelled(inputs, "heights", |input, p| match p {
        Product::Field(f) => Ok(f),
        other => Err(ReportError::input(
            input,
            format!("is a {}, expected a field", other.kind()),
        )),
    })?;
    for (label, f) in heights {
        slot(map, label).height = Some(f);
    }
    let psd = labelled(inputs, "psd", |input, p| {
        read_psd(input, sample_table(input, p)?)
    })?;
    for (label, (x, y)) in psd {
        let s = slot(map, label);
        s.psd_x = x;
        s.psd_y = y;
    }
    let stats = labelled(inputs, "stats", |input, p| {
        read_stats(input, sample_table(input, p)?)
    })?;
    for (label, stats) in stats {
        slot(map, label).stats = Some(stats);
    }
    let profiles = labelled(inputs, "profiles", |input, p| {
        read_profile(input, sample_table(input, p)?)
    })?;
    for (label, profile) in profiles {
        slot(map, label).profile = Some(profile);
    }
    crate::surface_stats::read_extras(inputs, map)
}

/// Every contact model's response, band and summary, by sample and label.
fn read_models<'a>(inputs: &'a Inputs, map: &mut Slots<'a>) -> Result<(), ReportError> {
    let response = |input: &str, p: &Product| read_response(input, sample_table(input, p)?);
    for (sample, label, response) in nested(inputs, "responses", response)? {
        slot(map, sample).models.push(ModelResponse {
            label: label.to_owned(),
            response,
        });
    }
    for (sample, label, band) in nested(inputs, "bands", |input, p| {
        Band::read(input, sample_table::<BandTable>(input, p)?)
    })? {
        // A table without rows is no band: the sample gets no slot for it.
        if let Some(band) = band {
            slot(map, sample).bands.insert(label.to_owned(), band);
        }
    }
    for (sample, label, table) in nested(inputs, "model_summaries", as_table)? {
        slot(map, sample)
            .model_summaries
            .insert(label.to_owned(), table);
    }
    Ok(())
}

/// The contact experiment and contact-compare's products.
fn read_comparisons<'a>(inputs: &'a Inputs, map: &mut Slots<'a>) -> Result<(), ReportError> {
    for (label, t) in labelled(inputs, "experiments", |input, p| {
        let t: ContactTable = sample_table(input, p)?;
        finite!(input, t.area_fraction)?;
        finite!(input, t.force_n)?;
        Ok(t)
    })? {
        slot(map, label).experiment = Some(Experiment {
            area_fraction: t.area_fraction,
            force_n: t.force_n,
        });
    }
    for (label, t) in labelled(inputs, "agreement", sample_table::<AgreementTable>)? {
        slot(map, label).agreement = Some(t);
    }
    for (label, t) in labelled(inputs, "load_ratio", sample_table::<LoadRatioTable>)? {
        slot(map, label).load_ratio = Some(t);
    }
    for (label, t) in labelled(inputs, "transforms", |input, p| {
        let t: TransformTable = sample_table(input, p)?;
        if t.angle_deg.len() != 1 {
            return Err(ReportError::input(
                input,
                format!("has {} rows; a transform table has one", t.angle_deg.len()),
            ));
        }
        Ok(t)
    })? {
        slot(map, label).transform = Some(t);
    }
    for label in inputs
        .labelled("compare_figures")
        .into_iter()
        .map(|(label, _)| label)
    {
        let input = format!("compare_figures.{label}");
        let (files, index) = inputs
            .indexed_files::<FigureIndex>(&input)
            .map_err(|e| ReportError::input(&input, e.to_string()))?;
        slot(map, label).compare_figures = Some((files, index));
    }
    Ok(())
}

/// Orders `T2` before `T10`: the text before the trailing number, then the number.
fn natural_key(label: &str) -> (String, u64, String) {
    let digits = label.len() - label.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (head, tail) = label.split_at(label.len() - digits);
    (head.to_owned(), tail.parse().unwrap_or(0), label.to_owned())
}

fn read_psd(input: &str, table: PsdTable) -> Result<(Option<Series>, Option<Series>), ReportError> {
    finite!(input, table.q_per_m)?;
    finite!(input, table.c)?;
    let PsdTable {
        direction,
        q_per_m: q,
        c,
    } = table;
    // Log–log axes: q = 0 (the mean) and C = 0 cannot be drawn and carry no slope.
    let series = |dir: &str| -> Option<Series> {
        let rows: Vec<usize> = (0..q.len())
            .filter(|&i| direction[i].eq_ignore_ascii_case(dir) && q[i] > 0.0 && c[i] > 0.0)
            .collect();
        if rows.is_empty() {
            return None;
        }
        let pick = |v: &[f64]| rows.iter().map(|&i| v[i]).collect::<Vec<_>>();
        let [x, y] = sort_by_first([&pick(&q), &pick(&c)]);
        Some(Series { x, y })
    };
    Ok((series("x"), series("y")))
}

fn read_stats(input: &str, table: StatsTable) -> Result<SurfaceStats, ReportError> {
    if table.sigma_m.is_empty() {
        return Err(ReportError::input(input, "the statistics table has no row"));
    }
    // A statistic the upstream could not estimate may be NaN: it is shown as
    // "n/a" and written as null, never as a number.
    Ok(SurfaceStats {
        sigma_m: table.sigma_m[0],
        rms_slope: table.rms_slope[0],
        hurst_x: table.hurst_x[0],
        hurst_y: table.hurst_y[0],
        hurst_radial: table.hurst_radial[0],
    })
}

fn read_profile(input: &str, table: ProfileTable) -> Result<Series, ReportError> {
    finite!(input, table.z_over_sigma)?;
    finite!(input, table.area_fraction)?;
    let [x, y] = sort_by_first([&table.z_over_sigma, &table.area_fraction]);
    Ok(Series { x, y })
}

/// A response table, sorted by A/A0, with the E0* behind its `load_norm`.
pub(crate) fn read_response(input: &str, table: ResponseTable) -> Result<Response, ReportError> {
    finite!(input, table.area_fraction)?;
    finite!(input, table.load_norm)?;
    finite!(input, table.tangent_ratio)?;
    let [area_fraction, load_norm, tangent_ratio] =
        sort_by_first([&table.area_fraction, &table.load_norm, &table.tangent_ratio]);
    Ok(Response {
        area_fraction,
        load_norm,
        tangent_ratio,
        e0_star_pa: normalising_modulus_pa(&table),
        per_newton: load_norm_per_newton(&table),
    })
}

/// Input `finite_strain`, by sample and model label.
fn read_patches(inputs: &Inputs) -> Result<Vec<PatchCurves>, ReportError> {
    let read = |input: &str, p: &Product| {
        let table: ResponseTable = sample_table(input, p)?;
        finite!(input, table.area_fraction)?;
        finite!(input, table.load_norm)?;
        let [area_fraction, load_norm] = sort_by_first([&table.area_fraction, &table.load_norm]);
        Ok(PatchCurve {
            area_fraction,
            load_norm,
        })
    };
    let mut by_sample: BTreeMap<(String, u64, String), PatchCurves> = BTreeMap::new();
    for (sample, label, curve) in nested(inputs, "finite_strain", read)? {
        by_sample
            .entry(natural_key(sample))
            .or_insert_with(|| PatchCurves {
                sample: sample.to_owned(),
                curves: Vec::new(),
            })
            .curves
            .push((label.to_owned(), curve));
    }
    Ok(by_sample.into_values().collect())
}

/// load_norm / load_n at the most loaded row (1/(E0* A0)).
fn load_norm_per_newton(table: &ResponseTable) -> Option<f64> {
    let row =
        (0..table.load_n.len()).max_by(|&i, &j| table.load_n[i].total_cmp(&table.load_n[j]))?;
    let (f, norm) = (table.load_n[row], table.load_norm[row]);
    (f > 0.0 && norm > 0.0 && f.is_finite()).then(|| norm / f)
}

/// The E0* of `load_norm` = F/(E0* A0), from the table's own columns:
/// `mean_stress_pa` · `area_fraction` = F/A · A/A0 = F/A0, so E0* is that
/// over `load_norm`. Read at the most loaded row, where rounding matters
/// least; no profile is needed, so every contact model's table is checked.
fn normalising_modulus_pa(table: &ResponseTable) -> Option<f64> {
    let row = (0..table.load_norm.len())
        .max_by(|&i, &j| table.load_norm[i].total_cmp(&table.load_norm[j]))?;
    let (a, f) = (table.area_fraction[row], table.load_norm[row]);
    (f > 0.0 && a > 0.0).then(|| table.mean_stress_pa[row] * a / f)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let curves = read_curves(read("curves", &t).unwrap()).unwrap();
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
        let (x, y) = read_psd("psd.T1", read("psd.T1", &t).unwrap()).unwrap();
        assert_eq!(x.unwrap().x, [2e3]);
        assert_eq!(y.unwrap().y, [2e-20]);
    }

    #[test]
    fn nan_limits_and_wrong_kinds_are_named() {
        // The monotonic range and note are the rest of the `stability`
        // schema; the report does not draw them.
        let t = Table::new()
            .with("mode", vec!["UT"])
            .with("lambda_min", vec![f64::NAN])
            .with("lambda_max", vec![2.0])
            .with("monotonic_min", vec![0.5])
            .with("monotonic_max", vec![2.0])
            .with("note", vec![""])
            .with("lambda_min_at_edge", vec![0_i64])
            .with("lambda_max_at_edge", vec![0_i64])
            .with("window_min", vec![f64::NAN])
            .with("window_max", vec![f64::NAN]);
        let e = read_stability(read("stability", &t).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("stability") && e.contains("NaN"), "{e}");
        let inputs = Inputs::new().with("heights.T1", Product::Table(Table::new()));
        let e = ReportData::gather(&inputs, 0.5, &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("heights.T1") && e.contains("expected a field"),
            "{e}"
        );
    }

    #[test]
    fn a_response_without_load_has_no_normalisation() {
        let zero = ResponseTable {
            z_m: vec![1.0, 0.0],
            area_fraction: vec![0.0, 0.5],
            load_n: vec![0.0; 2],
            load_norm: vec![0.0; 2],
            mean_stress_pa: vec![0.0; 2],
            tangent_ratio: vec![1.0; 2],
        };
        assert_eq!(normalising_modulus_pa(&zero), None);
    }
}
