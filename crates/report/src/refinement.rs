//! The refinement study (issue #49): is the finite-strain judge converged?
//! The same window solved by the finite-element block (`fem`, linear
//! material at small strain) and by the boundary elements (`bem`, linear,
//! periodic on the window's mirror tiling: the same problem) at several
//! refine factors k. Their loads F/(E0* A0) are compared at equal approach
//! (the plane's height z_m above the lowest point, which both stages write
//! the same way) and at equal counted contact area, and the observed order
//! of convergence is read from the three finest levels (Richardson
//! extrapolation with unequal refinement ratios: Roache, Verification and
//! Validation in Computational Science and Engineering, 1998, Ch. 5).

use crate::ReportError;
use crate::figures::fig11::Fig11;
use crate::figures::plotting::{Rendered, render};
use crate::gather::{check_finite, nested, sample_table, sort_by_first};
use crate::html::{anchored_table, fmt_sig};
use crate::interp::interpolate;
use hypercontact_core::Product;
use hypercontact_core::contact::ResponseTable;

/// The two models a level holds, by their labels in `refinement`.
pub const MODELS: [&str; 2] = ["fem", "bem"];

/// What the refinement section reads and how it labels its axis.
#[derive(Clone, Debug, PartialEq)]
pub struct RefinementOptions {
    /// A/A0 of the equal-area comparison; the equal-approach comparison
    /// reads at the approaches where the finest `bem` reaches them.
    pub area_fractions: Vec<f64>,
    /// Points per shortest wavelength at k = 1 (k times that at level k).
    pub points_per_wavelength: f64,
}

impl Default for RefinementOptions {
    fn default() -> Self {
        Self {
            area_fractions: vec![0.05, 0.1, 0.2],
            points_per_wavelength: 2.0,
        }
    }
}

/// One model's response at one level: its rows sorted by A/A0 (with z_m
/// and F/(E0* A0) alongside) and by z_m.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RefinementCurve {
    pub area_fraction: Vec<f64>,
    pub z_by_area: Vec<f64>,
    pub load_by_area: Vec<f64>,
    pub z_m: Vec<f64>,
    pub load_by_z: Vec<f64>,
}

impl RefinementCurve {
    /// The curve of a response's columns (any row order).
    pub fn new(z_m: &[f64], area_fraction: &[f64], load_norm: &[f64]) -> Self {
        let [area_fraction, z_by_area, load_by_area] =
            sort_by_first([area_fraction, z_m, load_norm]);
        let [z_m, load_by_z] = sort_by_first([z_m, load_norm]);
        Self {
            area_fraction,
            z_by_area,
            load_by_area,
            z_m,
            load_by_z,
        }
    }

    /// F/(E0* A0) at A/A0 `a` (None outside the curve).
    pub fn load_at_area(&self, a: f64) -> Option<f64> {
        interpolate(&self.area_fraction, &self.load_by_area, a)
    }

    /// F/(E0* A0) at plane height `z_m` (None outside the curve).
    pub fn load_at_z(&self, z_m: f64) -> Option<f64> {
        interpolate(&self.z_m, &self.load_by_z, z_m)
    }

    /// The plane height at which the curve reaches A/A0 `a`.
    pub fn z_at_area(&self, a: f64) -> Option<f64> {
        interpolate(&self.area_fraction, &self.z_by_area, a)
    }
}

/// Both models at one refine factor.
#[derive(Clone, Debug, PartialEq)]
pub struct RefinementLevel {
    pub refine: u32,
    pub fem: RefinementCurve,
    pub bem: RefinementCurve,
}

