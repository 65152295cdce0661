//! Stage `icm`: the truncation profile and a material in, the load–area
//! response out. A thin wrapper: table checks here, the physics in
//! [`crate::solver`] and [`crate::modulus`].
use hypercontact_core::contact::{BandTable, Curve, ResponseTable};
use hypercontact_core::{
    Arity, Checked, Context, InputSpec, Inputs, OutputSpec, Outputs, Schema, Stage, StageError,
    StageInfo, params,
};
use hypercontact_material::bootstrap::ReplicatesTable;
use hypercontact_material::table::MaterialTable;
use hypercontact_truncation::stage::ProfileTable;

use crate::bands::{BandAxes, replicate_bands, wired_replicates};
use crate::modulus::CompositeModulus;
use crate::solver::{ProfileSlices, Solution, solve};
use crate::tangent::TangentLoad;
use crate::{IcmError, LawParams};

/// Parameters of `icm`: the contact law.
#[params]
pub struct IcmParams {
    #[param(flatten)]
    pub law: LawParams,
}

/// The `icm` stage.
pub struct Icm;

static INFO: StageInfo = StageInfo {
    kind: "icm",
    version: 2,
    summary: "Incremental contact model: load against contact area from a truncation profile",
    doc: "Integrates dF/d(-z) = 2 E_t*(S) r(z) N(z) from F(z_max) = 0 downward over the \
          profile's planes (the paper's Eqs. 5-7); `z_m` is the plane's height. Hyperelastic: \
          E_t* = E_t(phi^-1(S)) / (1 - nu^2) with phi a nominal stress curve of the material \
          (Eq. 2), E_t = dphi/deps (Eq. 6), evaluated at the compressive mean stress S = -F/A \
          (so eps < 0). `tangent: equibiaxial` (default) is the paper's phi, the equibiaxial \
          curve: E_t*/E0* = 2 at first contact for nu = 1/2, so the curve starts at twice the \
          linear one; it assumes the patch's material is stretched equally in its plane. \
          `tangent: uniaxial` takes phi from the uniaxial curve in compression (free lateral \
          expansion, the small-strain limit of Hertz and Boussinesq): E_t*/E0* = 1 at first \
          contact, where the curve meets the linear one. Linear (Wang's original ICM): E_t* = \
          E0* = E0/(1 - nu^2), E0 = 2 mu0 (1 + nu). A linear-elastic material (stage \
          `material`, family `linear`) gives E* = E/(1 - nu^2) with its own nu at every stress, \
          whatever `model`, `tangent` and `poisson` say (a note says so). Schemes: `euler` is \
          the paper's explicit step; `heun` the explicit trapezoidal rule (second order, using \
          only tabulated planes; exact for a flat punch). Planes with A = 0 or N = 0 add no \
          load. A0 is area_m2 / area_fraction of the profile. If S leaves the range where phi \
          is invertible, the stage stops and names the plane and the stress. With `replicates` \
          (material-fit's bootstrap) every replicate material is solved over the same planes \
          (in parallel; the same on any thread count) and `bands` gives, per plane, the 5th, \
          50th and 95th percentiles of load_norm (each replicate's load over the main \
          material's E0* A0, on the response's axes) and of tangent_ratio (each replicate's \
          E_t* over its own E0*); a replicate whose law gives out is left out with a note.",
    inputs: &[
        InputSpec::table::<ProfileTable>("profile", Arity::One, "the truncation profile, top down"),
        InputSpec::table::<MaterialTable>(
            "material",
            Arity::One,
            "the material table (a preset or a fit)",
        ),
        InputSpec::table::<ReplicatesTable>(
            "replicates",
            Arity::Optional,
            "material-fit's bootstrap replicates: each is solved too, for `bands`",
        ),
    ],
    outputs: &[
        OutputSpec::table::<ResponseTable>("response", "one row per profile plane"),
        OutputSpec::table::<BandTable>(
            "bands",
            "5–95 % bands over the material's bootstrap replicates, one row per plane (no \
             rows without `replicates`)",
        ),
    ],
};

impl Stage for Icm {
    type Params = IcmParams;
    /// Parallel (rayon) over its work: a few cores pay off on a cluster.
    const RESOURCES: hypercontact_core::Resources = hypercontact_core::Resources::PARALLEL;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<IcmParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let profile: ProfileTable = inputs.read("profile")?;
        let patches: Vec<f64> = profile.patches.iter().map(|&n| n as f64).collect();
        let nominal_area_m2 =
            nominal_area(&profile.area_fraction, &profile.area_m2).map_err(StageError::other)?;

