//! The 2-D DFT of real arrays by the row-column method: a real-to-complex
//! transform along each row (`realfft`), then complex transforms down the
//! columns of the half spectrum (`rustfft`).
//!
//! For real x the spectrum is Hermitian, X[k, l] = conj X[−k, −l] (indices
//! cyclic), so the columns l = 0 … cols/2 hold all of it: the layout of
//! FFTW's real-data transforms ("Multi-Dimensional DFTs of Real Data" in its
//! manual), here kept column-major, `spectrum[l · rows + k]`, so that the
//! transforms down the columns run over contiguous memory.
//!
//! A map smaller than the transform grid is zero-extended (Hockney's padding
//! for an aperiodic convolution, or a fast size for speed): the zero rows
//! are never transformed along their length (their transform is zero), and
//! the inverse returns the map's part only.
//!
//! Every row and every column is transformed by one thread with the same
//! arithmetic whatever the number of threads, and nothing is summed across
//! them, so the result is the same to the bit on 1 or 64 threads.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::{ComplexToReal, RealToComplex};
use rustfft::Fft;
use rustfft::num_complex::Complex64;

use super::plans::{self, Direction};
use super::transpose::{BLOCK, gather_columns, gather_rows};
use crate::NumericError;

mod filter;

/// The plans of a real 2-D transform on one `rows × cols` grid (each row
/// contiguous, the real transform along it).
pub struct RealFft2 {
    rows: usize,
    cols: usize,
    /// cols / 2 + 1: the columns of the half spectrum
    half: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

/// Buffers kept between calls; sized on first use.
#[derive(Default)]
pub struct RealWorkspace {
    /// the row transforms of a map: its rows × half, row-major
    rows: Vec<Complex64>,
    /// a half spectrum, column-major (for [`RealFft2::convolve`])
    columns: Vec<Complex64>,
}

impl RealFft2 {
    /// Plans for a `rows × cols` transform grid.
    pub fn new(rows: usize, cols: usize) -> Result<Self, NumericError> {
        if rows == 0 || cols == 0 {
            return Err(NumericError::EmptyGrid {
                what: "real 2-D FFT",
                rows,
                cols,
            });
        }
        let (r2c, c2r) = plans::real(cols);
        Ok(Self {
            rows,
            cols,
            half: cols / 2 + 1,
            r2c,
            c2r,
            forward: plans::complex(rows, Direction::Forward),
            inverse: plans::complex(rows, Direction::Inverse),
        })
    }

