//! Frictionless contact of the block's top with a rigid flat plane moving
//! down, enforced exactly by an active set on the top nodes (a node in
//! contact has its z displacement prescribed to the plane; it is released
//! when its reaction becomes tensile, and a free node that penetrates is
//! added), solved by Newton's method with a line search, the active set
//! updated after every Newton step (a primal–dual active-set, i.e.
//! semi-smooth Newton, iteration: Hintermüller, Ito & Kunisch, SIAM J.
//! Optim. 13, 2002; releases wait for a near-equilibrium, see
//! [`crate::newton`]). Steps are controlled by the approach, the plane's
//! travel since it first touched the highest top node; a step starts from
//! the last converged state (extrapolated for a linear law), and an attempt whose held nodes cannot be
//! carried to the plane in one undamped move is cut in half at once (the
//! first-touch cut, [`ContactProblem::advance`]).
//!
//! Held unknowns keep their place in the matrix (row and column replaced by
//! the diagonal alone), so the pattern, and the symbolic factorisation,
//! never change.

use crate::FemError;
use crate::assembly::{self, Evaluation, Pattern};
use crate::dofs::Dofs;
use crate::law::Law;
use crate::linear_solver::{Krylov, LinearSolver};
use crate::mesh::{Lateral, Mesh};

/// Halvings of a step's increment before its failure is reported.
pub const MAX_CUTS: usize = 4;

/// Newton and active-set controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Converged when the residual's 2-norm on the free unknowns is at most
    /// this times the 2-norm of the contact reactions (and the active set
    /// did not change).
    pub tolerance: f64,
    /// Newton iterations per attempt before the increment is halved (and,
    /// after [`MAX_CUTS`] halvings, the step fails).
    pub max_iterations: usize,
    /// An iteration keeps the last factorisation (a chord step) when the
    /// one before it, with the same held set and every held node on the
    /// plane, cut the residual by at least this factor
    /// ([`crate::newton`]); 0: a factorisation at every iteration.
    pub chord_contraction: f64,
    /// First-touch cut: while a halving of the increment is left, an
    /// attempt is abandoned (and the increment halved) as soon as a line
    /// search damps the held nodes' move to the plane to a step length of
    /// at most this; 0: never before `max_iterations`.
    pub cut_damping: f64,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 30,
            chord_contraction: 0.25,
            cut_damping: 0.25,
        }
    }
}

/// The converged state of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Travel of the plane since first touch, m.
    pub approach_m: f64,
    /// Top nodes in contact / top nodes.
    pub area_fraction: f64,
    /// Contact area in the deformed configuration / deformed projected area
    /// (each top face counts with the share of its nodes in contact).
    pub area_fraction_current: f64,
    /// The plane's force on the block, positive in compression, N.
    pub load_n: f64,
    /// Newton iterations of this step (chord steps on a kept factorisation
    /// and failed attempts included).
    pub iterations: usize,
    /// Largest height of a free top node above the plane (0 if none), m.
    pub largest_penetration_m: f64,
    /// Mean gap between the plane and the deformed top (reference tributary
    /// areas as weights), m.
    pub mean_gap_m: f64,
}

/// A finite-element contact problem: the block, its law, its boundary
/// conditions and its current state.
pub struct ContactProblem {
    pub mesh: Mesh,
    pub law: Law,
    pub dofs: Dofs,
    pattern: Pattern,
    solver: LinearSolver,
    diagonal: Vec<usize>,
    /// Highest reference top z (first touch), m.
    top_m: f64,
    /// The unknowns (displacements), m.
    unknowns: Vec<f64>,
    /// Per top node: held at the plane.
    active: Vec<bool>,
    /// The last converged states (approach, unknowns), newest last.
    history: Vec<(f64, Vec<f64>)>,
    /// Residual at the last converged state.
    last: Option<Evaluation>,
    /// The assembled tangent of a law whose tangent does not depend on the
    /// state (small-strain linear elasticity): assembled once, the same bits
    /// as assembling it at every iteration.
    constant_tangent: Option<Vec<f64>>,
    /// Numeric factorisations so far.
    factorizations: usize,
    /// The held set of the last factorisation (a chord step needs the
    /// current one).
    factored_held: Option<Vec<bool>>,
    /// Conjugate-gradient iterations on the last factorisation so far.
    krylov_iterations: usize,
    /// How Newton directions are solved on the last factorisation.
    krylov: Krylov,
    options: NewtonOptions,
}

