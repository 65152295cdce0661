//! The `material` table: how a fitted or preset model travels between
//! stages. One row per parameter: `model` (family), `param`, `value` (SI).

use hypercontact_core::{Schema, Table};

use crate::{
    ArrudaBoyce, Hyperelastic, MaterialError, MooneyRivlin, NeoHookean, Ogden, Parameter, Yeoh,
};

/// The `material` table, one row per parameter.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct MaterialTable {
    /// model family: ogden, neo-hookean, mooney-rivlin, yeoh, arruda-boyce
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

/// Reads a model back from a `material` table.
pub fn from_table(table: &Table) -> Result<Box<dyn Hyperelastic>, MaterialError> {
    let MaterialTable {
        model: models,
        param: names,
        value: values,
    } = MaterialTable::from_table(table).map_err(|e| MaterialError::Table(e.to_string()))?;
    from_parts(&models, &names, &values)
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
        other => Err(MaterialError::Table(format!(
            "unknown model family `{other}` (known: ogden, neo-hookean, mooney-rivlin, yeoh, \
             arruda-boyce)"
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
