//! Stage `report`: the paper's Figs. 2, 4, 7 and 8, its Table 1, the model
//! comparison and a per-sample summary, as one `Files` product `report`
//! (`index.html`, `figN.png`, `figN.svg`, `summary.json`).

use hypercontact_compare::stage::{AgreementTable, FigureIndex, LoadRatioTable, TransformTable};
use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::{BandTable, ResponseTable};
use hypercontact_core::{
    Arity, Checked, Context, InputSpec, Inputs, OutputSpec, Outputs, ProductKind, Stage,
    StageError, StageInfo, params,
};
use hypercontact_material::fit_stage::{
    ComparisonTable, CurvesTable, ParamsTable, QualityTable, StabilityTable,
};
use hypercontact_material::table::MaterialTable;
use hypercontact_surface::surface_stage::{
    AcfTable, ArealTable, DistributionsTable, MaterialRatioTable, PsdTable, ScaleDependentTable,
    StatsTable,
};
use hypercontact_truncation::stage::ProfileTable;

use hypercontact_material::Poisson;
use hypercontact_material::presets::Preset;

use crate::report::{ModelChoice, ReportOptions, render_report};

/// Parameters of `report`.
#[params]
pub struct ReportParams {
    /// the page title
    #[param(default = ReportOptions::default().title, check = not_blank)]
    pub title: String,
    /// A/A0 values at which the summary reads F/(E0* A0) (1 to 10 of them)
    #[param(default = ReportOptions::default().area_fractions, positive, range = ..=1.0, check = one_to_ten)]
    pub area_fractions: Vec<f64>,
    /// Poisson's ratio ν of Table 1's E0 and E0*: that of the contact model
    /// whose responses are wired
    #[param(default = Poisson::INCOMPRESSIBLE)]
    pub poisson: Poisson,
    /// the contact models' order in legends and colours, by their labels in `responses` (labels not listed follow in label order); a model's colour is its family's (the label's text before its first `-`)
    #[param(default = Vec::new())]
    pub models: Vec<String>,
    /// the models Fig. 7 draws, by label (none listed: every wired model)
    #[param(default = Vec::new())]
    pub fig7_models: Vec<String>,
    /// the models Fig. 9 compares side by side, by label (none listed: every wired model)
    #[param(default = Vec::new())]
    pub fig9_models: Vec<String>,
    /// the models whose loads the per-sample summary table shows, by label (none listed: the first model)
    #[param(default = Vec::new())]
    pub summary_models: Vec<String>,
    /// the model every other model's load is divided by at equal A/A0 in the load-ratio table (unset: no table)
    pub reference_model: Option<String>,
    /// the label of the finite-element reference in `finite_strain`, that every other curve there is divided by
    #[param(default = "fem".to_owned())]
    pub finite_strain_reference: String,
    /// A/A0 at which the finite-strain table reads F_model / F_reference (1 to 10 of them)
    #[param(default = vec![0.05, 0.1, 0.2, 0.3], positive, range = ..=1.0, check = one_to_ten)]
    pub finite_strain_area_fractions: Vec<f64>,
    /// A/A0 at which the refinement study compares fem and bem at equal area, and (where the finest bem reaches them) at equal approach (1 to 10 of them)
    #[param(default = vec![0.05, 0.1, 0.2], positive, range = ..=1.0, check = one_to_ten)]
    pub refinement_area_fractions: Vec<f64>,
    /// points per shortest wavelength at refine factor 1 in the refinement study (the surface's filter wavelength over its spacing; refine k gives k times it)
    #[param(default = 2.0, positive)]
    pub refinement_points_per_wavelength: f64,
    /// a published material set beside the fit in Table 1 with its error on the same tensile data, not refitted (`paper-epdm`: the paper's Table 1; unset: none)
    pub published_material: Option<Preset>,
}

fn not_blank(title: &str) -> Result<(), String> {
    if title.trim().is_empty() {
        Err("must not be empty".into())
    } else {
        Ok(())
    }
}

fn one_to_ten(values: &[f64]) -> Result<(), String> {
    if (1..=10).contains(&values.len()) {
        Ok(())
    } else {
        Err(format!("needs 1 to 10 values, got {}", values.len()))
    }
}

/// The `report` stage.
pub struct Report;

