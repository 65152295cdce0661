//! Writes the open-hole tension image set the README's "your own lab data"
//! DIC example runs on (`pipelines/lab-dic.yaml`): 16-bit TIFFs of 12-bit
//! counts without frames.csv or force.csv, and mask.png
//! (see `hypercontact_synth::tensile::open_hole`).
//!
//! cargo run -p hypercontact-synth --example open_hole_sample [-- OUT_DIR]
//! (default `data/samples/open-hole-tiff`, relative to the current folder).

use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).map_or_else(
        || PathBuf::from("data/samples/open-hole-tiff"),
        PathBuf::from,
    );
    std::fs::create_dir_all(&out)?;
    let files = hypercontact_synth::tensile::open_hole::files()?;
    for (name, bytes) in &files.files {
        std::fs::write(out.join(name), bytes)?;
    }
    println!("{} files → {}", files.files.len(), out.display());
    Ok(())
}
