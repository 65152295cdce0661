//! The contact of a rough elastic half-space with a rigid plane, solved for
//! the pressure by the constrained conjugate gradient of I. A. Polonsky and
//! L. M. Keer, "A numerical method for solving rough contact problems based
//! on the multi-level multi-summation and conjugate gradient techniques",
//! Wear 231 (1999) 206–219, by default with an FFT preconditioner.
//!
//! Conventions: heights h (m, up), a rigid plane at height s above them,
//! pressure p ≥ 0 pushing the surface down by u = K p ([`Influence`],
//! E* = 1, so p is in units of E*). The gap g = s − h + u must be ≥ 0,
//! with g = 0 where p > 0 and p = 0 where g > 0. The plane's approach δ is
//! measured from first contact: s = max h − δ. NaN heights never touch.
//!
//! Two controls:
//! - [`Control::Approach`]: δ given (for a periodic map, where u has zero
//!   mean, this is a given mean gap: Rey, Anciaux & Molinari, Comput. Mech.
//!   60 (2017) 69–81). A periodic map measured everywhere has a largest
//!   approach: the mean gap max h − δ − mean h of a solution is the mean
//!   of g ≥ 0, so from δ = max h − mean h on there is none (at it only full
//!   contact with any added uniform pressure); such a δ is refused
//!   ([`SolveError::BeyondFullContact`]) rather than iterated on, where the
//!   mean pressure grows without bound until the iterations run out or the
//!   step breaks down;
//! - [`Control::MeanPressure`]: the mean pressure over the measured points
//!   given; s follows from the mean of h − u over the contact set, and the
//!   pressure is rescaled to the load after every step (PK's version).
//!
//! Each iteration (PK's steps): the gap on the current contact set
//! {p > 0} (centred under load control), a conjugate direction t on that
//! set, r = K t, the step τ = Σ g t / Σ r t, p ← max(p − τ t, 0).
//! - PK as published (`preconditioned: false`): t = g + β t_old, points with
//!   p = 0 and g < 0 enter with p = −τ g, and conjugacy restarts after an
//!   entry. Iterations grow with the map's size (the operator's condition
//!   number grows like N).
//! - Preconditioned (the default): the direction is z = K̃⁻¹ g on the set
//!   {p > 0} ∪ {g < 0}, K̃⁻¹ the operator's inverse on the transform grid (a
//!   multiplier |q|/2-like in Fourier space, so the iterations hardly depend
//!   on N; for a free map on an unpadded grid of the map's size, a quarter
//!   of the padded transforms for the same iterations: 1519 against 1526 on
//!   a 453² 40-step curve), the overlapping points entering along it; conjugacy is kept
//!   across entries (restarting there, as PK do, stalls this variant in an
//!   enter-and-leave cycle at the contact edge), with a steepest-descent
//!   restart whenever the conjugate step is not a descent. The FFT
//!   preconditioner on the contact set follows E. A. H. Vollebregt, "A new
//!   solver for the elastic normal contact problem using conjugate
//!   gradients, deflation, and an FFT-based preconditioner", J. Comput.
//!   Phys. 257 (2014) 333–351, corrected for the points off the set
//!   ([`crate::complement`]: a Schur-complement term that K̃⁻¹ restricted
//!   to a ragged set leaves out), and β is Polak–Ribière's, clipped at
//!   zero, so conjugacy fades by itself where the set's changes spoil it.
//!   On the 768 × 576 instrument map's 40-step curve the two together take
//!   1 151 iterations where K̃⁻¹ on the set with Fletcher–Reeves' β took
//!   2 166 (Polak–Ribière alone: 1 927).
//!
//! While at most a few pressures are clipped, u follows the step (u − τ r,
//! plus the clipped amounts summed point by point) instead of being
//! recomputed by a convolution; it is recomputed otherwise and always before
//! convergence is declared, so the residual of the returned pressure is that
//! of u = K p (see [`Solution::residual`]): what is returned is checked, not
//! extrapolated.

use hypercontact_numeric::reduce::{CHUNK, fill_sums, sum, sums};
use rayon::prelude::*;

use crate::complement::Complement;
use crate::influence::{Boundary, Influence};

/// At most this many clipped points are added to u directly (each costs one
/// pass over the map); more, and u is recomputed by a convolution.
const DIRECT_CLIPS: usize = 24;

