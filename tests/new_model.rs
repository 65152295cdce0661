//! Issue #30's acceptance test: contact models are a role. A contact model
//! that exists only here (a flat-punch law on the truncated surface) is
//! registered beside the real stages, wired into `contact-compare` and
//! `report` by its label in a small pipeline run by the runner, and shows
//! up in Figs. 7, 8 and 9, the κ table, the load-ratio table and the
//! agreement table, with no line of the report or the comparison naming it.
//! Also pinned: a model input wired without its labels is refused when the
//! pipeline is planned, with the form to write.

use std::path::{Path, PathBuf};

use hypercontact_core::contact::{Curve, ModelMapIndex, ResponseTable};
use hypercontact_core::{
    Arity, Checked, Context, Field, Files, InputSpec, Inputs, OutputSpec, Outputs, Schema, Stage,
    StageError, StageInfo, params,
};
use hypercontact_runner::{Pipeline, RunOptions, run};

/// Parameters of the throwaway `flat-punch` model.
#[params]
struct PunchParams {
    /// E0* of the law
    #[param(default = 4.0e6, positive, unit = "Pa")]
    e0_star_pa: f64,
}

/// A made-up contact law: the load grows as (A/A0)^1.5 and the tangent
/// modulus stiffens linearly with the area; its contact at each area
/// fraction is the surface cut there (the highest points in contact).
struct FlatPunch;

static PUNCH: StageInfo = StageInfo {
    kind: "flat-punch",
    version: 1,
    summary: "a throwaway contact model for the role test",
    doc: "",
    inputs: &[InputSpec::field("surface", Arity::One, "height map")],
    outputs: &[
        OutputSpec::table::<ResponseTable>("response", "load against area"),
        OutputSpec::files_indexed::<ModelMapIndex>("contact_maps", "pressure maps"),
    ],
};

/// The area fractions the punch's curve is given at, and the maps kept.
const FRACTIONS: [f64; 9] = [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.8, 0.9];
const MAPS: [f64; 3] = [0.1, 0.5, 0.9];

impl Stage for FlatPunch {
    type Params = PunchParams;

    fn info(&self) -> &'static StageInfo {
        &PUNCH
    }

    fn run(
        &self,
        p: &Checked<PunchParams>,
        inputs: &Inputs,
        _: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.field("surface")?;
        let a0_m2 = surface.nx() as f64 * surface.dx_m * surface.ny() as f64 * surface.dy_m;
        let curve = Curve {
            z_m: FRACTIONS.iter().map(|a| -a * 1e-5).collect(),
            area_fraction: FRACTIONS.to_vec(),
            area_m2: FRACTIONS.iter().map(|a| a * a0_m2).collect(),
            load_n: FRACTIONS
                .iter()
                .map(|a| 0.05 * p.e0_star_pa * a0_m2 * a.powf(1.5))
                .collect(),
            modulus_pa: FRACTIONS.iter().map(|a| p.e0_star_pa * (1.0 + a)).collect(),
        };
        let response = ResponseTable::from_curve(curve, p.e0_star_pa, a0_m2);
        let mut heights: Vec<f64> = surface
            .values
            .iter()
            .copied()
            .filter(|h| !h.is_nan())
            .collect();
        heights.sort_by(|a, b| b.total_cmp(a));
        let mut files = Files::new();
        let mut index = ModelMapIndex::default();
        for a in MAPS {
            let level = heights[((a * heights.len() as f64) as usize).min(heights.len() - 1)];
            let pressure = surface.values.mapv(|h| if h >= level { 1e5 } else { 0.0 });
            let field = Field::new(pressure, surface.dx_m, surface.dy_m).unwrap();
            let mut bytes = Vec::new();
            field.write_npy(&mut bytes).unwrap();
            let name = format!("pressure_a{a:.3}.npy");
            files.files.insert(name.clone(), bytes);
            index.requested_area_fraction.push(a);
            index.area_fraction.push(a);
            index.load_n.push(0.0);
            index.pressure_file.push(name);
            index.dx_m.push(surface.dx_m);
            index.dy_m.push(surface.dy_m);
        }
        Ok(Outputs::new()
            .table("response", response.into_table())
            .files("contact_maps", files.with_index(index)))
    }
}

fn samples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/samples")
}

