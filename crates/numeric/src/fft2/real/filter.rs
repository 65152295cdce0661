//! Filtering a real grid by a real gain in Fourier space,
//! x ← DFT⁻¹(g · DFT x) unnormalised, for grids whose half spectrum is as
//! large as the memory allows (a paper-scale synthetic truth grid is
//! ~14 000² points, its half spectrum 1.4 GiB; issue #35).
//!
//! The rows go through their transforms a band at a time, straight into
//! the column-major half spectrum, which is then the one large array alive
//! while the columns are filtered. [`RealFft2::filter_in_place`] reads the
//! grid from a map and returns all of it there; [`RealFft2::filtered_crop`]
//! asks a callback for the rows, band by band, and returns a corner only,
//! so neither the grid nor its whole half spectrum ever exists: two passes
//! over the rows each filter part of the columns and keep only the rows
//! returned, which go back in place (#48).
//! Both give the bits of [`RealFft2::convolve`] with that gain, since every
//! row and column meets the same transforms in the same order.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use super::RealFft2;
use crate::NumericError;

/// Rows transformed per band: enough for every thread, a small buffer
/// beside the spectrum.
const BAND: usize = 64;

/// Columns moved from a pass's spectrum to the kept rows before the
/// spectrum is shrunk: a row's 256 bytes written at a time.
const TRANSFER: usize = 16;

impl RealFft2 {
    /// Multiplies the spectrum of `map`, a whole `rows × cols` grid, by a
    /// real `gain(k, l)` (row k, half-spectrum column l) and transforms back
    /// into `map`, unnormalised (a factor rows · cols). The same bits as
    /// [`Self::convolve`] with that gain, holding one half spectrum beside
    /// the map instead of two.
    pub fn filter_in_place(
        &self,
        map: &mut [f64],
        gain: impl Fn(usize, usize) -> f64 + Sync,
    ) -> Result<(), NumericError> {
        let size = (self.rows, self.cols);
        self.check_map("filtered map", size, map.len())?;
        let mut columns = vec![Complex64::ZERO; self.spectrum_len()];
        let mut band = vec![Complex64::ZERO; BAND * self.half];
        for (b, block) in map.chunks(BAND * self.cols).enumerate() {
            self.band_into_columns(b * BAND, block, &mut band, 0..self.half, &mut columns);
        }
        self.filter_columns(&mut columns, 0, gain);
        self.rows_back(&columns, size, map, 1.0);
        Ok(())
    }

    /// The first `crop.0` rows and `crop.1` columns (row-major) of what
    /// [`Self::filter_in_place`] makes of the grid whose rows
    /// `fill_rows(first, rows)` writes: it is called once per band of
    /// whole rows, in row order from row 0, and must overwrite all of
    /// `rows` (`rows.len() / cols` rows from row `first`). When the crop
    /// has fewer rows than the grid the rows are asked for twice, each time
    /// from row 0, and must be the same both times (a seeded generator
    /// starts again at `first == 0`). The same bits as filtering the whole
    /// grid and cutting out the corner.
    ///
    /// Memory (#48): the half spectrum is never whole. The first pass
    /// transforms and filters the columns `0..split`, the second the rest,
    /// each keeping only its columns' first `crop.0` rows, row-major, in
    /// one buffer that the rows are then transformed back in, in place.
    /// With S the half spectrum's bytes and C its cropped rows', the split
    /// at `S / (2S − C)` of the columns makes both passes peak at the same
    /// ~S² / (2S − C): 1.13 GB instead of the 1.62 GB of one whole
    /// spectrum and a separate crop on a paper-scale truth grid (13 824²,
    /// crop 8 900²), for a second draw and row transform of the grid.
    pub fn filtered_crop(
        &self,
        mut fill_rows: impl FnMut(usize, &mut [f64]),
        gain: impl Fn(usize, usize) -> f64 + Sync,
        crop: (usize, usize),
    ) -> Result<Vec<f64>, NumericError> {
        self.check_map("filtered crop", crop, crop.0 * crop.1)?;
        // Re and im of the kept spectrum, row k of the crop at 2·k·half;
        // zeroed pages are only touched as a pass writes them.
        let mut kept = vec![0.0; crop.0 * 2 * self.half];
        let split = (self.half * self.rows)
            .div_ceil(2 * self.rows - crop.0)
            .clamp(1, self.half);
        for columns in [0..split, split..self.half] {
            if !columns.is_empty() {
                self.filter_pass(&mut fill_rows, &gain, columns, crop.0, &mut kept);
            }
        }
        self.rows_back_in_place(&mut kept, crop);
        Ok(kept)
    }

