//! Stage `material`: any material by its constants, as the `material` table
//! every contact stage reads ([`crate::constants`] says what each family's
//! parameters mean; [`crate::constants_file`] the parameter file).

use hypercontact_core::{
    Checked, Context, InputPath, Inputs, OutputSpec, Outputs, ParamError, Stage, StageError,
    StageInfo, params,
};

use crate::Poisson;
use crate::constants::{self, Constants, Given, NAMES, Numbers};
use crate::constants_file::ConstantsFile;
use crate::material::Material;
use crate::table::{MaterialTable, material_to_table};

/// Parameters of `material`: a family and its parameters, or a file.
#[params(check = check_constants)]
pub struct MaterialParams {
    /// the family (or give `file`): linear | neo-hookean | mooney-rivlin | yeoh | arruda-boyce | ogden
    pub family: Option<Constants>,
    /// Young's modulus E (linear)
    #[param(unit = "Pa", positive)]
    pub e_pa: Option<f64>,
    /// Poisson's ratio ν (linear; 0.5 when absent)
    pub poisson: Option<Poisson>,
    /// neo-hookean: the shear modulus μ0; arruda-boyce: μ; ogden: the list μ_i (Abaqus' convention, Σ μ_i = μ0)
    #[param(unit = "Pa", range = ..)]
    pub mu_pa: Option<Numbers>,
    /// ogden: the exponents α_i, one per μ_i, non-zero
    #[param(range = ..)]
    pub alpha: Option<Numbers>,
    /// mooney-rivlin, yeoh: C10
    #[param(unit = "Pa", range = ..)]
    pub c10_pa: Option<f64>,
    /// mooney-rivlin: C01
    #[param(unit = "Pa", range = ..)]
    pub c01_pa: Option<f64>,
    /// yeoh: C20
    #[param(unit = "Pa", range = ..)]
    pub c20_pa: Option<f64>,
    /// yeoh: C30
    #[param(unit = "Pa", range = ..)]
    pub c30_pa: Option<f64>,
    /// arruda-boyce: the locking stretch λm, > 1
    #[param(range = ..)]
    pub lambda_m: Option<f64>,
    /// a parameter file instead of the parameters above (lines `name, value[, value...]`, see the stage doc)
    pub file: Option<InputPath>,
}

impl Given for MaterialParams {
    fn get(&self, name: &str) -> Option<&[f64]> {
        match name {
            "e_pa" => one(&self.e_pa),
            "poisson" => self.poisson.as_ref().map(|p| std::slice::from_ref(&p.0)),
            "mu_pa" => self.mu_pa.as_ref().map(Numbers::values),
            "alpha" => self.alpha.as_ref().map(Numbers::values),
            "c10_pa" => one(&self.c10_pa),
            "c01_pa" => one(&self.c01_pa),
            "c20_pa" => one(&self.c20_pa),
            "c30_pa" => one(&self.c30_pa),
            "lambda_m" => one(&self.lambda_m),
            _ => None,
        }
    }
}

/// A single value as the slice [`Given`] hands out.
fn one(value: &Option<f64>) -> Option<&[f64]> {
    value.as_ref().map(std::slice::from_ref)
}

impl MaterialParams {
    /// The material these parameters give, the file read if there is one.
    pub fn material(&self) -> Result<Material, StageError> {
        match (&self.file, self.family) {
            (Some(file), _) => ConstantsFile::read(file),
            (None, Some(family)) => {
                constants::material(family, self).map_err(|e| StageError::invalid(e.to_string()))
            }
            (None, None) => Err(StageError::invalid(missing_family().to_string())),
        }
    }
}

fn missing_family() -> ParamError {
    ParamError::new(
        "family",
        "give a family and its parameters, or a parameter `file`",
    )
}

/// Either a file and nothing else, or a family and exactly its parameters.
fn check_constants(p: &MaterialParams) -> Result<(), ParamError> {
    if p.file.is_some() {
        let given = std::iter::once("family")
            .filter(|_| p.family.is_some())
            .chain(NAMES.into_iter().filter(|n| p.get(n).is_some()));
        return match given.into_iter().next() {
            Some(name) => Err(ParamError::new(
                name,
                "with `file`, every parameter comes from the file: give it there",
            )),
            None => Ok(()),
        };
    }
    let family = p.family.ok_or_else(missing_family)?;
    constants::material(family, p).map(drop)
}

/// The `material` stage.
pub struct MaterialConstants;

static INFO: StageInfo = StageInfo {
    kind: "material",
    version: 1,
    summary: "Any material by its constants (linear E, ν or a hyperelastic family) as the \
              material table",
    doc: "Writes the `material` table every contact stage reads (icm, bem, persson, \
          greenwood-williamson, synth-contact), from `family` and exactly its parameters \
          (any other is refused, naming it), moduli in Pa: `linear` e_pa, poisson (default \
          0.5); `neo-hookean` mu_pa (W = (mu/2)(I1 - 3), mu = mu0); `mooney-rivlin` c10_pa, \
          c01_pa (mu0 = 2 (C10 + C01) > 0); `yeoh` c10_pa > 0, c20_pa, c30_pa; `arruda-boyce` \
          mu_pa > 0, lambda_m > 1 (Abaqus' five-term series); `ogden` mu_pa and alpha, lists of \
          one length (Abaqus' W = sum 2 mu_i/alpha_i^2 (...), mu0 = sum mu_i > 0, alpha_i != \
          0). Or `file` alone: a text file of lines `name, value[, value...]` with the same \
          names (`family, ogden` / `mu_pa, 1.2e6, -2e5` / `alpha, 2, -2`), `#` comments and \
          blank lines skipped, each name once; errors name the file and line. Refused, naming \
          the parameter: a modulus term of size outside 1 Pa to 1e12 Pa (0 is allowed), and a \
          hyperelastic law that is Drucker-unstable anywhere in 0.7 <= lambda <= 1.5 in \
          uniaxial, planar or equibiaxial loading (Abaqus' check, as material-fit reports it; \
          the message says in which test and beyond which stretch). A `linear` \
          material is not hyperelastic: the contact stages use E* = E/(1 - nu^2) with its own \
          nu at every stress, whatever their `model`, `tangent` and `poisson` say (they note \
          it when these differ), so the hyperelastic and linear runs on it coincide. The \
          paper's EPDM stays the preset `material-preset`.",
    inputs: &[],
    outputs: &[OutputSpec::table::<MaterialTable>(
        "material",
        "the material: one row per parameter (model, param, value in SI); `linear` writes e \
         and poisson",
    )],
};

impl Stage for MaterialConstants {
    type Params = MaterialParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<MaterialParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let material = p.material()?;
        ctx.note(&summary(&material));
        Ok(Outputs::new().table("material", material_to_table(&material)))
    }
}

/// The small-strain moduli the contact stages will start from, in words.
fn summary(material: &Material) -> String {
    match material {
        Material::Linear(solid) => format!(
            "linear: E = {:.6e} Pa, ν = {}, E* = E/(1 − ν²) = {:.6e} Pa at every stress",
            solid.e_pa,
            solid.poisson,
            solid.composite_modulus_pa()
        ),
        Material::Hyperelastic(model) => {
            let mu0_pa = model.shear_modulus_pa();
            format!(
                "{}: μ0 = {mu0_pa:.6e} Pa, E0 = 3 μ0 = {:.6e} Pa (ν = ½)",
                model.family(),
                3.0 * mu0_pa
            )
        }
    }
}

#[cfg(test)]
mod tests;
