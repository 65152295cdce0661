//! The surface statistics beyond σ, slope and Hurst that the `surface`
//! stage writes (issue #36): its ISO 25178-2 areal parameters, the
//! material-ratio curve, the autocorrelation, the scale-dependent rms slope
//! and curvature and the histograms, read per sample, and the areal
//! parameters as one HTML table (one column per sample). Each is optional:
//! a pipeline (or a cache) from before these outputs wires none of them,
//! and the page then says which are missing instead of failing.

use hypercontact_core::{Inputs, Schema};
use hypercontact_surface::surface_stage::{
    AcfTable, ArealTable, DistributionsTable, MaterialRatioTable, ScaleDependentTable,
};

use crate::ReportError;
use crate::gather::{Sample, Series, Slots, check_finite, labelled, sample_table, slot};
use crate::html::{escape, fmt_sig, simple_table};

/// The autocorrelation of one sample: radially averaged and along x and
/// y, lag in metres, points where it is defined (finite) only.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AcfCurves {
    pub radial: Series,
    pub x: Series,
    pub y: Series,
}

/// A histogram as a probability density: bin edges and density (in 1 over
/// the unit of the edges), bins of finite density only.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Density {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub density: Vec<f64>,
}

/// The histograms of one sample, each absent when its rows are.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Distributions {
    /// Height about the mean plane, m.
    pub height: Option<Density>,
    /// Slope |∇h|, dimensionless.
    pub slope: Option<Density>,
    /// Curvature ∇²h/2, 1/m.
    pub curvature: Option<Density>,
}

/// Rms slope and rms curvature against scale (m), positive finite points
/// only (a log–log plot).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScaleCurves {
    pub slope: Series,
    pub curvature_per_m: Series,
}

/// What one sample's `surface` stage adds to σ, slope and Hurst.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceExtras {
    /// The one row of the areal parameters (NaN = not defined).
    pub areal: Option<ArealTable>,
    /// Height (m, about the mean plane) against material ratio (%),
    /// ratio ascending; `None` also when the table has no row.
    pub material_ratio: Option<Series>,
    pub acf: Option<AcfCurves>,
    pub scale_dependent: Option<ScaleCurves>,
    pub distributions: Option<Distributions>,
}

/// The inputs read here, in the order the page names them.
pub const INPUTS: [&str; 5] = [
    "areal",
    "material_ratio",
    "acf",
    "scale_dependent",
    "distributions",
];

/// Reads the five per-sample inputs into the samples' slots.
pub(crate) fn read_extras<'a>(inputs: &'a Inputs, map: &mut Slots<'a>) -> Result<(), ReportError> {
    for (label, t) in labelled(inputs, "areal", |input, p| {
        let t: ArealTable = sample_table(input, p)?;
        if t.sa_m.len() != 1 {
            return Err(ReportError::input(
                input,
                format!("has {} rows; the areal table has one", t.sa_m.len()),
            ));
        }
        Ok(t)
    })? {
        slot(map, label).extras.areal = Some(t);
    }
    for (label, curve) in labelled(inputs, "material_ratio", |input, p| {
        let t: MaterialRatioTable = sample_table(input, p)?;
        check_finite(input, "material_ratio_percent", &t.material_ratio_percent)?;
        check_finite(input, "height_m", &t.height_m)?;
        let [x, y] = crate::gather::sort_by_first([&t.material_ratio_percent, &t.height_m]);
        Ok((!x.is_empty()).then_some(Series { x, y }))
    })? {
        slot(map, label).extras.material_ratio = curve;
    }
    for (label, acf) in labelled(inputs, "acf", |input, p| {
        read_acf(input, sample_table(input, p)?)
    })? {
        slot(map, label).extras.acf = Some(acf);
    }
    for (label, curves) in labelled(inputs, "scale_dependent", |input, p| {
        read_scale(input, sample_table(input, p)?)
    })? {
        slot(map, label).extras.scale_dependent = Some(curves);
    }
    for (label, d) in labelled(inputs, "distributions", |input, p| {
        read_distributions(input, sample_table(input, p)?)
    })? {
        slot(map, label).extras.distributions = Some(d);
    }
    Ok(())
}

/// The rows of `direction` (its finite values) sorted by lag.
fn acf_series(t: &AcfTable, direction: &str) -> Series {
    let rows: Vec<usize> = (0..t.lag_m.len())
        .filter(|&r| t.direction[r] == direction && t.acf[r].is_finite())
        .collect();
    let pick = |v: &[f64]| rows.iter().map(|&r| v[r]).collect::<Vec<_>>();
    let [x, y] = crate::gather::sort_by_first([&pick(&t.lag_m), &pick(&t.acf)]);
    Series { x, y }
}

fn read_acf(input: &str, t: AcfTable) -> Result<AcfCurves, ReportError> {
    check_finite(input, "lag_m", &t.lag_m)?;
    Ok(AcfCurves {
        radial: acf_series(&t, "radial"),
        x: acf_series(&t, "x"),
        y: acf_series(&t, "y"),
    })
}

