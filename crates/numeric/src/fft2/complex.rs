//! The 2-D DFT of complex arrays in place, by the row-column method: the
//! transforms along every (contiguous) row first, then down every column,
//! X[k, l] = Σ_m Σ_n x[m, n] e^{∓2πi (km/rows + ln/cols)}, unnormalised
//! both ways (the inverse of the forward transform is the inverse divided
//! by rows · cols).
//!
//! The columns are transposed into a contiguous buffer a strip at a time,
//! transformed and transposed back; every row and column is transformed by
//! one thread with the same arithmetic whatever the number of threads, so
//! the result is the same to the bit on any number of them.

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::Fft;
use rustfft::num_complex::Complex64;

use super::plans::{self, Direction};
use super::transpose::{BLOCK, gather_columns, gather_rows};
use crate::NumericError;

/// The plans of a complex 2-D transform of one `rows × cols` shape, both
/// directions.
pub struct ComplexFft2 {
    rows: usize,
    cols: usize,
    /// along a row (cols points): forward, inverse
    along_rows: [Arc<dyn Fft<f64>>; 2],
    /// down a column (rows points): forward, inverse
    along_columns: [Arc<dyn Fft<f64>>; 2],
}

impl ComplexFft2 {
    pub fn new(rows: usize, cols: usize) -> Result<Self, NumericError> {
        if rows == 0 || cols == 0 {
            return Err(NumericError::EmptyGrid {
                what: "complex 2-D FFT",
                rows,
                cols,
            });
        }
        let both = |n: usize| {
            [
                plans::complex(n, Direction::Forward),
                plans::complex(n, Direction::Inverse),
            ]
        };
        Ok(Self {
            rows,
            cols,
            along_rows: both(cols),
            along_columns: both(rows),
        })
    }

    /// The shape, (rows, cols).
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// Transforms the row-major `data` (rows × cols) in place.
    pub fn process(
        &self,
        data: &mut [Complex64],
        direction: Direction,
    ) -> Result<(), NumericError> {
        let (rows, cols) = (self.rows, self.cols);
        if data.len() != rows * cols {
            return Err(NumericError::Length {
                what: "complex 2-D FFT's array",
                expected: rows * cols,
                got: data.len(),
            });
        }
        let k = match direction {
            Direction::Forward => 0,
            Direction::Inverse => 1,
        };
        let (along_rows, along_columns) = (&self.along_rows[k], &self.along_columns[k]);
        data.par_chunks_mut(BLOCK * cols).for_each_init(
            || vec![Complex64::ZERO; along_rows.get_inplace_scratch_len()],
            |scratch, band| along_rows.process_with_scratch(band, scratch),
        );
        let mut columns = vec![Complex64::ZERO; rows * cols];
        let source: &[Complex64] = data;
        columns
            .par_chunks_mut(BLOCK * rows)
            .enumerate()
            .for_each_init(
                || vec![Complex64::ZERO; along_columns.get_inplace_scratch_len()],
                |scratch, (block, strip)| {
                    gather_columns(source, cols, block * BLOCK, rows, strip);
                    along_columns.process_with_scratch(strip, scratch);
                },
            );
        data.par_chunks_mut(BLOCK * cols)
            .enumerate()
            .for_each(|(block, band)| gather_rows(&columns, rows, block * BLOCK, cols, band));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use hypercontact_fuzz::on_threads;
    use proptest::prelude::*;

    use super::*;
    use crate::fft2::direct::{dft2, max_difference};

    fn array(rows: usize, cols: usize, seed: u64) -> Vec<Complex64> {
        (0..rows * cols)
            .map(|k| {
                let x = (k as u64 + 3).wrapping_mul(seed.wrapping_mul(2) + 0x2545_F491);
                Complex64::new(
                    ((x % 1009) as f64 - 504.0) / 61.0,
                    ((x / 1009 % 997) as f64 - 498.0) / 59.0,
                )
            })
            .collect()
    }

    #[test]
    fn a_wrong_length_or_an_empty_shape_is_refused() {
        assert!(ComplexFft2::new(3, 0).is_err());
        let fft = ComplexFft2::new(3, 4).unwrap();
        assert!(matches!(
            fft.process(&mut [Complex64::ZERO; 11], Direction::Forward),
            Err(NumericError::Length {
                expected: 12,
                got: 11,
                ..
            })
        ));
    }

    #[test]
    fn one_and_two_threads_give_the_same_bits() {
        let (rows, cols) = (67, 90);
        let run = || {
            let fft = ComplexFft2::new(rows, cols).unwrap();
            let mut data = array(rows, cols, 4);
            fft.process(&mut data, Direction::Forward).unwrap();
            data.iter()
                .flat_map(|c| [c.re.to_bits(), c.im.to_bits()])
                .collect::<Vec<_>>()
        };
        assert_eq!(on_threads(1, run), on_threads(2, run));
    }

    proptest! {
        #![proptest_config(hypercontact_fuzz::config(48))]

        /// Odd, prime and even shapes, both directions: the direct DFT.
        #[test]
        fn both_directions_are_the_direct_dft(
            rows in 1usize..14,
            cols in 1usize..14,
            inverse in any::<bool>(),
            seed in 0u64..1000,
        ) {
            let direction = if inverse { Direction::Inverse } else { Direction::Forward };
            let x = array(rows, cols, seed);
            let mut fast = x.clone();
            ComplexFft2::new(rows, cols).unwrap().process(&mut fast, direction).unwrap();
            let slow = dft2(&x, rows, cols, direction);
            prop_assert!(max_difference(&fast, &slow) < 1e-10);
        }
    }
}
