//! Stage `report`: the paper's Figs. 2, 4, 7 and 8, its Table 1, the model
//! comparison and a per-sample summary, as one `Files` product `report`
//! (`index.html`, `figN.png`, `figN.svg`, `summary.json`).

use hypercontact_classical::stage::{GwSummaryTable, PerssonSummaryTable};
use hypercontact_compare::stage::{AgreementTable, LoadRatioTable, TransformTable};
use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::{BandTable, ResponseTable};
use hypercontact_core::{
    Arity, Checked, Context, InputSpec, Inputs, OutputSpec, Outputs, Stage, StageError, StageInfo,
    params,
};
use hypercontact_material::fit_stage::{
    ComparisonTable, CurvesTable, ParamsTable, QualityTable, StabilityTable,
};
use hypercontact_material::table::MaterialTable;
use hypercontact_surface::surface_stage::{PsdTable, StatsTable};
use hypercontact_truncation::stage::ProfileTable;

use hypercontact_material::Poisson;

use crate::report::{ReportOptions, render_report};

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
    version: 6,
    summary: "HTML report with the paper's Figs. 2, 4, 6, 7, 8, a model comparison (Fig. 9; PNG + \
              SVG), Table 1 and a summary",
    doc: "Every input is optional: a figure whose inputs are not wired is skipped and the \
          page says why (e.g. a pipeline without the tensile branch still gets Figs. 4, 7 \
          and 8). Per-sample inputs are labelled by sample (`responses: {T1: icm1, ...}`); \
          one label gets one colour in every figure. Fig. 2 needs `curves` (R² from \
          `quality`, limits from `stability`); Fig. 4 any of `heights`, `psd`, `profiles` \
          (the H of the drawn power law comes from `stats` when wired, otherwise from a \
          log-log least-squares fit); Fig. 7 any of `responses`, `responses_linear` (ICM, \
          hyperelastic and linear), `responses_bem`, `responses_bem_linear` (boundary \
          elements), with the ICM/BEM load ratio at `area_fractions` per sample and law where \
          both are wired, and the measured points of `experiments` (contact-images' contact, \
          the force over the models' E0* A0) with the agreement table of `agreement` and \
          `load_ratio` (contact-compare) under it; Fig. 6 the first sample's \
          `compare_figures` (observed, predicted and overlay maps at one scale with a bar) with \
          the registrations of `transforms`; Fig. 8 `responses` and/or `responses_bem`; Fig. 9 \
          (the contact models side by side: hyperelastic and linear ICM, hyperelastic BEM, \
          `responses_persson`, `responses_gw`, with the experiment) needs Persson or GW wired, \
          and comes with a table of kappa = (A/A0)/(F/(A0 E0* h'rms)) per model at A/A0 = \
          0.02 and 0.1 (h'rms from `stats`, one yardstick for every model; read off each curve \
          by linear interpolation in A/A0, n/a outside it) and the theories' inputs from \
          `persson_summary` and `gw_summary`. `bands` (icm's bands of the hyperelastic ICM, \
          labelled per sample like `responses`; a table without rows is no band) shades the \
          5–95 % bootstrap band of F/(E0* A0) under Fig. 7's curves and of E_t*/E0* under Fig. \
          8's (sample colour at opacity 0.2; in Fig. 7's per-sample panels the ICM's grey; \
          points at or below zero left off the log axis), with a legend entry. Table 1 decodes \
          `material` and gives its initial moduli μ0, E0 and E0* at Poisson's ratio `poisson`; \
          with `params` wired, each parameter and modulus with its 5–95 % bootstrap interval \
          where finite; with `comparison` wired, a line under it states the fit's constraint \
          and RMS relative error (and condition number) beside the same family's under the \
          other setting. One E0* on the page: each wired response must \
          have been normalised by Table 1's (its E0* is mean_stress_pa · area_fraction / \
          load_norm, from the response alone), and a wired `params` must be the fit of \
          `material` at the same ν; otherwise the stage stops and names the input, so set \
          `poisson` to the contact model's (and the fit's). The summary reads F/(E0* A0) \
          at `area_fractions` by linear interpolation in A/A0 (null outside the computed \
          range), and the band's 5th and 95th percentiles the same way (`load_norm_p05`, \
          `load_norm_p95`; null without a band). Figures use the bundled DejaVu Sans font; no system font or network is \
          needed.",
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
        InputSpec::table::<ResponseTable>("responses", Arity::Many, "hyperelastic ICM per sample"),
        InputSpec::table::<BandTable>(
            "bands",
            Arity::Many,
            "hyperelastic ICM's 5–95 % bootstrap bands per sample (icm's bands): shaded in Figs. \
             7 and 8, read in the summary",
        ),
        InputSpec::table::<ResponseTable>("responses_linear", Arity::Many, "linear ICM per sample"),
        InputSpec::table::<ResponseTable>(
            "responses_bem",
            Arity::Many,
            "hyperelastic boundary elements per sample",
        ),
        InputSpec::table::<ResponseTable>(
            "responses_bem_linear",
            Arity::Many,
            "linear boundary elements per sample",
        ),
        InputSpec::table::<ResponseTable>(
            "responses_persson",
            Arity::Many,
            "Persson's theory per sample (model comparison, Fig. 9)",
        ),
        InputSpec::table::<ResponseTable>(
            "responses_gw",
            Arity::Many,
            "Greenwood-Williamson per sample (model comparison, Fig. 9)",
        ),
        InputSpec::table::<PerssonSummaryTable>(
            "persson_summary",
            Arity::Many,
            "persson's summary per sample: the variant and spectrum of Fig. 9's curve",
        ),
        InputSpec::table::<GwSummaryTable>(
            "gw_summary",
            Arity::Many,
            "greenwood-williamson's summary per sample: the asperity parameters",
        ),
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
        InputSpec::files(
            "compare_figures",
            Arity::Many,
            "contact-compare's figures per sample: Fig. 6 (the first sample wired)",
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
                .all(|i| matches!(i.arity, Arity::Optional | Arity::Many))
        );
    }
}
