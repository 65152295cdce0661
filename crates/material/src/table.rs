//! The `material` table: how a fitted, preset or given material travels
//! between stages. One row per parameter: `model` (family), `param`, `value`
//! (SI). A hyperelastic model writes its own parameters; a linear solid
//! (family `linear`) writes `e` (Pa) and `poisson` (1).

use hypercontact_core::{Schema, Table};

use crate::material::{LinearElastic, Material};
use crate::{
    ArrudaBoyce, Hyperelastic, MaterialError, MooneyRivlin, NeoHookean, Ogden, Parameter, Yeoh,
};

/// The `material` table, one row per parameter.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct MaterialTable {
    /// model family: ogden, neo-hookean, mooney-rivlin, yeoh, arruda-boyce, linear
    pub model: Vec<String>,
    /// parameter name (mu_1, alpha_1, c10, ...)
    pub param: Vec<String>,
    /// parameter value in SI units (moduli in Pa)
    #[column(unit = "Pa or 1")]
    pub value: Vec<f64>,
}

/// A model's rows of the `material` table: family, parameter name, value.
pub(crate) fn parameter_rows(model: &dyn Hyperelastic) -> (Vec<String>, Vec<String>, Vec<f64>) {
    let params = model.parameters();
    (
        vec![model.family().to_owned(); params.len()],
        params.iter().map(Parameter::name).collect(),
        params.iter().map(|p| p.value).collect(),
    )
}

/// Writes a model as a `material` table.
pub fn to_table(model: &dyn Hyperelastic) -> Table {
    let (model, param, value) = parameter_rows(model);
    MaterialTable {
        model,
        param,
        value,
    }
    .into_table()
}

/// Writes any material (a linear solid too) as a `material` table.
pub fn material_to_table(material: &Material) -> Table {
    let params = material.parameters();
    MaterialTable {
        model: vec![material.family().to_owned(); params.len()],
        param: params.iter().map(Parameter::name).collect(),
        value: params.iter().map(|p| p.value).collect(),
    }
    .into_table()
}

/// Reads a hyperelastic model back from a `material` table: for the steps
/// that need a strain energy (the report's material page, the bootstrap); a
/// linear solid is refused, saying so.
pub fn from_table(table: &Table) -> Result<Box<dyn Hyperelastic>, MaterialError> {
    let MaterialTable {
        model: models,
        param: names,
        value: values,
    } = MaterialTable::from_table(table).map_err(|e| MaterialError::Table(e.to_string()))?;
    from_parts(&models, &names, &values)
}

/// Reads whatever a `material` table holds: what the contact stages read.
pub fn material_from_table(table: &Table) -> Result<Material, MaterialError> {
    let MaterialTable {
        model: models,
        param: names,
        value: values,
    } = MaterialTable::from_table(table).map_err(|e| MaterialError::Table(e.to_string()))?;
    if models.first().map(String::as_str) == Some(LinearElastic::FAMILY) {
        let (e_pa, poisson) = linear_parts(&models, &names, &values)?;
        return Ok(Material::Linear(LinearElastic::new(e_pa, poisson)?));
    }
    from_parts(&models, &names, &values).map(Material::from)
}

/// E and ν of a `linear` table's rows, each exactly once and nothing else.
fn linear_parts(
    models: &[String],
    names: &[String],
    values: &[f64],
) -> Result<(f64, f64), MaterialError> {
    if let Some(other) = models.iter().find(|m| *m != LinearElastic::FAMILY) {
        return Err(MaterialError::Table(format!(
            "one table holds two models, `linear` and `{other}`"
        )));
    }
    if let Some(extra) = names
        .iter()
        .find(|n| !["e", "poisson"].contains(&n.as_str()))
    {
        return Err(MaterialError::Table(format!(
            "`linear` takes parameters `e` and `poisson`, not `{extra}`"
        )));
    }
    let get = |name: &str| -> Result<f64, MaterialError> {
        let mut given = (names.iter().zip(values)).filter(|(n, _)| *n == name);
        match (given.next(), given.next()) {
            (Some((_, value)), None) => Ok(*value),
            (None, _) => Err(MaterialError::Table(format!(
                "`linear` needs parameter `{name}`"
            ))),
            (Some(_), Some(_)) => Err(MaterialError::Table(format!(
                "`linear` lists parameter `{name}` more than once"
            ))),
        }
    };
    Ok((get("e")?, get("poisson")?))
}

