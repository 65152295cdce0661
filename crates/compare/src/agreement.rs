//! How well a model's load–area curve agrees with the experiment's: the
//! load the model needs for each measured contact area, against the load
//! measured there.
//!
//! Both curves are read as load against area fraction. Between its points a
//! curve is interpolated linearly in (ln A/A0, ln F): load–area curves of
//! rough contact are close to power laws, which this follows exactly, and
//! it keeps F > 0. A model point or an experiment point with A or F not
//! positive cannot be placed on those axes and is left out.

use crate::error::CompareError;

/// A load–area curve: `area_fraction[i]` with `load_n[i]`.
#[derive(Clone, Copy, Debug)]
pub struct Curve<'a> {
    pub area_fraction: &'a [f64],
    pub load_n: &'a [f64],
}

/// A curve's usable points in (ln A, ln F), sorted by A, equal areas
/// merged (the larger load kept: the first step that reaches an area).
#[derive(Clone, Debug, PartialEq)]
pub struct LogCurve {
    ln_area: Vec<f64>,
    ln_load: Vec<f64>,
}

impl LogCurve {
    /// The points of `curve` with 0 < A ≤ 1 and F > 0 (finite); an error
    /// when the columns differ in length or fewer than two points remain.
    pub fn new(curve: Curve, what: &str) -> Result<Self, CompareError> {
        if curve.area_fraction.len() != curve.load_n.len() {
            return Err(CompareError::Curve {
                what: what.to_owned(),
                message: format!(
                    "{} area fractions but {} loads",
                    curve.area_fraction.len(),
                    curve.load_n.len()
                ),
            });
        }
        let mut points: Vec<(f64, f64)> = curve
            .area_fraction
            .iter()
            .zip(curve.load_n)
            .filter(|(a, f)| **a > 0.0 && **a <= 1.0 && **f > 0.0 && f.is_finite())
            .map(|(a, f)| (a.ln(), f.ln()))
            .collect();
        points.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
        points.dedup_by(|later, kept| {
            let same = later.0 == kept.0;
            if same {
                kept.1 = kept.1.max(later.1);
            }
            same
        });
        if points.len() < 2 {
            return Err(CompareError::Curve {
                what: what.to_owned(),
                message: format!(
                    "{} points with 0 < A/A0 <= 1 and a positive load; a curve needs 2",
                    points.len()
                ),
            });
        }
        Ok(Self {
            ln_area: points.iter().map(|p| p.0).collect(),
            ln_load: points.iter().map(|p| p.1).collect(),
        })
    }

    /// The smallest and largest area fraction the curve covers.
    pub fn area_range(&self) -> (f64, f64) {
        (
            self.ln_area[0].exp(),
            self.ln_area[self.ln_area.len() - 1].exp(),
        )
    }

    /// The load at area fraction `a`, interpolated; `None` outside the
    /// curve's range (no extrapolation) or for `a` ≤ 0.
    pub fn load_at(&self, a: f64) -> Option<f64> {
        self.ln_load_at(a).map(f64::exp)
    }

    /// ln of [`LogCurve::load_at`] (exact at the curve's points: no round
    /// trip through exp).
    pub fn ln_load_at(&self, a: f64) -> Option<f64> {
        if a.is_nan() || a <= 0.0 {
            return None;
        }
        let x = a.ln();
        let n = self.ln_area.len();
        if x < self.ln_area[0] || x > self.ln_area[n - 1] {
            return None;
        }
        let i = self.ln_area.partition_point(|&v| v < x);
        if i == 0 || self.ln_area[i] == x {
            return Some(self.ln_load[i]);
        }
        let (x0, x1) = (self.ln_area[i - 1], self.ln_area[i]);
        let (y0, y1) = (self.ln_load[i - 1], self.ln_load[i]);
        Some(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
    }
}

/// What [`agreement`] found for one model.
#[derive(Clone, Debug, PartialEq)]
pub struct Agreement {
    /// sqrt(mean over the experiment's points of ln²(F_model / F_exp)), at
    /// equal area fraction; 0 for perfect agreement.
    pub rms_log_ratio: f64,
    /// The mean of ln(F_model / F_exp): its sign says whether the model
    /// needs more load (> 0) or less for the same area.
    pub mean_log_ratio: f64,
    /// Experiment points scored.
    pub points: usize,
    /// Experiment points in the range but outside the model's curve.
    pub outside_model: usize,
    /// F_model / F_exp at each requested area fraction (NaN where either
    /// curve does not reach it).
    pub ratio_at: Vec<f64>,
}

/// The range of area fractions scored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    pub min_area_fraction: f64,
    pub max_area_fraction: f64,
}

