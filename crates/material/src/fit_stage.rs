//! Stage `material-fit`: fits a strain-energy family to UT, PT and BT data at
//! once, reports per-mode quality, the fitted curves, the Drucker-stable
//! stretch ranges, and (optionally) the same for every family, ranked — the
//! way the paper chose its 6-term Ogden model in Abaqus.

use hypercontact_core::{
    Arity, Checked, ColumnSpec, Context, InputSpec, Inputs, OutputSpec, Outputs, ParamError,
    Product, ProductKind, Stage, StageError, StageInfo, Table, params,
};

use crate::fit::{FitOptions, FitResult, Residual, fit};
use crate::quality::{Quality, quality};
use crate::stability::{StabilityRange, stability_ranges};
use crate::table::{MaterialTable, to_table};
use crate::tensile::TensileData;
use crate::tensile_stage::TensilePoints;
use crate::{Family, Hyperelastic, Mode};

/// Weights of the three modes in the objective; 0 leaves a mode out.
#[params(check = some_weight_positive)]
pub struct ModeWeights {
    /// uniaxial
    #[param(default = 1.0, range = 0.0.., rename = "UT")]
    pub ut: f64,
    /// planar
    #[param(default = 1.0, range = 0.0.., rename = "PT")]
    pub pt: f64,
    /// equibiaxial
    #[param(default = 1.0, range = 0.0.., rename = "BT")]
    pub bt: f64,
}

fn some_weight_positive(w: &ModeWeights) -> Result<(), ParamError> {
    if w.ut + w.pt + w.bt > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new("", "at least one weight must be positive"))
    }
}

/// Parameters of `material-fit`.
#[params]
pub struct MaterialFitParams {
    /// the strain-energy family to fit
    #[param(default = Family::Ogden(6))]
    pub model: Family,
    /// how a residual is measured (relative, as Abaqus)
    #[param(default = Residual::Relative)]
    pub residual: Residual,
    /// number of starts for Ogden and Arruda–Boyce (deterministic)
    #[param(default = 8, range = 1..=1000)]
    pub starts: usize,
    /// mode weights in the objective
    #[param(default = ModeWeights::default())]
    pub weights: ModeWeights,
    /// also fit and rank every family
    #[param(default = true)]
    pub compare: bool,
    /// seed of the random starts
    #[param(default = 1)]
    pub seed: u64,
}

impl MaterialFitParams {
    pub fn options(&self) -> FitOptions {
        FitOptions {
            residual: self.residual,
            starts: self.starts,
            weights: [self.weights.ut, self.weights.pt, self.weights.bt],
            seed: self.seed,
            ..FitOptions::default()
        }
    }
}

const PARAMS_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::str("model", "the fitted family, e.g. ogden-6"),
    ColumnSpec::i64(
        "term",
        "",
        "Ogden term i (1…N); 0 for other families' parameters and derived moduli",
    ),
    ColumnSpec::str(
        "param",
        "mu_i, alpha_i (Ogden); c10, c01, c20, c30; mu, lambda_m; derived: mu0, e0, e0_star",
    ),
    ColumnSpec::f64("value", "Pa or 1", "the value, in the unit of `unit`"),
    ColumnSpec::str("unit", "Pa for moduli, 1 for α_i and λm"),
];

const QUALITY_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::str("mode", "UT, PT, BT, or all"),
    ColumnSpec::f64("r2", "1", "coefficient of determination of the stresses"),
    ColumnSpec::f64(
        "rms_rel_err",
        "1",
        "RMS of (T_fit − T)/max(|T|, 1 % of the mode's largest |T|)",
    ),
    ColumnSpec::f64("max_rel_err", "1", "largest relative error"),
    ColumnSpec::i64("n_points", "", "points in the mode"),
];

const CURVES_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::str("mode", "UT, PT or BT"),
    ColumnSpec::f64("stretch", "1", "measured stretch"),
    ColumnSpec::f64("measured_pa", "Pa", "measured nominal stress"),
    ColumnSpec::f64("fitted_pa", "Pa", "the fitted model's nominal stress"),
];

