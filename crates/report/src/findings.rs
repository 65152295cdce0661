//! "What this rerun finds" (issue #49): the report's opening sentences,
//! written from the numbers its later sections compute, each pointing to
//! the figure or table it comes from. A sentence whose inputs are not wired
//! is left out, so a small pipeline still gets a page. The same numbers go
//! to `summary.json` under `findings`.
//!
//! - the paper's claim: the contact models compared with the equibiaxial
//!   tangent modulus (the responses' roster);
//! - the finite-strain verdict: Fig. 10's table of F_model/F_fem
//!   ([`crate::finite_strain::ratios`], the same numbers);
//! - the judge's resolution: the refinement study's F_fem/F_bem at equal
//!   approach (Fig. 11's table, [`crate::refinement::level_ratios`]): the
//!   coarsest refine factor from which linear fem and linear bem agree
//!   within 5 % over A/A0 0.05–0.3, or the closest level when none does;
//! - the experiment: contact-compare's agreement and load-ratio tables,
//!   with the models of the experiment's own physics set apart.

use serde::Serialize;

use crate::experiment::{AGREEMENT_ID, Scored, marked, physics_of};
use crate::finite_strain::{FiniteStrainOptions, Ratios, TABLE_ID, ratios};
use crate::gather::{PatchCurves, ReportData, Sample};
use crate::html::{escape, fmt_sig};
use crate::refinement::{RefinementLevel, RefinementOptions, comparisons, level_ratios};
use crate::roster::{LabelLaw, Roster, label_law};

/// Every finding the data allow; `None` where its inputs are absent.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Findings {
    pub claim: Option<Claim>,
    pub finite_strain: Option<FiniteStrainFinding>,
    pub experiment: Option<ExperimentFinding>,
    /// Left out of summary.json (not null) without the refinement study, so
    /// a summary without it keeps its bytes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refinement: Option<RefinementFinding>,
}

/// The smallest and largest of some numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Span {
    pub min: f64,
    pub max: f64,
}

impl Span {
    fn of(values: impl IntoIterator<Item = f64>) -> Option<Self> {
        values
            .into_iter()
            .filter(|v| v.is_finite())
            .fold(None, |span, v| {
                Some(match span {
                    None => Span { min: v, max: v },
                    Some(Span { min, max }) => Span {
                        min: min.min(v),
                        max: max.max(v),
                    },
                })
            })
    }

    /// "a–b" with `digits` significant digits, one number when they agree.
    fn text(self, digits: usize) -> String {
        let (lo, hi) = (fmt_sig(self.min, digits), fmt_sig(self.max, digits));
        if lo == hi { lo } else { format!("{lo}–{hi}") }
    }
}

/// The paper's comparison as wired: the models with the equibiaxial tangent
/// of the fitted law, and the linear-elastic ones beside them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Claim {
    pub equibiaxial_models: Vec<String>,
    pub linear_models: Vec<String>,
    /// E_t*/E0* of the equibiaxial models at their first computed row,
    /// over the models and samples (the sentence gives the smallest: the
    /// start of Fig. 8's curves).
    pub first_contact_tangent: Option<Span>,
}

/// Fig. 10's table in a few numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FiniteStrainFinding {
    /// The finite-strain reference's label and its small-strain twin's.
    pub reference: String,
    pub small_strain: Option<String>,
    pub samples: Vec<String>,
    /// The A/A0 range the ratios were read over.
    pub area_fractions: Span,
    /// F_reference / F_small over every sample and area fraction.
    pub finite_over_small: Option<Span>,
    /// Per sample the largest |F_reference / F_small − 1| (per cent), as a
    /// range over the samples.
    pub finite_vs_small_percent: Option<Span>,
    pub equibiaxial_models: Vec<String>,
    /// F_model / F_reference of the equibiaxial-tangent models, over every
    /// sample, area fraction and model.
    pub equibiaxial_over_finite: Option<Span>,
    pub linear_models: Vec<String>,
    pub linear_over_finite: Option<Span>,
}

/// Within how many per cent F_fem/F_bem must be of 1 for the two to agree.
pub const REFINEMENT_TOLERANCE_PERCENT: f64 = 5.0;
/// The A/A0 over which they must agree (issue #49's criterion); the
/// compared points inside it are read.
pub const REFINEMENT_AREA_RANGE: [f64; 2] = [0.05, 0.3];

/// The refinement study in a few numbers: at which refine factor linear fem
/// and linear bem agree at equal approach.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RefinementFinding {
    pub tolerance_percent: f64,
    /// The equal-approach points read: the compared A/A0 inside
    /// `REFINEMENT_AREA_RANGE` where every level's ratio is read.
    pub area_fractions: Span,
    /// The refine factors computed, ascending.
    pub refines: Vec<u32>,
    /// true: `level` is the coarsest level from which on every level agrees
    /// within the tolerance; false: none does from any level on, and
    /// `level` is the one with the smallest largest deviation.
    pub agrees: bool,
    pub level: LevelAgreement,
    /// The finest level, where it is not `level`.
    pub finest: Option<LevelAgreement>,
}

