//! The load–area curve of a rough surface: solves from first contact up to a
//! top area fraction, at rigid-plane approaches chosen so that A/A0 is
//! spaced about evenly (each step lands within a quarter of the spacing of
//! its target k · max / steps, or as near as six solves get it). The last
//! step lands at or above the top area fraction (within a quarter of the
//! spacing above it), so a reader can interpolate anywhere up to it.
//!
//! The approach for a target is interpolated between the nearest solved
//! approaches below and above it, or extrapolated from the last two; the
//! first one is guessed from the bearing area (an elastic contact covers
//! about half the area the rigid plane cuts through), the second from the
//! share of it the first solve found. Every solve starts from the pressure
//! extrapolated from the previous two. The approaches only grow from step to
//! step, so the rows are ordered.
//!
//! A periodic map has no solution from the approach of full contact on
//! ([`Problem::full_contact_approach_m`]); a prediction there (the secant
//! doubles the approach where two solves found the same area, as happens
//! on a mirror-image map, whose contacts come in mirrored pairs) is moved
//! halfway from the largest solved approach to it instead.

use rayon::prelude::*;

use crate::polonsky_keer::{Control, Problem, Solution, SolveError, SolverOptions};

/// Solves per step before the nearest one is taken.
const MAX_SOLVES_PER_STEP: usize = 6;

/// What the curve spans and how each solve stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveOptions {
    /// Steps after first contact.
    pub steps: usize,
    /// A/A0 of the last step.
    pub max_area_fraction: f64,
    pub solver: SolverOptions,
}

/// One row of the curve, for E* = 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// The rigid plane's approach δ from first contact, m.
    pub approach_m: f64,
    /// Contact pixels / measured pixels.
    pub area_fraction: f64,
    pub contact_pixels: usize,
    /// Σ p / (measured points), in units of E*: F / (E* A0).
    pub mean_pressure: f64,
    /// Iterations of every solve spent on this step.
    pub iterations: usize,
    /// Solves spent on this step (the accepted one and the trials).
    pub solves: usize,
    /// Iterations of the accepted solve alone (the rest of `iterations`
    /// went into trials that were not kept).
    pub accepted_iterations: usize,
    /// The accepted solve's residual.
    pub residual: f64,
}

/// A step that could not be solved.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "step {step} of {steps} (approach {approach_m:.6e} m, target A/A0 = {target:.4}): {source}"
)]
pub struct CurveError {
    pub step: usize,
    pub steps: usize,
    pub approach_m: f64,
    pub target: f64,
    pub source: SolveError,
}