    /// The transform grid, (rows, cols).
    pub fn grid(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// Columns of the half spectrum: cols / 2 + 1.
    pub fn half_cols(&self) -> usize {
        self.half
    }

    /// Points of a half spectrum: (cols / 2 + 1) · rows, index `l · rows + k`.
    pub fn spectrum_len(&self) -> usize {
        self.half * self.rows
    }

    pub fn workspace(&self) -> RealWorkspace {
        RealWorkspace::default()
    }

    /// The half spectrum of a `map_rows × map_cols` row-major map,
    /// zero-extended to the grid, into `spectrum` ([`Self::spectrum_len`]
    /// points, column-major); unnormalised.
    pub fn forward(
        &self,
        map: &[f64],
        map_size: (usize, usize),
        spectrum: &mut [Complex64],
        work: &mut RealWorkspace,
    ) -> Result<(), NumericError> {
        self.check_map("forward transform's map", map_size, map.len())?;
        self.check_spectrum(spectrum.len())?;
        work.rows.resize(map_size.0 * self.half, Complex64::ZERO);
        self.rows_forward(map, map_size.1, &mut work.rows);
        self.columns_forward(Some(&work.rows), spectrum, |_, _, _| {});
        Ok(())
    }

    /// The inverse transform of a half spectrum (which it overwrites), its
    /// first `map_rows × map_cols` values times `scale` into `output`. A
    /// scale of 1/(rows · cols) makes it the inverse of [`Self::forward`].
    pub fn inverse(
        &self,
        spectrum: &mut [Complex64],
        map_size: (usize, usize),
        output: &mut [f64],
        scale: f64,
    ) -> Result<(), NumericError> {
        self.check_map("inverse transform's output", map_size, output.len())?;
        self.check_spectrum(spectrum.len())?;
        spectrum.par_chunks_mut(BLOCK * self.rows).for_each_init(
            || vec![Complex64::ZERO; self.inverse.get_inplace_scratch_len()],
            |scratch, strip| self.inverse.process_with_scratch(strip, scratch),
        );
        self.rows_back(spectrum, map_size, output, scale);
        Ok(())
    }

    /// Forward transform of `input`, `apply(offset, strip)` on the spectrum
    /// a strip of columns at a time (the strip is `spectrum[offset..]` of
    /// the layout of [`Self::forward`]), inverse transform times `scale`
    /// into `output`; `input` and `output` are `map_size` maps. The same
    /// bits as the three steps apart, without holding a whole spectrum
    /// between them: each strip is filtered while it is in cache.
    pub fn convolve(
        &self,
        input: &[f64],
        map_size: (usize, usize),
        output: &mut [f64],
        scale: f64,
        work: &mut RealWorkspace,
        apply: impl Fn(usize, &mut [Complex64]) + Sync,
    ) -> Result<(), NumericError> {
        self.check_map("convolution's input", map_size, input.len())?;
        self.check_map("convolution's output", map_size, output.len())?;
        work.rows.resize(map_size.0 * self.half, Complex64::ZERO);
        work.columns.resize(self.spectrum_len(), Complex64::ZERO);
        self.rows_forward(input, map_size.1, &mut work.rows);
        self.columns_forward(
            Some(&work.rows),
            &mut work.columns,
            |offset, strip, scratch| {
                apply(offset, strip);
                self.inverse.process_with_scratch(strip, scratch);
            },
        );
        self.rows_back(&work.columns, map_size, output, scale);
        Ok(())
    }

    fn check_map(
        &self,
        what: &'static str,
        (map_rows, map_cols): (usize, usize),
        len: usize,
    ) -> Result<(), NumericError> {
        if map_rows == 0 || map_cols == 0 {
            return Err(NumericError::EmptyGrid {
                what,
                rows: map_rows,
                cols: map_cols,
            });
        }
        if map_rows > self.rows || map_cols > self.cols {
            return Err(NumericError::MapTooLarge {
                what,
                map_rows,
                map_cols,
                grid_rows: self.rows,
                grid_cols: self.cols,
            });
        }
        if len != map_rows * map_cols {
            return Err(NumericError::Length {
                what,
                expected: map_rows * map_cols,
                got: len,
            });
        }
        Ok(())
    }

    fn check_spectrum(&self, len: usize) -> Result<(), NumericError> {
        if len != self.spectrum_len() {
            return Err(NumericError::Length {
                what: "half spectrum",
                expected: self.spectrum_len(),
                got: len,
            });
        }
        Ok(())
    }

    /// Real-to-complex transforms of the rows of `map` (each `map_cols`
    /// long, zero-extended to the grid) into `out`, `half` per row.
    fn rows_forward(&self, map: &[f64], map_cols: usize, out: &mut [Complex64]) {
        out.par_chunks_mut(self.half)
            .zip(map.par_chunks(map_cols))
            .for_each_init(
                || (vec![0.0; self.cols], self.r2c.make_scratch_vec()),
                |(line, scratch), (spectrum, row)| {
                    // The transform uses its input as scratch: refill it.
                    line[..map_cols].copy_from_slice(row);
                    line[map_cols..].fill(0.0);
                    self.r2c
                        .process_with_scratch(line, spectrum, scratch)
                        .expect("buffer lengths come from the plan");
                },
            );
    }

    /// Gathers the columns of the row transforms `rows` into `columns`
    /// (zero below the map's rows; `None`: `columns` holds them already),
    /// transforms them, and hands each strip to `then` with its offset and
    /// a scratch fit for either direction.
    fn columns_forward(
        &self,
        rows: Option<&[Complex64]>,
        columns: &mut [Complex64],
        then: impl Fn(usize, &mut [Complex64], &mut [Complex64]) + Sync,
    ) {
        let scratch_len = self
            .forward
            .get_inplace_scratch_len()
            .max(self.inverse.get_inplace_scratch_len());
        columns
            .par_chunks_mut(BLOCK * self.rows)
            .enumerate()
            .for_each_init(
                || vec![Complex64::ZERO; scratch_len],
                |scratch, (block, strip)| {
                    if let Some(rows) = rows {
                        gather_columns(rows, self.half, block * BLOCK, self.rows, strip);
                    }
                    self.forward.process_with_scratch(strip, scratch);
                    then(block * BLOCK * self.rows, strip, scratch);
                },
            );
    }

    /// Complex-to-real transforms of the first `map_rows` rows of the
    /// column-major `columns`, their first `map_cols` values times `scale`
    /// into `output`. The columns are `columns.len() / half` long: the
    /// grid's, or only their first rows when no more are returned.
    fn rows_back(
        &self,
        columns: &[Complex64],
        (_, map_cols): (usize, usize),
        output: &mut [f64],
        scale: f64,
    ) {
        let (half, even) = (self.half, self.cols.is_multiple_of(2));
        let column_len = columns.len() / half;
        output
            .par_chunks_mut(BLOCK * map_cols)
            .enumerate()
            .for_each_init(
                || {
                    (
                        vec![Complex64::ZERO; BLOCK * half],
                        vec![0.0; self.cols],
                        self.c2r.make_scratch_vec(),
                    )
                },
                |(band, line, scratch), (block, out)| {
                    let band = &mut band[..out.len() / map_cols * half];
                    gather_rows(columns, column_len, block * BLOCK, half, band);
                    for (row, out) in band.chunks_mut(half).zip(out.chunks_mut(map_cols)) {
                        // The DC and Nyquist terms of a real row's spectrum
                        // are real; the column transforms leave ~1e-17 in
                        // their imaginary parts, which realfft refuses.
                        row[0].im = 0.0;
                        if even {
                            row[half - 1].im = 0.0;
                        }
                        self.c2r
                            .process_with_scratch(row, line, scratch)
                            .expect("buffer lengths come from the plan");
                        for (o, v) in out.iter_mut().zip(&line[..map_cols]) {
                            *o = v * scale;
                        }
                    }
                },
            );
    }
}

#[cfg(test)]
mod tests {
    use hypercontact_fuzz::on_threads;
    use proptest::prelude::*;