/// One small sample: a material, a scan, the synthetic lab's contact
/// experiment, the ICM (the reference model) and the punch, compared and
/// reported.
fn pipeline(report_responses: &str) -> String {
    let t1 = samples_dir().join("T1.yaml");
    format!(
        r#"name: role
stages:
  mat:
    uses: synth-tensile
    with: {{ mode: UT, seed: 11, width_px: 64, height_px: 64, frames: 4 }}
  scan:
    uses: synth-surface
    with_file: {t1}
    with: {{ tile_px: 256, pixel_m: 4.0e-6, lambda_min_m: 20.0e-6, tiles_x: 2, tiles_y: 2 }}
  s1:
    uses: surface
    inputs: {{ tiles: scan.tiles }}
    with: {{ resolution_m: 20.0e-6 }}
  trunc:
    uses: truncation
    inputs: {{ surface: s1.height }}
    with: {{ levels: 200 }}
  icm:
    uses: icm
    inputs: {{ profile: trunc, material: mat.material }}
  punch:
    uses: flat-punch
    inputs: {{ surface: s1.height }}
  lab:
    uses: synth-contact
    inputs: {{ surface: scan.truth, material: mat.material }}
    with: {{ width_px: 256, height_px: 256, magnification: 1.5, frames: 10 }}
  images:
    uses: contact-images
    inputs: {{ sequence: lab.sequence }}
    with: {{ pixel_m: 4.3333333333e-6, exposure_s: 0.05, map_fractions: [0.1, 0.5] }}
  compare:
    uses: contact-compare
    inputs:
      contact: images.contact
      observed_maps: images.contact_maps
      surface: s1.height
      responses: {{ icm: icm.response, punch: punch.response }}
      model_maps: {{ punch: punch.contact_maps }}
    with: {{ figure_fractions: [0.5], figure_px: 64 }}
  report:
    uses: report
    inputs:
      stats: {{ S1: s1.stats }}
      responses: {report_responses}
      experiments: {{ S1: images.contact }}
      agreement: {{ S1: compare.agreement }}
      load_ratio: {{ S1: compare.load_ratio }}
      transforms: {{ S1: compare.transform }}
      compare_figures: {{ S1: compare.figures }}
    with: {{ reference_model: icm }}
"#,
        t1 = t1.display()
    )
}

fn registry() -> hypercontact_core::Registry {
    let mut registry = hypercontact::registry();
    registry.add(FlatPunch);
    registry
}

fn options(dir: &Path) -> RunOptions {
    RunOptions::in_folders(dir.join("out"), dir.join("cache"))
}

fn load(dir: &Path, text: &str) -> Result<Pipeline, String> {
    let path = dir.join("role.yaml");
    std::fs::write(&path, text).unwrap();
    Pipeline::load(&path, &registry()).map_err(|e| e.to_string())
}

/// The `<table>` after the caption starting with `caption`.
fn table_after<'h>(html: &'h str, caption: &str) -> &'h str {
    let start = html
        .find(caption)
        .unwrap_or_else(|| panic!("no table {caption}"));
    let table = &html[start..];
    &table[..table.find("</table>").unwrap()]
}

#[test]
fn a_new_contact_model_appears_in_the_figures_and_tables_by_its_label() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = load(
        dir.path(),
        &pipeline("{ S1: { icm: icm.response, punch: punch.response } }"),
    )
    .unwrap();
    run(&pipeline, &options(dir.path())).unwrap();
    let report = dir.path().join("out/report");
    let read = |name: &str| std::fs::read_to_string(report.join(name)).unwrap();

    // Figs. 7 and 9: its label in the key and its curve drawn in the
    // second family's colour (vermillion; the ICM, first in label order,
    // is black). Fig. 8: its tangent ratio 1 + A/A0 is not 1.
    for fig in ["fig7.svg", "fig9.svg", "fig8.svg"] {
        let svg = read(fig);
        assert!(svg.contains("punch"), "{fig}: no `punch` in the key");
        if fig != "fig8.svg" {
            assert!(
                svg.contains("<polyline") && svg.contains("#D55E00"),
                "{fig}: no vermillion curve"
            );
        }
    }
    let html = read("index.html");
    // κ: a column headed by the label, with a number at A/A0 = 0.1.
    let kappa = table_after(&html, "κ = (A/A0)");
    assert!(kappa.contains("<th>punch</th>"), "{kappa}");
    // Load ratio against the ICM: a row of numbers for the punch.
    let ratio = table_after(&html, "Load ratio F_model / F_icm");
    let row = &ratio[ratio
        .find("<td>S1</td><td>punch</td>")
        .expect("a punch row")..];
    let row = &row[..row.find("</tr>").unwrap()];
    assert!(
        row.matches("<td>").count() == 5 && !row.contains("n/a"),
        "{row}"
    );
    // Agreement with the (synthetic) experiment: scored and ranked.
    let agreement = table_after(&html, "Agreement of the models");
    assert!(
        agreement.contains("</td><td>punch</td><td>view (punch)</td>"),
        "{agreement}"
    );
    // Fig. 6: its predicted map beside the observed one.
    assert!(report.join("fig6_S1_overlay_punch_a0.500.png").exists());

    let summary: serde_json::Value = serde_json::from_str(&read("summary.json")).unwrap();
    let kappa = &summary["samples"][0]["kappa"][1];
    assert_eq!(kappa["area_fraction"], 0.1);
    assert!(kappa["models"]["punch"].as_f64().unwrap() > 0.0);
}

#[test]
fn a_model_input_without_its_labels_is_refused_when_planned() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = load(dir.path(), &pipeline("punch.response")).unwrap();
    let dry = RunOptions {
        dry_run: true,
        ..options(dir.path())
    };
    let e = run(&pipeline, &dry).unwrap_err().to_string();
    let e = e.replace(&*dir.path().to_string_lossy(), "<dir>");
    assert!(e.contains("responses: { T1: { icm: <stage>"), "{e}");
    insta::assert_snapshot!(e);
}
