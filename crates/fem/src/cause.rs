//! The likely cause of a failed solve, said after the solver's own error
//! (issue #50, item 2): a material whose tangent is not positive, a contact
//! area that stopped growing (the map cannot reach `max_area_fraction`), or
//! a first step too large for the first contact.

use hypercontact_material::Hyperelastic;
use hypercontact_material::constants::STABLE_STRETCHES;
use hypercontact_material::stability::stability_ranges;

use crate::FemError;

/// What the stage knows when its solve fails.
#[derive(Clone, Copy, Debug)]
pub struct Failure<'a> {
    /// (approach m, A/A0) of every converged step, in order.
    pub reached: &'a [(f64, f64)],
    /// Where the material is Drucker-unstable within the stretches
    /// contact reaches ([`unstable_stretches`]), if it is.
    pub unstable_material: Option<&'a str>,
    /// The stage's `steps`.
    pub steps: usize,
    pub max_area_fraction: f64,
}

/// Where `model` is Drucker-unstable (its tangent not positive) within
/// the stretches contact reaches ([`STABLE_STRETCHES`], over which the
/// `material` stage requires stability) in uniaxial, planar or equibiaxial
/// loading, if anywhere.
pub fn unstable_stretches(model: &dyn Hyperelastic) -> Option<String> {
    let (low, high) = STABLE_STRETCHES;
    stability_ranges(model).into_iter().find_map(|range| {
        let label = range.mode.label();
        if !range.stable_at_rest {
            Some(format!("{label} at rest"))
        } else if range.lambda_min > low {
            Some(format!("{label} below λ = {:.3}", range.lambda_min))
        } else if range.lambda_max < high {
            Some(format!("{label} above λ = {:.3}", range.lambda_max))
        } else {
            None
        }
    })
}

/// `error` with its likely cause appended, when one is recognised.
pub fn with_likely_cause(mut error: FemError, failure: &Failure) -> FemError {
    if let Some(cause) = likely_cause(&error, failure)
        && let FemError::NotConverged { detail, .. } | FemError::Solver(detail) = &mut error
    {
        detail.push_str(&format!("; likely cause: {cause}"));
    }
    error
}

fn likely_cause(error: &FemError, failure: &Failure) -> Option<String> {
    let failed_step = match error {
        FemError::NotConverged { step, .. } => *step,
        FemError::Solver(_) => failure.reached.len() + 1,
        _ => return None,
    };
    if let Some(unstable) = failure.unstable_material {
        return Some(format!(
            "an unstable material, its tangent not positive ({unstable}): fit it with the \
             stability constraint or take a stable model"
        ));
    }
    if let Some(stall) = stalled(failure) {
        return Some(stall);
    }
    (failed_step <= 2).then(|| {
        format!(
            "the step is too large for the first contact: raise `steps` (now {})",
            failure.steps
        )
    })
}

/// The contact area stalled from the first contact: the steps from the
/// first on that kept its A/A0, if there are two or more (a lone peak
/// above a flat: the approach doubles each step while one node touches,
/// until the plane meets the flat).
fn stalled(failure: &Failure) -> Option<String> {
    let (first, rest) = failure.reached.split_first()?;
    let run = rest.iter().take_while(|s| s.1 <= first.1).count();
    if run == 0 {
        return None;
    }
    let last_flat = rest[run - 1];
    let then = match rest.get(run) {
        Some(after) => format!(", then jumped to {:.4}", after.1),
        None => String::new(),
    };
    Some(format!(
        "the contact area stalled at A/A0 = {:.4} from approach {:.3e} to {:.3e} m ({} steps){then}: \
         this map's contact cannot grow steadily to max_area_fraction = {} (a lone peak above a \
         flat cannot); take a window where more of the surface touches",
        first.1,
        first.0,
        last_flat.0,
        run + 1,
        failure.max_area_fraction
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn not_converged(step: usize) -> FemError {
        FemError::NotConverged {
            step,
            approach_m: 1e-6,
            iterations: 30,
            residual_n: 1.0,
            tolerance_n: 1e-8,
            contact_nodes: 3,
            detail: String::new(),
        }
    }

    /// The constants stage's refused Yeoh law (C20 = −1e7 Pa) turns
    /// unstable inside the stretches contact reaches; the paper's EPDM
    /// does not.
    #[test]
    fn an_unstable_law_is_found() {
        let unstable = hypercontact_material::yeoh::Yeoh::new(5e5, -1e7, 0.0).unwrap();
        let said = unstable_stretches(&unstable).unwrap();
        assert!(said.contains(" λ = "), "{said}");
        let epdm = hypercontact_material::presets::paper_epdm();
        assert_eq!(unstable_stretches(&epdm), None);
    }

    #[test]
    fn each_cause_is_named_and_others_left_alone() {
        let failure = Failure {
            reached: &[],
            unstable_material: None,
            steps: 5,
            max_area_fraction: 0.3,
        };
        let said = with_likely_cause(not_converged(1), &failure).to_string();
        assert!(
            said.ends_with(
                "likely cause: the step is too large for the first contact: raise `steps` (now 5)"
            ),
            "{said}"
        );
        let flat = [(1e-6, 0.01), (2e-6, 0.01)];
        let saturated = Failure {
            reached: &flat,
            ..failure
        };
        let said = with_likely_cause(not_converged(3), &saturated).to_string();
        assert!(
            said.contains(
                "stalled at A/A0 = 0.0100 from approach 1.000e-6 to 2.000e-6 m (2 steps):"
            ) && said.contains("max_area_fraction = 0.3"),
            "{said}"
        );
        let unstable = Failure {
            unstable_material: Some("UT above λ = 1.200"),
            ..saturated
        };
        let said = with_likely_cause(FemError::Solver("not positive".into()), &unstable);
        assert!(said.to_string().contains("unstable material"), "{said}");
        let growing = [(1e-6, 0.01), (2e-6, 0.05), (3e-6, 0.1)];
        let later = Failure {
            reached: &growing,
            ..failure
        };
        assert_eq!(
            with_likely_cause(not_converged(4), &later),
            not_converged(4)
        );
    }
}
