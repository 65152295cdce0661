//! Filtering to a lateral resolution: ISO 16610-61 areal Gaussian low-pass,
//! then resampling to the resolution's grid, NaN-aware.
//!
//! The ISO 16610-61 weighting function is s(r) = exp(−π (r/(α λc))²)/(α λc)²
//! with α = √(ln 2 / π), which transmits 50 % of the amplitude at the cut-off
//! wavelength λc. The new grid spacing is the resolution Δ; the cut-off is
//! λc = 2Δ, the Nyquist wavelength of that grid, so what the new grid cannot
//! represent is attenuated (to 6 % at λ = Δ) instead of aliased.
//!
//! Gaps: the filter is a normalised convolution, Σ s·h / Σ s over measured
//! points only; a new grid point is NaN when less than half of the kernel
//! weight that lies inside the map falls on measured points.
//! The Gaussian is separable, so both sums are two 1-D passes, and each
//! pass is evaluated only at the new grid points.

use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;

/// α of ISO 16610-61: 50 % transmission at the cut-off.
/// The wavelength above which the Gaussian of cut-off `cutoff_m` passes at
/// least `power` (0…1) of the power: its amplitude transmission is
/// exp(−π (α λc / λ)²) (ISO 16610-61), squared for power.
pub fn wavelength_passing_m(cutoff_m: f64, power: f64) -> f64 {
    iso_alpha() * cutoff_m / (power.recip().ln() / (2.0 * std::f64::consts::PI)).sqrt()
}

pub fn iso_alpha() -> f64 {
    (std::f64::consts::LN_2 / std::f64::consts::PI).sqrt()
}

/// One axis of the separable kernel: for each new grid point, the first old
/// index and the weights.
struct AxisKernel {
    taps: Vec<(usize, Vec<f64>)>,
}

impl AxisKernel {
    fn new(n_in: usize, spacing_m: f64, n_out: usize, resolution_m: f64, cutoff_m: f64) -> Self {
        let width_m = iso_alpha() * cutoff_m;
        // exp(−π·4) ≈ 3.5e-6: beyond two widths the weights do not matter.
        let reach = (2.0 * width_m / spacing_m).ceil() as i64;
        let taps = (0..n_out)
            .map(|o| {
                let x_m = o as f64 * resolution_m;
                let centre = (x_m / spacing_m).round() as i64;
                let lo = (centre - reach).max(0) as usize;
                let hi = ((centre + reach) as usize).min(n_in - 1);
                let weights = (lo..=hi)
                    .map(|i| {
                        let u = (i as f64 * spacing_m - x_m) / width_m;
                        (-std::f64::consts::PI * u * u).exp()
                    })
                    .collect();
                (lo, weights)
            })
            .collect();
        Self { taps }
    }
}

/// A map the filter reads a row (constant x) at a time, so it need not be
/// held whole: a stitched mosaic makes its rows when asked
/// ([`crate::blend::StitchedRows`]).
pub trait MapRows: Sync {
    /// Points along x and y.
    fn dim(&self) -> (usize, usize);
    /// Writes row `x` (its ny heights) into `row`.
    fn write_row(&self, x: usize, row: &mut [f64]);
}

impl MapRows for ArrayView2<'_, f64> {
    fn dim(&self) -> (usize, usize) {
        ArrayView2::dim(self)
    }

    fn write_row(&self, x: usize, row: &mut [f64]) {
        for (o, v) in row.iter_mut().zip(self.row(x)) {
            *o = *v;
        }
    }
}

/// New grid rows (constant x) filtered per band of map rows: a band holds
/// the ~20 rows each new row steps over plus two kernel reaches, 16 times
/// (27 MB on the paper's 8843-point rows).
const NEW_ROWS_PER_BAND: usize = 16;

/// Consecutive rows of a map, `first..first + len`, x-major.
struct RowBand {
    ny: usize,
    first: usize,
    values: Vec<f64>,
}

impl RowBand {
    /// Holds rows `first..end` of `map`, keeping those already held (the
    /// bands of successive new rows overlap by a kernel's reach).
    fn advance(&mut self, map: &dyn MapRows, first: usize, end: usize) {
        let held_end = self.first + self.values.len() / self.ny;
        if first >= self.first && first < held_end {
            self.values.drain(..(first - self.first) * self.ny);
        } else {
            self.values.clear();
        }
        self.first = first;
        let have = (first + self.values.len() / self.ny).min(end);
        self.values.truncate((have - first) * self.ny);
        self.values.resize((end - first) * self.ny, 0.0);
        self.values[(have - first) * self.ny..]
            .par_chunks_mut(self.ny)
            .enumerate()
            .for_each(|(k, row)| map.write_row(have + k, row));
    }

