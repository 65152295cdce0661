//! Stage `material-fit`: fits a strain-energy family to UT, PT and BT data at
//! once, reports per-mode quality, the fitted curves, the Drucker-stable
//! stretch ranges, and (optionally) the same for every family, ranked — the
//! way the paper chose its 6-term Ogden model in Abaqus.

use hypercontact_core::param::Choice;
use hypercontact_core::{
    Arity, Checked, Context, InputSpec, Inputs, OutputSpec, Outputs, ParamError, Product, Schema,
    Stage, StageError, StageInfo, Table, params,
};

use crate::bootstrap::Bootstrap;
use crate::bootstrap::{ReplicatesTable, replicates};
use crate::drucker_windows::{DEFAULT_COMPRESSION_STRETCH, DruckerWindows};
use crate::fit::FitResult;
use crate::fit::{Constraint, FitOptions, Residual, fit};
use crate::fit_tables::ComparisonRow;
pub use crate::fit_tables::{
    ComparisonTable, CurvesTable, ParamsTable, QualityTable, StabilityTable,
};
use crate::quality::quality;
use crate::stability::stability_ranges;
use crate::table::{MaterialTable, to_table};
use crate::tensile::{TensileData, TensilePoints};
use crate::{Family, Hyperelastic, MaterialError, Mode, Poisson};

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

/// Stretch windows where `constraint: in-range` imposes Drucker stability,
/// replacing the defaults mode by mode.
#[params(check = windows_hold_rest)]
pub struct WindowParams {
    /// uniaxial [lo, hi] (default: the UT data's stretches and λ = 1)
    #[param(range = 0.1..=10.0, rename = "UT")]
    pub ut: Option<[f64; 2]>,
    /// planar [lo, hi] (default: the PT data's stretches and λ = 1)
    #[param(range = 0.1..=10.0, rename = "PT")]
    pub pt: Option<[f64; 2]>,
    /// equibiaxial [lo, hi] (default: the BT data's stretches and λ = 1, down to `compression_stretch`)
    #[param(range = 0.1..=10.0, rename = "BT")]
    pub bt: Option<[f64; 2]>,
}

impl WindowParams {
    fn given(&self) -> [(Mode, Option<[f64; 2]>); 3] {
        [
            (Mode::Uniaxial, self.ut),
            (Mode::Planar, self.pt),
            (Mode::Equibiaxial, self.bt),
        ]
    }
}

fn windows_hold_rest(w: &WindowParams) -> Result<(), ParamError> {
    for (mode, window) in w.given() {
        if let Some([lo, hi]) = window.filter(|[lo, hi]| !(*lo <= 1.0 && 1.0 <= *hi)) {
            return Err(ParamError::new(
                mode.label(),
                format!("[{lo}, {hi}] must hold λ = 1 (lo ≤ 1 ≤ hi)"),
            ));
        }
    }
    Ok(())
}

/// Bootstrap replicates of the fit (see [`crate::bootstrap`]).
#[params]
pub struct BootstrapParams {
    /// number of refits on resampled data (0: none)
    #[param(default = 0, range = 0..=100000)]
    pub count: usize,
    /// seed of the resampling (replicate r draws from stream r)
    #[param(default = 1)]
    pub seed: u64,
    /// seeded starts per refit, beside the full-data optimum it starts from
    #[param(default = 4, range = 0..=1000)]
    pub starts: usize,
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
    /// stable (all moduli ≥ 0, Drucker-stable at every stretch), in-range (Drucker-stable on the windows, imposed in the fit) or none
    #[param(default = Constraint::Stable)]
    pub constraint: Constraint,
    /// lower end of the default equibiaxial window of `in-range` (BT compression)
    #[param(default = DEFAULT_COMPRESSION_STRETCH, range = 0.1..=1.0)]
    pub compression_stretch: f64,
    /// explicit windows of `in-range`, e.g. { BT: [0.5, 2.0] }
    #[param(default = WindowParams::default())]
    pub windows: WindowParams,
    /// number of starts for Ogden and Arruda–Boyce (deterministic)
    #[param(default = 64, range = 1..=1000)]
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
    /// refits on resampled data, carried downstream as `replicates`
    #[param(default = BootstrapParams::default())]
    pub bootstrap: BootstrapParams,
}