impl ContactProblem {
    pub fn new(
        mesh: Mesh,
        law: Law,
        lateral: Lateral,
        options: NewtonOptions,
    ) -> Result<Self, FemError> {
        let dofs = crate::dofs::Dofs::new(&mesh, lateral);
        let pattern = Pattern::new(&mesh, &dofs);
        let order = crate::ordering::nested_dissection(&mesh, &dofs);
        let solver = LinearSolver::new(&pattern, Some(&order))?;
        let top_m = dofs
            .top
            .iter()
            .map(|t| mesh.nodes_m[t.node][2])
            .fold(f64::NEG_INFINITY, f64::max);
        // A bad reference element fails every evaluation: it is reported by
        // the first one of the solve, as without the cache.
        let constant_tangent = match law {
            Law::LinearElastic { .. } => {
                let zero = vec![0.0; dofs.count];
                assembly::evaluate(&mesh, &dofs, &law, Some(&pattern), &zero)
                    .ok()
                    .and_then(|e| e.tangent)
            }
            Law::Hyperelastic { .. } => None,
        };
        let constant = constant_tangent.is_some();
        Ok(Self {
            constant_tangent,
            factorizations: 0,
            factored_held: None,
            krylov_iterations: 0,
            krylov: Krylov {
                max_iterations: if constant { KRYLOV.max_iterations } else { 0 },
                ..KRYLOV
            },
            diagonal: pattern.diagonal_positions(),
            active: vec![false; dofs.top.len()],
            unknowns: vec![0.0; dofs.count],
            history: Vec::new(),
            last: None,
            mesh,
            law,
            dofs,
            pattern,
            solver,
            top_m,
            options,
        })
    }

    /// The nodal displacements of the current state, m.
    pub fn displacement_m(&self) -> Vec<[f64; 3]> {
        self.dofs.expand(&self.unknowns)
    }

    /// The numeric factorisations of the tangent so far (each Newton
    /// iteration but the chord steps).
    pub fn factorizations(&self) -> usize {
        self.factorizations
    }

    /// The memory the solve will hold at its peak, bytes: the Cholesky
    /// factor and its work space, the tangent's pattern and element value
    /// indices, three tangents' values (the one factorised, the line
    /// search's next, a constant one kept), a dozen vectors of the
    /// unknowns, and the mesh. Measured peaks are within 10 % of it (the
    /// fem bench, `cargo bench -p hypercontact-fem --bench patch`).
    pub fn memory_estimate_bytes(&self) -> usize {
        let stored = self.pattern.row_idx.len();
        // The pattern, and the solver's 32-bit copy of it.
        let pattern = self.pattern.heap_bytes() + 4 * (self.pattern.col_ptr.len() + stored);
        let tangents = 3 * 8 * stored;
        let vectors = 12 * 8 * self.dofs.count;
        let mesh = 24 * self.mesh.nodes_m.len() + 64 * self.mesh.elements.len();
        self.solver.factor_bytes() + pattern + tangents + vectors + mesh
    }

    /// The memory of the Cholesky factor and its work space, bytes.
    pub fn factor_bytes(&self) -> usize {
        self.solver.factor_bytes()
    }

    /// The conjugate-gradient iterations that solved Newton directions on
    /// a kept factorisation so far.
    pub fn krylov_iterations(&self) -> usize {
        self.krylov_iterations
    }

    /// Solves every Newton direction by a fresh factorisation (`false`), or
    /// first by conjugate gradients on the last one (`true`; the default for
    /// a law whose tangent does not change, where only the rows of nodes
    /// entering or leaving contact separate the matrix from its factor).
    pub fn set_krylov(&mut self, on: bool) {
        self.krylov.max_iterations = if on { KRYLOV.max_iterations } else { 0 };
    }

    /// Whether the last factorisation was of a system with the held set
    /// `held` (a chord step solves with it as it stands).
    pub(crate) fn factored_with(&self, held: &[bool]) -> bool {
        self.factored_held.as_deref() == Some(held)
    }

    /// Which top nodes are in contact (per entry of [`Dofs::top`]).
    pub fn active(&self) -> &[bool] {
        &self.active
    }

