//! What the readers' integration tests share: the vendor reference files of
//! `shared/reference/topography/` and the heights SurfaceTopography 1.27
//! reads from them (`<name>_m.npy`, metres, axis 0 = x, NaN = missing,
//! spacings in `index.json`), the crate's own test files in `tests/data/`
//! (listed likewise in `datx-index.json`), the comparisons of maps, and
//! the unpacking and re-zipping of X3P archives. A missing file fails the
//! test: it never skips.

#![allow(dead_code)]

use std::io::{Cursor, Read, Write};

use hypercontact_formats::Topography;
use ndarray::Array2;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipArchive, ZipWriter};

pub mod sur_streams;

const REFERENCE_DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/reference/topography/"
);

/// The second set of reference files (issue 36's instruments), `index.json` beside them.
const MORE_DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/reference/topography/more/"
);

const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");

fn read_file(dir: &str, file: &str) -> Vec<u8> {
    let path = format!("{dir}{file}");
    std::fs::read(&path).unwrap_or_else(|e| {
        panic!("test file {path} is missing ({e}): clone the repository beside shared/")
    })
}

/// The bytes of a reference file; panics (fails the test) when it is missing.
pub fn bytes(file: &str) -> Vec<u8> {
    read_file(REFERENCE_DIR, file)
}

/// The bytes of a reference file of `more/`.
pub fn more(file: &str) -> Vec<u8> {
    read_file(MORE_DIR, file)
}

/// `more/index.json`'s entry for `<stem>_m.npy` and the heights in it; a
/// line scan's 1-D heights as an n × 1 map (and `dy_m` = `dx_m`).
pub fn expected_more(stem: &str) -> Expected {
    let npy = format!("{stem}_m.npy");
    expected_in(MORE_DIR, "index.json", &npy, &npy)
}

/// The bytes of a file of `tests/data/`.
pub fn data(file: &str) -> Vec<u8> {
    read_file(DATA_DIR, file)
}

/// What an index says of a map, and SurfaceTopography's heights.
pub struct Expected {
    pub shape: (usize, usize),
    pub dx_m: f64,
    pub dy_m: f64,
    pub nan_count: usize,
    pub heights_m: Array2<f64>,
}

/// `index.json`'s entry for the reference map `<stem>_m.npy` and the heights in it.
pub fn expected(stem: &str) -> Expected {
    let npy = format!("{stem}_m.npy");
    expected_in(REFERENCE_DIR, "index.json", &npy, &npy)
}

/// `datx-index.json`'s entry for `stem` of `tests/data/` and `<stem>_m.npy`.
pub fn expected_data(stem: &str) -> Expected {
    expected_in(DATA_DIR, "datx-index.json", stem, &format!("{stem}_m.npy"))
}

fn expected_in(dir: &str, index: &str, key: &str, npy: &str) -> Expected {
    let index: serde_json::Value =
        serde_json::from_slice(&read_file(dir, index)).expect("the index is JSON");
    let entry = &index[key];
    let number = |field: &str| {
        entry[field]
            .as_f64()
            .unwrap_or_else(|| panic!("{key}.{field} is not a number"))
    };
    let size = |axis: usize| {
        entry["shape"][axis]
            .as_u64()
            .unwrap_or_else(|| panic!("{key}.shape[{axis}] is not a size")) as usize
    };
    let path = format!("{dir}{npy}");
    let line = entry["shape"].as_array().is_some_and(|s| s.len() == 1);
    let heights_m: Array2<f64> = if line {
        let line: ndarray::Array1<f64> = ndarray_npy::read_npy(&path)
            .unwrap_or_else(|e| panic!("reference heights {path} unreadable: {e}"));
        line.insert_axis(ndarray::Axis(1))
    } else {
        ndarray_npy::read_npy(&path)
            .unwrap_or_else(|e| panic!("reference heights {path} unreadable: {e}"))
    };
    Expected {
        shape: (size(0), if line { 1 } else { size(1) }),
        dx_m: number("dx_m"),
        dy_m: if line { number("dx_m") } else { number("dy_m") },
        nan_count: number("nan_count") as usize,
        heights_m,
    }
}

