//! Drucker stability imposed inside the fit over stated stretch windows
//! (`constraint: in-range`): the moduli for given shape parameters θ are
//! least squares subject to the log-strain Hessian H being positive
//! definite at every stretch of each mode's window.
//!
//! For fixed θ every family's energy is linear in its moduli μ, and so is
//! H = Σ μ_i H_i(λ; θ) (H_i: the Hessian of the model with μ = e_i, see
//! [`crate::stability`] for why H decides Drucker's condition). "H positive
//! definite" is then, for each unit direction v of log strain, one linear
//! inequality vᵀ H v = Σ μ_i vᵀ H_i v ≥ m, with a margin m of
//! [`MARGIN`] times the largest measured stress so that the model is
//! strictly stable where it was imposed. The infinitely many (λ, v) are
//! handled by cutting planes (Kelley 1960): solve the least squares with
//! the constraints collected so far ([`crate::lsi::lsi`]), evaluate the
//! model's own Drucker stiffness ([`crate::Hyperelastic::drucker_stiffness`],
//! the accurate expanded form) on a geometric grid of each window, add
//! for every run of grid points that fails the worst point and its
//! eigenvector of the smallest eigenvalue, and solve again until no grid
//! point fails. The solution is feasible for the windows' grid and, among
//! the constraints it saw, optimal.
//!
//! Windows ([`DruckerWindows`]): by default each fitted mode's data range
//! extended to λ = 1, and equibiaxial compression down to
//! [`DEFAULT_COMPRESSION_STRETCH`], which covers the deepest mean contact
//! stress the paper pipeline's contact stages reach (see the stage doc).
//! For every family the cone μ ≥ 0 lies inside the feasible set (each term
//! is then stable at every stretch), so the constraints are never
//! inconsistent; a solve that does not settle within [`MAX_ROUNDS`] is a
//! breakdown of that θ, like α = 0.

use nalgebra::{DMatrix, DVector};

use crate::lsi::lsi;
use crate::stability::{LAMBDA_HIGH, LAMBDA_LOW};
use crate::tensile::TensileData;
use crate::{Family, Hyperelastic, Mode};

/// The default lower end of the equibiaxial window: BT compression to
/// λ = 0.6, beyond the paper pipeline's deepest mean contact stress.
pub const DEFAULT_COMPRESSION_STRETCH: f64 = 0.6;

/// Drucker margin, in units of the largest measured stress: the smallest
/// eigenvalue of H the constraints ask for.
pub const MARGIN: f64 = 1e-6;

/// Cutting-plane rounds before a solve counts as failed.
pub const MAX_ROUNDS: usize = 40;

/// Grid stretches per window while searching, and for the final check of
/// each converged start.
pub const SEARCH_GRID: usize = 64;
pub const FINAL_GRID: usize = 2000;

/// The stretch window [lo, hi] per mode (indexed by [`Mode`]) where the
/// fit imposes Drucker stability; None where it imposes none.
#[derive(Clone, Debug, PartialEq)]
pub struct DruckerWindows {
    pub ranges: [Option<(f64, f64)>; 3],
}

impl DruckerWindows {
    /// Each weighted mode's data range extended to λ = 1 (and cut to the
    /// stability check's 0.1 ≤ λ ≤ 10), and BT further down to
    /// `compression_stretch`.
    pub fn from_data(data: &TensileData, weights: [f64; 3], compression_stretch: f64) -> Self {
        let mut ranges = [None; 3];
        for curve in &data.curves {
            if weights[curve.mode as usize] <= 0.0 {
                continue;
            }
            let slot: &mut Option<(f64, f64)> = &mut ranges[curve.mode as usize];
            let (mut lo, mut hi) = slot.unwrap_or((1.0, 1.0));
            for &l in &curve.stretch {
                lo = lo.min(l);
                hi = hi.max(l);
            }
            // Data beyond the stability check's range impose up to its edge.
            *slot = Some((lo.max(LAMBDA_LOW), hi.min(LAMBDA_HIGH)));
        }
        let bt = &mut ranges[Mode::Equibiaxial as usize];
        let (lo, hi) = bt.unwrap_or((1.0, 1.0));
        *bt = Some((lo.min(compression_stretch), hi));
        Self { ranges }
    }

    /// The window of `mode`.
    pub fn get(&self, mode: Mode) -> Option<(f64, f64)> {
        self.ranges[mode as usize]
    }

    /// Replaces `mode`'s window.
    pub fn with(mut self, mode: Mode, window: (f64, f64)) -> Self {
        self.ranges[mode as usize] = Some(window);
        self
    }

