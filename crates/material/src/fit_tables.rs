//! The tables `material-fit` writes, each declared once as a schema (the
//! stage's declaration, its builder and a reader for other stages) and
//! built from the fit's results.

use hypercontact_core::Schema;
use hypercontact_core::contact::quantile;
use hypercontact_core::param::Choice;

use crate::drucker_windows::DruckerWindows;
use crate::fit::{Conditioning, Constraint, FitResult};
use crate::quality::{Quality, quality};
use crate::stability::{StabilityRange, stability_ranges};
use crate::tensile::TensileData;
use crate::{Family, Hyperelastic, Mode, Parameter, composite_modulus_pa, youngs_modulus_pa};

/// The `params` table: fitted parameters, then the derived initial moduli.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ParamsTable {
    /// the fitted family, e.g. ogden-6
    pub model: Vec<String>,
    /// Ogden term i (1…N); 0 for other families' parameters and derived moduli
    pub term: Vec<i64>,
    /// mu_i, alpha_i (Ogden); c10, c01, c20, c30; mu, lambda_m; derived: mu0, e0, e0_star
    pub param: Vec<String>,
    /// the value, in the unit of `unit`
    #[column(unit = "Pa or 1")]
    pub value: Vec<f64>,
    /// Pa for moduli, 1 for α_i and λm
    pub unit: Vec<String>,
    /// 5th percentile over the bootstrap replicates (NaN without a
    /// bootstrap); Ogden terms are matched in ascending α
    #[column(unit = "Pa or 1")]
    pub p05: Vec<f64>,
    /// 95th percentile over the bootstrap replicates (NaN without)
    #[column(unit = "Pa or 1")]
    pub p95: Vec<f64>,
}

impl ParamsTable {
    /// The model's parameters followed by μ0, E0 = 2 μ0 (1 + ν) and
    /// E0* = E0 / (1 − ν²), as the paper normalises, at Poisson's ratio ν.
    pub fn new(family: Family, model: &dyn Hyperelastic, poisson: f64) -> Self {
        let rows = rows_of(model, poisson);
        Self {
            p05: vec![f64::NAN; rows.len()],
            p95: vec![f64::NAN; rows.len()],
            model: vec![family.name(); rows.len()],
            term: rows
                .iter()
                .map(|p| p.term.map_or(0, |i| i as i64))
                .collect(),
            param: rows.iter().map(Parameter::name).collect(),
            value: rows.iter().map(|p| p.value).collect(),
            unit: rows.iter().map(|p| p.unit.label().to_owned()).collect(),
        }
    }
}

impl ParamsTable {
    /// The 5–95 % interval of every row over bootstrap replicates of the
    /// same family (rows matched by position: Ogden terms in ascending α).
    /// A term the fit holds dead (μ_i = 0) gets none, for μ_i nor α_i:
    /// its α moves nothing, and its replicates' values say nothing.
    pub fn with_intervals<'a>(
        mut self,
        replicates: impl IntoIterator<Item = &'a dyn Hyperelastic>,
        poisson: f64,
    ) -> Self {
        let values: Vec<Vec<f64>> = replicates
            .into_iter()
            .map(|m| rows_of(m, poisson).iter().map(|p| p.value).collect())
            .filter(|v: &Vec<f64>| v.len() == self.value.len())
            .collect();
        if values.is_empty() {
            return self;
        }
        for row in 0..self.value.len() {
            let column: Vec<f64> = values.iter().map(|v| v[row]).collect();
            self.p05[row] = quantile(&column, 0.05);
            self.p95[row] = quantile(&column, 0.95);
        }
        let dead: Vec<i64> = (0..self.value.len())
            .filter(|&row| {
                self.term[row] > 0 && self.param[row].starts_with("mu_") && self.value[row] == 0.0
            })
            .map(|row| self.term[row])
            .collect();
        for row in 0..self.value.len() {
            if dead.contains(&self.term[row]) {
                self.p05[row] = f64::NAN;
                self.p95[row] = f64::NAN;
            }
        }
        self
    }
}

/// A model's parameters followed by μ0, E0 and E0* at ν.
fn rows_of(model: &dyn Hyperelastic, poisson: f64) -> Vec<Parameter> {
    let mu0 = model.shear_modulus_pa();
    let derived = [
        Parameter::modulus("mu0", mu0),
        Parameter::modulus("e0", youngs_modulus_pa(mu0, poisson)),
        Parameter::modulus("e0_star", composite_modulus_pa(mu0, poisson)),
    ];
    model.parameters().into_iter().chain(derived).collect()
}

