//! Newton's method with a backtracking line search for one contact step
//! ([`crate::contact`]): each iteration factorises the tangent, takes the
//! step −K⁻¹r on the free unknowns, halves it until the residual or the
//! energy decreases enough (Armijo's condition on either; Nocedal & Wright,
//! Numerical Optimization, § 3.1), then updates the active set: free nodes
//! that penetrate the plane enter at once; held nodes that pull leave only
//! once the free residual is within √tolerance of the reactions. A
//! reaction's sign far from equilibrium is not the answer's: at finite
//! strain a node released there was carried back above the plane by the
//! next step, held again, pulled again, for ever (a 2-cycle seen on rough
//! patches of rms slope 0.3; the nested "equilibrate, then release" order
//! of the classical active-set loops, e.g. Wriggers, Computational Contact
//! Mechanics, 2nd ed., § 6.3.1, applied to releases only).
//!
//! Chord steps: an iteration keeps the last factorisation (the step
//! −K_old⁻¹ r) when the one before it, with the same held set and every
//! held node on the plane, cut the residual by at least
//! [`NewtonOptions::chord_contraction`]. Newton is then in its convergence
//! range, where the tangent barely changes from one iteration to the next,
//! and a chord step converges almost as fast for the cost of a residual
//! and a solve instead of a tangent and a factorisation (Kelley, Iterative
//! Methods for Linear and Nonlinear Equations, SIAM 1995, § 5.4, the
//! Shamanskii method); it also makes the last iteration of a step, the one
//! that finds the residual at the round-off floor of the assembly, cheap.
//! A chord step that contracts less hands back to Newton. A chord step
//! follows only an iteration that itself had every held node on the plane
//! and the same set (its contraction then measures Newton's range; after a
//! move of held nodes it measured nothing and the chord step was damped).
//!
//! Held nodes within the round-off of the plane count as on it: their
//! pending move is taken as zero, so that the energy, a merit only when no
//! held node still has to move, judges the line search.

use crate::FemError;
use crate::assembly::Evaluation;
use crate::contact::ContactProblem;
#[cfg(doc)]
use crate::contact::NewtonOptions;

/// Halvings of the step before the line search gives up and takes the
/// best trial it has seen.
const MAX_HALVINGS: usize = 8;

/// Armijo's sufficient-decrease factor.
const ARMIJO: f64 = 1e-4;

/// The 2-norm of the residual on the free unknowns.
fn free_norm(residual_n: &[f64], held: &[bool]) -> f64 {
    (residual_n.iter().zip(held))
        .filter(|(_, h)| !**h)
        .map(|(r, _)| r * r)
        .sum::<f64>()
        .sqrt()
}

/// Whether the update from `before` to `after` is below 1e-10 of the
/// largest displacement: the residual is then at the round-off floor of the
/// assembly (forces of a κ = 5000 μ material cancel to ~1e-16 κ/μ of their
/// size), and further iterations cannot lower it.
fn is_small(before: &[f64], after: &[f64]) -> bool {
    let largest = after.iter().fold(0.0_f64, |m, u| m.max(u.abs()));
    let change = before
        .iter()
        .zip(after)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    change <= 1e-10 * largest
}

