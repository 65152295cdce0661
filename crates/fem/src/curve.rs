//! The load–area curve: approach-controlled steps from first touch, with
//! the contact maps and the deformed state kept at requested area
//! fractions.

use crate::FemError;
use crate::contact::{ContactProblem, Step};

/// What to solve.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct CurveOptions {
    /// Approaches of the plane since first touch, increasing, m.
    pub approaches_m: Vec<f64>,
    /// Keep maps and displacements at the first step whose area fraction
    /// reaches each of these.
    pub snapshot_area_fractions: Vec<f64>,
    /// Stop after the first step whose area fraction reaches this.
    pub stop_at_area_fraction: Option<f64>,
}

impl CurveOptions {
    /// `steps` equal increments up to `final_approach_m`.
    pub fn uniform(final_approach_m: f64, steps: usize) -> Self {
        Self {
            approaches_m: (1..=steps)
                .map(|s| final_approach_m * s as f64 / steps as f64)
                .collect(),
            ..Default::default()
        }
    }
}

/// The state at one requested area fraction.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    pub requested_area_fraction: f64,
    /// Index into [`Curve::steps`].
    pub step: usize,
    /// Nodal displacements, m.
    pub displacement_m: Vec<[f64; 3]>,
    /// Contact pressure per map point (i * ny + j), Pa.
    pub pressure_pa: Vec<f64>,
    /// Contact per map point.
    pub contact: Vec<bool>,
}

/// The solved curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pub steps: Vec<Step>,
    pub snapshots: Vec<Snapshot>,
}

/// Solves every step of `options` on `problem` (which keeps the last state).
pub fn solve_curve(
    problem: &mut ContactProblem,
    options: &CurveOptions,
) -> Result<Curve, FemError> {
    check(options)?;
    let mut curve = Curve {
        steps: Vec::with_capacity(options.approaches_m.len()),
        snapshots: Vec::new(),
    };
    let mut wanted: Vec<f64> = options.snapshot_area_fractions.clone();
    for (index, &approach) in options.approaches_m.iter().enumerate() {
        let step = problem.solve_step(index + 1, approach)?;
        let fraction = step.area_fraction;
        curve.steps.push(step);
        keep_snapshots(
            problem,
            &mut wanted,
            (index, fraction),
            &mut curve.snapshots,
        );
        if options
            .stop_at_area_fraction
            .is_some_and(|stop| fraction >= stop)
        {
            break;
        }
    }
    Ok(curve)
}

/// Takes the fractions of `wanted` that step `step` (at A/A0 `fraction`)
/// reaches out of it, and keeps the problem's current state for each.
fn keep_snapshots(
    problem: &ContactProblem,
    wanted: &mut Vec<f64>,
    (step, fraction): (usize, f64),
    snapshots: &mut Vec<Snapshot>,
) {
    let (reached, rest): (Vec<f64>, Vec<f64>) = wanted.iter().partition(|f| fraction >= **f);
    *wanted = rest;
    for requested in reached {
        snapshots.push(Snapshot {
            requested_area_fraction: requested,
            step,
            displacement_m: problem.displacement_m(),
            pressure_pa: problem.pressure_map_pa(),
            contact: problem.contact_mask(),
        });
    }
}

fn check(options: &CurveOptions) -> Result<(), FemError> {
    let approaches = &options.approaches_m;
    if approaches.is_empty() {
        return Err(FemError::CurveOption {
            option: "approaches_m",
            message: "no steps".into(),
        });
    }
    let mut previous = 0.0;
    for (k, a) in approaches.iter().enumerate() {
        if !(a.is_finite() && *a > previous) {
            return Err(FemError::CurveOption {
                option: "approaches_m",
                message: format!(
                    "approach {} = {a:e} m must be finite, positive and above the previous \
                     ({previous:e} m)",
                    k + 1
                ),
            });
        }
        previous = *a;
    }
    if let Some(f) = options
        .snapshot_area_fractions
        .iter()
        .find(|f| !(0.0..=1.0).contains(*f))
    {
        return Err(FemError::CurveOption {
            option: "snapshot_area_fractions",
            message: format!("{f} is not an area fraction in [0, 1]"),
        });
    }
    Ok(())
}