const STABILITY_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::str("mode", "UT, PT or BT"),
    ColumnSpec::f64(
        "lambda_min",
        "1",
        "lower end of the Drucker-stable stretch interval around λ = 1 (0.1 = stable down to 0.1)",
    ),
    ColumnSpec::f64(
        "lambda_max",
        "1",
        "upper end of that interval (10 = stable up to 10)",
    ),
    ColumnSpec::f64(
        "monotonic_min",
        "1",
        "lower end of the interval around λ = 1 where the nominal stress rises (dT/dλ > 0)",
    ),
    ColumnSpec::f64(
        "monotonic_max",
        "1",
        "upper end of that interval (for BT: where the paper's φ peaks)",
    ),
    ColumnSpec::str("note", "where the model turns unstable, in words"),
];

const COMPARISON_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::i64(
        "rank",
        "",
        "1 = smallest total RMS relative error; failed fits last",
    ),
    ColumnSpec::str("model", "family name as accepted by `model`"),
    ColumnSpec::i64("n_params", "", "number of fitted parameters"),
    ColumnSpec::f64(
        "rms_rel_err",
        "1",
        "RMS relative error over all points (NaN if failed)",
    ),
    ColumnSpec::f64("max_rel_err", "1", "largest relative error over all points"),
    ColumnSpec::f64("ut_lambda_min", "1", "UT stable range, lower end"),
    ColumnSpec::f64("ut_lambda_max", "1", "UT stable range, upper end"),
    ColumnSpec::f64("pt_lambda_min", "1", "PT stable range, lower end"),
    ColumnSpec::f64("pt_lambda_max", "1", "PT stable range, upper end"),
    ColumnSpec::f64("bt_lambda_min", "1", "BT stable range, lower end"),
    ColumnSpec::f64("bt_lambda_max", "1", "BT stable range, upper end"),
    ColumnSpec::i64("selected", "", "1 for the model chosen by `model`"),
    ColumnSpec::str("status", "ok, or why the family could not be fitted"),
];

/// The `material-fit` stage.
pub struct MaterialFit;

static INFO: StageInfo = StageInfo {
    kind: "material-fit",
    version: 1,
    summary: "Fit a hyperelastic model to UT, PT and BT data at once; quality, stability, comparison",
    doc: "Fits one strain-energy family to all modes simultaneously by Levenberg–Marquardt \
          (MINPACK-style, the `levenberg-marquardt` crate). Residuals are relative errors \
          (T_fit − T)/T by default, as in Abaqus' material evaluation (the denominator is \
          floored at 1 % of the mode's largest stress so points at λ ≈ 1 cannot dominate); \
          `residual: absolute` uses stress differences. `weights` multiply each mode's squared \
          residuals. Ogden (Abaqus convention, W = Σ 2μ_i/α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3), \
          μ0 = Σ μ_i) and Arruda–Boyce (Abaqus' five-term series) are non-convex: each of \
          `starts` deterministic starts draws the shape parameters (α_i; λm) from a seeded \
          generator, solves the moduli by linear least squares, then refines everything; the \
          best converged start wins. A fit that converges from no start is an error naming \
          the model; so is data with fewer points than parameters. \
          Stability, as Abaqus checks it: Drucker's condition dσ:dε > 0 for every \
          volume-keeping increment of log strain (true stress against log strain), i.e. the \
          Hessian of W in the log strains (ε1, ε2) is positive definite, checked along UT, PT \
          and BT for 0.1 ≤ λ ≤ 10; `stability` gives the interval around λ = 1 where it holds \
          (λ < 1 is compression), and beside it the interval where the nominal stress rises \
          (dT/dλ > 0), which is where a load-controlled test is stable and, in BT, where the \
          paper's φ can be inverted. For the paper's Table 1 material the BT nominal stress φ \
          peaks at λ ≈ 1.46 (ε ≈ 0.46) and falls until λ ≈ 2; the Drucker condition itself \
          holds in BT tension up to λ ≈ 4.4 but fails in equibiaxial compression below \
          λ ≈ 0.56 (ε ≈ −0.44; the same state as UT tension beyond λ ≈ 3.2). Contact uses the \
          compressive branch: the contact stress is compressive, so the incremental contact \
          model evaluates ε = φ⁻¹(S) at S = −F/A < 0 (ε < 0), where φ rises monotonically. \
          `comparison` fits every family (ogden-1…6, neo-hookean, mooney-rivlin, yeoh, \
          arruda-boyce) to the same data and ranks them by total RMS relative error, with \
          their stable ranges, so the choice of model can be justified as the paper did.",
    inputs: &[InputSpec {
        name: "tensile",
        kind: ProductKind::Table,
        arity: Arity::Many,
        columns: <TensilePoints as hypercontact_core::Schema>::COLUMNS,
        doc: "UT/PT/BT stress–stretch data (tensile-table or the DIC stage): one table \
              (`tensile: csv`) or several fitted together (`tensile: { UT: dic-ut, PT: dic-pt }`)",
    }],
    outputs: &[
        OutputSpec {
            name: "material",
            kind: ProductKind::Table,
            columns: <MaterialTable as hypercontact_core::Schema>::COLUMNS,
            doc: "the fitted model, for downstream stages (the ICM reads it)",
        },
        OutputSpec {
            name: "params",
            kind: ProductKind::Table,
            columns: PARAMS_COLUMNS,
            doc: "fitted parameters and the derived initial moduli",
        },
        OutputSpec {
            name: "quality",
            kind: ProductKind::Table,
            columns: QUALITY_COLUMNS,
            doc: "fit quality per mode and over all points",
        },
        OutputSpec {
            name: "curves",
            kind: ProductKind::Table,
            columns: CURVES_COLUMNS,
            doc: "measured and fitted stress at every measured stretch",
        },
        OutputSpec {
            name: "stability",
            kind: ProductKind::Table,
            columns: STABILITY_COLUMNS,
            doc: "Drucker-stable stretch range per mode",
        },
        OutputSpec {
            name: "comparison",
            kind: ProductKind::Table,
            columns: COMPARISON_COLUMNS,
            doc: "every family fitted to the same data, ranked (only the chosen one if compare: false)",
        },
    ],
};

