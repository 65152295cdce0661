//! Table 1's material: the fitted parameters and the initial moduli μ0, E0
//! and E0* at the report's Poisson's ratio ν, and the checks that no other
//! E0* reaches the page: the one each response's `load_norm` = F/(E0* A0)
//! was divided by, and the one in the fit's `params` table.

use hypercontact_core::Table;
use hypercontact_material::fit_stage::ParamsTable;
use hypercontact_material::{Family, Parameter, composite_modulus_pa, youngs_modulus_pa};

use crate::ReportError;
use crate::gather::Response;

/// Relative difference above which two E0* (or two parameter values) are
/// different numbers: far above rounding (icm's A0 agrees across rows to
/// 1e-9), far below a change of ν worth a figure (E0* = 2 μ0 / (1 − ν), so
/// 1e-6 of E0* is under 1e-6 of ν).
const RTOL: f64 = 1e-6;

/// The fitted material as the `material` table holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSummary {
    /// The family as the table names it (`ogden`, `yeoh`, ...).
    pub model: String,
    /// In table order, each with its symbol, Ogden term and unit.
    pub parameters: Vec<Parameter>,
    /// Poisson's ratio ν of `e0_pa` and `e0_star_pa` (parameter `poisson`).
    pub poisson: f64,
    pub mu0_pa: f64,
    pub e0_pa: f64,
    pub e0_star_pa: f64,
}

/// Whether `a` and `b` are different numbers (NaN differs from everything).
fn differ(a: f64, b: f64) -> bool {
    let close = (a - b).abs() <= RTOL * a.abs().max(b.abs());
    !close
}

impl MaterialSummary {
    /// Decodes the `material` table; when the fit's `params` table is wired
    /// too, it must be that model's at the same ν, so the page shows one E0*.
    pub fn read(
        table: &Table,
        poisson: f64,
        params: Option<&ParamsTable>,
    ) -> Result<Self, ReportError> {
        let model = hypercontact_material::table::from_table(table)
            .map_err(|e| ReportError::Material(e.to_string()))?;
        let mu0_pa = model.shear_modulus_pa();
        if let Some(fit) = params.filter(|p| !p.model.is_empty()) {
            let family = Family::parse(&fit.model[0])
                .map_err(|e| ReportError::input("params", e.to_string()))?;
            let expected = ParamsTable::new(family, model.as_ref(), poisson);
            if expected.param != fit.param {
                return Err(ReportError::input(
                    "params",
                    format!(
                        "lists {:?}, but `material` at poisson = {poisson} gives {:?}: both \
                         must come from one fit",
                        fit.param, expected.param
                    ),
                ));
            }
            let rows = fit.value.iter().zip(&expected.value).enumerate();
            if let Some((row, (found, wanted))) =
                rows.into_iter().find(|(_, (f, w))| differ(**f, **w))
            {
                return Err(ReportError::input(
                    "params",
                    format!(
                        "row {row} `{}` is {found:e}, but `material` at the report's poisson = \
                         {poisson} gives {wanted:e}: give material-fit and the report the same \
                         poisson, and both the same fit",
                        fit.param[row]
                    ),
                ));
            }
        }
        Ok(MaterialSummary {
            model: model.family().to_owned(),
            parameters: model.parameters(),
            poisson,
            mu0_pa,
            e0_pa: youngs_modulus_pa(mu0_pa, poisson),
            e0_star_pa: composite_modulus_pa(mu0_pa, poisson),
        })
    }