impl Default for Range {
    /// The paper's range, A/A0 ≤ 0.9, from 0.01 (below it a handful of
    /// pixels and a force within the sensor's resolution decide).
    fn default() -> Self {
        Self {
            min_area_fraction: 0.01,
            max_area_fraction: 0.9,
        }
    }
}

/// Scores `model` against `experiment` over `range`: at each experiment
/// point (A, F) in the range the model's load at A is interpolated and the
/// log ratio taken; and the ratio of the two curves at each of `at`.
pub fn agreement(
    model: &LogCurve,
    experiment: Curve,
    range: Range,
    at: &[f64],
) -> Result<Agreement, CompareError> {
    if !(range.min_area_fraction >= 0.0
        && range.min_area_fraction < range.max_area_fraction
        && range.max_area_fraction <= 1.0)
    {
        return Err(CompareError::param(
            "area range",
            format!("{} … {}", range.min_area_fraction, range.max_area_fraction),
            "0 <= min < max <= 1",
        ));
    }
    let measured = LogCurve::new(experiment, "the experiment")?;
    let mut logs = Vec::new();
    let mut outside_model = 0;
    for (&a, &f) in experiment.area_fraction.iter().zip(experiment.load_n) {
        if !(a >= range.min_area_fraction && a <= range.max_area_fraction && f > 0.0) {
            continue;
        }
        match model.ln_load_at(a) {
            Some(m) => logs.push(m - f.ln()),
            None => outside_model += 1,
        }
    }
    if logs.is_empty() {
        let (lo, hi) = model.area_range();
        return Err(CompareError::NoOverlap {
            message: format!(
                "no experiment point with {} <= A/A0 <= {} and a positive force lies on the \
                 model's curve ({lo:.4} … {hi:.4})",
                range.min_area_fraction, range.max_area_fraction
            ),
        });
    }
    // Fixed-order sums: the same bytes on any thread count.
    let n = logs.len() as f64;
    let mean_log_ratio = logs.iter().sum::<f64>() / n;
    let rms_log_ratio = (logs.iter().map(|l| l * l).sum::<f64>() / n).sqrt();
    let ratio_at = at
        .iter()
        .map(|&a| match (model.ln_load_at(a), measured.ln_load_at(a)) {
            (Some(m), Some(e)) => (m - e).exp(),
            _ => f64::NAN,
        })
        .collect();
    Ok(Agreement {
        rms_log_ratio,
        mean_log_ratio,
        points: logs.len(),
        outside_model,
        ratio_at,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A model curve of the tests (errors name it `m`).
    fn model(area_fraction: &[f64], load_n: &[f64]) -> LogCurve {
        LogCurve::new(
            Curve {
                area_fraction,
                load_n,
            },
            "m",
        )
        .unwrap()
    }

    /// F = c A^1.2 sampled at `areas`.
    fn power(c: f64, areas: &[f64]) -> Vec<f64> {
        areas.iter().map(|a| c * a.powf(1.2)).collect()
    }

    #[test]
    fn a_power_law_interpolates_exactly_and_nothing_is_extrapolated() {
        let areas = [0.05, 0.2, 0.6, 0.95];
        let loads = power(100.0, &areas);
        let curve = model(&areas, &loads);
        for a in [0.05, 0.1, 0.33, 0.9, 0.95] {
            let want = 100.0 * f64::powf(a, 1.2);
            assert!(
                (curve.load_at(a).unwrap() / want - 1.0).abs() < 1e-12,
                "{a}"
            );
        }
        assert_eq!(curve.load_at(0.04), None);
        assert_eq!(curve.load_at(0.96), None);
        assert_eq!(curve.load_at(f64::NAN), None);
        assert_eq!(curve.load_at(0.0), None);
    }

    #[test]
    fn a_model_against_itself_scores_zero_and_a_doubled_load_scores_ln2() {
        let areas: Vec<f64> = (1..=40).map(|k| k as f64 / 40.0).collect();
        let loads = power(50.0, &areas);
        let exp = Curve {
            area_fraction: &areas,
            load_n: &loads,
        };
        let same = LogCurve::new(exp, "m").unwrap();
        let at = [0.1, 0.5, 0.9];
        let a = agreement(&same, exp, Range::default(), &at).unwrap();
        assert_eq!(a.rms_log_ratio, 0.0);
        assert_eq!(a.ratio_at, [1.0, 1.0, 1.0]);
        // 0.025 … 0.9: points 1 … 36 of 40.
        assert_eq!((a.points, a.outside_model), (36, 0));
        let doubled: Vec<f64> = loads.iter().map(|f| 2.0 * f).collect();
        let twice = model(&areas, &doubled);
        let b = agreement(&twice, exp, Range::default(), &at).unwrap();
        assert!((b.rms_log_ratio - 2f64.ln()).abs() < 1e-12);
        assert!((b.mean_log_ratio - 2f64.ln()).abs() < 1e-12);
        for r in &b.ratio_at {
            assert!((r - 2.0).abs() < 1e-12);
        }
        assert!(b.rms_log_ratio > a.rms_log_ratio);
        // Half the load is as far off as twice: the score is symmetric in
        // the log.
        let halved: Vec<f64> = loads.iter().map(|f| 0.5 * f).collect();
        let half = model(&areas, &halved);
        let c = agreement(&half, exp, Range::default(), &at).unwrap();
        assert!((c.rms_log_ratio - b.rms_log_ratio).abs() < 1e-12);
        assert!((c.mean_log_ratio + b.mean_log_ratio).abs() < 1e-12);
    }

    /// Hand-computed: experiment points (0.1, 10), (0.4, 50); a model
    /// F = 100 A (exact in log-log) needs 10 and 40: ratios 1 and 0.8.
    #[test]
    fn a_hand_computed_score() {
        let model_a = [0.05, 1.0];
        let model_f = [5.0, 100.0];
        let model = model(&model_a, &model_f);
        let exp_a = [0.0, 0.1, 0.4, 0.95];
        let exp_f = [0.0, 10.0, 50.0, 120.0];
        let a = agreement(
            &model,
            Curve {
                area_fraction: &exp_a,
                load_n: &exp_f,
            },
            Range::default(),
            &[0.1],
        )
        .unwrap();
        let want = (0.5 * 0.8f64.ln().powi(2)).sqrt();
        assert!(
            (a.rms_log_ratio - want).abs() < 1e-15,
            "{}",
            a.rms_log_ratio
        );
        assert_eq!(a.points, 2);
        assert!((a.ratio_at[0] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_curves_and_ranges_are_named() {
        let a = [0.1, 0.2];
        let refused = |load_n: &[f64]| {
            LogCurve::new(
                Curve {
                    area_fraction: &a,
                    load_n,
                },
                "icm",
            )
            .unwrap_err()
            .to_string()
        };
        let e = refused(&[1.0]);
        assert!(
            e.contains("icm") && e.contains("2 area fractions but 1 loads"),
            "{e}"
        );
        let e = refused(&[0.0, 1.0]);
        assert!(e.contains("1 points"), "{e}");
        let model_f = [1.0, 2.0];
        let model = model(&a, &model_f);
        let exp_a = [0.5, 0.6];
        let exp = Curve {
            area_fraction: &exp_a,
            load_n: &model_f,
        };
        let e = agreement(&model, exp, Range::default(), &[]).unwrap_err();
        assert!(e.to_string().contains("no experiment point"), "{e}");
        let bad = Range {
            min_area_fraction: 0.5,
            max_area_fraction: 0.4,
        };
        assert!(agreement(&model, exp, bad, &[]).is_err());
    }
}
