//! The finite-strain judgement (issue #33): on one patch per sample, each
//! contact model's load over the finite-element solution's (`fem`, the
//! nearly incompressible hyperelastic block at finite strain) at equal
//! contact area, as a figure, a table and a few sentences that say what the
//! numbers find. Loads are compared as F/(E0* A0), so models whose nominal
//! area differs (a periodic model on the patch's mirror tiling has four
//! times the patch's) still compare mean contact pressures.

use crate::ReportError;
use crate::figures::fig10::Fig10;
use crate::figures::plotting::{Rendered, render};
use crate::gather::{PatchCurve, PatchCurves};
use crate::html::{anchored_table, escape, fmt_sig};
use crate::interp::interpolate;

/// What the finite-strain section compares.
#[derive(Clone, Debug, PartialEq)]
pub struct FiniteStrainOptions {
    /// The label of the reference (the finite-element solution).
    pub reference: String,
    /// A/A0 at which the ratios are read.
    pub area_fractions: Vec<f64>,
}

impl Default for FiniteStrainOptions {
    fn default() -> Self {
        Self {
            reference: "fem".into(),
            area_fractions: vec![0.05, 0.1, 0.2, 0.3],
        }
    }
}

/// One model's ratios on one sample: F_model / F_reference at each area
/// fraction (None outside either curve).
#[derive(Clone, Debug, PartialEq)]
pub struct Ratios {
    pub sample: String,
    pub model: String,
    pub ratios: Vec<Option<f64>>,
}

/// The ratios of every non-reference curve of every sample that has the
/// reference; samples without it are named in the second list.
pub fn ratios(
    patches: &[PatchCurves],
    options: &FiniteStrainOptions,
) -> (Vec<Ratios>, Vec<String>) {
    let mut out = Vec::new();
    let mut missing = Vec::new();
    for patch in patches {
        let Some(reference) = curve(patch, &options.reference) else {
            missing.push(patch.sample.clone());
            continue;
        };
        for (label, c) in &patch.curves {
            if *label == options.reference {
                continue;
            }
            let ratios = options
                .area_fractions
                .iter()
                .map(|&a| {
                    let model = interpolate(&c.area_fraction, &c.load_norm, a)?;
                    let fem = interpolate(&reference.area_fraction, &reference.load_norm, a)?;
                    (fem > 0.0).then(|| model / fem)
                })
                .collect();
            out.push(Ratios {
                sample: patch.sample.clone(),
                model: label.clone(),
                ratios,
            });
        }
    }
    (out, missing)
}

fn curve<'a>(patch: &'a PatchCurves, label: &str) -> Option<&'a PatchCurve> {
    patch
        .curves
        .iter()
        .find(|(l, _)| l == label)
        .map(|(_, c)| c)
}

/// Per model (in first-seen order), the mean of its ratios over the
/// samples at each area fraction (None where no sample has one).
pub fn means(rows: &[Ratios], fractions: usize) -> Vec<(String, Vec<Option<f64>>)> {
    let mut models: Vec<String> = Vec::new();
    for r in rows {
        if !models.contains(&r.model) {
            models.push(r.model.clone());
        }
    }
    models
        .into_iter()
        .map(|m| {
            let mean = (0..fractions)
                .map(|k| {
                    let values: Vec<f64> = rows
                        .iter()
                        .filter(|r| r.model == m)
                        .filter_map(|r| r.ratios[k])
                        .collect();
                    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
                })
                .collect();
            (m, mean)
        })
        .collect()
}

