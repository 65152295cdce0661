//! The areal autocorrelation function of ISO 25178-2 §3.1.5 and the spatial
//! parameters built on it (§4.2): Sal, Str, and a correlation length.
//!
//! f_ACF(τx, τy) = ⟨z(x, y) z(x + τx, y + τy)⟩ / ⟨z²⟩, z = h − z̄ (mean of the
//! measured points), the numerator averaged over the pairs of measured
//! points that lag apart (the "overlap count"), so that every lag is an
//! unbiased mean rather than a sum that shrinks with the overlap; f_ACF(0)
//! = 1. The sums over pairs are circular autocorrelations of the map
//! zero-padded to at least (2nx − 1) × (2ny − 1) (so no lag wraps onto
//! another), computed as IFFT(|FFT(z)|²) (Wiener–Khinchin); NaN points enter
//! as zero height and zero weight, and the overlap count of a lag is the same
//! transform of the 0/1 mask of measured points (exactly (nx − |a|)(ny − |b|)
//! when all are measured).
//!
//! - Sal is the shortest lag length at which f_ACF has decayed to s (ISO's
//!   default s = 0.2), Str the shortest over the longest such length, over
//!   all directions: along each of [`DIRECTIONS`] directions θ ∈ [0°, 180°)
//!   (f_ACF(−τ) = f_ACF(τ)), f_ACF is read by bilinear interpolation every
//!   quarter pixel of lag from the origin outwards, and the first
//!   fall to s or below is located by linear interpolation between the last
//!   two readings. The search stays within the ellipse whose semi-axes are
//!   half the map's extent along x and y, ⌊(n − 1)/2⌋ pixels (where at least
//!   a quarter of the map still overlaps; an ellipse rather than the box, so
//!   that no direction is searched further for lying along a diagonal); a
//!   direction that has not decayed by then counts with its search length,
//!   so Str is then an upper bound (a texture of parallel ridges has a small
//!   Str).
//! - The correlation length is the lag at which the radially averaged f_ACF
//!   (mean over the lags within the same ellipse, binned by |τ| in rings one
//!   finer spacing wide (wider where that would make more rings than
//!   2(hx + hy) + 1, for very unequal spacings), each ring at the mean |τ| of its lags) first falls
//!   to 1/e, linearly interpolated between rings. For f_ACF = exp(−r²/ξ²)
//!   it is ξ; for exp(−r/ξ), ξ.

use std::f64::consts::PI;

use hypercontact_numeric::fft2::{Complex64, RealFft2, fast_even_size, fast_size};
use ndarray::Array2;

use super::{check_spacing, checked_heights, measured_mean};
use crate::SurfaceError;

/// Directions over [0°, 180°) along which decay lengths are searched.
pub const DIRECTIONS: usize = 360;

/// The normalised areal autocorrelation f_ACF of a map, every lag.
#[derive(Clone, Debug, PartialEq)]
pub struct Autocorrelation {
    /// f_ACF at lag (a·dx, b·dy) in `values[[a + nx − 1, b + ny − 1]]`,
    /// a ∈ (−nx, nx), b ∈ (−ny, ny); NaN where no pair of measured points
    /// lies that far apart, and everywhere for a flat map.
    pub values: Array2<f64>,
    pub dx_m: f64,
    pub dy_m: f64,
}

/// A lag axis of the map: x (array axis 0) or y (axis 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
}

/// Decay lengths of f_ACF to a threshold s over directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecayLengths {
    /// The threshold s.
    pub threshold: f64,
    /// The shortest decay length, m (NaN if no direction decays).
    pub shortest_m: f64,
    /// Its direction from the x axis towards y, degrees in [0, 180).
    pub shortest_direction_deg: f64,
    /// The longest decay length, m: a lower bound when `all_decayed` is
    /// false (it is then the search length of a direction that did not).
    pub longest_m: f64,
    pub longest_direction_deg: f64,
    /// Whether f_ACF fell to s within the search in every direction.
    pub all_decayed: bool,
}