/// A model from the `material` table's columns.
pub(crate) fn from_parts(
    models: &[String],
    names: &[String],
    values: &[f64],
) -> Result<Box<dyn Hyperelastic>, MaterialError> {
    let family = models
        .first()
        .ok_or_else(|| MaterialError::Table("the material table is empty".into()))?;
    if let Some(other) = models.iter().find(|m| *m != family) {
        return Err(MaterialError::Table(format!(
            "one table holds two models, `{family}` and `{other}`"
        )));
    }
    let get = |name: &str| -> Result<f64, MaterialError> {
        names
            .iter()
            .position(|n| n == name)
            .map(|i| values[i])
            .ok_or_else(|| MaterialError::Table(format!("`{family}` needs parameter `{name}`")))
    };
    match family.as_str() {
        "ogden" => {
            let n = names.iter().filter(|n| n.starts_with("mu_")).count();
            let mu = (1..=n)
                .map(|i| get(&format!("mu_{i}")))
                .collect::<Result<_, _>>()?;
            let alpha = (1..=n)
                .map(|i| get(&format!("alpha_{i}")))
                .collect::<Result<_, _>>()?;
            Ok(Box::new(Ogden::new(mu, alpha)?))
        }
        "neo-hookean" => Ok(Box::new(NeoHookean::new(get("c10")?)?)),
        "mooney-rivlin" => Ok(Box::new(MooneyRivlin::new(get("c10")?, get("c01")?)?)),
        "yeoh" => Ok(Box::new(Yeoh::new(get("c10")?, get("c20")?, get("c30")?)?)),
        "arruda-boyce" => Ok(Box::new(ArrudaBoyce::new(get("mu")?, get("lambda_m")?)?)),
        LinearElastic::FAMILY => Err(MaterialError::Table(format!(
            "the material is a linear solid (E = {:e} Pa, ν = {}), not a hyperelastic model: this \
             step needs a strain energy (a preset, a fit, or `material` with a hyperelastic \
             family)",
            get("e")?,
            get("poisson")?
        ))),
        other => Err(MaterialError::Table(format!(
            "unknown model family `{other}` (known: ogden, neo-hookean, mooney-rivlin, yeoh, \
             arruda-boyce, linear)"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mode;
    use crate::presets::paper_epdm;

    #[test]
    fn round_trip_keeps_the_model() {
        let m = paper_epdm();
        let back = from_table(&to_table(&m)).unwrap();
        for l in [0.6, 1.0, 1.4] {
            assert_eq!(
                back.nominal_stress_pa(Mode::Equibiaxial, l),
                m.nominal_stress_pa(Mode::Equibiaxial, l)
            );
        }
    }

    #[test]
    fn every_family_round_trips() {
        let models: Vec<Box<dyn Hyperelastic>> = vec![
            Box::new(NeoHookean::new(0.2e6).unwrap()),
            Box::new(MooneyRivlin::new(0.2e6, 0.03e6).unwrap()),
            Box::new(Yeoh::new(0.2e6, -0.01e6, 0.001e6).unwrap()),
            Box::new(ArrudaBoyce::new(0.3e6, 2.7).unwrap()),
        ];
        for m in models {
            let back = from_table(&to_table(m.as_ref())).unwrap();
            assert_eq!(back.family(), m.family());
            assert_eq!(back.parameters(), m.parameters());
        }
    }

    #[test]
    fn unknown_family_is_named() {
        let t = Table::new()
            .with("model", vec!["gent"])
            .with("param", vec!["mu"])
            .with("value", vec![1.0e6]);
        let e = from_table(&t).unwrap_err().to_string();
        assert!(e.contains("`gent`") && e.contains("yeoh"), "{e}");
    }

    #[test]
    fn missing_parameter_is_named() {
        let t = Table::new()
            .with("model", vec!["ogden"])
            .with("param", vec!["mu_1"])
            .with("value", vec![1.0e6]);
        let e = from_table(&t).unwrap_err().to_string();
        assert!(e.contains("alpha_1"), "{e}");
    }
}
