//! Assembles the report from whatever inputs are wired: decides which
//! figures can be drawn (and notes why the others cannot), renders them,
//! and writes `index.html`, `figN.png`, `figN.svg` and `summary.json`.

use hypercontact_core::param::Choice;
use hypercontact_core::{Files, Inputs};
use hypercontact_material::presets::Preset;
use hypercontact_material::table::to_table;
use serde_json::Value;

use crate::ReportError;
use crate::figures::fig2::Fig2;
use crate::figures::fig4::Fig4;
use crate::figures::fig4b::{Fig4b, Fig4c};
use crate::figures::fig4d::{Fig4d, Fig4e};
use crate::figures::fig7::{Drawn, Fig7, SampleResponses};
use crate::figures::fig8::Fig8;
use crate::figures::{Rendered, render};
use crate::gather::{ReportData, Response, Sample, StabilityRange};
use crate::html::{escape, fmt_sig, generic_table, page, provenance_section, simple_table};
use crate::material::{FitSetting, MaterialSummary};
use crate::roster::{ModelKey, is_linear};
use crate::summary::{FigureStatus, Summary};

/// What the report shows beyond its inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportOptions {
    pub title: String,
    /// A/A0 at which the summary reads F/(E0* A0).
    pub area_fractions: Vec<f64>,
    /// Poisson's ratio ν of Table 1's E0 and E0*; the responses must have
    /// been normalised by the same E0*.
    pub poisson: f64,
    /// Which contact models go where, by their labels in `responses`.
    pub models: ModelChoice,
    /// A published material set beside the fit in Table 1, with its error
    /// on the same tensile data.
    pub published_material: Option<Preset>,
    /// The finite-strain comparison's reference and area fractions.
    pub finite_strain: crate::finite_strain::FiniteStrainOptions,
    /// The refinement study's comparison points and axis.
    pub refinement: crate::refinement::RefinementOptions,
}

/// The contact models' order and which of them each figure and table
/// shows, by label; an empty list means every wired model (the summary:
/// the first).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelChoice {
    /// Legend and colour order; labels not listed follow in label order.
    pub order: Vec<String>,
    pub fig7: Vec<String>,
    pub fig9: Vec<String>,
    /// The models whose loads the per-sample summary table shows.
    pub summary: Vec<String>,
    /// The model every other's load is divided by in the load-ratio table.
    pub reference: Option<String>,
}

/// [`ModelChoice`] checked against the wired models.
pub(crate) struct Chosen<'a> {
    pub fig7: Vec<&'a ModelKey>,
    pub fig9: Vec<&'a ModelKey>,
    pub summary: Vec<&'a ModelKey>,
    pub reference: Option<&'a ModelKey>,
}

impl ModelChoice {
    fn resolve<'a>(&self, data: &'a ReportData<'_>) -> Result<Chosen<'a>, ReportError> {
        let roster = &data.roster;
        roster.check("models", &self.order)?;
        let summary = if self.summary.is_empty() {
            roster.models.iter().take(1).collect()
        } else {
            roster.select("summary_models", &self.summary)?
        };
        let reference = match &self.reference {
            Some(label) => {
                roster.check("reference_model", std::slice::from_ref(label))?;
                roster.get(label)
            }
            None => None,
        };
        Ok(Chosen {
            fig7: roster.select("fig7_models", &self.fig7)?,
            fig9: roster.select("fig9_models", &self.fig9)?,
            summary,
            reference,
        })
    }
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            title: "hypercontact — rough-surface contact of a hyperelastic rubber".into(),
            area_fractions: vec![0.1, 0.5, 0.9],
            // Incompressible rubber, as the paper takes it.
            poisson: hypercontact_material::Poisson::INCOMPRESSIBLE.0,
            models: ModelChoice::default(),
            published_material: None,
            finite_strain: Default::default(),
            refinement: Default::default(),
        }
    }
}

/// Reads the inputs and builds the report's files. `provenance` is the
/// run's record when the caller has one (the runner does not pass it to
/// stages yet); `None` renders a placeholder section.
pub fn render_report(
    inputs: &Inputs,
    options: &ReportOptions,
    provenance: Option<&Value>,
) -> Result<Files, ReportError> {
    let data = ReportData::gather(inputs, options.poisson, &options.models.order)?;
    build_report(&data, options, provenance)
}

/// One figure's outcome: rendered, or skipped with the reason.
struct Outcome {
    status: FigureStatus,
    rendered: Option<Rendered>,
}

fn skipped(name: &str, why: String) -> Outcome {
    Outcome {
        status: FigureStatus {
            name: name.to_owned(),
            rendered: false,
            note: Some(why),
        },
        rendered: None,
    }
}

fn drawn(rendered: Rendered, notes: Vec<String>) -> Outcome {
    Outcome {
        status: FigureStatus {
            name: rendered.name.to_owned(),
            rendered: true,
            note: (!notes.is_empty()).then(|| notes.join("; ")),
        },
        rendered: Some(rendered),
    }
}

