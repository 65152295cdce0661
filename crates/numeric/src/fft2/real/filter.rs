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
//! so the grid itself never exists: before the rows go back, each column
//! of the spectrum is cut to the rows returned and the rest is given back.
//! Both give the bits of [`RealFft2::convolve`] with that gain, since every
//! row and column meets the same transforms in the same order.

use rustfft::num_complex::Complex64;

use super::RealFft2;
use crate::NumericError;

/// Rows transformed per band: enough for every thread, a small buffer
/// beside the spectrum.
const BAND: usize = 64;

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
            self.band_into_columns(b * BAND, block, &mut band, &mut columns);
        }
        self.filter_columns(&mut columns, gain);
        self.rows_back(&columns, size, map, 1.0);
        Ok(())
    }

    /// The first `crop.0` rows and `crop.1` columns (row-major) of what
    /// [`Self::filter_in_place`] makes of the grid whose rows
    /// `fill_rows(first, rows)` writes: it is called once per band of
    /// whole rows, in row order from row 0, and must overwrite all of
    /// `rows` (`rows.len() / cols` rows from row `first`). The same bits as
    /// filtering the whole grid and cutting out the corner, holding one
    /// half spectrum (then its first `crop.0` rows beside the crop) instead
    /// of the grid and a half spectrum.
    pub fn filtered_crop(
        &self,
        mut fill_rows: impl FnMut(usize, &mut [f64]),
        gain: impl Fn(usize, usize) -> f64 + Sync,
        crop: (usize, usize),
    ) -> Result<Vec<f64>, NumericError> {
        self.check_map("filtered crop", crop, crop.0 * crop.1)?;
        let mut columns = vec![Complex64::ZERO; self.spectrum_len()];
        let mut band = vec![Complex64::ZERO; BAND * self.half];
        let mut lines = vec![0.0; BAND * self.cols];
        for first in (0..self.rows).step_by(BAND) {
            let lines = &mut lines[..(self.rows - first).min(BAND) * self.cols];
            fill_rows(first, lines);
            self.band_into_columns(first, lines, &mut band, &mut columns);
        }
        self.filter_columns(&mut columns, gain);
        // Each column keeps its first crop.0 points, moved down to close
        // the gaps: destinations lie below their sources, so column order
        // never overwrites a point still to be moved. Shrinking returns the
        // rest of the spectrum before the crop is allocated.
        for l in 1..self.half {
            let start = l * self.rows;
            columns.copy_within(start..start + crop.0, l * crop.0);
        }
        columns.truncate(self.half * crop.0);
        columns.shrink_to_fit();
        let mut corner = vec![0.0; crop.0 * crop.1];
        self.rows_back(&columns, crop, &mut corner, 1.0);
        Ok(corner)
    }

    /// Transforms the whole rows `lines` of the grid, from row `first`, and
    /// writes them into the column-major `columns`; `band` is room for
    /// [`BAND`] row transforms.
    fn band_into_columns(
        &self,
        first: usize,
        lines: &[f64],
        band: &mut [Complex64],
        columns: &mut [Complex64],
    ) {
        let band = &mut band[..lines.len() / self.cols * self.half];
        self.rows_forward(lines, self.cols, band);
        for (i, row) in band.chunks_exact(self.half).enumerate() {
            for (l, &v) in row.iter().enumerate() {
                columns[l * self.rows + first + i] = v;
            }
        }
    }

    /// Transforms the columns of a half spectrum holding the row
    /// transforms, multiplies each by its gain and transforms it back, a
    /// strip at a time while it is in cache.
    fn filter_columns(&self, columns: &mut [Complex64], gain: impl Fn(usize, usize) -> f64 + Sync) {
        self.columns_forward(None, columns, |offset, strip, scratch| {
            for (c, column) in strip.chunks_exact_mut(self.rows).enumerate() {
                let l = offset / self.rows + c;
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
    fn a_filtered_crop_asks_for_each_row_once_in_order() {
        // 150 rows: two whole bands and a short one.
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
        assert_eq!(asked, [(0, 64), (64, 64), (128, 22)]);
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
