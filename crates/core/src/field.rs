//! Regular 2-D fields (height maps, strain maps) with their grid spacing.
//!
//! Axis 0 of `values` is x and axis 1 is y, the convention of the
//! SurfaceTopography package, so `.npy` files exchanged with it need no
//! transposition. NaN marks a point that was not measured.

use std::io::{Read, Write};

use ndarray::Array2;
use ndarray_npy::npy::header::Header;
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
    /// The shortest length scale the instrument measured reliably, metres,
    /// where known (SurfaceTopography's `short_reliability_cutoff`: for a
    /// probe, the scale below which its tip distorts the map); `None` when
    /// nothing is known or every scale of the grid is reliable. Kept in the
    /// grid sidecar.
    pub short_cutoff_m: Option<f64>,
}

/// The sidecar that keeps a field's grid next to its `.npy` file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub dx_m: f64,
    pub dy_m: f64,
    /// [`Field::short_cutoff_m`]; absent when `None`, so a field without
    /// one keeps the sidecar it always had.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub short_cutoff_m: Option<f64>,
}

#[derive(Debug, thiserror::Error)]
pub enum FieldError {
    #[error("grid spacing must be positive and finite, got dx_m = {dx_m}, dy_m = {dy_m}")]
    BadSpacing { dx_m: f64, dy_m: f64 },
    #[error("a reliability cut-off must be positive and finite, got short_cutoff_m = {0}")]
    BadCutoff(f64),
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
    #[error(
        "the .npy header claims shape {shape} of {item_bytes}-byte values, {claimed} bytes of \
         data, but the file holds {held}"
    )]
    Size {
        shape: String,
        item_bytes: usize,
        /// The byte count the shape implies.
        claimed: String,
        /// The bytes after the header (`more than N` when reading stopped).
        held: String,
    },
    #[error(
        "the .npy header claims shape {shape} = {points} points, above the limit of \
         {max_points} (max_points); raise `max_points` if the map is real"
    )]
    TooManyPoints {
        shape: String,
        points: String,
        max_points: String,
    },
    #[error("bad grid sidecar: {0}")]
    Grid(String),
}

