//! The report against the real `icm` stage: the E0* the report recovers
//! from a response (mean_stress_pa · area_fraction / load_norm) is the one
//! the ICM divided by, for both contact laws, so Table 1 can be held to it.

mod common;

use hypercontact_core::contact::ResponseTable;
use hypercontact_core::{Context, Inputs, Params, Product, Schema, Stage, Table};
use hypercontact_icm::Model;
use hypercontact_icm::stage::{Icm, IcmParams};
use hypercontact_report::{Report, ReportParams};

fn icm(model: Model, poisson: f64, profile: &Table) -> Table {
    let params = IcmParams {
        model,
        poisson: hypercontact_material::Poisson(poisson),
        ..Default::default()
    };
    let inputs = Inputs::new()
        .with("profile", Product::Table(profile.clone()))
        .with("material", Product::Table(common::material()));
    let out = Icm
        .run(&params.check().unwrap(), &inputs, &Context::new("icm"))
        .unwrap();
    match out.get("response") {
        Some(Product::Table(t)) => t.clone(),
        other => panic!("no response: {other:?}"),
    }
}

fn report(poisson: f64, inputs: &Inputs) -> Result<serde_json::Value, String> {
    let params = ReportParams {
        poisson: hypercontact_material::Poisson(poisson),
        ..Default::default()
    };
    let out = Report
        .run(&params.check().unwrap(), inputs, &Context::new("report"))
        .map_err(|e| e.to_string())?;
    match out.get("report") {
        Some(Product::Files(f)) => Ok(serde_json::from_slice(&f.files["summary.json"]).unwrap()),
        other => panic!("no report: {other:?}"),
    }
}

#[test]
fn table_1_is_held_to_the_e0_star_of_the_icm() {
    let profile = common::profile(201, 10e-6);
    let poisson = 0.4;
    let inputs = Inputs::new()
        .with("material", Product::Table(common::material()))
        .with("profiles.T1", Product::Table(profile.clone()))
        .with(
            "responses.T1",
            Product::Table(icm(Model::Hyperelastic, poisson, &profile)),
        )
        .with(
            "responses_linear.T1",
            Product::Table(icm(Model::Linear, poisson, &profile)),
        );
    let e = report(0.5, &inputs).unwrap_err();
    assert!(e.contains("responses.T1") && e.contains("`poisson`"), "{e}");

    let summary = report(poisson, &inputs).unwrap();
    let shown = summary["material"]["e0_star_pa"].as_f64().unwrap();
    // E0* · A0 = load_n / load_norm, A0 = area_m2 / area_fraction of the
    // profile: the ICM's own normalisation, read without the report's formula.
    let p = hypercontact_truncation::stage::ProfileTable::from_table(&profile).unwrap();
    let last = p.area_fraction.len() - 1;
    let a0 = p.area_m2[last] / p.area_fraction[last];
    for input in ["responses.T1", "responses_linear.T1"] {
        let r = ResponseTable::from_table(match inputs.get(input) {
            Some(Product::Table(t)) => t,
            _ => unreachable!(),
        })
        .unwrap();
        let used = r.load_n[last] / r.load_norm[last] / a0;
        assert!(
            (shown / used - 1.0).abs() < 1e-9,
            "{input}: Table 1 {shown} vs the ICM's {used}"
        );
    }
}