/// What is prescribed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// the rigid plane's approach δ from first contact, m
    Approach(f64),
    /// the mean pressure over the measured points, in units of E*
    MeanPressure(f64),
}

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverOptions {
    /// the largest accepted [`Solution::residual`]
    pub tolerance: f64,
    /// iterations (one iteration: two or three convolutions) before giving up
    pub max_iterations: usize,
    /// the FFT preconditioner (true) or PK as published (false)
    pub preconditioned: bool,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 1000,
            preconditioned: true,
        }
    }
}

/// A converged contact.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// p / E* per pixel (0 off contact and at NaN heights).
    pub pressure: Vec<f64>,
    /// g per pixel, m (NaN at NaN heights).
    pub gap_m: Vec<f64>,
    /// The plane's approach δ from first contact, m.
    pub approach_m: f64,
    /// Σ p / (measured points): the nominal mean pressure over E*.
    pub mean_pressure: f64,
    /// Pixels with p > 0.
    pub contact_pixels: usize,
    pub iterations: usize,
    /// The rms of the complementarity violation (g on {p > 0}, min(g, 0)
    /// elsewhere) over the points where it can be non-zero, divided by the
    /// approach δ (by the rms height when δ ≤ 0): the relative error of the
    /// gap closure.
    pub residual: f64,
}

/// Why no solution was returned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error(
        "no convergence after {iterations} iterations: residual {residual:.3e} > tolerance \
         {tolerance:.1e} (mean pressure of the last iterate {mean_pressure:.6e} E*)"
    )]
    NotConverged {
        iterations: usize,
        residual: f64,
        tolerance: f64,
        /// Σ p / (measured points) of the last iterate, in units of E*.
        mean_pressure: f64,
    },
    #[error(
        "the conjugate-gradient step broke down (a zero or non-finite step) at iteration \
         {iteration}"
    )]
    Breakdown { iteration: usize },
    #[error(
        "the approach {approach_m:.6e} m reaches or passes full contact of the periodic map \
         (max height − mean height = {limit_m:.6e} m): no pressure closes a negative mean gap"
    )]
    BeyondFullContact { approach_m: f64, limit_m: f64 },
    #[error("heights and the influence operator differ in size ({heights} vs {grid} points)")]
    Size { heights: usize, grid: usize },
    #[error("no height is measured (every value is NaN)")]
    NoPoints,
    #[error("point {index} holds the height {value} (finite or NaN expected)")]
    BadHeight { index: usize, value: f64 },
    #[error("the warm start has {warm} points, the map {grid}")]
    WarmStart { warm: usize, grid: usize },
    #[error("the control value {0} is negative or not finite")]
    BadControl(f64),
}

/// A height map prepared once for many solves.
pub struct Problem<'a> {
    influence: &'a Influence,
    /// Heights with NaN replaced by −∞ (a point that never reaches the plane).
    heights_m: Vec<f64>,
    top_m: f64,
    measured: usize,
    sigma_m: f64,
    /// See [`Problem::full_contact_approach_m`].
    full_contact_m: Option<f64>,
    /// The preconditioner's correction on a set.
    complement: Complement,
}

impl<'a> Problem<'a> {
    pub fn new(influence: &'a Influence, heights_m: &[f64]) -> Result<Self, SolveError> {
        let (nx, ny) = influence.dim();
        if heights_m.len() != nx * ny {
            return Err(SolveError::Size {
                heights: heights_m.len(),
                grid: nx * ny,
            });
        }
        if let Some(index) = heights_m.iter().position(|h| h.is_infinite()) {
            return Err(SolveError::BadHeight {
                index,
                value: heights_m[index],
            });
        }
        let heights_m: Vec<f64> = heights_m
            .iter()
            .map(|&h| if h.is_nan() { f64::NEG_INFINITY } else { h })
            .collect();
        let measured = heights_m.iter().filter(|h| h.is_finite()).count();
        if measured == 0 {
            return Err(SolveError::NoPoints);
        }
        let top_m = heights_m.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let finite = |i: usize| heights_m[i].is_finite();
        let [total] = sums(heights_m.len(), |i| {
            [if finite(i) { heights_m[i] } else { 0.0 }]
        });
        let mean = total / measured as f64;
        let [square] = sums(heights_m.len(), |i| {
            [if finite(i) {
                (heights_m[i] - mean).powi(2)
            } else {
                0.0
            }]
        });
        let everywhere = measured == heights_m.len();
        let periodic = influence.boundary() == Boundary::Periodic;
        Ok(Self {
            influence,
            heights_m,
            top_m,
            measured,
            sigma_m: (square / measured as f64).sqrt(),
            full_contact_m: (periodic && everywhere).then_some(top_m - mean),
            complement: Complement::new(influence),
        })
    }