/// Which figure the responses are gathered for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Plot {
    /// Fig. 7: the chosen models with their bands, and the experiment.
    LoadArea,
    /// Fig. 8: every model whose tangent ratio is not 1 throughout.
    Tangent,
    /// Fig. 9: the chosen models with their bands, and the experiment.
    Comparison,
}

/// The samples with a curve of `models` the figure can draw.
fn responses<'a>(
    data: &'a ReportData<'a>,
    models: &[&'a ModelKey],
    plot: Plot,
) -> Vec<SampleResponses<'a>> {
    data.samples
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let curves: Vec<Drawn<'a>> = models
                .iter()
                .filter_map(|&key| {
                    let response = s.response(&key.label)?;
                    let drawn = plot != Plot::Tangent || !is_linear(response);
                    drawn.then_some(Drawn { key, response })
                })
                .collect();
            let bands = models
                .iter()
                .filter_map(|&key| Some((key, s.bands.get(&key.label)?)))
                .filter(|(key, _)| plot != Plot::Tangent || curves.iter().any(|d| d.key == *key))
                .collect();
            SampleResponses {
                label: &s.label,
                colour_index: i,
                curves,
                experiment: if plot == Plot::Tangent {
                    None
                } else {
                    experiment_points(s)
                },
                bands,
            }
        })
        .filter(|s| !s.curves.is_empty() || !s.bands.is_empty())
        .collect()
}

/// The models with a curve in `samples`, in their order.
fn drawn_models<'a>(models: &[&'a ModelKey], samples: &[SampleResponses<'a>]) -> Vec<&'a ModelKey> {
    models
        .iter()
        .copied()
        .filter(|key| {
            samples
                .iter()
                .any(|s| s.curves.iter().any(|d| d.key == *key))
        })
        .collect()
}

/// The sample's measured (A/A0, F) on Fig. 7's axes: F/(E0* A0) with the
/// E0* A0 of its responses; frames without load (before contact, or noise
/// at or below zero) cannot be drawn on the log axis.
pub(crate) fn experiment_points(s: &Sample<'_>) -> Option<Response> {
    let e = s.experiment.as_ref()?;
    let per_newton = s.per_newton()?;
    let (area_fraction, load_norm): (Vec<f64>, Vec<f64>) = e
        .area_fraction
        .iter()
        .zip(&e.force_n)
        .filter(|(a, f)| **a > 0.0 && **f > 0.0)
        .map(|(a, f)| (*a, f * per_newton))
        .unzip();
    (!area_fraction.is_empty()).then(|| Response {
        tangent_ratio: vec![f64::NAN; area_fraction.len()],
        area_fraction,
        load_norm,
        e0_star_pa: None,
        per_newton: Some(per_newton),
    })
}

/// Decides on and renders one figure.
type FigureJob = fn(&ReportData<'_>, &Chosen<'_>) -> Result<Outcome, ReportError>;

/// Renders the figures on scoped threads (each figure is independent;
/// Fig. 4 with its height maps dominates), in figure order.
fn figure_outcomes(
    data: &ReportData<'_>,
    chosen: &Chosen<'_>,
) -> Result<Vec<Outcome>, ReportError> {
    let jobs: [FigureJob; 9] = [
        fig2_outcome,
        fig4_outcome,
        fig4b_outcome,
        fig4c_outcome,
        fig4d_outcome,
        fig4e_outcome,
        fig7_outcome,
        fig8_outcome,
        fig9_outcome,
    ];
    std::thread::scope(|scope| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|job| scope.spawn(move || job(data, chosen)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            })
            .collect()
    })
}

fn fig2_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let Some(curves) = &data.curves else {
        return Ok(skipped(
            "fig2",
            "input `curves` (the material fit's measured and fitted stresses) is not wired".into(),
        ));
    };
    let mut notes = Vec::new();
    if data.quality.is_none() {
        notes.push("`quality` not wired: no R² in the legend".to_owned());
    }
    if data.stability.is_none() {
        notes.push("`stability` not wired: stability limits not marked".to_owned());
    }
    let fig = Fig2 {
        curves,
        r2_by_mode: &data.r2_by_mode,
        stability: data.stability.as_deref(),
    };
    Ok(drawn(render(&fig)?, notes))
}

fn fig4_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let surfaces: Vec<_> = data
        .samples
        .iter()
        .enumerate()
        .filter(|(_, s)| {
            s.height.is_some() || s.psd_x.is_some() || s.psd_y.is_some() || s.profile.is_some()
        })
        .map(|(i, s)| (s, i))
        .collect();
    if surfaces.is_empty() {
        return Ok(skipped(
            "fig4",
            "no per-sample surface input (`heights`, `psd` or `profiles`) is wired".into(),
        ));
    }
    let mut notes = Vec::new();
    for (s, _) in &surfaces {
        let absent: Vec<&str> = [
            (s.height.is_none(), "height map"),
            (s.psd_x.is_none(), "PSD along x"),
            (s.psd_y.is_none(), "PSD along y"),
            (s.profile.is_none(), "truncation profile"),
        ]
        .into_iter()
        .filter_map(|(gone, what)| gone.then_some(what))
        .collect();
        if !absent.is_empty() {
            notes.push(format!("{}: no {}", s.label, absent.join(", ")));
        }
    }
    Ok(drawn(render(&Fig4 { samples: surfaces })?, notes))
}