    /// Checks that `response` (input `input`) plots F/(E0* A0) with this
    /// E0*, so Table 1 names the modulus behind Figs. 7 and 8.
    pub fn check_normalisation(&self, input: &str, response: &Response) -> Result<(), ReportError> {
        match response.e0_star_pa {
            Some(used) if differ(used, self.e0_star_pa) => Err(ReportError::input(
                input,
                format!(
                    "load_norm is F/(E0* A0) with E0* = {used:e} Pa (mean_stress_pa · \
                     area_fraction / load_norm), but Table 1 gives E0* = {:e} Pa at poisson = \
                     {}: set the report's `poisson` to that of the stage that wrote the response",
                    self.e0_star_pa, self.poisson
                ),
            )),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gather::read_response;
    use hypercontact_core::contact::ResponseTable;
    use hypercontact_material::table::to_table;
    use hypercontact_material::{Hyperelastic, Ogden};

    fn ogden() -> Ogden {
        Ogden::new(vec![1.0e6, 0.5e6], vec![2.0, -2.0]).unwrap()
    }

    #[test]
    fn material_gives_the_initial_moduli() {
        let t = Table::new()
            .with("model", vec!["ogden"; 4])
            .with("param", vec!["mu_1", "alpha_1", "mu_2", "alpha_2"])
            .with("value", vec![1.0e6, 2.0, 0.5e6, -2.0]);
        let m = MaterialSummary::read(&t, 0.5, None).unwrap();
        assert_eq!(m.mu0_pa, 1.5e6);
        assert!((m.e0_pa - 4.5e6).abs() < 1e-6);
        assert!((m.e0_star_pa - 6.0e6).abs() < 1e-6);
        assert_eq!(m.parameters, ogden().parameters());
        // E0* = 2 μ0 / (1 − ν): 6 MPa at ν = ½, 5 MPa at ν = 0.4.
        let m = MaterialSummary::read(&t, 0.4, None).unwrap();
        assert!((m.e0_star_pa - 5.0e6).abs() < 1e-6, "{}", m.e0_star_pa);
    }

    /// A response normalised by `e0_star_pa`, A0 = 2 m²: an unloaded row and a loaded one.
    fn response(e0_star_pa: f64) -> Response {
        let (a0, a, f) = (2.0, vec![0.1, 0.4], vec![0.0, 3.0e5]);
        let table = ResponseTable {
            z_m: vec![1.0, 0.0],
            load_norm: f.iter().map(|f| f / (e0_star_pa * a0)).collect(),
            mean_stress_pa: f.iter().zip(&a).map(|(f, a)| f / (a * a0)).collect(),
            tangent_ratio: vec![1.0; 2],
            area_fraction: a,
            load_n: f,
        };
        read_response("responses.T3", table).unwrap()
    }

    #[test]
    fn a_response_normalised_at_another_poisson_is_named() {
        let table = to_table(&ogden());
        let mu0 = ogden().shear_modulus_pa();
        let at_half = MaterialSummary::read(&table, 0.5, None).unwrap();
        let icm_045 = response(composite_modulus_pa(mu0, 0.45));
        assert!(
            (icm_045.e0_star_pa.unwrap() / composite_modulus_pa(mu0, 0.45) - 1.0).abs() < 1e-12
        );
        let e = at_half
            .check_normalisation("responses.T3", &icm_045)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("responses.T3") && e.contains("poisson = 0.5") && e.contains("`poisson`"),
            "{e}"
        );
        let at_045 = MaterialSummary::read(&table, 0.45, None).unwrap();
        at_045
            .check_normalisation("responses.T3", &icm_045)
            .unwrap();
        at_half
            .check_normalisation("responses.T3", &response(at_half.e0_star_pa))
            .unwrap();
    }

    #[test]
    fn params_of_another_poisson_or_model_are_named() {
        let table = to_table(&ogden());
        let fit = |poisson| ParamsTable::new(Family::Ogden(2), &ogden(), poisson);
        MaterialSummary::read(&table, 0.45, Some(&fit(0.45))).unwrap();
        let e = MaterialSummary::read(&table, 0.5, Some(&fit(0.45)))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("params") && e.contains("`e0`") && e.contains("poisson = 0.5"),
            "{e}"
        );
        let other = Ogden::new(vec![1.0e6], vec![2.0]).unwrap();
        let e = MaterialSummary::read(
            &table,
            0.5,
            Some(&ParamsTable::new(Family::Ogden(1), &other, 0.5)),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("params") && e.contains("one fit"), "{e}");
    }
}