    use super::*;
    use crate::fft2::direct::{dft2, embed, max_difference};

    /// A map with values of either sign and several magnitudes.
    pub(super) fn map(rows: usize, cols: usize, seed: u64) -> Vec<f64> {
        (0..rows * cols)
            .map(|k| {
                let x = (k as u64 + 1).wrapping_mul(seed.wrapping_mul(2) + 0x9E37_79B9);
                ((x % 2003) as f64 - 1001.0) / 97.0
            })
            .collect()
    }

    /// The half spectrum of the direct DFT of the zero-extended map, in
    /// [`RealFft2`]'s column-major layout.
    fn direct_half_spectrum(
        values: &[f64],
        map_size: (usize, usize),
        (rows, cols): (usize, usize),
    ) -> Vec<Complex64> {
        let full = dft2(
            &embed(values, map_size, rows, cols),
            rows,
            cols,
            Direction::Forward,
        );
        let half = cols / 2 + 1;
        let mut out = vec![Complex64::ZERO; half * rows];
        for l in 0..half {
            for k in 0..rows {
                out[l * rows + k] = full[k * cols + l];
            }
        }
        out
    }

    /// A direct cyclic convolution of a grid-sized kernel with a map on the
    /// transform grid, cut to the map.
    fn direct_convolution(
        kernel: &[f64],
        values: &[f64],
        (map_rows, map_cols): (usize, usize),
        (rows, cols): (usize, usize),
    ) -> Vec<f64> {
        let mut out = vec![0.0; map_rows * map_cols];
        for i in 0..map_rows {
            for j in 0..map_cols {
                let mut sum = 0.0;
                for k in 0..map_rows {
                    for l in 0..map_cols {
                        let (di, dj) = ((i + rows - k) % rows, (j + cols - l) % cols);
                        sum += kernel[di * cols + dj] * values[k * map_cols + l];
                    }
                }
                out[i * map_cols + j] = sum;
            }
        }
        out
    }

