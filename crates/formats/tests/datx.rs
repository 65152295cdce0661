//! Zygo `.datx` (HDF5): two small files built with h5py (no real `.datx`
//! was available; `data/make_datx.py` says how and why), each read as
//! SurfaceTopography 1.27 reads it: vlen strings, gzip-chunked f64 heights
//! in nm with a No Data value (datx-1), fixed-length strings, contiguous f32
//! heights in µm with NaN gaps (datx-2); non-square pixels in both. And
//! property tests: arbitrary bytes after the HDF5 signature and edits of the
//! files never panic.

use crate::common;

use std::path::Path;

use common::{assert_same_map, data, expected_data, meta};
use hypercontact_formats::{Format, FormatError, Topography, detect, read_bytes};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

fn read(file: &str) -> Topography {
    let bytes = data(file);
    // the HDF5 signature decides, whatever the name
    assert_eq!(detect(&bytes, None), Some(Format::Datx));
    assert_eq!(
        detect(&bytes, Some(Path::new("scan.dat"))),
        Some(Format::Datx)
    );
    read_bytes(&bytes, Some(Path::new("scan.dat"))).unwrap()
}

#[test]
fn datx_1_vlen_strings_gzip_f64_nanometres() {
    let read = read("datx-1.datx");
    assert_eq!(read.format, Format::Datx);
    // f64 nm times 1e-9: f64 rounding only
    let worst = assert_same_map(&read, &expected_data("datx-1"), 1e-12);
    eprintln!("datx-1: largest difference {worst:e} of the range");
    // missing points where the file has No Data, at (x, y) = (column, row)
    for (x, y) in [(0, 0), (7, 3), (16, 12), (2, 6), (11, 9)] {
        assert!(read.heights_m[[x, y]].is_nan(), "({x}, {y})");
    }
    assert_eq!((read.dx_m, read.dy_m), (0.8e-6, 1.25e-6));
    assert_eq!(meta(&read, "instrument"), Some("NewView 9000"));
    assert_eq!(meta(&read, "serial"), Some("12345678"));
    assert_eq!(meta(&read, "unit"), Some("NanoMeters"));
}

#[test]
fn datx_2_fixed_strings_contiguous_f32_micrometres() {
    let read = read("datx-2.datx");
    // f32 µm widened to f64, then times 1e-6, as SurfaceTopography does:
    // f64 rounding only, far below the f32 storage step (6e-8 of a value)
    let worst = assert_same_map(&read, &expected_data("datx-2"), 1e-12);
    eprintln!("datx-2: largest difference {worst:e} of the range");
    assert_eq!(meta(&read, "instrument"), Some("NewView 9000"));
    assert_eq!(meta(&read, "unit"), Some("MicroMeters"));
}

#[test]
fn without_metadata_the_first_surface_dataset_is_read() {
    // prysm's convention: the heights are the first dataset in /Data/Surface
    let mut bytes = data("datx-2.datx");
    let at = bytes
        .windows(8)
        .position(|w| w == b"MetaData")
        .expect("the name MetaData in the file");
    bytes[at..at + 8].copy_from_slice(b"NotMData");
    let read = read_bytes(&bytes, None).unwrap();
    assert_same_map(&read, &expected_data("datx-2"), 1e-12);
}

#[test]
fn other_hdf5_files_and_fringes_are_refused_with_advice() {
    let plain = data("plain.h5");
    assert_eq!(detect(&plain, None), Some(Format::Datx));
    let err = read_bytes(&plain, None).unwrap_err();
    assert!(err.to_string().contains("not a Zygo .datx file"), "{err}");
    let err = read_bytes(b"\x89HDF\r\n\x1a\n", None).unwrap_err();
    assert!(matches!(err, FormatError::Invalid { .. }), "{err}");
    // heights in fringes (Unit and the Z Converter's unit, fixed strings)
    let mut bytes = data("datx-2.datx");
    let mut edited = 0;
    while let Some(at) = bytes.windows(11).position(|w| w == b"MicroMeters") {
        bytes[at..at + 11].copy_from_slice(b"Fringes\0\0\0\0");
        edited += 1;
    }
    assert_eq!(edited, 2);
    let err = read_bytes(&bytes, None).unwrap_err();
    assert!(matches!(err, FormatError::Unsupported { .. }), "{err}");
    let message = err.to_string();
    assert!(message.contains("heights in \"Fringes\""), "{message}");
    assert!(
        message.contains("export the measurement from Mx as X3P or .sur"),
        "{message}"
    );
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_bytes_after_the_signature_never_panic(
        tail in prop::collection::vec(any::<u8>(), 0..4096),
    ) {
        let mut bytes = b"\x89HDF\r\n\x1a\n".to_vec();
        bytes.extend(tail);
        let _ = read_bytes(&bytes, None);
    }

    #[test]
    fn edited_datx_never_panics(second in any::<bool>(), edits in byte_edits()) {
        let file = if second { "datx-2.datx" } else { "datx-1.datx" };
        let edited = splice(data(file), &edits);
        if let Ok(read) = read_bytes(&edited, None) {
            let (nx, ny) = read.heights_m.dim();
            prop_assert!(nx * ny <= 1 << 28);
            prop_assert!(read.dx_m > 0.0 && read.dy_m > 0.0);
        }
    }

    #[test]
    fn truncated_datx_never_panics(second in any::<bool>(), keep in 0usize..16_000) {
        let file = data(if second { "datx-2.datx" } else { "datx-1.datx" });
        let _ = read_bytes(&file[..keep.min(file.len())], None);
    }
}
