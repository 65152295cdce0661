//! Writes the shipped sample height map `data/samples/self-affine-256.npy`:
//! 256 × 256 pixels of 20 µm, Hurst exponent 0.8 with power from the map's
//! side (5.12 mm) down to two pixels, rms height 10 µm, zero mean, periodic,
//! seed 256; float64, metres, axis 0 = x. The generator is
//! `hypercontact-synth`'s; its rms is an expectation, so the one realisation
//! is scaled to exactly 10 µm.
//!
//! `cargo run -p hypercontact-truncation --release --example make_sample -- data/samples/self-affine-256.npy`

use hypercontact_core::Field;
use hypercontact_synth::surface::SelfAffine;

const PIXEL_M: f64 = 2e-5;
const RMS_M: f64 = 1e-5;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/samples/self-affine-256.npy".into());
    let mut heights = SelfAffine {
        hurst: 0.8,
        rms_m: RMS_M,
        lambda_min_m: 2.0 * PIXEL_M,
        lambda_max_m: 256.0 * PIXEL_M,
    }
    .periodic(256, 256, PIXEL_M, 256);
    let rms = (heights.iter().map(|h| h * h).sum::<f64>() / heights.len() as f64).sqrt();
    heights.mapv_inplace(|h| h * RMS_M / rms);
    let field = Field::new(heights, PIXEL_M, PIXEL_M)?;
    if let Some(dir) = std::path::Path::new(&path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    field.write_npy(std::io::BufWriter::new(std::fs::File::create(&path)?))?;
    println!("wrote {path}: 256 × 256, pixel {PIXEL_M} m");
    Ok(())
}
