//! The AFM formats of issue 36 on their reference files
//! (`shared/reference/topography/more/`): Bruker Nanoscope `.di`, Nanosurf
//! `.nid`, Igor `.ibw` (Asylum Research) and Molecular Imaging `.mi`. The
//! default channel equals the heights SurfaceTopography reads by default
//! (`<stem>_m.npy`); other channels are checked against the rms heights
//! SurfaceTopography's own tests record for them (`test/IO/test_ezd.py`);
//! and the files are fuzzed: truncations, byte edits and absurd headers
//! never panic and never give more points than the file holds.

use crate::common;

use std::path::Path;

use common::{assert_same_map, check_fuzzed_read, expected_more, meta, more};
use hypercontact_formats::{Channel, Format, FormatError, detect, read_bytes, read_bytes_channel};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

fn read_default(name: &str, stem: &str, format: Format) -> hypercontact_formats::Topography {
    let bytes = more(name);
    assert_eq!(detect(&bytes, None), Some(format), "{name} by its bytes");
    let map = read_bytes(&bytes, Some(Path::new("scan.txt"))).unwrap();
    assert_eq!(map.format, format);
    let worst = assert_same_map(&map, &expected_more(stem), 1e-12);
    eprintln!("{name}: largest difference {worst:e} of the range");
    map
}

/// The rms height about the mean (SurfaceTopography's `rms_height_from_area`).
fn rms_height_m(map: &hypercontact_formats::Topography) -> f64 {
    let n = map.heights_m.len() as f64;
    let mean = map.heights_m.sum() / n;
    (map.heights_m.mapv(|h| (h - mean).powi(2)).sum() / n).sqrt()
}

#[test]
fn di_1_equals_surface_topography() {
    let map = read_default("di-1.di", "di-1", Format::Nanoscope);
    assert_eq!(meta(&map, "channel"), Some("Height"));
    assert_eq!(
        meta(&map, "channels"),
        Some("0: Height; 1: Height; 2: Phase; 3: AmplitudeError")
    );
    assert_eq!(meta(&map, "instrument"), Some("Dimension V"));
    assert_eq!(meta(&map, "line_direction"), Some("Trace"));
    // each stored row is a scan line (`Samps/line`): the fast axis is x
    assert_eq!(map.fast_axis(), Some("x"));
    let bytes = more("di-1.di");
    let retrace = read_bytes_channel(&bytes, None, &Channel::Index(1)).unwrap();
    assert_eq!(meta(&retrace, "line_direction"), Some("Retrace"));
    let phase = read_bytes_channel(&bytes, None, &Channel::Name("phase".into()));
    assert!(
        matches!(phase, Err(FormatError::Unsupported { .. })),
        "{phase:?}"
    );
}

#[test]
fn nid_1_equals_surface_topography_and_its_channels_their_rms() {
    let map = read_default("nid-1.nid", "nid-1", Format::Nid);
    assert_eq!(meta(&map, "instrument"), Some("DriveAFM"));
    assert_eq!(map.fast_axis(), Some("x"));
    assert_eq!(
        meta(&map, "channels"),
        Some(
            "0: Scan forward (Z-Axis); 1: Scan forward (Z-AxisSensor); \
             2: Scan backward (Z-Axis); 3: Scan backward (Z-AxisSensor)"
        )
    );
    // SurfaceTopography's test_ezd.py, rtol 1e-6
    let bytes = more("nid-1.nid");
    for (index, rms_m) in [
        (0, 2.395896706764167e-07),
        (1, 3.026701737129839e-07),
        (2, 2.3941867686171115e-07),
        (3, 3.029781629305204e-07),
    ] {
        let channel = read_bytes_channel(&bytes, None, &Channel::Index(index)).unwrap();
        let rms = rms_height_m(&channel);
        assert!(
            ((rms - rms_m) / rms_m).abs() < 1e-6,
            "channel {index}: {rms} vs {rms_m}"
        );
    }
}

#[test]
fn ibw_equals_surface_topography() {
    let map = read_default("spot_1-1000nm.ibw", "spot_1-1000nm", Format::Ibw);
    assert_eq!(meta(&map, "channel"), Some("HeightTrace"));
    assert_eq!(meta(&map, "instrument"), Some("Cypher"));
    // the note's `ScanPoints: 256` are the wave's first dimension
    assert_eq!(map.fast_axis(), Some("x"));
    let channels = meta(&map, "channels").unwrap();
    assert_eq!(channels.split("; ").count(), 8, "{channels}");
}

#[test]
fn mi_1_equals_surface_topography() {
    let map = read_default("mi-1.mi", "mi-1", Format::Mi);
    assert_eq!(map.fast_axis(), Some("x"));
    assert_eq!(
        meta(&map, "channels"),
        Some("0: Topography; 1: Deflection; 2: Friction; 3: Friction")
    );
    let err = read_bytes_channel(&more("mi-1.mi"), None, &Channel::Index(1)).unwrap_err();
    assert!(err.to_string().contains("not a length"), "{err}");
}

const FILES: [&str; 4] = ["di-1.di", "nid-1.nid", "spot_1-1000nm.ibw", "mi-1.mi"];

fn fuzz_bytes(bytes: &[u8]) -> Result<(), TestCaseError> {
    for channel in [Channel::Default, Channel::Index(1)] {
        check_fuzzed_read(read_bytes_channel(bytes, None, &channel), bytes.len())?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(128))]

    #[test]
    fn edited_files_never_panic(which in 0usize..FILES.len(), edits in byte_edits()) {
        fuzz_bytes(&splice(more(FILES[which]), &edits))?;
    }

    #[test]
    fn truncated_files_never_panic(which in 0usize..FILES.len(), keep in 0.0f64..1.0) {
        let bytes = more(FILES[which]);
        let keep = (keep * bytes.len() as f64) as usize;
        fuzz_bytes(&bytes[..keep])?;
    }

    #[test]
    fn absurd_header_numbers_never_panic(
        which in 0usize..FILES.len(),
        at in 0usize..6000,
        number in prop_oneof![Just("4294967296"), Just("-1"), Just("0"), Just("1e300"), Just("99999999")],
    ) {
        let mut bytes = more(FILES[which]);
        // a header number replaced where a digit stands
        let at = at % bytes.len();
        if let Some(start) = bytes[at..].iter().position(u8::is_ascii_digit).map(|p| at + p) {
            let end = bytes[start..].iter().position(|b| !b.is_ascii_digit()).map_or(bytes.len(), |p| start + p);
            bytes.splice(start..end, number.bytes());
        }
        fuzz_bytes(&bytes)?;
    }
}