fn read_scale(input: &str, t: ScaleDependentTable) -> Result<ScaleCurves, ReportError> {
    check_finite(input, "scale_m", &t.scale_m)?;
    let positive = |values: &[f64]| {
        let rows: Vec<usize> = (0..t.scale_m.len())
            .filter(|&r| values[r] > 0.0 && values[r].is_finite() && t.scale_m[r] > 0.0)
            .collect();
        let pick = |v: &[f64]| rows.iter().map(|&r| v[r]).collect::<Vec<_>>();
        let [x, y] = crate::gather::sort_by_first([&pick(&t.scale_m), &pick(values)]);
        Series { x, y }
    };
    Ok(ScaleCurves {
        slope: positive(&t.rms_slope),
        curvature_per_m: positive(&t.rms_curvature_per_m),
    })
}

fn read_distributions(input: &str, t: DistributionsTable) -> Result<Distributions, ReportError> {
    check_finite(input, "bin_lo", &t.bin_lo)?;
    check_finite(input, "bin_hi", &t.bin_hi)?;
    let quantity = |name: &str| {
        let rows: Vec<usize> = (0..t.bin_lo.len())
            .filter(|&r| t.quantity[r] == name && t.density[r].is_finite())
            .collect();
        let pick = |v: &[f64]| rows.iter().map(|&r| v[r]).collect::<Vec<_>>();
        let [lo, hi, density] =
            crate::gather::sort_by_first([&pick(&t.bin_lo), &pick(&t.bin_hi), &pick(&t.density)]);
        (!lo.is_empty()).then_some(Density { lo, hi, density })
    };
    Ok(Distributions {
        height: quantity("height"),
        slope: quantity("slope"),
        curvature: quantity("curvature"),
    })
}

/// The symbol a column of the areal table is shown as.
fn symbol(column: &str) -> String {
    let sub = |s: &str| format!("S<sub>{s}</sub>");
    match column {
        "sa_m" => sub("a"),
        "sq_m" => sub("q"),
        "ssk" => sub("sk"),
        "sku" => sub("ku"),
        "sp_m" => sub("p"),
        "sv_m" => sub("v"),
        "sz_m" => sub("z"),
        "sdq" => sub("dq"),
        "sdr_percent" => sub("dr"),
        "sal_m" => sub("al"),
        "str" => sub("tr"),
        "sk_m" => sub("k"),
        "spk_m" => sub("pk"),
        "svk_m" => sub("vk"),
        "smr1_percent" => "S<sub>mr1</sub>".into(),
        "smr2_percent" => "S<sub>mr2</sub>".into(),
        "correlation_length_m" => "correlation length".into(),
        other => escape(other),
    }
}

/// The areal parameters of every sample that has them: one row per
/// parameter (in the table's column order, with its unit and the
/// definition the surface stage declares), one column per sample; lengths
/// in µm. Empty when no sample has them.
pub fn areal_table_html(samples: &[Sample<'_>]) -> String {
    let with: Vec<(&str, &ArealTable)> = samples
        .iter()
        .filter_map(|s| Some((s.label.as_str(), s.extras.areal.as_ref()?)))
        .collect();
    if with.is_empty() {
        return String::new();
    }
    let table: Vec<hypercontact_core::Table> = with
        .iter()
        .map(|(_, t)| (*t).clone().into_table())
        .collect();
    let rows: Vec<Vec<String>> = ArealTable::COLUMNS
        .iter()
        .map(|c| {
            let (unit, scale) = match c.unit {
                "m" => ("µm", 1e6),
                "" => ("1", 1.0),
                other => (other, 1.0),
            };
            let mut row = vec![symbol(c.name), escape(unit)];
            for t in &table {
                let v = t.f64(c.name).ok().and_then(|v| v.first().copied());
                row.push(fmt_sig(v.unwrap_or(f64::NAN) * scale, 4));
            }
            row.push(escape(c.doc));
            row
        })
        .collect();
    let mut header = vec!["parameter".to_owned(), "unit".to_owned()];
    header.extend(with.iter().map(|(label, _)| escape(label)));
    header.push("definition (surface stage)".to_owned());
    let mut html = simple_table(
        "Areal surface parameters (ISO 25178-2; Sk, Spk, Svk, Smr1, Smr2 of ISO 13565-2) of \
         each sample's analysed map about its mean plane",
        &header,
        &rows,
    );
    html.push_str(
        "<p class=\"note\">Of the map the surface stage analysed (after its filter, if any, \
         and detrending), measured points only. Sq equals σ of the summary. S<sub>al</sub> and \
         S<sub>tr</sub> are read where the autocorrelation (normalised by the overlap count) \
         first falls to s = 0.2 over 360 directions; the correlation length where its radial \
         average falls to 1/e. Sk is the height span of the ISO 13565-2 equivalence line (the \
         40 % secant of least slope of the material-ratio curve); n/a = not defined for this \
         map (e.g. an autocorrelation that does not decay within half the map).</p>\n",
    );
    html
}

/// Which of the five inputs a sample with some of them lacks, for the
/// page's notes: `T2: no acf, distributions`.
pub fn missing_notes(samples: &[Sample<'_>]) -> Vec<String> {
    samples
        .iter()
        .filter_map(|s| {
            let e = &s.extras;
            let absent: Vec<&str> = [
                e.areal.is_none(),
                e.material_ratio.is_none(),
                e.acf.is_none(),
                e.scale_dependent.is_none(),
                e.distributions.is_none(),
            ]
            .into_iter()
            .zip(INPUTS)
            .filter_map(|(gone, name)| gone.then_some(name))
            .collect();
            let any = absent.len() < INPUTS.len();
            (any && !absent.is_empty()).then(|| format!("{}: no {}", s.label, absent.join(", ")))
        })
        .collect()
}