/// Input `refinement`: `{ "1": { fem: ..., bem: ... }, "2": ... }`, levels
/// in ascending k; a level label that is no positive whole number, a model
/// label other than `fem` and `bem`, or a level without both is an error
/// naming the input.
pub fn read(inputs: &hypercontact_core::Inputs) -> Result<Vec<RefinementLevel>, ReportError> {
    let mut levels: Vec<(u32, Option<RefinementCurve>, Option<RefinementCurve>)> = Vec::new();
    for (level, model, curve) in nested(inputs, "refinement", read_curve)? {
        let input = format!("refinement.{level}.{model}");
        let refine = level
            .parse::<u32>()
            .ok()
            .filter(|k| *k > 0)
            .ok_or_else(|| {
                ReportError::input(
                    &input,
                    format!("level `{level}` is no refine factor (a whole number from 1)"),
                )
            })?;
        let at = match levels.iter().position(|l| l.0 == refine) {
            Some(i) => i,
            None => {
                levels.push((refine, None, None));
                levels.len() - 1
            }
        };
        let slot = &mut levels[at];
        match model {
            "fem" => slot.1 = Some(curve),
            "bem" => slot.2 = Some(curve),
            other => {
                return Err(ReportError::input(
                    &input,
                    format!("model `{other}` is neither `fem` nor `bem`"),
                ));
            }
        }
    }
    levels.sort_by_key(|l| l.0);
    levels
        .into_iter()
        .map(|(refine, fem, bem)| match (fem, bem) {
            (Some(fem), Some(bem)) => Ok(RefinementLevel { refine, fem, bem }),
            (fem, _) => Err(ReportError::input(
                &format!("refinement.{refine}"),
                format!(
                    "has no `{}` response; each level needs `fem` and `bem`",
                    if fem.is_none() { "fem" } else { "bem" }
                ),
            )),
        })
        .collect()
}

fn read_curve(input: &str, product: &Product) -> Result<RefinementCurve, ReportError> {
    // The table is read with its schema, so a missing column names itself;
    // fem's tangent_ratio is NaN by design and is not read.
    let table: ResponseTable = sample_table(input, product)?;
    check_finite(input, "z_m", &table.z_m)?;
    check_finite(input, "area_fraction", &table.area_fraction)?;
    check_finite(input, "load_norm", &table.load_norm)?;
    // The caption calls bem linear: hold it to that (fem's ratio is NaN).
    if input.ends_with(".bem")
        && let Some(row) = table.tangent_ratio.iter().position(|r| *r != 1.0)
    {
        return Err(ReportError::input(
            input,
            format!(
                "column `tangent_ratio` row {row} is {}: the study compares linear models \
                 (bem's `model: linear`)",
                table.tangent_ratio[row]
            ),
        ));
    }
    Ok(RefinementCurve::new(
        &table.z_m,
        &table.area_fraction,
        &table.load_norm,
    ))
}

/// The observed order p of `values` F_k at grid spacings `spacing` h_k
/// (coarse to fine, unequal ratios allowed), from F_k = F* + C h_k^p:
/// (F1 − F2)/(F2 − F3) = (h1^p − h2^p)/(h2^p − h3^p), solved for p by
/// bisection (the right side grows monotonically with p). None when the
/// differences change sign (oscillating convergence), one is zero, or p
/// lies outside −8..16.
pub fn observed_order(spacing: [f64; 3], values: [f64; 3]) -> Option<f64> {
    let [h1, h2, h3] = spacing;
    if !(h1 > h2 && h2 > h3 && h3 > 0.0) {
        return None;
    }
    let (d12, d23) = (values[0] - values[1], values[1] - values[2]);
    let ratio = d12 / d23;
    if !ratio.is_finite() || ratio <= 0.0 {
        return None;
    }
    let g = |p: f64| (h1.powf(p) - h2.powf(p)) / (h2.powf(p) - h3.powf(p));
    let (mut lo, mut hi) = (-8.0_f64, 16.0_f64);
    if !(g(lo) <= ratio && ratio <= g(hi)) {
        return None;
    }
    // The bracket's midpoints never land on p = 0, where g is 0/0.
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < ratio {
            lo = mid
        } else {
            hi = mid
        }
        if hi - lo < 1e-12 {
            break;
        }
    }
    Some(0.5 * (lo + hi))
}

/// How two loads are put side by side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// At the same plane height z_m.
    Approach,
    /// At the same counted A/A0.
    Area,
}