/// Steps aimed at evenly spaced area fractions (the approach of each chosen
/// from the steps before), as the `fem` stage takes them.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaSteps {
    /// Steps aimed at A/A0 = k · max_area_fraction / steps, k = 1..=steps.
    pub steps: usize,
    /// The curve ends at the first step at or above this A/A0.
    pub max_area_fraction: f64,
    /// The approach of the first step, m (e.g. where the rigid plane's
    /// overlap with the undeformed surface covers the first target).
    pub first_approach_m: f64,
    /// Keep maps and displacements at the first step reaching each.
    pub snapshot_area_fractions: Vec<f64>,
    /// Steps allowed before the curve is refused (the aim can fall short
    /// where the area grows in jumps).
    pub max_steps: usize,
}

/// The next approach, aimed at `target`: A/A0 taken as a power of the
/// approach, A ∝ d^β, with β from the first and the last state (one
/// node-counted jump then bends the aim only a little), the increment kept
/// within 1/4 and 2 times the last one (a larger one can take in so many
/// nodes at once that the active set cycles).
fn next_approach(first: (f64, f64), last: (f64, f64), increment: f64, target: f64) -> f64 {
    let ((d0, a0), (d1, a1)) = (first, last);
    let beta = if a0 > 0.0 && a1 > a0 && d1 > d0 {
        ((a1 / a0).ln() / (d1 / d0).ln()).clamp(0.25, 4.0)
    } else {
        1.0
    };
    let aimed = if a1 > 0.0 && target > a1 {
        d1 * (target / a1).powf(1.0 / beta) - d1
    } else {
        2.0 * increment
    };
    d1 + aimed.clamp(0.25 * increment, 2.0 * increment)
}

/// Solves from first touch up to `options.max_area_fraction`, calling
/// `on_step` after every converged step (for progress).
pub fn solve_area_steps(
    problem: &mut ContactProblem,
    options: &AreaSteps,
    on_step: &mut dyn FnMut(&Step),
) -> Result<Curve, FemError> {
    check_area_steps(options)?;
    let mut curve = Curve {
        steps: Vec::new(),
        snapshots: Vec::new(),
    };
    let mut wanted = options.snapshot_area_fractions.clone();
    let spacing = options.max_area_fraction / options.steps as f64;
    let (mut first, mut last, mut increment) = ((0.0, 0.0), (0.0, 0.0), 0.0);
    while last.1 < options.max_area_fraction {
        let taken = curve.steps.len();
        if taken == options.max_steps {
            return Err(FemError::CurveOption {
                option: "steps",
                message: format!(
                    "{} steps reached A/A0 = {:.4} at approach {:.4e} m, short of \
                     max_area_fraction = {}",
                    options.max_steps, last.1, last.0, options.max_area_fraction
                ),
            });
        }
        // Step k aims at k · spacing whatever the steps before reached, so
        // the curve has about `steps` rows (after an overshoot, half a spacing
        // on); past the last, at the end.
        let target = ((taken + 1) as f64 * spacing)
            .max(last.1 + 0.5 * spacing)
            .min(options.max_area_fraction);
        let mut approach = if taken == 0 {
            options.first_approach_m
        } else {
            // From one state with contact β is a guess: at most double
            // the approach.
            let cap = if taken == 1 { last.0 } else { f64::INFINITY };
            next_approach(first, last, increment, target).min(last.0 + cap)
        };
        let mut step = problem.solve_step(taken + 1, approach)?;
        // A step that lands more than two spacings past its aim is solved
        // again at a third of its increment (three times at most), so the
        // curve resolves the areas it is read at. Frictionless elastic
        // contact has no history: stepping back solves the same problem.
        let mut wasted = 0;
        for _ in 0..3 {
            if step.area_fraction <= target + 2.0 * spacing {
                break;
            }
            wasted += step.iterations;
            approach = last.0 + (approach - last.0) / 3.0;
            step = problem.solve_step(taken + 1, approach)?;
        }
        step.iterations += wasted;
        on_step(&step);
        increment = approach - last.0;
        last = (approach, step.area_fraction);
        if first.1 == 0.0 {
            first = last;
        }
        let at = (curve.steps.len(), step.area_fraction);
        keep_snapshots(problem, &mut wanted, at, &mut curve.snapshots);
        curve.steps.push(step);
    }
    Ok(curve)
}