/// Why a height map cannot be a contact surface (see
/// [`Field::contact_surface_problem`]). The caller says what a flat map
/// means for its model after [`SurfaceProblem`]'s own text.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SurfaceProblem {
    #[error("the map is {nx} × {ny}; at least {min} × {min} points are needed")]
    TooSmall { nx: usize, ny: usize, min: usize },
    #[error("point [{i}, {j}] holds an infinite height")]
    Infinite { i: usize, j: usize },
    #[error("every height is NaN")]
    Unmeasured,
    #[error("the map is flat (every measured height is {0:e} m)")]
    Flat(f64),
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
        Ok(Self {
            values,
            dx_m,
            dy_m,
            short_cutoff_m: None,
        })
    }

    /// The field with its reliability cut-off (see
    /// [`Field::short_cutoff_m`]); a value that is not positive and finite
    /// is refused.
    pub fn with_short_cutoff_m(mut self, short_cutoff_m: Option<f64>) -> Result<Self, FieldError> {
        if let Some(cutoff_m) = short_cutoff_m
            && !(cutoff_m > 0.0 && cutoff_m.is_finite())
        {
            return Err(FieldError::BadCutoff(cutoff_m));
        }
        self.short_cutoff_m = short_cutoff_m;
        Ok(self)
    }

    pub fn nx(&self) -> usize {
        self.values.nrows()
    }

    pub fn ny(&self) -> usize {
        self.values.ncols()
    }

    /// The first reason the heights (m, NaN = not measured) cannot be a
    /// rough contact surface: under `min` points along an axis, an
    /// infinite height, nothing measured, or every measured height equal.
    pub fn contact_surface_problem(&self, min: usize) -> Option<SurfaceProblem> {
        let (nx, ny) = (self.nx(), self.ny());
        if nx < min || ny < min {
            return Some(SurfaceProblem::TooSmall { nx, ny, min });
        }
        if let Some(k) = self.values.iter().position(|h| h.is_infinite()) {
            return Some(SurfaceProblem::Infinite {
                i: k / ny,
                j: k % ny,
            });
        }
        let mut measured = self.values.iter().filter(|h| !h.is_nan());
        let Some(&first) = measured.next() else {
            return Some(SurfaceProblem::Unmeasured);
        };
        measured
            .all(|&h| h == first)
            .then_some(SurfaceProblem::Flat(first))
    }

    /// Whether the map is a line scan (a profile): one point across and
    /// more along, n × 1 (along x) or 1 × n (along y).
    pub fn is_line_scan(&self) -> bool {
        let (nx, ny) = self.values.dim();
        (nx == 1) != (ny == 1)
    }

    pub fn grid(&self) -> Grid {
        Grid {
            nx: self.nx(),
            ny: self.ny(),
            dx_m: self.dx_m,
            dy_m: self.dy_m,
            short_cutoff_m: self.short_cutoff_m,
        }
    }

    /// Writes the values as a little-endian float64 `.npy` array.
    pub fn write_npy<W: Write>(&self, writer: W) -> Result<(), FieldError> {
        self.values
            .write_npy(writer)
            .map_err(|e| FieldError::Npy(e.to_string()))
    }

    /// Reads a `.npy` array and attaches the grid spacing; never reads
    /// more data than the header promises.
    pub fn read_npy<R: Read>(reader: R, dx_m: f64, dy_m: f64) -> Result<Self, FieldError> {
        let values = read_npy_2d(reader, None, usize::MAX)?;
        Self::new(values, dx_m, dy_m)
    }

    /// Reads a `.npy` file a user named: its size (`file_bytes`) must be
    /// what the header promises and its points at most `max_points`, both
    /// judged from the header before the data is read.
    pub fn read_npy_file<R: Read>(
        reader: R,
        file_bytes: u64,
        dx_m: f64,
        dy_m: f64,
        max_points: usize,
    ) -> Result<Self, FieldError> {
        let values = read_npy_2d(reader, Some(file_bytes), max_points)?;
        Self::new(values, dx_m, dy_m)
    }

    /// Reads a `.npy` array with its grid sidecar (JSON) and checks they agree.
    pub fn read_with_grid<R: Read>(npy: R, grid_json: &[u8]) -> Result<Self, FieldError> {
        let grid: Grid =
            serde_json::from_slice(grid_json).map_err(|e| FieldError::Grid(e.to_string()))?;
        let field =
            Self::read_npy(npy, grid.dx_m, grid.dy_m)?.with_short_cutoff_m(grid.short_cutoff_m)?;
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
/// in instrument exports, either byte order and either memory order.
///
/// The header is read and judged before the data: ndarray-npy allocates the
/// header's and the data's claimed lengths before reading them, so a
/// 12-byte file claiming 10¹² values aborted the process on an 8 TB
/// allocation, and a sparse 6 GB file whose header says 1 × 1 was read
/// whole. Now a shape above `max_points`, or a file (of `file_bytes`, when
/// the caller knows it) whose size is not the header's promise, is refused
/// before any data is read, and no more than the promised bytes (and one
/// over, to see there are more) are ever read.
fn read_npy_2d<R: Read>(
    mut reader: R,
    file_bytes: Option<u64>,
    max_points: usize,
) -> Result<Array2<f64>, FieldError> {
    let mut bytes = read_header(&mut reader)?;
    let data_start = bytes.len();
    let header = Header::from_reader(&mut bytes.as_slice()).map_err(npy_error)?;
    let item_bytes = value_bytes(&header.type_descriptor.to_string())
        .and_then(|n| check_2d(&header.shape).map(|()| n))
        .map_err(|e| FieldError::Npy(e.to_string()))?;
    let shape = shape_text(&header.shape);
    let points = header
        .shape
        .iter()
        .try_fold(1usize, |n, &side| n.checked_mul(side));
    if let Some(points) = points.filter(|&n| n > max_points) {
        return Err(FieldError::TooManyPoints {
            shape,
            points: grouped(points),
            max_points: grouped(max_points),
        });
    }
    let claimed = points.and_then(|n| n.checked_mul(item_bytes));
    let size_error = |held: String| FieldError::Size {
        shape: shape.clone(),
        item_bytes,
        claimed: claimed.map_or_else(|| "more than a usize counts".into(), |n| n.to_string()),
        held,
    };
    if let Some(file_bytes) = file_bytes {
        let held = file_bytes.saturating_sub(data_start as u64);
        if claimed.is_none_or(|n| held != n as u64) {
            return Err(size_error(held.to_string()));
        }
    }
    // a claim beyond a usize is refused whatever follows; read what an
    // in-memory caller holds only to say how much that is
    let promised = claimed.map_or(u64::MAX, |n| n as u64 + 1);
    reader
        .take(promised)
        .read_to_end(&mut bytes)
        .map_err(|e| FieldError::Npy(e.to_string()))?;
    let held = bytes.len() - data_start;
    match claimed {
        Some(claimed) if held > claimed => {
            return Err(size_error(format!("at least {held}")));
        }
        Some(claimed) if held == claimed => {}
        _ => return Err(size_error(held.to_string())),
    }
    let values = if item_bytes == 8 {
        Array2::<f64>::read_npy(bytes.as_slice())
    } else {
        Array2::<f32>::read_npy(bytes.as_slice()).map(|a| a.mapv(f64::from))
    };
    values.map_err(npy_error)
}

/// Why an array's values cannot be a field's: the words of the `.npy`
/// reader, said also of an array handed over from another language (the
/// Python `Field`), so both refuse the same arrays alike.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ValuesError {
    /// The type descriptor as a `.npy` header writes it (`'<i8'`).
    #[error("the values are `{0}`, not float64 or float32")]
    Type(String),
    #[error("the array has shape {0}, not 2-D")]
    Shape(String),
}