    fn row(&self, x: usize) -> &[f64] {
        let start = (x - self.first) * self.ny;
        &self.values[start..start + self.ny]
    }
}

/// Low-pass filters `h` (spacing dx, dy) with cut-off 2·resolution and
/// samples it every `resolution_m`, starting at the first point. Returns
/// the new map; its spacing is `resolution_m` in both directions.
pub fn gaussian_resample(h: &Array2<f64>, dx_m: f64, dy_m: f64, resolution_m: f64) -> Array2<f64> {
    gaussian_resample_rows(&h.view(), dx_m, dy_m, resolution_m)
}

/// [`gaussian_resample`] of a map read a band of rows at a time: never
/// more than a band of its rows is held. An empty map gives an empty one.
pub fn gaussian_resample_rows(
    map: &dyn MapRows,
    dx_m: f64,
    dy_m: f64,
    resolution_m: f64,
) -> Array2<f64> {
    let (nx, ny) = map.dim();
    if nx == 0 || ny == 0 {
        return Array2::zeros((0, 0));
    }
    let cutoff_m = 2.0 * resolution_m;
    let n_out =
        |n: usize, d: f64| ((n as f64 - 1.0) * d / resolution_m + 1e-9).floor() as usize + 1;
    let (mx, my) = (n_out(nx, dx_m), n_out(ny, dy_m));
    let kx = AxisKernel::new(nx, dx_m, mx, resolution_m, cutoff_m);
    let ky = AxisKernel::new(ny, dy_m, my, resolution_m, cutoff_m);

    let mut out = Array2::<f64>::zeros((mx, my));
    let mut band = RowBand {
        ny,
        first: 0,
        values: Vec::new(),
    };
    for (rows_out, taps) in out
        .as_slice_mut()
        .expect("a fresh array is contiguous")
        .chunks_mut(my * NEW_ROWS_PER_BAND)
        .zip(kx.taps.chunks(NEW_ROWS_PER_BAND))
    {
        // The first tap of each new row never moves back.
        let first = taps[0].0;
        let end = taps
            .iter()
            .map(|(lo, w)| lo + w.len())
            .max()
            .unwrap_or(first);
        band.advance(map, first, end);
        rows_out
            .par_chunks_mut(my)
            .zip(taps.par_iter())
            .for_each(|(row_out, (lo, weights))| filter_row(&band, (*lo, weights), &ky, row_out));
    }
    out
}

/// One new row: pass 1 along x sums s·h and s over the measured points of
/// every old y (and s over all points, the weight inside the map); pass 2
/// along y at each new y, NaN where under half the kernel weight inside
/// the map was measured.
fn filter_row(
    band: &RowBand,
    (lo, weights): (usize, &[f64]),
    ky: &AxisKernel,
    row_out: &mut [f64],
) {
    let mut num = vec![0.0; band.ny];
    let mut den = vec![0.0; band.ny];
    for (k, &w) in weights.iter().enumerate() {
        let row = band.row(lo + k);
        for ((n, d), &v) in num.iter_mut().zip(den.iter_mut()).zip(row.iter()) {
            if !v.is_nan() {
                *n += w * v;
                *d += w;
            }
        }
    }
    let wx_total: f64 = weights.iter().sum();
    for (o, (lo, weights)) in row_out.iter_mut().zip(&ky.taps) {
        let (mut n, mut d, mut total) = (0.0, 0.0, 0.0);
        for (k, &w) in weights.iter().enumerate() {
            n += w * num[lo + k];
            d += w * den[lo + k];
            total += w;
        }
        *o = if d >= 0.5 * total * wx_total {
            n / d
        } else {
            f64::NAN
        };
    }
}

/// A map's grid: points and spacing along x and y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub dx_m: f64,
    pub dy_m: f64,
}