/// F_fem/F_bem at equal approach at one level, over the points read.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelAgreement {
    pub refine: u32,
    pub points_per_wavelength: f64,
    pub ratio_equal_approach: Span,
    /// The largest |F_fem/F_bem − 1| over those points (per cent).
    pub largest_deviation_percent: f64,
}

/// The refinement finding; None without levels or without an equal-approach
/// point inside the range that every level reads.
pub fn refinement(
    levels: &[RefinementLevel],
    options: &RefinementOptions,
) -> Option<RefinementFinding> {
    let per_level = level_ratios(&comparisons(levels, options), options);
    let [lo, hi] = REFINEMENT_AREA_RANGE;
    let ratio = |l: &crate::refinement::LevelRatios, i: usize| l.equal_approach.get(i).copied()?;
    let read: Vec<usize> = (0..options.area_fractions.len())
        .filter(|&i| (lo..=hi).contains(&options.area_fractions[i]))
        .filter(|&i| per_level.iter().all(|l| ratio(l, i).is_some()))
        .collect();
    let area_fractions = Span::of(read.iter().map(|&i| options.area_fractions[i]))?;
    let agreement: Vec<LevelAgreement> = per_level
        .iter()
        .map(|l| {
            let ratios: Vec<f64> = read.iter().filter_map(|&i| ratio(l, i)).collect();
            Some(LevelAgreement {
                refine: l.refine,
                points_per_wavelength: l.points_per_wavelength,
                ratio_equal_approach: Span::of(ratios.iter().copied())?,
                largest_deviation_percent: ratios
                    .iter()
                    .map(|r| 100.0 * (r - 1.0).abs())
                    .fold(0.0, f64::max),
            })
        })
        .collect::<Option<_>>()?;
    let within = |l: &LevelAgreement| l.largest_deviation_percent <= REFINEMENT_TOLERANCE_PERCENT;
    // A level that agrees while a finer one does not is no converged answer.
    let from = agreement
        .iter()
        .rposition(|l| !within(l))
        .map_or(0, |i| i + 1);
    let (agrees, at) = if from < agreement.len() {
        (true, from)
    } else {
        let closest = (0..agreement.len()).min_by(|&a, &b| {
            let deviation = |i: usize| agreement[i].largest_deviation_percent;
            deviation(a).total_cmp(&deviation(b))
        })?;
        (false, closest)
    };
    let finest = (at + 1 < agreement.len()).then(|| agreement[agreement.len() - 1].clone());
    Some(RefinementFinding {
        tolerance_percent: REFINEMENT_TOLERANCE_PERCENT,
        area_fractions,
        refines: agreement.iter().map(|l| l.refine).collect(),
        agrees,
        level: agreement[at].clone(),
        finest,
    })
}

/// The experiment against the models it is scored with.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExperimentFinding {
    pub samples: Vec<String>,
    /// The physics that rendered the experiment (empty: not stated).
    pub physics: Vec<String>,
    /// The models that share it: agreeing by construction, not ranked.
    pub by_construction: Vec<String>,
    /// The model ranked first among the others, per model that is.
    pub best: Vec<BestModel>,
    pub equibiaxial_models: Vec<String>,
    /// F_model / F_experiment of the equibiaxial-tangent models over the
    /// samples: at `load_ratio_area_fraction` from the load-ratio tables,
    /// or (None) exp of the mean ln ratio over the scored frames.
    pub equibiaxial_over_experiment: Option<Span>,
    pub load_ratio_area_fraction: Option<f64>,
}

/// A model ranked first (among the models not of the experiment's physics)
/// on `samples`, with its rms ln(F_model/F_exp) there.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BestModel {
    pub model: String,
    pub samples: Vec<String>,
    pub rms_log_ratio: Span,
}

impl Findings {
    /// The findings of the report's data.
    /// Model lists follow the roster's order (labels it lacks after).
    pub fn new(
        data: &ReportData<'_>,
        options: &FiniteStrainOptions,
        refinement_options: &RefinementOptions,
    ) -> Self {
        let mut findings = Findings {
            claim: claim(&data.roster, &data.samples),
            finite_strain: finite_strain(&data.finite_strain, options),
            experiment: experiment(&crate::experiment::scored(data), &data.roster),
            refinement: refinement(&data.refinement, refinement_options),
        };
        let roster = &data.roster;
        let order = |labels: &mut Vec<String>| labels.sort_by_key(|l| roster.position(l));
        if let Some(f) = &mut findings.finite_strain {
            order(&mut f.equibiaxial_models);
            order(&mut f.linear_models);
        }
        if let Some(e) = &mut findings.experiment {
            order(&mut e.by_construction);
            order(&mut e.equibiaxial_models);
        }
        findings
    }
}

/// A label of the equibiaxial tangent in the roster: no law suffix and a
/// tangent ratio that is not 1 throughout (where the data say).
fn equibiaxial(roster: &Roster, label: &str) -> bool {
    label_law(label) == LabelLaw::Equibiaxial && roster.get(label).is_none_or(|k| !k.linear)
}