/// Every table bound to `tensile`, single or labelled, as one data set.
fn gather_tensile(inputs: &Inputs) -> Result<TensileData, StageError> {
    let mut tables: Vec<(String, &Table)> = Vec::new();
    if inputs.get("tensile").is_some() {
        tables.push(("input `tensile`".to_owned(), inputs.table("tensile")?));
    }
    for (label, product) in inputs.labelled("tensile") {
        let Product::Table(t) = product else {
            return Err(StageError::invalid(format!(
                "input `tensile.{label}` is a {}, expected a table",
                product.kind()
            )));
        };
        tables.push((format!("input `tensile.{label}`"), t));
    }
    if tables.is_empty() {
        return Err(StageError::MissingInput("tensile".to_owned()));
    }
    let mut data = TensileData::default();
    for (origin, table) in tables {
        data.extend(TensileData::from_table(table, &origin).map_err(StageError::other)?);
    }
    Ok(data)
}

impl Stage for MaterialFit {
    type Params = MaterialFitParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<MaterialFitParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let family = p.model;
        let data = gather_tensile(inputs)?;
        let options = p.options();
        let chosen = fit(&data, family, &options).map_err(StageError::other)?;
        let model = chosen.model.as_ref();
        let qualities = quality(model, &data);
        let stability = stability_ranges(model);
        if let Some(all) = qualities.last() {
            ctx.note(&format!(
                "{}: RMS relative error {:.3} % over {} points ({}/{} starts converged)",
                family.name(),
                100.0 * all.rms_rel_err,
                all.n_points,
                chosen.starts_converged,
                chosen.starts_run
            ));
        }
        for s in stability.iter().filter(|s| !s.stable_everywhere()) {
            ctx.note(&format!("{}: {}", s.mode, s.describe()));
        }

        let mut rows = vec![ComparisonRow::from_fit(&chosen, &data, true)];
        if p.compare {
            let others: Vec<Family> = Family::all().into_iter().filter(|f| *f != family).collect();
            let bar = ctx.progress(others.len() as u64, "model comparison");
            for other in others {
                bar.set_message(&format!("fitting {}", other.name()));
                rows.push(match fit(&data, other, &options) {
                    Ok(result) => ComparisonRow::from_fit(&result, &data, false),
                    Err(e) => ComparisonRow::failed(other, e.to_string()),
                });
                bar.inc(1);
            }
        }

        Ok(Outputs::new()
            .table("material", to_table(model))
            .table("params", params_table(family, model))
            .table("quality", quality_table(&qualities))
            .table("curves", curves_table(model, &data))
            .table("stability", stability_table(&stability))
            .table("comparison", comparison_table(rows)))
    }
}