/// The bytes of one value of type `descr`, the type descriptor as a `.npy`
/// header writes it (a Python literal: `'<f8'`, `'|b1'`, `[('a', '<f8')]`):
/// float64 and float32 of either byte order are field values; integers
/// (which would be taken as metres), booleans, complex numbers (whose
/// imaginary part would be lost), objects and records are not.
pub fn value_bytes(descr: &str) -> Result<usize, ValuesError> {
    match descr {
        "'<f8'" | "'>f8'" => Ok(8),
        "'<f4'" | "'>f4'" => Ok(4),
        _ => Err(ValuesError::Type(descr.to_owned())),
    }
}

/// Refuses an array of any shape but 2-D, naming its shape (`()` for a
/// scalar).
pub fn check_2d(shape: &[usize]) -> Result<(), ValuesError> {
    match shape.len() {
        2 => Ok(()),
        _ => Err(ValuesError::Shape(shape_text(shape))),
    }
}

/// A count with its digits in groups of three (`268 435 456`).
fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, digit) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(digit);
    }
    out
}

/// ndarray-npy's message, cut short: a parse error quotes the header line,
/// which a broken file can make megabytes long.
fn npy_error(e: impl std::fmt::Display) -> FieldError {
    const LONGEST: usize = 300;
    let mut message = e.to_string();
    if let Some((cut, _)) = message.char_indices().nth(LONGEST) {
        message.truncate(cut);
        message.push_str(" …");
    }
    FieldError::Npy(message)
}

/// The largest header a `.npy` file may have: NumPy writes a few hundred
/// bytes; format 2.0 could claim 4 GiB, which would be read before judging.
const LONGEST_HEADER: u64 = 1 << 20;

