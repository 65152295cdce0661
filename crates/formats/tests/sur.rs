//! The Digital Surf reader on a real file: `sur-2.sur` (563 × 484 int32
//! counts in mm, 117 points not measured) against the heights
//! SurfaceTopography 1.27 reads from it (`sur-2_m.npy`, `index.json`).

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::sur_streams::compressed_sur;
use common::{Expected, assert_heights_within, bytes, expected, meta};
use hypercontact_formats::{Format, detect, read_bytes};
use ndarray::Axis;
use proptest::prelude::*;

#[test]
fn sur_2_equals_surface_topography() {
    let map = read_bytes(&bytes("sur-2.sur"), Some(Path::new("sur-2.sur"))).unwrap();
    let Expected {
        shape,
        dx_m: dx,
        dy_m: dy,
        nan_count,
        heights_m: expected,
    } = expected("sur-2");

    assert_eq!(map.format, Format::Sur);
    assert_eq!(map.heights_m.dim(), (563, 484));
    assert_eq!(shape, (563, 484));
    assert!((map.dx_m - dx).abs() <= 1e-9 * dx, "{} vs {dx}", map.dx_m);
    assert!((map.dy_m - dy).abs() <= 1e-9 * dy, "{} vs {dy}", map.dy_m);

    let nan = map.heights_m.iter().filter(|h| h.is_nan()).count();
    assert_eq!(nan, 117);
    assert_eq!(nan, nan_count);
    // int32 counts × the float32 Z spacing × 1e-3 (mm): both readers do the
    // same two f64 multiplications, so the heights agree to their rounding,
    // a few 1e-16 of the ~1e-5 m heights; 1e-12 of the height range allows
    // for a different order of the two
    let tolerance_m = 1e-12 * (103_880.0 - 89_120.0) * 1e-10;
    assert_heights_within(&map.heights_m, &expected, tolerance_m);
    // a mirrored read would not pass (nor a transposed one: 563 × 484)
    for axis in [Axis(0), Axis(1)] {
        let mut mirrored = expected.clone();
        mirrored.invert_axis(axis);
        let differs = mirrored
            .iter()
            .zip(&expected)
            .any(|(a, b)| (a - b).abs() > 1e6 * tolerance_m);
        assert!(differs, "sur-2 is symmetric about {axis:?}");
    }
}

#[test]
fn sur_2_metadata_is_what_the_header_says() {
    let map = read_bytes(&bytes("sur-2.sur"), None).unwrap();
    assert_eq!(meta(&map, "step_units"), Some("mm, mm, mm"));
    assert_eq!(meta(&map, "axis_names"), Some("X, Y, Z"));
    assert_eq!(meta(&map, "point_bits"), Some("32"));
    assert_eq!(meta(&map, "layout"), Some("plain"));
    // the file leaves the date, names and comment empty
    assert_eq!(meta(&map, "date"), None);
    assert_eq!(meta(&map, "operator_name"), None);
    assert_eq!(meta(&map, "comment"), None);
    // the header's X and Y offsets (float32 mm at bytes 466 and 470)
    let (x_m, y_m) = map.position_m.unwrap();
    assert!((x_m - 3.457248265448243e-12).abs() < 1e-24, "{x_m}");
    assert!((y_m + 1.4278494830932686e-11).abs() < 1e-24, "{y_m}");
}

#[test]
fn sur_is_detected_from_its_bytes_whatever_the_extension() {
    let file = bytes("sur-2.sur");
    assert_eq!(detect(&file[..16], None), Some(Format::Sur));
    let map = read_bytes(&file, Some(Path::new("scan.x3p"))).unwrap();
    assert_eq!(map.format, Format::Sur);
    assert_eq!(map.heights_m.dim(), (563, 484));
}

/// sur-2 rewritten in the compressed layout.
fn compressed_sur_2(stream_bytes: usize) -> Vec<u8> {
    let plain = bytes("sur-2.sur");
    let (header, points) = plain.split_at(512);
    compressed_sur(header, points, stream_bytes)
}

#[test]
fn the_compressed_layout_reads_as_the_plain_one() {
    let plain = read_bytes(&bytes("sur-2.sur"), None).unwrap();
    for stream_bytes in [usize::MAX, 300_000] {
        let file = compressed_sur_2(stream_bytes);
        assert_eq!(detect(&file[..16], None), Some(Format::Sur));
        let map = read_bytes(&file, None).unwrap();
        assert_heights_within(&map.heights_m, &plain.heights_m, 0.0);
        assert_eq!(meta(&map, "layout"), Some("zlib-compressed"));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_after_the_magic_are_an_error(
        compressed in any::<bool>(),
        tail in prop::collection::vec(any::<u8>(), 0..4096),
    ) {
        let magic: &[u8] = if compressed { b"DSCOMPRESSED" } else { b"DIGITAL SURF" };
        let file = [magic, &tail].concat();
        prop_assert!(read_bytes(&file, None).is_err());
    }

    #[test]
    fn a_truncated_file_is_an_error(len in 0usize..1_090_480) {
        let file = bytes("sur-2.sur");
        prop_assert!(read_bytes(&file[..len], None).is_err());
    }

    #[test]
    fn a_changed_header_byte_never_panics(position in 0usize..600, byte in any::<u8>()) {
        let mut file = bytes("sur-2.sur");
        file[position] = byte;
        if let Ok(map) = read_bytes(&file, None) {
            prop_assert!(map.heights_m.len() <= 563 * 484);
        }
    }

    #[test]
    fn a_changed_byte_of_the_compressed_file_never_panics(
        position in prop_oneof![0usize..700, 0usize..2_000_000],
        byte in any::<u8>(),
    ) {
        static COMPRESSED: OnceLock<Vec<u8>> = OnceLock::new();
        let mut file = COMPRESSED.get_or_init(|| compressed_sur_2(300_000)).clone();
        let position = position % file.len();
        file[position] = byte;
        if let Ok(map) = read_bytes(&file, None) {
            prop_assert!(map.heights_m.len() <= 563 * 484);
        }
    }
}