    /// One pass of [`Self::filtered_crop`]: the half-spectrum columns
    /// `range` of the whole grid's rows, filtered, their first `crop_rows`
    /// points written into `kept` (row-major re, im).
    fn filter_pass(
        &self,
        fill_rows: &mut impl FnMut(usize, &mut [f64]),
        gain: &(impl Fn(usize, usize) -> f64 + Sync),
        range: std::ops::Range<usize>,
        crop_rows: usize,
        kept: &mut [f64],
    ) {
        let mut columns = vec![Complex64::ZERO; range.len() * self.rows];
        let mut band = vec![Complex64::ZERO; BAND * self.half];
        let mut lines = vec![0.0; BAND * self.cols];
        for first in (0..self.rows).step_by(BAND) {
            let lines = &mut lines[..(self.rows - first).min(BAND) * self.cols];
            fill_rows(first, lines);
            self.band_into_columns(first, lines, &mut band, range.clone(), &mut columns);
        }
        drop((band, lines));
        self.filter_columns(&mut columns, range.start, gain);
        // From the last column back, a block at a time, each block's first
        // rows go to `kept` and the block is given back: the spectrum
        // shrinks as the kept rows grow.
        let mut end = range.len();
        while end > 0 {
            let start = end.saturating_sub(TRANSFER);
            for k in 0..crop_rows {
                let row = &mut kept[2 * (k * self.half + range.start)..];
                for l in start..end {
                    let v = columns[l * self.rows + k];
                    row[2 * l] = v.re;
                    row[2 * l + 1] = v.im;
                }
            }
            columns.truncate(start * self.rows);
            columns.shrink_to_fit();
            end = start;
        }
    }

    /// The complex-to-real transforms of the first `crop.0` rows of the
    /// spectrum held row-major in `kept` (re, im), their first `crop.1`
    /// values left in `kept`, which is cut to them. Done in place: a group
    /// of rows is copied out before its values are written back, and a
    /// row's values (at most `cols` ≤ 2·half) land below the rows still to
    /// be read.
    fn rows_back_in_place(&self, kept: &mut Vec<f64>, crop: (usize, usize)) {
        let (half, even) = (self.half, self.cols.is_multiple_of(2));
        let group = BAND * rayon::current_num_threads().max(1);
        let mut spectra = vec![Complex64::ZERO; group * half];
        let mut values = vec![0.0; group * crop.1];
        for first in (0..crop.0).step_by(group) {
            let n = (crop.0 - first).min(group);
            let source = &kept[2 * first * half..2 * (first + n) * half];
            for (c, re_im) in spectra.iter_mut().zip(source.chunks_exact(2)) {
                *c = Complex64::new(re_im[0], re_im[1]);
            }
            spectra[..n * half]
                .par_chunks_mut(half)
                .zip(values[..n * crop.1].par_chunks_mut(crop.1))
                .for_each_init(
                    || (vec![0.0; self.cols], self.c2r.make_scratch_vec()),
                    |(line, scratch), (row, out)| {
                        // As in rows_back: the DC and Nyquist terms of a
                        // real row's spectrum are real.
                        row[0].im = 0.0;
                        if even {
                            row[half - 1].im = 0.0;
                        }
                        self.c2r
                            .process_with_scratch(row, line, scratch)
                            .expect("buffer lengths come from the plan");
                        out.copy_from_slice(&line[..crop.1]);
                    },
                );
            kept[first * crop.1..(first + n) * crop.1].copy_from_slice(&values[..n * crop.1]);
        }
        kept.truncate(crop.0 * crop.1);
        kept.shrink_to_fit();
    }

