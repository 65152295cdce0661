//! The short-wavelength reliability cut-off of a map measured with a
//! probe tip (AFM, stylus): a rigid spherical tip of radius R cannot
//! follow a valley sharper than itself, so wherever the surface curves
//! down by more than about 1/R the measured map is the tip's shape, not
//! the surface's. Sanner, Nöhring, Thimons, Jacobs and Pastewka, Appl.
//! Surf. Sci. Adv. 7, 100190 (2022), doi:10.1016/j.apsadv.2021.100190,
//! with the convention of SurfaceTopography's
//! `scanning_probe_reliability_cutoff` (1.x, `Generic/ScanningProbe.py`),
//! which `short_reliability_cutoff` calls when a tip radius is stated:
//!
//! - the scale-dependent curvature at distance λ is the central second
//!   difference whose stencil spans λ (its steps are λ/2),
//!   h''_λ(x) = [h(x + λ/2) − 2 h(x) + h(x − λ/2)] / (λ/2)², along x
//!   (array axis 0) for a map, along the profile for a line scan; heights
//!   between grid points are interpolated linearly along x;
//! - only points whose stencil lies inside the map count: ⌈λ/(2Δx)⌉
//!   points are dropped at both ends along x and, for a map, ⌈λ/(2Δy)⌉
//!   at both ends along y (SurfaceTopography's 3 × 3 stencil array trims
//!   both axes); NaN points and stencils touching one take no part;
//! - the cut-off λ_c is where the most negative curvature over the map
//!   equals −f/R, f the safety factor (1/2 in the paper, from simulated
//!   scans; SurfaceTopography's default), found by Brent's method between
//!   2Δ̄ and L̄/2, Δ̄ the mean of the two spacings and L̄ the mean of the two
//!   sides (SurfaceTopography's `bandwidth`), distances scaled by the
//!   geometric mean of Δ̄ and L̄ for the root search;
//! - λ_c is the stencil's whole span, not its step: features shorter than
//!   λ_c are unreliable. No cut-off (`None`) when the curvature stays above
//!   −f/R already at 2Δ̄ (the tip resolves everything the grid does); L̄
//!   when it is still below at L̄/2 (nothing is reliable).
//!
//! A periodic sinusoid A cos(2πx/ℓ) has h''_λ = −A·16 sin²(πλ/(2ℓ))/λ² at
//! its crests, which tends to the curvature amplitude A(2π/ℓ)² for λ ≪ ℓ:
//! the cut-off is the λ where that equals f/R (the analytic test).
//!
//! The minimum is order-independent, so the cut-off is the same bits on
//! any number of threads.

use ndarray::ArrayView2;
use rayon::prelude::*;

use hypercontact_core::Field;

/// SurfaceTopography's default safety factor f: the tip is taken to
/// distort the map where the surface curves down by more than f/R.
pub const DEFAULT_SAFETY_FACTOR: f64 = 0.5;

/// Why no cut-off can be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TipCutoffError {
    #[error("tip_radius_m must be positive and finite, got {0}")]
    BadRadius(f64),
    #[error("the safety factor must be positive and finite, got {0}")]
    BadSafetyFactor(f64),
    #[error(
        "the map is {nx} × {ny} points; the tip's cut-off needs at least 5 points along x \
         (or along a line scan)"
    )]
    TooSmall { nx: usize, ny: usize },
}

/// The cut-off of a probe of `tip_radius_m` on `field` with
/// SurfaceTopography's safety factor (see the module doc): `Ok(None)`
/// when the tip resolves every scale of the grid, else the shortest
/// reliable length scale, metres.
pub fn tip_reliability_cutoff_m(
    field: &Field,
    tip_radius_m: f64,
) -> Result<Option<f64>, TipCutoffError> {
    tip_reliability_cutoff_with(field, tip_radius_m, DEFAULT_SAFETY_FACTOR)
}

/// [`tip_reliability_cutoff_m`] with another safety factor f (the tip
/// is taken to distort the map where the curvature is below −f/R).
pub fn tip_reliability_cutoff_with(
    field: &Field,
    tip_radius_m: f64,
    safety_factor: f64,
) -> Result<Option<f64>, TipCutoffError> {
    if !(tip_radius_m > 0.0 && tip_radius_m.is_finite()) {
        return Err(TipCutoffError::BadRadius(tip_radius_m));
    }
    if !(safety_factor > 0.0 && safety_factor.is_finite()) {
        return Err(TipCutoffError::BadSafetyFactor(safety_factor));
    }
    let probe = Probe::of(field)?;
    let (lower_m, upper_m) = probe.bandwidth_m();
    // The root search runs on distances in units of the bandwidth's
    // geometric mean, as SurfaceTopography's does, so its tolerances mean
    // the same.
    let unit_m = (lower_m * upper_m).sqrt();
    let target = safety_factor / tip_radius_m;
    let objective = |lambda: f64| {
        probe
            .min_curvature(lambda * unit_m)
            .map_or(target * unit_m, |c| (target + c) * unit_m)
    };
    let (a, b) = (2.0 * lower_m / unit_m, upper_m / (2.0 * unit_m));
    let (fa, fb) = (objective(a), objective(b));
    if fa > 0.0 {
        return Ok(None);
    }
    if fb < 0.0 {
        return Ok(Some(upper_m));
    }
    Ok(Some(unit_m * brent_root(objective, (a, fa), (b, fb))))
}