/// The samples (with their colour index) for which `has` holds, and the
/// notes on the samples with surface statistics that lack `input`.
fn with_statistic<'a>(
    data: &'a ReportData<'a>,
    input: &str,
    has: fn(&Sample<'_>) -> bool,
) -> (Vec<(&'a Sample<'a>, usize)>, Vec<String>) {
    let mut notes = Vec::new();
    let mut samples = Vec::new();
    for (i, s) in data.samples.iter().enumerate() {
        if has(s) {
            samples.push((s, i));
        } else if s.extras != Default::default() || s.stats.is_some() {
            notes.push(format!("{}: no `{input}`", s.label));
        }
    }
    (samples, notes)
}

/// The reason a surface-statistics figure is not drawn.
fn statistic_skipped(name: &str, input: &str) -> Outcome {
    skipped(
        name,
        format!(
            "input `{input}` (an output of the surface stage from version 6) is not wired for              any sample"
        ),
    )
}

fn fig4b_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let (samples, notes) = with_statistic(data, "material_ratio", |s| {
        s.extras.material_ratio.is_some()
    });
    if samples.is_empty() {
        return Ok(statistic_skipped("fig4b", "material_ratio"));
    }
    Ok(drawn(render(&Fig4b { samples })?, notes))
}

fn fig4c_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let (samples, notes) = with_statistic(data, "acf", |s| {
        s.extras
            .acf
            .as_ref()
            .is_some_and(|a| !a.radial.x.is_empty())
    });
    if samples.is_empty() {
        return Ok(statistic_skipped("fig4c", "acf"));
    }
    Ok(drawn(render(&Fig4c { samples })?, notes))
}

fn fig4d_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let (samples, notes) = with_statistic(data, "scale_dependent", |s| {
        s.extras
            .scale_dependent
            .as_ref()
            .is_some_and(|c| !c.slope.x.is_empty() || !c.curvature_per_m.x.is_empty())
    });
    if samples.is_empty() {
        return Ok(statistic_skipped("fig4d", "scale_dependent"));
    }
    Ok(drawn(render(&Fig4d { samples })?, notes))
}

fn fig4e_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let (samples, notes) = with_statistic(data, "distributions", |s| {
        s.extras
            .distributions
            .as_ref()
            .is_some_and(|d| d.height.is_some() || d.slope.is_some())
    });
    if samples.is_empty() {
        return Ok(statistic_skipped("fig4e", "distributions"));
    }
    Ok(drawn(render(&Fig4e { samples })?, notes))
}

fn fig7_outcome(data: &ReportData<'_>, chosen: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let samples = responses(data, &chosen.fig7, Plot::LoadArea);
    if samples.is_empty() {
        return Ok(skipped(
            "fig7",
            "no contact-model response (`responses`) is wired".into(),
        ));
    }
    let models = drawn_models(&chosen.fig7, &samples);
    let fig = Fig7 {
        samples,
        models,
        comparison: false,
    };
    Ok(drawn(render(&fig)?, Vec::new()))
}

fn fig8_outcome(data: &ReportData<'_>, _: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let all: Vec<&ModelKey> = data.roster.models.iter().collect();
    let samples = responses(data, &all, Plot::Tangent);
    if samples.is_empty() {
        return Ok(skipped(
            "fig8",
            "no response whose tangent ratio differs from 1 is wired; a linear model's ratio \
             is 1 by construction"
                .into(),
        ));
    }
    let models = drawn_models(&all, &samples);
    Ok(drawn(render(&Fig8 { samples, models })?, Vec::new()))
}

fn fig9_outcome(data: &ReportData<'_>, chosen: &Chosen<'_>) -> Result<Outcome, ReportError> {
    let samples = responses(data, &chosen.fig9, Plot::Comparison);
    if samples.is_empty() {
        return Ok(skipped(
            "fig9",
            "no contact-model response (`responses`) of `fig9_models` is wired".into(),
        ));
    }
    let models = drawn_models(&chosen.fig9, &samples);
    let fig = Fig7 {
        samples,
        models,
        comparison: true,
    };
    Ok(drawn(render(&fig)?, Vec::new()))
}

