//! The report stage end to end on synthetic upstream tables: every figure
//! is a real PNG and SVG, the page embeds and links them, summary.json
//! holds the numbers of the input tables, and unwired inputs skip their
//! figure with a note instead of failing.

use crate::common;

use std::collections::BTreeMap;

use base64::Engine;
use common::{ALL, SAMPLES, Wiring, run, run_with, text};
use hypercontact_core::contact::ResponseTable;
use hypercontact_core::{Context, Files, Inputs, Params, Product, Schema, Stage, Table};
use hypercontact_report::{Report, ReportParams};
use quick_xml::events::Event;
use serde_json::Value;

const MAP_N: usize = 96;
const LEVELS: usize = 301;

/// A PNG that decodes, has the expected size and is not blank: at least 2 %
/// of its pixels are not white and it uses many colours.
fn assert_png(name: &str, bytes: &[u8], min_w: u32, min_h: u32) {
    assert!(
        bytes.starts_with(&[0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n']),
        "{name}: no PNG signature"
    );
    let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .unwrap_or_else(|e| panic!("{name}: does not decode: {e}"))
        .to_rgb8();
    assert!(
        img.width() >= min_w && img.height() >= min_h,
        "{name}: {}x{} is smaller than {min_w}x{min_h}",
        img.width(),
        img.height()
    );
    let inked = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    let total = (img.width() * img.height()) as usize;
    assert!(
        inked * 50 > total,
        "{name}: only {inked} of {total} pixels drawn"
    );
    let colours: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    assert!(colours.len() > 50, "{name}: only {} colours", colours.len());
}

/// Parses an SVG fully (well-formed XML), checks the root element's size and
/// returns the count of elements by name.
fn assert_svg(name: &str, svg: &str, min_w: u32, min_h: u32) -> BTreeMap<String, usize> {
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut counts = BTreeMap::new();
    let mut root: Option<(u32, u32)> = None;
    loop {
        match reader.read_event() {
            Ok(Event::Eof) => break,
            Ok(Event::Start(e) | Event::Empty(e)) => {
                let tag = String::from_utf8_lossy(e.name().as_ref()).into_owned();
                if root.is_none() {
                    assert_eq!(tag, "svg", "{name}: root element is <{tag}>");
                    let attr = |key: &str| -> u32 {
                        let a = e
                            .try_get_attribute(key)
                            .unwrap()
                            .unwrap_or_else(|| panic!("{name}: <svg> has no {key}"));
                        String::from_utf8_lossy(&a.value).parse().unwrap()
                    };
                    root = Some((attr("width"), attr("height")));
                }
                *counts.entry(tag).or_insert(0) += 1;
            }
            Ok(_) => {}
            Err(e) => panic!("{name}: malformed at {}: {e}", reader.buffer_position()),
        }
    }
    let (w, h) = root.unwrap_or_else(|| panic!("{name}: no root element"));
    assert!(w >= min_w && h >= min_h, "{name}: {w}x{h}");
    let elements: usize = counts.values().sum();
    assert!(elements > 30, "{name}: only {elements} elements");
    assert!(
        counts.get("text").copied().unwrap_or(0) >= 10,
        "{name}: too little text"
    );
    counts
}

#[test]
fn full_report_has_every_figure_as_valid_png_and_svg_and_the_page_embeds_them() {
    let inputs = common::inputs(ALL, MAP_N, LEVELS);
    let files = run(&inputs);
    let expected = [
        "fig2.png",
        "fig2.svg",
        "fig4.png",
        "fig4.svg",
        "fig4b.png",
        "fig4b.svg",
        "fig4c.png",
        "fig4c.svg",
        "fig4d.png",
        "fig4d.svg",
        "fig4e.png",
        "fig4e.svg",
        "fig7.png",
        "fig7.svg",
        "fig8.png",
        "fig8.svg",
        "fig9.png",
        "fig9.svg",
        "index.html",
        "summary.json",
    ];
    assert_eq!(
        files.files.keys().map(String::as_str).collect::<Vec<_>>(),
        expected
    );
    let html = text(&files, "index.html");
    for (fig, w, h) in [
        ("fig2", 900, 600),
        ("fig4", 1500, 1500),
        ("fig4b", 1100, 900),
        ("fig4c", 1100, 900),
        ("fig4d", 1100, 450),
        ("fig4e", 1100, 450),
        ("fig7", 900, 600),
        ("fig8", 900, 600),
        ("fig9", 1200, 900),
    ] {
        assert_png(fig, &files.files[&format!("{fig}.png")], w, h);
        let svg = text(&files, &format!("{fig}.svg"));
        let counts = assert_svg(fig, &svg, w, h);
        // One polyline per drawn curve at least (4 samples; 3 modes in Fig. 2).
        let curves = if fig == "fig2" { 3 } else { SAMPLES.len() };
        assert!(
            counts.get("polyline").copied().unwrap_or(0) >= curves,
            "{fig}: {counts:?}"
        );
        // Embedded inline (the very same SVG) and linked as files.
        assert!(html.contains(&svg), "{fig}: SVG not embedded in index.html");
        assert!(
            html.contains(&format!("href=\"{fig}.png\"")),
            "{fig}.png not linked"
        );
        assert!(
            html.contains(&format!("href=\"{fig}.svg\"")),
            "{fig}.svg not linked"
        );
    }
    // Self-contained: nothing is fetched from a network.
    // Self-contained: no URL but the SVG namespace name (not fetched).
    let without_namespace = html.replace("http://www.w3.org/2000/svg", "");
    assert!(!without_namespace.contains("http://") && !without_namespace.contains("https://"));
    assert!(
        !html.contains("class=\"skipped\""),
        "nothing should be skipped"
    );
    assert!(html.contains("Provenance") && html.contains("No provenance record"));
    assert!(html.contains("Model comparison") && html.contains("mooney-rivlin"));
    // An unbounded stability limit is shown as such.
    assert!(
        html.contains("<td>UT</td><td>0.45</td><td>∞</td>"),
        "no ∞ limit"
    );
}

#[test]
fn fig4_svg_embeds_each_height_map_as_a_png_image() {
    let files = run(&common::inputs(ALL, MAP_N, LEVELS));
    let svg = text(&files, "fig4.svg");
    let counts = assert_svg("fig4", &svg, 1500, 1500);
    assert_eq!(counts.get("image"), Some(&SAMPLES.len()));
    let first = svg.split("href=\"data:image/png;base64,").nth(1).unwrap();
    let data = &first[..first.find('"').unwrap()];
    let png = base64::engine::general_purpose::STANDARD
        .decode(data)
        .unwrap();
    let img = image::load_from_memory(&png).unwrap();
    assert!(img.width() > 100 && img.height() > 100);
    // Every map is drawn before (under) the scale bar and colour bar.
    let image_at = svg.find("<image").unwrap();
    assert!(svg[..image_at].matches("<text").count() == 0);
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-300)
}

/// Linear interpolation written out independently of the crate's.
fn lerp_at(table: &Table, a: f64) -> f64 {
    let xs = table.f64("area_fraction").unwrap();
    let ys = table.f64("load_norm").unwrap();
    let i = xs.iter().position(|&x| x >= a).unwrap();
    if xs[i] == a {
        return ys[i];
    }
    ys[i - 1] + (a - xs[i - 1]) * (ys[i] - ys[i - 1]) / (xs[i] - xs[i - 1])
}

#[test]
fn summary_json_holds_the_numbers_of_the_input_tables() {
    let inputs = common::inputs(ALL, MAP_N, LEVELS);
    let files = run(&inputs);
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();

    // Material: μ0 = Σ μ_i, E0 = 3 μ0, E0* = 4 μ0 (ν = ½).
    let mu0 = common::MU_PA.iter().sum::<f64>();
    let m = &summary["material"];
    assert_eq!(m["model"], "ogden");
    assert!(close(m["mu0_pa"].as_f64().unwrap(), mu0));
    assert!(close(m["e0_pa"].as_f64().unwrap(), 3.0 * mu0));
    assert!(close(m["e0_star_pa"].as_f64().unwrap(), 4.0 * mu0));
    assert_eq!(summary["quality"][1]["mode"], "PT");
    assert_eq!(summary["quality"][1]["r2"].as_f64(), Some(0.9978));
    assert_eq!(summary["stability"][0]["lambda_max"], Value::Null);
    assert_eq!(summary["stability"][2]["lambda_max"].as_f64(), Some(1.8));
    assert_eq!(summary["comparison"].as_array().unwrap().len(), 6);

    let samples = summary["samples"].as_array().unwrap();
    assert_eq!(samples.len(), SAMPLES.len());
    let mut at_half = Vec::new();
    for (s, (label, sigma, hx, hy, scale)) in samples.iter().zip(SAMPLES) {
        assert_eq!(s["label"], label);
        assert_eq!(s["sigma_m"].as_f64(), Some(sigma));
        assert!(close(s["rms_slope"].as_f64().unwrap(), sigma * 2.0e4));
        assert_eq!(s["hurst_x"].as_f64(), Some(hx));
        assert_eq!(s["hurst_y"].as_f64(), Some(hy));
        let hyper = common::response(LEVELS, scale, false);
        let loads = s["load_norm"].as_array().unwrap();
        assert_eq!(loads.len(), 3);
        for (l, a) in loads.iter().zip([0.1, 0.5, 0.9]) {
            assert_eq!(l["area_fraction"].as_f64(), Some(a));
            let got = l["load_norm"]["icm"].as_f64().unwrap();
            let want = lerp_at(&hyper, a);
            assert!(close(got, want), "{label} at {a}: {got} vs {want}");
            // Within 1 % of the closed form s a^1.5 the table samples.
            assert!((got / (scale * a.powf(1.5)) - 1.0).abs() < 0.01);
            // The linear responses are exactly linear in A/A0.
            let linear = l["load_norm"]["icm-linear"].as_f64().unwrap();
            assert!((linear - scale * a / 2.0).abs() < 1e-12, "{linear}");
        }
        at_half.push(loads[1]["load_norm"]["icm"].as_f64().unwrap());
    }
    // The synthetic samples are ordered as the paper's: T1 > T2 > T3 > T4.
    assert!(at_half.windows(2).all(|w| w[0] > w[1]), "{at_half:?}");
    let figures = summary["figures"].as_array().unwrap();
    assert!(figures.iter().all(|f| f["rendered"] == true));
}

#[test]
fn without_the_tensile_branch_figs_4_7_8_still_render_and_fig2_is_noted() {
    let wiring = Wiring {
        tensile: false,
        ..ALL
    };
    let files = run(&common::inputs(wiring, 48, 101));
    for fig in ["fig4", "fig7", "fig8"] {
        assert!(files.files.contains_key(&format!("{fig}.png")), "{fig}");
    }
    assert!(!files.files.contains_key("fig2.png") && !files.files.contains_key("fig2.svg"));
    let html = text(&files, "index.html");
    assert!(
        html.contains("<b>Fig. 2</b> skipped") && html.contains("`curves`"),
        "no note on Fig. 2"
    );
    assert!(html.contains("<b>Table 1</b> skipped"));
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    assert_eq!(summary["material"], Value::Null);
    let fig2 = &summary["figures"][0];
    assert_eq!(fig2["name"], "fig2");
    assert_eq!(fig2["rendered"], false);
    assert!(fig2["note"].as_str().unwrap().contains("curves"));
}

#[test]
fn only_the_tensile_branch_gives_fig2_and_notes_the_rest() {
    let wiring = Wiring {
        tensile: true,
        surfaces: false,
        responses: false,
        linear: false,
    };
    let files = run(&common::inputs(wiring, 8, 11));
    let names: Vec<&str> = files.files.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        ["fig2.png", "fig2.svg", "index.html", "summary.json"]
    );
    let html = text(&files, "index.html");
    for fig in ["Fig. 4", "Fig. 7", "Fig. 8"] {
        assert!(html.contains(&format!("<b>{fig}</b> skipped")), "{fig}");
    }
    assert!(html.contains("Sample summary</b> skipped"));
}