/// Solves the curve; `on_step(k, row, solution)` sees each accepted step
/// k = 1..=steps with its pressure and gap (row 0, first contact, has
/// none). Returns the rows, first contact first.
pub fn solve_curve(
    problem: &Problem,
    options: CurveOptions,
    on_step: &mut dyn FnMut(usize, &Step, &Solution),
) -> Result<Vec<Step>, CurveError> {
    let steps = options.steps.max(1);
    let spacing = options.max_area_fraction / steps as f64;
    let bearing = Bearing::new(problem.heights_m());
    let measured = problem.measured() as f64;

    let mut rows = vec![Step {
        approach_m: 0.0,
        area_fraction: 0.0,
        contact_pixels: 0,
        mean_pressure: 0.0,
        iterations: 0,
        solves: 0,
        accepted_iterations: 0,
        residual: 0.0,
    }];
    // Every (approach, area fraction) solved so far, by approach.
    let mut known: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    // The last two solves (approach, pressure), most recent last.
    let mut recent: Vec<(f64, Vec<f64>)> = Vec::with_capacity(2);
    for k in 1..=steps {
        // The last step aims at the middle of [max, max + spacing / 4].
        let last = k == steps;
        let (target, window) = if last {
            (options.max_area_fraction + 0.125 * spacing, 0.125 * spacing)
        } else {
            (spacing * k as f64, 0.25 * spacing)
        };
        let reaches = |fraction: f64| !last || fraction >= options.max_area_fraction;
        // Best so far: one that reaches the top (last step) before one that
        // misses the target by less.
        let mut best: Option<(Solution, (bool, f64))> = None;
        let (mut iterations, mut solves) = (0, 0);
        for _ in 0..MAX_SOLVES_PER_STEP * if last { 2 } else { 1 } {
            let approach_m = short_of_full_contact(
                predict(&known, target, &bearing),
                &known,
                problem.full_contact_approach_m(),
            );
            let warm = warm_start(&recent, approach_m);
            let solution = problem
                .solve(
                    Control::Approach(approach_m),
                    options.solver,
                    warm.as_deref(),
                )
                .map_err(|source| CurveError {
                    step: k,
                    steps,
                    approach_m,
                    target,
                    source,
                })?;
            iterations += solution.iterations;
            solves += 1;

            let fraction = solution.contact_pixels as f64 / measured;
            let at = known.partition_point(|&(d, _)| d < approach_m);
            known.insert(at, (approach_m, fraction));
            if recent.len() == 2 {
                let (_, mut oldest) = recent.remove(0);
                oldest.copy_from_slice(&solution.pressure);
                recent.push((approach_m, oldest));
            } else {
                recent.push((approach_m, solution.pressure.clone()));
            }
            let miss = (fraction - target).abs();
            let rank = (!reaches(fraction), miss);
            let done = miss <= window && reaches(fraction);
            if best.as_ref().is_none_or(|(_, r)| rank < *r) {
                best = Some((solution, rank));
            }
            if done {
                break;
            }
        }
        let (solution, _) = best.expect("at least one solve per step");
        let row = Step {
            approach_m: solution.approach_m,
            area_fraction: solution.contact_pixels as f64 / measured,
            contact_pixels: solution.contact_pixels,
            mean_pressure: solution.mean_pressure,
            iterations,
            solves,
            accepted_iterations: solution.iterations,
            residual: solution.residual,
        };
        on_step(k, &row, &solution);
        rows.push(row);
    }
    Ok(rows)
}

/// The start of a solve at `approach_m`: the pressure linearly extrapolated
/// (or interpolated) from the last two solves (`recent`: at most two
/// (approach, pressure), most recent last), clipped at zero; the last
/// solve alone when there is one; none at first. Starting from the last
/// pressure alone, the whole rim the plane newly overlaps enters contact in
/// the first iteration and the solver spends tens of iterations getting it
/// out again.
pub fn warm_start(recent: &[(f64, Vec<f64>)], approach_m: f64) -> Option<Vec<f64>> {
    match recent {
        [] => None,
        [(_, p)] => Some(p.clone()),
        [(d0, p0), (d1, p1)] => {
            let s = if d1 != d0 {
                ((approach_m - d1) / (d1 - d0)).clamp(-1.0, 2.0)
            } else {
                0.0
            };
            let mut guess = p1.clone();
            guess
                .par_iter_mut()
                .zip(p0)
                .for_each(|(p, &p0)| *p = (*p + s * (*p - p0)).max(0.0));
            Some(guess)
        }
        _ => unreachable!("two solves are kept"),
    }
}

/// The next approach to try for `target`, from the solved points (sorted by
/// approach, first (0, 0)).
fn predict(known: &[(f64, f64)], target: f64, bearing: &Bearing) -> f64 {
    let below = known.iter().rev().find(|&&(_, a)| a < target);
    let above = known.iter().find(|&&(_, a)| a > target);
    match (below, above) {
        (Some(&(d0, a0)), Some(&(d1, a1))) => d0 + (d1 - d0) * (target - a0) / (a1 - a0),
        _ if known.len() < 2 => bearing.approach_m((2.0 * target).min(1.0)),
        // One solve, below the target: the elastic area as the same share
        // of the bearing area as there (near the top neither is linear in
        // the approach, so a secant through first contact overshoots).
        (Some(&(d1, a1)), None) if known.len() == 2 && a1 > 0.0 => {
            let share = a1 / bearing.fraction(d1);
            bearing
                .approach_m((target / share).min(1.0))
                .max(d1 * 1.0001)
        }
        _ => {
            // Beyond the last point: the secant of the last two, at most
            // doubling the approach; flat there → double it.
            let (d1, a1) = known[known.len() - 1];
            let (d0, a0) = known[known.len() - 2];
            let secant = if a1 > a0 {
                d1 + (d1 - d0) * (target - a1) / (a1 - a0)
            } else {
                f64::INFINITY
            };
            secant.clamp(d1 * 1.0001, 2.0 * d1)
        }
    }
}

