//! The bootstrap's uncertainty on the page: icm's `bands` shaded under the
//! curves of Figs. 7 and 8 and read into the summary, the fit's `params`
//! intervals in Table 1, and the table of what each setting of the fit's
//! constraint costs (with a published material beside it when named). A
//! report without bands is the same to the byte as before.

use crate::common;

use common::{ALL, SAMPLES, run, run_with, text, wired_params};
use hypercontact_core::contact::BandTable;
use hypercontact_core::{Inputs, Product, Schema, Table};
use hypercontact_report::ReportParams;
use quick_xml::events::Event;
use serde_json::Value;

const MAP_N: usize = 48;
const LEVELS: usize = 301;

/// The first line of the bands' legend label.
const BAND_KEY: &str = "5–95 % bootstrap";

/// Okabe–Ito colours of T1…T4 as the SVG writes them.
const SAMPLE_FILLS: [&str; 4] = ["#0072B2", "#D55E00", "#009E73", "#CC79A7"];

fn plain() -> Inputs {
    common::inputs(ALL, MAP_N, LEVELS)
}

fn banded() -> Inputs {
    common::with_bands(plain(), LEVELS)
}

/// (fill, opacity) of every `<polygon>` of an SVG, parsed as XML.
fn polygons(svg: &str) -> Vec<(String, String)> {
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut found = Vec::new();
    loop {
        match reader.read_event().expect("well-formed SVG") {
            Event::Eof => return found,
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == b"polygon" => {
                let attr = |key: &str| {
                    let a = e.try_get_attribute(key).unwrap().expect("attribute");
                    String::from_utf8_lossy(&a.value).into_owned()
                };
                found.push((attr("fill"), attr("opacity")));
            }
            _ => {}
        }
    }
}

#[test]
fn bands_are_shaded_under_the_curves_of_figs_7_8_and_9() {
    let (files, plain) = (run(&banded()), run(&plain()));
    for fig in ["fig7", "fig8"] {
        let svg = text(&files, &format!("{fig}.svg"));
        let shaded = polygons(&svg);
        for fill in SAMPLE_FILLS {
            assert!(
                shaded.iter().any(|(f, o)| f == fill && o == "0.2"),
                "{fig}: no band in {fill}: {shaded:?}"
            );
        }
        // Under the curves: every band is drawn before T1's first curve.
        let first_curve = svg
            .find("stroke=\"#0072B2\" stroke-width=\"3\"")
            .expect("T1's curve");
        assert!(svg.rfind("<polygon").unwrap() < first_curve, "{fig}");
        assert!(svg.contains(BAND_KEY) && svg.contains("(tensile scatter)"));
        // The key's swatch: a grey (black at 0.2) rectangle.
        assert!(
            svg.contains("opacity=\"0.2\" fill=\"#000000\" stroke=\"none\""),
            "{fig}: no band swatch"
        );
        let unbanded = text(&plain, &format!("{fig}.svg"));
        assert!(polygons(&unbanded).is_empty() && !unbanded.contains(BAND_KEY));
        assert_ne!(
            files.files[&format!("{fig}.png")],
            plain.files[&format!("{fig}.png")]
        );
    }
    // Fig. 8's y range takes in the band: E_t*/E0* reaches 3.1 on the
    // curves and 3.7 on the band's upper edge, so the tick 3.5 appears.
    let tick = ">\n3.5\n</text>";
    assert!(text(&files, "fig8.svg").contains(tick));
    assert!(!text(&plain, "fig8.svg").contains(tick));
    // The model comparison shades the bands of its models too (#32, 6).
    assert!(!polygons(&text(&files, "fig9.svg")).is_empty());
    assert!(polygons(&text(&plain, "fig9.svg")).is_empty());
    let html = text(&files, "index.html");
    assert_eq!(html.matches("Shaded: the 5–95 % band").count(), 3);
    assert!(!text(&plain, "index.html").contains("Shaded:"));
}

#[test]
fn the_per_sample_panels_shade_the_band_in_the_icm_grey() {
    let mut inputs = banded();
    for (label, _, _, _, scale) in SAMPLES {
        inputs.insert(
            &format!("responses.{label}.bem"),
            std::sync::Arc::new(Product::Table(common::response(
                LEVELS,
                1.25 * scale,
                false,
            ))),
        );
    }
    let svg = text(&run(&inputs), "fig7.svg");
    let shaded = polygons(&svg);
    assert!(shaded.len() >= SAMPLES.len(), "{shaded:?}");
    assert!(
        shaded.iter().all(|(f, o)| f == "#000000" && o == "0.2"),
        "{shaded:?}"
    );
    assert!(svg.contains(BAND_KEY));
}

