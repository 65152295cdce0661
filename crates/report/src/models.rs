//! The contact models compared (Fig. 9's tables): κ of every wired model at
//! small load, and what each model was given (its one-row summary table).
//!
//! κ = (A/A0) / (F/(A0 E0* h'rms)) = (A/A0) h'rms / load_norm, the
//! dimensionless contact stiffness of the area: 1.596 for Persson's original
//! theory at vanishing load, about 2 for boundary elements on self-affine
//! surfaces (SPEC). One h'rms per sample for every model (the `stats` one:
//! forward differences on the map), so the numbers compare areas at equal
//! load, not the models' own yardsticks.

use std::collections::BTreeMap;

use hypercontact_core::{ColumnData, Table};
use serde::Serialize;

use crate::gather::{Response, Sample};
use crate::html::{escape, fmt_sig, simple_table};
use crate::interp::interpolate;
use crate::roster::ModelKey;

/// A/A0 at which κ is read: small load, and the top of the early regime.
pub const KAPPA_AREAS: [f64; 2] = [0.02, 0.1];

/// κ of each wired model of one sample at one A/A0, by label (None: no
/// h'rms, or A/A0 outside the curve), and of the experiment.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct KappaAt {
    pub area_fraction: f64,
    pub models: BTreeMap<String, Option<f64>>,
    pub experiment: Option<f64>,
}

/// κ of a response at A/A0 = `a` (load_norm linearly interpolated in A/A0).
pub fn kappa_at(r: &Response, a: f64, rms_slope: f64) -> Option<f64> {
    let load = interpolate(&r.area_fraction, &r.load_norm, a)?;
    (load > 0.0 && rms_slope > 0.0).then(|| a * rms_slope / load)
}

impl KappaAt {
    /// Every wired model of `s` at `a`; `experiment` is the measured curve
    /// on the models' axes (sorted by A/A0 here).
    pub fn read(s: &Sample<'_>, experiment: Option<&Response>, a: f64) -> Self {
        let slope = s.stats.as_ref().map_or(f64::NAN, |st| st.rms_slope);
        let measured = experiment.and_then(|e| {
            let mut points: Vec<(f64, f64)> = e
                .area_fraction
                .iter()
                .copied()
                .zip(e.load_norm.iter().copied())
                .collect();
            points.sort_by(|x, y| x.0.total_cmp(&y.0));
            let (area_fraction, load_norm) = points.into_iter().unzip();
            kappa_at(
                &Response {
                    area_fraction,
                    load_norm,
                    ..Default::default()
                },
                a,
                slope,
            )
        });
        KappaAt {
            area_fraction: a,
            models: s
                .models
                .iter()
                .map(|m| (m.label.clone(), kappa_at(&m.response, a, slope)))
                .collect(),
            experiment: measured,
        }
    }
}

/// The κ table under Fig. 9: a row per sample and A/A0, a column per model
/// of `models` with a value anywhere, then the experiment's.
pub fn kappa_table(samples: &[(&str, Vec<KappaAt>)], models: &[&ModelKey]) -> String {
    // A column is a model's label, or None for the experiment's.
    let value = |k: &KappaAt, column: Option<&str>| match column {
        Some(label) => k.models.get(label).copied().flatten(),
        None => k.experiment,
    };
    let mut columns: Vec<Option<&str>> = models.iter().map(|k| Some(k.label.as_str())).collect();
    columns.push(None);
    columns.retain(|&column| {
        samples
            .iter()
            .any(|(_, ks)| ks.iter().any(|k| value(k, column).is_some()))
    });
    if columns.is_empty() {
        return String::new();
    }
    let mut header = vec!["sample".to_owned(), "A/A<sub>0</sub>".to_owned()];
    header.extend(
        columns
            .iter()
            .map(|column| escape(column.unwrap_or("experiment"))),
    );
    let rows: Vec<Vec<String>> = samples
        .iter()
        .flat_map(|(label, ks)| ks.iter().map(move |k| (label, k)))
        .map(|(label, k)| {
            let mut row = vec![escape(label), fmt_sig(k.area_fraction, 3)];
            row.extend(
                columns
                    .iter()
                    .map(|&column| value(k, column).map_or("n/a".into(), |v| fmt_sig(v, 3))),
            );
            row
        })
        .collect();
    let mut html = simple_table(
        "κ = (A/A0) / (F/(A0 E0* h'rms)) at small load, per model",
        &header,
        &rows,
    );
    html.push_str(
        "<p class=\"note\">h'rms is the sample's rms slope from the surface statistics \
         (forward differences on the filtered map), the same for every model, so a larger κ \
         is more contact area at the same load. Loads read off each curve by linear \
         interpolation in A/A<sub>0</sub>; n/a = not wired or outside the curve. Known \
         values: Persson's original theory 1.596 at vanishing load on its own (spectral) \
         h'rms; boundary elements about 2 on self-affine surfaces, falling with load; \
         Greenwood–Williamson's κ grows without bound as the load vanishes. A hyperelastic \
         model's κ is about half its linear one (E<sub>t</sub>* ≈ 2 E<sub>0</sub>* at small \
         stress).</p>\n",
    );
    html
}

/// One cell of a summary table: column `name`'s first value.
fn first_cell(table: &Table, name: &str) -> String {
    match table
        .columns()
        .iter()
        .find(|c| c.name == name)
        .map(|c| &c.data)
    {
        Some(ColumnData::F64(v)) => v.first().map_or("n/a".into(), |v| fmt_sig(*v, 4)),
        Some(ColumnData::I64(v)) => v.first().map_or("n/a".into(), i64::to_string),
        Some(ColumnData::Str(v)) => v.first().map_or("n/a".into(), |v| escape(v)),
        None => "n/a".into(),
    }
}

/// What each model was given, as its one-row `model_summaries` tables
/// hold it: a table per model (in `models`' order), a row per sample, the
/// columns of its first sample's table as they are.
pub fn model_summary_tables(samples: &[Sample<'_>], models: &[ModelKey]) -> String {
    let mut html = String::new();
    for key in models {
        let tables: Vec<(&str, &Table)> = samples
            .iter()
            .filter_map(|s| Some((s.label.as_str(), *s.model_summaries.get(&key.label)?)))
            .collect();
        let Some((_, first)) = tables.first() else {
            continue;
        };
        let names = first.column_names();
        let mut header = vec!["sample".to_owned()];
        header.extend(names.iter().map(|n| escape(n)));
        let rows: Vec<Vec<String>> = tables
            .iter()
            .map(|(sample, table)| {
                let mut row = vec![escape(sample)];
                row.extend(names.iter().map(|n| first_cell(table, n)));
                row
            })
            .collect();
        html.push_str(&simple_table(
            &format!("What {} was given (its summary)", key.label),
            &header,
            &rows,
        ));
    }
    html
}
