//! The text and NetCDF formats of issue 36 on their reference files
//! (`shared/reference/topography/more/`): an ASCII matrix with a SPIP-style
//! header (`matrix-2.txt`), Gwyddion's ASCII export, a Dektak profile
//! (`dektak-1.csv`) and a NetCDF classic file (`nc-1.nc`), each read as
//! SurfaceTopography reads it, and fuzzed: truncations and edits never
//! panic and never give more points than the file holds.

use crate::common;

use std::path::Path;

use common::{assert_same_map, check_fuzzed_read, expected_more, meta, more};
use hypercontact_formats::{Channel, Format, detect, read_bytes, read_bytes_channel};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

fn read_as(name: &str, format: Format) -> hypercontact_formats::Topography {
    let bytes = more(name);
    assert_eq!(
        detect(&bytes, Some(Path::new(name))),
        Some(format),
        "{name}"
    );
    read_bytes(&bytes, Some(Path::new(name))).unwrap()
}

#[test]
fn matrix_2_equals_surface_topography() {
    // a .txt without a magic: told by its name and its rows of numbers
    let map = read_as("matrix-2.txt", Format::AsciiMatrix);
    assert_eq!(
        detect(&more("matrix-2.txt"), None),
        Some(Format::AsciiMatrix)
    );
    // value × 6.30079e-8 m, one multiplication as in SurfaceTopography
    let worst = assert_same_map(&map, &expected_more("matrix-2"), 0.0);
    eprintln!("matrix-2: largest difference {worst:e} of the range");
}

#[test]
fn gwyddion_export_equals_surface_topography() {
    let map = read_as("gwyddion-export-english.txt", Format::AsciiMatrix);
    assert_same_map(&map, &expected_more("gwyddion-export-english"), 1e-12);
    assert_eq!(meta(&map, "channel"), Some("My Channel Name"));
    let by_name = read_bytes_channel(
        &more("gwyddion-export-english.txt"),
        None,
        &Channel::Name("my channel name".into()),
    )
    .unwrap();
    assert_eq!(by_name, map);
}

#[test]
fn dektak_1_heights_equal_surface_topography_and_the_spacing_is_the_fit() {
    let map = read_as("dektak-1.csv", Format::DektakCsv);
    let expected = expected_more("dektak-1");
    assert_eq!(map.heights_m.dim(), (9600, 1));
    assert!(map.is_line_scan());
    assert_eq!(map.meta("line_scan"), Some("true"));
    // Raw Micrometer × 1e-6: the same single multiplication, bit for bit
    common::assert_identical(&map.heights_m, &expected.heights_m);
    // the spacing: 1500 µm over 9600 points (the header's Length) to 3e-8;
    // the index's dx_m is the positions' range 1499.8 µm over 9600 points
    let length_m = 1500e-6 / 9600.0;
    assert!(
        ((map.dx_m - length_m) / length_m).abs() < 3e-8,
        "{}",
        map.dx_m
    );
    assert!((expected.dx_m - 1499.8e-6 / 9600.0).abs() < 1e-12 * expected.dx_m);
    assert_eq!(map.dy_m, map.dx_m);
    assert_eq!(meta(&map, "stylus"), Some("Radius: 2.5 µm"));
}

#[test]
fn nc_1_equals_surface_topography() {
    let map = read_as("nc-1.nc", Format::NetCdf);
    assert!(!map.is_line_scan());
    assert_same_map(&map, &expected_more("nc-1"), 0.0);
    assert_eq!(meta(&map, "unit"), Some("nm"));
}

#[test]
fn unknown_text_names_what_it_found() {
    let err = read_bytes(b"hello, world\n", Some(Path::new("notes.md")))
        .unwrap_err()
        .to_string();
    // Named as text by its first bytes, its contents never echoed (#50).
    assert!(
        err.contains("text (first bytes 68 65 6c 6c 6f 2c 20 77)") && !err.contains("hello"),
        "{err}"
    );
    assert!(
        err.contains("Dektak .csv") && err.contains("Igor .ibw"),
        "{err}"
    );
}

const FILES: [&str; 4] = [
    "matrix-2.txt",
    "gwyddion-export-english.txt",
    "dektak-1.csv",
    "nc-1.nc",
];

fn fuzz_bytes(bytes: &[u8], name: &str) -> Result<(), TestCaseError> {
    check_fuzzed_read(read_bytes(bytes, Some(Path::new(name))), bytes.len())
}

proptest! {
    #![proptest_config(config(128))]

    #[test]
    fn edited_files_never_panic(which in 0usize..FILES.len(), edits in byte_edits()) {
        let edited = splice(more(FILES[which]), &edits);
        fuzz_bytes(&edited, FILES[which])?;
    }

    #[test]
    fn truncated_files_never_panic(which in 0usize..FILES.len(), keep in 0.0f64..1.0) {
        let bytes = more(FILES[which]);
        let keep = (keep * bytes.len() as f64) as usize;
        fuzz_bytes(&bytes[..keep], FILES[which])?;
    }

    #[test]
    fn arbitrary_text_never_panics(text in "[ -~\n\r#:=µ]{0,400}") {
        for name in ["a.txt", "a.csv", "a.nc"] {
            fuzz_bytes(text.as_bytes(), name)?;
        }
        let mut csv = b"Scan Parameters\n".to_vec();
        csv.extend(text.as_bytes());
        fuzz_bytes(&csv, "a.csv")?;
    }
}
