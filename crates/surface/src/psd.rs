//! Power spectral densities in the conventions of the SurfaceTopography
//! package (Jacobs, Junge & Pastewka, Surf. Topogr. Metrol. Prop. 5, 013001,
//! 2017; `Uniform/PowerSpectrum.py`), so numbers compare one to one:
//!
//! - array axis 0 is x; L = N·Δx; q = 2πk/L in rad/m;
//! - 1-D along x: C1D(q_k) = |Δx · FFT_x(w·h)|² / Lx for k = 0 … Nx/2 − 1
//!   (Nyquist dropped; +q and −q are equal for real h), averaged over all
//!   profiles; along y the same on the transposed map;
//! - radial: C2D(q) = |Δx Δy · FFT2(w·h)|² / (Lx Ly), averaged over all
//!   wavevectors whose |q| falls in a bin, up to q = π·min(1/Δx, 1/Δy);
//! - bins: log-spaced edges 10^linspace(log10 q_min − 0.01, log10 q_max + 0.01,
//!   ⌈(log10 q_max − log10 q_min + 1)·per_decade⌉), a point belongs to the bin
//!   whose upper edge is the first ≥ its q, each bin reports the mean q and
//!   the mean C of its members; empty bins are left out;
//! - window: none for periodic maps; otherwise a periodic Hann window along
//!   the profile for 1-D PSDs and the rotationally symmetric Hann window
//!   (radius min(Lx, Ly)/2 about grid point (Nx/2, Ny/2), zero outside) for
//!   the radial PSD, each scaled so that mean(w²) = 1.
//!
//! Inputs must be free of NaN: the caller decides how to fill gaps.

use std::f64::consts::{PI, TAU};

use hypercontact_numeric::fft1::{self, Complex64, Direction};
use hypercontact_numeric::fft2::RealFft2;
use ndarray::Array2;
use rayon::prelude::*;

use hypercontact_numeric::reduce::{ScratchPool, add_into, reduce};

/// The window applied before the Fourier transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Window {
    /// For periodic maps.
    None,
    /// Hann, scaled so mean(w²) = 1 (1-D along profiles, radial in 2-D).
    Hann,
}

/// A PSD sampled at wavevectors q (rad/m).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spectrum {
    pub q_per_m: Vec<f64>,
    /// m³ for 1-D PSDs, m⁴ for 2-D ones.
    pub c: Vec<f64>,
}

/// The periodic ("DFT-even") Hann window of length n, scaled to mean(w²) = 1.
fn hann_1d(n: usize) -> Vec<f64> {
    let w: Vec<f64> = (0..n)
        .map(|i| 0.5 - 0.5 * (TAU * i as f64 / n as f64).cos())
        .collect();
    let scale = (n as f64 / w.iter().map(|v| v * v).sum::<f64>()).sqrt();
    w.into_iter().map(|v| v * scale).collect()
}

/// SurfaceTopography's rotationally symmetric Hann window at grid point
/// (i, j), before scaling to mean(w²) = 1: radius min(Lx, Ly)/2 about grid
/// point (nx/2, ny/2), zero outside.
struct HannRadial {
    centre: (f64, f64),
    spacing_m: (f64, f64),
    r_max_m: f64,
}

impl HannRadial {
    fn new(nx: usize, ny: usize, dx_m: f64, dy_m: f64) -> Self {
        Self {
            centre: ((nx / 2) as f64, (ny / 2) as f64),
            spacing_m: (dx_m, dy_m),
            r_max_m: (nx as f64 * dx_m).min(ny as f64 * dy_m) / 2.0,
        }
    }

    /// Row i of the window into `out` (length ny). The window is mirror
    /// symmetric about column ny/2, so each distance is evaluated once; r is
    /// sqrt(x² + y²) as SurfaceTopography's `get_window_2D` computes it.
    fn row(&self, i: usize, out: &mut [f64]) {
        let x = (i as f64 - self.centre.0) * self.spacing_m.0;
        let centre = self.centre.1 as usize;
        let reach = centre.max(out.len() - 1 - centre);
        let mut inside = true;
        for d in 0..=reach {
            let value = if inside {
                let y = d as f64 * self.spacing_m.1;
                let r = (x * x + y * y).sqrt();
                // r grows with d: once outside, the rest of the row is zero.
                inside = r <= self.r_max_m;
                if inside {
                    0.5 + 0.5 * (PI * r / self.r_max_m).cos()
                } else {
                    0.0
                }
            } else {
                0.0
            };
            if let Some(v) = out.get_mut(centre + d) {
                *v = value;
            }
            if d > 0 && d <= centre {
                out[centre - d] = value;
            }
        }
    }
}