const CAPTIONS: [(&str, &str, &str); 9] = [
    (
        "fig2",
        "Fig. 2",
        "Nominal stress against stretch in uniaxial (UT), planar (PT) and equibiaxial (BT) \
         tension as the paper draws it: measured data as lines, the fitted model at the \
         measured stretches as symbols, with the fit's R² per mode. Dashed vertical lines \
         (listed in the legend) mark where the fitted model stops being Drucker stable, \
         where that falls inside the plotted stretches; the stability table gives every \
         limit, and the windows the fit was held stable on.",
    ),
    (
        "fig4",
        "Fig. 4",
        "Per sample, left to right: height map (heights above the lowest point; grey = not \
         measured; bar = scale); PSD C(q) along x and along y with the power law \
         C ∝ q<sup>−1−2H</sup> (dashed); contact area fraction A/A<sub>0</sub> of a plane \
         truncating the surface at height z (σ = rms height).",
    ),
    (
        "fig4b",
        "Fig. 4b",
        "Material-ratio (Abbott–Firestone) curve of each sample: the height about the mean \
         plane against the share Smr of the measured area at or above it (the surface \
         stage's curve at every whole per cent, linear between). The tinted band is the core of \
         ISO 13565-2 (as ISO 25178-2 adopts it), between the heights where the equivalence line \
         (dashed: the secant over 40 % of material ratio of least slope, extended to 0 and \
         100 %) starts and ends; its span is S<sub>k</sub>. Dotted: S<sub>mr1</sub> and \
         S<sub>mr2</sub>, where the curve crosses the core's limits; the peaks above the core \
         give S<sub>pk</sub>, the valleys below it S<sub>vk</sub> (values in the table \
         above).",
    ),
    (
        "fig4c",
        "Fig. 4c",
        "Autocorrelation ACF(τ) = ⟨z(<b>r</b>) z(<b>r</b> + <b>τ</b>)⟩/⟨z²⟩ of each sample \
         (z about the mean plane; each lag averaged over the pairs of measured points that \
         far apart, so ACF(0) = 1): radially averaged (solid; rings one pixel wide, each at \
         the mean |τ| of its lags) and along x (dashed) and y (dotted). Grey: the level 1/e, \
         where the radial average gives the correlation length (circle), and s = 0.2, ISO \
         25178-2's threshold of S<sub>al</sub> (the shortest decay length over all \
         directions, so it can fall short of where these curves cross 0.2). Lags are drawn \
         up to six correlation lengths; the surface stage's table <code>acf</code> goes to \
         half the map.",
    ),
    (
        "fig4d",
        "Fig. 4d",
        "Scale-dependent (variable-bandwidth) rms slope (a) and rms curvature (b) of each \
         sample, as SurfaceTopography's <code>scale_dependent_statistical_property</code> \
         defines them: at scale ℓ = kΔ (Δ the mean grid spacing, k = 1, 2, 4, …) the slope \
         from upwind differences over k pixels, √⟨g<sub>x</sub>² + g<sub>y</sub>²⟩ with \
         g<sub>x</sub> = (h(x + k dx, y) − h(x, y))/(k dx), and the curvature ∇²h/2 from \
         central second differences of step k/2 (a stencil ℓ long), each over the points \
         where its stencil is measured. On a self-affine surface of Hurst exponent H they fall \
         as ℓ<sup>H−1</sup> and ℓ<sup>H−2</sup>; the finest scale of (a) is SurfaceTopography's \
         rms gradient.",
    ),
    (
        "fig4e",
        "Fig. 4e",
        "Probability densities (histograms normalised to unit area; equal-width bins from \
         the smallest to the largest value) of the height about the mean plane (a) and of the \
         slope |∇h| (b), the slope by central differences at the points whose four neighbours \
         are measured. The curvature histogram is in the surface stage's table \
         <code>distributions</code>.",
    ),
    (
        "fig7",
        "Fig. 7",
        "Normalised load F/(E<sub>0</sub>* A<sub>0</sub>) against contact area fraction \
         A/A<sub>0</sub> of the contact models wired (the legend gives their labels): a \
         nonlinear law (such as the hyperelastic tangent modulus) solid, a linear law \
         (E<sub>t</sub>*/E<sub>0</sub>* = 1 throughout) dashed. With the models of one \
         family alone, every sample in its colour in one panel, as the paper draws it; with \
         several families or the contact experiment, one panel per sample on common axes, \
         colour = model family, the measured points as blue circles (the measured force over \
         the models' E<sub>0</sub>* A<sub>0</sub>; the measured area is the camera's view).",
    ),
    (
        "fig8",
        "Fig. 8",
        "Composite tangent modulus ratio E<sub>t</sub>*/E<sub>0</sub>* against contact area \
         fraction A/A<sub>0</sub> of every model whose ratio is not 1 throughout (a linear \
         law's is 1 by construction): colour = sample, stroke = model (legend). The paper's \
         tangent (<code>tangent: equibiaxial</code>, E<sub>t</sub> = dφ/dε of the \
         equibiaxial curve, Eq. 6) starts at 2 at first contact, since E<sub>t</sub>(0) = \
         6 μ<sub>0</sub> = 2 E<sub>0</sub>: such a model carries twice the linear load at \
         vanishing stress, where linear elasticity is exact. <code>tangent: uniaxial</code> \
         (the uniaxial curve in compression) starts at 1 and meets the linear model there. \
         Which is nearer the finite-strain solution only a finite-strain model can say; both \
         are drawn where both are wired.",
    ),
    (
        "fig9",
        "Fig. 9",
        "The contact models side by side on each sample's measured surface: normalised load \
         F/(E<sub>0</sub>* A<sub>0</sub>) against contact area fraction A/A<sub>0</sub>, \
         colour = model family (legend), linear laws dashed; the experiment as blue circles \
         where wired. The tables below give κ of each model at small load and what each \
         model was given (its own summary).",
    ),
];