    /// Nodal contact pressure per map point (i * ny + j): the reaction over
    /// the node's reference tributary area, Pa (0 off contact).
    pub fn pressure_map_pa(&self) -> Vec<f64> {
        let Some(last) = &self.last else {
            return vec![0.0; self.dofs.top_of_point.len()];
        };
        self.dofs
            .top_of_point
            .iter()
            .map(|&t| {
                let top = &self.dofs.top[t];
                if self.active[t] {
                    -last.residual_n[top.equation] / top.area_m2
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Contact mask per map point.
    pub fn contact_mask(&self) -> Vec<bool> {
        self.dofs
            .top_of_point
            .iter()
            .map(|&t| self.active[t])
            .collect()
    }

    fn plane_m(&self, approach_m: f64) -> f64 {
        self.top_m - approach_m
    }

    /// The reference z of top node t, m.
    fn top_z(&self, t: usize) -> f64 {
        self.mesh.nodes_m[self.dofs.top[t].node][2]
    }

    /// Solves step `step` (numbered from 1, for messages) at `approach_m`.
    /// A step whose Newton iteration fails (an active set that keeps
    /// changing over a large increment) is cut in half and retried from the
    /// last converged state, up to [`MAX_CUTS`] times.
    pub fn solve_step(&mut self, step: usize, approach_m: f64) -> Result<Step, FemError> {
        let start = self.history.last().map_or(0.0, |h| h.0);
        let iterations = self.advance(step, start, approach_m, 0)?;
        Ok(self.summary(approach_m, iterations))
    }

    /// Reaches `to_m` from the converged state at `from_m`, halving the
    /// increment on failure; returns the Newton iterations spent.
    ///
    /// First-touch cut: while a halving is left, an attempt is abandoned as
    /// soon as its line search damps the held nodes' move to the plane to
    /// η ≤ [`NewtonOptions::cut_damping`] (the increment carries nodes so
    /// far into the block that the linearisation fails there, typically in
    /// the first steps, where the approach grows fastest), instead of after
    /// `max_iterations` damped iterations; the last allowed halving still
    /// iterates to the end.
    fn advance(
        &mut self,
        step: usize,
        from_m: f64,
        to_m: f64,
        cuts: usize,
    ) -> Result<usize, FemError> {
        let saved = (self.unknowns.clone(), self.active.clone());
        self.predict(to_m);
        self.add_penetrating(self.plane_m(to_m), to_m);
        match crate::newton::solve(self, step, to_m, cuts < MAX_CUTS) {
            Ok(iterations) => {
                self.history.push((to_m, self.unknowns.clone()));
                if self.history.len() > 2 {
                    self.history.remove(0);
                }
                Ok(iterations)
            }
            Err(FemError::NotConverged { iterations, .. }) if cuts < MAX_CUTS => {
                (self.unknowns, self.active) = saved;
                let middle = 0.5 * (from_m + to_m);
                let first = self.advance(step, from_m, middle, cuts + 1)?;
                let second = self.advance(step, middle, to_m, cuts + 1)?;
                Ok(iterations + first + second)
            }
            Err(e) => Err(e),
        }
    }

    /// The start of a step. A linear law's: the last state extrapolated
    /// linearly in the approach from the last two (scaled from the last one
    /// at the second step), exact while the contact set stays, which leaves
    /// Newton one or two iterations. A hyperelastic law's: the last state
    /// itself. The extrapolation, used for both before, carried nodes at
    /// the edge of contact into the block and cost more Newton iterations
    /// than it saved at finite strain (the rough patches of
    /// tests/newton.rs: 145 against 249 iterations at rms slope 0.3 on
    /// 10 × 10 × 4, 368 against 597 at 0.6 on 12 × 12 × 6), while at small
    /// strain it saves a third (the paper's t1 patch: 41 against 59).
    fn predict(&mut self, approach_m: f64) {
        if !matches!(self.law, Law::LinearElastic { .. }) {
            if let Some((_, x)) = self.history.last() {
                self.unknowns.clone_from(x);
            }
            return;
        }
        match self.history.as_slice() {
            [.., (a0, x0), (a1, x1)] if a1 > a0 => {
                let s = (approach_m - a1) / (a1 - a0);
                for ((u, p), q) in self.unknowns.iter_mut().zip(x1).zip(x0) {
                    *u = p + s * (p - q);
                }
            }
            [(a1, x1)] if *a1 > 0.0 => {
                let s = approach_m / a1;
                for (u, p) in self.unknowns.iter_mut().zip(x1) {
                    *u = s * p;
                }
            }
            _ => {}
        }
    }

    /// Back to the last converged state (when the state a step starts from
    /// inverts an element).
    pub(crate) fn restore_last(&mut self) -> bool {
        match self.history.last() {
            Some((_, x)) => {
                self.unknowns.clone_from(x);
                true
            }
            None => false,
        }
    }

    /// Holds every free top node above the plane (by more than the
    /// tolerance). Returns whether the set changed. Held nodes are not moved
    /// here: the next Newton step carries them to the plane
    /// ([`ContactProblem::pending_m`]), through the tangent, so that no
    /// element is crushed by a node moved alone.
    pub(crate) fn add_penetrating(&mut self, plane_m: f64, approach_m: f64) -> bool {
        let tolerance =
            ENTRY_PENETRATION * approach_m + penetration_tolerance_m(approach_m, self.mesh.depth_m);
        let mut changed = false;
        for t in 0..self.active.len() {
            let e = self.dofs.top[t].equation;
            let z = self.top_z(t) + self.unknowns[e];
            if !self.active[t] && z > plane_m + tolerance {
                self.active[t] = true;
                changed = true;
            }
        }
        changed
    }

    /// The displacement each held node still needs to reach the plane, per
    /// unknown (0 elsewhere), m.
    pub(crate) fn pending_m(&self, plane_m: f64) -> Vec<f64> {
        let mut pending = vec![0.0; self.dofs.count];
        for (t, top) in self.dofs.top.iter().enumerate() {
            if self.active[t] {
                pending[top.equation] = plane_m - self.top_z(t) - self.unknowns[top.equation];
            }
        }
        pending
    }

    /// Releases held nodes whose reaction pulls on the plane. Returns
    /// whether any was released.
    pub(crate) fn release_tensile(&mut self, residual_n: &[f64], reaction_scale_n: f64) -> bool {
        let mut changed = false;
        for (t, top) in self.dofs.top.iter().enumerate() {
            // residual = internal force; the plane pushes down (negative),
            // so a positive value is the plane pulling.
            if self.active[t] && residual_n[top.equation] > RELEASE_PULL * reaction_scale_n {
                self.active[t] = false;
                changed = true;
            }
        }
        changed
    }

    /// Residual and (with `tangent`) tangent at the current unknowns.
    pub(crate) fn evaluate(
        &self,
        unknowns: &[f64],
        tangent: bool,
    ) -> Result<Evaluation, assembly::Failure> {
        let cached = self.constant_tangent.as_ref().filter(|_| tangent);
        let pattern = (tangent && cached.is_none()).then_some(&self.pattern);
        let mut evaluation =
            assembly::evaluate(&self.mesh, &self.dofs, &self.law, pattern, unknowns)?;
        if let Some(values) = cached {
            evaluation.tangent = Some(values.clone());
        }
        Ok(evaluation)
    }

    /// The held unknowns' equations and a flag per unknown.
    pub(crate) fn held(&self) -> Vec<bool> {
        let mut held = vec![false; self.dofs.count];
        for (t, top) in self.dofs.top.iter().enumerate() {
            if self.active[t] {
                held[top.equation] = true;
            }
        }
        held
    }

    /// The 2-norm of the reactions of the held nodes, N.
    pub(crate) fn reaction_norm_n(&self, residual_n: &[f64]) -> f64 {
        (self.dofs.top.iter().zip(&self.active))
            .filter(|(_, a)| **a)
            .map(|(t, _)| residual_n[t.equation].powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// The Newton step: the held unknowns move by `pending`, the free ones
    /// by the solution of K_ff d_f = −r_f − K_fh pending (the tangent with
    /// held rows and columns reduced to their diagonal, factorised); and
    /// ‖K_hh pending‖, the force that moving the held nodes alone would
    /// take, N (the line search's measure of what is still to do).
    /// The tangent is taken out of `evaluation` (and reduced in place).
    pub(crate) fn newton_direction(
        &mut self,
        evaluation: &mut Evaluation,
        held: &[bool],
        pending: &[f64],
    ) -> Result<(Vec<f64>, f64), FemError> {
        let mut values = evaluation
            .tangent
            .take()
            .ok_or_else(|| FemError::Solver("no tangent was assembled".into()))?;
        let mut step: Vec<f64> = (evaluation.residual_n.iter().zip(held))
            .map(|(r, h)| if *h { 0.0 } else { -r })
            .collect();
        for col in 0..self.pattern.size {
            let range = self.pattern.col_ptr[col]..self.pattern.col_ptr[col + 1];
            for (value, &row) in values[range.clone()]
                .iter_mut()
                .zip(&self.pattern.row_idx[range])
            {
                if row == col || !(held[row] || held[col]) {
                    continue;
                }
                // The upper triangle holds K_rc = K_cr once: move the held
                // increments' forces to the right-hand side, both ways.
                if held[col] && !held[row] {
                    step[row] -= *value * pending[col];
                }
                if held[row] && !held[col] {
                    step[col] -= *value * pending[row];
                }
                *value = 0.0;
            }
        }
        let mut pending_force_n = 0.0;
        for (col, &k) in self.diagonal.iter().enumerate() {
            if held[col] {
                if values[k] <= 0.0 {
                    values[k] = 1.0;
                }
                step[col] = values[k] * pending[col];
                pending_force_n += step[col] * step[col];
            }
        }
        // Conjugate gradients need about one iteration per node that
        // entered or left contact since the factorisation (each changes the
        // matrix by a rank-one term): with more than half the iterations
        // allowed, factorise at once.
        let changed = self.factored_held.as_ref().map_or(usize::MAX, |f| {
            f.iter().zip(held).filter(|(a, b)| a != b).count()
        });
        let krylov = Krylov {
            max_iterations: if 2 * changed > self.krylov.max_iterations {
                0
            } else {
                self.krylov.max_iterations
            },
            ..self.krylov
        };
        match self.solver.solve_preconditioned(&values, &mut step, krylov) {
            Ok(iterations) => self.krylov_iterations += iterations,
            Err(_) => {
                self.solver.factor(&values)?;
                self.factorizations += 1;
                self.factored_held = Some(held.to_vec());
                self.solver.solve(&mut step);
            }
        }
        Ok((step, pending_force_n.sqrt()))
    }

    /// A chord step: the solution of the last factorised system (whose
    /// held set must be `held`) with the right-hand side −r on the free
    /// unknowns and 0 on the held ones, which stay where they are.
    pub(crate) fn chord_direction(&mut self, residual_n: &[f64], held: &[bool]) -> Vec<f64> {
        let mut step: Vec<f64> = (residual_n.iter().zip(held))
            .map(|(r, h)| if *h { 0.0 } else { -r })
            .collect();
        self.solver.solve(&mut step);
        step
    }

    pub(crate) fn unknowns(&self) -> &[f64] {
        &self.unknowns
    }

    pub(crate) fn set_unknowns(&mut self, unknowns: Vec<f64>) {
        self.unknowns = unknowns;
    }

    pub(crate) fn set_last(&mut self, mut evaluation: Evaluation) {
        // Only the residual is read later: a tangent kept with it would hold
        // a matrix's worth of memory for nothing.
        evaluation.tangent = None;
        self.last = Some(evaluation);
    }

    pub(crate) fn options(&self) -> NewtonOptions {
        self.options
    }

    pub(crate) fn contact_count(&self) -> usize {
        self.active.iter().filter(|a| **a).count()
    }

    pub(crate) fn shear_modulus_pa(&self) -> f64 {
        self.law.shear_modulus_pa()
    }
}

/// Newton directions by conjugate gradients on the last factorisation: to
/// 1e-8 of the right-hand side, and at most 12 iterations (a solve costs a
/// twentieth of a factorisation on a 48² × 8 block, a thirtieth on 96² × 8)
/// before a fresh factorisation. On by default only for a constant tangent
/// (the small-strain law): measured on a 32² × 8 patch, 20 steps to A/A0 =
/// 0.3, 28 → 18 factorisations and 7.4 → 6.3 s of CPU at small strain,
/// but 27.5 → 31.0 s at finite strain, where the tangent moves every
/// iteration and the conjugate gradients need 5–11 iterations each.
const KRYLOV: Krylov = Krylov {
    tolerance: 1e-8,
    max_iterations: 12,
};

/// Hysteresis of the active set, so that a node at the edge of contact
/// cannot flip in and out for ever (seen on coarse patches: a node released
/// for a pull of 1e-10 of the reactions penetrates by 1e-9 of the approach,
/// is held again, pulls again): a free node enters only when it penetrates
/// by more than this fraction of the approach (the issue allows 1e-3), …
const ENTRY_PENETRATION: f64 = 1e-6;
/// … and a held node leaves only when it pulls with more than this fraction
/// of the 2-norm of the contact reactions (a load error of that order).
const RELEASE_PULL: f64 = 1e-9;

/// A free node counts as penetrating beyond 1e-9 of the approach (1e-15 of
/// the depth at first touch): far below any length that matters, above
/// the round-off of the positions.
pub(crate) fn penetration_tolerance_m(approach_m: f64, depth_m: f64) -> f64 {
    1e-9 * approach_m + 1e-15 * depth_m
}

impl ContactProblem {
    /// The mean gap between the plane at `approach_m` and the top as it
    /// stands now (reference tributary areas as weights), m; before the
    /// first step, the undeformed top's at first touch.
    pub fn mean_gap_m(&self, approach_m: f64) -> f64 {
        self.mean_gap(self.plane_m(approach_m), &self.displacement_m())
    }

    fn mean_gap(&self, plane_m: f64, displacement_m: &[[f64; 3]]) -> f64 {
        let k = self.mesh.layers;
        let (mut gap_sum, mut area_sum) = (0.0, 0.0);
        for i in 0..self.mesh.nx {
            for j in 0..self.mesh.ny {
                let node = self.mesh.node(i, j, k);
                let area = self.mesh.tributary_area_m2(i, j);
                gap_sum += area * (plane_m - self.mesh.nodes_m[node][2] - displacement_m[node][2]);
                area_sum += area;
            }
        }
        gap_sum / area_sum
    }

    /// The step's results from the converged state.
    fn summary(&self, approach_m: f64, iterations: usize) -> Step {
        let plane = self.plane_m(approach_m);
        let residual: &[f64] = self.last.as_ref().map_or(&[], |e| &e.residual_n);
        let mut load_n = 0.0;
        let mut largest_penetration_m: f64 = 0.0;
        for (t, top) in self.dofs.top.iter().enumerate() {
            let z = self.top_z(t) + self.unknowns[top.equation];
            if self.active[t] {
                load_n -= residual.get(top.equation).copied().unwrap_or(0.0);
            } else {
                largest_penetration_m = largest_penetration_m.max(z - plane);
            }
        }
        let displacement = self.displacement_m();
        let (nx, ny, k) = (self.mesh.nx, self.mesh.ny, self.mesh.layers);
        let mean_gap_m = self.mean_gap(plane, &displacement);
        let (mut contact_area, mut projected_area) = (0.0, 0.0);
        for i in 0..nx - 1 {
            for j in 0..ny - 1 {
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let xy = corners.map(|(a, b)| {
                    let node = self.mesh.node(a, b, k);
                    let x = self.mesh.nodes_m[node];
                    [x[0] + displacement[node][0], x[1] + displacement[node][1]]
                });
                // Shoelace formula for the deformed quadrilateral's projection.
                let area = 0.5
                    * (0..4)
                        .map(|c| xy[c][0] * xy[(c + 1) % 4][1] - xy[(c + 1) % 4][0] * xy[c][1])
                        .sum::<f64>();
                let touching = corners
                    .iter()
                    .filter(|(a, b)| self.active[self.dofs.top_of_point[a * ny + b]])
                    .count();
                contact_area += area * touching as f64 / 4.0;
                projected_area += area;
            }
        }
        Step {
            approach_m,
            area_fraction: self.contact_count() as f64 / self.active.len() as f64,
            area_fraction_current: contact_area / projected_area,
            load_n,
            iterations,
            largest_penetration_m,
            mean_gap_m,
        }
    }

    /// The sum of the top nodes' reference areas, m².
    pub(crate) fn top_area_m2(&self) -> f64 {
        self.dofs.top.iter().map(|t| t.area_m2).sum()
    }

    pub(crate) fn plane_at(&self, approach_m: f64) -> f64 {
        self.plane_m(approach_m)
    }
}