/// The radial Hann window as an array, scaled so that mean(w²) = 1.
#[cfg(test)]
fn hann_radial(nx: usize, ny: usize, dx_m: f64, dy_m: f64) -> Array2<f64> {
    let hann = HannRadial::new(nx, ny, dx_m, dy_m);
    let mut w = Array2::zeros((nx, ny));
    for (i, mut row) in w.rows_mut().into_iter().enumerate() {
        hann.row(i, row.as_slice_mut().expect("a fresh array is contiguous"));
    }
    let sum_sq: f64 = w.iter().map(|v| v * v).sum();
    let scale = ((nx * ny) as f64 / sum_sq).sqrt();
    w.mapv_inplace(|v| v * scale);
    w
}

/// Columns (axis 1) gathered into contiguous buffers per block when
/// transforming along axis 0: enough to read whole cache lines of each row.
/// Blocks are also the units whose power sums are added in a fixed order
/// (`hypercontact_numeric::reduce`), so the PSD does not depend on the
/// thread count.
const BLOCK: usize = 16;

/// Contiguous profiles summed in one piece before the fixed-order merge.
const PROFILES_PER_BLOCK: usize = 32;

/// Room for BLOCK gathered columns of length n, and the FFT's scratch.
fn column_buffers(n: usize, scratch_len: usize) -> (Vec<Complex64>, Vec<Complex64>) {
    (
        vec![Complex64::default(); BLOCK * n],
        vec![Complex64::default(); scratch_len],
    )
}

/// The element-wise sum of `block_power` over `n_blocks` blocks of
/// profiles (`len` values each), every block computed with working buffers
/// from `make_buffers` and the sums added in a fixed order, so the result
/// has the same bits on any thread count.
fn summed_block_power<S: Send, F: Fn() -> S + Sync>(
    n_blocks: usize,
    len: usize,
    make_buffers: F,
    block_power: impl Fn(&mut S, usize) -> Vec<f64> + Sync,
) -> Vec<f64> {
    let pool = ScratchPool::new(make_buffers);
    reduce(
        n_blocks,
        || vec![0.0; len],
        |block| pool.with(|buffers| block_power(buffers, block)),
        add_into,
    )
}

/// q_k = 2π k / L, k = 0 … count − 1: the wavevectors of a profile of length `l_m`.
fn wavevectors_per_m(count: usize, l_m: f64) -> Vec<f64> {
    (0..count).map(|k| TAU * k as f64 / l_m).collect()
}

/// Profile-averaged 1-D PSD of the contiguous profiles of length n in
/// `profiles`, k = 0 … n/2 − 1, unbinned.
fn mean_profile_psd(profiles: &[f64], n: usize, spacing_m: f64, window: Window) -> Spectrum {
    let n_profiles = profiles.len() / n;
    let fft = fft1::real_forward(n);
    let w = match window {
        Window::Hann => Some(hann_1d(n)),
        Window::None => None,
    };
    let half = n / 2;
    let block_len = PROFILES_PER_BLOCK * n;
    let block_power = |(input, out): &mut (Vec<f64>, Vec<Complex64>), block: usize| {
        let mut acc = vec![0.0; half];
        let end = profiles.len().min((block + 1) * block_len);
        for profile in profiles[block * block_len..end].chunks_exact(n) {
            match &w {
                Some(w) => input
                    .iter_mut()
                    .zip(profile.iter().zip(w))
                    .for_each(|(o, (h, w))| *o = h * w),
                None => input.copy_from_slice(profile),
            }
            fft.process(input, out)
                .expect("buffer sizes match the plan");
            for (a, v) in acc.iter_mut().zip(out.iter()) {
                *a += v.norm_sqr();
            }
        }
        acc
    };
    let power = summed_block_power(
        n_profiles.div_ceil(PROFILES_PER_BLOCK),
        half,
        || (vec![0.0; n], fft.make_output_vec()),
        block_power,
    );
    let l_m = n as f64 * spacing_m;
    let norm = spacing_m * spacing_m / l_m / n_profiles as f64;
    Spectrum {
        q_per_m: wavevectors_per_m(half, l_m),
        c: power.into_iter().map(|p| p * norm).collect(),
    }
}