/// What Figs. 7, 8 and 9's captions add when a band is drawn.
const BAND_CAPTION: &str = " Shaded: the 5–95 % band of a model over bootstrap refits of the \
     material (the tensile tests resampled within each mode and refitted, each refit carried \
     through the model): how far the tensile scatter and the fit's freedom move the curve.";

/// A figure with its caption, followed by `extra` (a sentence on what
/// this run adds), or the note saying why it was skipped.
fn figure_html(outcome: &Outcome, extra: &str) -> String {
    let name = outcome.status.name.as_str();
    let (_, label, caption) = CAPTIONS
        .iter()
        .find(|(n, _, _)| *n == name)
        .copied()
        .unwrap_or((name, name, ""));
    match &outcome.rendered {
        None => format!(
            "<p class=\"skipped\" id=\"{name}\"><b>{label}</b> skipped: {}.</p>\n",
            escape(outcome.status.note.as_deref().unwrap_or("no input"))
        ),
        Some(r) => {
            let note = outcome
                .status
                .note
                .as_deref()
                .map(|n| format!(" <span class=\"note\">(Incomplete: {}.)</span>", escape(n)))
                .unwrap_or_default();
            format!(
                "<figure id=\"{name}\">\n{svg}\n<figcaption><b>{label}.</b> {caption}{extra}{note} \
                 Files: <a href=\"{name}.png\">{name}.png</a>, \
                 <a href=\"{name}.svg\">{name}.svg</a>.</figcaption>\n</figure>\n",
                svg = r.svg
            )
        }
    }
}

/// Table 1 with what each constraint costs, and the published material
/// beside it when the options name one.
fn table1_html(data: &ReportData<'_>, m: &MaterialSummary, published: Option<Preset>) -> String {
    let mut html = crate::table1::parameter_table(m, "Table 1. Fitted");
    html.push_str(&crate::table1::moduli_table(m));
    let published = published.and_then(|preset| {
        let model = preset.model();
        let name = format!("<code>{}</code> (the paper's Table 1)", preset.name());
        let setting = FitSetting::of_model("published", model.as_ref(), data.curves.as_ref()?);
        let summary = MaterialSummary::read(&to_table(model.as_ref()), m.poisson, None).ok()?;
        Some((name, setting, summary))
    });
    if let Some(choice) = &data.fit_choice {
        let row = published.as_ref().map(|(name, s, _)| (name.as_str(), s));
        html.push_str(&crate::table1::constraint_table(choice, row));
    }
    if let Some((_, _, summary)) = &published {
        html.push_str(&crate::table1::parameter_table(
            summary,
            "The paper's Table 1 as published (preset paper-epdm):",
        ));
    }
    html
}

fn material_tables(data: &ReportData<'_>, published: Option<Preset>) -> String {
    let mut html = String::new();
    match &data.material {
        Some(m) => html.push_str(&table1_html(data, m, published)),
        None => html.push_str(
            "<p class=\"skipped\"><b>Table 1</b> skipped: input `material` is not wired.</p>\n",
        ),
    }
    if let Some(q) = data.quality {
        html.push_str(&generic_table("Fit quality per mode", q));
    }
    if let Some(ranges) = &data.stability {
        html.push_str(&stability_table(ranges));
    }
    if let Some(p) = data.params {
        html.push_str(&generic_table(
            "Fitted parameters, as the fit reports them",
            p,
        ));
    }
    match data.comparison {
        Some(c) => html.push_str(&generic_table(
            "Model comparison across strain-energy families",
            c,
        )),
        None => html.push_str(
            "<p class=\"skipped\"><b>Model comparison</b> skipped: input `comparison` is not wired.</p>\n",
        ),
    }
    html
}

/// Where the fitted model is Drucker-stable per mode: the limits found
/// (or the search range's edge, said so), and the window the fit imposed
/// stability on where it did.
fn stability_table(ranges: &[StabilityRange]) -> String {
    let limit = |lambda: f64, at_edge: bool| {
        if at_edge {
            format!(
                "{} (edge of the search: stable throughout)",
                fmt_limit(lambda)
            )
        } else {
            fmt_limit(lambda)
        }
    };
    let imposed = ranges.iter().any(|r| r.window.0.is_finite());
    let rows: Vec<Vec<String>> = ranges
        .iter()
        .map(|r| {
            let mut row = vec![
                escape(&r.mode),
                limit(r.lambda_min, r.min_at_edge),
                limit(r.lambda_max, r.max_at_edge),
            ];
            if imposed {
                row.push(match r.window {
                    (lo, hi) if lo.is_finite() && hi.is_finite() => {
                        format!("{} – {}", fmt_sig(lo, 4), fmt_sig(hi, 4))
                    }
                    _ => "none".into(),
                });
            }
            row
        })
        .collect();
    let mut header = vec![
        "mode".to_owned(),
        "λ<sub>min</sub>".to_owned(),
        "λ<sub>max</sub>".to_owned(),
    ];
    if imposed {
        header.push("stable by construction on (constraint in-range)".into());
    }
    simple_table(
        "Drucker-stable stretch range of the fitted model (searched over 0.1 ≤ λ ≤ 10; λ < 1 \
         is compression)",
        &header,
        &rows,
    )
}