impl DecayLengths {
    /// Sal: the shortest decay length, m.
    pub fn sal_m(&self) -> f64 {
        self.shortest_m
    }

    /// Str: shortest / longest decay length (an upper bound when not every
    /// direction decayed).
    pub fn str(&self) -> f64 {
        self.shortest_m / self.longest_m
    }
}

/// f_ACF of the levelled map `h` (NaN = not measured), O(N log N); an error
/// for fewer than four measured points, a ±∞ height or a bad spacing.
pub fn autocorrelation(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
) -> Result<Autocorrelation, SurfaceError> {
    const QUANTITY: &str = "the autocorrelation";
    check_spacing(dx_m, dy_m, QUANTITY)?;
    let heights = checked_heights(h, QUANTITY)?;
    let (nx, ny) = heights.shape;
    let mean = measured_mean(&heights.values);
    let z: Vec<f64> = heights
        .values
        .iter()
        .map(|v| if v.is_nan() { 0.0 } else { v - mean })
        .collect();
    let grid = (fast_size(2 * nx - 1), fast_even_size(2 * ny - 1));
    let fft = RealFft2::new(grid.0, grid.1).map_err(|e| SurfaceError::Areal {
        quantity: QUANTITY,
        message: e.to_string(),
    })?;
    let products = circular_autocorrelation(&fft, &z, (nx, ny))?;
    let counts = if heights.measured < z.len() {
        let mask: Vec<f64> = heights
            .values
            .iter()
            .map(|v| if v.is_nan() { 0.0 } else { 1.0 })
            .collect();
        Some(circular_autocorrelation(&fft, &mask, (nx, ny))?)
    } else {
        None
    };
    let at = |a: isize, b: isize| {
        let k = a.rem_euclid(grid.0 as isize) as usize * grid.1
            + b.rem_euclid(grid.1 as isize) as usize;
        let count = match &counts {
            // the transform's rounding is far below ½
            Some(c) => c[k].round(),
            None => ((nx - a.unsigned_abs()) * (ny - b.unsigned_abs())) as f64,
        };
        if count < 1.0 {
            f64::NAN
        } else {
            products[k] / count
        }
    };
    let variance = at(0, 0);
    let (cx, cy) = (nx as isize - 1, ny as isize - 1);
    let values = Array2::from_shape_fn((2 * nx - 1, 2 * ny - 1), |(i, j)| {
        let value = at(i as isize - cx, j as isize - cy) / variance;
        if value.is_finite() { value } else { f64::NAN }
    });
    Ok(Autocorrelation { values, dx_m, dy_m })
}

/// Σ x[m, n]·x[m + a, n + b] over the grid of `fft` (the map zero-extended),
/// every lag (a, b) cyclic, row-major over the grid.
fn circular_autocorrelation(
    fft: &RealFft2,
    map: &[f64],
    map_size: (usize, usize),
) -> Result<Vec<f64>, SurfaceError> {
    let (rows, cols) = fft.grid();
    let mut spectrum = vec![Complex64::ZERO; fft.spectrum_len()];
    let mut work = fft.workspace();
    let mut out = vec![0.0; rows * cols];
    let numeric = |e: hypercontact_numeric::NumericError| SurfaceError::Areal {
        quantity: "the autocorrelation",
        message: e.to_string(),
    };
    fft.forward(map, map_size, &mut spectrum, &mut work)
        .map_err(numeric)?;
    for c in spectrum.iter_mut() {
        *c = Complex64::new(c.norm_sqr(), 0.0);
    }
    fft.inverse(
        &mut spectrum,
        (rows, cols),
        &mut out,
        1.0 / (rows * cols) as f64,
    )
    .map_err(numeric)?;
    Ok(out)
}

impl Autocorrelation {
    /// The largest lags held, (nx − 1, ny − 1) in pixels.
    pub fn max_lag(&self) -> (usize, usize) {
        let (rows, cols) = self.values.dim();
        (rows / 2, cols / 2)
    }