impl Grid {
    /// The q range of the map's PSDs, as the radial PSD spans it:
    /// 2π / (longest side) to π / (coarser spacing).
    pub fn q_range_per_m(&self) -> (f64, f64) {
        let longest_m = (self.nx as f64 * self.dx_m).max(self.ny as f64 * self.dy_m);
        (
            std::f64::consts::TAU / longest_m,
            std::f64::consts::PI / self.dx_m.max(self.dy_m),
        )
    }
}

/// The share of the measured map's PSD range, in log q, that filtering to
/// `filtered` discards: the filter keeps q up to π / resolution (its
/// cut-off 2·resolution, 50 % amplitude there), the map's q range is
/// [`Grid::q_range_per_m`]. 0 when nothing is discarded. Log q because the
/// PSD is binned, fitted and plotted in log q: "half the range" is half the
/// decades.
pub fn discarded_log_q_fraction(measured: &Grid, filtered: &Grid) -> f64 {
    let (q_min, q_max) = measured.q_range_per_m();
    let kept_max = filtered.q_range_per_m().1;
    ((q_max / kept_max).ln() / (q_max / q_min).ln()).clamp(0.0, 1.0)
}

/// What filtering did to the grid, said in a note; a second note, starting
/// with "warning:", when more than half of the PSD's log-q range is gone.
pub fn filter_notes(measured: &Grid, filtered: &Grid, resolution_m: f64) -> Vec<String> {
    let mut notes = vec![format!(
        "filtered to resolution_m = {resolution_m:e} m: {} × {} points at {:.4e} × {:.4e} m → \
         {} × {} at {resolution_m:e} m (ISO 16610-61 Gaussian, cut-off {:e} m; resolution_m: 0 \
         keeps the measured grid)",
        measured.nx,
        measured.ny,
        measured.dx_m,
        measured.dy_m,
        filtered.nx,
        filtered.ny,
        2.0 * resolution_m
    )];
    let (before, after) = (measured.nx * measured.ny, filtered.nx * filtered.ny);
    if (after as f64) < 0.1 * before as f64 {
        notes.push(format!(
            "warning: the filter keeps {after} of the {before} measured points ({:.2} %): \
             resolution_m = {resolution_m:e} m is {:.0} times the measured spacing; set \
             resolution_m: 0 to keep the measured grid, or a resolution the instrument's \
             lateral resolution calls for",
            100.0 * after as f64 / before as f64,
            resolution_m / measured.dx_m.max(measured.dy_m)
        ));
    }
    let discarded = discarded_log_q_fraction(measured, filtered);
    if discarded > 0.5 {
        let (q_min, q_max) = measured.q_range_per_m();
        notes.push(format!(
            "warning: the filter discards {:.0} % of the PSD's range in log q (the measured map \
             spans q = {q_min:.3e} … {q_max:.3e} rad/m, the filtered one ends at {:.3e} rad/m): \
             the short wavelengths the instrument measured are not in the PSD, σ's slope or H; \
             lower resolution_m (0 keeps the measured grid)",
            100.0 * discarded,
            filtered.q_range_per_m().1
        ));
    }
    notes
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// Amplitude ratio of a sinusoid of wavelength λ through the filter.
    fn transmission(lambda_px: f64, resolution_px: f64) -> f64 {
        let (n, a) = (2048, 1.0);
        // A sinusoid along x only; rows along y are constant.
        let h = Array2::from_shape_fn((n, 4), |(i, _)| a * (TAU * i as f64 / lambda_px).cos());
        let f = gaussian_resample(&h, 1.0, 1.0, resolution_px);
        // Amplitude from the middle, away from edge effects: least-squares
        // fit of c·cos + s·sin.
        let rows = f.nrows();
        let (mut cc, mut cs, mut ss, mut fc, mut fs) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for o in rows / 4..3 * rows / 4 {
            let phase = TAU * o as f64 * resolution_px / lambda_px;
            let (c, s) = (phase.cos(), phase.sin());
            cc += c * c;
            cs += c * s;
            ss += s * s;
            fc += f[[o, 0]] * c;
            fs += f[[o, 0]] * s;
        }
        let det = cc * ss - cs * cs;
        if det.abs() < 1e-9 * cc * cc {
            return (fc / cc).abs() / a;
        }
        let (c, s) = ((fc * ss - fs * cs) / det, (fs * cc - fc * cs) / det);
        c.hypot(s) / a
    }

    /// The filter as it was before it read the map in bands: pass 1 for
    /// every new x over the whole map, then pass 2 (#35 keeps its bits).
    fn two_pass_reference(h: &Array2<f64>, dx_m: f64, dy_m: f64, resolution_m: f64) -> Array2<f64> {
        let (nx, ny) = h.dim();
        let n_out =
            |n: usize, d: f64| ((n as f64 - 1.0) * d / resolution_m + 1e-9).floor() as usize + 1;
        let (mx, my) = (n_out(nx, dx_m), n_out(ny, dy_m));
        let kx = AxisKernel::new(nx, dx_m, mx, resolution_m, 2.0 * resolution_m);
        let ky = AxisKernel::new(ny, dy_m, my, resolution_m, 2.0 * resolution_m);
        let pass1: Vec<(Vec<f64>, Vec<f64>, f64)> = kx
            .taps
            .iter()
            .map(|(lo, weights)| {
                let (mut num, mut den) = (vec![0.0; ny], vec![0.0; ny]);
                for (k, &w) in weights.iter().enumerate() {
                    for y in 0..ny {
                        let v = h[[lo + k, y]];
                        if !v.is_nan() {
                            num[y] += w * v;
                            den[y] += w;
                        }
                    }
                }
                (num, den, weights.iter().sum())
            })
            .collect();
        Array2::from_shape_fn((mx, my), |(o, p)| {
            let (num, den, wx_total) = &pass1[o];
            let (lo, weights) = &ky.taps[p];
            let (mut n, mut d, mut total) = (0.0, 0.0, 0.0);
            for (k, &w) in weights.iter().enumerate() {
                n += w * num[lo + k];
                d += w * den[lo + k];
                total += w;
            }
            if d >= 0.5 * total * wx_total {
                n / d
            } else {
                f64::NAN
            }
        })
    }

    #[test]
    fn filtering_in_bands_keeps_the_bits_of_two_whole_passes() {
        // Rough heights with scattered and large holes; grids whose new rows
        // span several bands (and a last, partial one), on 1–3 threads.
        let h = Array2::from_shape_fn((431, 67), |(i, j)| {
            let v = (0.37 * i as f64).sin() * 1e-6
                + (1.7 * j as f64 + 0.01 * (i * i) as f64).cos() * 3e-7;
            if (i * 31 + j * 17) % 23 == 0 || (200..260).contains(&i) && j < 40 {
                f64::NAN
            } else {
                v
            }
        });
        for (dx_m, dy_m, resolution_m) in [(1.0, 0.9, 2.3), (1.0, 1.0, 5.0), (0.7, 1.3, 1.31)] {
            let reference = two_pass_reference(&h, dx_m, dy_m, resolution_m);
            assert!(
                reference.nrows() > 2 * NEW_ROWS_PER_BAND,
                "{}",
                reference.nrows()
            );
            for threads in 1..=3 {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let banded = pool.install(|| gaussian_resample(&h, dx_m, dy_m, resolution_m));
                assert_eq!(banded.dim(), reference.dim());
                for (b, r) in banded.iter().zip(&reference) {
                    assert_eq!(b.to_bits(), r.to_bits(), "{dx_m} {dy_m} {resolution_m}");
                }
            }
            assert!(reference.iter().any(|v| v.is_nan()) && reference.iter().any(|v| !v.is_nan()));
        }
        for empty in [(0, 5), (5, 0)] {
            assert_eq!(
                gaussian_resample(&Array2::zeros(empty), 1.0, 1.0, 2.0).dim(),
                (0, 0)
            );
        }
    }

    #[test]
    fn transmits_half_the_amplitude_at_the_cut_off() {
        // ISO 16610-61: 50 % at λc = 2·resolution (10 px here); elsewhere
        // exp(−π α² (λc/λ)²).
        let res = 5.0;
        // At λc (the new grid's Nyquist wavelength) the sine is invisible:
        // the map is a pure cosine there, so the fit stays well posed.
        let at_cut_off = transmission(10.0, res);
        assert!((at_cut_off - 0.5).abs() < 0.01, "{at_cut_off}");
        for lambda in [20.0_f64, 40.0, 100.0] {
            let expected =
                (-std::f64::consts::PI * iso_alpha().powi(2) * (10.0 / lambda).powi(2)).exp();
            let got = transmission(lambda, res);
            assert!(
                (got - expected).abs() < 0.01,
                "λ {lambda}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn passes_the_stated_power_beyond_its_wavelength() {
        // Measured transmission of the filter itself, squared for power.
        let lambda_px = wavelength_passing_m(10.0, 0.9);
        assert!((lambda_px / 10.0 - 3.63).abs() < 0.01, "{lambda_px}");
        let got = transmission(lambda_px, 5.0).powi(2);
        assert!((got - 0.9).abs() < 0.01, "{got}");
    }

    #[test]
    fn keeps_constants_fills_small_gaps_and_leaves_big_holes_nan() {
        let mut h = Array2::from_elem((100, 100), 3.0);
        h[[50, 50]] = f64::NAN;
        for i in 0..40 {
            for j in 0..100 {
                h[[i, j]] = f64::NAN;
            }
        }
        let f = gaussian_resample(&h, 1.0, 1.0, 5.0);
        assert_eq!(f.dim(), (20, 20));
        assert!((f[[10, 10]] - 3.0).abs() < 1e-12);
        assert!(f[[0, 5]].is_nan());
        assert!(
            f.iter()
                .filter(|v| !v.is_nan())
                .all(|v| (v - 3.0).abs() < 1e-12)
        );
        // The hole's edge at x = 40 px sits between new points 7 and 8.
        assert!(f[[7, 5]].is_nan() && !f[[9, 5]].is_nan());
    }

    #[test]
    fn the_discarded_share_of_the_psd_range_is_counted_in_log_q() {
        // 1000 points at 1 µm: q from 2π/1 mm to π/1 µm, 2.7 decades.
        let measured = Grid {
            nx: 1000,
            ny: 800,
            dx_m: 1e-6,
            dy_m: 1e-6,
        };
        let at = |resolution_m: f64| Grid {
            nx: (1000.0e-6 / resolution_m) as usize,
            ny: (800.0e-6 / resolution_m) as usize,
            dx_m: resolution_m,
            dy_m: resolution_m,
        };
        // Half the decades: π/res = sqrt(2π/1 mm · π/1 µm).
        let half_m = std::f64::consts::PI / (TAU / 1e-3 * std::f64::consts::PI / 1e-6).sqrt();
        assert!((discarded_log_q_fraction(&measured, &at(half_m)) - 0.5).abs() < 1e-12);
        assert_eq!(discarded_log_q_fraction(&measured, &measured), 0.0);
        // Issue #17's case: a 1.1 µm map of 640 × 480 at 20 µm.
        let metropro = Grid {
            nx: 640,
            ny: 480,
            dx_m: 1.0982520279867458e-06,
            dy_m: 1.0982520279867458e-06,
        };
        let coarse = Grid {
            nx: 36,
            ny: 27,
            dx_m: 20e-6,
            dy_m: 20e-6,
        };
        let d = discarded_log_q_fraction(&metropro, &coarse);
        assert!((d - 0.503).abs() < 0.001, "{d}");
        let notes = filter_notes(&metropro, &coarse, 20e-6);
        assert!(
            notes[0].contains("640 × 480 points at 1.0983e-6 × 1.0983e-6 m → 36 × 27 at 2e-5 m")
        );
        assert!(
            notes[1].starts_with(
                "warning: the filter keeps 972 of the 307200 measured points (0.32 %): \
                 resolution_m = 2e-5 m is 18 times the measured spacing"
            ),
            "{notes:?}"
        );
        assert!(notes[2].starts_with("warning: the filter discards 50 % of the PSD's range"));
        // 3 µm keeps 333 × 266 of 1000 × 800 points (11 %) and most of the
        // log-q range: the grid note only.
        let notes = filter_notes(&measured, &at(3e-6), 3e-6);
        assert_eq!(notes.len(), 1, "{notes:?}");
        // 4 µm keeps 250 × 200 (6.25 %): a warning on the points alone.
        let notes = filter_notes(&measured, &at(4e-6), 4e-6);
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(notes[1].contains("keeps 50000 of the 800000 measured points (6.25 %)"));
        // 30 µm also discards more than half the log-q range.
        let notes = filter_notes(&measured, &at(30e-6), 30e-6);
        assert_eq!(notes.len(), 3, "{notes:?}");
        assert!(
            notes[2].starts_with("warning: the filter discards"),
            "{notes:?}"
        );
    }
}