/// A stability limit; an unbounded side is stored as ±∞.
fn fmt_limit(lambda: f64) -> String {
    match lambda {
        f64::INFINITY => "∞".into(),
        f64::NEG_INFINITY => "−∞".into(),
        v => fmt_sig(v, 4),
    }
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("n/a".into(), |v| fmt_sig(v, digits))
}

/// The summary table's load cells of one sample: per model of `models`,
/// F/(E0* A0) at each area fraction, with the model's band in brackets
/// where it has one.
fn load_cells(s: &crate::summary::SampleSummary, models: &[&ModelKey]) -> Vec<String> {
    let mut cells = Vec::new();
    for key in models {
        for l in &s.load_norm {
            let value = opt(l.load_norm.get(&key.label).copied().flatten(), 3);
            let p05 = l.load_norm_p05.get(&key.label).copied().flatten();
            let p95 = l.load_norm_p95.get(&key.label).copied().flatten();
            cells.push(match (p05, p95) {
                (None, None) => value,
                (p05, p95) => format!("{value} [{}, {}]", opt(p05, 3), opt(p95, 3)),
            });
        }
    }
    cells
}

fn sample_table(summary: &Summary, models: &[&ModelKey]) -> String {
    if summary.samples.is_empty() {
        return "<p class=\"skipped\"><b>Sample summary</b> skipped: no per-sample input is wired.</p>\n"
            .into();
    }
    let any_band = summary.samples.iter().any(|s| {
        s.load_norm.iter().any(|l| {
            models
                .iter()
                .any(|k| l.load_norm_p05.contains_key(&k.label))
        })
    });
    let mut header: Vec<String> = [
        "sample",
        "σ (µm)",
        "rms slope",
        "H<sub>x</sub>",
        "H<sub>y</sub>",
    ]
    .map(String::from)
    .to_vec();
    let areas: Vec<f64> = summary
        .samples
        .first()
        .map(|s| s.load_norm.iter().map(|l| l.area_fraction).collect())
        .unwrap_or_default();
    for key in models {
        for a in &areas {
            header.push(format!(
                "{}: F/(E<sub>0</sub>*A<sub>0</sub>) at A/A<sub>0</sub> = {a}",
                escape(&key.label)
            ));
        }
    }
    let rows: Vec<Vec<String>> = summary
        .samples
        .iter()
        .map(|s| {
            let mut row = vec![
                escape(&s.label),
                opt(s.sigma_m.map(|v| v * 1e6), 4),
                opt(s.rms_slope, 3),
                opt(s.hurst_x, 3),
                opt(s.hurst_y, 3),
            ];
            row.extend(load_cells(s, models));
            row
        })
        .collect();
    let names: Vec<&str> = models.iter().map(|k| k.label.as_str()).collect();
    let mut html = simple_table(
        &format!("Summary per sample (loads of {})", names.join(", ")),
        &header,
        &rows,
    );
    let band_note = if any_band {
        " [p05, p95] = the 5–95 % bootstrap band of the model (the tensile tests' scatter carried \
         through the fit), read the same way."
    } else {
        ""
    };
    html.push_str(&format!(
        "<p class=\"note\">Loads are read off the models' curves by linear interpolation in \
         A/A<sub>0</sub>; n/a = input not wired or A/A<sub>0</sub> outside the computed range.\
         {band_note} Every model's loads, unrounded, are in \
         <a href=\"summary.json\">summary.json</a>.</p>\n"
    ));
    html
}