/// Unbinned 1-D PSD along x (axis 0), averaged over all profiles.
///
/// Two real profiles a, b go through one complex FFT as z = a + i·b; since
/// A_k = (Z_k + Z*_{n−k})/2 and B_k = (Z_k − Z*_{n−k})/(2i),
/// |A_k|² + |B_k|² = (|Z_k|² + |Z_{n−k}|²)/2, which is all the profile sum
/// needs. An odd last profile goes in with b = 0, for which the same holds.
/// Profiles are gathered BLOCK pairs at a time, so no transposed copy is made.
pub fn profile_psd_x(h: &Array2<f64>, dx_m: f64, window: Window) -> Spectrum {
    let (nx, ny) = h.dim();
    let standard = h.as_standard_layout();
    let data = standard
        .as_slice()
        .expect("as_standard_layout gives a contiguous array");
    let fft = fft1::complex(nx, Direction::Forward);
    let w = match window {
        Window::Hann => Some(hann_1d(nx)),
        Window::None => None,
    };
    let n_pairs = ny.div_ceil(2);
    let block_power = |(buffer, scratch): &mut (Vec<Complex64>, Vec<Complex64>), block: usize| {
        let first = block * BLOCK;
        let width = BLOCK.min(n_pairs - first);
        let columns = &mut buffer[..width * nx];
        for (i, row) in data.chunks_exact(ny).enumerate() {
            let wi = w.as_ref().map_or(1.0, |w| w[i]);
            for c in 0..width {
                let col = 2 * (first + c);
                let im = if col + 1 < ny { row[col + 1] } else { 0.0 };
                columns[c * nx + i] = Complex64::new(row[col] * wi, im * wi);
            }
        }
        fft.process_with_scratch(columns, scratch);
        let mut acc = vec![0.0; nx];
        for spectrum in columns.chunks_exact(nx) {
            for (a, v) in acc.iter_mut().zip(spectrum) {
                *a += v.norm_sqr();
            }
        }
        acc
    };
    let power = summed_block_power(
        n_pairs.div_ceil(BLOCK),
        nx,
        || column_buffers(nx, fft.get_inplace_scratch_len()),
        block_power,
    );
    let l_m = nx as f64 * dx_m;
    let norm = dx_m * dx_m / l_m / ny as f64;
    Spectrum {
        q_per_m: wavevectors_per_m(nx / 2, l_m),
        c: (0..nx / 2)
            .map(|k| 0.5 * (power[k] + power[(nx - k) % nx]) * norm)
            .collect(),
    }
}

/// Unbinned 1-D PSD along y (axis 1), averaged over all profiles.
pub fn profile_psd_y(h: &Array2<f64>, dy_m: f64, window: Window) -> Spectrum {
    let standard = h.as_standard_layout();
    let data = standard
        .as_slice()
        .expect("as_standard_layout gives a contiguous array");
    mean_profile_psd(data, h.ncols(), dy_m, window)
}

/// SurfaceTopography's log-spaced bin edges between q_min and q_max.
pub fn log_bin_edges(q_min: f64, q_max: f64, per_decade: usize) -> Vec<f64> {
    let (lo, hi) = (q_min.log10() - 0.01, q_max.log10() + 0.01);
    let n = (((q_max.log10() - q_min.log10() + 1.0) * per_decade as f64).ceil() as usize).max(2);
    (0..n)
        .map(|i| 10f64.powf(lo + (hi - lo) * i as f64 / (n - 1) as f64))
        .collect()
}

/// Bin index (1 … edges.len() − 1) of q, or None outside the edges: the
/// first edge ≥ q, as numpy's `searchsorted` (side "left") finds it.
fn bin_of(edges: &[f64], q: f64) -> Option<usize> {
    let b = edges.partition_point(|e| *e < q);
    (b >= 1 && b < edges.len()).then_some(b)
}