impl MaterialFitParams {
    pub fn options(&self) -> FitOptions {
        FitOptions {
            residual: self.residual,
            constraint: self.constraint,
            starts: self.starts,
            weights: [self.weights.ut, self.weights.pt, self.weights.bt],
            seed: self.seed,
            ..FitOptions::default()
        }
    }

    /// The windows of `in-range` for `data`: the defaults from the data
    /// fitted, replaced mode by mode by `windows`.
    pub fn drucker_windows(&self, data: &TensileData) -> DruckerWindows {
        let weights = [self.weights.ut, self.weights.pt, self.weights.bt];
        let mut windows = DruckerWindows::from_data(data, weights, self.compression_stretch);
        for (mode, window) in self.windows.given() {
            if let Some([lo, hi]) = window {
                windows = windows.with(mode, (lo, hi));
            }
        }
        windows
    }
}

/// The `material-fit` stage.
pub struct MaterialFit;

static INFO: StageInfo = StageInfo {
    kind: "material-fit",
    version: 4,
    summary: "Fit a hyperelastic model to UT, PT and BT data at once; quality, stability, \
              comparison, bootstrap",
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
          the model; so is data with fewer points than parameters. Ogden terms are written in \
          ascending α. \
          `constraint: stable` (the default) holds every modulus ≥ 0 (Ogden μ_i in the Abaqus \
          convention, Mooney–Rivlin C10 and C01, Yeoh C10…C30, neo-Hookean and Arruda–Boyce \
          μ): each Ogden term is then convex in the log strains, so the model is Drucker-stable \
          at every stretch by construction, and the moduli are non-negative least squares \
          (Lawson–Hanson) inside the same search. It is the default because the unconstrained \
          optimum of a many-term Ogden fit is ill-conditioned: its μ_i come out as huge numbers \
          of both signs that cancel (±5e14 Pa on Treloar's data, ±5e9 Pa in the paper's own \
          Table 1), move with any change of the data, cannot be read or reused, and can turn \
          unstable just outside the data (the contact models evaluate the equibiaxial law in \
          compression, beyond every tensile test). The price is a larger error where the data \
          want cancelling terms: the `comparison` table fits every family under each \
          constraint and the stage notes the chosen family's RMS error under each. α is not \
          bounded: with μ_i ≥ 0 a large α is as stable as a small one, and the data decide. \
          `constraint: none` is Abaqus' plain least squares (the paper's fit). \
          `constraint: in-range` imposes Drucker stability inside the fit, over stated stretch \
          windows rather than at every stretch: for each trial shape the moduli are least \
          squares subject to the log-strain Hessian being positive definite (smallest \
          eigenvalue at least 1e-6 of the largest measured stress) on a geometric grid of each \
          window (Lawson–Hanson LSI, constraints added by cutting planes where the grid shows a \
          violation; 64 stretches per window during the search, 2000 for each converged start), \
          and the shape search's Jacobian is a forward difference. μ_i ≥ 0 is sufficient for \
          stability, not necessary where the material is used: the paper's own Table 1 cancels \
          at ±5e9 Pa and is Drucker-stable over the data, and in-range recovers it from its \
          synthetic tests (μ0 within 0.1 % of 1.79 MPa, RMS at the 0.5 % noise) where `stable` \
          keeps a single term (RMS 9.2 % on the shipped sample). It does not cure the \
          ill-conditioning: where the data want cancelling moduli it keeps them (±5e12 Pa in \
          the 6-term fit to Treloar's data), and assures only their stability on the windows. \
          The default windows are each fitted mode's data range \
          extended to λ = 1, and equibiaxial compression down to `compression_stretch` (0.6): \
          the paper pipeline's deepest mean contact stress is −4.9 MPa with its in-range fit \
          and −7.9 MPa with the softer `stable` one (Greenwood–Williamson on T1 at 95 % \
          contact), and with the paper's Table 1 material φ(0.64) ≈ −7.0 MPa and \
          φ(0.6) ≈ −9.9 MPa, so 0.6 covers it; the paper's material itself is Drucker-unstable \
          below λ ≈ 0.56 in BT. `windows: { UT: [lo, hi], PT: .., BT: .. }` replaces a mode's \
          window (0.1 ≤ lo ≤ 1 ≤ hi ≤ 10). Bootstrap refits and the comparison's in-range rows \
          use the windows of the full data set. The `quality` \
          table gives the fit's condition number (its Jacobian in the free parameters, columns \
          scaled to unit length) and the largest parameter correlation. \
          `bootstrap: {count, seed, starts}` refits `count` resampled data sets (each mode's \
          points drawn with replacement, as many as it has: the pairs bootstrap, which unlike \
          resampling residuals does not assume the family is the true law), each from the \
          full-data optimum plus `starts` seeded starts, in parallel and the same on any \
          thread count; `replicates` holds every refit's material for the contact models, \
          which then write 5–95 % bands, and `params` gains each parameter's 5–95 % interval (none \
          for an Ogden term held at μ_i = 0, neither μ_i nor its α_i). \
          Stability, as Abaqus checks it: Drucker's condition dσ:dε > 0 for every \
          volume-keeping increment of log strain (true stress against log strain), i.e. the \
          Hessian of W in the log strains (ε1, ε2) is positive definite, checked along UT, PT \
          and BT for 0.1 ≤ λ ≤ 10; `stability` gives the interval around λ = 1 where it holds \
          (λ < 1 is compression), flags a limit that is the search range's edge (0.1 or 10: \
          stable that far, not an instability found), gives the windows imposed under \
          `in-range` (NaN otherwise), and beside it the interval where the nominal stress rises \
          (dT/dλ > 0), which is where a load-controlled test is stable and, in BT, where the \
          paper's φ can be inverted. For the paper's Table 1 material the BT nominal stress φ \
          peaks at λ ≈ 1.46 (ε ≈ 0.46) and falls until λ ≈ 2; the Drucker condition itself \
          holds in BT tension up to λ ≈ 4.4 but fails in equibiaxial compression below \
          λ ≈ 0.56 (ε ≈ −0.44; the same state as UT tension beyond λ ≈ 3.2). Contact uses the \
          compressive branch: the contact stress is compressive, so the incremental contact \
          model evaluates ε = φ⁻¹(S) at S = −F/A < 0 (ε < 0), where φ rises monotonically. \
          `comparison` fits every family (ogden-1…6, neo-hookean, mooney-rivlin, yeoh, \
          arruda-boyce) to the same data under each constraint (stable, none, in-range) and \
          ranks them by total RMS relative error (each mode's beside it), with their stable \
          ranges, so the choice of \
          model and what each constraint costs can be read as the paper did; a note gives the \
          chosen family's RMS error under each constraint.",
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
        OutputSpec::table::<StabilityTable>(
            "stability",
            "Drucker-stable stretch range per mode, whether a limit is the search range's edge, \
             and the windows imposed",
        ),
        OutputSpec::table::<ComparisonTable>(
            "comparison",
            "every family fitted to the same data under each constraint (stable, none, \
             in-range), ranked (only the chosen family if compare: false)",
        ),
        OutputSpec::table::<ReplicatesTable>(
            "replicates",
            "the material of every bootstrap refit (no rows without `bootstrap`), for the \
             contact models' bands",
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
    /// Parallel (rayon) over its work: a few cores pay off on a cluster.
    const RESOURCES: hypercontact_core::Resources = hypercontact_core::Resources::PARALLEL;

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
        // Windows from the full data set: the replicates and the
        // comparison's in-range fits are held to the same ones.
        let options = FitOptions {
            windows: Some(p.drucker_windows(&data)),
            ..p.options()
        };
        let chosen = fit(&data, family, &options).map_err(StageError::other)?;
        let model = chosen.model.as_ref();
        let qualities = quality(model, &data);
        let stability = stability_ranges(model);
        if let Some(all) = qualities.last() {
            ctx.note(&format!(
                "{} ({}): RMS relative error {:.3} % over {} points ({}/{} starts converged; \
                 condition number {:.3e}){}",
                family.name(),
                p.constraint.name(),
                100.0 * all.rms_rel_err,
                all.n_points,
                chosen.starts_converged,
                chosen.starts_run,
                chosen.conditioning.condition_number,
                chosen.windows.as_ref().map_or(String::new(), |w| format!(
                    "; Drucker stability imposed on {}",
                    w.describe()
                ))
            ));
        }
        for s in stability.iter().filter(|s| !s.stable_everywhere()) {
            ctx.note(&format!("{}: {}", s.mode, s.describe()));
        }

        let fitted = bootstrap(p, &data, &chosen, &options, ctx);
        let replicate_models: Vec<(i64, &dyn Hyperelastic)> = fitted
            .iter()
            .zip(1..)
            .filter_map(|(m, r)| m.as_ref().ok().map(|m| (r, m.as_ref())))
            .collect();

        let comparison = compare(p, &data, &chosen, &options, ctx);
        let params = ParamsTable::new(family, model, p.poisson.0)
            .with_intervals(replicate_models.iter().map(|(_, m)| *m), p.poisson.0);
        Ok(Outputs::new()
            .table("material", to_table(model))
            .table("params", params.into_table())
            .table(
                "quality",
                QualityTable::new(&qualities, &chosen.conditioning).into_table(),
            )
            .table("curves", CurvesTable::new(model, &data).into_table())
            .table(
                "stability",
                StabilityTable::new(&stability, chosen.windows.as_ref()).into_table(),
            )
            .table("comparison", comparison.into_table())
            .table(
                "replicates",
                ReplicatesTable::new(replicate_models.iter().copied()).into_table(),
            ))
    }
}