fn check_area_steps(options: &AreaSteps) -> Result<(), FemError> {
    let bad = |option, message: String| Err(FemError::CurveOption { option, message });
    if options.steps == 0 || options.max_steps < options.steps {
        return bad(
            "steps",
            format!(
                "{} steps with at most {} allowed",
                options.steps, options.max_steps
            ),
        );
    }
    if !(options.max_area_fraction > 0.0 && options.max_area_fraction <= 1.0) {
        return bad(
            "max_area_fraction",
            format!("{} is not in (0, 1]", options.max_area_fraction),
        );
    }
    if !(options.first_approach_m > 0.0 && options.first_approach_m.is_finite()) {
        return bad(
            "first_approach_m",
            format!(
                "{:e} m must be positive and finite",
                options.first_approach_m
            ),
        );
    }
    if let Some(f) = options
        .snapshot_area_fractions
        .iter()
        .find(|f| !(0.0..=1.0).contains(*f))
    {
        return bad(
            "snapshot_area_fractions",
            format!("{f} is not an area fraction in [0, 1]"),
        );
    }
    Ok(())
}

/// The approach at which the rigid plane, moved into the undeformed
/// surface, overlaps `area_fraction` of the map's points (the geometric
/// bearing ratio, an upper bound on the elastic contact area at that
/// approach), m. NaN heights never touch.
pub fn bearing_approach_m(heights_m: &[f64], area_fraction: f64) -> f64 {
    let mut sorted: Vec<f64> = heights_m.iter().copied().filter(|h| !h.is_nan()).collect();
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted.sort_by(|a, b| b.total_cmp(a));
    let n = heights_m.len() as f64;
    let index = ((area_fraction * n).ceil() as usize).clamp(1, sorted.len());
    sorted[0] - sorted[index - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_law_aims_and_is_bounded() {
        // A = d²: from (1, 1) and (2, 4) the target 9 is at 3.
        let d = next_approach((1.0, 1.0), (2.0, 4.0), 1.0, 9.0);
        assert!((d - 3.0).abs() < 1e-12, "{d}");
        // Only one state with contact: β = 1.
        assert_eq!(next_approach((0.0, 0.0), (2.0, 1.0), 2.0, 1.5), 3.0);
        // A target already passed doubles the increment.
        assert_eq!(next_approach((1.0, 1.0), (2.0, 4.0), 0.5, 3.0), 3.0);
        // Increments stay within ¼ and 2 times the last.
        assert_eq!(next_approach((1.0, 1.0), (2.0, 4.0), 0.1, 1e6), 2.2);
        assert_eq!(next_approach((1.0, 1.0), (2.0, 4.0), 1.0, 4.001), 2.25);
    }

    #[test]
    fn bearing_approach_counts_points_from_the_top() {
        let h = [5.0, 1.0, f64::NAN, 3.0, 4.0];
        // 2 of 5 points (40 %): the plane down to the second highest, 4.
        assert_eq!(bearing_approach_m(&h, 0.4), 1.0);
        assert_eq!(bearing_approach_m(&h, 0.01), 0.0);
        // More than the measured points: the lowest measured.
        assert_eq!(bearing_approach_m(&h, 1.0), 4.0);
    }
}