/// A `.npy` file's magic string, version, header length and header, once
/// each is checked; the data is left unread.
fn read_header<R: Read>(reader: &mut R) -> Result<Vec<u8>, FieldError> {
    const MAGIC: &[u8] = b"\x93NUMPY";
    let bad = FieldError::Npy;
    let mut bytes = Vec::new();
    let mut read_upto = |bytes: &mut Vec<u8>, len: u64| -> Result<(), FieldError> {
        let want = bytes.len() + len as usize;
        reader
            .by_ref()
            .take(len)
            .read_to_end(bytes)
            .map_err(|e| FieldError::Npy(e.to_string()))?;
        if bytes.len() < want {
            return Err(FieldError::Npy(if bytes.is_empty() {
                "the file is empty".into()
            } else {
                format!(
                    "the file ends inside the header (after {} bytes)",
                    bytes.len()
                )
            }));
        }
        Ok(())
    };
    let magic_or_empty = read_upto(&mut bytes, 8);
    if !bytes.is_empty() && !bytes.starts_with(&MAGIC[..bytes.len().min(MAGIC.len())]) {
        return Err(bad("no .npy magic string (\\x93NUMPY) at the start".into()));
    }
    magic_or_empty?;
    let (major, minor) = (bytes[6], bytes[7]);
    // Format 1.0 counts the header in 2 bytes, 2.0 and 3.0 in 4.
    let header_len = match major {
        1 => {
            read_upto(&mut bytes, 2)?;
            u64::from(u16::from_le_bytes([bytes[8], bytes[9]]))
        }
        2 | 3 => {
            read_upto(&mut bytes, 4)?;
            u64::from(u32::from_le_bytes([
                bytes[8], bytes[9], bytes[10], bytes[11],
            ]))
        }
        _ => return Err(bad(format!("unknown .npy format version {major}.{minor}"))),
    };
    if header_len > LONGEST_HEADER {
        return Err(bad(format!(
            "the header claims {header_len} bytes of header, more than the {LONGEST_HEADER} \
             a .npy header may take"
        )));
    }
    let preamble = bytes.len();
    read_upto(&mut bytes, header_len).map_err(|_| {
        FieldError::Npy(format!(
            "the header claims {header_len} bytes of header, the file holds {} after its \
             {preamble}-byte preamble",
            bytes.len() - preamble
        ))
    })?;
    Ok(bytes)
}