#[test]
fn linear_only_responses_draw_fig7_and_skip_fig8() {
    let wiring = Wiring {
        tensile: false,
        surfaces: false,
        responses: false,
        linear: true,
    };
    let files = run(&common::inputs(wiring, 8, 51));
    assert!(files.files.contains_key("fig7.png"));
    assert!(!files.files.contains_key("fig8.png"));
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    let fig8 = summary["figures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == "fig8")
        .unwrap();
    assert!(
        fig8["note"]
            .as_str()
            .unwrap()
            .contains("tangent ratio differs from 1")
    );
    assert_eq!(
        summary["samples"][0]["load_norm"][1]["load_norm"]["icm"],
        Value::Null
    );
}

#[test]
fn no_inputs_at_all_still_give_a_page() {
    let files = run(&Inputs::new());
    let html = text(&files, "index.html");
    assert_eq!(html.matches("skipped:").count(), 4 + 2 + 1, "{html}");
    assert!(files.files.contains_key("summary.json"));
    // #49: no finding has its inputs: no section, nulls in summary.json.
    assert!(!html.contains("What this rerun finds"), "{html}");
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    for key in ["claim", "finite_strain", "experiment"] {
        assert_eq!(summary["findings"][key], Value::Null, "{key}");
    }
}

#[test]
fn a_nan_in_a_plotted_column_names_input_column_and_row() {
    // Every other column of the response schema stays as the fixture has it.
    let mut bad = ResponseTable::from_table(&common::response(21, 0.3, false)).unwrap();
    bad.load_norm[3] = f64::NAN;
    let inputs = Inputs::new().with("responses.T2.icm", Product::Table(bad.into_table()));
    let e = Report
        .run(
            &ReportParams::default().check().unwrap(),
            &inputs,
            &Context::new("report"),
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("responses.T2") && e.contains("load_norm") && e.contains("row 3"),
        "{e}"
    );
}

#[test]
fn a_missing_column_names_the_input() {
    // The profile schema reads z_m, z_over_sigma, then area_fraction: with
    // the first two present, area_fraction is the column found missing.
    let inputs = Inputs::new().with(
        "profiles.T1",
        Product::Table(
            Table::new()
                .with("z_m", vec![1e-5, 0.0])
                .with("z_over_sigma", vec![0.0, 1.0]),
        ),
    );
    let e = Report
        .run(
            &ReportParams::default().check().unwrap(),
            &inputs,
            &Context::new("report"),
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("profiles.T1") && e.contains("area_fraction"),
        "{e}"
    );
}

#[test]
fn provenance_record_is_rendered_when_given() {
    let inputs = common::inputs(
        Wiring {
            tensile: false,
            surfaces: false,
            responses: true,
            linear: false,
        },
        8,
        21,
    );
    let record = serde_json::json!({"hypercontact": "0.1.0", "pipeline": "paper.yaml"});
    let files = hypercontact_report::render_report(
        &inputs,
        &hypercontact_report::ReportOptions::default(),
        Some(&record),
    )
    .unwrap();
    let html = text(&files, "index.html");
    assert!(html.contains("<td>pipeline</td><td>paper.yaml</td>"));
    assert!(!html.contains("No provenance record"));
}

/// Table 1's E0* and the E0* behind the plotted F/(E0* A0) are one number:
/// responses normalised at ν = 0.4 are refused by a report at its default
/// ν = ½ (which would show E0* = 4 μ0) and accepted at ν = 0.4, where
/// Table 1 shows exactly the E0* they were divided by.
#[test]
fn table_1_shows_the_e0_star_the_responses_were_normalised_by() {
    let poisson = 0.4;
    let inputs = common::inputs_at(ALL, 16, 51, poisson);
    let e = run_with(&ReportParams::default(), &inputs).unwrap_err();
    assert!(e.contains("params") && e.contains("poisson = 0.5"), "{e}");
    // Without the fit's params table the responses are what disagrees.
    let responses_only = Inputs::new()
        .with("material", Product::Table(common::material()))
        .with(
            "responses.T2.icm-linear",
            Product::Table(common::response_at(51, 0.3, true, poisson)),
        );
    let e = run_with(&ReportParams::default(), &responses_only).unwrap_err();
    assert!(
        e.contains("responses.T2.icm-linear") && e.contains("`poisson`"),
        "{e}"
    );

    let at_04 = ReportParams {
        poisson: hypercontact_material::Poisson(poisson),
        ..Default::default()
    };
    for inputs in [&inputs, &responses_only] {
        let files = run_with(&at_04, inputs).unwrap();
        let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
        let shown = summary["material"]["e0_star_pa"].as_f64().unwrap();
        assert_eq!(summary["material"]["poisson"].as_f64(), Some(poisson));
        // E0* from the response's own load: F / (load_norm · A0).
        let r = ResponseTable::from_table(&common::response_at(51, 0.3, true, poisson)).unwrap();
        let used = r.load_n[50] / (r.load_norm[50] * common::A0_M2);
        assert!(close(shown, used), "Table 1 {shown} vs plotted {used}");
        assert!(!close(shown, common::e0_star_pa(0.5)));
        let html = text(&files, "index.html");
        assert!(html.contains("Initial moduli (ν = 0.4)"));
    }
}

/// The inputs of the full report plus boundary-element responses: the
/// hyperelastic BEM needs 1.25 × the ICM's load at every area, the linear
/// BEM 0.8 × (a different factor, so swapped laws would show).
fn with_bem(hyperelastic_samples: usize) -> Inputs {
    let mut inputs = common::inputs(ALL, MAP_N, LEVELS);
    let table = |t: Table| std::sync::Arc::new(Product::Table(t));
    for (i, (label, _, _, _, scale)) in SAMPLES.iter().enumerate() {
        if i < hyperelastic_samples {
            inputs.insert(
                &format!("responses.{label}.bem"),
                table(common::response(LEVELS, 1.25 * scale, false)),
            );
        }
        inputs.insert(
            &format!("responses.{label}.bem-linear"),
            table(common::response(LEVELS, 0.8 * scale, true)),
        );
    }
    inputs
}

#[test]
fn bem_responses_add_curves_and_the_icm_bem_load_ratio_table() {
    let plain = run(&common::inputs(ALL, MAP_N, LEVELS));
    // T4 has no hyperelastic BEM: its hyperelastic ratio is absent, not 0.
    // Each law is compared with itself: the ICM with the hyperelastic BEM
    // as the reference, the linear ICM with the linear BEM.
    let inputs = with_bem(3);
    let files = run(&inputs);
    let linear_reference = ReportParams {
        reference_model: Some("bem-linear".into()),
        ..common::wired_params(&inputs)
    };
    let linear_files = run_with(&linear_reference, &inputs).unwrap();
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    let linear_summary: Value =
        serde_json::from_slice(&linear_files.files["summary.json"]).unwrap();
    for (i, s) in summary["samples"].as_array().unwrap().iter().enumerate() {
        let scale = SAMPLES[i].4;
        let linear_loads = &linear_summary["samples"][i]["load_norm"];
        for ((k, l), a) in s["load_norm"]
            .as_array()
            .unwrap()
            .iter()
            .enumerate()
            .zip([0.1f64, 0.5, 0.9])
        {
            // The hyperelastic loads are a^1.5 sampled and interpolated
            // alike, so their ratio is the factor to rounding.
            match l["over_reference"]["icm"].as_f64() {
                Some(r) => {
                    assert!(i < 3);
                    assert!((r - 0.8).abs() < 1e-12, "{a}: {r}");
                    let bem = l["load_norm"]["bem"].as_f64().unwrap();
                    assert!((bem / (1.25 * scale * a.powf(1.5)) - 1.0).abs() < 0.01);
                }
                None => assert!(i == 3 && l["load_norm"]["bem"].is_null()),
            }
            let r = linear_loads[k]["over_reference"]["icm-linear"]
                .as_f64()
                .unwrap();
            assert!((r - 1.25).abs() < 1e-12, "{a}: {r}");
        }
    }
    let html = text(&files, "index.html");
    let table = &html[html.find("F_model / F_bem at").expect("the ratio table")..];
    let table = &table[..table.find("</table>").unwrap()];
    assert!(table.contains("<td>T1</td><td>icm</td><td>0.8</td><td>0.8</td><td>0.8</td>"));
    assert!(!table.contains("<td>T4</td><td>icm</td>"));
    let linear_html = text(&linear_files, "index.html");
    let table = &linear_html[linear_html.find("F_model / F_bem-linear").unwrap()..];
    assert!(table.contains("<td>T4</td><td>icm-linear</td><td>1.25</td>"));
    assert!(!text(&plain, "index.html").contains("F_model / F_"));
    // Fig. 7 turns into a panel per sample (each titled), with every curve
    // drawn; Fig. 8 adds the hyperelastic BEM.
    let polylines = |f: &Files, fig: &str, w, h| {
        assert_svg(fig, &text(f, &format!("{fig}.svg")), w, h)["polyline"]
    };
    let fig7 = text(&files, "fig7.svg");
    for label in ["T1", "T2", "T3", "T4"] {
        assert!(fig7.contains(label), "no panel {label}");
    }
    // Both labels in the key: `bem` also on its own, not only in `bem-linear`.
    assert!(fig7.matches("bem").count() > fig7.matches("bem-linear").count());
    assert!(fig7.contains("bem-linear"));
    assert!(!text(&plain, "fig7.svg").contains("bem"));
    assert!(polylines(&files, "fig7", 1200, 900) >= polylines(&plain, "fig7", 900, 600) + 3);
    // Fig. 8 draws every nonlinear model: the BEM's curve on each of the
    // three samples that have one is added to the ICM's and the theories'.
    // Strokes follow the models drawn, so the counts of segments are not
    // comparable across the two: the curves differ and the key names them.
    assert_ne!(text(&files, "fig8.svg"), text(&plain, "fig8.svg"));
    let fig8 = text(&files, "fig8.svg");
    for model in ["icm", "bem", "persson", "gw"] {
        assert!(fig8.contains(model), "{model} not in Fig. 8's key");
    }
    assert!(!fig8.contains("linear"), "a linear law's ratio is drawn");
}

#[test]
fn bem_alone_draws_figs_7_and_8() {
    let mut inputs = Inputs::new();
    let (label, _, _, _, scale) = SAMPLES[0];
    inputs.insert(
        &format!("responses.{label}.bem"),
        std::sync::Arc::new(Product::Table(common::response(LEVELS, scale, false))),
    );
    let files = run(&inputs);
    assert!(files.files.contains_key("fig7.png") && files.files.contains_key("fig8.png"));
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    let l = &summary["samples"][0]["load_norm"][1];
    assert!(l["load_norm"]["bem"].as_f64().is_some());
    assert!(l["load_norm"]["icm"].is_null() && l["over_reference"]["icm"].is_null());
}

/// A 40 × 40 RGB PNG of one colour.
fn flat_png(rgb: [u8; 3]) -> Vec<u8> {
    let pixels: Vec<u8> = (0..40 * 40).flat_map(|_| rgb).collect();
    hypercontact_labfiles::png::encode_png(40, 40, hypercontact_labfiles::png::Pixels::Rgb8(pixels))
        .unwrap()
}

/// The physics of [`with_experiment`]'s experiment (synth-contact's default).
const PHYSICS: &str = "bem, hyperelastic, equibiaxial tangent, free boundary";

/// T1 with the contact experiment and contact-compare's products.
fn with_experiment() -> Inputs {
    use hypercontact_compare::stage::{
        AgreementTable, FigureIndex, LoadRatioTable, TransformTable,
    };
    use hypercontact_contact_images::stage::ContactTable;
    let mut inputs = common::inputs(ALL, MAP_N, LEVELS);
    let table = |t: Table| std::sync::Arc::new(Product::Table(t));
    let experiment = ContactTable {
        frame: (0..7).collect(),
        time_s: (0..7).map(f64::from).collect(),
        // Frame 1 before contact, frame 2 a noisy negative force: not drawn.
        force_n: vec![0.0, 0.0, -0.01, 0.5, 2.0, 5.0, 9.0],
        area_fraction: vec![0.0, 0.0, 0.01, 0.1, 0.3, 0.6, 0.85],
        contact_area_m2: vec![0.0; 7],
        patches: vec![0; 7],
        threshold: vec![0.0; 7],
        method: vec!["calibrated".into(); 7],
    };
    inputs.insert("experiments.T1", table(experiment.into_table()));
    let agreement = AgreementTable {
        model: vec!["icm".into(), "bem".into()],
        rms_log_ratio: vec![1.25, 0.125],
        mean_log_ratio: vec![-1.0, -0.1],
        points: vec![4, 4],
        outside_model: vec![0, 0],
        area: vec!["view (truncation)".into(), "view (bem)".into()],
        // #49: bem is the experiment's own physics, marked and not ranked.
        rank: vec![1, 0],
        by_construction: vec![0, 1],
        experiment_physics: vec![PHYSICS.into(); 2],
    };
    inputs.insert("agreement.T1", table(agreement.into_table()));
    let ratios = LoadRatioTable {
        model: vec!["icm".into(), "bem".into()],
        area_fraction: vec![0.5, 0.5],
        load_ratio: vec![0.375, f64::NAN],
        by_construction: vec![0, 1],
        experiment_physics: vec![PHYSICS.into(); 2],
    };
    inputs.insert("load_ratio.T1", table(ratios.into_table()));
    let transform = TransformTable {
        against: vec!["truncation".into()],
        frame: vec![5],
        area_fraction: vec![0.6],
        angle_deg: vec![2.5],
        shift_x_m: vec![1.5e-4],
        shift_y_m: vec![-1e-4],
        scale: vec![1.0],
        zncc: vec![0.8],
        registrations: vec![1],
        angle_sd_deg: vec![f64::NAN],
        shift_x_sd_m: vec![f64::NAN],
        shift_y_sd_m: vec![f64::NAN],
        scale_sd: vec![f64::NAN],
    };
    inputs.insert("transforms.T1", table(transform.into_table()));
    let figures = Files::new()
        .with("observed_a0.500.png", flat_png([0, 0, 0]))
        .with("predicted_truncation_a0.500.png", flat_png([255, 255, 255]))
        .with("overlay_truncation_a0.500.png", flat_png([213, 94, 0]))
        .with_index(FigureIndex {
            model: vec!["truncation".into()],
            requested_area_fraction: vec![0.5],
            area_fraction: vec![0.6],
            model_area_fraction: vec![0.6],
            frame: vec![5],
            observed_file: vec!["observed_a0.500.png".into()],
            predicted_file: vec!["predicted_truncation_a0.500.png".into()],
            overlay_file: vec!["overlay_truncation_a0.500.png".into()],
            pixel_m: vec![1e-5],
            width_px: vec![40],
            height_px: vec![40],
        });
    inputs.insert(
        "compare_figures.T1",
        std::sync::Arc::new(Product::Files(figures)),
    );
    inputs
}

#[test]
fn the_experiment_adds_fig6_its_points_in_fig7_and_the_agreement_table() {
    let files = run(&with_experiment());
    let html = text(&files, "index.html");
    assert!(html.contains("<figure id=\"fig6\">"));
    // 40 px of 10 µm: the bar is the longest of the list under a quarter
    // of the 0.4 mm width, 100 µm, drawn into each panel's copy.
    assert!(html.contains("bar = 100 µm"), "no scale");
    for name in ["observed", "predicted_truncation", "overlay_truncation"] {
        let png = &files.files[&format!("fig6_T1_{name}_a0.500.png")];
        let image = image::load_from_memory(png).unwrap().into_rgb8();
        // Bar pixels black on a white margin, at the lower left.
        let black = image.pixels().filter(|p| p.0 == [0, 0, 0]).count();
        assert!(name == "observed" || black >= 10, "{name}: {black}");
    }
    let registration = &html[html.find("Registration of the camera").unwrap()..];
    assert!(registration.contains("<td>T1</td><td>truncation</td><td>5 (0.6)</td><td>2.5</td>"));
    // Agreement: best first, the experiment's own physics (#49) after the
    // ranked ones as "by construction"; a missing ratio as n/a.
    let agreement = &html[html.find("Agreement of the models").unwrap()..];
    let agreement = &agreement[..agreement.find("</table>").unwrap()];
    let bem = agreement
        .find("<td>T1</td><td>by construction</td><td>bem</td><td>view (bem)</td><td>0.125</td>")
        .unwrap();
    let icm = agreement
        .find("<td>T1</td><td>1</td><td>icm</td><td>view (truncation)</td><td>1.25</td>")
        .unwrap();
    assert!(
        icm < bem && agreement.contains("<td>n/a</td>") && agreement.contains("<td>0.375</td>")
    );
    // Its physics named under the table, in Fig. 7's caption and in the
    // experiment's section, with the model that shares it.
    let named = "The experiment of T1: rendered by <i>bem, hyperelastic, equibiaxial tangent, \
                 free boundary</i>; bem shares it, so agrees with the experiment by \
                 construction (marked, not ranked).";
    assert!(html.matches(named).count() >= 3, "{html}");
    let fig7_caption = &html[html.find("<figure id=\"fig7\">").unwrap()..];
    let fig7_caption = &fig7_caption[..fig7_caption.find("</figure>").unwrap()];
    assert!(fig7_caption.contains(named), "{fig7_caption}");
    assert!(html.contains("synthetic lab"));
    // #49: the page opens with the findings: the experiment's sentence,
    // linked to Fig. 7 and the agreement table; no finite-strain sentence
    // without `finite_strain`.
    let findings = &html[html.find("<section id=\"findings\">").unwrap()..];
    let findings = &findings[..findings.find("</section>").unwrap()];
    assert!(html.find("<section id=\"findings\">") < html.find("<h2>Material"));
    for part in [
        "<b>The experiment.</b> The experiment is rendered by <i>bem, hyperelastic, \
         equibiaxial tangent, free boundary</i>; bem shares it",
        "Among the others the best-ranked is icm on T1 (rms ln(F<sub>model</sub>/\
         F<sub>exp</sub>) 1.2)",
        "<a href=\"#agreement-table\">the agreement table</a>",
        "<a href=\"#fig7\">Fig. 7</a>",
    ] {
        assert!(findings.contains(part), "{part}\n{findings}");
    }
    assert!(html.contains("<p class=\"table-caption\" id=\"agreement-table\">"));
    assert!(!findings.contains("Against finite strain"), "{findings}");
    assert_eq!(
        summary_of(&files)["findings"]["experiment"]["samples"][0],
        "T1"
    );
    // Fig. 7: four measured points (positive area and force) and the key.
    let fig7 = text(&files, "fig7.svg");
    assert_eq!(fig7.matches("<circle").count(), 4 + 1);
    // summary.json: the tables as they are (NaN as null).
    let summary: Value = serde_json::from_slice(&files.files["summary.json"]).unwrap();
    let t1 = &summary["samples"][0];
    assert_eq!(t1["agreement"][1]["rms_log_ratio"], 0.125);
    assert!(t1["load_ratio"][1]["load_ratio"].is_null());
    assert_eq!(t1["transform"]["angle_deg"], 2.5);
    assert!(summary["samples"][1]["agreement"].is_null());
    // A figures product without its index is named.
    let mut broken = with_experiment();
    broken.insert(
        "compare_figures.T1",
        std::sync::Arc::new(Product::Files(Files::new())),
    );
    let e = run_with(&ReportParams::default(), &broken).unwrap_err();
    assert!(
        e.contains("compare_figures.T1") && e.contains("index"),
        "{e}"
    );
}

fn summary_of(files: &Files) -> Value {
    serde_json::from_slice(&files.files["summary.json"]).unwrap()
}

/// The x of every `<text>` of an SVG, with its content.
fn svg_texts(svg: &str) -> Vec<(f64, String)> {
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut out = Vec::new();
    let mut x = None;
    loop {
        match reader.read_event() {
            Ok(Event::Eof) => break,
            Ok(Event::Start(e)) if e.name().as_ref() == b"text" => {
                x = e
                    .try_get_attribute("x")
                    .unwrap()
                    .map(|a| String::from_utf8_lossy(&a.value).parse::<f64>().unwrap());
            }
            Ok(Event::Text(t)) => {
                if let Some(x) = x.take() {
                    out.push((x, String::from_utf8_lossy(&t).trim().to_owned()));
                }
            }
            Ok(_) => {}
            Err(e) => panic!("malformed SVG: {e}"),
        }
    }
    out
}

/// Issue #37, 6: with one sample, Figs. 7 and 9 are one panel across the
/// figure (not a half-width panel with an empty second column, as two
/// panels a row drew it), the key in the column right beside it. Checked
/// on the SVG: the figure is the single panel's 1000 × 680; the panel's
/// x-axis labels reach past 60 % of the width (the half-width panel ended
/// at 525 of 1300 px, 40 %); the key's labels sit right of the panel,
/// within the last 250 px.
#[test]
fn one_sample_draws_figs_7_and_9_as_one_full_width_panel_with_the_key_beside() {
    let mut inputs = Inputs::new();
    let (label, _, _, _, scale) = SAMPLES[0];
    let table = |t: Table| std::sync::Arc::new(Product::Table(t));
    inputs.insert(
        &format!("responses.{label}.icm"),
        table(common::response(LEVELS, scale, false)),
    );
    inputs.insert(
        &format!("responses.{label}.bem"),
        table(common::response(LEVELS, 1.25 * scale, false)),
    );
    let files = run(&inputs);
    for fig in ["fig7", "fig9"] {
        let svg = text(&files, &format!("{fig}.svg"));
        assert_svg(fig, &svg, 1000, 680);
        assert!(svg.contains("width=\"1000\"") && svg.contains("height=\"680\""));
        let png = image::load_from_memory(&files.files[&format!("{fig}.png")]).unwrap();
        assert_eq!(png.width() * 680, png.height() * 1000, "{fig}: aspect");
        let texts = svg_texts(&svg);
        let key: Vec<f64> = texts
            .iter()
            .filter(|(_, t)| t == "icm" || t == "bem")
            .map(|(x, _)| *x)
            .collect();
        assert_eq!(key.len(), 2, "{fig}: {texts:?}");
        assert!(
            key.iter().all(|&x| x > 750.0 && x < 1000.0),
            "{fig}: key at {key:?}"
        );
        let panel_right = texts
            .iter()
            .map(|(x, _)| *x)
            .filter(|&x| x < 750.0)
            .fold(0.0, f64::max);
        assert!(panel_right > 600.0, "{fig}: panel ends at {panel_right}");
    }
}