    /// f_ACF at lag (a·dx, b·dy); NaN outside the map's lags.
    pub fn at(&self, a: isize, b: isize) -> f64 {
        let (mx, my) = self.max_lag();
        let (i, j) = (a + mx as isize, b + my as isize);
        if i < 0 || j < 0 {
            return f64::NAN;
        }
        self.values
            .get((i as usize, j as usize))
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// f_ACF at the fractional lag (u·dx, v·dy), bilinear between its four
    /// neighbouring lags.
    fn interpolate(&self, u: f64, v: f64) -> f64 {
        let (a, b) = (u.floor(), v.floor());
        let (fu, fv) = (u - a, v - b);
        let (a, b) = (a as isize, b as isize);
        let corner = |da: isize, db: isize, w: f64| {
            if w == 0.0 {
                0.0
            } else {
                w * self.at(a + da, b + db)
            }
        };
        corner(0, 0, (1.0 - fu) * (1.0 - fv))
            + corner(1, 0, fu * (1.0 - fv))
            + corner(0, 1, (1.0 - fu) * fv)
            + corner(1, 1, fu * fv)
    }

    /// The half extents searched, in pixel lags: ⌊(n − 1)/2⌋ along x and y.
    fn search_extent(&self) -> (f64, f64) {
        let (mx, my) = self.max_lag();
        ((mx / 2) as f64, (my / 2) as f64)
    }

    /// Where f_ACF first falls to `threshold` along direction `theta` (rad):
    /// (length m, true), or (search length m, false) if it does not; None if
    /// the search is empty (a map one pixel wide across the direction).
    fn decay_along(&self, theta: f64, threshold: f64) -> Option<(f64, bool)> {
        let (ux, uy) = (theta.cos(), theta.sin());
        let (hx, hy) = self.search_extent();
        // where the ray leaves the ellipse (x/(hx·dx))² + (y/(hy·dy))² = 1
        let (ex, ey) = (ux / (hx * self.dx_m), uy / (hy * self.dy_m));
        let (ex, ey) = (
            if ux.abs() < 1e-12 { 0.0 } else { ex },
            if uy.abs() < 1e-12 { 0.0 } else { ey },
        );
        let reach_m = 1.0 / ex.hypot(ey);
        if !(reach_m > 0.0 && reach_m.is_finite()) {
            return None;
        }
        // a quarter pixel of lag per step, whatever the direction
        let step_m = 0.25 / (ux / self.dx_m).hypot(uy / self.dy_m);
        let (mut last_r, mut last_value) = (0.0, 1.0);
        let mut k = 1usize;
        loop {
            let r = (k as f64 * step_m).min(reach_m);
            let value = self.interpolate(r * ux / self.dx_m, r * uy / self.dy_m);
            if value <= threshold {
                let t = (last_value - threshold) / (last_value - value);
                return Some((last_r + t * (r - last_r), true));
            }
            if r >= reach_m {
                return Some((reach_m, false));
            }
            if !value.is_nan() {
                (last_r, last_value) = (r, value);
            }
            k += 1;
        }
    }

    /// The decay lengths to `threshold` (0 ≤ s < 1; ISO's default is
    /// [`super::ISO_DECAY_THRESHOLD`]) over [`DIRECTIONS`] directions.
    pub fn decay_lengths(&self, threshold: f64) -> Result<DecayLengths, SurfaceError> {
        if !(0.0..1.0).contains(&threshold) {
            return Err(SurfaceError::Areal {
                quantity: "Sal and Str",
                message: format!("the threshold s = {threshold} must be in [0, 1)"),
            });
        }
        let mut out = DecayLengths {
            threshold,
            shortest_m: f64::NAN,
            shortest_direction_deg: f64::NAN,
            longest_m: f64::NAN,
            longest_direction_deg: f64::NAN,
            all_decayed: true,
        };
        for k in 0..DIRECTIONS {
            let theta = PI * k as f64 / DIRECTIONS as f64;
            let Some((length_m, decayed)) = self.decay_along(theta, threshold) else {
                continue;
            };
            out.all_decayed &= decayed;
            let degrees = theta.to_degrees();
            // NaN (none yet) compares false: the first length is taken
            if decayed && (out.shortest_m.is_nan() || length_m < out.shortest_m) {
                (out.shortest_m, out.shortest_direction_deg) = (length_m, degrees);
            }
            if out.longest_m.is_nan() || length_m > out.longest_m {
                (out.longest_m, out.longest_direction_deg) = (length_m, degrees);
            }
        }
        Ok(out)
    }

    /// The radially averaged f_ACF over the lags within the search ellipse:
    /// (mean |τ| of each ring, m; mean f_ACF in it), rings as the module doc
    /// says, empty rings left out.
    pub fn radial_average(&self) -> (Vec<f64>, Vec<f64>) {
        let (hx, hy) = self.search_extent();
        let (hx, hy) = (hx as isize, hy as isize);
        let (x_m, y_m) = (hx as f64 * self.dx_m, hy as f64 * self.dy_m);
        // no more rings than lags along the axes (very unequal spacings)
        let most = 2 * (hx + hy) as usize + 1;
        let width_m = self.dx_m.min(self.dy_m).max(x_m.hypot(y_m) / most as f64);
        let rings = ((x_m.hypot(y_m) / width_m).round() as usize + 1).min(most + 1);
        let mut sums = vec![(0usize, 0.0, 0.0); rings];
        let inside = |a: isize, b: isize| {
            let along = |lag: isize, half: isize| {
                if half == 0 {
                    0.0
                } else {
                    lag as f64 / half as f64
                }
            };
            along(a, hx).hypot(along(b, hy)) <= 1.0
        };
        for a in -hx..=hx {
            for b in -hy..=hy {
                let value = self.at(a, b);
                if value.is_nan() || !inside(a, b) {
                    continue;
                }
                let r = (a as f64 * self.dx_m).hypot(b as f64 * self.dy_m);
                let ring = &mut sums[((r / width_m).round() as usize).min(rings - 1)];
                ring.0 += 1;
                ring.1 += r;
                ring.2 += value;
            }
        }
        sums.into_iter()
            .filter(|ring| ring.0 > 0)
            .map(|(n, r, value)| (r / n as f64, value / n as f64))
            .unzip()
    }

    /// f_ACF along the x axis (`Axis::X`, lags (a·dx, 0)) or the y axis
    /// (lags (0, b·dy)) from lag 0 out to the search extent, ⌊(n − 1)/2⌋
    /// pixels (as far as [`Self::radial_average`] reaches along it): (lag,
    /// m; f_ACF), NaN where no pair of measured points lies that far apart.
    pub fn axis_profile(&self, axis: Axis) -> (Vec<f64>, Vec<f64>) {
        let (hx, hy) = self.search_extent();
        let (reach, spacing_m) = match axis {
            Axis::X => (hx as isize, self.dx_m),
            Axis::Y => (hy as isize, self.dy_m),
        };
        (0..=reach)
            .map(|k| {
                let value = match axis {
                    Axis::X => self.at(k, 0),
                    Axis::Y => self.at(0, k),
                };
                (k as f64 * spacing_m, value)
            })
            .unzip()
    }

    /// The lag at which the radially averaged f_ACF first falls to 1/e, m;
    /// NaN if it does not within the search extent.
    pub fn correlation_length_m(&self) -> f64 {
        let (r_m, acf) = self.radial_average();
        let threshold = (-1.0f64).exp();
        for k in 1..r_m.len() {
            if acf[k] <= threshold {
                let t = (acf[k - 1] - threshold) / (acf[k - 1] - acf[k]);
                return r_m[k - 1] + t * (r_m[k] - r_m[k - 1]);
            }
        }
        f64::NAN
    }
}

#[cfg(test)]
mod tests;