/// Weighted sums per bin: (Σw, Σw·q, Σw·C).
type BinSums = Vec<[f64; 3]>;

fn finish_bins(sums: &BinSums) -> Spectrum {
    let mut out = Spectrum::default();
    for s in sums.iter().skip(1) {
        if s[0] > 0.0 {
            out.q_per_m.push(s[1] / s[0]);
            out.c.push(s[2] / s[0]);
        }
    }
    out
}

/// Averages an unbinned spectrum in log bins from q_min to q_max.
pub fn bin_average(spectrum: &Spectrum, q_min: f64, q_max: f64, per_decade: usize) -> Spectrum {
    let edges = log_bin_edges(q_min, q_max, per_decade);
    let mut sums: BinSums = vec![[0.0; 3]; edges.len()];
    for (&q, &c) in spectrum.q_per_m.iter().zip(&spectrum.c) {
        if let Some(b) = bin_of(&edges, q) {
            sums[b][0] += 1.0;
            sums[b][1] += q;
            sums[b][2] += c;
        }
    }
    finish_bins(&sums)
}

/// Binned 1-D PSD along x, as SurfaceTopography's
/// `power_spectrum_from_profile()` (q from 2π/Lx to π/Δx, q = 0 left out).
pub fn psd_x(h: &Array2<f64>, dx_m: f64, window: Window, per_decade: usize) -> Spectrum {
    let raw = profile_psd_x(h, dx_m, window);
    let l_m = h.nrows() as f64 * dx_m;
    bin_average(&raw, TAU / l_m, PI / dx_m, per_decade)
}

/// Binned 1-D PSD along y (the x convention on the transposed map).
pub fn psd_y(h: &Array2<f64>, dy_m: f64, window: Window, per_decade: usize) -> Spectrum {
    let raw = profile_psd_y(h, dy_m, window);
    let l_m = h.ncols() as f64 * dy_m;
    bin_average(&raw, TAU / l_m, PI / dy_m, per_decade)
}

/// Radially averaged 2-D PSD, as SurfaceTopography's
/// `power_spectrum_from_area()`.
pub fn psd_radial(
    h: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    window: Window,
    per_decade: usize,
) -> Spectrum {
    let (nx, ny) = h.dim();
    let (lx, ly) = (nx as f64 * dx_m, ny as f64 * dy_m);
    let nh = ny / 2 + 1;
    let standard = h.as_standard_layout();
    let data = standard
        .as_slice()
        .expect("as_standard_layout gives a contiguous array");

    // The window is made a row at a time and its mean square folded into
    // the normalisation; the per-row sums are added in row order (a
    // parallel sum would not be the same on every thread count).
    let hann = HannRadial::new(nx, ny, dx_m, dy_m);
    let (windowed, sum_w2) = match window {
        Window::Hann => {
            let mut windowed = vec![0.0; nx * ny];
            let row_sums_w2: Vec<f64> = windowed
                .par_chunks_mut(ny)
                .zip(data.par_chunks(ny))
                .enumerate()
                .map_init(
                    || vec![0.0; ny],
                    |w_row, (i, (out, row))| {
                        hann.row(i, w_row);
                        let mut sum_w2 = 0.0;
                        for ((x, h), w) in out.iter_mut().zip(row).zip(w_row.iter()) {
                            *x = h * w;
                            sum_w2 += w * w;
                        }
                        sum_w2
                    },
                )
                .collect();
            (Some(windowed), row_sums_w2.iter().sum())
        }
        Window::None => (None, 0.0),
    };
    let window_scale2 = match window {
        Window::Hann => (nx * ny) as f64 / sum_w2,
        Window::None => 1.0,
    };
    // The half spectrum (real transforms along y, complex ones along x),
    // column-major: column j of it is spectrum[j·nx ..].
    let fft = RealFft2::new(nx, ny).expect("the map is not empty");
    let mut spectrum = vec![Complex64::default(); fft.spectrum_len()];
    fft.forward(
        windowed.as_deref().unwrap_or(data),
        (nx, ny),
        &mut spectrum,
        &mut fft.workspace(),
    )
    .expect("the spectrum's length comes from the plan");

    // Columns binned BLOCK at a time, the blocks' sums merged in a fixed order.
    let q_min = (TAU / lx).min(TAU / ly);
    let q_max = PI * (1.0 / dx_m).min(1.0 / dy_m);
    let edges = log_bin_edges(q_min, q_max, per_decade);
    let wrap = |k: usize, n: usize| if k > n / 2 { n - k } else { k } as f64;
    let block_sums = |block: usize| {
        let first = block * BLOCK;
        let width = BLOCK.min(nh - first);
        let mut sums: BinSums = vec![[0.0; 3]; edges.len()];
        let columns = &spectrum[first * nx..(first + width) * nx];
        for (c, column) in columns.chunks_exact(nx).enumerate() {
            let j = first + c;
            bin_column(
                &mut sums,
                &edges,
                column,
                j,
                ny,
                TAU / lx,
                TAU / ly * wrap(j, ny),
            );
        }
        sums
    };
    let mut sums = reduce(
        nh.div_ceil(BLOCK),
        || vec![[0.0; 3]; edges.len()],
        block_sums,
        |mut a: BinSums, b: BinSums| {
            for (x, y) in a.iter_mut().zip(b) {
                for k in 0..3 {
                    x[k] += y[k];
                }
            }
            a
        },
    );
    let norm = (dx_m * dy_m).powi(2) / (lx * ly) * window_scale2;
    for s in &mut sums {
        s[2] *= norm;
    }
    finish_bins(&sums)
}

