//! Wyko `.opd`: the reference file `opd-1.opd` (Vision, 640 × 480, 0.197 µm
//! pixels, 116 bad points) read as SurfaceTopography 1.27 reads it,
//! detection by the directory's name alone, and property tests: arbitrary
//! bytes and edits of the real file never panic.

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::{assert_same_map, bytes, expected, meta};
use hypercontact_formats::{Format, detect, read_bytes};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

fn opd_1() -> &'static [u8] {
    static FILE: OnceLock<Vec<u8>> = OnceLock::new();
    FILE.get_or_init(|| bytes("opd-1.opd"))
}

#[test]
fn opd_1_equals_surface_topography() {
    let file = opd_1();
    assert_eq!(detect(file, None), Some(Format::Opd));
    assert_eq!(detect(file, Some(Path::new("scan.dat"))), Some(Format::Opd));
    // the directory's name ends at byte 18: what `detect` says it needs
    assert_eq!(detect(&file[..18], None), Some(Format::Opd));
    assert_eq!(detect(&file[..17], None), None);
    let read = read_bytes(file, Some(Path::new("scan.dat"))).unwrap();
    assert_eq!(read.format, Format::Opd);
    // f32 values times λ/Mult in f64, in SurfaceTopography's order: f64
    // rounding only (1e-12 of the range), far below the f32 step (6e-8)
    let worst = assert_same_map(&read, &expected("opd-1"), 1e-12);
    eprintln!("opd-1: largest difference {worst:e} of the range");
    assert_eq!(read.position_m, None);
    assert_eq!(meta(&read, "vendor"), Some("Wyko"));
    assert_eq!(meta(&read, "array"), Some("Raw"));
    assert_eq!(meta(&read, "date"), Some("7/7/2015 16:19:48"));
    let wavelength_nm: f64 = meta(&read, "wavelength_nm").unwrap().parse().unwrap();
    assert!((wavelength_nm - 577.295).abs() < 1e-3, "{wavelength_nm}");
    let magnification: f64 = meta(&read, "magnification").unwrap().parse().unwrap();
    assert!((magnification - 50.322).abs() < 1e-3, "{magnification}");
}

/// #31, 15: a negative length on the "Raw" array's directory entry was
/// told "no height array"; the block and its length are named now.
#[test]
fn a_height_array_of_negative_length_is_named() {
    let mut file = opd_1().to_vec();
    // directory entries are 24 bytes from byte 2: a 16-byte name, an i16
    // type, an i32 length
    let entry = (2..file.len().min(24_000))
        .step_by(24)
        .find(|&at| file[at..at + 16].starts_with(b"Raw\0"))
        .expect("opd-1 has a Raw entry");
    file[entry + 18..entry + 22].copy_from_slice(&(-5i32).to_le_bytes());
    let err = read_bytes(&file, None).unwrap_err().to_string();
    assert_eq!(
        err,
        format!(
            "Wyko .opd: the height array block \"Raw\" (directory entry at byte {entry}) has \
             the length -5: it holds no heights"
        )
    );
}

#[test]
fn absurd_arrays_are_refused_before_allocation() {
    // the "Raw" array's width and height (u16 at byte 24020): 65535² points
    let mut file = opd_1().to_vec();
    file[24020..24024].copy_from_slice(&[0xff; 4]);
    let err = read_bytes(&file, None).unwrap_err().to_string();
    assert!(err.contains("array \"Raw\" at byte 24020"), "{err}");
    assert!(
        err.contains("65535 × 65535 = 4 294 836 225 points, above the limit of 67 108 864"),
        "{err}"
    );
    // a directory longer than the file
    let mut file = opd_1().to_vec();
    file[20..24].copy_from_slice(&0x7fff_fff8i32.to_le_bytes());
    let err = read_bytes(&file, None).unwrap_err().to_string();
    assert!(err.contains("the directory needs bytes 2.."), "{err}");
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_bytes_after_the_directory_name_never_panic(
        data in prop::collection::vec(any::<u8>(), 0..6000),
    ) {
        let mut file = b"\x01\x00Directory\0\0\0\0\0\0\0".to_vec();
        file.extend(data);
        prop_assert_eq!(detect(&file, None), Some(Format::Opd));
        let _ = read_bytes(&file, None);
    }

    #[test]
    fn edited_opd_1_never_panics(edits in byte_edits()) {
        let edited = splice(opd_1().to_vec(), &edits);
        if let Ok(read) = read_bytes(&edited, None) {
            let (nx, ny) = read.heights_m.dim();
            prop_assert!(nx * ny <= 1 << 28);
            prop_assert!(read.dx_m > 0.0 && read.dy_m > 0.0);
        }
    }

    #[test]
    fn truncated_opd_1_never_panics(keep in 0usize..4_020_870) {
        let _ = read_bytes(&opd_1()[..keep], None);
    }
}