/// The mean of a model's available means over the area fractions.
fn overall(values: &[Option<f64>]) -> Option<f64> {
    let v: Vec<f64> = values.iter().flatten().copied().collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// What the numbers find, in words: the closest and the farthest model,
/// then, for each family wired with both its hyperelastic law (`x`) and
/// its linear law (`x-linear`), whether the tangent modulus brings the
/// load nearer the finite-strain solution or takes it away.
pub fn findings(means: &[(String, Vec<Option<f64>>)], reference: &str) -> String {
    let all: Vec<(&str, f64)> = means
        .iter()
        .filter_map(|(m, v)| overall(v).map(|r| (m.as_str(), r)))
        .collect();
    // The reference's own variants (e.g. `fem-small`, the same mesh at small
    // strain) measure the finite-strain effect; they are no contact model.
    let own = |m: &str| m.split('-').next() == reference.split('-').next();
    let mut text = String::new();
    for (m, r) in all.iter().filter(|(m, _)| own(m)) {
        text.push_str(&format!(
            "The same finite-element problem as {} gives {}× F<sub>{reference}</sub>: the \
             finite-strain effect itself. ",
            escape(m),
            fmt_sig(*r, 3)
        ));
    }
    let scored: Vec<(&str, f64)> = all.into_iter().filter(|(m, _)| !own(m)).collect();
    let distance = |r: f64| r.ln().abs();
    let Some(best) = scored
        .iter()
        .min_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))
    else {
        return String::new();
    };
    let worst = scored
        .iter()
        .max_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))
        .unwrap_or(best);
    text.push_str(&format!(
        "Averaged over the samples and the area fractions, the contact model nearest the \
         finite-strain solution is {} ({}× F<sub>{reference}</sub>), the farthest {} ({}×).",
        escape(best.0),
        fmt_sig(best.1, 3),
        escape(worst.0),
        fmt_sig(worst.1, 3),
    ));
    for (model, hyper) in &scored {
        let linear_label = format!("{model}-linear");
        let Some((_, linear)) = scored.iter().find(|(m, _)| *m == linear_label) else {
            continue;
        };
        let verdict = if distance(*hyper) < distance(*linear) {
            "brings the load nearer the finite-strain solution"
        } else {
            "takes the load further from the finite-strain solution"
        };
        text.push_str(&format!(
            " {}: {}× with its hyperelastic law, {}× with the linear one, so the tangent \
             modulus {verdict}.",
            escape(model),
            fmt_sig(*hyper, 3),
            fmt_sig(*linear, 3),
        ));
    }
    text
}

/// The section's HTML (figure embedded when rendered) and the figure.
pub fn section(
    patches: &[PatchCurves],
    options: &FiniteStrainOptions,
) -> Result<(String, Option<Rendered>), ReportError> {
    if patches.is_empty() {
        return Ok((String::new(), None));
    }
    let (rows, missing) = ratios(patches, options);
    let mut html = String::from("<h2>Finite strain: the tangent-modulus models judged</h2>\n");
    let figure = render(&Fig10 {
        patches,
        reference: &options.reference,
    })?;
    html.push_str(&format!(
        "<figure id=\"fig10\">\n{}\n<figcaption><b>Fig. 10.</b> {CAPTION} Files: \
         <a href=\"fig10.png\">fig10.png</a>, <a href=\"fig10.svg\">fig10.svg</a>.\
         </figcaption>\n</figure>\n",
        figure.svg
    ));
    if !missing.is_empty() {
        html.push_str(&format!(
            "<p class=\"note\">No `{}` curve is wired for {}: no ratios there.</p>\n",
            escape(&options.reference),
            escape(&missing.join(", "))
        ));
    }
    html.push_str(&ratio_table(&rows, options));
    Ok((html, Some(figure)))
}

const CAPTION: &str = "One patch per sample, every model on the same window: the finite-element \
     solution at finite strain (fem: the nearly incompressible hyperelastic block pressed by a \
     rigid flat, black) beside the profile (icm), boundary-element (bem) and Persson models; \
     colour = model family, stroke = law (solid: the paper's equibiaxial tangent modulus; \
     dashed: the uniaxial tangent; dotted: linear elasticity with E0*). The periodic models \
     (bem, Persson) solve the patch's mirror-image tiling, which is the problem fem solves with \
     symmetry planes for lateral faces; icm reads the patch's own truncation profile.";