    /// An error message unless every window holds λ = 1 and lies within
    /// the stability check's search range [0.1, 10].
    pub fn check(&self) -> Result<(), String> {
        for mode in Mode::ALL {
            let Some((lo, hi)) = self.get(mode) else {
                continue;
            };
            if !(LAMBDA_LOW..=1.0).contains(&lo) || !(1.0..=LAMBDA_HIGH).contains(&hi) {
                return Err(format!(
                    "{mode} window [{lo}, {hi}] must satisfy {LAMBDA_LOW} ≤ lo ≤ 1 ≤ hi ≤ \
                     {LAMBDA_HIGH} (the stretch range of the stability check)"
                ));
            }
        }
        Ok(())
    }

    /// `UT 1–7.6, PT 1–4.97, BT 0.6–4.45`.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = Mode::ALL
            .iter()
            .filter_map(|&m| self.get(m).map(|(lo, hi)| format!("{m} {lo:.4}–{hi:.4}")))
            .collect();
        parts.join(", ")
    }

    /// `n` geometric stretches per window, both ends included, in order.
    fn grid(&self, n: usize) -> Vec<(Mode, Vec<f64>)> {
        Mode::ALL
            .iter()
            .filter_map(|&mode| {
                let (lo, hi) = self.get(mode)?;
                let (a, b) = (lo.ln(), hi.ln());
                let steps = n.max(2) - 1;
                Some((
                    mode,
                    (0..=steps)
                        .map(|k| (a + (b - a) * k as f64 / steps as f64).exp())
                        .collect(),
                ))
            })
            .collect()
    }
}

/// One Drucker constraint: vᵀ H v ≥ margin at `stretch` of `mode`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cut {
    pub mode: Mode,
    pub stretch: f64,
    pub direction: [f64; 2],
}

/// The smallest eigenvalue of H from its trace and determinant (the
/// accurate form, without the cancelling difference of a closed formula);
/// −∞ where the trace is not positive.
fn smallest_eigenvalue(model: &dyn Hyperelastic, mode: Mode, stretch: f64) -> f64 {
    let d = model.drucker_stiffness(mode.stretches(stretch));
    if d.trace_pa <= 0.0 || !d.trace_pa.is_finite() || !d.determinant_pa2.is_finite() {
        return f64::NEG_INFINITY;
    }
    let root = (d.trace_pa * d.trace_pa - 4.0 * d.determinant_pa2)
        .max(0.0)
        .sqrt();
    2.0 * d.determinant_pa2 / (d.trace_pa + root)
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric 2 × 2.
fn softest_direction([[a, b], [_, c]]: [[f64; 2]; 2]) -> [f64; 2] {
    let low = 0.5 * (a + c) - (0.25 * (a - c) * (a - c) + b * b).sqrt();
    // Of the two equivalent forms take the longer: the other may vanish.
    let (p, q) = ((low - c, b), (b, low - a));
    let (x, y) = if p.0.hypot(p.1) >= q.0.hypot(q.1) {
        p
    } else {
        q
    };
    let norm = x.hypot(y);
    if norm > 0.0 && norm.is_finite() {
        [x / norm, y / norm]
    } else if a <= c {
        [1.0, 0.0]
    } else {
        [0.0, 1.0]
    }
}

/// The constrained inner solve of the `in-range` fit at one θ.
pub(crate) struct InRange<'a> {
    pub family: Family,
    pub windows: &'a DruckerWindows,
    /// Grid stretches per window for this solve.
    pub grid_points: usize,
}

