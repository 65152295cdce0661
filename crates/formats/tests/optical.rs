//! The optical instruments' formats of issue 36 on their reference files
//! (`shared/reference/topography/more/`): Alicona `.al3d`, FRT `.frt`,
//! Digital Surf `.mnt` and TrueMap `.tmd`, each read as SurfaceTopography
//! reads it (`<stem>_m.npy`, `index.json`), told by its bytes whatever the
//! name, and fuzzed: truncations, byte edits and absurd headers never panic
//! and never give more points than the file holds.

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::{assert_same_map, expected_more, meta, more};
use hypercontact_formats::{Channel, Format, detect, read_bytes, read_bytes_channel};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

/// The reference files read so far, kept for the property tests' cases.
type Loaded = std::sync::Mutex<Vec<(&'static str, &'static [u8])>>;

fn file(name: &'static str) -> &'static [u8] {
    static FILES: OnceLock<Loaded> = OnceLock::new();
    let files = FILES.get_or_init(Default::default);
    let mut files = files.lock().unwrap();
    if let Some((_, bytes)) = files.iter().find(|(n, _)| *n == name) {
        return bytes;
    }
    let bytes: &'static [u8] = Box::leak(more(name).into_boxed_slice());
    files.push((name, bytes));
    bytes
}

/// Reads `name` (detected from its bytes under a wrong name) and compares
/// it with its reference; returns the map.
fn equals_reference(
    name: &'static str,
    stem: &str,
    format: Format,
) -> hypercontact_formats::Topography {
    let bytes = file(name);
    assert_eq!(detect(bytes, None), Some(format), "{name} by its bytes");
    let map = read_bytes(bytes, Some(Path::new("scan.x3p"))).unwrap();
    assert_eq!(map.format, format);
    let worst = assert_same_map(&map, &expected_more(stem), 1e-12);
    eprintln!("{name}: largest difference {worst:e} of the range");
    map
}

#[test]
fn al3d_1_equals_surface_topography() {
    let map = equals_reference("al3d-1.al3d", "al3d-1", Format::Al3d);
    assert_eq!(meta(&map, "vendor"), Some("Alicona Imaging"));
    assert_eq!(
        meta(&map, "creatingapplication"),
        Some("MeasureSuite 5.3.6")
    );
    assert_eq!(meta(&map, "channels"), Some("0: Default"));
}

#[test]
fn frt_1_equals_surface_topography() {
    let map = equals_reference("frt-1.frt", "frt-1", Format::Frt);
    assert_eq!(meta(&map, "serial"), Some("SN_1036"));
    // the measurement's start, 1678463840 s: index.json's acquisition_time
    assert_eq!(meta(&map, "date"), Some("2023-03-10T15:57:20Z"));
}

#[test]
fn mnt_1_equals_surface_topography() {
    let map = equals_reference("mnt-1.mnt", "mnt-1", Format::Mnt);
    // the X and Y records' offsets, 10.3595 mm and 156.152 mm
    let (x_m, y_m) = map.position_m.unwrap();
    assert!((x_m - 10.3595e-3).abs() < 1e-12 && (y_m - 156.152e-3).abs() < 1e-12);
    // a compound file without ScopedContents is named as such
    let mut other = file("mnt-1.mnt").to_vec();
    let name: Vec<u8> = "ScopedContents"
        .encode_utf16()
        .flat_map(u16::to_le_bytes)
        .collect();
    let places: Vec<usize> = other
        .windows(name.len())
        .enumerate()
        .filter(|(_, w)| *w == name.as_slice())
        .map(|(at, _)| at)
        .collect();
    assert!(!places.is_empty());
    for at in places {
        other[at] = b'X';
    }
    let err = read_bytes(&other, None).unwrap_err().to_string();
    assert!(err.contains("no stream \"ScopedContents\""), "{err}");
}

#[test]
fn tmd_1_equals_surface_topography_in_millimetres() {
    let map = equals_reference("tmd-1.tmd", "tmd-1", Format::Tmd);
    assert_eq!(meta(&map, "comment"), Some("Created by TrueMap v6"));
    // the one channel by index or name, and a wrong name listed
    let bytes = file("tmd-1.tmd");
    assert!(read_bytes_channel(bytes, None, &Channel::Index(0)).is_ok());
    let err = read_bytes_channel(bytes, None, &Channel::Name("Height".into()))
        .unwrap_err()
        .to_string();
    assert!(err.contains("1 channel: 0: Default"), "{err}");
}

/// The fuzz cases of one file: edits never panic, a read map is no larger
/// than the original and has positive spacings.
fn fuzz(name: &'static str, edits: &[(usize, usize, Vec<u8>)]) -> Result<(), TestCaseError> {
    let original = file(name);
    let edited = splice(original.to_vec(), edits);
    if let Ok(map) = read_bytes(&edited, Some(Path::new(name))) {
        let (nx, ny) = map.heights_m.dim();
        prop_assert!(nx * ny <= 1 << 28);
        prop_assert!(map.dx_m > 0.0 && map.dy_m > 0.0);
    }
    Ok(())
}

const FILES: [&str; 4] = ["al3d-1.al3d", "tmd-1.tmd", "frt-1.frt", "mnt-1.mnt"];

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn edited_files_never_panic(which in 0usize..FILES.len(), edits in byte_edits()) {
        fuzz(FILES[which], &edits)?;
    }

    #[test]
    fn truncated_files_never_panic(which in 0usize..FILES.len(), keep in 0.0f64..1.0) {
        let bytes = file(FILES[which]);
        let keep = (keep * bytes.len() as f64) as usize;
        // a file cut after its heights (an al3d's texture image follows them) may still read
        fuzz_bytes(&bytes[..keep])?;
    }

    #[test]
    fn edited_headers_never_panic(
        which in 0usize..FILES.len(),
        at in 0usize..1024,
        value in prop_oneof![Just(u32::MAX), Just(0u32), any::<u32>()],
    ) {
        let mut bytes = file(FILES[which]).to_vec();
        let at = at.min(bytes.len() - 4);
        bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
        fuzz_bytes(&bytes)?;
    }
}

/// An edited file that still reads has no more points than its bytes hold
/// (4 bytes a point and more; an .mnt's zlib blocks: the points limit).
fn fuzz_bytes(bytes: &[u8]) -> Result<(), TestCaseError> {
    if let Ok(map) = read_bytes(bytes, None) {
        let (nx, ny) = map.heights_m.dim();
        if map.format == Format::Mnt {
            prop_assert!(nx * ny <= 1 << 28);
        } else {
            prop_assert!(nx * ny * 2 <= bytes.len());
        }
    }
    Ok(())
}