    /// The highest measured height, m.
    pub fn top_m(&self) -> f64 {
        self.top_m
    }

    /// The heights, −∞ where none was measured, m.
    pub fn heights_m(&self) -> &[f64] {
        &self.heights_m
    }

    /// Measured (non-NaN) points.
    pub fn measured(&self) -> usize {
        self.measured
    }

    /// The rms height about the mean of the measured points, m.
    pub fn sigma_m(&self) -> f64 {
        self.sigma_m
    }

    /// The approach of full contact, max h − mean h, m, beyond which an
    /// approach has no solution: for a periodic map measured everywhere
    /// (u has zero mean there, so the mean gap is fixed by δ alone); None
    /// otherwise (a free map takes any approach; with unmeasured points the
    /// mean of u over the measured ones is not fixed).
    pub fn full_contact_approach_m(&self) -> Option<f64> {
        self.full_contact_m
    }

    /// Solves for the pressure, starting from `warm` (a previous solution's
    /// pressure, or None for the PK start).
    pub fn solve(
        &self,
        control: Control,
        options: SolverOptions,
        warm: Option<&[f64]>,
    ) -> Result<Solution, SolveError> {
        let mut it = Iterate::new(self.start_pressure(control, warm)?, self.influence);
        let load_control = matches!(control, Control::MeanPressure(_));
        let target_sum = self.target_sum(control);
        let pre = options.preconditioned;
        let mut iteration = 0;
        loop {
            if it.stale {
                self.influence.apply(&it.p, &mut it.u, &mut it.work);
                (it.stale, it.updated) = (false, false);
            }
            let plane_m = self.plane_m(control, &it);
            let [contact, entering, violation] = self.gap(plane_m, &mut it);
            let approach_m = self.top_m - plane_m;
            let residual = self.residual(contact + entering, violation, approach_m);
            if residual <= options.tolerance || target_sum == Some(0.0) {
                if !it.updated {
                    return Ok(self.solution(it.p, it.g, approach_m, iteration, residual));
                }
                // Converged on an updated u: check it on a computed one.
                it.stale = true;
                continue;
            }
            if iteration >= options.max_iterations {
                let p = &it.p;
                return Err(SolveError::NotConverged {
                    iterations: iteration,
                    residual,
                    tolerance: options.tolerance,
                    mean_pressure: sum(p.len(), |i| p[i]) / self.measured as f64,
                });
            }
            iteration += 1;

            if contact == 0.0 && !pre {
                self.close_overlaps_alone(&mut it);
                continue;
            }
            // The set the direction lives on: the contact, and under the
            // preconditioner the overlapping points too.
            let count = contact + if pre { entering } else { 0.0 };
            let rhos = self.direction(&mut it, pre, load_control, count);
            let tau = self.step_length(&mut it, rhos, pre, load_control, count);
            if !(tau.is_finite() && tau > 0.0) {
                return Err(SolveError::Breakdown { iteration });
            }
            it.rho_old = rhos.0;
            let follow = !load_control && (pre || entering == 0.0);
            let clipped = self.step(&mut it, tau, follow);
            it.conjugate = pre || entering == 0.0;
            if let Some(target) = target_sum {
                rescale(&mut it.p, target, &self.heights_m);
                it.stale = true;
            } else if follow && clipped.len() <= DIRECT_CLIPS {
                // p moved by −τ t plus the clipped amounts: so does u.
                self.influence.add_point_loads(&clipped, &mut it.u);
                it.updated = true;
            } else {
                it.stale = true;
            }
        }
    }