/// The bootstrap refits `p.bootstrap` asks for (none for count 0), with a
/// progress bar and a note on how many failed.
fn bootstrap(
    p: &MaterialFitParams,
    data: &TensileData,
    chosen: &FitResult,
    options: &FitOptions,
    ctx: &Context,
) -> Vec<Result<Box<dyn Hyperelastic>, MaterialError>> {
    let b = &p.bootstrap;
    if b.count == 0 {
        return Vec::new();
    }
    let bar = ctx.progress(b.count as u64, "bootstrap refits");
    let plan = Bootstrap {
        count: b.count,
        seed: b.seed,
        starts: b.starts,
    };
    let fitted = replicates(data, chosen, options, plan, &|| bar.inc(1));
    let failed: Vec<String> = fitted
        .iter()
        .zip(1..)
        .filter_map(|(m, r)| m.as_ref().err().map(|e| format!("{r}: {e}")))
        .collect();
    ctx.note(&format!(
        "bootstrap: {} of {} refits on resampled points (pairs within each mode) succeeded{}",
        b.count - failed.len(),
        b.count,
        match failed.first() {
            Some(first) => format!("; left out, e.g. replicate {first}"),
            None => String::new(),
        }
    ));
    fitted
}

/// The comparison table: every family (or only the chosen one) under each
/// constraint, ranked; a note gives the chosen family's RMS error under
/// each.
fn compare(
    p: &MaterialFitParams,
    data: &TensileData,
    chosen: &FitResult,
    options: &FitOptions,
    ctx: &Context,
) -> ComparisonTable {
    let families = if p.compare {
        Family::all()
    } else {
        vec![p.model]
    };
    let constraints = [Constraint::Stable, Constraint::Free, Constraint::InRange];
    let bar = ctx.progress(
        (constraints.len() * families.len()) as u64,
        "model comparison",
    );
    let mut rows = Vec::new();
    for family in families {
        for constraint in constraints {
            let selected = family == p.model && constraint == p.constraint;
            bar.set_message(&format!(
                "fitting {} ({})",
                family.name(),
                constraint.name()
            ));
            rows.push(if selected {
                ComparisonRow::from_fit(chosen, data, constraint, true)
            } else {
                let settings = FitOptions {
                    constraint,
                    ..options.clone()
                };
                match fit(data, family, &settings) {
                    Ok(result) => ComparisonRow::from_fit(&result, data, constraint, false),
                    Err(e) => ComparisonRow::failed(family, constraint, e.to_string()),
                }
            });
            bar.inc(1);
        }
    }
    let table = ComparisonTable::ranked(rows);
    let rms = |constraint: Constraint| {
        (0..table.model.len())
            .find(|&i| table.model[i] == p.model.name() && table.constraint[i] == constraint.name())
            .map_or(f64::NAN, |i| table.rms_rel_err[i])
    };
    let each: Vec<String> = constraints
        .iter()
        .map(|&c| format!("{:.3} % {}", 100.0 * rms(c), c.name()))
        .collect();
    ctx.note(&format!(
        "{}: RMS relative error {}",
        p.model.name(),
        each.join(", ")
    ));
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params, Product};

    /// The shipped 150-point sample as the stage's `tensile` input.
    fn sample_inputs() -> Inputs {
        Inputs::new().with(
            "tensile",
            Product::Table(crate::sample::paper_sample().to_table()),
        )
    }

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
        assert_eq!(comparison.n_rows(), 3 * Family::all().len());
        let rms = comparison.f64("rms_rel_err").unwrap();
        assert!(rms.windows(2).all(|w| w[0] <= w[1]), "{rms:?}");
        let selected = comparison.i64("selected").unwrap();
        assert_eq!(selected.iter().sum::<i64>(), 1);
        let chosen = selected.iter().position(|s| *s == 1).unwrap();
        assert_eq!(comparison.str("constraint").unwrap()[chosen], "stable");
        // Each family once under each setting; the constraint never lowers
        // the error below the unconstrained optimum (1e-9: two searches).
        let (models, constraints) = (
            comparison.str("model").unwrap(),
            comparison.str("constraint").unwrap(),
        );
        for family in Family::all() {
            let row = |c: &str| {
                (0..models.len())
                    .find(|&i| models[i] == family.name() && constraints[i] == c)
                    .unwrap()
            };
            assert!(rms[row("none")] <= rms[row("stable")] * (1.0 + 1e-9));
            // in-range lies between: μ ≥ 0 is stable on any window. (Below
            // the free optimum only by a free search stopping short.)
            assert!(rms[row("in-range")] <= rms[row("stable")] * (1.0 + 1e-9));
            assert!(rms[row("in-range")] >= rms[row("none")] * 0.99);
        }
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
        assert_eq!(p.starts, 64);
        assert_eq!(p.constraint, Constraint::Stable);
        assert_eq!(p.bootstrap.count, 0);
        p.check().unwrap();
        let typo = serde_json::from_value::<MaterialFitParams>(serde_json::json!({"wieghts": {}}));
        assert!(typo.unwrap_err().to_string().contains("wieghts"));
        let mode =
            serde_json::from_value::<MaterialFitParams>(serde_json::json!({"weights": {"ET": 1}}));
        assert!(mode.is_err());
    }

    #[test]
    fn register_adds_the_four_stages() {
        let mut registry = hypercontact_core::Registry::new();
        crate::register(&mut registry);
        let kinds: Vec<&str> = registry.kinds().collect();
        assert_eq!(
            kinds,
            [
                "material",
                "material-fit",
                "material-preset",
                "tensile-table"
            ]
        );
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

    /// The sample fitted with Mooney–Rivlin alone (`compare: false`).
    fn fit_mooney_rivlin(bootstrap: BootstrapParams) -> Outputs {
        let p = MaterialFitParams {
            model: Family::MooneyRivlin,
            compare: false,
            bootstrap,
            ..Default::default()
        }
        .check()
        .unwrap();
        MaterialFit
            .run(&p, &sample_inputs(), &Context::new("fit"))
            .unwrap()
    }

    #[test]
    fn bootstrap_writes_every_replicate_and_intervals_around_the_fit() {
        let out = fit_mooney_rivlin(BootstrapParams {
            count: 40,
            seed: 5,
            starts: 1,
        });
        let reps = crate::bootstrap::from_replicates_table(table(&out, "replicates")).unwrap();
        assert_eq!(reps.len(), 40);
        assert_eq!(reps.last().unwrap().0, 40);
        let params = table(&out, "params");
        let (value, p05, p95) = (
            params.f64("value").unwrap(),
            params.f64("p05").unwrap(),
            params.f64("p95").unwrap(),
        );
        let mu0 = params
            .str("param")
            .unwrap()
            .iter()
            .position(|n| n == "mu0")
            .unwrap();
        // μ0 of the full data lies inside its own bootstrap interval, which
        // is narrow: 150 points at 0.5 % noise (a misfitting 2-parameter
        // family, so wider than the noise alone).
        assert!(
            p05[mu0] < value[mu0] && value[mu0] < p95[mu0],
            "{p05:?} {value:?} {p95:?}"
        );
        assert!((p95[mu0] - p05[mu0]) / value[mu0] < 0.05);
        // Without a bootstrap: no rows, NaN intervals.
        let out = fit_mooney_rivlin(BootstrapParams::default());
        assert_eq!(table(&out, "replicates").n_rows(), 0);
        assert!(
            table(&out, "params")
                .f64("p05")
                .unwrap()
                .iter()
                .all(|v| v.is_nan())
        );
    }

    #[test]
    fn compare_false_gives_one_comparison_row() {
        let out = fit_mooney_rivlin(BootstrapParams::default());
        let c = table(&out, "comparison");
        assert_eq!(c.str("model").unwrap(), ["mooney-rivlin"; 3]);
        let selected = c.i64("selected").unwrap();
        assert_eq!(selected.iter().sum::<i64>(), 1);
        assert_eq!(
            c.str("constraint").unwrap()[selected.iter().position(|s| *s == 1).unwrap()],
            "stable"
        );
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
        assert_eq!(status.iter().filter(|s| *s == "ok").count(), 18);
        for (row, model) in models.iter().enumerate().skip(18) {
            assert!(model.starts_with("ogden-"), "{model}");
            assert!(
                status[row].contains("parameters need at least"),
                "{}",
                status[row]
            );
            assert!(c.f64("rms_rel_err").unwrap()[row].is_nan());
        }
        assert_eq!(c.i64("rank").unwrap(), (1..=30).collect::<Vec<i64>>());
    }

    #[test]
    fn e0_and_e0_star_follow_poisson() {
        let inputs = sample_inputs();
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

    #[test]
    fn bad_windows_are_refused_by_name() {
        let bad = |v: serde_json::Value| {
            MaterialFit
                .params_from_json(v, std::path::Path::new("."))
                .unwrap_err()
        };
        let e = bad(serde_json::json!({"windows": {"UT": [1.2, 3.0]}}));
        assert_eq!(e.param, "windows.UT");
        assert!(e.message.contains("lo ≤ 1 ≤ hi"), "{e:?}");
        let e = bad(serde_json::json!({"windows": {"BT": [0.05, 2.0]}}));
        assert!(e.param.starts_with("windows.BT"), "{e:?}");
        let e = bad(serde_json::json!({"compression_stretch": 1.5}));
        assert_eq!(e.param, "compression_stretch");
        let p: MaterialFitParams = serde_json::from_value(serde_json::json!({
            "constraint": "in-range",
            "windows": {"PT": [0.5, 3.0]},
            "compression_stretch": 0.7,
        }))
        .unwrap();
        assert_eq!(p.constraint, Constraint::InRange);
        let w = p.drucker_windows(&crate::sample::paper_sample());
        assert_eq!(w.get(Mode::Planar), Some((0.5, 3.0)));
        assert_eq!(w.get(Mode::Equibiaxial).unwrap().0, 0.7);
    }

    #[test]
    fn in_range_writes_its_windows_and_marks_range_edges() {
        let p = MaterialFitParams {
            model: Family::Ogden(2),
            constraint: Constraint::InRange,
            compare: false,
            starts: 8,
            ..Default::default()
        }
        .check()
        .unwrap();
        let out = MaterialFit
            .run(&p, &sample_inputs(), &Context::new("fit"))
            .unwrap();
        let t = StabilityTable::from_table(table(&out, "stability")).unwrap();
        assert_eq!(t.window_min, [1.0, 1.0, 0.6]);
        assert_eq!(t.window_max, [2.5, 2.0, 1.4]);
        for row in 0..3 {
            assert!(t.lambda_min[row] <= t.window_min[row], "{t:?}");
            assert!(t.lambda_max[row] >= t.window_max[row], "{t:?}");
            // The edge flags say exactly when a limit is the search range.
            assert_eq!(t.lambda_min_at_edge[row] == 1, t.lambda_min[row] <= 0.1);
            assert_eq!(t.lambda_max_at_edge[row] == 1, t.lambda_max[row] >= 10.0);
            if t.lambda_max_at_edge[row] == 1 {
                assert!(
                    t.note[row].contains("edge of the search range (λ = 10)"),
                    "{}",
                    t.note[row]
                );
            }
        }
        let c = ComparisonTable::from_table(table(&out, "comparison")).unwrap();
        assert_eq!(c.constraint.len(), 3);
        // Per-mode errors: 50 points in each mode, so the overall mean
        // square is the mean of the modes'.
        for row in 0..3 {
            let modes = [
                c.ut_rms_rel_err[row],
                c.pt_rms_rel_err[row],
                c.bt_rms_rel_err[row],
            ];
            let mean_square = modes.iter().map(|r| r * r).sum::<f64>() / 3.0;
            assert!(
                (mean_square.sqrt() / c.rms_rel_err[row] - 1.0).abs() < 1e-12,
                "{modes:?} vs {}",
                c.rms_rel_err[row]
            );
        }
        // Without in-range the windows are NaN, and a model stable at every
        // stretch is reported at both edges, not as a finding.
        let out = fit_mooney_rivlin(BootstrapParams::default());
        let t = StabilityTable::from_table(table(&out, "stability")).unwrap();
        assert!(t.window_min.iter().chain(&t.window_max).all(|v| v.is_nan()));
        assert_eq!(t.lambda_min_at_edge, [1, 1, 1]);
        assert_eq!(t.lambda_max_at_edge, [1, 1, 1]);
        assert!(t.note[0].contains("down to the edge of the search range (λ = 0.1)"));
    }

    #[test]
    fn dead_ogden_terms_get_no_bootstrap_interval() {
        // Under `stable` the paper's data take one live term (see fit.rs):
        // the dead terms' μ_i and α_i get no interval, the live one does.
        let p = MaterialFitParams {
            model: Family::Ogden(2),
            compare: false,
            starts: 8,
            bootstrap: BootstrapParams {
                count: 8,
                seed: 2,
                starts: 1,
            },
            ..Default::default()
        }
        .check()
        .unwrap();
        let out = MaterialFit
            .run(&p, &sample_inputs(), &Context::new("fit"))
            .unwrap();
        let t = ParamsTable::from_table(table(&out, "params")).unwrap();
        let dead: Vec<i64> = (0..t.value.len())
            .filter(|&r| t.param[r].starts_with("mu_") && t.value[r] == 0.0)
            .map(|r| t.term[r])
            .collect();
        assert_eq!(dead.len(), 1, "{t:?}");
        for row in 0..t.value.len() {
            let has_interval = !t.p05[row].is_nan() && !t.p95[row].is_nan();
            assert_eq!(has_interval, !dead.contains(&t.term[row]), "{t:?}");
        }
    }
}