    /// Transforms the whole rows `lines` of the grid, from row `first`, and
    /// writes the half-spectrum columns `range` of them into the
    /// column-major `columns`; `band` is room for [`BAND`] row transforms.
    fn band_into_columns(
        &self,
        first: usize,
        lines: &[f64],
        band: &mut [Complex64],
        range: std::ops::Range<usize>,
        columns: &mut [Complex64],
    ) {
        let band = &mut band[..lines.len() / self.cols * self.half];
        self.rows_forward(lines, self.cols, band);
        for (i, row) in band.chunks_exact(self.half).enumerate() {
            for (l, &v) in row[range.clone()].iter().enumerate() {
                columns[l * self.rows + first + i] = v;
            }
        }
    }

    /// Transforms the columns of a half spectrum holding the row
    /// transforms, multiplies each by its gain and transforms it back, a
    /// strip at a time while it is in cache; `columns` starts at half-spectrum
    /// column `first_column`.
    fn filter_columns(
        &self,
        columns: &mut [Complex64],
        first_column: usize,
        gain: impl Fn(usize, usize) -> f64 + Sync,
    ) {
        self.columns_forward(None, columns, |offset, strip, scratch| {
            for (c, column) in strip.chunks_exact_mut(self.rows).enumerate() {
                let l = first_column + offset / self.rows + c;
                for (k, v) in column.iter_mut().enumerate() {
                    *v *= gain(k, l);
                }
            }
            self.inverse.process_with_scratch(strip, scratch);
        });
    }
}

#[cfg(test)]
mod tests {
    use hypercontact_fuzz::on_threads;

    use super::super::tests::map;
    use super::*;

    fn bits(values: &[f64]) -> Vec<u64> {
        values.iter().map(|x| x.to_bits()).collect()
    }

    /// A gain that is not symmetric in k, so the clean-up of DC and
    /// Nyquist is exercised.
    fn gain(k: usize, l: usize) -> f64 {
        1.0 / (1.0 + (k * 3 + l) as f64)
    }

    /// The filtered crop of `values` (a whole grid), the rows handed over
    /// from it.
    fn crop_of(fft: &RealFft2, values: &[f64], crop: (usize, usize)) -> Vec<f64> {
        let cols = fft.grid().1;
        fft.filtered_crop(
            |first, lines| lines.copy_from_slice(&values[first * cols..][..lines.len()]),
            gain,
            crop,
        )
        .unwrap()
    }

