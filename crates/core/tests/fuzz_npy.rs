//! Property tests of the `.npy` reader: arbitrary bytes, headers with any
//! shape, dtype and order, and valid files with bytes changed, inserted or
//! cut never panic (nor abort on a huge allocation), and every error names
//! the file, as the reader a stage uses reports it.
//!
//! Bounded for CI: a fixed seed and a few hundred cases per property;
//! `PROPTEST_CASES` and `PROPTEST_RNG_SEED` widen or move the search.

use std::path::PathBuf;

use hypercontact_core::FieldReader;
use hypercontact_core::{Field, ProductReader};
use hypercontact_fuzz::{config, splice};
use ndarray::Array2;
use proptest::prelude::*;

/// A file path of this test, one per property (cases run one after the
/// other within a property).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hc-fuzz-npy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Reads `bytes` as a field file through the reader stages use: an error
/// must name the file; a field must match the shape its header gave.
fn read_named(path: &PathBuf, bytes: &[u8]) -> Result<Field, String> {
    std::fs::write(path, bytes).unwrap();
    let result = FieldReader.read_field(path, 1e-6, 1e-6);
    // The same bytes without the file around them.
    let direct = Field::read_npy(bytes, 1e-6, 1e-6);
    assert_eq!(result.is_ok(), direct.is_ok());
    match result {
        Ok(field) => Ok(field),
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.starts_with(&path.display().to_string()),
                "the error does not name the file: {message}"
            );
            Err(message)
        }
    }
}

/// A `.npy` file of `header` (the dict text, padded) and `data`, format
/// 1.0 or 2.0.
fn npy_file(version: u8, header: &str, data: &[u8]) -> Vec<u8> {
    let preamble = if version == 1 { 10 } else { 12 };
    let mut dict = header.to_owned();
    while !(preamble + dict.len() + 1).is_multiple_of(64) {
        dict.push(' ');
    }
    dict.push('\n');
    let mut bytes = b"\x93NUMPY".to_vec();
    bytes.extend_from_slice(&[version, 0]);
    if version == 1 {
        bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    } else {
        bytes.extend_from_slice(&(dict.len() as u32).to_le_bytes());
    }
    bytes.extend_from_slice(dict.as_bytes());
    bytes.extend_from_slice(data);
    bytes
}

/// Valid files: float64 or float32, either byte order and memory order,
/// format 1.0 or 2.0, 1…12 × 1…12 values (NaN and infinities included).
fn valid_npy() -> impl Strategy<Value = (Vec<u8>, (usize, usize))> {
    (
        1usize..=12,
        1usize..=12,
        prop_oneof![Just("<f8"), Just(">f8"), Just("<f4"), Just(">f4")],
        any::<bool>(),
        prop_oneof![Just(1u8), Just(2u8)],
        prop::collection::vec(any::<f64>(), 144),
    )
        .prop_map(|(nx, ny, descr, fortran, version, values)| {
            let mut data = Vec::new();
            for &v in &values[..nx * ny] {
                match descr {
                    "<f8" => data.extend_from_slice(&v.to_le_bytes()),
                    ">f8" => data.extend_from_slice(&v.to_be_bytes()),
                    "<f4" => data.extend_from_slice(&(v as f32).to_le_bytes()),
                    _ => data.extend_from_slice(&(v as f32).to_be_bytes()),
                }
            }
            let order = if fortran { "True" } else { "False" };
            let header = format!(
                "{{'descr': '{descr}', 'fortran_order': {order}, 'shape': ({nx}, {ny}), }}"
            );
            (npy_file(version, &header, &data), (nx, ny))
        })
}

/// One edit of a byte string: at `at` (modulo its length + 1) remove
/// `remove` bytes and put `insert` there. Changing, inserting, deleting and
/// truncating are all such splices.
fn splices() -> impl Strategy<Value = Vec<(usize, usize, Vec<u8>)>> {
    prop::collection::vec(
        (
            any::<usize>(),
            prop_oneof![Just(0usize), 1usize..4, 0usize..200],
            prop::collection::vec(any::<u8>(), 0..4),
        ),
        1..6,
    )
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let _ = read_named(&scratch("arbitrary.npy"), &bytes);
        // With the magic string and a version in front, the parser gets further.
        let mut framed = b"\x93NUMPY\x01\x00".to_vec();
        framed.extend_from_slice(&bytes);
        let _ = read_named(&scratch("framed.npy"), &framed);
    }

    #[test]
    fn valid_files_read_back_with_their_shape((bytes, shape) in valid_npy()) {
        let field = read_named(&scratch("valid.npy"), &bytes).unwrap();
        prop_assert_eq!(field.values.dim(), shape);
    }

    #[test]
    fn mutated_valid_files_never_panic((bytes, _) in valid_npy(), edits in splices()) {
        let _ = read_named(&scratch("mutated.npy"), &splice(bytes, &edits));
    }

    /// Any shape (huge, zero, many dimensions), any of several dtypes, any
    /// amount of data: read only when the header and the bytes agree.
    #[test]
    fn headers_are_checked_against_the_bytes_held(
        shape in prop::collection::vec(
            prop_oneof![0usize..5, any::<usize>(), Just(1_000_000usize)],
            0..4,
        ),
        descr in prop_oneof![
            Just("<f8"), Just(">f4"), Just("<i8"), Just("|u1"), Just("<U4"), Just("bogus")
        ],
        fortran in any::<bool>(),
        version in prop_oneof![Just(1u8), Just(2u8)],
        data_len in 0usize..300,
    ) {
        let tuple = match shape.as_slice() {
            [n] => format!("({n},)"),
            _ => format!(
                "({})",
                shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
            ),
        };
        let order = if fortran { "True" } else { "False" };
        let header = format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {tuple}, }}");
        let bytes = npy_file(version, &header, &vec![0; data_len]);
        let result = read_named(&scratch("header.npy"), &bytes);
        let item = match descr {
            "<f8" => Some(8usize),
            ">f4" => Some(4),
            _ => None,
        };
        let agrees = item.is_some_and(|item| {
            shape.len() == 2
                && shape
                    .iter()
                    .try_fold(item, |n, &side| n.checked_mul(side))
                    == Some(data_len)
        });
        // An empty grid is not a field, whatever the header says.
        let non_empty = shape.iter().all(|&n| n > 0);
        prop_assert_eq!(result.is_ok(), agrees && non_empty, "{:?}", result.err());
    }
}

#[test]
fn a_written_field_reads_back_through_the_stage_reader() {
    let values = Array2::from_shape_fn((3, 4), |(i, j)| i as f64 - 0.5 * j as f64);
    let mut bytes = Vec::new();
    Field::new(values.clone(), 1.0, 1.0)
        .unwrap()
        .write_npy(&mut bytes)
        .unwrap();
    let field = read_named(&scratch("written.npy"), &bytes).unwrap();
    assert_eq!(field.values, values);
}
