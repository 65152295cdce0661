//! Harmonic in-filling of missing points (NaN) before a Fourier transform:
//! the missing heights solve the discrete Laplace equation ∇²h = 0 with the
//! measured heights as Dirichlet data.
//!
//! The convention is SurfaceTopography's `interpolate_undefined_data`
//! (`Uniform/Imputation.py`): a 5-point stencil over the four nearest
//! neighbours; at the edge of a non-periodic map the legs leaving the map
//! are dropped, which is a vanishing normal derivative (Neumann); a periodic
//! map wraps around. One difference: legs are weighted 1/Δx² and 1/Δy², so
//! the stencil is the Laplacian also on non-square pixels (SurfaceTopography
//! weights all legs 1; the two agree when Δx = Δy).
//!
//! For every missing point p: Σ_n w_pn (h_p − h_n) = 0. The unknowns are the
//! missing points only; the matrix (diagonal Σ w, off-diagonal −w between
//! missing neighbours) is symmetric positive definite when every connected
//! missing region touches a measured point, which holds unless nothing was
//! measured. It is solved by conjugate gradients preconditioned with
//! symmetric successive over-relaxation (SSOR), to a relative residual of
//! [`TOLERANCE`]; a solve that does not get there is an error, never a
//! silent early stop.

use ndarray::Array2;

/// Relative residual ‖b − A u‖ / ‖b‖ at which the solve stops.
pub const TOLERANCE: f64 = 1e-12;

/// What the fill did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Infill {
    /// Points that were NaN and now hold a height.
    pub filled: usize,
    /// Conjugate-gradient iterations.
    pub iterations: usize,
    /// Final relative residual (recomputed from the solution, not the
    /// recursion's estimate).
    pub relative_residual: f64,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum InfillError {
    #[error("every point of the map is missing: nothing to in-fill from")]
    NothingMeasured,
    #[error("a measured height is not finite ({value} at [{i}, {j}]): cannot in-fill from it")]
    NotFinite { value: f64, i: usize, j: usize },
    #[error(
        "harmonic in-fill of {unknowns} missing points did not converge: relative residual \
         {relative_residual:e} after {iterations} iterations (wanted {TOLERANCE:e})"
    )]
    NotConverged {
        unknowns: usize,
        iterations: usize,
        relative_residual: f64,
    },
}

/// No missing neighbour in this slot of [`System::neighbours`].
const NONE: u32 = u32::MAX;

/// The Laplace system on the missing points: row p couples the unknown p to
/// its missing neighbours (slots 0, 1 along x with weight wx; 2, 3 along y
/// with weight wy).
struct System {
    diagonal: Vec<f64>,
    neighbours: Vec<[u32; 4]>,
    weights: [f64; 4],
}

