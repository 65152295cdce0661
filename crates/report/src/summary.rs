//! `summary.json`: the numbers of the report's tables, as computed from the
//! upstream tables (no rounding). Values that are not available (an input
//! not wired, a statistic the upstream could not estimate, an area fraction
//! outside the computed range) are `null`, never NaN. The refinement
//! study's numbers sit under `refinement`, a key left out without the
//! study (the stage's doc lists its fields).

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
    /// The refinement study's numbers; the key is left out (not null)
    /// without input `refinement`, so a summary without the study keeps
    /// its bytes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refinement: Option<RefinementSummary>,
}

/// The refinement study (Fig. 11 and its table): linear fem against linear
/// bem at each refine factor k.
#[derive(Clone, Debug, Serialize)]
pub struct RefinementSummary {
    /// Points per shortest wavelength at k = 1 (k times that at level k).
    pub points_per_wavelength_at_refine_1: f64,
    /// The compared A/A0, in order: the equal-area points, and where the
    /// finest bem reaches each, the equal-approach points.
    pub area_fractions: Vec<f64>,
    /// The plane height z_m (m) of each equal-approach point, aligned with
    /// `area_fractions` (null where the finest bem does not reach it).
    pub z_m_equal_approach: Vec<Option<f64>>,
    pub levels: Vec<RefinementLevelSummary>,
    /// Per compared point, the observed order over the three finest levels.
    pub observed_order: Vec<ObservedOrder>,
}

/// F_fem / F_bem (both as F/(E0* A0)) at one level; each list aligned with
/// `area_fractions`, null where a load is not read; min and max over the
/// points where it is (null: none).
#[derive(Clone, Debug, Serialize)]
pub struct RefinementLevelSummary {
    pub refine: u32,
    pub points_per_wavelength: f64,
    pub ratio_equal_approach: Vec<Option<f64>>,
    pub ratio_equal_approach_min: Option<f64>,
    pub ratio_equal_approach_max: Option<f64>,
    pub ratio_equal_area: Vec<Option<f64>>,
    pub ratio_equal_area_min: Option<f64>,
    pub ratio_equal_area_max: Option<f64>,
}

/// The observed order p of F_fem, F_bem and F_fem / F_bem at one compared
/// point (F_k = F* + C h_k^p, h_k = 1/k; null with fewer than three levels
/// or without monotone convergence).
#[derive(Clone, Debug, Serialize)]
pub struct ObservedOrder {
    /// `equal_approach` or `equal_area`.
    pub compared_at: &'static str,
    pub area_fraction: f64,
    pub order_fem: Option<f64>,
    pub order_bem: Option<f64>,
    pub order_ratio: Option<f64>,
}

