//! The report's surface statistics (issue #36): the areal parameters'
//! table, one column per sample, and Figs. 4b–4e from the surface stage's
//! tables; without those tables (a pipeline or cache from before them) the
//! report still renders and says what is missing.

use crate::common;

use common::{ALL, SAMPLES, run, text};
use hypercontact_core::{Inputs, Product};
use hypercontact_report::html::fmt_sig;

const MAP_N: usize = 64;
const LEVELS: usize = 101;
const STATISTICS: [&str; 5] = [
    "areal",
    "material_ratio",
    "acf",
    "scale_dependent",
    "distributions",
];

/// `inputs` without the products whose name (before the label) `drop` keeps.
fn without(inputs: &Inputs, drop: impl Fn(&str) -> bool) -> Inputs {
    let mut kept = Inputs::new();
    for name in inputs.names() {
        let (input, _) = name.split_once('.').unwrap_or((name, ""));
        if !drop(input) {
            kept = kept.with(name, inputs.get(name).unwrap().clone());
        }
    }
    kept
}

#[test]
fn the_surface_section_has_the_areal_table_and_figs_4b_to_4e() {
    let inputs = common::inputs(ALL, MAP_N, LEVELS);
    let files = run(&inputs);
    let html = text(&files, "index.html");
    // One column per sample, lengths in µm with four significant digits.
    let header: String = SAMPLES
        .iter()
        .map(|s| format!("<th>{}</th>", s.0))
        .collect();
    assert!(
        html.contains(&format!("<th>parameter</th><th>unit</th>{header}")),
        "no areal table header"
    );
    for (column, symbol, unit, scale) in [
        ("sq_m", "S<sub>q</sub>", "µm", 1e6),
        ("sku", "S<sub>ku</sub>", "1", 1.0),
        ("sdr_percent", "S<sub>dr</sub>", "%", 1.0),
        ("sal_m", "S<sub>al</sub>", "µm", 1e6),
        ("correlation_length_m", "correlation length", "µm", 1e6),
    ] {
        let cells: String = SAMPLES
            .iter()
            .map(|s| {
                let t = match inputs.get(&format!("areal.{}", s.0)) {
                    Some(Product::Table(t)) => t,
                    other => panic!("no areal table: {other:?}"),
                };
                format!("<td>{}</td>", fmt_sig(t.f64(column).unwrap()[0] * scale, 4))
            })
            .collect();
        let row = format!("<tr><td>{symbol}</td><td>{unit}</td>{cells}<td>");
        assert!(html.contains(&row), "no row {row}");
    }
    // The figures follow Fig. 4 and the table, in order, each with its
    // caption's conventions and its files.
    let at = |needle: &str| {
        html.find(needle)
            .unwrap_or_else(|| panic!("{needle} not in the page"))
    };
    let order = [
        at("<figure id=\"fig4\">"),
        at("Areal surface parameters"),
        at("<figure id=\"fig4b\">"),
        at("<figure id=\"fig4c\">"),
        at("<figure id=\"fig4d\">"),
        at("<figure id=\"fig4e\">"),
        at("<figure id=\"fig7\">"),
    ];
    assert!(order.windows(2).all(|w| w[0] < w[1]), "{order:?}");
    for caption in [
        "secant over 40 % of material ratio",
        "the level 1/e",
        "s = 0.2",
        "central second differences of step k/2",
        "normalised to unit area",
    ] {
        assert!(html.contains(caption), "no caption with {caption}");
    }
    for fig in ["fig4b", "fig4c", "fig4d", "fig4e"] {
        let svg = text(&files, &format!("{fig}.svg"));
        assert!(html.contains(&svg), "{fig} not embedded");
        assert!(files.files.contains_key(&format!("{fig}.png")), "{fig}.png");
        // Each sample drawn: one curve a sample at least.
        assert!(svg.matches("<polyline").count() >= SAMPLES.len(), "{fig}");
    }
    let fig4b = text(&files, "fig4b.svg");
    for label in [
        "material ratio Smr (%)",
        "core band, height Sk",
        "equivalence line",
    ] {
        assert!(fig4b.contains(label), "fig4b: {label}");
    }
    let fig4c = text(&files, "fig4c.svg");
    for label in [
        "lag τ (µm)",
        "1/e: correlation length",
        "s = 0.2: Sal",
        "along x",
    ] {
        assert!(fig4c.contains(label), "fig4c: {label}");
    }
    assert!(text(&files, "fig4d.svg").contains("rms curvature ∇²h/2 (1/m)"));
    assert!(text(&files, "fig4e.svg").contains("probability density (1/µm)"));
    assert!(!html.contains("Surface statistics not wired"));
}

#[test]
fn without_the_surface_statistics_the_report_builds_and_notes_them() {
    let all = common::inputs(ALL, MAP_N, LEVELS);
    // None wired: Figs. 4b–4e skipped with the reason, Fig. 4 drawn.
    let files = run(&without(&all, |input| STATISTICS.contains(&input)));
    assert!(files.files.contains_key("fig4.png"));
    let html = text(&files, "index.html");
    for fig in ["fig4b", "fig4c", "fig4d", "fig4e"] {
        assert!(!files.files.contains_key(&format!("{fig}.png")), "{fig}");
        let label = format!("<b>Fig. {}</b> skipped", &fig[3..]);
        assert!(html.contains(&label), "{label}");
    }
    assert!(html.contains("surface stage from version 6"));
    assert!(html.contains("<b>Areal parameters</b> not shown"));
    // One sample without its ACF and another without its areal table: the
    // figures are drawn for the others and the page names what is missing.
    let partial = without(&all, |_| false);
    let partial = {
        let mut kept = Inputs::new();
        for name in partial.names() {
            if name != "acf.T2" && name != "areal.T3" {
                kept = kept.with(name, partial.get(name).unwrap().clone());
            }
        }
        kept
    };
    let files = run(&partial);
    let html = text(&files, "index.html");
    assert!(files.files.contains_key("fig4c.png"));
    assert!(html.contains("T2: no acf; T3: no areal"), "no note");
    assert!(
        html.contains("T2: no `acf`"),
        "no incomplete note on Fig. 4c"
    );
    // The table has the three samples that have it.
    assert!(html.contains("<th>parameter</th><th>unit</th><th>T1</th><th>T2</th><th>T4</th>"));
}

#[test]
fn a_malformed_statistic_is_named() {
    let mut inputs = common::inputs(ALL, MAP_N, LEVELS);
    let two_rows = hypercontact_core::Table::new().with("sa_m", vec![1.0, 2.0]);
    inputs.insert("areal.T1", std::sync::Arc::new(Product::Table(two_rows)));
    let e = common::run_with(&common::wired_params(&inputs), &inputs).unwrap_err();
    assert!(e.contains("areal.T1"), "{e}");
}