    /// The checked warm start, or PK's start, scaled to the load under load
    /// control.
    fn start_pressure(
        &self,
        control: Control,
        warm: Option<&[f64]>,
    ) -> Result<Vec<f64>, SolveError> {
        let n = self.heights_m.len();
        let value = match control {
            Control::Approach(v) | Control::MeanPressure(v) => v,
        };
        if !(value >= 0.0 && value.is_finite()) {
            return Err(SolveError::BadControl(value));
        }
        // (A flat map is in full contact at δ = 0, under no pressure.)
        if let (Control::Approach(approach_m), Some(limit_m)) = (control, self.full_contact_m)
            && approach_m >= limit_m
            && approach_m > 0.0
        {
            return Err(SolveError::BeyondFullContact {
                approach_m,
                limit_m,
            });
        }
        let h = &self.heights_m;
        let mut p = match warm {
            Some(w) if w.len() != n => {
                return Err(SolveError::WarmStart {
                    warm: w.len(),
                    grid: n,
                });
            }
            Some(w) => w
                .iter()
                .zip(h)
                .map(|(&p, h)| if h.is_finite() { p.max(0.0) } else { 0.0 })
                .collect(),
            None => match control {
                // PK's start: the load spread over every measured point.
                Control::MeanPressure(_) => h
                    .iter()
                    .map(|h| if h.is_finite() { 1.0 } else { 0.0 })
                    .collect(),
                Control::Approach(_) => vec![0.0; n],
            },
        };
        if let Some(target) = self.target_sum(control) {
            rescale(&mut p, target, h);
        }
        Ok(p)
    }

    /// Σ p prescribed by a load control.
    fn target_sum(&self, control: Control) -> Option<f64> {
        match control {
            Control::MeanPressure(mean) => Some(mean * self.measured as f64),
            Control::Approach(_) => None,
        }
    }

    /// The rigid plane's height: where the approach puts it, or (load
    /// control) the mean of h − u over the contact set.
    fn plane_m(&self, control: Control, it: &Iterate) -> f64 {
        match control {
            Control::Approach(delta) => self.top_m - delta,
            Control::MeanPressure(_) => {
                let (h, p, u) = (&self.heights_m, &it.p, &it.u);
                let [count, sum_hu] = sums(p.len(), |i| {
                    if p[i] > 0.0 {
                        [1.0, h[i] - u[i]]
                    } else {
                        [0.0, 0.0]
                    }
                });
                if count > 0.0 {
                    sum_hu / count
                } else {
                    self.top_m
                }
            }
        }
    }

    /// The gap g = plane − h + u into `it.g`, with the counts of the
    /// contact set and of the overlapping points off it, and the sum of the
    /// squared complementarity violation.
    fn gap(&self, plane_m: f64, it: &mut Iterate) -> [f64; 3] {
        let (h, p, u) = (&self.heights_m, &it.p, &it.u);
        fill_sums(&mut it.g, |i| {
            let g = plane_m - h[i] + u[i];
            let terms = if p[i] > 0.0 {
                [1.0, 0.0, g * g]
            } else if g < 0.0 {
                [0.0, 1.0, g * g]
            } else {
                [0.0, 0.0, 0.0]
            };
            (g, terms)
        })
    }

    /// Nothing in contact yet (approach control from p = 0, PK as
    /// published): each overlapping point alone closes its own overlap.
    fn close_overlaps_alone(&self, it: &mut Iterate) {
        let stiffness = 1.0 / self.influence.self_displacement_m();
        it.p.par_iter_mut()
            .zip(&it.g)
            .for_each(|(p, &g)| *p = if g < 0.0 { -g * stiffness } else { 0.0 });
        it.conjugate = false;
        it.stale = true;
    }

    /// The direction before conjugation into `it.z`, on the set `it.active`
    /// (made here): the gap there (PK), or the gap through the
    /// preconditioner corrected for the points off the set
    /// ([`crate::complement`]; M_AA alone where that is not a descent
    /// direction); under load control centred on the set, so that a step
    /// keeps the load. Returns ρ = Σ g z and Polak–Ribière's
    /// Σ (g − g_old) z (g_old: the last direction's gap on its set).
    fn direction(&self, it: &mut Iterate, pre: bool, load_control: bool, count: f64) -> (f64, f64) {
        std::mem::swap(&mut it.masked, &mut it.masked_old);
        it.masked
            .par_iter_mut()
            .zip(it.active.par_iter_mut())
            .zip(&it.p)
            .zip(&it.g)
            .for_each(|(((m, a), &p), &g)| {
                *a = p > 0.0 || (pre && g < 0.0);
                *m = if *a { g } else { 0.0 };
            });
        if !pre {
            return self.fill_direction(it, Source::Gap, load_control, count);
        }
        self.influence
            .precondition(&it.masked, &mut it.r, &mut it.work);
        let with = (self.influence, &mut it.work);
        (self.complement).correction(with, &it.active, &it.r, &mut it.s, &mut it.y);
        let rhos = self.fill_direction(it, Source::Corrected, load_control, count);
        if rhos.0 > 0.0 {
            rhos
        } else {
            self.fill_direction(it, Source::Preconditioned, load_control, count)
        }
    }

