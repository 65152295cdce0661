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

/// The fitted parameters, one row per Ogden term when every parameter
/// belongs to a term, otherwise one row per parameter (SI). An interval
/// column follows each value column when any parameter has an interval.
pub fn parameter_table(m: &MaterialSummary) -> String {
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
            &format!("Table 1. Fitted {} parameters (SI units)", m.model),
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
                if with_intervals {
                    let interval = parameter.and_then(|p| m.interval(&p.name()));
                    row.push(interval_cell(interval, unit));
                }
            }
            row
        })
        .collect();
    simple_table(
        &format!("Table 1. Fitted {} parameters (Abaqus convention)", m.model),
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
/// (lower case; the sentence capitalises it where it starts one).
fn setting_words(constraint: &str, model: &str) -> String {
    match constraint {
        "stable" if model.starts_with("ogden") => "with the stable constraint (every \
             μ<sub>i</sub> ≥ 0 in the Abaqus convention: Drucker-stable at every stretch)"
            .into(),
        "stable" => {
            "with the stable constraint (every modulus ≥ 0: Drucker-stable at every stretch)".into()
        }
        "none" => "without the constraint (plain least squares, the paper's Abaqus fit)".into(),
        other => format!("with constraint “{}”", escape(other)),
    }
}

/// "RMS relative error 9.16 %, condition number 1.5", or why there is none.
fn objective_words(s: &FitSetting) -> String {
    if !s.rms_rel_err.is_finite() {
        return format!("not fitted ({})", escape(&s.status));
    }
    let mut words = format!("RMS relative error {} %", fmt_sig(100.0 * s.rms_rel_err, 3));
    let condition = s.condition_number;
    if condition.is_finite() {
        // Powers of ten are what matters: 4.5e5, not 450000.
        let shown = if condition.abs() >= 1e4 {
            format!("{condition:.1e}")
        } else {
            fmt_sig(condition, 2)
        };
        words.push_str(&format!(", condition number {shown}"));
    }
    words
}

/// The line under Table 1: the fit's constraint and objective, then the
/// same family's under the other setting.
pub fn constraint_line(choice: &FitChoice) -> String {
    let model = escape(&choice.model);
    let mut line = format!(
        "{model} fitted {}: {}.",
        setting_words(&choice.chosen.constraint, &choice.model),
        objective_words(&choice.chosen)
    );
    match &choice.other {
        Some(other) => {
            let words = setting_words(&other.constraint, &choice.model);
            let mut chars = words.chars();
            let capitalised: String = chars
                .next()
                .map(|c| c.to_uppercase().chain(chars).collect())
                .unwrap_or_default();
            line.push_str(&format!(" {capitalised}: {}.", objective_words(other)));
        }
        None => line.push_str(" The model comparison holds no fit of it under the other setting."),
    }
    format!("<p class=\"note\" id=\"fit-constraint\">{line}</p>\n")
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
        let html = parameter_table(&m);
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
        let html = parameter_table(&m);
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
        let html = parameter_table(&m);
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
            condition_number: condition,
            status: "ok".into(),
        }
    }

    #[test]
    fn the_constraint_line_gives_both_objectives() {
        let choice = FitChoice {
            model: "ogden-6".into(),
            chosen: setting("stable", 0.0916, 1.5),
            other: Some(setting("none", 0.005, 6.1e7)),
        };
        let line = constraint_line(&choice);
        assert!(
            line.contains(
                "ogden-6 fitted with the stable constraint (every μ<sub>i</sub> ≥ 0 in the Abaqus \
                 convention: Drucker-stable at every stretch): RMS relative error 9.16 %, \
                 condition number 1.5. Without the constraint (plain least squares, the paper's \
                 Abaqus fit): RMS relative error 0.5 %, condition number 6.1e7."
            ),
            "{line}"
        );
        let failed = FitChoice {
            model: "yeoh".into(),
            chosen: setting("none", 0.02, f64::NAN),
            other: Some(FitSetting {
                status: "no start converged".into(),
                ..setting("stable", f64::NAN, f64::NAN)
            }),
        };
        let line = constraint_line(&failed);
        assert!(
            line.contains("yeoh fitted without the constraint"),
            "{line}"
        );
        assert!(line.contains("RMS relative error 2 %."), "{line}");
        assert!(
            line.contains("With the stable constraint (every modulus ≥ 0"),
            "{line}"
        );
        assert!(line.contains("not fitted (no start converged)"), "{line}");
    }
}
