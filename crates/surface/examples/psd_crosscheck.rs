//! Writes a 512 × 512 non-periodic map (a crop of a periodic synthetic
//! surface) as raw little-endian f64 (row-major, axis 0 = x) and our binned
//! PSDs as CSV, for comparison with SurfaceTopography
//! (`power_spectrum_from_profile`, `power_spectrum_from_area`).
//!
//! Run: `cargo run -p hypercontact-surface --release --example psd_crosscheck -- OUT_DIR`

use std::fmt::Write as _;
use std::path::PathBuf;

use hypercontact_surface::psd::{Spectrum, Window, psd_radial, psd_x, psd_y};
use hypercontact_synth::surface::SelfAffine;

fn main() -> std::io::Result<()> {
    let out_dir = PathBuf::from(std::env::args().nth(1).expect("argument: output directory"));
    let (n, pixel_m) = (512, 1e-6);
    let h = SelfAffine {
        lambda_max_m: 2e-4,
        ..SelfAffine::MICRON
    }
    .non_periodic(n, n, pixel_m, 9);
    let bytes: Vec<u8> = h.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(out_dir.join("map_512.f64"), bytes)?;
    let mut csv = String::from("case,q_per_m,c\n");
    let mut add = |case: &str, s: Spectrum| {
        for (q, c) in s.q_per_m.iter().zip(&s.c) {
            writeln!(csv, "{case},{q:.17e},{c:.17e}").unwrap();
        }
    };
    for (name, window) in [("hann", Window::Hann), ("periodic", Window::None)] {
        add(&format!("x_{name}"), psd_x(&h, pixel_m, window, 10));
        add(&format!("y_{name}"), psd_y(&h, pixel_m, window, 10));
        add(
            &format!("radial_{name}"),
            psd_radial(&h, pixel_m, pixel_m, window, 10),
        );
    }
    std::fs::write(out_dir.join("ours_512.csv"), csv)
}