/// Linear interpolation of column `y` over `area_fraction`, written out
/// independently of the crate's.
fn lerp(table: &Table, y: &str, a: f64) -> f64 {
    let xs = table.f64("area_fraction").unwrap();
    let ys = table.f64(y).unwrap();
    let i = xs.iter().position(|&x| x >= a).unwrap();
    if xs[i] == a {
        return ys[i];
    }
    ys[i - 1] + (a - xs[i - 1]) * (ys[i] - ys[i - 1]) / (xs[i] - xs[i - 1])
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

#[test]
fn the_summary_reads_the_band_at_the_area_fractions() {
    let files = run(&banded());
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    for (i, s) in summary["samples"].as_array().unwrap().iter().enumerate() {
        let (label, _, _, _, scale) = SAMPLES[i];
        let reached = if i == 3 { 0.7 } else { 1.0 };
        let band = common::band(LEVELS, scale, reached);
        for (l, a) in s["load_norm"]
            .as_array()
            .unwrap()
            .iter()
            .zip([0.1, 0.5, 0.9])
        {
            let value = l["load_norm"]["icm"].as_f64().unwrap();
            if a > reached {
                // No replicate reached A/A0 = 0.9 on T4: no band there.
                assert!(l["load_norm_p05"]["icm"].is_null() && l["load_norm_p95"]["icm"].is_null());
                continue;
            }
            let (p05, p95) = (
                l["load_norm_p05"]["icm"].as_f64().unwrap(),
                l["load_norm_p95"]["icm"].as_f64().unwrap(),
            );
            assert!(p05 <= value && value <= p95, "{label} at {a}");
            assert!(close(p05, lerp(&band, "load_norm_p05", a)), "{label} {a}");
            assert!(close(p95, lerp(&band, "load_norm_p95", a)), "{label} {a}");
            // The band is 0.8 × and 1.25 × the curve row by row, and linear
            // interpolation keeps the factor.
            assert!(close(p05, 0.8 * value) && close(p95, 1.25 * value));
        }
    }
    // The page: "value [p05, p95]" at 3 significant digits (T1 at 0.5:
    // 0.4 · 0.5^1.5 ≈ 0.141, all three between 0.1 and 1).
    let t1 = &summary["samples"][0]["load_norm"][1];
    let cell = format!(
        "<td>{:.3} [{:.3}, {:.3}]</td>",
        t1["load_norm"]["icm"].as_f64().unwrap(),
        t1["load_norm_p05"]["icm"].as_f64().unwrap(),
        t1["load_norm_p95"]["icm"].as_f64().unwrap()
    );
    let html = text(&files, "index.html");
    assert!(html.contains(&cell), "no {cell}");
    let row = |html: &str, label: &str| -> String {
        let table = between(html, "Summary per sample (loads", "</table>");
        between(table, &format!("<tr><td>{label}</td>"), "</tr>").to_owned()
    };
    assert_eq!(row(&html, "T1").matches(" [").count(), 3);
    assert_eq!(row(&html, "T4").matches(" [").count(), 2);
    assert!(html.contains("[p05, p95] = the 5–95 % bootstrap band"));
    let plain = run(&plain());
    let plain_summary: Value = serde_json::from_slice(&plain.files["summary.json"]).unwrap();
    let l = &plain_summary["samples"][0]["load_norm"][1];
    assert!(l["load_norm_p05"]["icm"].is_null() && l["load_norm_p95"]["icm"].is_null());
    assert_eq!(
        row(&text(&plain, "index.html"), "T1").matches(" [").count(),
        0
    );
}

/// The part of the page from `start` to the next `end`.
fn between<'h>(html: &'h str, start: &str, end: &str) -> &'h str {
    let from = html.find(start).unwrap_or_else(|| panic!("no {start}"));
    let rest = &html[from..];
    &rest[..rest.find(end).unwrap_or(rest.len())]
}