/// The anchor of the F_model/F_reference table.
pub const TABLE_ID: &str = "fig10-table";

fn ratio_table(rows: &[Ratios], options: &FiniteStrainOptions) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let cell = |v: Option<f64>| v.map_or("n/a".into(), |v| fmt_sig(v, 3));
    let mut header = vec!["sample".to_owned(), "model".to_owned()];
    header.extend(
        options
            .area_fractions
            .iter()
            .map(|a| format!("A/A<sub>0</sub> = {a}")),
    );
    let mut body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            let mut row = vec![escape(&r.sample), escape(&r.model)];
            row.extend(r.ratios.iter().map(|v| cell(*v)));
            row
        })
        .collect();
    let means = means(rows, options.area_fractions.len());
    for (model, values) in &means {
        let mut row = vec!["mean".to_owned(), escape(model)];
        row.extend(values.iter().map(|v| cell(*v)));
        body.push(row);
    }
    let mut html = anchored_table(
        TABLE_ID,
        &format!(
            "Load ratio F_model / F_{} at equal contact area A/A0 on the patch",
            options.reference
        ),
        &header,
        &body,
    );
    html.push_str(&format!(
        "<p class=\"note\">Loads as F/(E<sub>0</sub>* A<sub>0</sub>) read off each curve by \
         linear interpolation in A/A<sub>0</sub> (n/a outside a curve). A ratio of 1: the model \
         predicts the finite-strain load; 2: twice it. {}</p>\n",
        findings(&means, &options.reference)
    ));
    html
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A straight load–area curve of `slope` (test fixture, shared with
    /// `findings`).
    pub(crate) fn line(slope: f64) -> PatchCurve {
        PatchCurve {
            area_fraction: vec![0.0, 0.1, 0.2, 0.4],
            load_norm: vec![0.0, slope * 0.1, slope * 0.2, slope * 0.4],
        }
    }

    /// A sample's patch curves, each a [`line`] of the given slope.
    pub(crate) fn patch(sample: &str, curves: &[(&str, f64)]) -> PatchCurves {
        PatchCurves {
            sample: sample.into(),
            curves: curves
                .iter()
                .map(|(l, s)| (l.to_string(), line(*s)))
                .collect(),
        }
    }

    #[test]
    fn ratios_divide_at_equal_area_and_average_over_samples() {
        let patches = [
            patch(
                "T1",
                &[
                    ("fem", 1.0),
                    ("icm", 2.0),
                    ("icm-linear", 1.1),
                    ("fem-small", 0.5),
                ],
            ),
            patch("T2", &[("fem", 2.0), ("icm", 5.0), ("icm-linear", 2.0)]),
            patch("T3", &[("icm", 1.0)]),
        ];
        let options = FiniteStrainOptions {
            area_fractions: vec![0.05, 0.3, 0.5],
            ..Default::default()
        };
        let (rows, missing) = ratios(&patches, &options);
        assert_eq!(missing, vec!["T3".to_owned()]);
        assert_eq!(rows.len(), 5);
        assert_eq!(rows[0].model, "icm");
        // Linear curves through the origin: the ratio of the slopes; none
        // beyond the curves' end (0.4).
        let r = &rows[0].ratios;
        assert!((r[0].unwrap() - 2.0).abs() < 1e-12 && (r[1].unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(r[2], None);
        let m = means(&rows, 3);
        assert_eq!(m[0].0, "icm");
        assert!((m[0].1[0].unwrap() - 2.25).abs() < 1e-12);
        assert!((m[1].1[1].unwrap() - 1.05).abs() < 1e-12);
        let words = findings(&m, "fem");
        assert!(
            words.contains("nearest the finite-strain solution is icm-linear"),
            "{words}"
        );
        assert!(words.contains("the farthest icm"), "{words}");
        assert!(
            words.contains(
                "icm: 2.25× with its hyperelastic law, 1.05× with the linear one, so \
                            the tangent modulus takes the load further"
            ),
            "{words}"
        );
    }
}