/// Both loads at one level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelLoads {
    pub refine: u32,
    pub fem: Option<f64>,
    pub bem: Option<f64>,
}

impl LevelLoads {
    /// F_fem / F_bem where both are read and F_bem > 0.
    pub fn ratio(&self) -> Option<f64> {
        let (fem, bem) = (self.fem?, self.bem?);
        (bem > 0.0).then(|| fem / bem)
    }
}

/// One comparison point: at equal area, A/A0 = `area_fraction`; at equal
/// approach, z_m where the finest `bem` reaches that A/A0.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    pub measure: Measure,
    pub area_fraction: f64,
    /// The plane height read at (equal approach only).
    pub z_m: Option<f64>,
    pub levels: Vec<LevelLoads>,
    /// Observed orders of F_fem, F_bem and their ratio over the three
    /// finest levels (None with fewer levels or no monotone convergence).
    pub order_fem: Option<f64>,
    pub order_bem: Option<f64>,
    pub order_ratio: Option<f64>,
}

/// Every comparison, equal approach first (it converges fastest), then
/// equal area, each at the options' A/A0 in order.
pub fn comparisons(levels: &[RefinementLevel], options: &RefinementOptions) -> Vec<Comparison> {
    let finest = levels.last();
    let mut out = Vec::new();
    for measure in [Measure::Approach, Measure::Area] {
        for &a in &options.area_fractions {
            let z_m = match measure {
                Measure::Approach => finest.and_then(|l| l.bem.z_at_area(a)),
                Measure::Area => None,
            };
            let read = |c: &RefinementCurve| match measure {
                Measure::Approach => z_m.and_then(|z| c.load_at_z(z)),
                Measure::Area => c.load_at_area(a),
            };
            let loads: Vec<LevelLoads> = levels
                .iter()
                .map(|l| LevelLoads {
                    refine: l.refine,
                    fem: read(&l.fem),
                    bem: read(&l.bem),
                })
                .collect();
            let order = |pick: &dyn Fn(&LevelLoads) -> Option<f64>| finest_order(&loads, pick);
            out.push(Comparison {
                measure,
                area_fraction: a,
                z_m,
                order_fem: order(&|l| l.fem),
                order_bem: order(&|l| l.bem),
                order_ratio: order(&|l| l.ratio()),
                levels: loads,
            });
        }
    }
    out
}

/// One level's F_fem / F_bem at every compared point, each list in the
/// order of the options' A/A0; None where a load is not read.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelRatios {
    pub refine: u32,
    /// k times the options' points per shortest wavelength at k = 1.
    pub points_per_wavelength: f64,
    pub equal_approach: Vec<Option<f64>>,
    pub equal_area: Vec<Option<f64>>,
}

/// The ratios of [`comparisons`]' rows regrouped by level, ascending k.
pub fn level_ratios(rows: &[Comparison], options: &RefinementOptions) -> Vec<LevelRatios> {
    let Some(first) = rows.first() else {
        return Vec::new();
    };
    first
        .levels
        .iter()
        .enumerate()
        .map(|(i, level)| {
            let of = |measure: Measure| -> Vec<Option<f64>> {
                rows.iter()
                    .filter(|c| c.measure == measure)
                    .map(|c| c.levels.get(i).and_then(LevelLoads::ratio))
                    .collect()
            };
            LevelRatios {
                refine: level.refine,
                points_per_wavelength: options.points_per_wavelength * f64::from(level.refine),
                equal_approach: of(Measure::Approach),
                equal_area: of(Measure::Area),
            }
        })
        .collect()
}

/// The observed order over the last three levels, spacing 1/k.
fn finest_order(loads: &[LevelLoads], pick: &dyn Fn(&LevelLoads) -> Option<f64>) -> Option<f64> {
    let last = loads.get(loads.len().checked_sub(3)?..)?;
    let spacing = [0, 1, 2].map(|i| 1.0 / f64::from(last[i].refine));
    let values = [pick(&last[0])?, pick(&last[1])?, pick(&last[2])?];
    observed_order(spacing, values)
}

