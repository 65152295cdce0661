//! The report against the real `icm` stage: the E0* the report recovers
//! from a response (mean_stress_pa · area_fraction / load_norm) is the one
//! the ICM divided by, for both contact laws, so Table 1 can be held to it;
//! and the ICM's bootstrap bands land on the response's axes.

use crate::common;

use hypercontact_core::contact::ResponseTable;
use hypercontact_core::{Context, Inputs, Params, Product, Schema, Stage, Table};
use hypercontact_icm::stage::{Icm, IcmParams};
use hypercontact_icm::{LawParams, Model};
use hypercontact_report::{Report, ReportParams};

fn icm(model: Model, poisson: f64, profile: &Table) -> Table {
    icm_outputs(model, poisson, profile, None).0
}

/// The ICM's `response` and `bands`, with `replicates` wired when given.
fn icm_outputs(
    model: Model,
    poisson: f64,
    profile: &Table,
    replicates: Option<Table>,
) -> (Table, Table) {
    let params = IcmParams {
        law: LawParams {
            model,
            poisson: hypercontact_material::Poisson(poisson),
            ..Default::default()
        },
    };
    let mut inputs = Inputs::new()
        .with("profile", Product::Table(profile.clone()))
        .with("material", Product::Table(common::material()));
    if let Some(r) = replicates {
        inputs = inputs.with("replicates", Product::Table(r));
    }
    let out = Icm
        .run(&params.check().unwrap(), &inputs, &Context::new("icm"))
        .unwrap();
    let table = |name: &str| match out.get(name) {
        Some(Product::Table(t)) => t.clone(),
        other => panic!("no {name}: {other:?}"),
    };
    (table("response"), table("bands"))
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
            "responses.T1.icm",
            Product::Table(icm(Model::Hyperelastic, poisson, &profile)),
        )
        .with(
            "responses.T1.icm-linear",
            Product::Table(icm(Model::Linear, poisson, &profile)),
        );
    let e = report(0.5, &inputs).unwrap_err();
    assert!(
        e.contains("responses.T1.icm") && e.contains("`poisson`"),
        "{e}"
    );

    let summary = report(poisson, &inputs).unwrap();
    let shown = summary["material"]["e0_star_pa"].as_f64().unwrap();
    // E0* · A0 = load_n / load_norm, A0 = area_m2 / area_fraction of the
    // profile: the ICM's own normalisation, read without the report's formula.
    let p = hypercontact_truncation::stage::ProfileTable::from_table(&profile).unwrap();
    let last = p.area_fraction.len() - 1;
    let a0 = p.area_m2[last] / p.area_fraction[last];
    for input in ["responses.T1.icm", "responses.T1.icm-linear"] {
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

/// Replicates whose every μ_i is the fit's times c, c = 0.90, 0.91, …, 1.10:
/// stress, tangent modulus and so the ICM's load all scale with c (the
/// mean stress S = −F/A scales with φ, so φ⁻¹(S) and the strain do not
/// move), and E_t*/E0* does not change. The type-7 percentiles of 21
/// values are the 2nd and 20th: load_norm p05 = 0.91 ×, p95 = 1.09 × the
/// response, exactly.
#[test]
fn the_icm_bands_bracket_its_curve_by_the_replicates_scale() {
    use hypercontact_material::bootstrap::ReplicatesTable;
    use hypercontact_material::{Hyperelastic, Ogden};
    let scaled: Vec<Ogden> = (0..21)
        .map(|k| {
            let c = 0.9 + 0.01 * k as f64;
            Ogden::new(
                common::MU_PA.iter().map(|m| c * m).collect(),
                common::ALPHA.to_vec(),
            )
            .unwrap()
        })
        .collect();
    let replicates = ReplicatesTable::new(
        scaled
            .iter()
            .enumerate()
            .map(|(r, m)| (r as i64 + 1, m as &dyn Hyperelastic)),
    );
    let profile = common::profile(201, 10e-6);
    let (response, bands) = icm_outputs(
        Model::Hyperelastic,
        0.5,
        &profile,
        Some(replicates.into_table()),
    );
    let inputs = Inputs::new()
        .with("material", Product::Table(common::material()))
        .with("responses.T1.icm", Product::Table(response))
        .with("bands.T1.icm", Product::Table(bands));
    let summary = report(0.5, &inputs).unwrap();
    let mut read = 0;
    for l in summary["samples"][0]["load_norm"].as_array().unwrap() {
        let Some(value) = l["load_norm"]["icm"].as_f64() else {
            continue;
        };
        let (p05, p95) = (
            l["load_norm_p05"]["icm"].as_f64().unwrap(),
            l["load_norm_p95"]["icm"].as_f64().unwrap(),
        );
        assert!((p05 / value - 0.91).abs() < 1e-9, "{p05} vs {value}");
        assert!((p95 / value - 1.09).abs() < 1e-9, "{p95} vs {value}");
        read += 1;
    }
    assert!(
        read >= 2,
        "the profile covers too few of the summary's A/A0"
    );
}