/// Iterates the current state of `problem` to equilibrium at `approach_m`
/// with a converged active set; returns the number of iterations. With
/// `may_cut`, fails (as not converged) as soon as a line search damps the
/// held nodes' move to η ≤ [`NewtonOptions::cut_damping`], for the caller
/// to halve the increment.
pub fn solve(
    problem: &mut ContactProblem,
    step: usize,
    approach_m: f64,
    may_cut: bool,
) -> Result<usize, FemError> {
    let options = problem.options();
    let plane = problem.plane_at(approach_m);
    let floor_n = 1e-12 * problem.shear_modulus_pa() * problem.top_area_m2();
    let reach_m = crate::contact::penetration_tolerance_m(approach_m, problem.mesh.depth_m);
    let mut evaluation = first_evaluation(problem, step, approach_m)?;
    let mut set_changed = false;
    let mut small_update = false;
    let mut previous_n = f64::INFINITY;
    let mut iterations = 0;
    // The held set of the factorisation the solver keeps.
    let mut factored_held: Option<Vec<bool>> = None;
    // Whether the last line search took the full step: after a damped one
    // the next full step is likely damped too, and its tangent, assembled
    // with it, wasted; it is then assembled when needed.
    let mut full_step = true;
    loop {
        let held = problem.held();
        let (pending, placed) = pending_moves(problem, plane, reach_m);
        let scale_n = problem.reaction_norm_n(&evaluation.residual_n).max(floor_n);
        let residual_n = free_norm(&evaluation.residual_n, &held);
        let tolerance_n = options.tolerance * scale_n;
        // Newton halves any residual in its quadratic range; one that does
        // not, though already below √tolerance of the reactions, is the
        // round-off of the assembly (the paper's Ogden terms, ±5e9 Pa,
        // cancel to 2e6 Pa and leave ~1e-7 of the reactions).
        let stagnant =
            residual_n <= options.tolerance.sqrt() * scale_n && residual_n > 0.5 * previous_n;
        if (residual_n <= tolerance_n || small_update || stagnant) && !set_changed && placed {
            // Converged, unless a held node pulls (kept by an unsettled trial).
            if !problem.release_tensile(&evaluation.residual_n, scale_n) {
                problem.set_last(evaluation);
                return Ok(iterations);
            }
            set_changed = true;
            continue;
        }
        let mut at = Progress {
            step,
            approach_m,
            iterations,
            residual_n,
            tolerance_n,
        };
        if iterations >= options.max_iterations {
            return Err(at.not_converged(problem, ""));
        }
        // previous_n is finite only after an iteration with every held node
        // placed and the set unchanged.
        let settled = placed && !set_changed;
        let chord =
            settled && chord_allowed(problem, &held, &factored_held, residual_n, previous_n);
        if !chord {
            factored_held = Some(held.clone());
        }
        let (direction, pending_force_n) =
            direction(problem, &mut evaluation, chord, (&held, &pending), at)?;
        iterations += 1;
        at.iterations = iterations;
        previous_n = if settled { residual_n } else { f64::INFINITY };
        let search = line_search(
            problem,
            (&evaluation, &direction, &held),
            residual_n,
            pending_force_n,
            !chord && full_step,
        );
        let (unknowns, trial, eta) = search.ok_or_else(|| {
            at.not_converged(
                problem,
                "; every trial along the Newton direction inverts an element",
            )
        })?;
        full_step = eta == 1.0;
        if may_cut && pending_force_n > 0.0 && eta <= options.cut_damping {
            return Err(at.not_converged(
                problem,
                format!("; the held nodes' move damped to η = {eta}: the increment is cut"),
            ));
        }
        small_update = placed && is_small(problem.unknowns(), &unknowns);
        problem.set_unknowns(unknowns);
        set_changed = update_set(problem, (&trial, &held), small_update, floor_n, approach_m);
        // The active set does not move the unknowns, so the trial's
        // evaluation stands (its tangent is assembled when a factorisation
        // needs it).
        evaluation = trial;
    }
}

/// Whether the kept factorisation may serve (a chord step): the last
/// iteration (`previous_n` finite: every held node placed, the set
/// unchanged) cut the residual by [`NewtonOptions::chord_contraction`], and
/// the factor was made with this held set.
fn chord_allowed(
    problem: &ContactProblem,
    held: &[bool],
    factored_held: &Option<Vec<bool>>,
    residual_n: f64,
    previous_n: f64,
) -> bool {
    previous_n.is_finite()
        && residual_n <= problem.options().chord_contraction * previous_n
        && factored_held.as_deref() == Some(held)
        && problem.factored_with(held)
}

/// A chord step on the kept factorisation, or a Newton step (and the
/// force owed to held nodes, N), assembling the tangent if `evaluation`
/// lacks it.
fn direction(
    problem: &mut ContactProblem,
    evaluation: &mut Evaluation,
    chord: bool,
    (held, pending): (&[bool], &[f64]),
    at: Progress,
) -> Result<(Vec<f64>, f64), FemError> {
    if chord {
        return Ok((problem.chord_direction(&evaluation.residual_n, held), 0.0));
    }
    if evaluation.tangent.is_none() {
        *evaluation = problem
            .evaluate(problem.unknowns(), true)
            .map_err(|f| at.not_converged(problem, format!("; element {} inverted", f.element)))?;
    }
    problem.newton_direction(evaluation, held, pending)
}

/// The move each held node still owes the plane (per unknown, m), and
/// whether every one is within `reach_m` of it: the held nodes are then
/// placed and owe nothing (a leftover of 1e-22 m would keep the energy from
/// judging the line search).
fn pending_moves(problem: &ContactProblem, plane_m: f64, reach_m: f64) -> (Vec<f64>, bool) {
    let mut pending = problem.pending_m(plane_m);
    let placed = pending.iter().all(|d| d.abs() <= reach_m);
    if placed {
        pending.fill(0.0);
    }
    (pending, placed)
}