#[test]
fn table_1_gives_the_intervals_and_what_each_constraint_costs() {
    let html = text(&run(&banded()), "index.html");
    // μ_i and α_i ∓ 10 % (common::params_with_intervals), μ in MPa.
    let table1 = between(&html, "Table 1.", "</table>");
    assert!(table1.contains("<th>5–95 % (bootstrap)</th>"), "{table1}");
    for row in [
        "<tr><td>1</td><td>0.55</td><td>[0.495, 0.605]</td><td>1.8</td><td>[1.62, 1.98]</td></tr>",
        "<tr><td>2</td><td>0.02</td><td>[0.018, 0.022]</td><td>-2.5</td><td>[-2.75, -2.25]</td></tr>",
    ] {
        assert!(table1.contains(row), "no {row} in {table1}");
    }
    // E0* = 4 μ0 = 2.28 MPa at ν = ½, ∓ 10 %.
    let moduli = between(&html, "Initial moduli", "</table>");
    assert!(
        moduli.contains("<td>2.28</td><td>[2.05, 2.51]</td>"),
        "{moduli}"
    );
    // The cost table under Table 1 gives both settings' RMS errors, per
    // mode, μ0 and condition numbers from the synthetic comparison
    // (common::STABLE_RMS, FREE_RMS, STABLE_CONDITION, FREE_CONDITION).
    let costs = between(&html, "What each constraint costs", "</table>");
    for words in [
        "<tr><td>ogden-2, <code>stable</code> (adopted): every μ<sub>i</sub> ≥ 0 (Abaqus \
         convention): Drucker-stable at every stretch</td><td>1.8</td><td>1.5</td><td>1.7</td>\
         <td>2.2</td><td>5</td><td>0.56</td><td>3.2</td></tr>",
        "<tr><td>ogden-2, <code>none</code>: plain least squares, as the paper's Abaqus \
         fit</td><td>1.2</td><td>1</td><td>1.1</td><td>1.5</td><td>4</td><td>0.57</td>\
         <td>4.5e5</td></tr>",
    ] {
        assert!(costs.contains(words), "no {words:?} in {costs}");
    }
    // No published material unless the report names one.
    assert!(!html.contains("as published"));
    let (table_at, moduli_at, costs_at) = (
        html.find("Table 1.").unwrap(),
        html.find("Initial moduli").unwrap(),
        html.find("What each constraint costs").unwrap(),
    );
    assert!(table_at < moduli_at && moduli_at < costs_at);

    // Without intervals the columns are not there; without the comparison
    // neither is the line.
    let inputs = plain();
    let html = text(&run(&inputs), "index.html");
    assert!(!between(&html, "Table 1.", "</table>").contains("bootstrap"));
    assert!(html.contains("What each constraint costs"));
    let mut without = Inputs::new();
    for name in inputs.names().filter(|&n| n != "comparison") {
        without.insert(name, std::sync::Arc::new(inputs.get(name).unwrap().clone()));
    }
    let html = text(&run(&without), "index.html");
    assert!(html.contains("Table 1.") && !html.contains("What each constraint costs"));
}

#[test]
fn a_band_table_without_rows_changes_nothing_and_a_bad_one_is_named() {
    let plain_files = run(&plain());
    let mut inputs = plain();
    let empty = BandTable {
        area_fraction: vec![],
        load_norm_p05: vec![],
        load_norm_p50: vec![],
        load_norm_p95: vec![],
        tangent_ratio_p05: vec![],
        tangent_ratio_p50: vec![],
        tangent_ratio_p95: vec![],
        replicates: vec![],
    };
    inputs.insert(
        "bands.T1.icm",
        std::sync::Arc::new(Product::Table(empty.into_table())),
    );
    assert_eq!(run(&inputs).files, plain_files.files);

    // A response table is no band table: the input and a missing column
    // are named.
    let mut inputs = plain();
    inputs.insert(
        "bands.T2.icm",
        std::sync::Arc::new(Product::Table(common::response(LEVELS, 0.25, false))),
    );
    let e = run_with(&ReportParams::default(), &inputs).unwrap_err();
    assert!(
        e.contains("bands.T2.icm") && e.contains("load_norm_p05"),
        "{e}"
    );
    // Percentiles out of order are refused, not drawn.
    let mut swapped = BandTable::from_table(&common::band(LEVELS, 0.25, 1.0)).unwrap();
    std::mem::swap(&mut swapped.load_norm_p05, &mut swapped.load_norm_p95);
    let mut inputs = plain();
    inputs.insert(
        "bands.T2.icm",
        std::sync::Arc::new(Product::Table(swapped.into_table())),
    );
    let e = run_with(&ReportParams::default(), &inputs).unwrap_err();
    assert!(e.contains("bands.T2.icm") && e.contains("above"), "{e}");
}

/// With `published_material: paper-epdm` Table 1's cost table gains the
/// paper's own parameters evaluated on the same curves (not refitted,
/// μ0 = 1.79 MPa), and the published parameters follow as a table of
/// their own in the paper's order.
#[test]
fn the_published_material_stands_beside_the_fit() {
    use hypercontact_material::presets::Preset;
    let inputs = plain();
    let params = ReportParams {
        published_material: Some(Preset::PaperEpdm),
        ..wired_params(&inputs)
    };
    let html = text(&run_with(&params, &inputs).unwrap(), "index.html");
    let costs = between(&html, "What each constraint costs", "</table>");
    let row = between(
        costs,
        "<code>paper-epdm</code> (the paper's Table 1), as published",
        "</tr>",
    );
    assert!(row.contains("<td>1.79</td><td>n/a</td>"), "{row}");
    let published = between(&html, "The paper&#39;s Table 1 as published", "</table>");
    for term in [
        "<tr><td>1</td><td>5025.77</td><td>0.635</td></tr>",
        "<tr><td>6</td><td>-1079.81</td><td>-0.219</td></tr>",
    ] {
        assert!(published.contains(term), "no {term} in {published}");
    }
}
