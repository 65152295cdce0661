//! `height-map`'s `mask` parameter: a file saying which points of the map
//! to keep. A 2-D `.npy` array of the map's shape as read (axis 0 = x, as
//! the map), of bool (true = keep), uint8 or float64/float32 (1 = keep,
//! 0 = drop; any other value is refused, so a height map given by mistake
//! is not read as a mask). Its dropped points become NaN; [`crate::region`]
//! applies it.

use std::io::Read;
use std::path::Path;

use hypercontact_core::StageError;
use ndarray::Array2;
use ndarray_npy::ReadNpyExt;

/// Header bytes allowed beside the data of a mask file of at most
/// `max_points` points (numpy's headers are 64 … a few hundred bytes).
const HEADER_BYTES: u64 = 1 << 16;

/// The keep-mask of the `.npy` file at `path`, true = keep. A file larger
/// than a float64 mask of `max_points` points is refused unread.
pub fn read_mask(path: &Path, max_points: usize) -> Result<Array2<bool>, StageError> {
    hypercontact_core::regular_file::check_regular_file(path)?;
    let io_error = |e: std::io::Error| StageError::file(path, format!("mask: {e}"));
    let file = std::fs::File::open(path).map_err(io_error)?;
    let bound = (max_points as u64).saturating_mul(8) + HEADER_BYTES;
    let file_bytes = file.metadata().map_err(io_error)?.len();
    if file_bytes > bound {
        return Err(StageError::file(
            path,
            format!(
                "mask: the file is {file_bytes} bytes, more than a float64 mask of at most \
                 {max_points} points (max_points) can be"
            ),
        ));
    }
    let mut bytes = Vec::new();
    file.take(bound + 1)
        .read_to_end(&mut bytes)
        .map_err(io_error)?;
    if !bytes.starts_with(b"\x93NUMPY") {
        return Err(StageError::file(
            path,
            "mask: not a .npy file (a 2-D array of bool, uint8 or float 0/1, axis 0 = x, of \
             the map's shape)",
        ));
    }
    mask_of_npy(&bytes).map_err(|why| StageError::file(path, format!("mask: {why}")))
}

/// The keep-mask of the `.npy` bytes, or why they are not one.
fn mask_of_npy(bytes: &[u8]) -> Result<Array2<bool>, String> {
    if let Ok(mask) = Array2::<bool>::read_npy(bytes) {
        return Ok(mask);
    }
    let ones = |values: Array2<f64>| -> Result<Array2<bool>, String> {
        if let Some(((i, j), v)) = values
            .indexed_iter()
            .find(|(_, v)| **v != 0.0 && **v != 1.0)
        {
            return Err(format!(
                "point [{i}, {j}] holds {v}: a mask holds 1 (keep) or 0 (drop) only"
            ));
        }
        Ok(values.mapv(|v| v == 1.0))
    };
    if let Ok(values) = Array2::<u8>::read_npy(bytes) {
        return ones(values.mapv(f64::from));
    }
    if let Ok(values) = Array2::<f32>::read_npy(bytes) {
        return ones(values.mapv(f64::from));
    }
    match Array2::<f64>::read_npy(bytes) {
        Ok(values) => ones(values),
        Err(e) => Err(format!(
            "not a 2-D .npy array of bool, uint8, float32 or float64 ({e})"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;
    use ndarray_npy::WriteNpyExt;

    fn npy<T: ndarray_npy::WritableElement>(a: &Array2<T>) -> Vec<u8> {
        let mut bytes = Vec::new();
        a.write_npy(&mut bytes).unwrap();
        bytes
    }

    #[test]
    fn masks_of_each_type_read_alike_and_other_values_are_refused() {
        let keep = array![[true, false, true], [false, true, true]];
        assert_eq!(mask_of_npy(&npy(&keep)).unwrap(), keep);
        let u8s = keep.mapv(u8::from);
        assert_eq!(mask_of_npy(&npy(&u8s)).unwrap(), keep);
        let f64s = keep.mapv(|k| if k { 1.0 } else { 0.0 });
        assert_eq!(mask_of_npy(&npy(&f64s)).unwrap(), keep);
        assert_eq!(mask_of_npy(&npy(&f64s.mapv(|v| v as f32))).unwrap(), keep);
        let e = mask_of_npy(&npy(&array![[1.0, 0.5]])).unwrap_err();
        assert!(e.contains("point [0, 1] holds 0.5"), "{e}");
        let e = mask_of_npy(&npy(&array![[1.0, f64::NAN]])).unwrap_err();
        assert!(e.contains("holds NaN"), "{e}");
        let e = mask_of_npy(&npy(&array![[1i64, 0]])).unwrap_err();
        assert!(e.contains("not a 2-D .npy array of bool"), "{e}");
    }
}