/// The `quality` table: one row per mode, then one over all points.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct QualityTable {
    /// UT, PT, BT, or all
    pub mode: Vec<String>,
    /// coefficient of determination of the stresses
    #[column(unit = "1")]
    pub r2: Vec<f64>,
    /// RMS of (T_fit − T)/max(|T|, 1 % of the mode's largest |T|)
    #[column(unit = "1")]
    pub rms_rel_err: Vec<f64>,
    /// largest relative error
    #[column(unit = "1")]
    pub max_rel_err: Vec<f64>,
    /// points in the mode
    pub n_points: Vec<i64>,
    /// condition number of the fit's Jacobian in its free parameters,
    /// columns scaled to unit length (`all` row; NaN on the mode rows)
    #[column(unit = "1")]
    pub condition_number: Vec<f64>,
    /// largest |correlation| between two free parameters (`all` row)
    #[column(unit = "1")]
    pub max_correlation: Vec<f64>,
    /// parameters not held at a bound (`all` row; 0 on the mode rows)
    pub free_params: Vec<i64>,
}

impl QualityTable {
    pub fn new(qualities: &[Quality], conditioning: &Conditioning) -> Self {
        let whole = |q: &Quality, v: f64, other: f64| if q.mode.is_none() { v } else { other };
        Self {
            condition_number: qualities
                .iter()
                .map(|q| whole(q, conditioning.condition_number, f64::NAN))
                .collect(),
            max_correlation: qualities
                .iter()
                .map(|q| whole(q, conditioning.max_correlation, f64::NAN))
                .collect(),
            free_params: qualities
                .iter()
                .map(|q| {
                    if q.mode.is_none() {
                        conditioning.free_params as i64
                    } else {
                        0
                    }
                })
                .collect(),
            mode: qualities.iter().map(|q| q.label().to_owned()).collect(),
            r2: qualities.iter().map(|q| q.r2).collect(),
            rms_rel_err: qualities.iter().map(|q| q.rms_rel_err).collect(),
            max_rel_err: qualities.iter().map(|q| q.max_rel_err).collect(),
            n_points: qualities.iter().map(|q| q.n_points as i64).collect(),
        }
    }
}

/// The `curves` table: measured and fitted stress at every measured stretch.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct CurvesTable {
    /// UT, PT or BT
    pub mode: Vec<String>,
    /// measured stretch
    #[column(unit = "1")]
    pub stretch: Vec<f64>,
    /// measured nominal stress
    #[column(unit = "Pa")]
    pub measured_pa: Vec<f64>,
    /// the fitted model's nominal stress
    #[column(unit = "Pa")]
    pub fitted_pa: Vec<f64>,
}

impl CurvesTable {
    pub fn new(model: &dyn Hyperelastic, data: &TensileData) -> Self {
        let mut t = Self {
            mode: Vec::new(),
            stretch: Vec::new(),
            measured_pa: Vec::new(),
            fitted_pa: Vec::new(),
        };
        for c in &data.curves {
            for (&l, &measured) in c.stretch.iter().zip(&c.stress_pa) {
                t.mode.push(c.mode.label().to_owned());
                t.stretch.push(l);
                t.measured_pa.push(measured);
                t.fitted_pa.push(model.nominal_stress_pa(c.mode, l));
            }
        }
        t
    }
}

/// The `stability` table: one row per mode.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct StabilityTable {
    /// UT, PT or BT
    pub mode: Vec<String>,
    /// lower end of the Drucker-stable stretch interval around λ = 1
    /// (0.1 = stable down to 0.1)
    #[column(unit = "1")]
    pub lambda_min: Vec<f64>,
    /// upper end of that interval (10 = stable up to 10)
    #[column(unit = "1")]
    pub lambda_max: Vec<f64>,
    /// lower end of the interval around λ = 1 where the nominal stress rises
    /// (dT/dλ > 0)
    #[column(unit = "1")]
    pub monotonic_min: Vec<f64>,
    /// upper end of that interval (for BT: where the paper's φ peaks)
    #[column(unit = "1")]
    pub monotonic_max: Vec<f64>,
    /// where the model turns unstable, in words
    pub note: Vec<String>,
    /// 1 when `lambda_min` is the search range's edge (λ = 0.1), not a
    /// found instability
    pub lambda_min_at_edge: Vec<i64>,
    /// 1 when `lambda_max` is the search range's edge (λ = 10)
    pub lambda_max_at_edge: Vec<i64>,
    /// lower end of the window where the fit imposed Drucker stability
    /// (`constraint: in-range`; NaN otherwise)
    #[column(unit = "1")]
    pub window_min: Vec<f64>,
    /// upper end of that window (NaN without in-range)
    #[column(unit = "1")]
    pub window_max: Vec<f64>,
}