    fn transform(fft: &RealFft2, values: &[f64], map_size: (usize, usize)) -> Vec<Complex64> {
        let mut spectrum = vec![Complex64::ZERO; fft.spectrum_len()];
        fft.forward(values, map_size, &mut spectrum, &mut fft.workspace())
            .unwrap();
        spectrum
    }

    #[test]
    fn sizes_that_do_not_fit_are_refused() {
        assert!(matches!(
            RealFft2::new(0, 4),
            Err(NumericError::EmptyGrid { .. })
        ));
        let fft = RealFft2::new(4, 6).unwrap();
        let mut spectrum = vec![Complex64::ZERO; fft.spectrum_len()];
        let mut work = fft.workspace();
        assert!(matches!(
            fft.forward(&[0.0; 35], (5, 7), &mut spectrum, &mut work),
            Err(NumericError::MapTooLarge { .. })
        ));
        assert!(matches!(
            fft.forward(&[0.0; 5], (2, 3), &mut spectrum, &mut work),
            Err(NumericError::Length { got: 5, .. })
        ));
        assert!(matches!(
            fft.forward(&[], (0, 3), &mut spectrum, &mut work),
            Err(NumericError::EmptyGrid { .. })
        ));
        assert!(matches!(
            fft.inverse(&mut spectrum[1..], (2, 2), &mut [0.0; 4], 1.0),
            Err(NumericError::Length { .. })
        ));
    }