/// Replaces every NaN of `h` (spacing dx, dy) by the harmonic in-fill of
/// the measured points. A map without NaN is left as it is.
pub fn fill_harmonic(
    h: &mut Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    periodic: bool,
) -> Result<Infill, InfillError> {
    let missing = h.iter().filter(|v| v.is_nan()).count();
    if missing == 0 {
        return Ok(Infill {
            filled: 0,
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    if missing == h.len() {
        return Err(InfillError::NothingMeasured);
    }
    if let Some(((i, j), &value)) = h.indexed_iter().find(|(_, v)| v.is_infinite()) {
        return Err(InfillError::NotFinite { value, i, j });
    }
    let problem = Problem::assemble(h, dx_m, dy_m, periodic, missing);
    let solution = problem.system.solve(&problem.b)?;
    for (&(i, j), v) in problem.position.iter().zip(&solution.u) {
        h[[i, j]] = v + problem.offset;
    }
    Ok(Infill {
        filled: missing,
        iterations: solution.iterations,
        relative_residual: solution.relative_residual,
    })
}

/// The Laplace problem on the missing points of a map.
struct Problem {
    system: System,
    /// Map index of each unknown, in row-major order.
    position: Vec<(usize, usize)>,
    /// Right-hand side: the measured neighbours' pull, about `offset`.
    b: Vec<f64>,
    /// Weighted mean of the measured neighbours' heights.
    offset: f64,
}

impl Problem {
    /// The rows of the system for the `missing` NaN points of `h`; the
    /// measured neighbours go to the right-hand side, taken about their
    /// mean so that the tolerance is relative to the roughness, not to an
    /// offset (and a constant fills exactly).
    fn assemble(h: &Array2<f64>, dx_m: f64, dy_m: f64, periodic: bool, missing: usize) -> Self {
        let (nx, ny) = h.dim();
        // Unknowns numbered in row-major order.
        let mut index = vec![NONE; nx * ny];
        let mut position = Vec::with_capacity(missing);
        for ((i, j), v) in h.indexed_iter() {
            if v.is_nan() {
                index[i * ny + j] = position.len() as u32;
                position.push((i, j));
            }
        }
        let (wx, wy) = (1.0 / (dx_m * dx_m), 1.0 / (dy_m * dy_m));
        let step = |k: usize, n: usize, forward: bool| -> Option<usize> {
            match (forward, periodic) {
                (true, _) if k + 1 < n => Some(k + 1),
                (false, _) if k > 0 => Some(k - 1),
                (true, true) => Some(0),
                (false, true) => Some(n - 1),
                _ => None,
            }
        };
        let mut diagonal = vec![0.0; missing];
        let mut neighbours = vec![[NONE; 4]; missing];
        // (unknown, weight, measured height) per leg onto a measured point.
        let mut known: Vec<(usize, f64, f64)> = Vec::new();
        for (p, &(i, j)) in position.iter().enumerate() {
            let legs = [
                step(i, nx, false).map(|a| (a, j)),
                step(i, nx, true).map(|a| (a, j)),
                step(j, ny, false).map(|b| (i, b)),
                step(j, ny, true).map(|b| (i, b)),
            ];
            for (slot, leg) in legs.into_iter().enumerate() {
                // A periodic axis of length 1 wraps onto the point itself.
                let Some((a, b)) = leg.filter(|&n| n != (i, j)) else {
                    continue;
                };
                let w = if slot < 2 { wx } else { wy };
                diagonal[p] += w;
                match index[a * ny + b] {
                    NONE => known.push((p, w, h[[a, b]])),
                    n => neighbours[p][slot] = n,
                }
            }
        }
        let boundary_weight: f64 = known.iter().map(|k| k.1).sum();
        let offset = known.iter().map(|k| k.1 * k.2).sum::<f64>() / boundary_weight;
        let mut b = vec![0.0; missing];
        for (p, w, value) in known {
            b[p] += w * (value - offset);
        }
        Self {
            system: System {
                diagonal,
                neighbours,
                weights: [wx, wx, wy, wy],
            },
            position,
            b,
            offset,
        }
    }
}

/// The in-fill heights (about the offset) and how the solve went.
struct Solution {
    u: Vec<f64>,
    iterations: usize,
    relative_residual: f64,
}

impl System {
    /// Solves A u = b by SSOR-preconditioned conjugate gradients to
    /// [`TOLERANCE`]; an error when the true residual stays above it.
    fn solve(&self, b: &[f64]) -> Result<Solution, InfillError> {
        let missing = b.len();
        let mut u = vec![0.0; missing];
        let b_norm = dot(b, b).sqrt();
        let mut iterations = 0;
        let mut relative_residual = 0.0;
        if b_norm > 0.0 {
            // SSOR's best ω for a Laplacian over a region m points wide is
            // 2 / (1 + π/m); m from the number of unknowns (a square hole).
            let width = (missing as f64).sqrt().max(1.0);
            let omega = 2.0 / (1.0 + std::f64::consts::PI / width);
            let mut r = b.to_vec();
            let mut z = vec![0.0; missing];
            let mut ap = vec![0.0; missing];
            self.precondition(omega, &r, &mut z);
            let mut d = z.clone();
            let mut rz = dot(&r, &z);
            // CG ends in at most `missing` steps in exact arithmetic; the slack
            // is for rounding.
            let limit = missing + 1000;
            loop {
                relative_residual = dot(&r, &r).sqrt() / b_norm;
                if relative_residual <= TOLERANCE || iterations == limit {
                    break;
                }
                iterations += 1;
                self.apply(&d, &mut ap);
                let alpha = rz / dot(&d, &ap);
                for k in 0..missing {
                    u[k] += alpha * d[k];
                    r[k] -= alpha * ap[k];
                }
                self.precondition(omega, &r, &mut z);
                let rz_next = dot(&r, &z);
                let beta = rz_next / rz;
                rz = rz_next;
                for k in 0..missing {
                    d[k] = z[k] + beta * d[k];
                }
            }
            // The recursion's residual drifts from the true one by rounding:
            // judge convergence on b − A u itself.
            self.apply(&u, &mut ap);
            let true_residual = b
                .iter()
                .zip(&ap)
                .map(|(b, a)| (b - a).powi(2))
                .sum::<f64>()
                .sqrt();
            relative_residual = relative_residual.max(true_residual / b_norm);
            if relative_residual > 10.0 * TOLERANCE || !relative_residual.is_finite() {
                return Err(InfillError::NotConverged {
                    unknowns: missing,
                    iterations,
                    relative_residual,
                });
            }
        }
        Ok(Solution {
            u,
            iterations,
            relative_residual,
        })
    }

    /// y = A u.
    fn apply(&self, u: &[f64], y: &mut [f64]) {
        for (p, (out, nbrs)) in y.iter_mut().zip(&self.neighbours).enumerate() {
            let mut sum = self.diagonal[p] * u[p];
            for (&n, w) in nbrs.iter().zip(&self.weights) {
                if n != NONE {
                    sum -= w * u[n as usize];
                }
            }
            *out = sum;
        }
    }

    /// z = M⁻¹ r for the SSOR preconditioner
    /// M = (D + ωL) D⁻¹ (D + ωU) / (ω (2 − ω)), L and U the strictly lower
    /// and upper parts of A in unknown order.
    fn precondition(&self, omega: f64, r: &[f64], z: &mut [f64]) {
        for p in 0..z.len() {
            let mut sum = r[p];
            for (&n, w) in self.neighbours[p].iter().zip(&self.weights) {
                if n != NONE && (n as usize) < p {
                    sum += omega * w * z[n as usize];
                }
            }
            z[p] = sum / self.diagonal[p];
        }
        z.iter_mut().zip(&self.diagonal).for_each(|(v, d)| *v *= d);
        for p in (0..z.len()).rev() {
            let mut sum = z[p];
            for (&n, w) in self.neighbours[p].iter().zip(&self.weights) {
                if n != NONE && (n as usize) > p {
                    sum += omega * w * z[n as usize];
                }
            }
            z[p] = sum / self.diagonal[p];
        }
        let scale = omega * (2.0 - omega);
        z.iter_mut().for_each(|v| *v *= scale);
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Replaces every NaN of `h` by zero (the mean of a detrended map): the
/// fill before harmonic in-filling, kept to reproduce old runs.
pub fn fill_zero(h: &mut Array2<f64>) -> usize {
    let mut filled = 0;
    for v in h.iter_mut().filter(|v| v.is_nan()) {
        *v = 0.0;
        filled += 1;
    }
    filled
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Largest |a − b| over the points that were missing in `holes`.
    fn max_error(filled: &Array2<f64>, exact: &Array2<f64>, holes: &Array2<f64>) -> f64 {
        filled
            .iter()
            .zip(exact)
            .zip(holes)
            .filter(|(_, h)| h.is_nan())
            .map(|((f, e), _)| (f - e).abs())
            .fold(0.0, f64::max)
    }

    /// `exact` with NaN wherever `cut` says so.
    fn cut_out(exact: &Array2<f64>, cut: impl Fn(usize, usize) -> bool) -> Array2<f64> {
        let mut h = exact.clone();
        for ((i, j), v) in h.indexed_iter_mut() {
            if cut(i, j) {
                *v = f64::NAN;
            }
        }
        h
    }

    /// Deterministic pseudo-random numbers in [0, 1).
    fn uniform(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// h = cos(θ(i + ½)) cosh(μ(ny − ½ − j)) with θ = πk/nx and
    /// cosh μ = 1 + (wx/wy)(1 − cos θ): the 5-point stencil vanishes on it
    /// at every point, including the dropped legs at the x edges and at
    /// j = ny − 1 (a cell-centred cosine has zero difference across them).
    /// Only the edge j = 0 is not Neumann, so it must stay measured.
    fn neumann_harmonic(nx: usize, ny: usize, k: f64, dx: f64, dy: f64) -> Array2<f64> {
        let theta = std::f64::consts::PI * k / nx as f64;
        let mu = (1.0 + (dy * dy) / (dx * dx) * (1.0 - theta.cos())).acosh();
        Array2::from_shape_fn((nx, ny), |(i, j)| {
            (theta * (i as f64 + 0.5)).cos() * (mu * (ny as f64 - 0.5 - j as f64)).cosh()
        })
    }

    #[test]
    fn a_harmonic_function_is_reproduced_in_its_holes() {
        // x² − y² on non-square pixels: its 5-point Laplacian weighted
        // 1/Δx², 1/Δy² is exactly 2 − 2 = 0.
        let (nx, ny, dx, dy) = (120, 90, 1.5e-6, 1e-6);
        let exact = Array2::from_shape_fn((nx, ny), |(i, j)| {
            let (x, y) = ((i as f64 - 40.0) * dx, (j as f64 - 50.0) * dy);
            (x * x - y * y) / 1e-4
        });
        let mut state = 3;
        let scattered: Vec<bool> = (0..nx * ny).map(|_| uniform(&mut state) < 0.05).collect();
        let holes = cut_out(&exact, |i, j| {
            let disk = (i as f64 - 60.0).hypot(j as f64 - 45.0) < 25.0;
            let inside = i > 0 && j > 0 && i < nx - 1 && j < ny - 1;
            inside && (disk || scattered[i * ny + j])
        });
        let mut h = holes.clone();
        let fill = fill_harmonic(&mut h, dx, dy, false).unwrap();
        assert!(fill.filled > 1900 && fill.relative_residual <= TOLERANCE * 10.0);
        let scale = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let error = max_error(&h, &exact, &holes);
        assert!(error < 1e-9 * scale, "{error} of {scale}");
        // Unmeasured points only: the measured ones are untouched.
        for ((f, e), m) in h.iter().zip(&exact).zip(&holes) {
            if !m.is_nan() {
                assert_eq!(f, e);
            }
        }
    }

    #[test]
    fn constants_fill_constant_and_planes_fill_the_plane() {
        let constant = Array2::from_elem((50, 40), 7.5e-6);
        let cut = |i: usize, j: usize| (10..30).contains(&i) && (5..35).contains(&j) || i == 45;
        let mut h = cut_out(&constant, cut);
        let fill = fill_harmonic(&mut h, 1e-6, 1e-6, false).unwrap();
        assert_eq!(fill.iterations, 0);
        assert!(h.iter().all(|v| *v == 7.5e-6));

        // A plane is harmonic; the hole stays off the edges, where the
        // Neumann condition would bend it.
        let plane = Array2::from_shape_fn((50, 40), |(i, j)| {
            3e-6 + 2e-3 * i as f64 * 1e-6 - 5e-4 * j as f64 * 2e-6
        });
        let holes = cut_out(&plane, |i, j| (10..30).contains(&i) && (5..35).contains(&j));
        let mut h = holes.clone();
        fill_harmonic(&mut h, 1e-6, 2e-6, false).unwrap();
        let error = max_error(&h, &plane, &holes);
        assert!(error < 1e-9 * 3e-6, "{error}");
    }

    #[test]
    fn holes_touching_the_edge_meet_the_neumann_condition() {
        let (nx, ny, dx, dy) = (64, 48, 2e-6, 1e-6);
        let exact = neumann_harmonic(nx, ny, 3.0, dx, dy);
        // A hole over the corner i = 0, j = ny − 1, and a band across the
        // whole map in x (touching both x edges).
        let holes = cut_out(&exact, |i, j| (i < 20 && j > 30) || (10..14).contains(&j));
        let mut h = holes.clone();
        fill_harmonic(&mut h, dx, dy, false).unwrap();
        let scale = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let error = max_error(&h, &exact, &holes);
        assert!(error < 1e-9 * scale, "{error} of {scale}");
    }

    #[test]
    fn a_map_measured_on_one_row_only_fills_from_it() {
        // Everything missing but the row j = 0: the fill is the Neumann
        // harmonic function with that row's values, cosh profile in y.
        let (nx, ny, dx, dy) = (40, 30, 1e-6, 1e-6);
        let exact = neumann_harmonic(nx, ny, 2.0, dx, dy);
        let holes = cut_out(&exact, |_, j| j > 0);
        let mut h = holes.clone();
        let fill = fill_harmonic(&mut h, dx, dy, false).unwrap();
        assert_eq!(fill.filled, nx * (ny - 1));
        let scale = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let error = max_error(&h, &exact, &holes);
        assert!(error < 1e-9 * scale, "{error} of {scale}");
    }

    #[test]
    fn periodic_maps_wrap_around() {
        // cos(2πk i/nx) cosh(μ j) is harmonic on a map periodic in x; a hole
        // across the x seam is filled from both sides.
        let (nx, ny, k) = (48usize, 40usize, 2.0);
        let theta = std::f64::consts::TAU * k / nx as f64;
        let mu = (2.0 - theta.cos()).acosh();
        let exact = Array2::from_shape_fn((nx, ny), |(i, j)| {
            (theta * i as f64).cos() * (mu * (j as f64 - 20.0)).cosh()
        });
        let holes = cut_out(&exact, |i, j| {
            (i < 6 || i > nx - 7) && (10..30).contains(&j)
        });
        let mut h = holes.clone();
        fill_harmonic(&mut h, 1e-6, 1e-6, true).unwrap();
        let scale = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(max_error(&h, &exact, &holes) < 1e-9 * scale);
        // The same hole without wrapping is filled differently.
        let mut open = holes.clone();
        fill_harmonic(&mut open, 1e-6, 1e-6, false).unwrap();
        assert!(max_error(&open, &exact, &holes) > 1e-3 * scale);
    }

    #[test]
    fn a_megapixel_map_with_a_large_hole_fills_in_under_a_second() {
        // Issue #17's case: 1 % scattered missing points and one 100 × 100
        // hole on a 1024² map.
        let n = 1024;
        let mut state = 17;
        let mut h = Array2::from_shape_fn((n, n), |(i, j)| {
            1e-6 * ((i as f64 * 0.05).sin() + (j as f64 * 0.031).cos()) + 1e-8 * uniform(&mut state)
        });
        for ((i, j), v) in h.indexed_iter_mut() {
            let hole = (400..500).contains(&i) && (600..700).contains(&j);
            if hole || uniform(&mut state) < 0.01 {
                *v = f64::NAN;
            }
        }
        let start = std::time::Instant::now();
        let fill = fill_harmonic(&mut h, 1e-6, 1e-6, false).unwrap();
        let seconds = start.elapsed().as_secs_f64();
        eprintln!(
            "in-fill of {} points on 1024²: {seconds:.3} s, {} iterations",
            fill.filled, fill.iterations
        );
        assert!(fill.filled > 20_000);
        assert!(h.iter().all(|v| v.is_finite()));
        assert!(seconds < 1.0, "{seconds} s");
    }

    #[test]
    fn nothing_measured_and_infinite_heights_are_errors() {
        let mut h = Array2::from_elem((4, 5), f64::NAN);
        assert_eq!(
            fill_harmonic(&mut h, 1.0, 1.0, false),
            Err(InfillError::NothingMeasured)
        );
        h[[1, 2]] = f64::INFINITY;
        let e = fill_harmonic(&mut h, 1.0, 1.0, false).unwrap_err();
        assert!(e.to_string().contains("inf at [1, 2]"), "{e}");
        let mut full = Array2::from_elem((3, 3), 1.0);
        let fill = fill_harmonic(&mut full, 1.0, 1.0, false).unwrap();
        assert_eq!(fill.filled, 0);
        let mut zero = Array2::from_elem((3, 3), f64::NAN);
        zero[[0, 0]] = 2.0;
        assert_eq!(fill_zero(&mut zero), 8);
        assert_eq!(zero.sum(), 2.0);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Any shape (also one point wide, periodic or not), any mask with
        /// a measured point: a finite fill bounded by the measured range
        /// (the discrete maximum principle), never a panic.
        #[test]
        fn any_mask_fills_within_the_measured_range(
            nx in 1usize..12,
            ny in 1usize..12,
            periodic: bool,
            seed: u64,
            missing in 0.0f64..1.0,
        ) {
            let mut state = seed;
            let mut h = Array2::from_shape_fn((nx, ny), |_| {
                let v = uniform(&mut state) - 0.5;
                if uniform(&mut state) < missing { f64::NAN } else { v }
            });
            h[[0, 0]] = 0.25;
            let (lo, hi) = h.iter().filter(|v| !v.is_nan())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
            fill_harmonic(&mut h, 1e-6, 2e-6, periodic).unwrap();
            for v in &h {
                prop_assert!(v.is_finite() && *v >= lo - 1e-9 && *v <= hi + 1e-9);
            }
        }
    }
}