static INFO: StageInfo = StageInfo {
    kind: "report",
    version: 15,
    summary: "HTML report with the paper's Figs. 2, 4, 6, 7, 8, a model comparison (Fig. 9; PNG + \
              SVG), Table 1 and a summary",
    doc: "Every input is optional: a figure whose inputs are not wired is skipped and the \
          page says why (e.g. a pipeline without the tensile branch still gets Figs. 4, 7 \
          and 8). Per-sample inputs are labelled by sample (`stats: {T1: s1, ...}`); one \
          sample gets one colour in every single-panel figure. The contact models are a role: \
          `responses` takes any number of them per sample, labelled by sample and then by \
          model (`responses: {T1: {icm: a, bem: b}}`), and `bands` and `model_summaries` \
          likewise; a model's label is its legend name, its colour comes from a fixed \
          palette by the order of the labels (parameter `models`, then label order; labels \
          `x` and `x-...` share a family's colour), and its stroke from its law as the data \
          say (a response whose tangent_ratio is 1 everywhere is linear: dashed). Fig. 2 \
          needs `curves` (R² from `quality`, limits from `stability`); Fig. 4 any of \
          `heights`, `psd`, `profiles` (the H of the drawn power law comes from `stats` when \
          wired, otherwise from a log-log least-squares fit); the surface stage's \
          statistics per sample (`areal`, `material_ratio`, `acf`, `scale_dependent`, \
          `distributions`, each optional) give a table of the ISO 25178-2 areal parameters \
          (one column per sample, lengths in µm), Fig. 4b (the Abbott–Firestone curve with \
          the ISO 13565-2 core band, equivalence line, Smr1 and Smr2), Fig. 4c (the ACF \
          radially averaged and along x and y, with the 1/e and s = 0.2 levels, up to six \
          correlation lengths), Fig. 4d (rms slope and curvature against scale, log–log) and \
          Fig. 4e (height and slope densities); a sample without one of them is named in a \
          note, and a figure none of whose inputs is wired is skipped with the reason; Fig. 7 the `fig7_models` \
          (default every wired model) with the measured points of `experiments` \
          (contact-images' contact, the force over the models' E0* A0) and the agreement \
          table of `agreement` and `load_ratio` (contact-compare) under it (a model \
          contact-compare marked by_construction, its physics the experiment's, shows \
          \"by construction\" in place of a rank, after the ranked ones; the captions of \
          Figs. 7 and 9 and the experiment's section name the experiment's physics from the \
          tables' experiment_physics column, and the models that share it), then each \
          model's load over `reference_model`'s at `area_fractions` where that is set; Fig. \
          6 the first sample's `compare_figures` (observed, predicted and overlay maps at one \
          scale with a bar, read through contact-compare's figure index) with the \
          registrations of `transforms`; Fig. 8 every model whose tangent_ratio is not 1 \
          throughout; Fig. 9 the `fig9_models` side by side with the experiment, with a \
          table of kappa = (A/A0)/(F/(A0 E0* h'rms)) per model at A/A0 = 0.02 and 0.1 (h'rms \
          from `stats`, one yardstick for every model; read off each curve by linear \
          interpolation in A/A0, n/a outside it) and each model's `model_summaries` table \
          (one row: what it was given) as it is. A label in a model parameter that no \
          response is wired under stops the stage, naming the parameter, the label and the \
          wired ones. `bands` (a model's bootstrap bands; a table without rows is no band) \
          shades the 5–95 % band of F/(E0* A0) under the curves of Figs. 7 and 9 and of \
          E_t*/E0* under Fig. 8's (opacity 0.2; sample colour in single panels, the model's in per-sample \
          panels; points at or below zero left off the log axis), with a legend entry. \
          Table 1 decodes `material` and gives its initial moduli μ0, E0 and E0* at \
          Poisson's ratio `poisson`; with `params` wired, each parameter and modulus with its \
          5–95 % bootstrap interval where finite (none for an Ogden term held at μ_i = 0, \
          which moves nothing); with `comparison` wired, a table of what each constraint \
          costs: the same family under every setting of material-fit's `constraint` (the \
          adopted one first) with its RMS relative error over all points and per mode, the \
          largest, μ0 and the condition number; with `published_material`, that material \
          (not refitted) on the same measured curves as a last row, and its parameters as a \
          table of their own. Fig. 2 draws the measured curves as lines and the fitted model \
          as symbols, as the paper's caption says. One E0* on the page: each wired \
          response must have been normalised by Table 1's (its E0* is mean_stress_pa · \
          area_fraction / load_norm, from the response alone), and a wired `params` must be \
          the fit of `material` at the same ν; otherwise the stage stops and names the \
          input, so set `poisson` to the contact model's (and the fit's). The summary reads \
          F/(E0* A0) of every model at `area_fractions` by linear interpolation in A/A0 \
          (null outside the computed range), and each band's 5th and 95th percentiles the \
          same way; its table on the page shows `summary_models`. FINITE STRAIN: with \
          `finite_strain` wired (one patch per sample: `fem` and the other models on the same \
          window), Fig. 10 draws every curve per sample over the reference's range of A/A0 \
          (reference black and thick; colour = family, the label's text before `-`; stroke = \
          the label's suffix: none solid, `-uniaxial` dashed, `-linear` dotted, other long \
          dashes) and a table gives F_model / F_reference at `finite_strain_area_fractions` per \
          sample with the mean over samples, both as F/(E0* A0) read by linear interpolation \
          in A/A0, and says in words which model comes nearest and whether each family's \
          tangent modulus moves its load toward the finite-strain one or away (against its \
          `-linear` variant). FINDINGS: the page opens with \"What this rerun finds\", \
          sentences written from the numbers above, each linking its figure or table and left \
          out when its inputs are not wired: the models compared with the equibiaxial tangent \
          (labels without a law suffix whose tangent_ratio is not 1), the finite-strain \
          verdict (F_reference/F of its small-strain twin, the reference's family, and the \
          range of F_model/F_reference of the equibiaxial and the `-linear` models, from the \
          finite-strain table), and the experiment (its physics, the models marked \
          by_construction, the best-ranked of the others and the equibiaxial models' load \
          ratio at the load_ratio A/A0 nearest 0.5), and with `refinement` wired the judge's \
          resolution (the coarsest refine factor k from which on every level's F_fem/F_bem at \
          equal approach lies within 5 % of 1 at each of `refinement_area_fractions` inside \
          0.05–0.3 that every level reads, or, when none does, the level whose largest \
          deviation is smallest, with the finest level's ratios beside it); summary.json holds \
          them under `findings`. REFINEMENT: with `refinement` wired (levels labelled by the \
          refine factor k, each with `fem` and `bem`; a level without both, another label, or \
          a bem whose tangent_ratio is not 1 stops the stage naming the input), the section \
          \"Is the finite-strain judge converged?\" gives F_fem, F_bem (as F/(E0* A0)) and \
          their ratio per k at equal approach (the same z_m, read where the finest bem \
          reaches each of `refinement_area_fractions`; linear in z_m) and at equal counted \
          area (those A/A0; linear in A/A0), n/a outside a curve, with the observed order p of \
          each from the three finest levels (F_k = F* + C h_k^p with h_k = 1/k solved for p \
          by bisection, as the refinement ratios differ; n/a if the differences change sign \
          or vanish), and Fig. 11: the ratio against the points per shortest wavelength \
          (k times `refinement_points_per_wavelength`), solid at equal approach and dashed at equal area; \
          its caption names fem's block depth from the depth_m of the fem stages in the \
          run's record. summary.json then holds `refinement` (absent without the input): \
          `points_per_wavelength_at_refine_1`, the compared `area_fractions`, \
          `z_m_equal_approach` (m, per A/A0; null where the finest bem does not reach it), \
          `levels` (per k: `refine`, `points_per_wavelength`, F_fem/F_bem per A/A0 as \
          `ratio_equal_approach` and `ratio_equal_area`, null where a load is not read, each \
          with its `_min` and `_max` over the A/A0 read) and `observed_order` (per compared \
          point: `compared_at` equal_approach or equal_area, `area_fraction`, and the order p \
          of F_fem, F_bem and their ratio as `order_fem`, `order_bem`, `order_ratio`). Figures use the bundled \
          DejaVu Sans font; no system font or network is needed.",
    inputs: &[
        InputSpec::table::<CurvesTable>(
            "curves",
            Arity::Optional,
            "material fit: measured and fitted stress per mode",
        ),
        InputSpec::table::<QualityTable>(
            "quality",
            Arity::Optional,
            "material fit: quality per mode (shown as is)",
        ),
        InputSpec::table::<ParamsTable>(
            "params",
            Arity::Optional,
            "material fit: parameter table (shown as is)",
        ),
        InputSpec::table::<StabilityTable>(
            "stability",
            Arity::Optional,
            "material fit: Drucker-stable stretch ranges",
        ),
        InputSpec::table::<ComparisonTable>(
            "comparison",
            Arity::Optional,
            "material fit: model ranking (shown as is)",
        ),
        InputSpec::table::<MaterialTable>("material", Arity::Optional, "the fitted material"),
        InputSpec::field("heights", Arity::Many, "height map per sample"),
        InputSpec::table::<PsdTable>("psd", Arity::Many, "PSD per sample"),
        InputSpec::table::<StatsTable>("stats", Arity::Many, "surface statistics per sample"),
        InputSpec::table::<ProfileTable>("profiles", Arity::Many, "truncation profile per sample"),
        InputSpec::table::<ArealTable>(
            "areal",
            Arity::Many,
            "surface stage's ISO 25178-2 areal parameters per sample: the areal table",
        ),
        InputSpec::table::<MaterialRatioTable>(
            "material_ratio",
            Arity::Many,
            "surface stage's Abbott-Firestone curve per sample: Fig. 4b",
        ),
        InputSpec::table::<AcfTable>(
            "acf",
            Arity::Many,
            "surface stage's autocorrelation per sample: Fig. 4c",
        ),
        InputSpec::table::<ScaleDependentTable>(
            "scale_dependent",
            Arity::Many,
            "surface stage's scale-dependent rms slope and curvature per sample: Fig. 4d",
        ),
        InputSpec::table::<DistributionsTable>(
            "distributions",
            Arity::Many,
            "surface stage's height, slope and curvature histograms per sample: Fig. 4e",
        ),
        InputSpec::table::<ResponseTable>(
            "responses",
            Arity::Nested,
            "every contact model's load-area curve, by sample and model label: Figs. 7, 8, 9, \
             the κ, load-ratio and summary tables",
        ),
        InputSpec::table::<BandTable>(
            "bands",
            Arity::Nested,
            "contact models' 5–95 % bootstrap bands, by sample and model label: shaded in Figs. \
             7 and 8, read in the summary",
        ),
        // Any table: each model's summary has its own columns.
        InputSpec {
            name: "model_summaries",
            kind: ProductKind::Table,
            arity: Arity::Nested,
            columns: &[],
            doc: "what each model was given (any one-row table), by sample and model label: \
                  shown as is under Fig. 9",
        },
        InputSpec::table::<ContactTable>(
            "experiments",
            Arity::Many,
            "contact experiment per sample (contact-images' contact): Fig. 7's symbols",
        ),
        InputSpec::table::<AgreementTable>(
            "agreement",
            Arity::Many,
            "contact-compare's agreement per sample: the table under Fig. 7",
        ),
        InputSpec::table::<LoadRatioTable>(
            "load_ratio",
            Arity::Many,
            "contact-compare's load ratios per sample",
        ),
        InputSpec::table::<TransformTable>(
            "transforms",
            Arity::Many,
            "contact-compare's registration per sample",
        ),
        InputSpec::table::<ResponseTable>(
            "finite_strain",
            Arity::Nested,
            "the finite-strain comparison on one patch per sample, by sample and model label: \
             the finite-element reference (`finite_strain_reference`) and the models on the same \
             window (Fig. 10 and its load-ratio table)",
        ),
        InputSpec::table::<ResponseTable>(
            "refinement",
            Arity::Nested,
            "the refinement study, by refine factor and then `fem` and `bem` (`{\"1\": {fem: \
             a.response, bem: b.response}, ...}`): linear fem at small strain and linear \
             periodic bem on the mirror tiling of one window (the table and Fig. 11)",
        ),
        InputSpec::files_indexed::<FigureIndex>(
            "compare_figures",
            Arity::Many,
            "contact-compare's figures per sample, indexed: Fig. 6 (the first sample wired)",
        ),
    ],
    outputs: &[OutputSpec::files(
        "report",
        "index.html, figN.png, figN.svg, summary.json",
    )],
};