/// The active set after a step to `trial`: free nodes that penetrate enter;
/// held nodes that pull leave only when the trial has settled (free
/// residual within √tolerance of its reactions, or a `small_update`, at
/// round-off), see the module doc. Returns whether the set changed.
fn update_set(
    problem: &mut ContactProblem,
    (trial, held): (&Evaluation, &[bool]),
    small_update: bool,
    floor_n: f64,
    approach_m: f64,
) -> bool {
    let scale_n = problem.reaction_norm_n(&trial.residual_n).max(floor_n);
    let tolerance = problem.options().tolerance;
    let settled = small_update || free_norm(&trial.residual_n, held) <= tolerance.sqrt() * scale_n;
    let released = settled && problem.release_tensile(&trial.residual_n, scale_n);
    let added = problem.add_penetrating(problem.plane_at(approach_m), approach_m);
    released || added
}

/// The residual and tangent at the state the step starts from, or, if it
/// inverts an element, at the last converged state.
fn first_evaluation(
    problem: &mut ContactProblem,
    step: usize,
    approach_m: f64,
) -> Result<Evaluation, FemError> {
    let at = Progress::start(step, approach_m);
    match problem.evaluate(problem.unknowns(), true) {
        Ok(e) => Ok(e),
        Err(_) if problem.restore_last() => {
            problem.add_penetrating(problem.plane_at(approach_m), approach_m);
            problem.evaluate(problem.unknowns(), true).map_err(|f| {
                at.not_converged(
                    problem,
                    format!("; element {} inverted at the start of the step", f.element),
                )
            })
        }
        Err(f) => Err(at.not_converged(
            problem,
            format!("; element {} inverted at the start", f.element),
        )),
    }
}

/// The first of x + η d, η = 1, ½, ¼, … whose merit (free residual norm
/// plus the force owed to held nodes) or energy decreases sufficiently, else the trial with the smallest residual; `None`
/// if every trial inverts an element; with the η taken. The full step's
/// tangent is assembled with it if `tangent` (the next iteration will
/// likely factorise it).
fn line_search(
    problem: &ContactProblem,
    (start, direction, held): (&Evaluation, &[f64], &[bool]),
    residual_n: f64,
    pending_force_n: f64,
    tangent: bool,
) -> Option<(Vec<f64>, Evaluation, f64)> {
    let x = problem.unknowns();
    let slope: f64 = (start.residual_n.iter().zip(direction).zip(held))
        .filter(|(_, h)| !**h)
        .map(|((r, d), _)| r * d)
        .sum();
    let mut best: Option<(f64, Vec<f64>, Evaluation, f64)> = None;
    let mut eta = 1.0;
    for _ in 0..=MAX_HALVINGS {
        let trial: Vec<f64> = x.iter().zip(direction).map(|(u, d)| u + eta * d).collect();
        // The full step is usually taken: assemble its tangent with it, for
        // the next iteration.
        if let Ok(e) = problem.evaluate(&trial, tangent && eta == 1.0) {
            // Merit: the free residual plus the force still owed to the held
            // nodes, (1 − η) of the pending one.
            let norm = free_norm(&e.residual_n, held) + (1.0 - eta) * pending_force_n;
            let residual_ok = norm <= (1.0 - ARMIJO * eta) * (residual_n + pending_force_n);
            // The energy is a merit function only when no held node still
            // has to move (the plane's work is not in it).
            let energy_ok =
                pending_force_n == 0.0 && e.energy_j <= start.energy_j + ARMIJO * eta * slope;
            if residual_ok || energy_ok {
                return Some((trial, e, eta));
            }
            if best.as_ref().is_none_or(|(n, _, _, _)| norm < *n) {
                best = Some((norm, trial, e, eta));
            }
        }
        eta *= 0.5;
    }
    best.map(|(_, trial, e, eta)| (trial, e, eta))
}

/// Where Newton stands when it stops short: what the error reports.
#[derive(Clone, Copy)]
struct Progress {
    step: usize,
    approach_m: f64,
    iterations: usize,
    residual_n: f64,
    tolerance_n: f64,
}

impl Progress {
    /// Before the first iteration: no residual yet.
    fn start(step: usize, approach_m: f64) -> Self {
        Self {
            step,
            approach_m,
            iterations: 0,
            residual_n: f64::NAN,
            tolerance_n: f64::NAN,
        }
    }

    fn not_converged(self, problem: &ContactProblem, detail: impl Into<String>) -> FemError {
        FemError::NotConverged {
            step: self.step,
            approach_m: self.approach_m,
            iterations: self.iterations,
            residual_n: self.residual_n,
            tolerance_n: self.tolerance_n,
            contact_nodes: problem.contact_count(),
            detail: detail.into(),
        }
    }
}