impl StabilityTable {
    /// The ranges found, and the windows the fit imposed (None: not
    /// `in-range`).
    pub fn new(ranges: &[StabilityRange], windows: Option<&DruckerWindows>) -> Self {
        let window = |r: &StabilityRange| {
            windows
                .and_then(|w| w.get(r.mode))
                .unwrap_or((f64::NAN, f64::NAN))
        };
        Self {
            mode: ranges.iter().map(|r| r.mode.label().to_owned()).collect(),
            lambda_min: ranges.iter().map(|r| r.lambda_min).collect(),
            lambda_max: ranges.iter().map(|r| r.lambda_max).collect(),
            monotonic_min: ranges.iter().map(|r| r.monotonic_min).collect(),
            monotonic_max: ranges.iter().map(|r| r.monotonic_max).collect(),
            note: ranges.iter().map(StabilityRange::describe).collect(),
            lambda_min_at_edge: ranges
                .iter()
                .map(|r| i64::from(r.lambda_min_at_edge()))
                .collect(),
            lambda_max_at_edge: ranges
                .iter()
                .map(|r| i64::from(r.lambda_max_at_edge()))
                .collect(),
            window_min: ranges.iter().map(|r| window(r).0).collect(),
            window_max: ranges.iter().map(|r| window(r).1).collect(),
        }
    }
}

/// The `comparison` table: every family fitted to the same data, ranked.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ComparisonTable {
    /// 1 = smallest total RMS relative error; failed fits last
    pub rank: Vec<i64>,
    /// family name as accepted by `model`
    pub model: Vec<String>,
    /// stable (moduli ≥ 0) or none, as accepted by `constraint`
    pub constraint: Vec<String>,
    /// number of fitted parameters
    pub n_params: Vec<i64>,
    /// parameters not held at a bound
    pub free_params: Vec<i64>,
    /// condition number of the fit (see `quality`); NaN if failed
    #[column(unit = "1")]
    pub condition_number: Vec<f64>,
    /// RMS relative error over all points (NaN if failed)
    #[column(unit = "1")]
    pub rms_rel_err: Vec<f64>,
    /// largest relative error over all points
    #[column(unit = "1")]
    pub max_rel_err: Vec<f64>,
    /// RMS relative error over the UT points (NaN if failed or no UT data)
    #[column(unit = "1")]
    pub ut_rms_rel_err: Vec<f64>,
    /// RMS relative error over the PT points
    #[column(unit = "1")]
    pub pt_rms_rel_err: Vec<f64>,
    /// RMS relative error over the BT points
    #[column(unit = "1")]
    pub bt_rms_rel_err: Vec<f64>,
    /// initial shear modulus μ0 of the fit (NaN if failed)
    #[column(unit = "Pa")]
    pub mu0_pa: Vec<f64>,
    /// UT stable range, lower end
    #[column(unit = "1")]
    pub ut_lambda_min: Vec<f64>,
    /// UT stable range, upper end
    #[column(unit = "1")]
    pub ut_lambda_max: Vec<f64>,
    /// PT stable range, lower end
    #[column(unit = "1")]
    pub pt_lambda_min: Vec<f64>,
    /// PT stable range, upper end
    #[column(unit = "1")]
    pub pt_lambda_max: Vec<f64>,
    /// BT stable range, lower end
    #[column(unit = "1")]
    pub bt_lambda_min: Vec<f64>,
    /// BT stable range, upper end
    #[column(unit = "1")]
    pub bt_lambda_max: Vec<f64>,
    /// 1 for the model and constraint chosen by `model` and `constraint`
    pub selected: Vec<i64>,
    /// ok, or why the family could not be fitted
    pub status: Vec<String>,
}

