//! Moving a 2-D array of complex numbers between its row-major layout
//! (rows contiguous, for the transforms along a row) and its column-major
//! one (columns contiguous, for the transforms down a column), a strip of
//! columns or a band of rows at a time so that each task reads whole cache
//! lines and one thread owns every element it writes.

use rustfft::num_complex::Complex64;

/// Columns or rows moved per task: 16 complex numbers are 256 bytes, a few
/// cache lines per read.
pub(crate) const BLOCK: usize = 16;

/// Columns `first..` of the row-major `rows` (`rows.len() / row_len` rows
/// of `row_len`) as contiguous columns of `column_len` ≥ that many rows,
/// zero below the last row, into `strip` (as many columns as it holds).
pub(crate) fn gather_columns(
    rows: &[Complex64],
    row_len: usize,
    first: usize,
    column_len: usize,
    strip: &mut [Complex64],
) {
    let width = strip.len() / column_len;
    let filled = rows.len() / row_len;
    for (i, row) in rows.chunks_exact(row_len).enumerate() {
        for (b, &v) in row[first..first + width].iter().enumerate() {
            strip[b * column_len + i] = v;
        }
    }
    for column in strip.chunks_exact_mut(column_len) {
        column[filled..].fill(Complex64::ZERO);
    }
}

/// Rows `first..` of the column-major `columns` (columns of `column_len`)
/// as contiguous rows of `row_len` (the number of columns), into `band`
/// (as many rows as it holds).
pub(crate) fn gather_rows(
    columns: &[Complex64],
    column_len: usize,
    first: usize,
    row_len: usize,
    band: &mut [Complex64],
) {
    let height = band.len() / row_len;
    for (j, column) in columns.chunks_exact(column_len).take(row_len).enumerate() {
        for (b, &v) in column[first..first + height].iter().enumerate() {
            band[b * row_len + j] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gather_there_and_back_is_the_identity_with_zero_padding() {
        let (n_rows, row_len, column_len) = (5, 7, 8);
        let rows: Vec<Complex64> = (0..n_rows * row_len)
            .map(|k| Complex64::new(k as f64, -(k as f64)))
            .collect();
        let mut columns = vec![Complex64::new(9.0, 9.0); row_len * column_len];
        for (s, strip) in columns.chunks_mut(3 * column_len).enumerate() {
            gather_columns(&rows, row_len, 3 * s, column_len, strip);
        }
        for j in 0..row_len {
            for i in 0..column_len {
                let expected = if i < n_rows {
                    rows[i * row_len + j]
                } else {
                    Complex64::ZERO
                };
                assert_eq!(columns[j * column_len + i], expected, "({i}, {j})");
            }
        }
        let mut back = vec![Complex64::ZERO; n_rows * row_len];
        for (b, band) in back.chunks_mut(2 * row_len).enumerate() {
            gather_rows(&columns, column_len, 2 * b, row_len, band);
        }
        assert_eq!(back, rows);
    }
}