/// Each model's load over the reference model's at the summary's area
/// fractions, per sample: how far a model's load is from the reference's
/// at the same contact area. Without a reference, a note saying how to ask
/// for it.
fn load_ratio_table(summary: &Summary, chosen: &Chosen<'_>, data: &ReportData<'_>) -> String {
    let Some(reference) = chosen.reference else {
        if data.roster.models.len() < 2 {
            return String::new();
        }
        return format!(
            "<p class=\"note\">Load ratios between the models are not tabulated: the report's \
             `reference_model` is not set (one of {}).</p>\n",
            escape(&data.roster.labels())
        );
    };
    let mut rows = Vec::new();
    for s in &summary.samples {
        for key in &data.roster.models {
            let ratios: Vec<Option<f64>> = s
                .load_norm
                .iter()
                .map(|l| l.over_reference.get(&key.label).copied().flatten())
                .collect();
            if ratios.iter().any(Option::is_some) {
                let mut row = vec![escape(&s.label), escape(&key.label)];
                row.extend(ratios.iter().map(|v| opt(*v, 3)));
                rows.push(row);
            }
        }
    }
    if rows.is_empty() {
        return String::new();
    }
    let mut header = vec!["sample".to_owned(), "model".to_owned()];
    if let Some(first) = summary.samples.first() {
        header.extend(
            first
                .load_norm
                .iter()
                .map(|l| format!("A/A<sub>0</sub> = {}", l.area_fraction)),
        );
    }
    let mut html = simple_table(
        &format!(
            "Load ratio F_model / F_{} at equal contact area A/A0",
            reference.label
        ),
        &header,
        &rows,
    );
    html.push_str(&format!(
        "<p class=\"note\">Both loads read off the curves of Fig. 7 by linear interpolation \
         in A/A<sub>0</sub>. A ratio below 1: the model reaches the area at a smaller load \
         than {}. n/a = A/A<sub>0</sub> outside a model's computed range.</p>\n",
        escape(&reference.label)
    ));
    html
}

/// The page's contact sections: Fig. 6 and the registrations, Figs. 7 and
/// 8 with the agreement and load-ratio tables, Fig. 9 with κ and the
/// models' summaries.
fn contact_sections(
    data: &ReportData<'_>,
    chosen: &Chosen<'_>,
    summary: &Summary,
    outcomes: &[Outcome],
    fig6_html: &str,
) -> String {
    let mut body = String::new();
    let by_name = |name: &str| outcomes.iter().find(|o| o.status.name == name);
    let compared = data
        .samples
        .iter()
        .any(|s| s.compare_figures.is_some() || s.transform.is_some());
    let physics = crate::experiment::experiment_physics(data);
    if compared {
        body.push_str("<h2>Contact experiment: observed against predicted contact</h2>\n");
        if !physics.is_empty() {
            body.push_str(&format!(
                "<p class=\"note\">What the experiment is:{physics} A model of the \
                 experiment's own physics agrees with it by construction: its score measures \
                 the imaging, the image analysis and the scan, not the physics.</p>\n"
            ));
        }
        body.push_str(fig6_html);
        body.push_str(&crate::experiment::transform_table(data));
    }
    body.push_str("<h2>Contact: the contact models' load against area</h2>\n");
    let band_caption = if data.samples.iter().any(|s| !s.bands.is_empty()) {
        BAND_CAPTION
    } else {
        ""
    };
    let with_physics = format!("{band_caption}{physics}");
    if let Some(o) = by_name("fig7") {
        body.push_str(&figure_html(o, &with_physics));
    }
    body.push_str(&crate::experiment::agreement_table(data));
    body.push_str(&load_ratio_table(summary, chosen, data));
    if let Some(o) = by_name("fig8") {
        body.push_str(&figure_html(o, band_caption));
    }
    if let Some(o) = by_name("fig9").filter(|o| o.status.rendered) {
        body.push_str("<h2>Contact models compared</h2>\n");
        body.push_str(&figure_html(o, &with_physics));
        let kappas: Vec<(&str, Vec<crate::models::KappaAt>)> = summary
            .samples
            .iter()
            .map(|s| (s.label.as_str(), s.kappa.clone()))
            .collect();
        body.push_str(&crate::models::kappa_table(&kappas, &chosen.fig9));
        body.push_str(&crate::models::model_summary_tables(
            &data.samples,
            &data.roster.models,
        ));
    }
    body
}

