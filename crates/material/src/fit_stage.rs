//! Stage `material-fit`: fits a strain-energy family to UT, PT and BT data at
//! once, reports per-mode quality, the fitted curves, the Drucker-stable
//! stretch ranges, and (optionally) the same for every family, ranked — the
//! way the paper chose its 6-term Ogden model in Abaqus.

use hypercontact_core::{
    Arity, Checked, Context, InputSpec, Inputs, OutputSpec, Outputs, ParamError, Product, Schema,
    Stage, StageError, StageInfo, Table, params,
};

use crate::fit::{FitOptions, Residual, fit};
use crate::fit_tables::ComparisonRow;
pub use crate::fit_tables::{
    ComparisonTable, CurvesTable, ParamsTable, QualityTable, StabilityTable,
};
use crate::quality::quality;
use crate::stability::stability_ranges;
use crate::table::{MaterialTable, to_table};
use crate::tensile::{TensileData, TensilePoints};
use crate::{Family, Poisson};

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
    /// Poisson's ratio ν of the derived moduli e0 and e0_star
    #[param(default = Poisson::INCOMPRESSIBLE)]
    pub poisson: Poisson,
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

/// The `material-fit` stage.
pub struct MaterialFit;

static INFO: StageInfo = StageInfo {
    kind: "material-fit",
    version: 2,
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
    inputs: &[InputSpec::table::<TensilePoints>(
        "tensile",
        Arity::OneOrMore,
        "UT/PT/BT stress–stretch data (tensile-table or the DIC stage): one table \
         (`tensile: csv`) or several fitted together (`tensile: { UT: dic-ut, PT: dic-pt }`)",
    )],
    outputs: &[
        OutputSpec::table::<MaterialTable>(
            "material",
            "the fitted model, for downstream stages (the ICM reads it)",
        ),
        OutputSpec::table::<ParamsTable>(
            "params",
            "fitted parameters and the derived initial moduli",
        ),
        OutputSpec::table::<QualityTable>("quality", "fit quality per mode and over all points"),
        OutputSpec::table::<CurvesTable>(
            "curves",
            "measured and fitted stress at every measured stretch",
        ),
        OutputSpec::table::<StabilityTable>("stability", "Drucker-stable stretch range per mode"),
        OutputSpec::table::<ComparisonTable>(
            "comparison",
            "every family fitted to the same data, ranked (only the chosen one if compare: false)",
        ),
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

        let params = ParamsTable::new(family, model, p.poisson.0);
        Ok(Outputs::new()
            .table("material", to_table(model))
            .table("params", params.into_table())
            .table("quality", QualityTable::from(&qualities[..]).into_table())
            .table("curves", CurvesTable::new(model, &data).into_table())
            .table(
                "stability",
                StabilityTable::from(&stability[..]).into_table(),
            )
            .table("comparison", ComparisonTable::ranked(rows).into_table()))
    }
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
    fn a_first_ut_row_at_the_reference_state_fits_and_compares() {
        // `UT,1.0,0` (λ = 1, T = 0) leading the table once made ogden-6,
        // and with it the whole comparison, panic in the SVD.
        let mut data = crate::sample::paper_sample();
        data.curves[0].stretch.insert(0, 1.0);
        data.curves[0].stress_pa.insert(0, 0.0);
        let inputs = Inputs::new().with("tensile", Product::Table(data.to_table()));
        let p = MaterialFitParams::default().check().unwrap();
        let out = MaterialFit.run(&p, &inputs, &Context::new("fit")).unwrap();
        let c = table(&out, "comparison");
        assert!(
            c.str("status").unwrap().iter().all(|s| s == "ok"),
            "{:?}",
            c.str("status").unwrap()
        );
        assert_eq!(table(&out, "curves").n_rows(), 151);
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
    fn e0_and_e0_star_follow_poisson() {
        let inputs = Inputs::new().with(
            "tensile",
            Product::Table(crate::sample::paper_sample().to_table()),
        );
        let run = |poisson: f64| {
            let p = MaterialFitParams {
                model: Family::NeoHookean,
                compare: false,
                poisson: Poisson(poisson),
                ..Default::default()
            }
            .check()
            .unwrap();
            let out = MaterialFit.run(&p, &inputs, &Context::new("fit")).unwrap();
            let params = ParamsTable::from_table(table(&out, "params")).unwrap();
            let row =
                |name: &str| params.value[params.param.iter().position(|p| p == name).unwrap()];
            (row("mu0"), row("e0"), row("e0_star"))
        };
        let (mu0, e0, e0_star) = run(0.5);
        // The numbers written before ν became a parameter: E0 = 3 μ0, E0* = E0 / 0.75.
        assert_eq!(e0, 3.0 * mu0);
        assert_eq!(e0_star, 3.0 * mu0 / 0.75);
        assert_eq!(e0_star, crate::composite_modulus_pa(mu0, 0.5));
        let (mu0_03, e0, e0_star) = run(0.3);
        assert_eq!(mu0_03, mu0);
        assert_eq!(e0, 2.0 * mu0 * 1.3);
        assert_eq!(e0_star, crate::composite_modulus_pa(mu0, 0.3));
        assert!((e0_star / mu0 - 2.6 / 0.91).abs() < 1e-12, "{e0_star}");
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
        let poisson = |poisson| MaterialFitParams {
            poisson: Poisson(poisson),
            ..p.clone()
        };
        assert_eq!(bad(poisson(0.6)), "poisson");
        assert_eq!(bad(poisson(-0.1)), "poisson");
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