/// Adds the power |v|² of column j (of ny) of the half spectrum to the bins.
/// Column j stands for itself and its mirror ny − j, except j = 0 and (for
/// even ny) j = ny/2, so the result is the full-grid average. Rows k and
/// nx − k share |q| and go in together; along k, |q| grows, so the bin is
/// found by walking the edges once (numpy's `searchsorted`, side "left").
/// |q| is sqrt(qx² + qy²) as SurfaceTopography computes it.
fn bin_column(
    sums: &mut BinSums,
    edges: &[f64],
    column: &[Complex64],
    j: usize,
    ny: usize,
    dqx_per_m: f64,
    qy_per_m: f64,
) {
    let nx = column.len();
    let weight = if j == 0 || 2 * j == ny { 1.0 } else { 2.0 };
    let qy2 = qy_per_m * qy_per_m;
    let mut b = 0;
    for k in 0..=nx / 2 {
        let qx = dqx_per_m * k as f64;
        let q = (qx * qx + qy2).sqrt();
        while b < edges.len() && edges[b] < q {
            b += 1;
        }
        if b == edges.len() {
            break;
        }
        if b == 0 {
            continue;
        }
        let (members, power) = if k == 0 || 2 * k == nx {
            (1.0, column[k].norm_sqr())
        } else {
            (2.0, column[k].norm_sqr() + column[nx - k].norm_sqr())
        };
        let s = &mut sums[b];
        s[0] += weight * members;
        s[1] += weight * members * q;
        s[2] += weight * power;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinusoid_peaks_at_its_wavevector_with_parseval_power() {
        // h = a·cos(q0 x) along x with q0 = 2π·k0/L: the 1-D PSD is zero but
        // at k0, where C = |Δx·a·N/2|² / L = a² L / 4; summing C·Δq over
        // ±q gives back the mean square a²/2 (Parseval).
        let (nx, ny, dx, a, k0) = (256, 8, 2e-6, 3e-7, 19);
        let l = nx as f64 * dx;
        let h = Array2::from_shape_fn((nx, ny), |(i, _)| {
            a * (TAU * k0 as f64 * i as f64 / nx as f64).cos()
        });
        let s = profile_psd_x(&h, dx, Window::None);
        let peak = (0..s.c.len())
            .max_by(|&i, &j| s.c[i].total_cmp(&s.c[j]))
            .unwrap();
        assert_eq!(peak, k0);
        assert!((s.q_per_m[k0] - TAU * k0 as f64 / l).abs() < 1e-6);
        assert!((s.c[k0] / (a * a * l / 4.0) - 1.0).abs() < 1e-12);
        let dq = TAU / l;
        let mean_square: f64 = s.c.iter().skip(1).map(|c| 2.0 * c * dq / TAU).sum();
        assert!((mean_square / (a * a / 2.0) - 1.0).abs() < 1e-12);
        // Along y the map is constant: all power at q = 0.
        let sy = profile_psd_y(&h, dx, Window::None);
        assert!(sy.c.iter().skip(1).all(|c| *c < 1e-30));
    }

    #[test]
    fn radial_psd_of_a_plane_wave_has_parseval_power() {
        // A plane wave along (k0, k1) puts its power in two Fourier
        // coefficients; the radial bin holding them has
        // Σ C·(2π)²/(Lx Ly) over members = mean square.
        let (nx, ny, dx) = (128, 96, 1e-6);
        let (k0, k1, a) = (12.0, 9.0, 1e-7);
        let h = Array2::from_shape_fn((nx, ny), |(i, j)| {
            a * (TAU * (k0 * i as f64 / nx as f64 + k1 * j as f64 / ny as f64)).sin()
        });
        let s = psd_radial(&h, dx, dx, Window::None, 10);
        let (lx, ly) = (nx as f64 * dx, ny as f64 * dx);
        let q0 = (TAU * k0 / lx).hypot(TAU * k1 / ly);
        let b = (0..s.c.len())
            .max_by(|&i, &j| s.c[i].total_cmp(&s.c[j]))
            .unwrap();
        // The bin's mean q is q0 pulled by its empty members; the bin holds q0.
        let edges = log_bin_edges(TAU / lx, PI / dx, 10);
        let bq = bin_of(&edges, q0).unwrap();
        assert!(edges[bq - 1] < s.q_per_m[b] && s.q_per_m[b] <= edges[bq]);
        // Count the bin's members to undo the average.
        let mut members = 0.0;
        for i in 0..nx {
            for j in 0..ny {
                let wi = if i > nx / 2 { nx - i } else { i } as f64;
                let wj = if j > ny / 2 { ny - j } else { j } as f64;
                if bin_of(&edges, (TAU / lx * wi).hypot(TAU / ly * wj)) == Some(bq) {
                    members += 1.0;
                }
            }
        }
        let mean_square = s.c[b] * members / (lx * ly);
        assert!((mean_square / (a * a / 2.0) - 1.0).abs() < 1e-10);
    }

    #[test]
    fn windows_have_unit_mean_square() {
        let w = hann_1d(100);
        assert!((w.iter().map(|v| v * v).sum::<f64>() / 100.0 - 1.0).abs() < 1e-12);
        assert_eq!(w[0], 0.0);
        let w2 = hann_radial(64, 48, 1.0, 1.0);
        assert!((w2.iter().map(|v| v * v).sum::<f64>() / (64.0 * 48.0) - 1.0).abs() < 1e-12);
        assert_eq!(w2[[0, 0]], 0.0);
        assert!(w2[[32, 24]] > 1.0);
    }

    #[test]
    fn white_noise_has_a_flat_psd_at_its_variance() {
        // Uncorrelated heights of variance s²: C1D = s²·Δx, C2D = s²·Δx·Δy.
        let (n, dx) = (256, 1e-6);
        let mut state = 12345u64;
        let h = Array2::from_shape_fn((n, n), |_| {
            // Sum of 12 uniforms − 6: unit variance, enough for this check.
            (0..12)
                .map(|_| {
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    (state >> 11) as f64 / (1u64 << 53) as f64
                })
                .sum::<f64>()
                - 6.0
        });
        let x = psd_x(&h, dx, Window::None, 10);
        let r = psd_radial(&h, dx, dx, Window::None, 10);
        let tail = |s: &Spectrum| s.c[s.c.len() - 5..].iter().sum::<f64>() / 5.0;
        assert!((tail(&x) / dx - 1.0).abs() < 0.05, "{}", tail(&x) / dx);
        assert!((tail(&r) / (dx * dx) - 1.0).abs() < 0.05);
    }

    /// Uniform pseudo-random heights in [−0.5, 0.5), deterministic.
    fn noise(nx: usize, ny: usize, seed: u64) -> Array2<f64> {
        let mut state = seed;
        Array2::from_shape_fn((nx, ny), |_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    #[test]
    fn spectra_have_the_same_bits_on_any_number_of_threads() {
        // Big enough that every parallel loop splits into many blocks, odd
        // sizes so the last blocks are partial.
        let h = noise(301, 389, 11);
        let all = || {
            [Window::None, Window::Hann].map(|window| {
                [
                    psd_x(&h, 1e-6, window, 10),
                    psd_y(&h, 1e-6, window, 10),
                    psd_radial(&h, 1e-6, 1.2e-6, window, 10),
                ]
            })
        };
        let in_pool = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(all)
        };
        let bits = |spectra: [[Spectrum; 3]; 2]| -> Vec<Vec<u64>> {
            spectra
                .iter()
                .flatten()
                .flat_map(|s| [&s.q_per_m, &s.c])
                .map(|v| v.iter().map(|x| x.to_bits()).collect())
                .collect()
        };
        let one = bits(in_pool(1));
        for threads in [2, 4] {
            assert!(bits(in_pool(threads)) == one, "{threads} threads");
        }
    }

    /// |Σ_i Σ_j v_ij e^{−2πi(k i/nx + l j/ny)}|² by direct summation.
    fn direct_power(v: &Array2<f64>, k: usize, l: usize) -> f64 {
        let (nx, ny) = v.dim();
        let mut sum = Complex64::default();
        for ((i, j), h) in v.indexed_iter() {
            let phase =
                -TAU * (((k * i) % nx) as f64 / nx as f64 + ((l * j) % ny) as f64 / ny as f64);
            sum += Complex64::from_polar(*h, phase);
        }
        sum.norm_sqr()
    }

    #[test]
    fn fast_paths_match_direct_fourier_sums() {
        // Odd ny (an unpaired profile, a half spectrum without Nyquist
        // column), non-square pixels, both windows: the paired-profile FFT,
        // the blocked column transforms and the walking bin search against
        // the definitions in the module doc evaluated term by term.
        let (nx, ny, dx, dy) = (40, 37, 1e-6, 1.3e-6);
        let h = noise(nx, ny, 7);
        let (lx, ly) = (nx as f64 * dx, ny as f64 * dy);
        for window in [Window::None, Window::Hann] {
            // 1-D along x: each column's DFT, averaged over columns.
            let w = match window {
                Window::Hann => hann_1d(nx),
                Window::None => vec![1.0; nx],
            };
            let fast = profile_psd_x(&h, dx, window);
            assert_eq!(fast.c.len(), nx / 2);
            for k in 0..nx / 2 {
                let mut c = 0.0;
                for j in 0..ny {
                    let column = Array2::from_shape_fn((nx, 1), |(i, _)| w[i] * h[[i, j]]);
                    c += direct_power(&column, k, 0) * dx * dx / lx;
                }
                c /= ny as f64;
                assert!(
                    (fast.c[k] / c - 1.0).abs() < 1e-10,
                    "x, k = {k}: {} vs {c}",
                    fast.c[k]
                );
            }

            // Radial: the full 2-D grid, binned with bin_of.
            let windowed = match window {
                Window::Hann => &h * &hann_radial(nx, ny, dx, dy),
                Window::None => h.clone(),
            };
            let edges = log_bin_edges((TAU / lx).min(TAU / ly), PI / dy, 10);
            let mut sums: BinSums = vec![[0.0; 3]; edges.len()];
            for k in 0..nx {
                for l in 0..ny {
                    let qx = TAU / lx * (if k > nx / 2 { nx - k } else { k }) as f64;
                    let qy = TAU / ly * (if l > ny / 2 { ny - l } else { l }) as f64;
                    let q = (qx * qx + qy * qy).sqrt();
                    if let Some(b) = bin_of(&edges, q) {
                        let c = direct_power(&windowed, k, l) * (dx * dy).powi(2) / (lx * ly);
                        sums[b][0] += 1.0;
                        sums[b][1] += q;
                        sums[b][2] += c;
                    }
                }
            }
            let expected = finish_bins(&sums);
            let fast = psd_radial(&h, dx, dy, window, 10);
            assert_eq!(fast.c.len(), expected.c.len());
            for (b, (c, e)) in fast.c.iter().zip(&expected.c).enumerate() {
                assert!((c / e - 1.0).abs() < 1e-9, "radial bin {b}: {c} vs {e}");
                assert!((fast.q_per_m[b] / expected.q_per_m[b] - 1.0).abs() < 1e-12);
            }
        }
    }
}