/// The fem block depths (`depth_m`) of the fem stages upstream, from the
/// run's record, distinct and ascending (none without a record).
pub fn fem_depths_m(provenance: Option<&serde_json::Value>) -> Vec<f64> {
    let Some(upstream) = provenance
        .and_then(|p| p.get("upstream"))
        .and_then(|u| u.as_object())
    else {
        return Vec::new();
    };
    let mut depths: Vec<f64> = upstream
        .values()
        .filter(|s| s.get("kind").and_then(|k| k.as_str()) == Some("fem"))
        .filter_map(|s| s.get("params")?.get("depth_m")?.as_f64())
        .collect();
    depths.sort_by(f64::total_cmp);
    depths.dedup();
    depths
}

/// The section's HTML (figure embedded) and Fig. 11; nothing when
/// `refinement` is not wired.
pub fn section(
    levels: &[RefinementLevel],
    options: &RefinementOptions,
    provenance: Option<&serde_json::Value>,
) -> Result<(String, Option<Rendered>), ReportError> {
    if levels.is_empty() {
        return Ok((String::new(), None));
    }
    let rows = comparisons(levels, options);
    let figure = render(&Fig11 {
        comparisons: &rows,
        points_per_wavelength: options.points_per_wavelength,
    })?;
    let mut html = String::from(
        "<h2 id=\"refinement\">Is the finite-strain judge converged?</h2>\n<p>The same window \
         solved by the finite-element block and by the boundary elements at each refine factor \
         k, both linear; where the two agree as the grid is refined, the finite-element \
         discretisation is no longer what separates fem from the other models.</p>\n",
    );
    html.push_str(&format!(
        "<figure id=\"fig11\">\n{}\n<figcaption><b>Fig. 11.</b> {} Files: \
         <a href=\"fig11.png\">fig11.png</a>, <a href=\"fig11.svg\">fig11.svg</a>.\
         </figcaption>\n</figure>\n",
        figure.svg,
        caption(options, &fem_depths_m(provenance))
    ));
    html.push_str(&table(&rows, options));
    Ok((html, Some(figure)))
}