        let modulus = (p.law)
            .modulus_from_table(inputs.table("material")?, ctx)
            .map_err(|e| StageError::other(IcmError::Material(e)))?;
        let slices = ProfileSlices {
            z_m: &profile.z_m,
            area_m2: &profile.area_m2,
            patches: &patches,
            radius_m: &profile.radius_m,
        };
        let (modulus, solution) = respond(modulus, slices, p)?;
        let e0_star = modulus.e0_star_pa();
        let axes = BandAxes {
            area_fraction: &profile.area_fraction,
            e0_star_pa: e0_star,
            nominal_area_m2,
        };
        let bands = replicate_bands(
            wired_replicates(inputs)?,
            &p.law,
            axes,
            &|modulus| solved_load(slices, p, modulus),
            ctx,
        );
        let curve = Curve {
            z_m: profile.z_m,
            area_fraction: profile.area_fraction,
            area_m2: profile.area_m2,
            load_n: solution.load_n,
            modulus_pa: solution.modulus_pa,
        };
        let response = ResponseTable::from_curve(curve, e0_star, nominal_area_m2);
        Ok(Outputs::new()
            .table("response", response.into_table())
            .table("bands", bands.into_table()))
    }
}

/// One material's law and its solution over the profile, or why not.
type Solved = Result<(CompositeModulus, Solution), StageError>;

/// One material's solve over the profile under its law.
fn respond(modulus: CompositeModulus, slices: ProfileSlices<'_>, p: &IcmParams) -> Solved {
    let solution = solve(slices, p.law.scheme, &mut |s| {
        modulus.at_stress_pa(s).map_err(|e| e.to_string())
    })
    .map_err(|e| StageError::other(IcmError::Solve(e)))?;
    Ok((modulus, solution))
}

/// The ICM's loads and moduli over the profile under one law, for a
/// replicate's band.
fn solved_load(
    slices: ProfileSlices<'_>,
    p: &IcmParams,
    modulus: &CompositeModulus,
) -> Result<TangentLoad, String> {
    let solution = solve(slices, p.law.scheme, &mut |s| {
        modulus.at_stress_pa(s).map_err(|e| e.to_string())
    })
    .map_err(|e| e.to_string())?;
    Ok(TangentLoad {
        load_n: solution.load_n,
        modulus_pa: solution.modulus_pa,
    })
}

