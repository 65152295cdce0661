//! Writes the sample tensile data the default pipeline starts from:
//! `paper-epdm` (the paper's Table 1) in UT to λ = 2.5, PT to 2.0 and BT to
//! 1.4, 50 points each, with 0.5 % multiplicative Gaussian noise from a
//! fixed seed.
//!
//! cargo run -p hypercontact-material --example tensile_sample [-- OUT.csv]
//! (default `data/tensile/epdm.csv`, relative to the current folder).

use std::path::PathBuf;

use hypercontact_material::sample::{SAMPLE_NOISE, SAMPLE_SEED, paper_sample, to_csv};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("data/tensile/epdm.csv"), PathBuf::from);
    let data = paper_sample();
    let comment = format!(
        "synthetic: paper-epdm (Table 1, 6-term Ogden) with {} % multiplicative Gaussian noise, \
         ChaCha8 seed {SAMPLE_SEED}; written by `cargo run -p hypercontact-material --example \
         tensile_sample`",
        100.0 * SAMPLE_NOISE
    );
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(&out, to_csv(&data, &comment))?;
    println!(
        "{} points ({}) → {}",
        data.n_points(),
        data.counts(),
        out.display()
    );
    Ok(())
}