/// Asserts the grid, spacing and missing points equal the reference and the
/// heights agree to `tolerance` × the reference's height range; returns the
/// largest difference relative to that range.
pub fn assert_same_map(read: &Topography, expected: &Expected, tolerance: f64) -> f64 {
    assert_eq!(read.heights_m.dim(), expected.shape, "shape");
    assert_eq!(expected.heights_m.dim(), expected.shape, "the .npy's shape");
    let relative = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(
        relative(read.dx_m, expected.dx_m) < 1e-9,
        "dx {} vs {}",
        read.dx_m,
        expected.dx_m
    );
    assert!(
        relative(read.dy_m, expected.dy_m) < 1e-9,
        "dy {} vs {}",
        read.dy_m,
        expected.dy_m
    );
    let nan_read = read.heights_m.iter().filter(|h| h.is_nan()).count();
    assert_eq!(nan_read, expected.nan_count, "missing points");
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for h in expected.heights_m.iter().filter(|h| !h.is_nan()) {
        low = low.min(*h);
        high = high.max(*h);
    }
    let range = high - low;
    assert!(range > 0.0, "the reference map is flat");
    let mut worst: f64 = 0.0;
    for ((index, a), b) in read.heights_m.indexed_iter().zip(expected.heights_m.iter()) {
        assert_eq!(a.is_nan(), b.is_nan(), "missing point differs at {index:?}");
        if !a.is_nan() {
            worst = worst.max((a - b).abs() / range);
        }
    }
    assert!(
        worst <= tolerance,
        "heights differ by {worst:e} of the range (> {tolerance:e})"
    );
    worst
}

/// Equal shapes, NaN at the same places, the other heights within
/// `tolerance_m`.
pub fn assert_heights_within(actual: &Array2<f64>, expected: &Array2<f64>, tolerance_m: f64) {
    assert_eq!(actual.dim(), expected.dim());
    for ((index, a), e) in actual.indexed_iter().zip(expected) {
        assert_eq!(a.is_nan(), e.is_nan(), "missing point differs at {index:?}");
        if !a.is_nan() {
            assert!((a - e).abs() <= tolerance_m, "{index:?}: {a} vs {e}");
        }
    }
}

/// Equal shapes and the same numbers bit for bit (any NaN matching any NaN).
pub fn assert_identical(actual: &Array2<f64>, expected: &Array2<f64>) {
    assert_eq!(actual.dim(), expected.dim());
    for ((index, a), e) in actual.indexed_iter().zip(expected) {
        assert!(
            a.to_bits() == e.to_bits() || (a.is_nan() && e.is_nan()),
            "{index:?}: {a} vs {e}"
        );
    }
}

/// What a read of fuzzed bytes must satisfy: an error, or a map with no
/// more points than the file has bytes and positive spacings.
pub fn check_fuzzed_read(
    read: Result<Topography, hypercontact_formats::FormatError>,
    file_len: usize,
) -> Result<(), proptest::test_runner::TestCaseError> {
    let Ok(map) = read else {
        return Ok(());
    };
    let (nx, ny) = map.heights_m.dim();
    proptest::prop_assert!(nx * ny <= file_len);
    proptest::prop_assert!(map.dx_m > 0.0 && map.dy_m > 0.0);
    Ok(())
}

/// The value of a metadata key, if present.
pub fn meta<'a>(read: &'a Topography, key: &str) -> Option<&'a str> {
    read.meta(key)
}

/// The members of a zip archive (an X3P file), inflated, in their order.
pub fn zip_members(archive: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut archive = ZipArchive::new(Cursor::new(archive)).expect("a zip archive");
    (0..archive.len())
        .map(|i| {
            let mut member = archive.by_index(i).unwrap();
            let mut content = Vec::new();
            member.read_to_end(&mut content).unwrap();
            (member.name().unwrap().to_string(), content)
        })
        .collect()
}

/// A zip archive of `members`, stored, in their order.
pub fn stored_zip(members: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut writer = ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Stored);
    for (name, content) in members {
        writer.start_file(name.as_str(), options).unwrap();
        writer.write_all(content).unwrap();
    }
    writer.finish().unwrap().into_inner()
}