    #[test]
    fn the_inverse_with_its_scale_undoes_the_forward_transform() {
        for (rows, cols, map_size) in [(8, 6, (8, 6)), (9, 7, (5, 4)), (1, 1, (1, 1))] {
            let fft = RealFft2::new(rows, cols).unwrap();
            let values = map(map_size.0, map_size.1, 3);
            let mut spectrum = transform(&fft, &values, map_size);
            let mut back = vec![0.0; values.len()];
            let scale = 1.0 / (rows * cols) as f64;
            fft.inverse(&mut spectrum, map_size, &mut back, scale)
                .unwrap();
            for (a, b) in back.iter().zip(&values) {
                assert!((a - b).abs() < 1e-12, "{rows}×{cols}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn convolution_equals_its_three_steps_to_the_bit() {
        let (rows, cols, map_size) = (40, 36, (23, 18));
        let fft = RealFft2::new(rows, cols).unwrap();
        let kernel = transform(&fft, &map(rows, cols, 5), (rows, cols));
        let values = map(map_size.0, map_size.1, 6);
        let mut spectrum = transform(&fft, &values, map_size);
        for (s, k) in spectrum.iter_mut().zip(&kernel) {
            *s *= k;
        }
        let mut apart = vec![0.0; values.len()];
        fft.inverse(&mut spectrum, map_size, &mut apart, 0.25)
            .unwrap();
        let mut fused = vec![0.0; values.len()];
        let mut work = fft.workspace();
        for _ in 0..2 {
            fft.convolve(
                &values,
                map_size,
                &mut fused,
                0.25,
                &mut work,
                |o, strip| {
                    for (s, k) in strip.iter_mut().zip(&kernel[o..]) {
                        *s *= k;
                    }
                },
            )
            .unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fused), bits(&apart));
        }
    }

    #[test]
    fn one_and_two_threads_give_the_same_bits() {
        // Strips and bands of several blocks, odd sizes, a padded map.
        let (rows, cols, map_size) = (75, 98, (61, 53));
        let kernel = map(rows, cols, 8);
        let values = map(map_size.0, map_size.1, 9);
        let run = || {
            let fft = RealFft2::new(rows, cols).unwrap();
            let spectrum = transform(&fft, &kernel, (rows, cols));
            let mut out = vec![0.0; values.len()];
            fft.convolve(
                &values,
                map_size,
                &mut out,
                1.0,
                &mut fft.workspace(),
                |o, strip| {
                    for (s, k) in strip.iter_mut().zip(&spectrum[o..]) {
                        *s *= k.conj();
                    }
                },
            )
            .unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let spectrum_bits: Vec<u64> = spectrum
                .iter()
                .flat_map(|c| [c.re.to_bits(), c.im.to_bits()])
                .collect();
            (spectrum_bits, bits(&out))
        };
        assert_eq!(on_threads(1, run), on_threads(2, run));
    }

    /// A grid of 1 to `end` − 1 cells per side, a map that fits in it (as
    /// small as one cell) and a seed for the map's values.
    fn grid_and_map(end: usize) -> impl Strategy<Value = ((usize, usize), (usize, usize), u64)> {
        (1..end, 1..end, 0usize..6, 0usize..6, 0u64..1000).prop_map(
            |(rows, cols, cut_rows, cut_cols, seed)| {
                let map_size = (
                    rows.saturating_sub(cut_rows).max(1),
                    cols.saturating_sub(cut_cols).max(1),
                );
                ((rows, cols), map_size, seed)
            },
        )
    }

    proptest! {
        #![proptest_config(hypercontact_fuzz::config(48))]

        /// Odd, prime and even grids, maps smaller than the grid: the
        /// half spectrum is the direct DFT's.
        #[test]
        fn forward_is_the_direct_dft(((rows, cols), map_size, seed) in grid_and_map(14)) {
            let values = map(map_size.0, map_size.1, seed);
            let fft = RealFft2::new(rows, cols).unwrap();
            let fast = transform(&fft, &values, map_size);
            let slow = direct_half_spectrum(&values, map_size, (rows, cols));
            let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let tolerance = 1e-13 * largest * (rows * cols) as f64;
            prop_assert!(max_difference(&fast, &slow) <= tolerance);
        }

        /// The fused convolution is the direct cyclic sum on the grid, and
        /// the inverse returns the map's part only.
        #[test]
        fn convolution_is_the_direct_cyclic_sum(((rows, cols), map_size, seed) in grid_and_map(12)) {
            let kernel = map(rows, cols, seed + 1);
            let values = map(map_size.0, map_size.1, seed);
            let fft = RealFft2::new(rows, cols).unwrap();
            // Any kernel, not only an even one: its full complex spectrum.
            let spectrum = transform(&fft, &kernel, (rows, cols));
            let mut out = vec![0.0; values.len()];
            let scale = 1.0 / (rows * cols) as f64;
            fft.convolve(&values, map_size, &mut out, scale, &mut fft.workspace(), |o, strip| {
                for (s, k) in strip.iter_mut().zip(&spectrum[o..]) {
                    *s *= k;
                }
            }).unwrap();
            let slow = direct_convolution(&kernel, &values, map_size, (rows, cols));
            for (a, b) in out.iter().zip(&slow) {
                prop_assert!((a - b).abs() < 1e-10 * (1.0 + b.abs()), "{} vs {}", a, b);
            }
        }
    }
}