/// The models compared, from the roster, with the tangent ratio their
/// responses in `samples` start from; None without an equibiaxial model.
pub fn claim(roster: &Roster, samples: &[Sample<'_>]) -> Option<Claim> {
    let labels = |keep: &dyn Fn(&str) -> bool| -> Vec<String> {
        roster
            .models
            .iter()
            .filter(|k| keep(&k.label))
            .map(|k| k.label.clone())
            .collect()
    };
    let equibiaxial_models = labels(&|l| equibiaxial(roster, l));
    let linear_models = labels(&|l| roster.get(l).is_some_and(|k| k.linear));
    let first_contact_tangent = Span::of(samples.iter().flat_map(|s| {
        equibiaxial_models.iter().filter_map(|m| {
            let r = s.response(m)?;
            r.tangent_ratio.iter().copied().find(|t| t.is_finite())
        })
    }));
    (!equibiaxial_models.is_empty()).then_some(Claim {
        equibiaxial_models,
        linear_models,
        first_contact_tangent,
    })
}

/// The distinct labels of `rows` that `keep` accepts, in first-seen order.
fn models_of(rows: &[Ratios], keep: impl Fn(&str) -> bool) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in rows.iter().filter(|r| keep(&r.model)) {
        if !out.contains(&r.model) {
            out.push(r.model.clone());
        }
    }
    out
}

/// Every ratio of the rows of `models`.
fn cells<'a>(rows: &'a [Ratios], models: &'a [String]) -> impl Iterator<Item = f64> + 'a {
    rows.iter()
        .filter(|r| models.contains(&r.model))
        .flat_map(|r| r.ratios.iter().flatten().copied())
}

/// Fig. 10's numbers; None without any ratio to the reference.
pub fn finite_strain(
    patches: &[PatchCurves],
    options: &FiniteStrainOptions,
) -> Option<FiniteStrainFinding> {
    let (rows, _) = ratios(patches, options);
    let reference = options.reference.as_str();
    let family = |l: &str| l.split('-').next().unwrap_or(l).to_owned();
    let own = |l: &str| family(l) == family(reference);
    let small_strain = models_of(&rows, own).into_iter().next();
    let small: Vec<&Ratios> = rows
        .iter()
        .filter(|r| Some(&r.model) == small_strain.as_ref())
        .collect();
    let inverse =
        |r: &&Ratios| -> Vec<f64> { r.ratios.iter().flatten().map(|x| 1.0 / x).collect() };
    let finite_over_small = Span::of(small.iter().flat_map(inverse));
    let finite_vs_small_percent = Span::of(small.iter().filter_map(|r| {
        let deviations = inverse(r).into_iter().map(|v| 100.0 * (v - 1.0).abs());
        deviations.reduce(f64::max)
    }));
    let equibiaxial_models = models_of(&rows, |l| !own(l) && label_law(l) == LabelLaw::Equibiaxial);
    let linear_models = models_of(&rows, |l| !own(l) && label_law(l) == LabelLaw::Linear);
    let finding = FiniteStrainFinding {
        reference: reference.to_owned(),
        small_strain,
        samples: models_of_samples(&rows),
        area_fractions: Span::of(options.area_fractions.iter().copied())?,
        finite_over_small,
        finite_vs_small_percent,
        equibiaxial_over_finite: Span::of(cells(&rows, &equibiaxial_models)),
        equibiaxial_models,
        linear_over_finite: Span::of(cells(&rows, &linear_models)),
        linear_models,
    };
    let any = finding.finite_over_small.is_some()
        || finding.equibiaxial_over_finite.is_some()
        || finding.linear_over_finite.is_some();
    any.then_some(finding)
}

/// The samples of `rows` in first-seen order.
fn models_of_samples(rows: &[Ratios]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in rows {
        if !out.contains(&r.sample) {
            out.push(r.sample.clone());
        }
    }
    out
}

