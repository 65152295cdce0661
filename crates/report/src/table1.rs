//! Table 1 of the paper as HTML: the fitted parameters (one row per Ogden
//! term), each with its 5–95 % bootstrap interval where the fit's `params`
//! carries one, the initial moduli μ0, E0 and E0*, and one line stating the
//! fit's constraint and objective beside the other setting's (from
//! `comparison`), so both the paper's unconstrained Abaqus fit and the
//! readable constrained one are visible.

use hypercontact_material::ParamUnit;

use crate::html::{escape, fmt_sig, simple_table};
use crate::material::{FitChoice, FitSetting, MaterialSummary};

/// Header of an interval column.
const INTERVAL: &str = "5–95 % (bootstrap)";

/// An interval as "[p05, p95]" in `unit`'s display unit (MPa for moduli).
fn interval_cell(interval: Option<(f64, f64)>, unit: ParamUnit) -> String {
    let scale = match unit {
        ParamUnit::Pa => 1e-6,
        ParamUnit::One => 1.0,
    };
    interval.map_or("n/a".into(), |(lo, hi)| {
        format!("[{}, {}]", fmt_sig(lo * scale, 3), fmt_sig(hi * scale, 3))
    })
}

/// The parameters, one row per Ogden term when every parameter belongs to
/// a term, otherwise one row per parameter (SI), under the caption
/// `{title} {model} parameters (...)`. An interval column follows each
/// value column when any parameter has an interval; a term whose modulus
/// is zero (held there by a constraint) moves nothing, so its parameters
/// get no interval.
pub fn parameter_table(m: &MaterialSummary, title: &str) -> String {
    let with_intervals = m.parameters.iter().any(|p| m.interval(&p.name()).is_some());
    let by_term = !m.parameters.is_empty() && m.parameters.iter().all(|p| p.term.is_some());
    if !by_term {
        let rows: Vec<Vec<String>> = m
            .parameters
            .iter()
            .map(|p| {
                let mut row = vec![escape(&p.name()), fmt_sig(p.value, 6)];
                if with_intervals {
                    // SI, as the value column.
                    row.push(interval_cell(m.interval(&p.name()), ParamUnit::One));
                }
                row
            })
            .collect();
        let mut header = vec!["parameter".to_owned(), "value".to_owned()];
        if with_intervals {
            header.push(INTERVAL.into());
        }
        return simple_table(
            &format!("{title} {} parameters (SI units)", m.model),
            &header,
            &rows,
        );
    }
    // Columns: the symbols in table order, each with its unit.
    let mut columns: Vec<(&str, ParamUnit)> = Vec::new();
    for p in &m.parameters {
        if !columns.iter().any(|(s, _)| *s == p.symbol) {
            columns.push((p.symbol, p.unit));
        }
    }
    let mut terms: Vec<usize> = m.parameters.iter().filter_map(|p| p.term).collect();
    terms.sort_unstable();
    terms.dedup();
    let mut header = vec!["i".to_owned()];
    for (symbol, unit) in &columns {
        header.push(match unit {
            ParamUnit::Pa => format!("{}<sub>i</sub> (MPa)", symbol_html(symbol)),
            ParamUnit::One => format!("{}<sub>i</sub>", symbol_html(symbol)),
        });
        if with_intervals {
            header.push(INTERVAL.into());
        }
    }
    let rows: Vec<Vec<String>> = terms
        .iter()
        .map(|&i| {
            let unused = m
                .parameters
                .iter()
                .any(|p| p.term == Some(i) && p.unit == ParamUnit::Pa && p.value == 0.0);
            let mut row = vec![i.to_string()];
            for &(symbol, unit) in &columns {
                let parameter = m
                    .parameters
                    .iter()
                    .find(|p| p.term == Some(i) && p.symbol == symbol);
                row.push(match (parameter.map(|p| p.value), unit) {
                    (None, _) => "n/a".into(),
                    (Some(v), ParamUnit::Pa) => fmt_sig(v / 1e6, 6),
                    (Some(v), ParamUnit::One) => fmt_sig(v, 4),
                });
                if with_intervals && unused {
                    row.push("— (term unused)".into());
                } else if with_intervals {
                    let interval = parameter.and_then(|p| m.interval(&p.name()));
                    row.push(interval_cell(interval, unit));
                }
            }
            row
        })
        .collect();
    simple_table(
        &format!("{title} {} parameters (Abaqus convention)", m.model),
        &header,
        &rows,
    )
}

