//! Sensofar `.plu`: the reference file `plu-1.plu` (PLu neox, 768 × 576,
//! 1.66 µm pixels) read as SurfaceTopography 1.27 reads it, and property
//! tests: arbitrary bytes and edits of the real file never panic.

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::{assert_same_map, bytes, expected, meta};
use hypercontact_formats::{Format, FormatError, detect, read_bytes};
use hypercontact_fuzz::{byte_edits, config, splice};
use proptest::prelude::*;

fn plu_1() -> &'static [u8] {
    static FILE: OnceLock<Vec<u8>> = OnceLock::new();
    FILE.get_or_init(|| bytes("plu-1.plu"))
}

#[test]
fn plu_1_equals_surface_topography() {
    let file = plu_1();
    let path = Path::new("plu-1.plu");
    assert_eq!(detect(file, Some(path)), Some(Format::Plu));
    let read = read_bytes(file, Some(path)).unwrap();
    assert_eq!(read.format, Format::Plu);
    // f32 µm times 1e-6 in f64, as SurfaceTopography does: the only error
    // allowed is f64 rounding (1e-12 of the range), far below the f32
    // storage step (6e-8 of a value), so a wrong scale, flip or offset fails
    let worst = assert_same_map(&read, &expected("plu-1"), 1e-12);
    eprintln!("plu-1: largest difference {worst:e} of the range");
    assert_eq!(read.position_m, None);
    assert_eq!(meta(&read, "vendor"), Some("Sensofar"));
    assert_eq!(meta(&read, "instrument"), Some("PLu neox"));
    assert_eq!(meta(&read, "date"), Some("Fri Mar 10 16:35:59 2023"));
    assert_eq!(meta(&read, "date_utc"), Some("2023-03-10T15:35:59Z"));
    assert_eq!(meta(&read, "objective_id"), Some("14"));
}

#[test]
fn plu_needs_its_extension_and_a_consistent_header() {
    let file = plu_1();
    // no magic number: the bytes alone, or under another extension, are not .plu
    assert_eq!(detect(file, None), None);
    assert_eq!(detect(file, Some(Path::new("plu-1.dat"))), None);
    assert_eq!(
        detect(file, Some(Path::new("PLU-1.PLU"))),
        Some(Format::Plu)
    );
    // .apx is the same layout (SurfaceTopography 1.27's PLUReader lists both)
    assert_eq!(
        detect(file, Some(Path::new("plu-1.apx"))),
        Some(Format::Plu)
    );
    // without its whole first layer the header is not believed
    assert_eq!(detect(&file[..16], Some(Path::new("plu-1.plu"))), None);
    // another format's bytes named .plu are refused, not misread
    let opd = bytes("opd-1.opd");
    assert_ne!(detect(&opd, Some(Path::new("x.plu"))), Some(Format::Plu));
    let sur = bytes("sur-2.sur");
    assert_eq!(
        detect(&sur[..sur.len().min(4096)], Some(Path::new("x.plu"))),
        Some(Format::Sur)
    );
    // a truncated layer makes the header inconsistent with the file length
    let cut = &file[..600_000];
    assert!(matches!(
        read_bytes(cut, Some(Path::new("x.plu"))),
        Err(FormatError::Unknown(_))
    ));
}

#[test]
fn absurd_grid_sizes_are_refused_before_allocation() {
    let mut file = plu_1().to_vec();
    // calibration rows/columns (388, 392) and the layer's (500, 504)
    for offset in [388, 392, 500, 504] {
        file[offset..offset + 4].copy_from_slice(&1_000_000_000u32.to_le_bytes());
    }
    // not plausible, so not detected; the reader itself says why (unit tests)
    assert!(read_bytes(&file, Some(Path::new("x.plu"))).is_err());
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn arbitrary_bytes_named_plu_never_panic(data in prop::collection::vec(any::<u8>(), 0..2048)) {
        let _ = read_bytes(&data, Some(Path::new("x.plu")));
    }

    #[test]
    fn edited_plu_1_never_panics(edits in byte_edits()) {
        let edited = splice(plu_1().to_vec(), &edits);
        if let Ok(read) = read_bytes(&edited, Some(Path::new("x.plu"))) {
            let (nx, ny) = read.heights_m.dim();
            prop_assert!(nx * ny <= 1 << 28);
            prop_assert!(read.dx_m > 0.0 && read.dy_m > 0.0);
        }
    }

    #[test]
    fn truncated_plu_1_never_panics(keep in 0usize..3_230_225) {
        let _ = read_bytes(&plu_1()[..keep], Some(Path::new("x.plu")));
    }
}