fn params_table(family: Family, model: &dyn Hyperelastic) -> Table {
    let mut term = Vec::new();
    let mut name = Vec::new();
    let mut value = Vec::new();
    let mut unit = Vec::new();
    for (param, v) in model.parameters() {
        let index = match family {
            Family::Ogden(_) => param
                .rsplit('_')
                .next()
                .and_then(|i| i.parse::<i64>().ok())
                .unwrap_or(0),
            _ => 0,
        };
        let dimensionless = param.starts_with("alpha") || param == "lambda_m";
        term.push(index);
        unit.push(if dimensionless { "1" } else { "Pa" });
        name.push(param);
        value.push(v);
    }
    // E0 = 3 μ0 (ν = ½) and E0* = E0 / (1 − ν²), as the paper normalises.
    let mu0 = model.shear_modulus_pa();
    let e0 = model.youngs_modulus_pa();
    for (param, v) in [("mu0", mu0), ("e0", e0), ("e0_star", e0 / 0.75)] {
        term.push(0);
        name.push(param.to_owned());
        value.push(v);
        unit.push("Pa");
    }
    Table::new()
        .with("model", vec![family.name(); term.len()])
        .with("term", term)
        .with("param", name)
        .with("value", value)
        .with("unit", unit)
}

fn quality_table(qualities: &[Quality]) -> Table {
    Table::new()
        .with(
            "mode",
            qualities.iter().map(Quality::label).collect::<Vec<_>>(),
        )
        .with("r2", qualities.iter().map(|q| q.r2).collect::<Vec<_>>())
        .with(
            "rms_rel_err",
            qualities.iter().map(|q| q.rms_rel_err).collect::<Vec<_>>(),
        )
        .with(
            "max_rel_err",
            qualities.iter().map(|q| q.max_rel_err).collect::<Vec<_>>(),
        )
        .with(
            "n_points",
            qualities
                .iter()
                .map(|q| q.n_points as i64)
                .collect::<Vec<_>>(),
        )
}

fn curves_table(model: &dyn Hyperelastic, data: &TensileData) -> Table {
    let mut mode = Vec::new();
    let (mut stretch, mut measured, mut fitted) = (Vec::new(), Vec::new(), Vec::new());
    for c in &data.curves {
        for (&l, &t) in c.stretch.iter().zip(&c.stress_pa) {
            mode.push(c.mode.label());
            stretch.push(l);
            measured.push(t);
            fitted.push(model.nominal_stress_pa(c.mode, l));
        }
    }
    Table::new()
        .with("mode", mode)
        .with("stretch", stretch)
        .with("measured_pa", measured)
        .with("fitted_pa", fitted)
}

fn stability_table(ranges: &[StabilityRange]) -> Table {
    Table::new()
        .with(
            "mode",
            ranges.iter().map(|r| r.mode.label()).collect::<Vec<_>>(),
        )
        .with(
            "lambda_min",
            ranges.iter().map(|r| r.lambda_min).collect::<Vec<_>>(),
        )
        .with(
            "lambda_max",
            ranges.iter().map(|r| r.lambda_max).collect::<Vec<_>>(),
        )
        .with(
            "monotonic_min",
            ranges.iter().map(|r| r.monotonic_min).collect::<Vec<_>>(),
        )
        .with(
            "monotonic_max",
            ranges.iter().map(|r| r.monotonic_max).collect::<Vec<_>>(),
        )
        .with(
            "note",
            ranges
                .iter()
                .map(StabilityRange::describe)
                .collect::<Vec<_>>(),
        )
}

/// One family's line in the comparison.
struct ComparisonRow {
    family: Family,
    rms_rel_err: f64,
    max_rel_err: f64,
    /// (λ_min, λ_max) for UT, PT, BT.
    ranges: [(f64, f64); 3],
    selected: bool,
    status: String,
}

impl ComparisonRow {
    fn from_fit(result: &FitResult, data: &TensileData, selected: bool) -> Self {
        let model = result.model.as_ref();
        let all = quality(model, data).pop();
        let mut ranges = [(f64::NAN, f64::NAN); 3];
        for s in stability_ranges(model) {
            ranges[s.mode as usize] = (s.lambda_min, s.lambda_max);
        }
        Self {
            family: result.family,
            rms_rel_err: all.map_or(f64::NAN, |q| q.rms_rel_err),
            max_rel_err: all.map_or(f64::NAN, |q| q.max_rel_err),
            ranges,
            selected,
            status: "ok".into(),
        }
    }

