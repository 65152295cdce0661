//! Cyclic 2-D convolution of a real map with a real, even kernel by FFTs, on
//! a transform grid at least as large as the map (the rest zero: Hockney's
//! padding for the free surface, none for a periodic one).
//!
//! Layout: maps are row-major with axis 1 (y) contiguous, as `Field` holds
//! them. A transform is real-to-complex along y (`realfft`), then complex
//! along x (`rustfft`) on the transposed half-spectrum, so that both passes
//! run over contiguous memory. The padding rows are never transformed along
//! y (their spectrum is zero) and only the map's rows come back, which
//! saves a quarter of the row transforms.
//!
//! Each row and each column is transformed by one thread with the same
//! arithmetic whatever the thread count, so the result is the same to the
//! bit on 1 or 64 threads.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

/// Rows or columns moved per task in the transposes: 16 complex numbers
/// are 256 bytes, a few cache lines per read.
const BLOCK: usize = 16;

/// The FFT plans for one map size and one transform size.
pub struct Fft2 {
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    /// my / 2 + 1: the columns of the half-spectrum.
    hy: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

/// How a convolution uses the kernel's spectrum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factor {
    /// by the kernel: `kernel ⊛ input`
    Multiply,
    /// by its inverse (0 where the spectrum is 0): the kernel's
    /// (pseudo-)inverse applied to the input
    Divide,
}

/// Buffers one convolution needs, kept between calls.
pub struct Workspace {
    /// nx rows of hy complex numbers: the half-spectrum along y.
    rows: Vec<Complex64>,
    /// hy columns of mx complex numbers: the transposed half-spectrum.
    columns: Vec<Complex64>,
}

impl Fft2 {
    /// Plans for an `nx × ny` map on an `mx × my` transform grid
    /// (`mx ≥ nx`, `my ≥ ny`).
    pub fn new(nx: usize, ny: usize, mx: usize, my: usize) -> Self {
        assert!(nx >= 1 && ny >= 1 && mx >= nx && my >= ny);
        let mut real = RealFftPlanner::<f64>::new();
        let mut complex = FftPlanner::<f64>::new();
        Self {
            nx,
            ny,
            mx,
            my,
            hy: my / 2 + 1,
            r2c: real.plan_fft_forward(my),
            c2r: real.plan_fft_inverse(my),
            forward: complex.plan_fft_forward(mx),
            inverse: complex.plan_fft_inverse(mx),
        }
    }

    /// The transform grid, (mx, my).
    pub fn transform_size(&self) -> (usize, usize) {
        (self.mx, self.my)
    }

    /// Points of a spectrum (see [`Fft2::spectrum`]): hy · mx.
    pub fn spectrum_len(&self) -> usize {
        self.hy * self.mx
    }

    pub fn workspace(&self) -> Workspace {
        Workspace {
            rows: vec![Complex64::ZERO; self.nx * self.hy],
            columns: vec![Complex64::ZERO; self.spectrum_len()],
        }
    }

    /// The real part of the DFT of a full `mx × my` real array, divided by
    /// mx · my so that [`Fft2::convolve`] needs no further scaling; index
    /// `jy · mx + ix`. For an even kernel (k[i, j] = k[−i, −j] cyclically)
    /// the imaginary part is zero up to rounding.
    pub fn spectrum(&self, full: Vec<f64>) -> Vec<f64> {
        assert_eq!(full.len(), self.mx * self.my);
        // Each buffer is dropped as soon as it is read: at 2048² they are
        // 134 MB each, and this is the peak of the memory a solve needs.
        let mut rows = vec![Complex64::ZERO; self.mx * self.hy];
        self.rows_forward(&full, self.mx, self.my, &mut rows);
        drop(full);
        let mut columns = vec![Complex64::ZERO; self.spectrum_len()];
        transpose_in(&rows, self.mx, self.hy, self.mx, &mut columns);
        drop(rows);
        columns.par_chunks_mut(self.mx).for_each_init(
            || vec![Complex64::ZERO; self.forward.get_inplace_scratch_len()],
            |scratch, column| self.forward.process_with_scratch(column, scratch),
        );
        let scale = 1.0 / (self.mx * self.my) as f64;
        columns.iter().map(|c| c.re * scale).collect()
    }

