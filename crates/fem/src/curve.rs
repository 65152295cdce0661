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
        let (reached, rest): (Vec<f64>, Vec<f64>) = wanted.iter().partition(|f| fraction >= **f);
        wanted = rest;
        for requested in reached {
            curve.snapshots.push(Snapshot {
                requested_area_fraction: requested,
                step: index,
                displacement_m: problem.displacement_m(),
                pressure_pa: problem.pressure_map_pa(),
                contact: problem.contact_mask(),
            });
        }
        if options
            .stop_at_area_fraction
            .is_some_and(|stop| fraction >= stop)
        {
            break;
        }
    }
    Ok(curve)
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