impl InRange<'_> {
    /// The models with unit modulus i and shape θ: H_i at any stretch.
    fn unit_models(&self, theta: &[f64]) -> Option<Vec<Box<dyn Hyperelastic>>> {
        let k = self.family.n_linear();
        (0..k)
            .map(|i| {
                let mut x = vec![0.0; k];
                x[i] = 1.0;
                x.extend_from_slice(theta);
                self.family.model(&x, 1.0).ok()
            })
            .collect()
    }

    /// The rows G, h of the cuts at θ.
    fn rows(units: &[Box<dyn Hyperelastic>], cuts: &[Cut]) -> (DMatrix<f64>, DVector<f64>) {
        let g = DMatrix::from_fn(cuts.len(), units.len(), |r, i| {
            let cut = &cuts[r];
            let [[h11, h12], [_, h22]] =
                units[i].log_strain_hessian_pa(cut.mode.stretches(cut.stretch));
            let [v1, v2] = cut.direction;
            v1 * v1 * h11 + 2.0 * v1 * v2 * h12 + v2 * v2 * h22
        });
        (g, DVector::from_element(cuts.len(), MARGIN))
    }

    /// The moduli minimising |B μ − y| with H positive definite on the
    /// windows' grid at θ, adding to `cuts` what the grid shows is needed;
    /// None if the rounds run out or a solve breaks down.
    pub fn solve(
        &self,
        basis: &DMatrix<f64>,
        y: &DVector<f64>,
        theta: &[f64],
        cuts: &mut Vec<Cut>,
    ) -> Option<DVector<f64>> {
        let units = self.unit_models(theta)?;
        let grid = self.windows.grid(self.grid_points);
        for _ in 0..MAX_ROUNDS {
            let moduli = self.solve_with(basis, y, &units, cuts)?;
            let mut x = moduli.as_slice().to_vec();
            x.extend_from_slice(theta);
            let model = self.family.model(&x, 1.0).ok()?;
            let found = violations(model.as_ref(), &grid);
            if found.is_empty() {
                return Some(moduli);
            }
            cuts.extend(found);
        }
        None
    }

    /// The moduli under exactly `cuts` at θ (no new cuts): the projected
    /// problem whose differences make the search's Jacobian.
    pub fn solve_fixed(
        &self,
        basis: &DMatrix<f64>,
        y: &DVector<f64>,
        theta: &[f64],
        cuts: &[Cut],
    ) -> Option<DVector<f64>> {
        let units = self.unit_models(theta)?;
        self.solve_with(basis, y, &units, cuts)
    }

    fn solve_with(
        &self,
        basis: &DMatrix<f64>,
        y: &DVector<f64>,
        units: &[Box<dyn Hyperelastic>],
        cuts: &[Cut],
    ) -> Option<DVector<f64>> {
        let (g, h) = Self::rows(units, cuts);
        if g.iter().any(|v| !v.is_finite()) {
            return None;
        }
        lsi(basis, y, &g, &h)
    }
}

/// For each run of grid points where the smallest eigenvalue of H is below
/// half the margin, the worst point as a new cut.
fn violations(model: &dyn Hyperelastic, grid: &[(Mode, Vec<f64>)]) -> Vec<Cut> {
    let mut cuts = Vec::new();
    for (mode, stretches) in grid {
        let mut worst: Option<(f64, f64)> = None;
        let mut close = |worst: &mut Option<(f64, f64)>| {
            if let Some((stretch, _)) = worst.take() {
                let h = model.log_strain_hessian_pa(mode.stretches(stretch));
                cuts.push(Cut {
                    mode: *mode,
                    stretch,
                    direction: softest_direction(h),
                });
            }
        };
        for &stretch in stretches {
            let low = smallest_eigenvalue(model, *mode, stretch);
            if low.is_nan() || low < 0.5 * MARGIN {
                let low = if low.is_nan() { f64::NEG_INFINITY } else { low };
                if worst.is_none_or(|(_, w)| low < w) {
                    worst = Some((stretch, low));
                }
            } else {
                close(&mut worst);
            }
        }
        close(&mut worst);
    }
    cuts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn softest_direction_is_the_eigenvector_of_the_smallest_eigenvalue() {
        for h in [
            [[2.0, 1.0], [1.0, 2.0]],
            [[1.0, 0.0], [0.0, 3.0]],
            [[3.0, 0.0], [0.0, 1.0]],
            [[1e9, 1e9 - 1.0], [1e9 - 1.0, 1e9]],
        ] {
            let [x, y] = softest_direction(h);
            let (a, b, c) = (h[0][0], h[0][1], h[1][1]);
            let low = 0.5 * (a + c) - (0.25 * (a - c) * (a - c) + b * b).sqrt();
            let (hx, hy) = (a * x + b * y, b * x + c * y);
            assert!(
                (hx - low * x).abs() + (hy - low * y).abs() <= 1e-6 * (a.abs() + c.abs()),
                "{h:?}"
            );
            assert!((x.hypot(y) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn default_windows_extend_the_data_to_rest_and_bt_into_compression() {
        let data = crate::sample::paper_sample();
        let w = DruckerWindows::from_data(&data, [1.0; 3], DEFAULT_COMPRESSION_STRETCH);
        for curve in &data.curves {
            let (lo, hi) = w.get(curve.mode).unwrap();
            let top = curve.stretch.iter().fold(1.0_f64, |m, l| m.max(*l));
            assert_eq!(hi, top);
            assert!(lo <= 1.0);
        }
        assert_eq!(w.get(Mode::Equibiaxial).unwrap().0, 0.6);
        w.check().unwrap();
        // A mode left out by its weight gets no window; BT keeps its
        // compression even without data.
        let w = DruckerWindows::from_data(&data, [1.0, 0.0, 0.0], 0.5);
        assert_eq!(w.get(Mode::Planar), None);
        assert_eq!(w.get(Mode::Equibiaxial), Some((0.5, 1.0)));
        let bad = w.with(Mode::Uniaxial, (1.2, 3.0)).check().unwrap_err();
        assert!(bad.contains("UT window [1.2, 3]"), "{bad}");
    }
}