    /// `output = (kernel ⊛ input)` (or the inverse operation, see
    /// [`Factor`]) restricted to the map, where `input` and `output` are
    /// `nx × ny` maps (zero beyond them on the transform grid) and `spectrum`
    /// comes from [`Fft2::spectrum`].
    pub fn convolve(
        &self,
        input: &[f64],
        spectrum: &[f64],
        factor: Factor,
        output: &mut [f64],
        work: &mut Workspace,
    ) {
        let (nx, ny, mx, hy) = (self.nx, self.ny, self.mx, self.hy);
        assert!(input.len() == nx * ny && output.len() == nx * ny);
        assert_eq!(spectrum.len(), self.spectrum_len());
        self.rows_forward(input, nx, ny, &mut work.rows);
        // The spectrum carries 1/(mx my) once; its inverse must too.
        let inverse_scale = ((self.mx * self.my) as f64).powi(-2);
        let scratch_len = self
            .forward
            .get_inplace_scratch_len()
            .max(self.inverse.get_inplace_scratch_len());
        // A strip of columns at a time, while it is in cache: gathered from
        // the rows, transformed along x, multiplied, transformed back.
        let rows = &work.rows;
        work.columns
            .par_chunks_mut(BLOCK * mx)
            .zip(spectrum.par_chunks(BLOCK * mx))
            .enumerate()
            .for_each_init(
                || vec![Complex64::ZERO; scratch_len],
                |scratch, (block, (strip, spectrum))| {
                    gather_columns(rows, nx, hy, mx, block * BLOCK, strip);
                    self.forward.process_with_scratch(strip, scratch);
                    match factor {
                        Factor::Multiply => {
                            for (c, &s) in strip.iter_mut().zip(spectrum) {
                                *c *= s;
                            }
                        }
                        Factor::Divide => {
                            for (c, &s) in strip.iter_mut().zip(spectrum) {
                                *c *= if s > 0.0 { inverse_scale / s } else { 0.0 };
                            }
                        }
                    }
                    self.inverse.process_with_scratch(strip, scratch);
                },
            );
        // A band of rows at a time: gathered from the columns, transformed
        // back along y, the map's part written out.
        let columns = &work.columns;
        let even = self.my.is_multiple_of(2);
        output.par_chunks_mut(BLOCK * ny).enumerate().for_each_init(
            || {
                (
                    vec![Complex64::ZERO; BLOCK * hy],
                    vec![0.0; self.my],
                    vec![Complex64::ZERO; self.c2r.get_scratch_len()],
                )
            },
            |(band, line, scratch), (block, out)| {
                let height = out.len() / ny;
                let band = &mut band[..height * hy];
                gather_rows(columns, hy, mx, block * BLOCK, band);
                for (row, out) in band.chunks_mut(hy).zip(out.chunks_mut(ny)) {
                    // The spectrum of a real row: these are real; rounding in
                    // the column passes leaves ~1e-17 there, which the
                    // inverse would refuse.
                    row[0].im = 0.0;
                    if even {
                        row[hy - 1].im = 0.0;
                    }
                    self.c2r
                        .process_with_scratch(row, line, scratch)
                        .expect("lengths come from the plan");
                    out.copy_from_slice(&line[..ny]);
                }
            },
        );
    }

    /// Real-to-complex transforms along y of the first `rows` rows of a
    /// `rows × cols` array (each zero-padded to my) into `out` (rows × hy).
    fn rows_forward(&self, input: &[f64], rows: usize, cols: usize, out: &mut [Complex64]) {
        let hy = self.hy;
        out[..rows * hy]
            .par_chunks_mut(hy)
            .zip(input.par_chunks(cols))
            .for_each_init(
                || {
                    (
                        vec![0.0; self.my],
                        vec![Complex64::ZERO; self.r2c.get_scratch_len()],
                    )
                },
                |(line, scratch), (spectrum, row)| {
                    line[..cols].copy_from_slice(row);
                    line[cols..].fill(0.0);
                    self.r2c
                        .process_with_scratch(line, spectrum, scratch)
                        .expect("lengths come from the plan");
                },
            );
    }
}

/// `columns[j · mx + i] = rows[i · hy + j]` for i < nx, zero for nx ≤ i < mx.
fn transpose_in(rows: &[Complex64], nx: usize, hy: usize, mx: usize, columns: &mut [Complex64]) {
    columns
        .par_chunks_mut(BLOCK * mx)
        .enumerate()
        .for_each(|(block, strip)| gather_columns(rows, nx, hy, mx, block * BLOCK, strip));
}

/// Columns j0.. of the `nx × hy` row-major `rows`, as contiguous columns of
/// length mx (zero below row nx), into `strip`.
fn gather_columns(
    rows: &[Complex64],
    nx: usize,
    hy: usize,
    mx: usize,
    j0: usize,
    strip: &mut [Complex64],
) {
    let width = strip.len() / mx;
    for i in 0..nx {
        let source = &rows[i * hy + j0..i * hy + j0 + width];
        for (b, &v) in source.iter().enumerate() {
            strip[b * mx + i] = v;
        }
    }
    for b in 0..width {
        strip[b * mx + nx..(b + 1) * mx].fill(Complex64::ZERO);
    }
}

