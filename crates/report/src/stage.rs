//! Stage `report`: the paper's Figs. 2, 4, 7 and 8, its Table 1, the model
//! comparison and a per-sample summary, as one `Files` product `report`
//! (`index.html`, `figN.png`, `figN.svg`, `summary.json`).

use hypercontact_core::product::ProductKind;
use hypercontact_core::{
    Arity, Checked, ColumnSpec, Context, InputSpec, Inputs, OutputSpec, Outputs, Stage, StageError,
    StageInfo, params,
};

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

const CURVES: &[ColumnSpec] = &[
    ColumnSpec::str("mode", "UT, PT or BT"),
    ColumnSpec::f64("stretch", "", "stretch λ"),
    ColumnSpec::f64("measured_pa", "Pa", "measured nominal stress"),
    ColumnSpec::f64("fitted_pa", "Pa", "fitted nominal stress"),
];
const QUALITY: &[ColumnSpec] = &[
    ColumnSpec::str("mode", "UT, PT or BT"),
    ColumnSpec::f64("r2", "", "coefficient of determination"),
];
const STABILITY: &[ColumnSpec] = &[
    ColumnSpec::str("mode", "UT, PT or BT"),
    ColumnSpec::f64("lambda_min", "", "lowest Drucker-stable stretch"),
    ColumnSpec::f64("lambda_max", "", "highest Drucker-stable stretch"),
];
const PSD: &[ColumnSpec] = &[
    ColumnSpec::str("direction", "x, y or radial"),
    ColumnSpec::f64("q_per_m", "1/m", "wavevector"),
    ColumnSpec::f64("c", "m^3 (1-D)", "power spectral density"),
];
const STATS: &[ColumnSpec] = &[
    ColumnSpec::f64("sigma_m", "m", "rms height"),
    ColumnSpec::f64("rms_slope", "", "rms slope"),
    ColumnSpec::f64("hurst_x", "", "Hurst exponent along x"),
    ColumnSpec::f64("hurst_y", "", "Hurst exponent along y"),
    ColumnSpec::f64("hurst_radial", "", "Hurst exponent, radial PSD"),
];
const PROFILE: &[ColumnSpec] = &[
    ColumnSpec::f64("z_over_sigma", "", "truncation height over σ"),
    ColumnSpec::f64("area_fraction", "", "A/A0"),
];
const RESPONSE: &[ColumnSpec] = &[
    ColumnSpec::f64("area_fraction", "", "A/A0"),
    ColumnSpec::f64("load_norm", "", "F/(E0* A0)"),
    ColumnSpec::f64("tangent_ratio", "", "E_t*/E0*"),
];

const fn optional_table(
    name: &'static str,
    columns: &'static [ColumnSpec],
    doc: &'static str,
) -> InputSpec {
    InputSpec {
        name,
        kind: ProductKind::Table,
        arity: Arity::Optional,
        columns,
        doc,
    }
}

const fn per_sample(
    name: &'static str,
    kind: ProductKind,
    columns: &'static [ColumnSpec],
    doc: &'static str,
) -> InputSpec {
    InputSpec {
        name,
        kind,
        arity: Arity::Many,
        columns,
        doc,
    }
}

static INFO: StageInfo = StageInfo {
    kind: "report",
    version: 1,
    summary: "HTML report with the paper's Figs. 2, 4, 7, 8 (PNG + SVG), Table 1 and a summary",
    doc: "Every input is optional: a figure whose inputs are not wired is skipped and the \
          page says why (e.g. a pipeline without the tensile branch still gets Figs. 4, 7 \
          and 8). Per-sample inputs are labelled by sample (`responses: {T1: icm1, ...}`); \
          one label gets one colour in every figure. Fig. 2 needs `curves` (R² from \
          `quality`, limits from `stability`); Fig. 4 any of `heights`, `psd`, `profiles` \
          (the H of the drawn power law comes from `stats` when wired, otherwise from a \
          log-log least-squares fit); Fig. 7 `responses` and/or `responses_linear`; Fig. 8 \
          `responses`. Table 1 decodes `material` (μ0 = Σ μ_i, E0 = 3 μ0, \
          E0* = E0/(1 − ν²) with ν = ½). The summary reads F/(E0* A0) at `area_fractions` \
          by linear interpolation in A/A0 (null outside the computed range). Figures use \
          the bundled DejaVu Sans font; no system font or network is needed.",
    inputs: &[
        optional_table(
            "curves",
            CURVES,
            "material fit: measured and fitted stress per mode",
        ),
        optional_table("quality", QUALITY, "material fit: quality per mode"),
        optional_table("params", &[], "material fit: parameter table (shown as is)"),
        optional_table(
            "stability",
            STABILITY,
            "material fit: Drucker-stable stretch ranges",
        ),
        optional_table(
            "comparison",
            &[],
            "material fit: model ranking (shown as is)",
        ),
        optional_table(
            "material",
            <hypercontact_material::table::MaterialTable as hypercontact_core::Schema>::COLUMNS,
            "the fitted material (model, param, value)",
        ),
        per_sample(
            "heights",
            ProductKind::Field,
            &[],
            "height map per sample, m",
        ),
        per_sample("psd", ProductKind::Table, PSD, "PSD per sample"),
        per_sample(
            "stats",
            ProductKind::Table,
            STATS,
            "surface statistics per sample",
        ),
        per_sample(
            "profiles",
            ProductKind::Table,
            PROFILE,
            "truncation profile per sample",
        ),
        per_sample(
            "responses",
            ProductKind::Table,
            RESPONSE,
            "hyperelastic ICM per sample",
        ),
        per_sample(
            "responses_linear",
            ProductKind::Table,
            RESPONSE,
            "linear ICM per sample",
        ),
    ],
    outputs: &[OutputSpec {
        name: "report",
        kind: ProductKind::Files,
        columns: &[],
        doc: "index.html, figN.png, figN.svg, summary.json",
    }],
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
