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
//! 57.29925741943928 nm from the file itself.

use std::path::{Path, PathBuf};

use hypercontact_core::Field;
use hypercontact_surface::tip_cutoff::tip_reliability_cutoff_m;

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