/// A parameter symbol as the paper writes it.
fn symbol_html(symbol: &str) -> String {
    match symbol {
        "mu" => "μ".into(),
        "alpha" => "α".into(),
        other => escape(other),
    }
}

/// μ0, E0 and E0* at the report's ν, with their intervals when `params`
/// gives them.
pub fn moduli_table(m: &MaterialSummary) -> String {
    let rows = [
        ("μ<sub>0</sub> = Σ μ<sub>i</sub>", m.mu0_pa, "mu0"),
        ("E<sub>0</sub> = 2 μ<sub>0</sub> (1 + ν)", m.e0_pa, "e0"),
        (
            "E<sub>0</sub>* = E<sub>0</sub> / (1 − ν²)",
            m.e0_star_pa,
            "e0_star",
        ),
    ];
    let with_intervals = rows.iter().any(|(_, _, name)| m.interval(name).is_some());
    let mut header = vec!["modulus".to_owned(), "value (MPa)".to_owned()];
    if with_intervals {
        header.push(format!("{INTERVAL} (MPa)"));
    }
    let rows: Vec<Vec<String>> = rows
        .iter()
        .map(|&(label, value_pa, name)| {
            let mut row = vec![label.to_owned(), fmt_sig(value_pa / 1e6, 6)];
            if with_intervals {
                row.push(interval_cell(m.interval(name), ParamUnit::Pa));
            }
            row
        })
        .collect();
    simple_table(
        &format!("Initial moduli (ν = {})", fmt_sig(m.poisson, 6)),
        &header,
        &rows,
    )
}

/// How a setting of material-fit's `constraint` was fitted, in words
/// (lower case, to follow the setting's name).
fn setting_words(constraint: &str, model: &str) -> String {
    match constraint {
        "stable" if model.starts_with("ogden") => {
            "every μ<sub>i</sub> ≥ 0 (Abaqus convention): Drucker-stable at every stretch".into()
        }
        "stable" => "every modulus ≥ 0: Drucker-stable at every stretch".into(),
        "none" => "plain least squares, as the paper's Abaqus fit".into(),
        "in-range" => "Drucker-stable inside the stretch windows of the stability table, \
             imposed in the fit"
            .into(),
        _ => String::new(),
    }
}

/// A relative error as a percentage cell.
fn percent(value: f64) -> String {
    if value.is_finite() {
        fmt_sig(100.0 * value, 3)
    } else {
        "n/a".into()
    }
}

/// A condition number: powers of ten are what matters (4.5e5, not 450000).
fn condition_cell(condition: f64) -> String {
    match condition {
        c if !c.is_finite() => "n/a".into(),
        c if c.abs() >= 1e4 => format!("{c:.1e}"),
        c => fmt_sig(c, 2),
    }
}

