//! Writes the benchmark's self-affine map (H = 0.8, rms 10 µm, power from
//! the map's side down to two pixels, 20 µm pixels, seed 4096) as a float64
//! `.npy`, so `benches/scipy_per_level.py` labels exactly the map that
//! `benches/truncation.rs` truncates.
//!
//! `cargo run -p hypercontact-truncation --release --example bench_map -- 2048 /tmp/map-2048.npy`

use hypercontact_core::Field;
use hypercontact_synth::surface::SelfAffine;

const PIXEL_M: f64 = 2e-5;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(2048);
    let path = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| format!("map-{n}.npy"));
    let heights = SelfAffine::whole_band(n, PIXEL_M).periodic(n, n, PIXEL_M, 4096);
    let field = Field::new(heights, PIXEL_M, PIXEL_M)?;
    field.write_npy(std::io::BufWriter::new(std::fs::File::create(&path)?))?;
    println!("wrote {path}: {n} × {n}, pixel {PIXEL_M} m, seed 4096");
    Ok(())
}