    /// `it.z` from `source` on the set (centred under load control), with
    /// ρ and Polak–Ribière's numerator (see [`Problem::direction`]).
    fn fill_direction(
        &self,
        it: &mut Iterate,
        source: Source,
        load_control: bool,
        count: f64,
    ) -> (f64, f64) {
        let (active, g, g_old) = (&it.active, &it.g, &it.masked_old);
        let (masked, r, s) = (&it.masked, &it.r, &it.s);
        let value = |i: usize| match source {
            Source::Gap => masked[i],
            Source::Preconditioned => r[i],
            Source::Corrected => r[i] - s[i],
        };
        // (Off the set g may be +∞: an unmeasured point.)
        let [z_sum, gz, g_sum, g_old_z, g_old_sum] = fill_sums(&mut it.z, |i| {
            if active[i] {
                let v = value(i);
                (v, [v, g[i] * v, g[i], g_old[i] * v, g_old[i]])
            } else {
                (0.0, [0.0; 5])
            }
        });
        if load_control {
            // Keep the load: directions of zero sum on the set.
            let z_mean = z_sum / count;
            it.z.par_iter_mut().zip(active).for_each(|(z, &a)| {
                if a {
                    *z -= z_mean
                }
            });
            let rho = gz - z_mean * g_sum;
            (rho, rho - (g_old_z - z_mean * g_old_sum))
        } else {
            (gz, gz - g_old_z)
        }
    }

    /// The conjugate direction into `it.t` (and r = K t into `it.r`) and
    /// the step τ along it; if it is not a descent direction (the set
    /// changed under it), the steepest one's, found out before the
    /// convolution (τ has the sign of Σ g t: the denominator is tᵀ K t on
    /// the set). β is Fletcher–Reeves' ρ / ρ_old for PK as published, and
    /// with the preconditioner Polak–Ribière's, clipped at zero
    /// (max(Σ (g − g_old) z, 0) / ρ_old: J. C. Gilbert and J. Nocedal, SIAM
    /// J. Optim. 2 (1992) 21–42), which restarts by itself when the set's
    /// changes have spoilt conjugacy. NaN or τ ≤ 0 is a breakdown.
    fn step_length(
        &self,
        it: &mut Iterate,
        (rho, rho_pr): (f64, f64),
        pre: bool,
        load_control: bool,
        count: f64,
    ) -> f64 {
        let mut tau = f64::NAN;
        for restart in [false, true] {
            if restart && !it.conjugate {
                break;
            }
            let beta = match (it.conjugate && !restart, pre) {
                (false, _) => 0.0,
                (true, false) => rho / it.rho_old,
                (true, true) => rho_pr.max(0.0) / it.rho_old,
            };
            let (active, g, z, t) = (&it.active, &it.g, &it.z, &it.t);
            // The new direction into r (free until K t), then swapped in.
            let [gt] = fill_sums(&mut it.r, |i| {
                if active[i] {
                    let v = z[i] + beta * t[i];
                    (v, [g[i] * v])
                } else {
                    (0.0, [0.0])
                }
            });
            std::mem::swap(&mut it.t, &mut it.r);
            let descent = gt > 0.0;
            if !descent && !restart && it.conjugate {
                continue;
            }
            self.influence.apply(&it.t, &mut it.r, &mut it.work);
            let (active, t, r) = (&it.active, &it.t, &it.r);
            let [r_sum, rt] = sums(t.len(), |i| {
                if active[i] {
                    [r[i], r[i] * t[i]]
                } else {
                    [0.0, 0.0]
                }
            });
            // Under load control r is centred on the set: Σ (r − r̄) t.
            let t_sum = if load_control {
                sum(t.len(), |i| t[i])
            } else {
                0.0
            };
            tau = gt / (rt - r_sum / count * t_sum);
            if tau.is_finite() && tau > 0.0 {
                break;
            }
        }
        tau
    }

