//! Writes the shipped sample height map `data/samples/self-affine-256.npy`:
//! 256 × 256 pixels of 20 µm, Hurst exponent 0.8, rms height 10 µm, seed
//! 256; float64, metres, axis 0 = x.
//!
//! `cargo run -p hypercontact-truncation --release --example make_sample -- data/samples/self-affine-256.npy`

use hypercontact_core::Field;
use hypercontact_truncation::self_affine::self_affine_map;

const PIXEL_M: f64 = 2e-5;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/samples/self-affine-256.npy".into());
    let heights = self_affine_map(256, 256, PIXEL_M, 0.8, 1e-5, 256);
    let field = Field::new(heights, PIXEL_M, PIXEL_M)?;
    if let Some(dir) = std::path::Path::new(&path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    field.write_npy(std::io::BufWriter::new(std::fs::File::create(&path)?))?;
    println!("wrote {path}: 256 × 256, pixel {PIXEL_M} m");
    Ok(())
}
