//! Regular 2-D fields (height maps, strain maps) with their grid spacing.
//!
//! Axis 0 of `values` is x and axis 1 is y, the convention of the
//! SurfaceTopography package, so `.npy` files exchanged with it need no
//! transposition. NaN marks a point that was not measured.

use std::io::{Read, Write};

use ndarray::Array2;
use ndarray_npy::{ReadNpyExt, WriteNpyExt};
use serde::{Deserialize, Serialize};

/// A 2-D array sampled on a regular grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Values indexed `[ix, iy]`; NaN where nothing was measured.
    pub values: Array2<f64>,
    /// Grid spacing along axis 0 (x), metres.
    pub dx_m: f64,
    /// Grid spacing along axis 1 (y), metres.
    pub dy_m: f64,
}

/// The sidecar that keeps a field's grid next to its `.npy` file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub dx_m: f64,
    pub dy_m: f64,
}

#[derive(Debug, thiserror::Error)]
pub enum FieldError {
    #[error("grid spacing must be positive and finite, got dx_m = {dx_m}, dy_m = {dy_m}")]
    BadSpacing { dx_m: f64, dy_m: f64 },
    #[error("the field is empty ({nx} × {ny})")]
    Empty { nx: usize, ny: usize },
    #[error("grid sidecar says {grid_nx} × {grid_ny} but the array is {nx} × {ny}")]
    GridMismatch {
        grid_nx: usize,
        grid_ny: usize,
        nx: usize,
        ny: usize,
    },
    #[error("not a 2-D float64 .npy array: {0}")]
    Npy(String),
    #[error("bad grid sidecar: {0}")]
    Grid(String),
}

impl Field {
    /// A field with checked spacing and a non-empty grid.
    pub fn new(values: Array2<f64>, dx_m: f64, dy_m: f64) -> Result<Self, FieldError> {
        if !(dx_m > 0.0 && dx_m.is_finite() && dy_m > 0.0 && dy_m.is_finite()) {
            return Err(FieldError::BadSpacing { dx_m, dy_m });
        }
        let (nx, ny) = values.dim();
        if nx == 0 || ny == 0 {
            return Err(FieldError::Empty { nx, ny });
        }
        Ok(Self { values, dx_m, dy_m })
    }

    pub fn nx(&self) -> usize {
        self.values.nrows()
    }

    pub fn ny(&self) -> usize {
        self.values.ncols()
    }

    pub fn grid(&self) -> Grid {
        Grid {
            nx: self.nx(),
            ny: self.ny(),
            dx_m: self.dx_m,
            dy_m: self.dy_m,
        }
    }

    /// Writes the values as a little-endian float64 `.npy` array.
    pub fn write_npy<W: Write>(&self, writer: W) -> Result<(), FieldError> {
        self.values
            .write_npy(writer)
            .map_err(|e| FieldError::Npy(e.to_string()))
    }

    /// Reads a `.npy` array and attaches the grid spacing.
    pub fn read_npy<R: Read>(reader: R, dx_m: f64, dy_m: f64) -> Result<Self, FieldError> {
        let values = read_npy_2d(reader)?;
        Self::new(values, dx_m, dy_m)
    }

    /// Reads a `.npy` array with its grid sidecar (JSON) and checks they agree.
    pub fn read_with_grid<R: Read>(npy: R, grid_json: &[u8]) -> Result<Self, FieldError> {
        let grid: Grid =
            serde_json::from_slice(grid_json).map_err(|e| FieldError::Grid(e.to_string()))?;
        let field = Self::read_npy(npy, grid.dx_m, grid.dy_m)?;
        if (field.nx(), field.ny()) != (grid.nx, grid.ny) {
            return Err(FieldError::GridMismatch {
                grid_nx: grid.nx,
                grid_ny: grid.ny,
                nx: field.nx(),
                ny: field.ny(),
            });
        }
        Ok(field)
    }

    /// The grid sidecar as pretty JSON.
    pub fn grid_json(&self) -> Vec<u8> {
        let mut bytes = serde_json::to_vec_pretty(&self.grid()).expect("a grid always serialises");
        bytes.push(b'\n');
        bytes
    }
}

/// Reads a 2-D `.npy` array of float64, or of float32 (widened), both common
/// in instrument exports.
fn read_npy_2d<R: Read>(mut reader: R) -> Result<Array2<f64>, FieldError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| FieldError::Npy(e.to_string()))?;
    match Array2::<f64>::read_npy(bytes.as_slice()) {
        Ok(a) => Ok(a),
        Err(first) => Array2::<f32>::read_npy(bytes.as_slice())
            .map(|a| a.mapv(f64::from))
            .map_err(|_| FieldError::Npy(first.to_string())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn npy_round_trip_keeps_values_nan_and_grid() {
        let f = Field::new(array![[1.0, f64::NAN], [3.0, 4.5e-6]], 2e-5, 3e-5).unwrap();
        let mut npy = Vec::new();
        f.write_npy(&mut npy).unwrap();
        let back = Field::read_with_grid(npy.as_slice(), &f.grid_json()).unwrap();
        assert_eq!(back.values[[0, 0]], 1.0);
        assert!(back.values[[0, 1]].is_nan());
        assert_eq!(back.values[[1, 1]], 4.5e-6);
        assert_eq!((back.dx_m, back.dy_m), (2e-5, 3e-5));
    }

    #[test]
    fn bad_spacing_and_mismatched_grid_are_errors() {
        assert!(matches!(
            Field::new(array![[1.0]], 0.0, 1.0),
            Err(FieldError::BadSpacing { .. })
        ));
        let f = Field::new(array![[1.0, 2.0]], 1.0, 1.0).unwrap();
        let mut npy = Vec::new();
        f.write_npy(&mut npy).unwrap();
        let grid = br#"{"nx": 2, "ny": 1, "dx_m": 1.0, "dy_m": 1.0}"#;
        assert!(matches!(
            Field::read_with_grid(npy.as_slice(), grid),
            Err(FieldError::GridMismatch { .. })
        ));
    }

    #[test]
    fn reads_float32_npy() {
        let a = array![[1.5_f32, 2.0], [3.0, 4.0]];
        let mut npy = Vec::new();
        a.write_npy(&mut npy).unwrap();
        let f = Field::read_npy(npy.as_slice(), 1.0, 1.0).unwrap();
        assert_eq!(f.values[[0, 0]], 1.5);
    }
}