/// The load ratio's A/A0 nearest 0.5 in any sample's table.
fn ratio_fraction(samples: &[Scored<'_>]) -> Option<f64> {
    samples
        .iter()
        .flat_map(|s| s.load_ratio.iter().flat_map(|r| r.area_fraction.iter()))
        .copied()
        .min_by(|a, b| (a - 0.5).abs().total_cmp(&(b - 0.5).abs()))
}

/// The first-ranked model among those judged, per sample, grouped by model.
fn best_models(samples: &[Scored<'_>]) -> Vec<BestModel> {
    let mut best: Vec<BestModel> = Vec::new();
    for s in samples {
        let a = s.agreement;
        let judged =
            (0..a.model.len()).filter(|&k| a.by_construction.get(k).is_none_or(|&b| b == 0));
        let Some(k) = judged.min_by_key(|&k| a.rank[k]) else {
            continue;
        };
        let rms = a.rms_log_ratio[k];
        match best.iter_mut().find(|b| b.model == a.model[k]) {
            Some(b) => {
                b.samples.push(s.label.to_owned());
                b.rms_log_ratio = Span::of([b.rms_log_ratio.min, b.rms_log_ratio.max, rms])
                    .unwrap_or(b.rms_log_ratio);
            }
            None => best.extend(Span::of([rms]).map(|span| BestModel {
                model: a.model[k].clone(),
                samples: vec![s.label.to_owned()],
                rms_log_ratio: span,
            })),
        }
    }
    best
}

/// The experiment's finding; None without an agreement table.
pub fn experiment(samples: &[Scored<'_>], roster: &Roster) -> Option<ExperimentFinding> {
    if samples.is_empty() {
        return None;
    }
    let mut physics: Vec<String> = Vec::new();
    let mut by_construction: Vec<String> = Vec::new();
    let mut equibiaxial_models: Vec<String> = Vec::new();
    for s in samples {
        let a = s.agreement;
        let shared = marked(a);
        if let Some(p) = physics_of(a).filter(|p| !physics.iter().any(|q| q == p)) {
            physics.push(p.to_owned());
        }
        for m in &a.model {
            let list = if shared.contains(&m.as_str()) {
                &mut by_construction
            } else if equibiaxial(roster, m) {
                &mut equibiaxial_models
            } else {
                continue;
            };
            if !list.contains(m) {
                list.push(m.clone());
            }
        }
    }
    let at = ratio_fraction(samples);
    let ratios = samples.iter().flat_map(|s| {
        let a = s.agreement;
        let of_model = |m: &String| equibiaxial_models.contains(m) && !by_construction.contains(m);
        match (at, s.load_ratio) {
            (Some(at), Some(r)) => (0..r.model.len())
                .filter(|&i| r.area_fraction[i] == at && of_model(&r.model[i]))
                .map(|i| r.load_ratio[i])
                .collect::<Vec<f64>>(),
            (Some(_), None) => Vec::new(),
            (None, _) => (0..a.model.len())
                .filter(|&k| of_model(&a.model[k]))
                .map(|k| a.mean_log_ratio[k].exp())
                .collect(),
        }
    });
    let equibiaxial_over_experiment = Span::of(ratios);
    Some(ExperimentFinding {
        samples: samples.iter().map(|s| s.label.to_owned()).collect(),
        physics,
        by_construction,
        best: best_models(samples),
        equibiaxial_over_experiment,
        equibiaxial_models,
        load_ratio_area_fraction: at,
    })
}

/// A comma-separated list of labels, escaped.
fn list(labels: &[String]) -> String {
    escape(&labels.join(", "))
}

/// The sentence on the paper's claim.
fn claim_html(c: &Claim) -> String {
    let linear = if c.linear_models.is_empty() {
        String::new()
    } else {
        format!(
            "; this rerun draws linear elasticity with E<sub>0</sub>* ({}) beside them",
            list(&c.linear_models)
        )
    };
    let start = c.first_contact_tangent.map_or(String::new(), |t| {
        format!(
            " (E<sub>t</sub>*/E<sub>0</sub>* from {} at first contact)",
            fmt_sig(t.min, 3)
        )
    });
    format!(
        "<p><b>The paper's comparison.</b> The paper compares contact models ({}) that load \
         the rubber with the tangent modulus of the fitted hyperelastic law read off its \
         equibiaxial curve{start}{linear} (<a href=\"#fig7\">Fig. 7</a>, \
         <a href=\"#fig8\">Fig. 8</a>).</p>\n",
        list(&c.equibiaxial_models)
    )
}

/// The sentence on the finite-strain verdict.
fn finite_strain_html(f: &FiniteStrainFinding) -> String {
    let areas = f.area_fractions.text(3);
    let samples = list(&f.samples);
    let reference = escape(&f.reference);
    let mut clauses = Vec::new();
    if let (Some(small), Some(ratio), Some(percent)) = (
        &f.small_strain,
        f.finite_over_small,
        f.finite_vs_small_percent,
    ) {
        clauses.push(format!(
            "the finite-strain solution ({reference}) carries the small-strain load to within \
             {} % (F<sub>{reference}</sub>/F<sub>{}</sub> = {}; per sample its largest \
             deviation)",
            percent.text(2),
            escape(small),
            ratio.text(4)
        ));
    }
    if let Some(span) = f.equibiaxial_over_finite {
        clauses.push(format!(
            "with the equibiaxial tangent the models ({}) carry {}× the finite-strain load",
            list(&f.equibiaxial_models),
            span.text(2)
        ));
    }
    if let Some(span) = f.linear_over_finite {
        clauses.push(format!(
            "with linear elasticity ({}) {}×",
            list(&f.linear_models),
            span.text(2)
        ));
    }
    format!(
        "<p><b>Against finite strain.</b> On these surfaces {} (F<sub>model</sub>/\
         F<sub>{reference}</sub> at equal A/A<sub>0</sub> = {areas} on one patch per \
         sample, range over {samples} and these A/A<sub>0</sub>; <a href=\"#fig10\">Fig. 10</a> and \
         <a href=\"#{TABLE_ID}\">its table</a>).</p>\n",
        clauses.join("; ")
    )
}

/// "k = 2 (4 points per shortest wavelength)".
fn level_text(l: &LevelAgreement) -> String {
    format!(
        "k = {} ({} points per shortest wavelength)",
        l.refine,
        fmt_sig(l.points_per_wavelength, 3)
    )
}

/// The sentence on the refinement study.
fn refinement_html(r: &RefinementFinding) -> String {
    let tolerance = fmt_sig(r.tolerance_percent, 2);
    let ratio = |l: &LevelAgreement| {
        format!(
            "F<sub>fem</sub>/F<sub>bem</sub> = {}",
            l.ratio_equal_approach.text(4)
        )
    };
    let level = &r.level;
    let head = if r.agrees {
        let (from, on) = if r.finest.is_some() {
            ("from", " on")
        } else {
            ("at the finest level computed,", "")
        };
        format!(
            "linear fem and linear bem agree within {tolerance} % at equal approach {from} {}{on}: \
             {}",
            level_text(level),
            ratio(level)
        )
    } else {
        let refines: Vec<String> = r.refines.iter().map(u32::to_string).collect();
        format!(
            "linear fem and linear bem do not stay within {tolerance} % of each other at equal \
             approach up to the finest refine factor computed (k = {}); the closest is {}: {}",
            refines.join(", "),
            level_text(level),
            ratio(level)
        )
    };
    let finest = r.finest.as_ref().map_or(String::new(), |f| {
        format!("; at the finest, {}: {}", level_text(f), ratio(f))
    });
    format!(
        "<p><b>The judge's resolution.</b> On the same window, {head}{finest} (read at the \
         approaches where the finest bem reaches A/A<sub>0</sub> = {}; <a href=\"#fig11\">Fig. \
         11</a> and <a href=\"#{}\">its table</a>).</p>\n",
        r.area_fractions.text(3),
        crate::refinement::TABLE_ID
    )
}

/// The sentence on the experiment.
fn experiment_html(e: &ExperimentFinding) -> String {
    let physics = if e.physics.is_empty() {
        "The experiment's physics is not stated (no truth wired)".to_owned()
    } else {
        format!("The experiment is rendered by <i>{}</i>", list(&e.physics))
    };
    let shared = match e.by_construction.len() {
        0 => "; no compared model shares that physics".to_owned(),
        n => format!(
            "; {} {} it and so {} with the experiment by construction (marked, not ranked)",
            list(&e.by_construction),
            if n == 1 { "shares" } else { "share" },
            if n == 1 { "agrees" } else { "agree" },
        ),
    };
    let best: Vec<String> = e
        .best
        .iter()
        .map(|b| {
            format!(
                "{} on {} (rms ln(F<sub>model</sub>/F<sub>exp</sub>) {})",
                escape(&b.model),
                list(&b.samples),
                b.rms_log_ratio.text(2)
            )
        })
        .collect();
    let mut text = format!("<p><b>The experiment.</b> {physics}{shared}.");
    if !best.is_empty() {
        text.push_str(&format!(
            " Among the others the best-ranked is {}.",
            best.join("; ")
        ));
    }
    if let Some(span) = e.equibiaxial_over_experiment {
        let basis = match e.load_ratio_area_fraction {
            Some(a) => format!("at A/A<sub>0</sub> = {}", fmt_sig(a, 3)),
            None => "on geometric average over the scored frames".to_owned(),
        };
        text.push_str(&format!(
            " The equibiaxial-tangent models ({}) carry {}× the measured load {basis}.",
            list(&e.equibiaxial_models),
            span.text(2)
        ));
    }
    text.push_str(&format!(
        " See <a href=\"#fig7\">Fig. 7</a> and <a href=\"#{AGREEMENT_ID}\">the agreement \
         table</a>.</p>\n"
    ));
    text
}

/// The section's HTML; empty when no finding has its inputs.
pub fn section(f: &Findings) -> String {
    let sentences: Vec<String> = [
        f.claim.as_ref().map(claim_html),
        f.finite_strain.as_ref().map(finite_strain_html),
        f.refinement.as_ref().map(refinement_html),
        f.experiment.as_ref().map(experiment_html),
    ]
    .into_iter()
    .flatten()
    .collect();
    if sentences.is_empty() {
        return String::new();
    }
    format!(
        "<section id=\"findings\">\n<h2>What this rerun finds</h2>\n{}<p class=\"note\">\
         Written from the numbers below (unrounded in <a href=\"summary.json\">summary.json</a>, \
         key <code>findings</code>); a finding whose inputs are not wired is left out.</p>\n\
         </section>\n",
        sentences.concat()
    )
}

#[cfg(test)]
mod tests {
    use hypercontact_compare::stage::{AgreementTable, LoadRatioTable};

    use super::*;
    use crate::finite_strain::tests::patch;
    use crate::roster::ModelKey;

    fn roster(models: &[(&str, bool)]) -> Roster {
        Roster {
            models: models
                .iter()
                .enumerate()
                .map(|(i, &(label, linear))| ModelKey {
                    label: label.into(),
                    colour: i,
                    linear,
                })
                .collect(),
        }
    }

    const LINEAR: &str = "bem, linear elastic, small-strain modulus, free boundary";

    /// icm, bem-linear (the experiment's physics, marked), bem, gw.
    fn agreement(rms: [f64; 4], mean: [f64; 4]) -> AgreementTable {
        AgreementTable {
            model: ["icm", "bem-linear", "bem", "icm-linear"]
                .map(String::from)
                .to_vec(),
            rms_log_ratio: rms.to_vec(),
            mean_log_ratio: mean.to_vec(),
            points: vec![9; 4],
            outside_model: vec![0; 4],
            area: vec!["whole".into(); 4],
            rank: {
                // rank among the judged (bem-linear marked: 0)
                let mut order: Vec<usize> = [0, 2, 3].into();
                order.sort_by(|&a, &b| rms[a].total_cmp(&rms[b]));
                let mut rank = vec![0; 4];
                for (r, k) in order.into_iter().enumerate() {
                    rank[k] = r as i64 + 1;
                }
                rank
            },
            by_construction: vec![0, 1, 0, 0],
            experiment_physics: vec![LINEAR.into(); 4],
        }
    }

    fn load_ratio(at_half: [f64; 4]) -> LoadRatioTable {
        let models = ["icm", "bem-linear", "bem", "icm-linear"];
        LoadRatioTable {
            model: models
                .iter()
                .chain(&models)
                .map(|m| m.to_string())
                .collect(),
            area_fraction: [[0.1; 4], [0.5; 4]].concat(),
            load_ratio: [[9.0; 4], at_half].concat(),
            by_construction: [0, 1, 0, 0, 0, 1, 0, 0].to_vec(),
            experiment_physics: vec![LINEAR.into(); 8],
        }
    }

    /// #49: the finite-strain sentence is Fig. 10's table in numbers: the
    /// small-strain twin per sample, the equibiaxial and linear ranges.
    #[test]
    fn the_finite_strain_finding_reads_fig10s_ratios() {
        let patches = [
            patch(
                "T1",
                &[
                    ("fem", 1.0),
                    ("fem-small", 1.0 / 1.004),
                    ("icm", 2.0),
                    ("bem", 1.6),
                    ("bem-uniaxial", 1.2),
                    ("icm-linear", 0.9),
                ],
            ),
            patch(
                "T2",
                &[
                    ("fem", 2.0),
                    ("fem-small", 2.0 / 0.998),
                    ("icm", 5.8),
                    ("icm-linear", 2.2),
                ],
            ),
        ];
        let options = FiniteStrainOptions::default();
        let f = finite_strain(&patches, &options).unwrap();
        assert_eq!(f.small_strain.as_deref(), Some("fem-small"));
        assert_eq!(f.samples, ["T1", "T2"]);
        assert_eq!(f.equibiaxial_models, ["icm", "bem"]);
        assert_eq!(f.linear_models, ["icm-linear"]);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        let small = f.finite_over_small.unwrap();
        assert!(
            close(small.min, 0.998) && close(small.max, 1.004),
            "{small:?}"
        );
        let percent = f.finite_vs_small_percent.unwrap();
        assert!(
            close(percent.min, 0.2) && close(percent.max, 0.4),
            "{percent:?}"
        );
        let hyper = f.equibiaxial_over_finite.unwrap();
        assert!(close(hyper.min, 1.6) && close(hyper.max, 2.9), "{hyper:?}");
        let linear = f.linear_over_finite.unwrap();
        assert!(
            close(linear.min, 0.9) && close(linear.max, 1.1),
            "{linear:?}"
        );
        assert_eq!((f.area_fractions.min, f.area_fractions.max), (0.05, 0.3));
        let html = finite_strain_html(&f);
        for part in [
            "carries the small-strain load to within 0.2–0.4 %",
            "F<sub>fem</sub>/F<sub>fem-small</sub> = 0.998–1.004",
            "with the equibiaxial tangent the models (icm, bem) carry 1.6–2.9× the \
             finite-strain load",
            "with linear elasticity (icm-linear) 0.9–1.1×",
            "equal A/A<sub>0</sub> = 0.05–0.3",
            "<a href=\"#fig10\">Fig. 10</a>",
            "<a href=\"#fig10-table\">its table</a>",
        ] {
            assert!(html.contains(part), "{part}\n{html}");
        }
        // Without fem-small the first clause goes, the rest stays; without
        // the reference nothing is said.
        let patches = [patch("T1", &[("fem", 1.0), ("icm", 2.0)])];
        let f = finite_strain(&patches, &options).unwrap();
        assert_eq!(f.finite_over_small, None);
        assert!(!finite_strain_html(&f).contains("small-strain"));
        assert_eq!(
            finite_strain(&[patch("T1", &[("icm", 2.0)])], &options),
            None
        );
        assert_eq!(finite_strain(&[], &options), None);
    }

    /// #49: the experiment's sentence: its physics, the model that shares
    /// it set apart, the best of the others, the equibiaxial models' load
    /// ratio at A/A0 = 0.5 (or, without a load-ratio table, exp of the
    /// mean ln ratio).
    #[test]
    fn the_experiment_finding_sets_the_models_of_its_physics_apart() {
        let models = roster(&[
            ("icm", false),
            ("icm-linear", true),
            ("bem", false),
            ("bem-linear", true),
        ]);
        let (a1, a2) = (
            agreement([0.3, 0.01, 0.5, 0.2], [0.3, 0.0, 0.5, -0.1]),
            agreement([0.4, 0.02, 0.3, 0.6], [0.4, 0.0, 0.3, 0.5]),
        );
        let (r1, r2) = (
            load_ratio([1.5, 1.0, 1.9, 0.9]),
            load_ratio([1.7, 1.0, 1.4, 1.1]),
        );
        let samples = [
            Scored {
                label: "T1",
                agreement: &a1,
                load_ratio: Some(&r1),
            },
            Scored {
                label: "T2",
                agreement: &a2,
                load_ratio: Some(&r2),
            },
        ];
        let e = experiment(&samples, &models).unwrap();
        assert_eq!(e.physics, [LINEAR]);
        assert_eq!(e.by_construction, ["bem-linear"]);
        assert_eq!(e.equibiaxial_models, ["icm", "bem"]);
        assert_eq!(e.best.len(), 2);
        assert_eq!(
            (e.best[0].model.as_str(), &e.best[0].samples),
            ("icm-linear", &vec!["T1".to_owned()])
        );
        assert_eq!(e.best[1].model, "bem");
        assert_eq!(e.best[1].rms_log_ratio, Span { min: 0.3, max: 0.3 });
        assert_eq!(e.load_ratio_area_fraction, Some(0.5));
        assert_eq!(
            e.equibiaxial_over_experiment,
            Some(Span { min: 1.4, max: 1.9 })
        );
        let html = experiment_html(&e);
        for part in [
            "rendered by <i>bem, linear elastic, small-strain modulus, free boundary</i>",
            "bem-linear shares it and so agrees with the experiment by construction",
            "the best-ranked is icm-linear on T1 (rms ln(F<sub>model</sub>/F<sub>exp</sub>) \
             0.2); bem on T2",
            "(icm, bem) carry 1.4–1.9× the measured load at A/A<sub>0</sub> = 0.5",
            "<a href=\"#fig7\">Fig. 7</a>",
            "<a href=\"#agreement-table\">the agreement table</a>",
        ] {
            assert!(html.contains(part), "{part}\n{html}");
        }
        // Without load ratios: exp of the mean ln ratio.
        let plain = [Scored {
            label: "T1",
            agreement: &a1,
            load_ratio: None,
        }];
        let e = experiment(&plain, &models).unwrap();
        assert_eq!(e.load_ratio_area_fraction, None);
        let span = e.equibiaxial_over_experiment.unwrap();
        assert!((span.min - 0.3f64.exp()).abs() < 1e-12 && (span.max - 0.5f64.exp()).abs() < 1e-12);
        assert_eq!(experiment(&[], &models), None);
    }

    /// The claim names the equibiaxial models; a section without any
    /// wired input is empty, and each absent input drops its sentence.
    #[test]
    fn absent_inputs_leave_their_sentences_out() {
        let models = roster(&[
            ("icm", false),
            ("icm-linear", true),
            ("icm-uniaxial", false),
        ]);
        let mut sample = Sample {
            label: "T1".into(),
            ..Default::default()
        };
        for (label, start) in [("icm", 2.0), ("icm-linear", 1.0)] {
            sample.models.push(crate::gather::ModelResponse {
                label: label.into(),
                response: crate::gather::Response {
                    area_fraction: vec![0.0, 0.1],
                    load_norm: vec![0.0, 0.01],
                    tangent_ratio: vec![f64::NAN, start],
                    ..Default::default()
                },
            });
        }
        let c = claim(&models, &[sample]).unwrap();
        assert_eq!(c.first_contact_tangent, Some(Span { min: 2.0, max: 2.0 }));
        assert_eq!(c.equibiaxial_models, ["icm"]);
        assert_eq!(c.linear_models, ["icm-linear"]);
        assert_eq!(claim(&roster(&[("icm-linear", true)]), &[]), None);
        assert_eq!(section(&Findings::default()), "");
        let only_claim = section(&Findings {
            claim: Some(c),
            ..Default::default()
        });
        assert!(only_claim.contains("<section id=\"findings\">"));
        assert!(only_claim.contains(
            "The paper compares contact models (icm) that load the rubber with the tangent \
             modulus of the fitted hyperelastic law read off its equibiaxial curve \
             (E<sub>t</sub>*/E<sub>0</sub>* from 2 at first contact); this rerun draws linear \
             elasticity with E<sub>0</sub>* (icm-linear) beside them"
        ));
        assert!(!only_claim.contains("Against finite strain"));
        assert!(!only_claim.contains("The experiment."));
        let json = serde_json::to_value(Findings::default()).unwrap();
        assert_eq!(json["finite_strain"], serde_json::Value::Null);
        // Without the study the key is left out, so such summaries keep
        // their bytes.
        assert!(json.get("refinement").is_none(), "{json}");
    }

    /// Three hand-made levels (`scaled_level`: F_fem/F_bem at equal
    /// approach is f0 at A/A0 ≤ 0.125, 0.25 f0 + 0.75 f1 at 0.2, and
    /// involves f2 beyond 0.25) read at A/A0 0.05, 0.1, 0.2 and 0.35.
    fn study(factors: [[f64; 3]; 3]) -> Option<RefinementFinding> {
        let levels: Vec<RefinementLevel> = (1u32..)
            .zip(factors)
            .map(|(k, f)| crate::refinement::tests::scaled_level(k, f))
            .collect();
        let options = RefinementOptions {
            area_fractions: vec![0.05, 0.1, 0.2, 0.35],
            points_per_wavelength: 2.0,
        };
        refinement(&levels, &options)
    }

    /// #49: the coarsest level from which on fem and bem agree within 5 %
    /// at equal approach over A/A0 0.05–0.3 (A/A0 = 0.35, where k = 2
    /// would be 50 % off, is outside the range and not read).
    #[test]
    fn the_refinement_finding_names_the_level_where_fem_and_bem_agree() {
        let r = study([[0.90, 0.92, 0.92], [0.96, 0.97, 0.5], [0.99, 1.0, 1.0]]).unwrap();
        assert!(r.agrees);
        assert_eq!(r.refines, [1, 2, 3]);
        assert_eq!((r.area_fractions.min, r.area_fractions.max), (0.05, 0.2));
        assert_eq!(r.level.refine, 2);
        assert_eq!(r.level.points_per_wavelength, 4.0);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        let span = r.level.ratio_equal_approach;
        assert!(close(span.min, 0.96) && close(span.max, 0.9675), "{span:?}");
        assert!(close(r.level.largest_deviation_percent, 4.0));
        let finest = r.finest.as_ref().unwrap();
        assert_eq!(finest.refine, 3);
        let html = refinement_html(&r);
        for part in [
            "linear fem and linear bem agree within 5 % at equal approach from k = 2 (4 points \
             per shortest wavelength) on: F<sub>fem</sub>/F<sub>bem</sub> = 0.96–0.9675",
            "at the finest, k = 3 (6 points per shortest wavelength): \
             F<sub>fem</sub>/F<sub>bem</sub> = 0.99–0.9975",
            "where the finest bem reaches A/A<sub>0</sub> = 0.05–0.2",
            "<a href=\"#fig11\">Fig. 11</a>",
            "<a href=\"#fig11-table\">its table</a>",
        ] {
            assert!(html.contains(part), "{part}\n{html}");
        }
        // A coarse level that agrees while a finer one does not is passed
        // over: here only the finest agrees from there on.
        let r = study([[0.99, 0.99, 0.99], [0.9, 0.9, 0.9], [0.98, 0.98, 0.98]]).unwrap();
        assert!(r.agrees && r.level.refine == 3 && r.finest.is_none());
        assert!(
            refinement_html(&r).contains("at the finest level computed, k = 3"),
            "{}",
            refinement_html(&r)
        );
        // The section exists with this sentence alone.
        let page = section(&Findings {
            refinement: Some(r),
            ..Default::default()
        });
        assert!(page.contains("<b>The judge's resolution.</b>"), "{page}");
    }

    /// #49: no level agrees within 5 %: the sentence says so and gives the
    /// closest level's numbers (and the finest's when that is another).
    #[test]
    fn the_refinement_finding_gives_the_closest_level_when_none_agrees() {
        let r = study([[0.80, 0.80, 0.80], [0.90, 0.88, 0.88], [0.93, 0.92, 0.92]]).unwrap();
        assert!(!r.agrees);
        assert_eq!(r.level.refine, 3);
        assert_eq!(r.finest, None);
        // 0.25 · 0.93 + 0.75 · 0.92 = 0.9225 at A/A0 = 0.2.
        let span = r.level.ratio_equal_approach;
        assert!((span.min - 0.9225).abs() < 1e-12 && (span.max - 0.93).abs() < 1e-12);
        assert!((r.level.largest_deviation_percent - 7.75).abs() < 1e-9);
        let html = refinement_html(&r);
        for part in [
            "do not stay within 5 % of each other at equal approach up to the finest refine \
             factor computed (k = 1, 2, 3)",
            "the closest is k = 3 (6 points per shortest wavelength): \
             F<sub>fem</sub>/F<sub>bem</sub> = 0.9225–0.93",
        ] {
            assert!(html.contains(part), "{part}\n{html}");
        }
        assert!(!html.contains("at the finest,"), "{html}");
        // The closest is not the finest: both are given.
        let r = study([[0.80, 0.80, 0.80], [0.93, 0.93, 0.93], [0.90, 0.90, 0.90]]).unwrap();
        assert!(!r.agrees && r.level.refine == 2);
        let html = refinement_html(&r);
        assert!(
            html.contains("the closest is k = 2 (4 points per shortest wavelength)")
                && html.contains(
                    "at the finest, k = 3 (6 points per shortest wavelength): \
                                  F<sub>fem</sub>/F<sub>bem</sub> = 0.9"
                ),
            "{html}"
        );
        // No level, or no compared point inside 0.05–0.3: no finding.
        assert_eq!(refinement(&[], &RefinementOptions::default()), None);
        let levels = [crate::refinement::tests::scaled_level(1, [1.0; 3])];
        let outside = RefinementOptions {
            area_fractions: vec![0.35],
            ..Default::default()
        };
        assert_eq!(refinement(&levels, &outside), None);
    }
}