impl Stage for Report {
    type Params = ReportParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<ReportParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let options = ReportOptions {
            title: p.title.clone(),
            area_fractions: p.area_fractions.clone(),
            poisson: p.poisson.0,
            models: ModelChoice {
                order: p.models.clone(),
                fig7: p.fig7_models.clone(),
                fig9: p.fig9_models.clone(),
                summary: p.summary_models.clone(),
                reference: p.reference_model.clone(),
            },
            published_material: p.published_material,
            finite_strain: crate::finite_strain::FiniteStrainOptions {
                reference: p.finite_strain_reference.clone(),
                area_fractions: p.finite_strain_area_fractions.clone(),
            },
            refinement: crate::refinement::RefinementOptions {
                area_fractions: p.refinement_area_fractions.clone(),
                points_per_wavelength: p.refinement_points_per_wavelength,
            },
        };
        let progress = ctx.progress(1, "figures and page");
        let files = render_report(inputs, &options, ctx.upstream())?;
        progress.inc(1);
        let skipped: Vec<&str> = ["fig2", "fig4", "fig7", "fig8"]
            .into_iter()
            .filter(|f| !files.files.contains_key(&format!("{f}.png")))
            .collect();
        if !skipped.is_empty() {
            ctx.note(&format!(
                "skipped {} (inputs not wired; see index.html)",
                skipped.join(", ")
            ));
        }
        Ok(Outputs::new().files("report", files))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Params;

    #[test]
    fn bad_parameters_are_named() {
        ReportParams::default().check().unwrap();
        let e = ReportParams {
            area_fractions: vec![0.5, 1.5],
            ..Default::default()
        }
        .check()
        .unwrap_err();
        assert_eq!(e.param, "area_fractions.1");
        assert!(e.message.contains("1.5"), "{}", e.message);
        let e = ReportParams {
            title: " ".into(),
            ..Default::default()
        }
        .check()
        .unwrap_err();
        assert_eq!(e.param, "title");
    }

    #[test]
    fn every_input_is_optional_or_many() {
        assert!(
            INFO.inputs
                .iter()
                .all(|i| matches!(i.arity, Arity::Optional | Arity::Many | Arity::Nested))
        );
    }
}
