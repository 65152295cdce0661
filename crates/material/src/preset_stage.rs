//! Stage `material-preset`: a built-in material as the `material` table.

use hypercontact_core::{
    Checked, Context, Inputs, OutputSpec, Outputs, Stage, StageError, StageInfo, params,
};

use crate::presets::Preset;
use crate::table::{MaterialTable, to_table};

/// Parameters of `material-preset`.
#[params]
pub struct MaterialPresetParams {
    /// the preset
    #[param(default = Preset::PaperEpdm)]
    pub name: Preset,
}

/// The `material-preset` stage.
pub struct MaterialPreset;

static INFO: StageInfo = StageInfo {
    kind: "material-preset",
    version: 1,
    summary: "A built-in material (default: the paper's 6-term Ogden EPDM, Table 1)",
    doc: "`paper-epdm` is the paper's Table 1: a 6-term Ogden model in the Abaqus convention \
          W = Σ 2μ_i/α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3), μ0 = Σ μ_i = 1.79 MPa, \
          E0 = 3 μ0 = 5.37 MPa, E0* = E0/(1 − ν²) = 7.16 MPa. Sign convention for contact: the \
          contact stress is compressive, so the incremental contact model evaluates \
          ε = φ⁻¹(S) at S = −F/A < 0 (ε < 0), where the equibiaxial tangent E_t rises from \
          E_t(0) = 6 μ0 = 2 E0. Stability: with these parameters φ (the equibiaxial nominal \
          stress) peaks at ε ≈ 0.46 in tension and is not invertible beyond; it rises \
          monotonically in compression. Abaqus' Drucker check holds in equibiaxial tension up \
          to λ ≈ 4.4 and fails in equibiaxial compression below λ ≈ 0.56 (ε ≈ −0.44, stresses \
          below about −15 MPa); see `material-fit`'s `stability` table.",
    inputs: &[],
    outputs: &[OutputSpec::table::<MaterialTable>(
        "material",
        "the model: one row per parameter (model, param, value in SI)",
    )],
};

impl Stage for MaterialPreset {
    type Params = MaterialPresetParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<MaterialPresetParams>,
        _: &Inputs,
        _: &Context,
    ) -> Result<Outputs, StageError> {
        Ok(Outputs::new().table("material", to_table(p.name.model().as_ref())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params, Product, Schema};

    #[test]
    fn emits_the_paper_preset() {
        let p = MaterialPresetParams::default().check().unwrap();
        let out = MaterialPreset
            .run(&p, &Inputs::new(), &Context::new("t"))
            .unwrap();
        let Some(Product::Table(t)) = out.get("material") else {
            panic!("no material table")
        };
        t.conform(MaterialTable::COLUMNS).unwrap();
        let m = crate::table::from_table(t).unwrap();
        assert!((m.shear_modulus_pa() - 1.79e6).abs() < 0.005e6);
    }

    #[test]
    fn unknown_name_is_a_parameter_error() {
        let e = MaterialPreset
            .params_from_json(
                serde_json::json!({"name": "nitrile"}),
                std::path::Path::new("."),
            )
            .unwrap_err();
        assert_eq!(e.param, "name");
        assert!(e.message.contains("paper-epdm"), "{}", e.message);
    }
}