/// Renders every figure the data allows and writes the report's files.
pub fn build_report(
    data: &ReportData<'_>,
    options: &ReportOptions,
    provenance: Option<&Value>,
) -> Result<Files, ReportError> {
    let chosen = options.models.resolve(data)?;
    let outcomes = figure_outcomes(data, &chosen)?;
    let findings =
        crate::findings::Findings::new(data, &options.finite_strain, &options.refinement);
    let findings_html = crate::findings::section(&findings);
    let summary = Summary::new(
        &options.title,
        data,
        &options.area_fractions,
        chosen.reference.map(|k| k.label.as_str()),
        outcomes.iter().map(|o| o.status.clone()).collect(),
        findings,
    )
    .with_refinement(&data.refinement, &options.refinement);

    let mut body = format!("<h1>{}</h1>\n", escape(&options.title));
    body.push_str(&findings_html);
    body.push_str(
        "<p class=\"note\">Reproduces the figures and tables of the study from the pipeline's \
         own results. Self-contained: figures are embedded; PNG and SVG copies and \
         <a href=\"summary.json\">summary.json</a> sit beside this page.</p>\n",
    );
    body.push_str(&skipped_list(&outcomes));
    let by_name = |name: &str| outcomes.iter().find(|o| o.status.name == name);
    body.push_str("<h2>Material: tensile tests and hyperelastic fit</h2>\n");
    if let Some(o) = by_name("fig2") {
        body.push_str(&figure_html(o, ""));
    }
    body.push_str(&material_tables(data, options.published_material));
    body.push_str("<h2>Rough surfaces</h2>\n");
    if let Some(o) = by_name("fig4") {
        body.push_str(&figure_html(o, ""));
    }
    body.push_str(&surface_statistics_html(data, &outcomes));
    let (fig6_html, fig6_images) = crate::experiment::fig6(data)?;
    body.push_str(&contact_sections(
        data, &chosen, &summary, &outcomes, &fig6_html,
    ));
    let (finite_html, fig10) =
        crate::finite_strain::section(&data.finite_strain, &options.finite_strain)?;
    body.push_str(&finite_html);
    let (refinement_html, fig11) =
        crate::refinement::section(&data.refinement, &options.refinement, provenance)?;
    body.push_str(&refinement_html);
    body.push_str("<h2>Summary per sample</h2>\n");
    body.push_str(&sample_table(&summary, &chosen.summary));
    body.push_str(&provenance_section(provenance));

    let mut files = Files::new()
        .with("index.html", page(&options.title, &body).into_bytes())
        .with("summary.json", summary.to_json());
    for (name, png) in fig6_images {
        files = files.with(&name, png);
    }
    for r in outcomes
        .into_iter()
        .filter_map(|o| o.rendered)
        .chain(fig10)
        .chain(fig11)
    {
        files = files
            .with(&format!("{}.png", r.name), r.png)
            .with(&format!("{}.svg", r.name), r.svg.into_bytes());
    }
    Ok(files)
}

/// The areal parameters' table and Figs. 4b–4e, or a note on what is not
/// wired (a pipeline or cache from before the surface stage wrote them).
fn surface_statistics_html(data: &ReportData<'_>, outcomes: &[Outcome]) -> String {
    let mut html = crate::surface_stats::areal_table_html(&data.samples);
    let any_surface = data
        .samples
        .iter()
        .any(|s| s.height.is_some() || s.stats.is_some() || s.extras != Default::default());
    if html.is_empty() && any_surface {
        html.push_str(
            "<p class=\"skipped\"><b>Areal parameters</b> not shown: input `areal` (an output \
             of the surface stage from version 6) is not wired for any sample.</p>\n",
        );
    }
    let missing = crate::surface_stats::missing_notes(&data.samples);
    if !missing.is_empty() {
        html.push_str(&format!(
            "<p class=\"note\">Surface statistics not wired: {}.</p>\n",
            escape(&missing.join("; "))
        ));
    }
    for name in ["fig4b", "fig4c", "fig4d", "fig4e"] {
        if let Some(o) = outcomes
            .iter()
            .find(|o| o.status.name == name)
            .filter(|o| o.status.rendered || any_surface)
        {
            html.push_str(&figure_html(o, ""));
        }
    }
    html
}

/// The list of figures not drawn, with the reasons.
fn skipped_list(outcomes: &[Outcome]) -> String {
    let skipped: Vec<&Outcome> = outcomes.iter().filter(|o| !o.status.rendered).collect();
    if skipped.is_empty() {
        return String::new();
    }
    let mut html =
        String::from("<div class=\"skipped\"><b>Figures not drawn in this run:</b><ul>\n");
    for o in skipped {
        html.push_str(&format!(
            "<li>{}: {}</li>\n",
            o.status.name,
            escape(o.status.note.as_deref().unwrap_or(""))
        ));
    }
    html.push_str("</ul></div>\n");
    html
}

#[cfg(test)]
mod tests {
    use super::*;

    fn range(
        mode: &str,
        lo: f64,
        hi: f64,
        edges: (bool, bool),
        window: (f64, f64),
    ) -> StabilityRange {
        StabilityRange {
            mode: mode.into(),
            lambda_min: lo,
            lambda_max: hi,
            min_at_edge: edges.0,
            max_at_edge: edges.1,
            window,
        }
    }

    /// A limit at the search range's edge is said to be one, not reported
    /// as a finding; the imposed windows get a column only when there are
    /// some.
    #[test]
    fn the_stability_table_tells_edges_from_limits_and_gives_the_windows() {
        let html = stability_table(&[
            range("UT", 0.18, 10.0, (false, true), (1.0, 3.2)),
            range("BT", 0.5612, 2.33, (false, false), (0.6, 2.3)),
        ]);
        assert!(
            html.contains(
                "<tr><td>UT</td><td>0.18</td><td>10 (edge of the search: stable throughout)</td>\
                 <td>1 – 3.2</td></tr>"
            ),
            "{html}"
        );
        assert!(
            html.contains("<tr><td>BT</td><td>0.5612</td><td>2.33</td><td>0.6 – 2.3</td></tr>")
        );
        let nan = (f64::NAN, f64::NAN);
        let html = stability_table(&[range("PT", 0.1, 10.0, (true, true), nan)]);
        assert!(!html.contains("in-range"), "{html}");
        assert!(html.contains("<td>0.1 (edge of the search: stable throughout)</td>"));
    }
}
