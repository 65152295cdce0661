//! Table 1's material: the fitted parameters and the initial moduli μ0, E0
//! and E0* at the report's Poisson's ratio ν, and the checks that no other
//! E0* reaches the page: the one each response's `load_norm` = F/(E0* A0)
//! was divided by, and the one in the fit's `params` table. Also what
//! Table 1 says about the fit beside the numbers: each parameter's 5–95 %
//! bootstrap interval (`params`) and the objective with and without the
//! stability constraint (`comparison`).

use hypercontact_core::Table;
use hypercontact_material::fit_stage::{ComparisonTable, ParamsTable};
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
    /// (parameter name as `params` writes it, p05, p95) of every row of
    /// the wired `params` whose bootstrap interval is finite.
    pub intervals: Vec<(String, f64, f64)>,
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
        let mut intervals = Vec::new();
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
            intervals = (0..fit.param.len())
                .filter(|&i| fit.p05[i].is_finite() && fit.p95[i].is_finite())
                .map(|i| (fit.param[i].clone(), fit.p05[i], fit.p95[i]))
                .collect();
        }
        Ok(MaterialSummary {
            model: model.family().to_owned(),
            parameters: model.parameters(),
            poisson,
            mu0_pa,
            e0_pa: youngs_modulus_pa(mu0_pa, poisson),
            e0_star_pa: composite_modulus_pa(mu0_pa, poisson),
            intervals,
        })
    }

    /// The 5–95 % bootstrap interval (p05, p95) of parameter `name`
    /// (`mu_1`, `alpha_2`, `mu0`, `e0`, `e0_star`, ...), when `params`
    /// carries a finite one.
    pub fn interval(&self, name: &str) -> Option<(f64, f64)> {
        self.intervals
            .iter()
            .find(|(n, _, _)| n == name)
            .map(|&(_, lo, hi)| (lo, hi))
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

/// One row of the `comparison` table: a family under one setting of the
/// constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct FitSetting {
    /// `stable` or `none`, as material-fit's `constraint` names them.
    pub constraint: String,
    /// RMS relative error over all points (NaN when the fit failed).
    pub rms_rel_err: f64,
    pub condition_number: f64,
    /// `ok`, or why the family could not be fitted.
    pub status: String,
}

/// The fit Table 1 shows (the `selected` row of `comparison`) and the same
/// family under the other setting of the constraint, so the page states
/// the objective both ways.
#[derive(Clone, Debug, PartialEq)]
pub struct FitChoice {
    /// The family as `comparison` names it (`ogden-6`).
    pub model: String,
    pub chosen: FitSetting,
    pub other: Option<FitSetting>,
}

impl FitChoice {
    /// `None` when no row is selected (a hand-made table).
    pub fn read(c: &ComparisonTable) -> Option<Self> {
        let setting = |i: usize| FitSetting {
            constraint: c.constraint[i].clone(),
            rms_rel_err: c.rms_rel_err[i],
            condition_number: c.condition_number[i],
            status: c.status[i].clone(),
        };
        let chosen = c.selected.iter().position(|&s| s == 1)?;
        let model = c.model[chosen].clone();
        let other = (0..c.model.len())
            .find(|&i| c.model[i] == model && c.constraint[i] != c.constraint[chosen])
            .map(setting);
        Some(FitChoice {
            model,
            chosen: setting(chosen),
            other,
        })
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

    #[test]
    fn finite_bootstrap_intervals_are_kept_by_parameter_name() {
        let table = to_table(&ogden());
        let mut fit = ParamsTable::new(Family::Ogden(2), &ogden(), 0.5);
        // mu_1, alpha_1, mu_2, alpha_2, mu0, e0, e0_star: an interval on
        // α_2 and E0* only.
        let alpha_2 = fit.param.iter().position(|p| p == "alpha_2").unwrap();
        let e0_star = fit.param.iter().position(|p| p == "e0_star").unwrap();
        fit.p05[alpha_2] = -2.2;
        fit.p95[alpha_2] = -1.8;
        fit.p05[e0_star] = 5.5e6;
        fit.p95[e0_star] = f64::INFINITY;
        let m = MaterialSummary::read(&table, 0.5, Some(&fit)).unwrap();
        assert_eq!(m.interval("alpha_2"), Some((-2.2, -1.8)));
        assert_eq!(m.interval("e0_star"), None);
        assert_eq!(m.interval("mu_1"), None);
        assert_eq!(m.intervals.len(), 1);
    }

    #[test]
    fn the_fit_choice_is_the_selected_row_and_its_family_under_the_other_setting() {
        let rows = [
            ("yeoh", "none", 0.010, 0),
            ("ogden-3", "none", 0.005, 0),
            ("ogden-3", "stable", 0.020, 1),
            ("yeoh", "stable", 0.030, 0),
        ];
        let nan = vec![f64::NAN; rows.len()];
        let c = ComparisonTable {
            rank: (1..=rows.len() as i64).collect(),
            model: rows.iter().map(|r| r.0.to_owned()).collect(),
            constraint: rows.iter().map(|r| r.1.to_owned()).collect(),
            n_params: vec![6; rows.len()],
            free_params: vec![6; rows.len()],
            condition_number: vec![2.0, 7e6, 3.0, 4.0],
            rms_rel_err: rows.iter().map(|r| r.2).collect(),
            max_rel_err: nan.clone(),
            ut_rms_rel_err: nan.clone(),
            pt_rms_rel_err: nan.clone(),
            bt_rms_rel_err: nan.clone(),
            ut_lambda_min: nan.clone(),
            ut_lambda_max: nan.clone(),
            pt_lambda_min: nan.clone(),
            pt_lambda_max: nan.clone(),
            bt_lambda_min: nan.clone(),
            bt_lambda_max: nan,
            selected: rows.iter().map(|r| r.3).collect(),
            status: vec!["ok".into(); rows.len()],
        };
        let choice = FitChoice::read(&c).unwrap();
        assert_eq!(choice.model, "ogden-3");
        assert_eq!(choice.chosen.constraint, "stable");
        assert_eq!(choice.chosen.rms_rel_err, 0.020);
        assert_eq!(choice.chosen.condition_number, 3.0);
        let other = choice.other.unwrap();
        assert_eq!(
            (other.constraint.as_str(), other.rms_rel_err),
            ("none", 0.005)
        );
        assert_eq!(other.condition_number, 7e6);
        let none_selected = ComparisonTable {
            selected: vec![0; 4],
            ..c
        };
        assert_eq!(FitChoice::read(&none_selected), None);
    }
}