/// The physics of both models and the area each counts.
fn caption(options: &RefinementOptions, depths_m: &[f64]) -> String {
    let depth = match depths_m {
        [] => "its block depth (fem's depth_m) is not in this run's record".to_owned(),
        [d] => format!("its block {} mm deep", fmt_sig(d * 1e3, 3)),
        many => format!(
            "its blocks {} mm deep (the fem stages upstream differ)",
            many.iter()
                .map(|d| fmt_sig(d * 1e3, 3))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    format!(
        "Load ratio F<sub>fem</sub> / F<sub>bem</sub> against points per shortest wavelength \
         ({} k at refine factor k), both as F/(E<sub>0</sub>* A<sub>0</sub>). Solid: at equal \
         approach, i.e. the same plane height z<sub>m</sub> above the window's lowest point \
         (both stages write it so), read where bem at the finest k reaches the A/A<sub>0</sub> \
         named; dashed: at equal counted area. Both models are linear elastic with E<sub>0</sub>*: \
         fem at small strain, {depth}, symmetry planes on its lateral faces; bem periodic on \
         the window's mirror-image tiling, the same problem. Area measures: fem counts top \
         nodes in contact over all top nodes; bem counts pixels with positive pressure over \
         the measured pixels. A ratio of 1 (dotted): the two agree.",
        fmt_sig(options.points_per_wavelength, 3)
    )
}

/// The anchor of the refinement table.
pub const TABLE_ID: &str = "fig11-table";

fn table(rows: &[Comparison], options: &RefinementOptions) -> String {
    let cell = |v: Option<f64>| v.map_or("n/a".into(), |v| fmt_sig(v, 4));
    let header: Vec<String> = [
        "compared at",
        "k",
        "points per shortest wavelength",
        "F<sub>fem</sub>/(E<sub>0</sub>* A<sub>0</sub>)",
        "F<sub>bem</sub>/(E<sub>0</sub>* A<sub>0</sub>)",
        "F<sub>fem</sub> / F<sub>bem</sub>",
    ]
    .map(str::to_owned)
    .to_vec();
    let mut body = Vec::new();
    for c in rows {
        let at = match (c.measure, c.z_m) {
            (Measure::Approach, Some(z)) => format!(
                "equal approach: z<sub>m</sub> = {} µm (bem's A/A<sub>0</sub> = {} at the \
                 finest k)",
                fmt_sig(z * 1e6, 4),
                c.area_fraction
            ),
            (Measure::Approach, None) => format!(
                "equal approach: none (bem at the finest k does not reach A/A<sub>0</sub> = {})",
                c.area_fraction
            ),
            (Measure::Area, _) => format!("equal area: A/A<sub>0</sub> = {}", c.area_fraction),
        };
        // The point is named on its group's first row only.
        let mut named = Some(at);
        for l in &c.levels {
            body.push(vec![
                named.take().unwrap_or_default(),
                l.refine.to_string(),
                fmt_sig(options.points_per_wavelength * f64::from(l.refine), 3),
                cell(l.fem),
                cell(l.bem),
                cell(l.ratio()),
            ]);
        }
        body.push(vec![
            named.unwrap_or_default(),
            "observed order p".into(),
            String::new(),
            cell(c.order_fem),
            cell(c.order_bem),
            cell(c.order_ratio),
        ]);
    }
    let mut html = anchored_table(
        TABLE_ID,
        "F_fem and F_bem at each refine factor k, their ratio and the observed order of \
         convergence",
        &header,
        &body,
    );
    html.push_str(
        "<p class=\"note\">Loads read off each curve by linear interpolation in z<sub>m</sub> \
         (equal approach) or in A/A<sub>0</sub> (equal area); n/a outside a curve. The observed \
         order p comes from the three finest levels with spacing h ∝ 1/k, solving \
         F<sub>k</sub> = F* + C h<sub>k</sub><sup>p</sup> for p (the refinement ratios \
         differ, so the equal-ratio formula ln(ΔF<sub>12</sub>/ΔF<sub>23</sub>)/ln r does not \
         apply); n/a with fewer than three levels, or where the differences change sign or \
         vanish (no monotone convergence).</p>\n",
    );
    html
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn the_observed_order_is_recovered_with_unequal_ratios() {
        // k = 1, 2, 3: ratios 2 and 1.5, so ln(d12/d23)/ln(r) has no one r.
        let spacing = [1.0, 0.5, 1.0 / 3.0];
        for p in [0.5, 1.0, 2.0, 3.5] {
            let values = spacing.map(|h: f64| 0.97 + 0.4 * h.powf(p));
            let got = observed_order(spacing, values).unwrap();
            assert!(close(got, p, 1e-9), "p = {p}: {got}");
            // Converging from below gives the same order.
            let values = spacing.map(|h: f64| 1.0 - 0.2 * h.powf(p));
            assert!(close(observed_order(spacing, values).unwrap(), p, 1e-9));
        }
        // Equal ratios (k = 1, 2, 4): the textbook ln(d12/d23)/ln 2.
        let spacing = [1.0, 0.5, 0.25];
        let values = [1.3, 1.1, 1.04];
        let expected = (0.2_f64 / 0.06).ln() / 2f64.ln();
        assert!(close(
            observed_order(spacing, values).unwrap(),
            expected,
            1e-9
        ));
    }

    #[test]
    fn oscillating_or_stalled_levels_have_no_order() {
        let spacing = [1.0, 0.5, 1.0 / 3.0];
        assert_eq!(observed_order(spacing, [1.0, 1.2, 1.1]), None);
        assert_eq!(observed_order(spacing, [1.0, 1.0, 1.0]), None);
        assert_eq!(observed_order([1.0, 1.0, 0.5], [1.0, 2.0, 3.0]), None);
    }

    /// A level whose fem and bem responses are straight lines: A/A0 =
    /// (z_top − z)/z_top · 0.5 and F/(E0* A0) = `slope` (z_top − z).
    pub(crate) fn level(refine: u32, fem_slope: f64, bem_slope: f64) -> RefinementLevel {
        let z_m = [1e-5, 7.5e-6, 5e-6, 2.5e-6];
        let area: Vec<f64> = z_m.iter().map(|z| (1e-5 - z) / 1e-5 * 0.5).collect();
        let curve = |slope: f64| {
            let load: Vec<f64> = z_m.iter().map(|z| slope * (1e-5 - z)).collect();
            RefinementCurve::new(&z_m, &area, &load)
        };
        RefinementLevel {
            refine,
            fem: curve(fem_slope),
            bem: curve(bem_slope),
        }
    }

    #[test]
    fn loads_are_read_at_equal_approach_and_at_equal_area() {
        // bem's A/A0 reaches 0.1 at z = 8e-6 (hand: 0.5 (1e-5 − z)/1e-5 = 0.1).
        let mut finest = level(3, 1000.0, 1000.0);
        assert!(close(finest.bem.z_at_area(0.1).unwrap(), 8e-6, 1e-18));
        // fem's area lags bem's: it counts A/A0 = 0.4 (1e-5 − z)/1e-5.
        let z = [1e-5, 7.5e-6, 5e-6, 2.5e-6];
        let fem_area: Vec<f64> = z.iter().map(|z| (1e-5 - z) / 1e-5 * 0.4).collect();
        let fem_load: Vec<f64> = z.iter().map(|z| 990.0 * (1e-5 - z)).collect();
        finest.fem = RefinementCurve::new(&z, &fem_area, &fem_load);
        let options = RefinementOptions {
            area_fractions: vec![0.1, 0.45],
            ..Default::default()
        };
        let rows = comparisons(&[level(1, 1100.0, 1000.0), finest], &options);
        assert_eq!(rows.len(), 4);
        let approach = &rows[0];
        assert_eq!(approach.measure, Measure::Approach);
        // At z = 8e-6: F_fem = 990 · 2e-6, F_bem = 1000 · 2e-6.
        let at3 = approach.levels[1];
        assert!(close(at3.fem.unwrap(), 1.98e-3, 1e-15));
        assert!(close(at3.bem.unwrap(), 2e-3, 1e-15));
        assert!(close(at3.ratio().unwrap(), 0.99, 1e-12));
        assert!(close(approach.levels[0].ratio().unwrap(), 1.1, 1e-12));
        // Equal area 0.1: fem reaches it at 1e-5 − 2.5e-6 = 7.5e-6, so
        // F_fem = 990 · 2.5e-6 against bem's 2e-3: the gap grows.
        let area = &rows[2];
        assert_eq!(area.measure, Measure::Area);
        assert_eq!(area.z_m, None);
        assert!(close(area.levels[1].fem.unwrap(), 2.475e-3, 1e-15));
        assert!(close(area.levels[1].ratio().unwrap(), 1.2375, 1e-12));
        // A/A0 = 0.45 is beyond fem's 0.3 at the finest level: n/a there,
        // and beyond bem's reach nowhere (0.375): no approach either.
        assert_eq!(rows[3].levels[1].fem, None);
        assert_eq!(rows[1].z_m, None);
        assert_eq!(rows[1].levels[0].fem, None);
        // Two levels: no order.
        assert_eq!(approach.order_ratio, None);
    }

    #[test]
    fn the_comparison_gives_the_order_of_each_load_and_of_the_ratio() {
        // F_fem/F_bem = 1 + 0.3 h², bem exact: fem's slope carries the error.
        let levels: Vec<RefinementLevel> = [1u32, 2, 3]
            .iter()
            .map(|&k| {
                let h = 1.0 / f64::from(k);
                level(k, 1000.0 * (1.0 + 0.3 * h * h), 1000.0)
            })
            .collect();
        let rows = comparisons(&levels, &RefinementOptions::default());
        for row in &rows {
            assert!(close(row.order_ratio.unwrap(), 2.0, 1e-6), "{row:?}");
            assert!(close(row.order_fem.unwrap(), 2.0, 1e-6), "{row:?}");
            // bem does not change: no order.
            assert_eq!(row.order_bem, None);
        }
    }
    /// A response table whose rows are `level`'s straight lines.
    fn response(slope: f64, tangent_ratio: f64) -> Product {
        let z_m = Z_ROWS.to_vec();
        let area_fraction: Vec<f64> = z_m.iter().map(|z| (1e-5 - z) / 1e-5 * 0.5).collect();
        let load_norm: Vec<f64> = z_m.iter().map(|z| slope * (1e-5 - z)).collect();
        response_of(area_fraction, load_norm, tangent_ratio)
    }

    /// The plane heights of the hand-made responses: the approach
    /// d = 1e-5 − z_m is 0, 2.5, 5 and 7.5 µm.
    pub(crate) const Z_ROWS: [f64; 4] = [1e-5, 7.5e-6, 5e-6, 2.5e-6];

    /// A response table at [`Z_ROWS`] with these A/A0 and F/(E0* A0).
    pub(crate) fn response_of(
        area_fraction: Vec<f64>,
        load_norm: Vec<f64>,
        tangent_ratio: f64,
    ) -> Product {
        use hypercontact_core::Schema;
        Product::Table(
            ResponseTable {
                load_n: load_norm.clone(),
                mean_stress_pa: vec![1.0; 4],
                tangent_ratio: vec![tangent_ratio; 4],
                z_m: Z_ROWS.to_vec(),
                area_fraction,
                load_norm,
            }
            .into_table(),
        )
    }

    /// A level's columns (A/A0, F/(E0* A0)) at [`Z_ROWS`], fem's then
    /// bem's: bem counts A/A0 = 0.5 d/10 µm and carries F = 1000 d; fem
    /// counts 0.8 of bem's area and carries bem's load times `factors` at
    /// the rows d = 2.5, 5 and 7.5 µm. So, read by linear interpolation,
    /// F_fem/F_bem at equal approach is factors[0] up to bem's A/A0 =
    /// 0.125 and 0.25 f0 + 0.75 f1 at A/A0 = 0.2; at equal area 0.1 and
    /// 0.2 it is 1.25 f0 and 1.25 f1.
    pub(crate) fn scaled_columns(factors: [f64; 3]) -> [(Vec<f64>, Vec<f64>); 2] {
        let approach = Z_ROWS.map(|z| 1e-5 - z);
        let bem_area: Vec<f64> = approach.iter().map(|d| 0.5 * d / 1e-5).collect();
        let bem_load: Vec<f64> = approach.iter().map(|d| 1000.0 * d).collect();
        let fem_area: Vec<f64> = bem_area.iter().map(|a| 0.8 * a).collect();
        let fem_load: Vec<f64> = [1.0, factors[0], factors[1], factors[2]]
            .iter()
            .zip(&bem_load)
            .map(|(f, l)| f * l)
            .collect();
        [(fem_area, fem_load), (bem_area, bem_load)]
    }

    /// [`scaled_columns`] as a level.
    pub(crate) fn scaled_level(refine: u32, factors: [f64; 3]) -> RefinementLevel {
        let [(fem_area, fem_load), (bem_area, bem_load)] = scaled_columns(factors);
        RefinementLevel {
            refine,
            fem: RefinementCurve::new(&Z_ROWS, &fem_area, &fem_load),
            bem: RefinementCurve::new(&Z_ROWS, &bem_area, &bem_load),
        }
    }

    fn study_inputs() -> hypercontact_core::Inputs {
        let mut inputs = hypercontact_core::Inputs::new();
        for k in [2u32, 1, 3] {
            let h = 1.0 / f64::from(k);
            inputs = inputs
                .with(
                    &format!("refinement.{k}.fem"),
                    response(1000.0 * (1.0 - 0.05 * h * h), f64::NAN),
                )
                .with(&format!("refinement.{k}.bem"), response(1000.0, 1.0));
        }
        inputs
    }

    #[test]
    fn the_section_renders_a_table_and_an_svg_figure() {
        let inputs = study_inputs();
        let levels = read(&inputs).unwrap();
        assert_eq!(
            levels.iter().map(|l| l.refine).collect::<Vec<_>>(),
            [1, 2, 3]
        );
        let record = serde_json::json!({"upstream": {
            "t1-fem-small-1": {"kind": "fem", "params": {"depth_m": 1.88e-3}},
            "t1-fem-small-2": {"kind": "fem", "params": {"depth_m": 1.88e-3}},
            "t1-bem-linear-1": {"kind": "bem", "params": {"depth_m": 9.0}},
        }});
        let (html, figure) =
            section(&levels, &RefinementOptions::default(), Some(&record)).unwrap();
        let figure = figure.unwrap();
        assert_eq!(figure.name, "fig11");

        assert!(figure.svg.contains("<svg") && html.contains(&figure.svg));
        assert!(
            html.contains("Is the finite-strain judge converged?"),
            "{html}"
        );
        assert!(html.contains(&format!("id=\"{TABLE_ID}\"")), "{html}");
        assert!(html.contains("its block 1.88 mm deep"), "{html}");
        assert!(html.contains("fem counts top nodes in contact"), "{html}");
        // k = 3 at equal approach: 1 − 0.05/9.
        assert!(html.contains("<td>3</td><td>6</td>"), "{html}");
        assert!(html.contains(&fmt_sig(1.0 - 0.05 / 9.0, 4)), "{html}");
        // The ratio's error is 0.05 h²: order 2 in every row.
        assert_eq!(html.matches("<td>observed order p</td>").count(), 6);
        assert!(html.contains("<td>2</td></tr>"), "{html}");
        // The whole page with nothing else wired: the section and its files.
        let files = crate::render_report(&inputs, &Default::default(), None).unwrap();
        let page = String::from_utf8(files.files["index.html"].clone()).unwrap();
        assert!(page.contains("<figure id=\"fig11\">") && page.contains(TABLE_ID));
        assert!(files.files.contains_key("fig11.svg") && files.files.contains_key("fig11.png"));
        // Without the input, nothing.
        let (html, figure) = section(&[], &RefinementOptions::default(), None).unwrap();
        assert!(html.is_empty() && figure.is_none());
        assert!(caption(&RefinementOptions::default(), &[]).contains("not in this run's record"));
    }

    #[test]
    fn a_malformed_study_is_named_by_its_input() {
        let mut table = match response(1000.0, 1.0) {
            Product::Table(t) => t,
            _ => unreachable!(),
        };
        table = {
            let mut kept = hypercontact_core::Table::new();
            for name in [
                "z_m",
                "area_fraction",
                "load_n",
                "mean_stress_pa",
                "tangent_ratio",
            ] {
                kept = kept.with(name, table.f64(name).unwrap().to_vec());
            }
            kept
        };
        let inputs = study_inputs().with("refinement.2.bem", Product::Table(table));
        let e = read(&inputs).unwrap_err().to_string();
        assert!(
            e.contains("refinement.2.bem") && e.contains("load_norm"),
            "{e}"
        );
        let only_fem =
            hypercontact_core::Inputs::new().with("refinement.1.fem", response(1.0, f64::NAN));
        let e = read(&only_fem).unwrap_err().to_string();
        assert!(e.contains("refinement.1") && e.contains("no `bem`"), "{e}");
        let bad = study_inputs().with("refinement.x.fem", response(1.0, f64::NAN));
        let e = read(&bad).unwrap_err().to_string();
        assert!(
            e.contains("refinement.x.fem") && e.contains("refine factor"),
            "{e}"
        );
        let icm = study_inputs().with("refinement.1.icm", response(1.0, 1.0));
        let e = read(&icm).unwrap_err().to_string();
        assert!(e.contains("refinement.1.icm"), "{e}");
        let nonlinear = study_inputs().with("refinement.3.bem", response(1.0, 1.8));
        let e = read(&nonlinear).unwrap_err().to_string();
        assert!(
            e.contains("refinement.3.bem") && e.contains("tangent_ratio"),
            "{e}"
        );
    }
}
