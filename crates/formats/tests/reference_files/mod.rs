//! The vendor reference files of `shared/reference/topography/` and the
//! heights SurfaceTopography 1.27 reads from them (`<name>_m.npy`, metres,
//! axis 0 = x, NaN = missing, spacings in `index.json`), shared by the
//! binary readers' tests. A missing file fails the test: it never skips.

#![allow(dead_code)]

use hypercontact_formats::Topography;
use ndarray::Array2;

const REFERENCE_DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/reference/topography/"
);

/// The bytes of a reference file; panics (fails the test) when it is missing.
pub fn bytes(file: &str) -> Vec<u8> {
    let path = format!("{REFERENCE_DIR}{file}");
    std::fs::read(&path).unwrap_or_else(|e| {
        panic!("reference file {path} is missing ({e}): clone the repository beside shared/")
    })
}

/// What `index.json` says of a reference map.
pub struct Expected {
    pub shape: (usize, usize),
    pub dx_m: f64,
    pub dy_m: f64,
    pub nan_count: usize,
    pub heights_m: Array2<f64>,
}

/// `index.json`'s entry for `<stem>_m.npy` and the heights in it.
pub fn expected(stem: &str) -> Expected {
    let npy = format!("{stem}_m.npy");
    let index: serde_json::Value =
        serde_json::from_slice(&bytes("index.json")).expect("index.json is JSON");
    let entry = &index[&npy];
    let number = |key: &str| {
        entry[key]
            .as_f64()
            .unwrap_or_else(|| panic!("index.json: {npy}.{key} is not a number"))
    };
    let shape = entry["shape"].as_array().expect("shape is a list");
    let path = format!("{REFERENCE_DIR}{npy}");
    let heights_m: Array2<f64> = ndarray_npy::read_npy(&path)
        .unwrap_or_else(|e| panic!("reference heights {path} unreadable: {e}"));
    Expected {
        shape: (
            shape[0].as_u64().expect("shape[0]") as usize,
            shape[1].as_u64().expect("shape[1]") as usize,
        ),
        dx_m: number("dx_m"),
        dy_m: number("dy_m"),
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

/// The value of a metadata key, if present.
pub fn meta<'a>(read: &'a Topography, key: &str) -> Option<&'a str> {
    read.metadata
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}
