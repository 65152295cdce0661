//! `summary.json`: the numbers of the report's tables, as computed from the
//! upstream tables (no rounding). Values that are not available (an input
//! not wired, a statistic the upstream could not estimate, an area fraction
//! outside the computed range) are `null`, never NaN.

use std::collections::BTreeMap;

use serde::Serialize;
use serde_json::{Map, Value};

use hypercontact_core::{ColumnData, Schema, Table};

use crate::gather::{ReportData, Response, Sample};
use crate::interp::interpolate;

#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub title: String,
    pub material: Option<MaterialJson>,
    pub quality: Option<Vec<Map<String, Value>>>,
    pub params: Option<Vec<Map<String, Value>>>,
    pub stability: Option<Vec<Map<String, Value>>>,
    pub comparison: Option<Vec<Map<String, Value>>>,
    pub samples: Vec<SampleSummary>,
    pub figures: Vec<FigureStatus>,
    /// The opening section's numbers ("What this rerun finds").
    pub findings: crate::findings::Findings,
}

#[derive(Clone, Debug, Serialize)]
pub struct MaterialJson {
    pub model: String,
    pub parameters: Vec<NamedValue>,
    /// Poisson's ratio ν of `e0_pa` and `e0_star_pa`.
    pub poisson: f64,
    pub mu0_pa: f64,
    pub e0_pa: f64,
    pub e0_star_pa: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct NamedValue {
    pub param: String,
    pub value: f64,
    /// `Pa` or `1`.
    pub unit: &'static str,
}

#[derive(Clone, Debug, Serialize)]
pub struct SampleSummary {
    pub label: String,
    pub sigma_m: Option<f64>,
    pub rms_slope: Option<f64>,
    pub hurst_x: Option<f64>,
    pub hurst_y: Option<f64>,
    pub hurst_radial: Option<f64>,
    /// F/(E0* A0) read off each response at the requested A/A0.
    pub load_norm: Vec<LoadAtArea>,
    /// contact-compare's tables as they are: the models against the
    /// experiment, and the registration of the camera onto the scan.
    pub agreement: Option<Vec<Map<String, Value>>>,
    pub load_ratio: Option<Vec<Map<String, Value>>>,
    pub transform: Option<Map<String, Value>>,
    /// κ of every wired model at small load (Fig. 9's table).
    pub kappa: Vec<crate::models::KappaAt>,
}

#[derive(Clone, Debug, Serialize)]
pub struct LoadAtArea {
    pub area_fraction: f64,
    /// F/(E0* A0) of each model, by label (null outside its curve).
    pub load_norm: BTreeMap<String, Option<f64>>,
    /// The 5th and 95th percentiles of each banded model's bootstrap band,
    /// by label (null outside the band).
    pub load_norm_p05: BTreeMap<String, Option<f64>>,
    pub load_norm_p95: BTreeMap<String, Option<f64>>,
    /// Each other model's load over the reference model's (the report's
    /// `reference_model`; empty without one).
    pub over_reference: BTreeMap<String, Option<f64>>,
}

impl LoadAtArea {
    /// The loads of every wired response of `s` at area fraction `a`, and
    /// their ratios to `reference`'s.
    fn read(s: &Sample<'_>, a: f64, reference: Option<&str>) -> Self {
        let load_norm: BTreeMap<String, Option<f64>> = s
            .models
            .iter()
            .map(|m| (m.label.clone(), load_norm_at(&m.response, a)))
            .collect();
        let (mut load_norm_p05, mut load_norm_p95) = (BTreeMap::new(), BTreeMap::new());
        for (label, band) in &s.bands {
            let (p05, p95) = band.load_norm_at(a);
            load_norm_p05.insert(label.clone(), p05);
            load_norm_p95.insert(label.clone(), p95);
        }
        let base = reference.and_then(|r| load_norm.get(r).copied().flatten());
        let over_reference = match reference {
            Some(r) if load_norm.contains_key(r) => load_norm
                .iter()
                .filter(|(label, _)| *label != r)
                .map(|(label, load)| {
                    let ratio = match (load, base) {
                        (Some(l), Some(b)) if b > 0.0 => Some(l / b),
                        _ => None,
                    };
                    (label.clone(), ratio)
                })
                .collect(),
            _ => BTreeMap::new(),
        };
        LoadAtArea {
            area_fraction: a,
            load_norm,
            load_norm_p05,
            load_norm_p95,
            over_reference,
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct FigureStatus {
    pub name: String,
    pub rendered: bool,
    /// Why the figure was skipped, or what it lacks.
    pub note: Option<String>,
}

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

/// F/(E0* A0) of a response at area fraction `a`, linearly interpolated.
pub fn load_norm_at(response: &Response, a: f64) -> Option<f64> {
    interpolate(&response.area_fraction, &response.load_norm, a)
}

/// Every row of a table as a JSON object (non-finite floats as null).
pub fn table_rows(table: &Table) -> Vec<Map<String, Value>> {
    (0..table.n_rows())
        .map(|row| {
            table
                .columns()
                .iter()
                .map(|c| {
                    let value = match &c.data {
                        ColumnData::F64(v) => finite(v[row]).map_or(Value::Null, Value::from),
                        ColumnData::I64(v) => Value::from(v[row]),
                        ColumnData::Str(v) => Value::from(v[row].clone()),
                    };
                    (c.name.clone(), value)
                })
                .collect()
        })
        .collect()
}

impl Summary {
    /// The numbers of `data`, loads read at `area_fractions` and divided
    /// by model `reference`'s where given.
    pub fn new(
        title: &str,
        data: &ReportData<'_>,
        area_fractions: &[f64],
        reference: Option<&str>,
        figures: Vec<FigureStatus>,
        findings: crate::findings::Findings,
    ) -> Self {
        Summary {
            title: title.to_owned(),
            material: data.material.as_ref().map(|m| MaterialJson {
                model: m.model.clone(),
                parameters: m
                    .parameters
                    .iter()
                    .map(|p| NamedValue {
                        param: p.name(),
                        value: p.value,
                        unit: p.unit.label(),
                    })
                    .collect(),
                poisson: m.poisson,
                mu0_pa: m.mu0_pa,
                e0_pa: m.e0_pa,
                e0_star_pa: m.e0_star_pa,
            }),
            quality: data.quality.map(table_rows),
            params: data.params.map(table_rows),
            stability: data.stability.as_ref().map(|ranges| {
                ranges
                    .iter()
                    .map(|r| {
                        let mut row = Map::new();
                        row.insert("mode".into(), r.mode.clone().into());
                        row.insert(
                            "lambda_min".into(),
                            finite(r.lambda_min).map_or(Value::Null, Value::from),
                        );
                        row.insert(
                            "lambda_max".into(),
                            finite(r.lambda_max).map_or(Value::Null, Value::from),
                        );
                        row
                    })
                    .collect()
            }),
            comparison: data.comparison.map(table_rows),
            samples: data
                .samples
                .iter()
                .map(|s| {
                    let stat = |f: fn(&crate::gather::SurfaceStats) -> f64| {
                        s.stats.as_ref().and_then(|st| finite(f(st)))
                    };
                    SampleSummary {
                        label: s.label.clone(),
                        sigma_m: stat(|st| st.sigma_m),
                        rms_slope: stat(|st| st.rms_slope),
                        hurst_x: stat(|st| st.hurst_x),
                        hurst_y: stat(|st| st.hurst_y),
                        hurst_radial: stat(|st| st.hurst_radial),
                        load_norm: area_fractions
                            .iter()
                            .map(|&a| LoadAtArea::read(s, a, reference))
                            .collect(),
                        agreement: s.agreement.clone().map(|t| table_rows(&t.into_table())),
                        load_ratio: s.load_ratio.clone().map(|t| table_rows(&t.into_table())),
                        transform: s
                            .transform
                            .clone()
                            .and_then(|t| table_rows(&t.into_table()).into_iter().next()),
                        kappa: {
                            let measured = crate::report::experiment_points(s);
                            crate::models::KAPPA_AREAS
                                .iter()
                                .map(|&a| crate::models::KappaAt::read(s, measured.as_ref(), a))
                                .collect()
                        },
                    }
                })
                .collect(),
            figures,
            findings,
        }
    }

    pub fn to_json(&self) -> Vec<u8> {
        let mut bytes =
            serde_json::to_vec_pretty(self).expect("a summary of plain numbers serialises");
        bytes.push(b'\n');
        bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_rows_turn_nan_into_null() {
        let t = Table::new()
            .with("model", vec!["ogden-3", "yeoh"])
            .with("aic", vec![1.5, f64::NAN])
            .with("n_params", vec![6_i64, 3]);
        let rows = table_rows(&t);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0]["aic"], Value::from(1.5));
        assert_eq!(rows[1]["aic"], Value::Null);
        assert_eq!(rows[1]["model"], Value::from("yeoh"));
        assert_eq!(rows[0]["n_params"], Value::from(6));
    }
}