/// A0 = A / (A/A0) from the row of largest area fraction, checked against
/// every other row with contact.
fn nominal_area(area_fraction: &[f64], area_m2: &[f64]) -> Result<f64, IcmError> {
    let (best, &fraction) = area_fraction
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .ok_or(IcmError::Profile("the profile has no rows".into()))?;
    if !(fraction > 0.0 && fraction.is_finite()) {
        return Err(IcmError::Profile(format!(
            "no row has a positive area_fraction (largest: {fraction}), so A0 is unknown"
        )));
    }
    let a0 = area_m2[best] / fraction;
    for (k, (&f, &a)) in area_fraction.iter().zip(area_m2).enumerate() {
        if f > 0.0 && ((a / f) / a0 - 1.0).abs() > 1e-9 {
            return Err(IcmError::Profile(format!(
                "row {k}: area_m2 / area_fraction = {:.6e} m² but row {best} gives A0 = \
                 {a0:.6e} m²",
                a / f
            )));
        }
    }
    Ok(a0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{Params, Product, Table};
    use hypercontact_material::presets::paper_epdm;
    use hypercontact_material::table::to_table;
    use hypercontact_material::{Hyperelastic, Poisson};

    fn inputs(profile: Table) -> Inputs {
        Inputs::new()
            .with("profile", Product::Table(profile))
            .with("material", Product::Table(to_table(&paper_epdm())))
    }

    fn defaults() -> Checked<IcmParams> {
        IcmParams::default().check().unwrap()
    }

    fn response(out: &Outputs) -> &Table {
        match out.get("response") {
            Some(Product::Table(t)) => t,
            _ => panic!("no response table"),
        }
    }

    /// Two planes on a 10 µm flat punch of radius 100 µm in a 1 mm² map.
    fn punch_profile() -> Table {
        let a_m = 1e-4;
        let area = std::f64::consts::PI * a_m * a_m;
        Table::new()
            .with("z_m", vec![1e-5, 5e-6, 0.0])
            .with("z_over_sigma", vec![2.0, 1.0, 0.0])
            .with("area_fraction", vec![area / 1e-6, area / 1e-6, 1.0])
            .with("patches", vec![1_i64, 1, 1])
            .with(
                "radius_m",
                vec![a_m, a_m, (1e-6 / std::f64::consts::PI).sqrt()],
            )
            .with("area_m2", vec![area, area, 1e-6])
    }

    #[test]
    fn linear_response_is_sneddons_and_normalised_by_e0_star_a0() {
        let params: IcmParams =
            serde_json::from_str(r#"{"model": "linear", "scheme": "euler"}"#).unwrap();
        let params = params.check().unwrap();
        let out = Icm
            .run(&params, &inputs(punch_profile()), &Context::new("t"))
            .unwrap();
        let t = response(&out);
        t.validate().unwrap();
        t.conform(ResponseTable::COLUMNS).unwrap();
        let names: Vec<&str> = ResponseTable::COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(t.column_names(), names);
        let e0_star =
            hypercontact_material::composite_modulus_pa(paper_epdm().shear_modulus_pa(), 0.5);
        let load = t.f64("load_n").unwrap();
        let exact = 2.0 * e0_star * 1e-4 * 5e-6;
        assert!(
            (load[1] / exact - 1.0).abs() < 1e-12,
            "{} vs {exact}",
            load[1]
        );
        let norm = t.f64("load_norm").unwrap();
        assert!((norm[1] / (exact / (e0_star * 1e-6)) - 1.0).abs() < 1e-12);
        assert_eq!(t.f64("tangent_ratio").unwrap(), &[1.0, 1.0, 1.0]);
        let stress = t.f64("mean_stress_pa").unwrap();
        assert!((stress[1] / (exact / (std::f64::consts::PI * 1e-8)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn hyperelastic_response_starts_at_twice_e0_star() {
        let out = Icm
            .run(&defaults(), &inputs(punch_profile()), &Context::new("t"))
            .unwrap();
        let ratio = response(&out).f64("tangent_ratio").unwrap().to_vec();
        assert!((ratio[0] - 2.0).abs() < 1e-9, "{ratio:?}");
        assert!(ratio[1] > ratio[0], "{ratio:?}");
    }

    #[test]
    fn stress_beyond_the_material_range_names_the_level() {
        // A tiny area under a huge stiffness: S far beyond φ's range.
        let profile = Table::new()
            .with("z_m", vec![1e-5, 0.0])
            .with("z_over_sigma", vec![1.0, 0.0])
            .with("area_fraction", vec![1.0, 1.0])
            .with("patches", vec![1_i64, 1])
            .with("radius_m", vec![1.0, 1.0])
            .with("area_m2", vec![1e-12, 1e-12]);
        let e = Icm
            .run(&defaults(), &inputs(profile), &Context::new("t"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("level 1") && e.contains("z = 0") && e.contains("Pa"),
            "{e}"
        );
    }

    #[test]
    fn bad_inputs_and_params_are_named() {
        let p = IcmParams {
            law: LawParams {
                poisson: Poisson(0.6),
                ..Default::default()
            },
        };
        assert_eq!(p.check().unwrap_err().param, "poisson");
        let e = serde_json::from_str::<IcmParams>(r#"{"scheme": "rk4"}"#).unwrap_err();
        assert!(e.to_string().contains("rk4"), "{e}");
        let no_radius = Table::new()
            .with("z_m", vec![1.0])
            .with("z_over_sigma", vec![1.0]);
        let e = Icm
            .run(&defaults(), &inputs(no_radius), &Context::new("t"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("profile") && e.contains("area_fraction"), "{e}");
        // Row 2 (A/A0 = 1) gives A0 = 2 m²; row 1 implies 2 / 0.5 = 4 m².
        let rows = Table::new()
            .with("z_m", vec![1e-5, 5e-6, 0.0])
            .with("z_over_sigma", vec![2.0, 1.0, 0.0])
            .with("area_fraction", vec![0.5, 0.5, 1.0])
            .with("patches", vec![1_i64, 1, 1])
            .with("radius_m", vec![1.0, 1.0, 1.0])
            .with("area_m2", vec![1.0, 2.0, 2.0]);
        let e = Icm
            .run(&defaults(), &inputs(rows), &Context::new("t"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 1") && e.contains("A0"), "{e}");
    }
}