    /// p ← max(p − τ t, 0) on the set, PK's points entering at −τ g off it,
    /// and u ← u − τ r when u follows the step; returns the clipped points
    /// and by how much they were clipped, in index order.
    fn step(&self, it: &mut Iterate, tau: f64, follow: bool) -> Vec<(usize, f64)> {
        let (active, g, t, r) = (&it.active, &it.g, &it.t, &it.r);
        it.p.par_chunks_mut(CHUNK)
            .zip(it.u.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (ps, us))| {
                let mut clipped = Vec::new();
                for (k, (p, u)) in ps.iter_mut().zip(us).enumerate() {
                    let i = c * CHUNK + k;
                    if active[i] {
                        let stepped = *p - tau * t[i];
                        if stepped < 0.0 {
                            clipped.push((i, -stepped));
                        }
                        *p = stepped.max(0.0);
                    } else {
                        *p = if g[i] < 0.0 { -tau * g[i] } else { 0.0 };
                    }
                    if follow {
                        *u -= tau * r[i];
                    }
                }
                clipped
            })
            .collect::<Vec<_>>()
            .concat()
    }

    /// See [`Solution::residual`]: from the count of the points where the
    /// violation can be non-zero and the sum of its squares.
    fn residual(&self, count: f64, violation: f64, approach_m: f64) -> f64 {
        if count == 0.0 {
            return 0.0;
        }
        let scale = if approach_m > 0.0 {
            approach_m
        } else if self.sigma_m > 0.0 {
            self.sigma_m
        } else {
            1.0
        };
        (violation / count).sqrt() / scale
    }

    fn solution(
        &self,
        pressure: Vec<f64>,
        mut gap_m: Vec<f64>,
        approach_m: f64,
        iterations: usize,
        residual: f64,
    ) -> Solution {
        gap_m
            .par_iter_mut()
            .zip(&self.heights_m)
            .for_each(|(g, h)| {
                if !h.is_finite() {
                    *g = f64::NAN;
                }
            });
        let [total, contact] = sums(pressure.len(), |i| {
            [pressure[i], if pressure[i] > 0.0 { 1.0 } else { 0.0 }]
        });
        Solution {
            mean_pressure: total / self.measured as f64,
            contact_pixels: contact as usize,
            pressure,
            gap_m,
            approach_m,
            iterations,
            residual,
        }
    }
}

/// Where a direction comes from (see [`Problem::direction`]).
#[derive(Clone, Copy)]
enum Source {
    /// the gap on the set (PK as published)
    Gap,
    /// M_AA g
    Preconditioned,
    /// M_AA g less the complement correction
    Corrected,
}

/// The iterate of a solve and the buffers its steps share.
struct Iterate {
    /// pressure, displacement K p, gap, conjugate direction, K t, the
    /// direction before conjugation, the gap on the set
    p: Vec<f64>,
    u: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    masked: Vec<f64>,
    /// the last direction's masked gap (Polak–Ribière)
    masked_old: Vec<f64>,
    /// the complement correction and its work buffer
    s: Vec<f64>,
    y: Vec<f64>,
    /// the set the direction lives on
    active: Vec<bool>,
    work: crate::influence::Workspace,
    /// u is stale (to compute from p)
    stale: bool,
    /// u is valid but was updated rather than computed (to compute before
    /// convergence is declared)
    updated: bool,
    /// the next direction is conjugated to the last
    conjugate: bool,
    /// ρ of the last step
    rho_old: f64,
}

impl Iterate {
    fn new(p: Vec<f64>, influence: &Influence) -> Self {
        let n = p.len();
        let [u, g, t, r, z, masked, masked_old, s, y] = std::array::from_fn(|_| vec![0.0; n]);
        Self {
            p,
            u,
            g,
            t,
            r,
            z,
            masked,
            masked_old,
            s,
            y,
            active: vec![false; n],
            work: influence.workspace(),
            stale: true,
            updated: false,
            conjugate: false,
            rho_old: 1.0,
        }
    }
}

/// Scales p so that Σ p = target (nothing to scale when Σ p = 0: then the
/// load goes to every measured point evenly, PK's start).
fn rescale(p: &mut [f64], target: f64, heights_m: &[f64]) {
    let total = sum(p.len(), |i| p[i]);
    if total > 0.0 {
        let factor = target / total;
        p.par_iter_mut().for_each(|p| *p *= factor);
    } else {
        let measured = heights_m.iter().filter(|h| h.is_finite()).count() as f64;
        p.par_iter_mut().zip(heights_m).for_each(|(p, h)| {
            *p = if h.is_finite() {
                target / measured
            } else {
                0.0
            }
        });
    }
}