/// What each setting of the constraint costs on the same data, the adopted
/// one first, then (when given) a published material (its name as HTML)
/// evaluated on these data without refitting: RMS relative error over all points and per
/// mode, the largest, μ0 and the fit's condition number.
pub fn constraint_table(choice: &FitChoice, published: Option<(&str, &FitSetting)>) -> String {
    let model = escape(&choice.model);
    let row = |label: String, s: &FitSetting| -> Vec<String> {
        if !s.rms_rel_err.is_finite() {
            let mut row = vec![label, format!("not fitted ({})", escape(&s.status))];
            row.extend(std::iter::repeat_n(String::new(), 6));
            return row;
        }
        let mut row = vec![label, percent(s.rms_rel_err)];
        row.extend(s.mode_rms_rel_err.iter().map(|&e| percent(e)));
        row.push(percent(s.max_rel_err));
        row.push(fmt_sig(s.mu0_pa / 1e6, 4));
        row.push(condition_cell(s.condition_number));
        row
    };
    let setting_label = |s: &FitSetting, adopted: bool| {
        let words = setting_words(&s.constraint, &choice.model);
        format!(
            "{model}, <code>{}</code>{}{}",
            escape(&s.constraint),
            if adopted { " (adopted)" } else { "" },
            if words.is_empty() {
                String::new()
            } else {
                format!(": {words}")
            }
        )
    };
    let mut rows = vec![row(setting_label(&choice.chosen, true), &choice.chosen)];
    rows.extend(
        choice
            .others
            .iter()
            .map(|s| row(setting_label(s, false), s)),
    );
    if let Some((name, s)) = published {
        rows.push(row(format!("{name}, as published (not refitted)"), s));
    }
    let header: Vec<String> = [
        "fit",
        "RMS (%)",
        "UT RMS (%)",
        "PT RMS (%)",
        "BT RMS (%)",
        "max (%)",
        "μ<sub>0</sub> (MPa)",
        "condition number",
    ]
    .iter()
    .map(|h| (*h).to_owned())
    .collect();
    simple_table(
        "What each constraint costs: the same family fitted to the same data under each \
         setting of material-fit's constraint (relative errors)",
        &header,
        &rows,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_material::table::to_table;
    use hypercontact_material::{Ogden, Yeoh};

    #[test]
    fn table_1_has_a_row_per_ogden_term_and_a_row_per_other_parameter() {
        let ogden = Ogden::new(vec![0.55e6, 0.02e6], vec![1.8, -2.5]).unwrap();
        let m = MaterialSummary::read(&to_table(&ogden), 0.5, None).unwrap();
        let html = parameter_table(&m, "Table 1. Fitted");
        assert!(
            html.contains(
                "<th>i</th><th>μ<sub>i</sub> (MPa)</th><th>α<sub>i</sub></th></tr></thead>"
            ),
            "{html}"
        );
        assert!(html.contains("<tr><td>1</td><td>0.55</td><td>1.8</td></tr>"));
        assert!(html.contains("<tr><td>2</td><td>0.02</td><td>-2.5</td></tr>"));
        assert!(!html.contains("bootstrap"));
        let yeoh = Yeoh::new(0.2e6, -0.01e6, 0.001e6).unwrap();
        let m = MaterialSummary::read(&to_table(&yeoh), 0.5, None).unwrap();
        let html = parameter_table(&m, "Table 1. Fitted");
        assert!(
            html.contains("(SI units)") && html.contains("<tr><td>c20</td><td>-10000</td></tr>")
        );
    }

    #[test]
    fn intervals_follow_their_values_in_display_units() {
        let ogden = Ogden::new(vec![0.55e6, 0.02e6], vec![1.8, -2.5]).unwrap();
        let mut m = MaterialSummary::read(&to_table(&ogden), 0.5, None).unwrap();
        m.intervals = vec![
            ("mu_1".into(), 0.5e6, 0.61e6),
            ("alpha_1".into(), 1.7, 1.95),
            ("e0_star".into(), 2.2e6, 2.4e6),
        ];
        let html = parameter_table(&m, "Table 1. Fitted");
        assert!(
            html.contains(
                "<th>i</th><th>μ<sub>i</sub> (MPa)</th><th>5–95 % (bootstrap)</th>\
                 <th>α<sub>i</sub></th><th>5–95 % (bootstrap)</th>"
            ),
            "{html}"
        );
        assert!(
            html.contains(
                "<tr><td>1</td><td>0.55</td><td>[0.5, 0.61]</td><td>1.8</td>\
                 <td>[1.7, 1.95]</td></tr>"
            ),
            "{html}"
        );
        assert!(html.contains("<tr><td>2</td><td>0.02</td><td>n/a</td><td>-2.5</td><td>n/a</td>"));
        let moduli = moduli_table(&m);
        assert!(
            moduli.contains("<th>5–95 % (bootstrap) (MPa)</th>"),
            "{moduli}"
        );
        assert!(
            moduli.contains("<td>2.28</td><td>[2.2, 2.4]</td>"),
            "{moduli}"
        );
    }

    fn setting(constraint: &str, rms: f64, condition: f64) -> FitSetting {
        FitSetting {
            constraint: constraint.into(),
            rms_rel_err: rms,
            mode_rms_rel_err: [rms / 2.0, rms, 2.0 * rms],
            max_rel_err: 3.0 * rms,
            mu0_pa: 1.5e6,
            condition_number: condition,
            status: "ok".into(),
        }
    }

    #[test]
    fn the_constraint_table_gives_every_setting_and_the_published_material() {
        let choice = FitChoice {
            model: "ogden-6".into(),
            chosen: setting("in-range", 0.0013, 6.1e7),
            others: vec![
                setting("none", 0.0012, 8.0e7),
                FitSetting {
                    status: "no start converged".into(),
                    ..setting("stable", f64::NAN, f64::NAN)
                },
            ],
        };
        let published = FitSetting {
            mu0_pa: 1.79e6,
            ..setting("published", 0.004, f64::NAN)
        };
        let html = constraint_table(&choice, Some(("<code>paper-epdm</code>", &published)));
        assert!(
            html.contains(
                "<tr><td>ogden-6, <code>in-range</code> (adopted): Drucker-stable inside the \
                 stretch windows of the stability table, imposed in the fit</td><td>0.13</td>\
                 <td>0.065</td><td>0.13</td><td>0.26</td><td>0.39</td><td>1.5</td>\
                 <td>6.1e7</td></tr>"
            ),
            "{html}"
        );
        assert!(html.contains(
            "<td>ogden-6, <code>none</code>: plain least squares, as the paper's Abaqus \
             fit</td><td>0.12</td>"
        ));
        assert!(
            html.contains("<td>not fitted (no start converged)</td>"),
            "{html}"
        );
        assert!(
            html.contains(
                "<tr><td><code>paper-epdm</code>, as published (not refitted)</td><td>0.4</td><td>0.2</td>\
                 <td>0.4</td><td>0.8</td><td>1.2</td><td>1.79</td><td>n/a</td></tr>"
            ),
            "{html}"
        );
        // The adopted row leads.
        assert!(html.find("(adopted)").unwrap() < html.find("<code>none</code>").unwrap());
    }

    #[test]
    fn a_term_held_at_zero_gets_no_interval() {
        let ogden = Ogden::new(vec![0.55e6, 0.0], vec![1.8, 9.0]).unwrap();
        let mut m = MaterialSummary::read(&to_table(&ogden), 0.5, None).unwrap();
        m.intervals = vec![
            ("mu_1".into(), 0.5e6, 0.61e6),
            ("alpha_2".into(), 3.7, 11.6),
        ];
        let html = parameter_table(&m, "Table 1. Fitted");
        assert!(
            html.contains(
                "<tr><td>2</td><td>0</td><td>— (term unused)</td><td>9</td>\
                 <td>— (term unused)</td></tr>"
            ),
            "{html}"
        );
        assert!(html.contains("<td>[0.5, 0.61]</td>"), "{html}");
    }

    /// A published material's errors come from the same relative residuals
    /// as the fit's quality table: Table 1's own parameters on data made
    /// from them are exact.
    #[test]
    fn a_published_material_on_its_own_curves_has_no_error() {
        use crate::gather::ModeCurve;
        use hypercontact_core::Mode;
        use hypercontact_material::Hyperelastic;
        use hypercontact_material::presets::paper_epdm;
        let paper = paper_epdm();
        let curves: Vec<ModeCurve> = Mode::ALL
            .iter()
            .map(|&mode| {
                let stretch: Vec<f64> = (1..=20).map(|k| 1.0 + 0.05 * f64::from(k)).collect();
                let stress: Vec<f64> = stretch
                    .iter()
                    .map(|&l| paper.nominal_stress_pa(mode, l))
                    .collect();
                ModeCurve {
                    mode: mode.label().to_owned(),
                    stretch,
                    measured_pa: stress.clone(),
                    fitted_pa: stress,
                }
            })
            .collect();
        let s = FitSetting::of_model("published", &paper, &curves);
        assert_eq!(s.rms_rel_err, 0.0);
        assert_eq!(s.mode_rms_rel_err, [0.0; 3]);
        assert!((s.mu0_pa / 1.79e6 - 1.0).abs() < 1e-12);
        let off = hypercontact_material::NeoHookean::new(0.895e6).unwrap();
        let s = FitSetting::of_model("published", &off, &curves);
        assert!(s.mode_rms_rel_err.iter().all(|&e| e > 0.01), "{s:?}");
    }
}