/// The heights as the tip's criterion sees them: a view whose axis 0 is
/// the direction of the stencil, with its spacing, and whether the y
/// trimming of a map applies.
struct Probe<'a> {
    heights: ArrayView2<'a, f64>,
    step_m: f64,
    /// Spacing across (axis 1); `None` for a line scan.
    across_m: Option<f64>,
}

impl<'a> Probe<'a> {
    fn of(field: &'a Field) -> Result<Self, TipCutoffError> {
        let (nx, ny) = field.values.dim();
        let probe = if nx == 1 && ny > 1 {
            // A profile along y: SurfaceTopography sees a line scan.
            Probe {
                heights: field.values.t(),
                step_m: field.dy_m,
                across_m: None,
            }
        } else {
            Probe {
                heights: field.values.view(),
                step_m: field.dx_m,
                across_m: (ny > 1).then_some(field.dy_m),
            }
        };
        if probe.heights.nrows() < 5 {
            return Err(TipCutoffError::TooSmall { nx, ny });
        }
        Ok(probe)
    }

    /// SurfaceTopography's `bandwidth`: the mean spacing and the mean side.
    fn bandwidth_m(&self) -> (f64, f64) {
        let along_m = self.heights.nrows() as f64 * self.step_m;
        match self.across_m {
            None => (self.step_m, along_m),
            Some(dy_m) => (
                0.5 * (self.step_m + dy_m),
                0.5 * (along_m + self.heights.ncols() as f64 * dy_m),
            ),
        }
    }

    /// The most negative second difference of span `lambda_m` over the
    /// points whose stencil lies inside the map; `None` when none does.
    fn min_curvature(&self, lambda_m: f64) -> Option<f64> {
        let (n, m) = self.heights.dim();
        let shift = lambda_m / (2.0 * self.step_m);
        let trim = shift.ceil() as usize;
        let trim_y = self
            .across_m
            .map_or(0, |dy_m| (lambda_m / (2.0 * dy_m)).ceil() as usize);
        if n <= 2 * trim || m <= 2 * trim_y {
            return None;
        }
        let half_span_m = lambda_m / 2.0;
        let per_m2 = 1.0 / (half_span_m * half_span_m);
        let columns = trim_y..m - trim_y;
        let lowest = (trim..n - trim)
            .into_par_iter()
            .map(|i| {
                let centre = self.heights.row(i);
                let plus = Lerp::at(i as f64 + shift, n);
                let minus = Lerp::at(i as f64 - shift, n);
                columns.clone().fold(f64::INFINITY, |low, j| {
                    let d = (plus.height(&self.heights, j) - 2.0 * centre[j]
                        + minus.height(&self.heights, j))
                        * per_m2;
                    if d < low { d } else { low }
                })
            })
            .reduce(|| f64::INFINITY, f64::min);
        lowest.is_finite().then_some(lowest)
    }
}

/// Linear interpolation along axis 0 at a fractional index: the two rows
/// and the weight of the second.
struct Lerp {
    below: usize,
    above: usize,
    weight: f64,
}

impl Lerp {
    fn at(position: f64, n: usize) -> Self {
        let floor = position.floor();
        // Kept stencils lie inside the map; the wrap only guards the index
        // of a neighbour whose weight is zero.
        let below = (floor.max(0.0) as usize).min(n - 1);
        Lerp {
            below,
            above: (below + 1) % n,
            weight: position - floor,
        }
    }

    fn height(&self, heights: &ArrayView2<f64>, j: usize) -> f64 {
        (1.0 - self.weight) * heights[[self.below, j]] + self.weight * heights[[self.above, j]]
    }
}

/// A root of `f` between `a` and `b`, where `f` changes sign, by Brent's
/// method (Brent, Algorithms for Minimization without Derivatives, 1973,
/// ch. 4): inverse quadratic or secant steps while they stay inside the
/// bracket and shrink it fast enough, bisection otherwise. The tolerance
/// is SurfaceTopography's: 2e-12 absolute plus 1e-8 relative, in the
/// scaled distances.
fn brent_root(mut f: impl FnMut(f64) -> f64, a: (f64, f64), b: (f64, f64)) -> f64 {
    const XTOL: f64 = 2e-12;
    const RTOL: f64 = 1e-8;
    const MAX_STEPS: usize = 200;
    let ((mut a, mut fa), (mut b, mut fb)) = (a, b);
    // c is the far end of the bracket [b, c]; b the best estimate.
    let (mut c, mut fc) = (a, fa);
    let mut step = b - a;
    let mut step_before = step;
    for _ in 0..MAX_STEPS {
        if (fb > 0.0) == (fc > 0.0) && fb != 0.0 {
            (c, fc) = (a, fa);
            step = b - a;
            step_before = step;
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol = 0.5 * (XTOL + RTOL * b.abs());
        let half = 0.5 * (c - b);
        if fb == 0.0 || half.abs() <= tol {
            return b;
        }
        if step_before.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * half * s, 1.0 - s)
            } else {
                let (qa, rb) = (fa / fc, fb / fc);
                (
                    s * (2.0 * half * qa * (qa - rb) - (b - a) * (rb - 1.0)),
                    (qa - 1.0) * (rb - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * half * q - (tol * q).abs()).min((step_before * q).abs()) {
                step_before = step;
                step = p / q;
            } else {
                step = half;
                step_before = half;
            }
        } else {
            step = half;
            step_before = half;
        }
        (a, fa) = (b, fb);
        b += if step.abs() > tol {
            step
        } else {
            tol.copysign(half)
        };
        fb = f(b);
    }
    b
}

#[cfg(test)]
mod tests;
