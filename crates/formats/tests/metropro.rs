//! Zygo MetroPro `.dat`: the reference file `metropro-1.dat` (MetroPro
//! 8.1.5, 640 × 480, 1.098 µm pixels, high phase resolution) read as
//! SurfaceTopography 1.27 reads it, detection by the magic number alone, and
//! property tests: arbitrary bytes and edits of the real file never panic.

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::{assert_same_map, bytes, expected, meta};
use hypercontact_formats::{Format, detect, read_bytes};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

fn metropro_1() -> &'static [u8] {
    static FILE: OnceLock<Vec<u8>> = OnceLock::new();
    FILE.get_or_init(|| bytes("metropro-1.dat"))
}

#[test]
fn metropro_1_equals_surface_topography() {
    let file = metropro_1();
    // the magic number decides, whatever the name
    assert_eq!(detect(file, None), Some(Format::MetroPro));
    assert_eq!(
        detect(file, Some(Path::new("scan.txt"))),
        Some(Format::MetroPro)
    );
    let read = read_bytes(file, Some(Path::new("renamed.plu"))).unwrap();
    assert_eq!(read.format, Format::MetroPro);
    // integer phase counts times S·O·λ/R in f64: exact up to f64 rounding
    // (1e-12 of the range), far below one count (4e-6 of this range)
    let worst = assert_same_map(&read, &expected("metropro-1"), 1e-12);
    eprintln!("metropro-1: largest difference {worst:e} of the range");
    assert_eq!(read.position_m, None);
    assert_eq!(meta(&read, "vendor"), Some("Zygo"));
    assert_eq!(meta(&read, "software"), Some("MetroPro 8.1.5"));
    assert_eq!(meta(&read, "date_utc"), Some("2011-07-23T16:49:36Z"));
    assert_eq!(meta(&read, "objective"), Some("20X  Mirau"));
    assert_eq!(meta(&read, "serial"), Some("59407"));
    assert_eq!(meta(&read, "scan"), Some("100 um bipolar"));
}

#[test]
fn absurd_phase_maps_are_refused_before_allocation() {
    let mut file = metropro_1().to_vec();
    // phase width and height (bytes 68, 70): 65535² points > 2^26
    file[68..72].copy_from_slice(&[0xff; 4]);
    let err = read_bytes(&file, None).unwrap_err().to_string();
    assert!(
        err.contains("65535 × 65535 = 4 294 836 225 points, above the limit of 67 108 864"),
        "{err}"
    );
    // a plausible size the file does not hold: says which bytes are missing
    let mut file = metropro_1().to_vec();
    file[68..72].copy_from_slice(&[0x10, 0x00, 0x10, 0x00]);
    let err = read_bytes(&file, None).unwrap_err().to_string();
    assert!(err.contains("the phase map needs bytes 615234.."), "{err}");
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_bytes_after_the_magic_never_panic(
        magic in prop::sample::select(vec![0x881b_036fu32, 0x881b_0370, 0x881b_0371]),
        data in prop::collection::vec(any::<u8>(), 0..6000),
    ) {
        let mut file = magic.to_be_bytes().to_vec();
        file.extend(data);
        prop_assert_eq!(detect(&file, None), Some(Format::MetroPro));
        let _ = read_bytes(&file, None);
    }

    #[test]
    fn edited_metropro_1_never_panics(edits in byte_edits()) {
        let edited = splice(metropro_1().to_vec(), &edits);
        if let Ok(read) = read_bytes(&edited, None) {
            let (nx, ny) = read.heights_m.dim();
            prop_assert!(nx * ny <= 1 << 28);
            prop_assert!(read.dx_m > 0.0);
        }
    }

    #[test]
    fn truncated_metropro_1_never_panics(keep in 0usize..1_844_034) {
        prop_assert!(read_bytes(&metropro_1()[..keep], None).is_err());
    }
}