/// Rows i0.. of the column-major `columns` (hy columns of length mx), as
/// contiguous rows of length hy, into `band`.
fn gather_rows(columns: &[Complex64], hy: usize, mx: usize, i0: usize, band: &mut [Complex64]) {
    let height = band.len() / hy;
    for j in 0..hy {
        let source = &columns[j * mx + i0..j * mx + i0 + height];
        for (b, &v) in source.iter().enumerate() {
            band[b * hy + j] = v;
        }
    }
}

/// The smallest n ≥ `min` of the form 2^a 3^b 5^c (the one fast size of
/// the workspace).
pub use hypercontact_core::fft::fast_size;

/// The smallest even [`fast_size`] ≥ `min` (a real FFT's half spectrum
/// wants an even length).
pub fn fast_even_size(min: usize) -> usize {
    let mut n = fast_size(min.max(2));
    while !n.is_multiple_of(2) {
        n = fast_size(n + 1);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A direct cyclic convolution on the transform grid, cut to the map.
    fn direct(
        kernel: &[f64],
        input: &[f64],
        (nx, ny): (usize, usize),
        (mx, my): (usize, usize),
    ) -> Vec<f64> {
        let mut out = vec![0.0; nx * ny];
        for i in 0..nx {
            for j in 0..ny {
                let mut s = 0.0;
                for k in 0..nx {
                    for l in 0..ny {
                        let di = (i + mx - k) % mx;
                        let dj = (j + my - l) % my;
                        s += kernel[di * my + dj] * input[k * ny + l];
                    }
                }
                out[i * ny + j] = s;
            }
        }
        out
    }

    /// An even kernel on the transform grid: a function of the wrapped
    /// distances.
    fn even_kernel(mx: usize, my: usize) -> Vec<f64> {
        let wrap = |i: usize, m: usize| {
            if i <= m / 2 {
                i as f64
            } else {
                i as f64 - m as f64
            }
        };
        (0..mx * my)
            .map(|k| {
                let (x, y) = (wrap(k / my, mx), wrap(k % my, my));
                1.0 / (1.0 + x * x + 0.5 * y * y) + 0.1 * (x * y).cos()
            })
            .collect()
    }

    #[test]
    fn convolution_matches_the_direct_sum_padded_and_periodic() {
        for (nx, ny, mx, my) in [(5, 7, 10, 14), (6, 4, 12, 10), (5, 7, 5, 7), (8, 6, 8, 6)] {
            let kernel = even_kernel(mx, my);
            let input: Vec<f64> = (0..nx * ny).map(|k| ((k * 37) % 11) as f64 - 4.0).collect();
            let fft = Fft2::new(nx, ny, mx, my);
            let spectrum = fft.spectrum(kernel.clone());
            let mut out = vec![0.0; nx * ny];
            let mut work = fft.workspace();
            fft.convolve(&input, &spectrum, Factor::Multiply, &mut out, &mut work);
            let expected = direct(&kernel, &input, (nx, ny), (mx, my));
            for (a, b) in out.iter().zip(&expected) {
                assert!(
                    (a - b).abs() < 1e-12 * 100.0,
                    "{nx}×{ny} on {mx}×{my}: {a} vs {b}"
                );
            }
            // A second call with the same workspace gives the same bits.
            let mut again = vec![0.0; nx * ny];
            fft.convolve(&input, &spectrum, Factor::Multiply, &mut again, &mut work);
            assert_eq!(out, again);
            // On a periodic grid, dividing by a positive spectrum undoes
            // multiplying by it: 2 + ½ cos qx + ½ cos qy ≥ 1.
            if mx == nx && my == ny {
                let mut positive = vec![0.0; mx * my];
                positive[0] = 2.0;
                for k in [my, (mx - 1) * my, 1, my - 1] {
                    positive[k] += 0.25;
                }
                let spectrum = fft.spectrum(positive);
                let (mut there, mut back) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
                fft.convolve(&input, &spectrum, Factor::Multiply, &mut there, &mut work);
                fft.convolve(&there, &spectrum, Factor::Divide, &mut back, &mut work);
                for (a, b) in back.iter().zip(&input) {
                    assert!((a - b).abs() < 1e-12, "{a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn fast_sizes_have_small_factors() {
        assert_eq!(fast_size(1), 1);
        assert_eq!(fast_size(7), 8);
        assert_eq!(fast_size(1025), 1080);
    }

    #[test]
    fn fast_sizes_are_even_and_smooth() {
        assert_eq!(fast_even_size(900), 900);
        assert_eq!(fast_even_size(242), 250);
        assert_eq!(fast_even_size(1), 2);
        assert_eq!(fast_even_size(4096), 4096);
    }
}