    #[test]
    fn filtering_in_place_is_the_convolution_with_that_gain_to_the_bit() {
        // More rows than one band, odd and even row lengths; a gain that is
        // not symmetric in k, so the clean-up of DC and Nyquist is exercised.
        for (rows, cols) in [(150, 37), (70, 64), (1, 5)] {
            let fft = RealFft2::new(rows, cols).unwrap();
            let gain = |k: usize, l: usize| 1.0 / (1.0 + (k * 3 + l) as f64);
            let values = map(rows, cols, 11);
            let mut fused = vec![0.0; values.len()];
            fft.convolve(
                &values,
                (rows, cols),
                &mut fused,
                1.0,
                &mut fft.workspace(),
                |o, strip| {
                    for (i, s) in strip.iter_mut().enumerate() {
                        let (l, k) = ((o + i) / rows, (o + i) % rows);
                        *s *= gain(k, l);
                    }
                },
            )
            .unwrap();
            let mut in_place = values.clone();
            fft.filter_in_place(&mut in_place, gain).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&in_place), bits(&fused), "{rows}×{cols}");
        }
    }

    #[test]
    fn filtering_with_unit_gain_scales_the_map_by_its_size() {
        let (rows, cols) = (90, 33);
        let fft = RealFft2::new(rows, cols).unwrap();
        let values = map(rows, cols, 12);
        let mut out = values.clone();
        fft.filter_in_place(&mut out, |_, _| 1.0).unwrap();
        let n = (rows * cols) as f64;
        for (a, b) in out.iter().zip(&values) {
            assert!((a / n - b).abs() < 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
        }
        let e = fft.filter_in_place(&mut out[1..], |_, _| 1.0).unwrap_err();
        assert!(e.to_string().contains("filtered map"), "{e}");
    }

    #[test]
    fn a_filtered_crop_is_the_filtered_grid_cut_to_its_corner_to_the_bit() {
        // Several bands and strips, odd and even rows and columns; crops of
        // the whole grid, a corner, one row, one column and one point.
        for (rows, cols) in [(150, 37), (131, 90), (70, 64), (1, 5)] {
            let fft = RealFft2::new(rows, cols).unwrap();
            let values = map(rows, cols, 13);
            let mut whole = values.clone();
            fft.filter_in_place(&mut whole, gain).unwrap();
            let crops = [
                (rows, cols),
                (rows / 2 + 1, cols / 3 + 1),
                (1, cols),
                (rows, 1),
                (1, 1),
            ];
            for crop in crops {
                let expected: Vec<f64> = (0..crop.0)
                    .flat_map(|i| whole[i * cols..][..crop.1].to_vec())
                    .collect();
                for threads in [1, 2, 3] {
                    let corner = on_threads(threads, || crop_of(&fft, &values, crop));
                    assert!(
                        bits(&corner) == bits(&expected),
                        "{rows}×{cols} cut to {crop:?} on {threads} threads"
                    );
                }
            }
        }
    }

    #[test]
    fn a_filtered_crop_asks_for_the_rows_in_order_once_per_pass() {
        // 150 rows: two whole bands and a short one, asked for by each of
        // the two passes; a crop of every row needs one pass.
        let (rows, cols) = (150, 21);
        let fft = RealFft2::new(rows, cols).unwrap();
        let mut asked = Vec::new();
        let values = map(rows, cols, 14);
        let corner = fft
            .filtered_crop(
                |first, lines| {
                    asked.push((first, lines.len() / cols));
                    lines.copy_from_slice(&values[first * cols..][..lines.len()]);
                },
                |_, _| 1.0,
                (40, 20),
            )
            .unwrap();
        let bands = [(0, 64), (64, 64), (128, 22)];
        assert_eq!(asked, [bands, bands].concat());
        let mut once = 0;
        fft.filtered_crop(
            |_, lines| {
                once += 1;
                lines.fill(1.0)
            },
            |_, _| 1.0,
            (rows, 3),
        )
        .unwrap();
        assert_eq!(once, bands.len());
        // With unit gain the filter multiplies by the grid's size.
        let n = (rows * cols) as f64;
        for i in 0..40 {
            for j in 0..20 {
                let (a, b) = (corner[i * 20 + j], values[i * cols + j]);
                assert!((a / n - b).abs() < 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
            }
        }
    }

    #[test]
    fn a_crop_outside_the_grid_is_refused_before_any_row_is_asked_for() {
        let fft = RealFft2::new(8, 6).unwrap();
        for crop in [(9, 6), (8, 7), (0, 3), (2, 0)] {
            let e = fft
                .filtered_crop(|_, _| panic!("no row is needed"), gain, crop)
                .unwrap_err();
            assert!(
                matches!(
                    e,
                    NumericError::MapTooLarge { .. } | NumericError::EmptyGrid { .. }
                ) && e.to_string().contains("filtered crop"),
                "{crop:?}: {e}"
            );
        }
    }
}
