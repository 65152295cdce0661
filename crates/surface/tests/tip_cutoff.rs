//! The tip's short-wavelength reliability cut-off (#53, part 2) on a real
//! AFM map against SurfaceTopography's own.
//!
//! Provenance of the reference numbers (a throwaway script, not kept):
//! SurfaceTopography 1.27.1 (PyPI), numpy 2.4.6, scipy 1.17.1, Python
//! 3.11.7 (`/work/venv`). The heights of `di-1.di` (Bruker Dimension V,
//! 512 × 512 at 0.9765625 nm) as SurfaceTopography reads them,
//! `shared/reference/topography/more/di-1_m.npy`, were made a
//! `Topography(h, (512 Δx, 512 Δy), periodic=False, unit='m',
//! info={'instrument': {'parameters': {'tip_radius': {'value': R, 'unit':
//! 'm'}}}})` and `short_reliability_cutoff()` asked (the same as
//! `scanning_probe_reliability_cutoff(R)`, default safety factor 1/2):
//! R = 10 nm → 3.147028439258052e-08 m, 20 nm → 5.729925741943928e-08 m,
//! 50 nm → 1.020759821647152e-07 m. `open_topography('di-1.di')
//! .topography(channel_index=0, info=… tip_radius 20 nm)` gives the same
//! 57.29925741943928 nm from the file itself (the `height-map` test
//! reads that file).

use std::path::{Path, PathBuf};

use hypercontact_core::Field;
use hypercontact_surface::tip_cutoff::tip_reliability_cutoff_m;
use serde_json::json;

use crate::common::height_map;

/// SurfaceTopography 1.27.1's cut-offs of di-1 (metres) by tip radius (m).
pub const SURFACE_TOPOGRAPHY_DI_1: [(f64, f64); 3] = [
    (10e-9, 3.147028439258052e-08),
    (20e-9, 5.729925741943928e-08),
    (50e-9, 1.020759821647152e-07),
];

/// A file of the shared reference folder (beside the repository).
fn shared_reference(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference/topography/more")
        .join(name);
    assert!(
        path.exists(),
        "{} is missing: clone the repository beside shared/",
        path.display()
    );
    path
}

/// The heights SurfaceTopography reads from di-1.di, at its spacing.
fn di_1() -> Field {
    let path = shared_reference("di-1_m.npy");
    let bytes = std::fs::metadata(&path).unwrap().len();
    let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    Field::read_npy_file(file, bytes, 9.765625e-10, 9.765625e-10, 1 << 20).unwrap()
}

// The bar is 2 %; the same convention and root search agree far
// closer (the root search's own tolerance is 1e-8).
#[test]
fn the_cut_off_of_an_afm_map_is_surface_topographys() {
    let map = di_1();
    for (radius_m, reference_m) in SURFACE_TOPOGRAPHY_DI_1 {
        let cutoff_m = tip_reliability_cutoff_m(&map, radius_m).unwrap().unwrap();
        let off = cutoff_m / reference_m - 1.0;
        eprintln!(
            "R = {radius_m:e} m: {cutoff_m:e} m, SurfaceTopography {reference_m:e} m ({off:+.2e})"
        );
        assert!(
            off.abs() < 0.02,
            "R = {radius_m}: {cutoff_m} vs {reference_m}"
        );
        assert!(
            off.abs() < 1e-6,
            "R = {radius_m}: {cutoff_m} vs {reference_m}"
        );
    }
    // A 1 nm tip is sharper than anything the 0.98 nm grid shows:
    // SurfaceTopography gives None as well.
    assert_eq!(tip_reliability_cutoff_m(&map, 1e-9), Ok(None));
}

/// The Bruker file itself, of the repository's reference folder.
fn di_1_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/reference/topography/more/di-1.di")
}

// The stage reads the instrument's file and carries SurfaceTopography's
// cut-off with the field, in a note too; without a tip, nothing.
#[test]
fn height_map_carries_the_tips_cut_off_with_the_field() {
    let (radius_m, reference_m) = SURFACE_TOPOGRAPHY_DI_1[1];
    let (map, notes) = height_map(&di_1_file(), json!({ "tip_radius_m": radius_m })).unwrap();
    let cutoff_m = map.short_cutoff_m.expect("a cut-off");
    assert!((cutoff_m / reference_m - 1.0).abs() < 0.02, "{cutoff_m}");
    assert!((cutoff_m / reference_m - 1.0).abs() < 1e-6, "{cutoff_m}");
    let note = notes.last().unwrap();
    assert!(
        note.starts_with("tip: R = 20.0000 nm: reliable above λ_c = 57.2993 nm"),
        "{notes:?}"
    );
    let grid = String::from_utf8(map.grid_json()).unwrap();
    assert!(grid.contains("\"short_cutoff_m\": 5.72992574194"), "{grid}");

    let (sharp, notes) = height_map(&di_1_file(), json!({ "tip_radius_m": 1e-9 })).unwrap();
    assert_eq!(sharp.short_cutoff_m, None);
    assert!(
        notes
            .last()
            .unwrap()
            .contains("resolves every scale of the grid")
            && notes.last().unwrap().contains("1.9531 nm"),
        "{notes:?}"
    );
    let (plain, notes) = height_map(&di_1_file(), json!({})).unwrap();
    assert_eq!(plain.short_cutoff_m, None);
    assert!(!notes.iter().any(|n| n.starts_with("tip")), "{notes:?}");
    assert!(
        !String::from_utf8(plain.grid_json())
            .unwrap()
            .contains("short_cutoff_m")
    );
}

// Errors name the parameter: a radius that is not positive is refused
// before any work; a window too short for a stencil, when the cut-off is
// asked.
#[test]
fn a_bad_tip_radius_or_a_too_small_map_names_tip_radius_m() {
    for bad in [json!(0.0), json!(-2e-8), json!("20 nm")] {
        let e = height_map(&di_1_file(), json!({ "tip_radius_m": bad })).unwrap_err();
        assert!(e.starts_with("tip_radius_m:"), "{bad}: {e}");
    }
    let e = height_map(
        &di_1_file(),
        json!({ "tip_radius_m": 2e-8, "crop_points": [0, 0, 4, 64] }),
    )
    .unwrap_err();
    assert!(e.contains("tip_radius_m: the map is 4 × 64 points"), "{e}");
}