/// `approach_m`, or, if it reaches the approach of full contact
/// `limit_m`, halfway from the largest solved approach (the last of
/// `known`, sorted) to it.
fn short_of_full_contact(approach_m: f64, known: &[(f64, f64)], limit_m: Option<f64>) -> f64 {
    match (limit_m, known.last()) {
        (Some(limit_m), Some(&(solved_m, _))) if approach_m >= limit_m => {
            solved_m + 0.5 * (limit_m - solved_m)
        }
        _ => approach_m,
    }
}

/// The rigid plane's bearing area: the approach at which a given fraction
/// of the measured points lies above the plane.
struct Bearing {
    /// Measured heights, highest first.
    descending_m: Vec<f64>,
}

impl Bearing {
    fn new(heights_m: &[f64]) -> Self {
        let mut descending_m: Vec<f64> = heights_m
            .iter()
            .copied()
            .filter(|h| h.is_finite())
            .collect();
        descending_m.sort_by(|a, b| b.total_cmp(a));
        Self { descending_m }
    }

    /// The fraction of the measured points at or above the plane at
    /// approach `approach_m`.
    fn fraction(&self, approach_m: f64) -> f64 {
        let plane = self.descending_m[0] - approach_m;
        let above = self.descending_m.partition_point(|&h| h >= plane);
        above as f64 / self.descending_m.len() as f64
    }

    fn approach_m(&self, fraction: f64) -> f64 {
        let n = self.descending_m.len();
        let k = ((fraction * n as f64).ceil() as usize).clamp(1, n);
        let approach = self.descending_m[0] - self.descending_m[k - 1];
        if approach > 0.0 {
            approach
        } else {
            // A plateau at the top: any small approach; the steps sort it out.
            (self.descending_m[0] - self.descending_m[n - 1]).max(f64::MIN_POSITIVE) * 1e-3
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn predictions_interpolate_extrapolate_and_start_from_the_bearing_area() {
        let heights = [3.0, 2.0, 1.0, 0.0];
        let bearing = Bearing::new(&heights);
        assert_eq!(bearing.approach_m(0.5), 1.0);
        assert_eq!(bearing.fraction(1.0), 0.5);
        assert_eq!(bearing.fraction(0.5), 0.25);
        // One solve below the target: the same share of the bearing area.
        assert_eq!(predict(&[(0.0, 0.0), (1.0, 0.25)], 0.375, &bearing), 2.0);
        // Only first contact known: the bearing area at twice the target.
        assert_eq!(predict(&[(0.0, 0.0)], 0.25, &bearing), 1.0);
        // Bracketed: linear between the neighbours.
        let known = [(0.0, 0.0), (1.0, 0.2), (2.0, 0.6)];
        assert!((predict(&known, 0.4, &bearing) - 1.5).abs() < 1e-15);
        // Beyond: the last secant, at most doubling.
        assert!((predict(&known, 0.8, &bearing) - 2.5).abs() < 1e-15);
        assert_eq!(predict(&known, 5.0, &bearing), 4.0);
        // Past full contact of a periodic map: halfway to it from the last.
        assert_eq!(short_of_full_contact(4.0, &known, Some(3.0)), 2.5);
        assert_eq!(short_of_full_contact(3.0, &known, Some(3.0)), 2.5);
        assert_eq!(short_of_full_contact(2.9, &known, Some(3.0)), 2.9);
        assert_eq!(short_of_full_contact(4.0, &known, None), 4.0);
    }
}