/// One family's line in the comparison.
pub struct ComparisonRow {
    family: Family,
    constraint: Constraint,
    conditioning: Option<Conditioning>,
    rms_rel_err: f64,
    max_rel_err: f64,
    /// RMS relative error per mode, indexed by [`Mode`].
    mode_rms_rel_err: [f64; 3],
    mu0_pa: f64,
    /// (λ_min, λ_max), indexed by [`Mode`].
    ranges: [(f64, f64); 3],
    selected: bool,
    status: String,
}

impl ComparisonRow {
    pub fn from_fit(
        result: &FitResult,
        data: &TensileData,
        constraint: Constraint,
        selected: bool,
    ) -> Self {
        let model = result.model.as_ref();
        let mut qualities = quality(model, data);
        let all = qualities.pop();
        let mut mode_rms_rel_err = [f64::NAN; 3];
        for q in &qualities {
            if let Some(mode) = q.mode {
                mode_rms_rel_err[mode as usize] = q.rms_rel_err;
            }
        }
        let mut ranges = [(f64::NAN, f64::NAN); 3];
        for s in stability_ranges(model) {
            ranges[s.mode as usize] = (s.lambda_min, s.lambda_max);
        }
        Self {
            family: result.family,
            constraint,
            conditioning: Some(result.conditioning),
            rms_rel_err: all.map_or(f64::NAN, |q| q.rms_rel_err),
            max_rel_err: all.map_or(f64::NAN, |q| q.max_rel_err),
            mode_rms_rel_err,
            mu0_pa: model.shear_modulus_pa(),
            ranges,
            selected,
            status: "ok".into(),
        }
    }

    pub fn failed(family: Family, constraint: Constraint, status: String) -> Self {
        Self {
            family,
            constraint,
            conditioning: None,
            rms_rel_err: f64::NAN,
            max_rel_err: f64::NAN,
            mode_rms_rel_err: [f64::NAN; 3],
            mu0_pa: f64::NAN,
            ranges: [(f64::NAN, f64::NAN); 3],
            selected: false,
            status,
        }
    }
}

impl ComparisonTable {
    /// The rows ranked by total RMS relative error, failed fits last.
    pub fn ranked(mut rows: Vec<ComparisonRow>) -> Self {
        rows.sort_by(|a, b| {
            a.rms_rel_err
                .is_nan()
                .cmp(&b.rms_rel_err.is_nan())
                .then(a.rms_rel_err.total_cmp(&b.rms_rel_err))
        });
        let col = |f: &dyn Fn(&ComparisonRow) -> f64| rows.iter().map(f).collect::<Vec<_>>();
        let low = |mode: Mode| col(&|r| r.ranges[mode as usize].0);
        let high = |mode: Mode| col(&|r| r.ranges[mode as usize].1);
        Self {
            rank: (1..=rows.len() as i64).collect(),
            model: rows.iter().map(|r| r.family.name()).collect(),
            constraint: rows
                .iter()
                .map(|r| r.constraint.name().to_owned())
                .collect(),
            n_params: rows.iter().map(|r| r.family.n_params() as i64).collect(),
            free_params: rows
                .iter()
                .map(|r| r.conditioning.map_or(0, |c| c.free_params as i64))
                .collect(),
            condition_number: col(&|r| r.conditioning.map_or(f64::NAN, |c| c.condition_number)),
            rms_rel_err: col(&|r| r.rms_rel_err),
            max_rel_err: col(&|r| r.max_rel_err),
            ut_rms_rel_err: col(&|r| r.mode_rms_rel_err[Mode::Uniaxial as usize]),
            pt_rms_rel_err: col(&|r| r.mode_rms_rel_err[Mode::Planar as usize]),
            bt_rms_rel_err: col(&|r| r.mode_rms_rel_err[Mode::Equibiaxial as usize]),
            mu0_pa: col(&|r| r.mu0_pa),
            ut_lambda_min: low(Mode::Uniaxial),
            ut_lambda_max: high(Mode::Uniaxial),
            pt_lambda_min: low(Mode::Planar),
            pt_lambda_max: high(Mode::Planar),
            bt_lambda_min: low(Mode::Equibiaxial),
            bt_lambda_max: high(Mode::Equibiaxial),
            selected: rows.iter().map(|r| i64::from(r.selected)).collect(),
            status: rows.into_iter().map(|r| r.status).collect(),
        }
    }
}
