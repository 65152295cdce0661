//! The X3P reader on a real file: `x3p-2.x3p` (MountainsMap 6.2 export,
//! 650 × 650 float64 heights, pixels 0.128 × 0.315 µm) against the heights
//! SurfaceTopography 1.27 reads from it (`x3p-2_m.npy`, `index.json`).

use crate::common;

use std::path::Path;

use common::{assert_identical, bytes, expected, meta, stored_zip, zip_members};
use hypercontact_formats::{Format, detect, read_bytes};
use md5::{Digest, Md5};
use proptest::prelude::*;

#[test]
fn x3p_2_equals_surface_topography() {
    let map = read_bytes(&bytes("x3p-2.x3p"), Some(Path::new("x3p-2.x3p"))).unwrap();
    let expected = expected("x3p-2");

    assert_eq!(map.format, Format::X3p);
    assert_eq!(map.heights_m.dim(), (650, 650));
    assert_eq!(map.heights_m.dim(), expected.heights_m.dim());
    assert_eq!(expected.shape, (650, 650));
    let (dx, dy) = (expected.dx_m, expected.dy_m);
    assert!((map.dx_m - dx).abs() <= 1e-9 * dx, "{} vs {dx}", map.dx_m);
    assert!((map.dy_m - dy).abs() <= 1e-9 * dy, "{} vs {dy}", map.dy_m);
    // the pixels are not square: x and y must not have been swapped
    assert!(map.dy_m / map.dx_m > 2.4);

    let nan = map.heights_m.iter().filter(|h| h.is_nan()).count();
    assert_eq!(nan, expected.nan_count);
    // float64 metres with no Z increment or offset: the same numbers, bit
    // for bit (a transposed or flipped read would differ: the map is not
    // symmetric)
    assert_identical(&map.heights_m, &expected.heights_m);
    assert_ne!(expected.heights_m, expected.heights_m.t());
}

#[test]
fn x3p_2_position_and_metadata_are_what_main_xml_says() {
    let map = read_bytes(&bytes("x3p-2.x3p"), None).unwrap();
    // Record1/Axes/CX/Offset and CY/Offset
    assert_eq!(
        map.position_m,
        Some((7.65614218798151e-5, 1.29451679506934e-5))
    );
    assert_eq!(meta(&map, "instrument_manufacturer"), Some("DIGITAL SURF"));
    assert_eq!(
        meta(&map, "instrument"),
        Some("DIGITAL SURF Mountains Map Technology Software version 6.2")
    );
    assert_eq!(meta(&map, "date"), Some("1970-01-01T01:00:00"));
    assert_eq!(meta(&map, "probing_system_type"), Some("Software"));
    assert_eq!(meta(&map, "z_data_type"), Some("D (float64)"));
    // both MD5 sums the file gives (data and main.xml) match
    assert_eq!(meta(&map, "md5_point_data"), Some("verified"));
    assert_eq!(meta(&map, "md5_main_xml"), Some("verified"));
    assert_eq!(meta(&map, "comment"), None);
}

#[test]
fn x3p_is_detected_from_its_bytes_whatever_the_extension() {
    let file = bytes("x3p-2.x3p");
    assert_eq!(detect(&file[..16], None), Some(Format::X3p));
    let map = read_bytes(&file, Some(Path::new("scan.sur"))).unwrap();
    assert_eq!(map.format, Format::X3p);
    let map = read_bytes(&file, Some(Path::new("scan"))).unwrap();
    assert_eq!(map.heights_m.dim(), (650, 650));
}

/// The members of the reference archive, inflated.
fn members() -> Vec<(String, Vec<u8>)> {
    zip_members(&bytes("x3p-2.x3p"))
}

#[test]
fn a_changed_height_fails_the_md5_check() {
    // re-zipped, so the zip's own CRC is right and only the MD5 in main.xml
    // can notice
    let mut members = members();
    let data = members
        .iter_mut()
        .find(|(name, _)| name == "bindata/data.bin")
        .unwrap();
    data.1[1000] ^= 0x10;
    let message = read_bytes(&stored_zip(&members), None)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("33EE4E6B66F3CC7F84C5728FC1AE5A03"),
        "{message}"
    );
    assert!(message.contains("bindata/data.bin"), "{message}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn arbitrary_bytes_after_the_zip_magic_are_an_error(
        tail in prop::collection::vec(any::<u8>(), 0..4096)
    ) {
        let file = [b"PK\x03\x04".as_slice(), &tail].concat();
        prop_assert!(read_bytes(&file, None).is_err());
    }

    #[test]
    fn a_truncated_file_is_an_error(fraction in 0.0f64..1.0) {
        let file = bytes("x3p-2.x3p");
        let len = (fraction * file.len() as f64) as usize;
        prop_assert!(read_bytes(&file[..len], None).is_err());
    }

    #[test]
    fn a_changed_byte_never_panics(
        position in prop_oneof![0usize..2048, 0usize..3_236_186],
        byte in any::<u8>(),
    ) {
        let mut file = bytes("x3p-2.x3p");
        let position = position % file.len();
        file[position] = byte;
        if let Ok(map) = read_bytes(&file, None) {
            prop_assert_eq!(map.heights_m.dim(), (650, 650));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// main.xml with one byte changed (and its checksum file updated, so the
    /// change reaches the XML reading rather than stopping at the MD5 check).
    #[test]
    fn a_changed_main_xml_never_panics(
        position in 0usize..1726,
        // mostly digits and printable text, which keep the XML well-formed
        // and reach the reading of sizes, types and spacings
        byte in prop_oneof![3 => b'0'..=b'9', 2 => 0x20u8..0x7f, 1 => any::<u8>()],
    ) {
        let mut members = members();
        let xml = &mut members.iter_mut().find(|(name, _)| name == "main.xml").unwrap().1;
        let position = position % xml.len();
        xml[position] = byte;
        let digest: String = Md5::digest(&*xml).iter().map(|b| format!("{b:02x}")).collect();
        let checksum = &mut members
            .iter_mut()
            .find(|(name, _)| name == "md5checksum.hex")
            .unwrap()
            .1;
        *checksum = format!("{digest} *main.xml\n").into_bytes();
        if let Ok(map) = read_bytes(&stored_zip(&members), None) {
            prop_assert!(map.heights_m.len() <= 650 * 650);
        }
    }
}