    fn failed(family: Family, status: String) -> Self {
        Self {
            family,
            rms_rel_err: f64::NAN,
            max_rel_err: f64::NAN,
            ranges: [(f64::NAN, f64::NAN); 3],
            selected: false,
            status,
        }
    }
}

fn comparison_table(mut rows: Vec<ComparisonRow>) -> Table {
    // NaN (failed) sorts last.
    rows.sort_by(|a, b| {
        a.rms_rel_err
            .is_nan()
            .cmp(&b.rms_rel_err.is_nan())
            .then(a.rms_rel_err.total_cmp(&b.rms_rel_err))
    });
    let col = |f: &dyn Fn(&ComparisonRow) -> f64| rows.iter().map(f).collect::<Vec<_>>();
    let mut t = Table::new()
        .with("rank", (1..=rows.len() as i64).collect::<Vec<_>>())
        .with(
            "model",
            rows.iter().map(|r| r.family.name()).collect::<Vec<_>>(),
        )
        .with(
            "n_params",
            rows.iter()
                .map(|r| r.family.n_params() as i64)
                .collect::<Vec<_>>(),
        )
        .with("rms_rel_err", col(&|r| r.rms_rel_err))
        .with("max_rel_err", col(&|r| r.max_rel_err));
    for mode in Mode::ALL {
        let i = mode as usize;
        let prefix = mode.label().to_ascii_lowercase();
        t.push(&format!("{prefix}_lambda_min"), col(&|r| r.ranges[i].0));
        t.push(&format!("{prefix}_lambda_max"), col(&|r| r.ranges[i].1));
    }
    t.with(
        "selected",
        rows.iter()
            .map(|r| i64::from(r.selected))
            .collect::<Vec<_>>(),
    )
    .with(
        "status",
        rows.iter().map(|r| r.status.clone()).collect::<Vec<_>>(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params, Product};

    fn table<'a>(out: &'a Outputs, name: &str) -> &'a Table {
        match out.get(name) {
            Some(Product::Table(t)) => t,
            _ => panic!("no table {name}"),
        }
    }

    #[test]
    fn writes_every_declared_table_with_its_columns() {
        let data = crate::sample::paper_sample();
        let inputs = Inputs::new().with("tensile", Product::Table(data.to_table()));
        let p = MaterialFitParams {
            model: Family::Ogden(3),
            starts: 4,
            ..Default::default()
        }
        .check()
        .unwrap();
        let out = MaterialFit.run(&p, &inputs, &Context::new("fit")).unwrap();
        for spec in INFO.outputs {
            let t = table(&out, spec.name);
            t.validate().unwrap();
            t.conform(spec.columns).unwrap();
            assert_eq!(
                &t.column_names()[..spec.columns.len()],
                spec.columns.iter().map(|c| c.name).collect::<Vec<_>>(),
                "{}",
                spec.name
            );
        }
        let comparison = table(&out, "comparison");
        assert_eq!(comparison.n_rows(), Family::all().len());
        let rms = comparison.f64("rms_rel_err").unwrap();
        assert!(rms.windows(2).all(|w| w[0] <= w[1]), "{rms:?}");
        assert_eq!(comparison.i64("selected").unwrap().iter().sum::<i64>(), 1);
        assert!(comparison.str("status").unwrap().iter().all(|s| s == "ok"));
        let quality = table(&out, "quality");
        assert_eq!(quality.str("mode").unwrap(), ["UT", "PT", "BT", "all"]);
        assert_eq!(table(&out, "curves").n_rows(), 150);
        let params = table(&out, "params");
        assert_eq!(params.n_rows(), 6 + 3);
        assert_eq!(params.i64("term").unwrap()[..3], [1, 2, 3]);
        crate::table::from_table(table(&out, "material")).unwrap();
    }

    #[test]
    fn too_few_points_names_the_model_and_the_counts() {
        let t = Table::new()
            .with("mode", vec!["UT", "UT", "BT"])
            .with("stretch", vec![1.1, 1.2, 1.1])
            .with("nominal_stress_pa", vec![1e5, 2e5, 2e5]);
        let inputs = Inputs::new().with("tensile", Product::Table(t));
        let p = MaterialFitParams {
            model: Family::Ogden(2),
            ..Default::default()
        }
        .check()
        .unwrap();
        let e = MaterialFit
            .run(&p, &inputs, &Context::new("fit"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`ogden-2`") && e.contains("4 parameters") && e.contains("UT 2, PT 0, BT 1"),
            "{e}"
        );
    }

    #[test]
    fn parameters_read_as_a_pipeline_writes_them() {
        let p: MaterialFitParams = serde_json::from_value(serde_json::json!({
            "model": "yeoh",
            "residual": "absolute",
            "weights": {"UT": 1.0, "BT": 2.0},
            "compare": false,
        }))
        .unwrap();
        assert_eq!(p.residual, Residual::Absolute);
        assert_eq!(p.options().weights, [1.0, 1.0, 2.0]);
        assert_eq!(p.starts, 8);
        p.check().unwrap();
        let typo = serde_json::from_value::<MaterialFitParams>(serde_json::json!({"wieghts": {}}));
        assert!(typo.unwrap_err().to_string().contains("wieghts"));
        let mode =
            serde_json::from_value::<MaterialFitParams>(serde_json::json!({"weights": {"ET": 1}}));
        assert!(mode.is_err());
    }

    #[test]
    fn register_adds_the_three_stages() {
        let mut registry = hypercontact_core::Registry::new();
        crate::register(&mut registry);
        let kinds: Vec<&str> = registry.kinds().collect();
        assert_eq!(kinds, ["material-fit", "material-preset", "tensile-table"]);
    }

    #[test]
    fn compare_false_gives_one_comparison_row() {
        let inputs = Inputs::new().with(
            "tensile",
            Product::Table(crate::sample::paper_sample().to_table()),
        );
        let p = MaterialFitParams {
            model: Family::MooneyRivlin,
            compare: false,
            ..Default::default()
        }
        .check()
        .unwrap();
        let out = MaterialFit.run(&p, &inputs, &Context::new("fit")).unwrap();
        let c = table(&out, "comparison");
        assert_eq!(c.str("model").unwrap(), ["mooney-rivlin"]);
        assert_eq!(c.i64("selected").unwrap(), [1]);
        // Mooney–Rivlin has no α: params are c10, c01 with term 0.
        let params = table(&out, "params");
        assert_eq!(params.str("param").unwrap()[..2], ["c10", "c01"]);
        assert_eq!(params.str("unit").unwrap()[..2], ["Pa", "Pa"]);
    }

    #[test]
    fn families_that_cannot_be_fitted_are_listed_last_with_the_reason() {
        // Four points: ogden-3 … ogden-6 have too many parameters.
        let t = Table::new()
            .with("mode", vec!["UT", "UT", "BT", "BT"])
            .with("stretch", vec![1.2, 1.5, 1.1, 1.3])
            .with("nominal_stress_pa", vec![2e5, 4e5, 2.5e5, 6e5]);
        let inputs = Inputs::new().with("tensile", Product::Table(t));
        let p = MaterialFitParams {
            model: Family::NeoHookean,
            ..Default::default()
        }
        .check()
        .unwrap();
        let out = MaterialFit.run(&p, &inputs, &Context::new("fit")).unwrap();
        let c = table(&out, "comparison");
        let status = c.str("status").unwrap();
        let models = c.str("model").unwrap();
        assert_eq!(status.iter().filter(|s| *s == "ok").count(), 6);
        for (row, model) in models.iter().enumerate().skip(6) {
            assert!(model.starts_with("ogden-"), "{model}");
            assert!(
                status[row].contains("parameters need at least"),
                "{}",
                status[row]
            );
            assert!(c.f64("rms_rel_err").unwrap()[row].is_nan());
        }
        assert_eq!(c.i64("rank").unwrap(), (1..=10).collect::<Vec<i64>>());
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = |p: MaterialFitParams| p.check().unwrap_err().param;
        let p = MaterialFitParams::default();
        let unknown = MaterialFit
            .params_from_json(
                serde_json::json!({"model": "ogden-9"}),
                std::path::Path::new("."),
            )
            .unwrap_err();
        assert_eq!(unknown.param, "model");
        assert_eq!(
            bad(MaterialFitParams {
                starts: 0,
                ..p.clone()
            }),
            "starts"
        );
        let mut w = p.clone();
        w.weights.pt = -1.0;
        assert_eq!(bad(w), "weights.PT");
        let mut w = p.clone();
        w.weights = ModeWeights {
            ut: 0.0,
            pt: 0.0,
            bt: 0.0,
        };
        assert_eq!(bad(w), "weights");
    }
}
