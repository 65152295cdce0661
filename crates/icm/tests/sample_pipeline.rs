//! The shipped sample map through the stages a pipeline chains:
//! `.npy` → `truncation` → `icm` (both models), as the runner would call them.

use hypercontact_core::{Context, Inputs, Outputs, Params, Product, Stage, Table};
use hypercontact_icm::stage::{Icm, IcmParams};
use hypercontact_icm::{LawParams, Model, Scheme};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_truncation::stage::{Truncation, TruncationParams};

fn table<'a>(out: &'a Outputs, name: &str) -> &'a Table {
    match out.get(name) {
        Some(Product::Table(t)) => t,
        _ => panic!("no table `{name}`"),
    }
}

#[test]
fn sample_map_runs_through_truncation_and_both_icm_models() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/samples/self-affine-256.npy");
    let ctx = Context::new("sample");
    let surface = ctx.read_field(&path, 2e-5, 2e-5).unwrap();
    assert_eq!((surface.nx(), surface.ny()), (256, 256));

    let params = TruncationParams::default().check().unwrap();
    let truncated = Truncation
        .run(
            &params,
            &Inputs::new().with("surface", Product::Field(surface)),
            &ctx,
        )
        .unwrap();
    let profile = table(&truncated, "profile");
    assert_eq!(profile.n_rows(), 1001);
    assert!(table(&truncated, "patch_sizes").n_rows() > 4);

    let mut responses = Vec::new();
    for model in [Model::Hyperelastic, Model::Linear] {
        let params = IcmParams {
            law: LawParams {
                model,
                tangent: hypercontact_icm::Tangent::Equibiaxial,
                scheme: Scheme::Heun,
                poisson: hypercontact_material::Poisson::INCOMPRESSIBLE,
            },
        }
        .check()
        .unwrap();
        let inputs = Inputs::new()
            .with("profile", Product::Table(profile.clone()))
            .with("material", Product::Table(to_table(&paper_epdm())));
        let out = Icm.run(&params, &inputs, &ctx).unwrap();
        responses.push(table(&out, "response").clone());
    }
    let (hyper, linear) = (&responses[0], &responses[1]);
    let fraction = hyper.f64("area_fraction").unwrap();
    let ratio = hyper.f64("tangent_ratio").unwrap();
    let (load_h, load_l) = (
        hyper.f64("load_norm").unwrap(),
        linear.f64("load_norm").unwrap(),
    );
    let half = fraction.iter().position(|&f| f >= 0.5).unwrap();
    println!(
        "sample at A/A0 = {:.3}: load_norm {:.4e} (hyperelastic) vs {:.4e} (linear), \
         E_t*/E0* = {:.4}",
        fraction[half], load_h[half], load_l[half], ratio[half]
    );
    for k in 1..fraction.len() {
        if fraction[k] < 0.9 {
            assert!((2.0..=3.0).contains(&ratio[k]), "row {k}: {}", ratio[k]);
            assert!(load_h[k] > load_l[k], "row {k}");
        }
    }
    assert!(
        linear
            .f64("tangent_ratio")
            .unwrap()
            .iter()
            .all(|&r| r == 1.0)
    );
}