/// `(1000, 2000)`, as NumPy writes a shape.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
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

    /// The cut-off travels in the sidecar; a field without one keeps the
    /// sidecar's bytes as they were before it existed (#53).
    #[test]
    fn the_reliability_cut_off_round_trips_and_is_absent_when_unknown() {
        let plain = Field::new(array![[1.0, 2.0], [3.0, 4.0]], 1e-9, 2e-9).unwrap();
        assert_eq!(
            String::from_utf8(plain.grid_json()).unwrap(),
            "{\n  \"nx\": 2,\n  \"ny\": 2,\n  \"dx_m\": 1e-9,\n  \"dy_m\": 2e-9\n}\n"
        );
        let cut = plain.clone().with_short_cutoff_m(Some(5.7e-8)).unwrap();
        let mut npy = Vec::new();
        cut.write_npy(&mut npy).unwrap();
        let back = Field::read_with_grid(npy.as_slice(), &cut.grid_json()).unwrap();
        assert_eq!(back, cut);
        assert_eq!(back.short_cutoff_m, Some(5.7e-8));
        for bad in [0.0, -1e-9, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                plain.clone().with_short_cutoff_m(Some(bad)),
                Err(FieldError::BadCutoff(_))
            ));
        }
        let grid = br#"{"nx": 2, "ny": 2, "dx_m": 1.0, "dy_m": 1.0, "short_cutoff_m": -1.0}"#;
        assert!(matches!(
            Field::read_with_grid(npy.as_slice(), grid),
            Err(FieldError::BadCutoff(_))
        ));
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

    /// The `.npy` reader and an array from another language are refused in
    /// the same words: integers, booleans, complex numbers and objects are
    /// not field values, nor is a scalar a map.
    #[test]
    fn value_types_and_shapes_are_refused_in_the_readers_words() {
        for (descr, bytes) in [("'<f8'", 8), ("'>f8'", 8), ("'<f4'", 4), ("'>f4'", 4)] {
            assert_eq!(value_bytes(descr), Ok(bytes), "{descr}");
        }
        for descr in [
            "'<i8'",
            "'|b1'",
            "'<c16'",
            "'|O'",
            "'<f2'",
            "[('a', '<f8')]",
        ] {
            assert_eq!(
                value_bytes(descr).unwrap_err().to_string(),
                format!("the values are `{descr}`, not float64 or float32")
            );
        }
        assert_eq!(check_2d(&[3, 4]), Ok(()));
        assert_eq!(
            check_2d(&[]).unwrap_err().to_string(),
            "the array has shape (), not 2-D"
        );
        assert_eq!(
            check_2d(&[5]).unwrap_err().to_string(),
            "the array has shape (5,), not 2-D"
        );
        let integers = npy_file(
            "{'descr': '<i8', 'fortran_order': False, 'shape': (1, 1), }",
            &[0; 8],
        );
        let read = Field::read_npy(integers.as_slice(), 1.0, 1.0).unwrap_err();
        assert_eq!(
            read.to_string(),
            "not a 2-D float64 .npy array: the values are `'<i8'`, not float64 or float32"
        );
    }

    /// A `.npy` file with `header` (the dict text) and `data`: format 1.0,
    /// or 2.0 for a header longer than 1.0 can count.
    fn npy_file(header: &str, data: &[u8]) -> Vec<u8> {
        let mut dict = header.to_owned();
        let v1 = dict.len() < 65_000;
        let preamble = if v1 { 10 } else { 12 };
        while !(preamble + dict.len() + 1).is_multiple_of(64) {
            dict.push(' ');
        }
        dict.push('\n');
        let mut bytes = b"\x93NUMPY".to_vec();
        if v1 {
            bytes.extend_from_slice(&[1, 0]);
            bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
        } else {
            bytes.extend_from_slice(&[2, 0]);
            bytes.extend_from_slice(&(dict.len() as u32).to_le_bytes());
        }
        bytes.extend_from_slice(dict.as_bytes());
        bytes.extend_from_slice(data);
        bytes
    }

    /// The issue's sparse file: a 1 × 1 header followed by 6 GB of holes is
    /// refused from its size, before the data is read (reading it took
    /// seconds and 6 GB of memory); a header above `max_points` is refused
    /// with the limit named; an honest file reads.
    #[test]
    fn a_file_whose_size_is_not_the_promise_is_refused_unread() {
        let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 1), }";
        let path = std::env::temp_dir().join(format!("hc-sparse-{}.npy", std::process::id()));
        let mut file = std::fs::File::create(&path).unwrap();
        file.write_all(&npy_file(header, &[0; 8])).unwrap();
        file.set_len(6_000_000_000).unwrap();
        let file_bytes = file.metadata().unwrap().len();
        let started = std::time::Instant::now();
        let e = Field::read_npy_file(
            std::fs::File::open(&path).unwrap(),
            file_bytes,
            1.0,
            1.0,
            1 << 26,
        )
        .unwrap_err()
        .to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(
            e.contains("shape (1, 1)")
                && e.contains("8 bytes of data")
                && e.contains("holds 5999999872"),
            "{e}"
        );
        assert!(started.elapsed().as_secs() < 2, "{:?}", started.elapsed());
        let big = "{'descr': '<f8', 'fortran_order': False, 'shape': (16384, 16384), }";
        let bytes = npy_file(big, &[]);
        let e = Field::read_npy_file(bytes.as_slice(), bytes.len() as u64, 1.0, 1.0, 1 << 26)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "the .npy header claims shape (16384, 16384) = 268 435 456 points, above the limit \
             of 67 108 864 (max_points); raise `max_points` if the map is real"
        );
        let bytes = npy_file(header, &2.5f64.to_le_bytes());
        let field =
            Field::read_npy_file(bytes.as_slice(), bytes.len() as u64, 1.0, 1.0, 1).unwrap();
        assert_eq!(field.values[[0, 0]], 2.5);
    }

    fn message_of(bytes: &[u8]) -> String {
        Field::read_npy(bytes, 1.0, 1.0).unwrap_err().to_string()
    }

    #[test]
    fn a_header_claiming_more_than_the_file_holds_is_refused_before_allocating() {
        // 10¹² values (8 TB) claimed, 16 bytes present: this aborted on the
        // failed allocation.
        let bytes = npy_file(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000, 1000000), }",
            &[0; 16],
        );
        let e = message_of(&bytes);
        assert!(
            e.contains("(1000000, 1000000)")
                && e.contains("8000000000000 bytes")
                && e.contains("holds 16"),
            "{e}"
        );
        // A shape whose byte count overflows usize.
        let bytes = npy_file(
            "{'descr': '<f4', 'fortran_order': True, 'shape': (18446744073709551615, 3), }",
            &[0; 16],
        );
        let e = message_of(&bytes);
        assert!(
            e.contains("18446744073709551615") && e.contains("holds 16"),
            "{e}"
        );
        // Too few and too many bytes for an honest shape.
        let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2), }";
        assert!(message_of(&npy_file(header, &[0; 31])).contains("holds 31"));
        // the reader stops one byte past the promise
        assert!(message_of(&npy_file(header, &[0; 33])).contains("holds at least 33"));
        assert!(Field::read_npy(npy_file(header, &[0; 32]).as_slice(), 1.0, 1.0).is_ok());
        // A v2 header length of 4 GB in a 12-byte file.
        let e = message_of(b"\x93NUMPY\x02\x00\xff\xff\xff\xff");
        assert!(e.contains("4294967295") && e.contains("header"), "{e}");
    }

    #[test]
    fn a_long_broken_header_gives_a_short_message() {
        let shape = format!("{}1{}", "(".repeat(100_000), ",)".repeat(100_000));
        let header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}");
        let e = message_of(&npy_file(&header, &[]));
        assert!(e.len() < 400 && e.ends_with('…'), "{} bytes", e.len());
    }

    #[test]
    fn only_2d_float_arrays_are_fields() {
        let e = message_of(&npy_file(
            "{'descr': '<i8', 'fortran_order': False, 'shape': (2, 2), }",
            &[0; 32],
        ));
        assert!(e.contains("<i8") && e.contains("float"), "{e}");
        let e = message_of(&npy_file(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2, 2), }",
            &[0; 64],
        ));
        assert!(e.contains("(2, 2, 2)") && e.contains("2-D"), "{e}");
        // Big-endian float32 in Fortran order reads as well.
        let mut data = Vec::new();
        for v in [1.0_f32, 2.0, 3.0, 4.0] {
            data.extend_from_slice(&v.to_be_bytes());
        }
        let f = Field::read_npy(
            npy_file(
                "{'descr': '>f4', 'fortran_order': True, 'shape': (2, 2), }",
                &data,
            )
            .as_slice(),
            1.0,
            1.0,
        )
        .unwrap();
        assert_eq!(f.values, array![[1.0, 3.0], [2.0, 4.0]]);
    }

    #[test]
    fn reads_float32_npy() {
        let a = array![[1.5_f32, 2.0], [3.0, 4.0]];
        let mut npy = Vec::new();
        a.write_npy(&mut npy).unwrap();
        let f = Field::read_npy(npy.as_slice(), 1.0, 1.0).unwrap();
        assert_eq!(f.values[[0, 0]], 1.5);
    }

    proptest::proptest! {
        #![proptest_config(hypercontact_fuzz::config(512))]

        /// Byte edits of a real 6 × 5 .npy (header and data), read as a
        /// user's file of that length: never a panic, and whatever is
        /// accepted holds no more points than the file has room for and
        /// at most `max_points` (#31, 6, 7).
        #[test]
        fn an_edited_npy_file_is_read_or_refused_within_its_size(
            edits in hypercontact_fuzz::byte_edits(),
            max_points in 1usize..64,
        ) {
            let values = Array2::from_shape_fn((6, 5), |(i, j)| (i * 5 + j) as f64);
            let mut npy = Vec::new();
            values.write_npy(&mut npy).unwrap();
            let bytes = hypercontact_fuzz::splice(npy, &edits);
            let len = bytes.len() as u64;
            if let Ok(field) = Field::read_npy_file(bytes.as_slice(), len, 1.0, 1.0, max_points) {
                let points = field.nx() * field.ny();
                proptest::prop_assert!(points <= max_points);
                proptest::prop_assert!(4 * points as u64 <= len, "{points} points in {len} bytes");
            }
        }
    }
}