impl RefinementSummary {
    /// The numbers of `levels`; None without any level.
    pub fn new(
        levels: &[crate::refinement::RefinementLevel],
        options: &crate::refinement::RefinementOptions,
    ) -> Option<Self> {
        use crate::refinement::{Measure, comparisons, level_ratios};
        if levels.is_empty() {
            return None;
        }
        let rows = comparisons(levels, options);
        let span = |ratios: &[Option<f64>]| {
            let read = ratios.iter().flatten().copied().filter(|r| r.is_finite());
            (read.clone().reduce(f64::min), read.reduce(f64::max))
        };
        let levels = level_ratios(&rows, options)
            .into_iter()
            .map(|l| {
                let (approach_min, approach_max) = span(&l.equal_approach);
                let (area_min, area_max) = span(&l.equal_area);
                RefinementLevelSummary {
                    refine: l.refine,
                    points_per_wavelength: l.points_per_wavelength,
                    ratio_equal_approach: l.equal_approach,
                    ratio_equal_approach_min: approach_min,
                    ratio_equal_approach_max: approach_max,
                    ratio_equal_area: l.equal_area,
                    ratio_equal_area_min: area_min,
                    ratio_equal_area_max: area_max,
                }
            })
            .collect();
        let observed_order = rows
            .iter()
            .map(|c| ObservedOrder {
                compared_at: match c.measure {
                    Measure::Approach => "equal_approach",
                    Measure::Area => "equal_area",
                },
                area_fraction: c.area_fraction,
                order_fem: c.order_fem,
                order_bem: c.order_bem,
                order_ratio: c.order_ratio,
            })
            .collect();
        Some(RefinementSummary {
            points_per_wavelength_at_refine_1: options.points_per_wavelength,
            area_fractions: options.area_fractions.clone(),
            z_m_equal_approach: rows
                .iter()
                .filter(|c| c.measure == Measure::Approach)
                .map(|c| c.z_m)
                .collect(),
            levels,
            observed_order,
        })
    }
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
            refinement: None,
        }
    }

    /// The summary with the refinement study's numbers (none without levels).
    pub fn with_refinement(
        mut self,
        levels: &[crate::refinement::RefinementLevel],
        options: &crate::refinement::RefinementOptions,
    ) -> Self {
        self.refinement = RefinementSummary::new(levels, options);
        self
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

    /// #49: summary.json carries the refinement study's ratios per level
    /// and the observed orders, from hand-made levels whose ratios are
    /// known by hand (`scaled_columns`); without the study, no key at all.
    #[test]
    fn the_summary_carries_the_refinement_ratios() {
        use crate::refinement::RefinementOptions;
        use crate::refinement::tests::{response_of, scaled_columns};
        let factors = [
            (1u32, [0.90, 0.92, 0.92]),
            (2, [0.96, 0.97, 0.97]),
            (3, [0.99, 1.00, 1.00]),
        ];
        let mut inputs = hypercontact_core::Inputs::new();
        for (k, f) in factors {
            let [(fem_area, fem_load), (bem_area, bem_load)] = scaled_columns(f);
            inputs = inputs
                .with(
                    &format!("refinement.{k}.fem"),
                    response_of(fem_area, fem_load, f64::NAN),
                )
                .with(
                    &format!("refinement.{k}.bem"),
                    response_of(bem_area, bem_load, 1.0),
                );
        }
        let options = crate::report::ReportOptions {
            refinement: RefinementOptions {
                area_fractions: vec![0.1, 0.2],
                points_per_wavelength: 2.0,
            },
            ..Default::default()
        };
        let files = crate::render_report(&inputs, &options, None).unwrap();
        let json: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
        let r = &json["refinement"];
        let close = |v: &Value, expected: f64| {
            let got = v.as_f64().unwrap_or(f64::NAN);
            assert!((got - expected).abs() < 1e-12, "{got} against {expected}");
        };
        assert_eq!(r["area_fractions"], serde_json::json!([0.1, 0.2]));
        close(&r["points_per_wavelength_at_refine_1"], 2.0);
        // bem reaches A/A0 = 0.1 and 0.2 at d = 2 and 4 µm below z = 10 µm.
        close(&r["z_m_equal_approach"][0], 8e-6);
        close(&r["z_m_equal_approach"][1], 6e-6);
        // (k, points, at equal approach f0 and 0.25 f0 + 0.75 f1, at equal
        // area 1.25 f0 and 1.25 f1).
        let expected = [
            (1, 2.0, [0.90, 0.915], [1.125, 1.15]),
            (2, 4.0, [0.96, 0.9675], [1.2, 1.2125]),
            (3, 6.0, [0.99, 0.9975], [1.2375, 1.25]),
        ];
        let levels = r["levels"].as_array().unwrap();
        assert_eq!(levels.len(), 3);
        for (level, (k, points, approach, area)) in levels.iter().zip(expected) {
            assert_eq!(level["refine"], Value::from(k));
            close(&level["points_per_wavelength"], points);
            for i in 0..2 {
                close(&level["ratio_equal_approach"][i], approach[i]);
                close(&level["ratio_equal_area"][i], area[i]);
            }
            close(&level["ratio_equal_approach_min"], approach[0]);
            close(&level["ratio_equal_approach_max"], approach[1]);
            close(&level["ratio_equal_area_min"], area[0]);
            close(&level["ratio_equal_area_max"], area[1]);
        }
        // The order p solves (1 − 2^−p)/(2^−p − 3^−p) = ΔF12/ΔF23: 2 for the
        // ratios 0.90, 0.96, 0.99 (and 1.125, 1.2, 1.2375); bem is constant.
        let orders = r["observed_order"].as_array().unwrap();
        assert_eq!(orders.len(), 4);
        let g = |p: f64| (1.0 - 2f64.powf(-p)) / (2f64.powf(-p) - 3f64.powf(-p));
        for (row, (at, a, ratio)) in orders.iter().zip([
            ("equal_approach", 0.1, 2.0),
            ("equal_approach", 0.2, 0.0525 / 0.03),
            ("equal_area", 0.1, 2.0),
            ("equal_area", 0.2, 0.0625 / 0.0375),
        ]) {
            assert_eq!(
                (row["compared_at"].as_str(), row["area_fraction"].as_f64()),
                (Some(at), Some(a))
            );
            let p = row["order_ratio"].as_f64().unwrap();
            assert!((g(p) - ratio).abs() < 1e-9, "{row}");
            assert_eq!(row["order_bem"], Value::Null, "{row}");
        }
        // The findings carry the study too; without it, neither key exists.
        assert_eq!(
            json["findings"]["refinement"]["level"]["refine"],
            Value::from(2)
        );
        let files =
            crate::render_report(&hypercontact_core::Inputs::new(), &options, None).unwrap();
        let json: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
        assert!(json.get("refinement").is_none(), "{json}");
        assert!(json["findings"].get("refinement").is_none(), "{json}");
    }
}
