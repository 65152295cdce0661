//! Runs the `synth-surface` stage on a sample recipe (default: the paper's
//! T1, `data/samples/T1.yaml`) exactly as the pipeline does, and prints its
//! wall time, the process's peak resident memory (VmHWM) and a BLAKE3 hash
//! of every product, so a change to the generator can be checked for
//! memory (issue #35) and for the same bits:
//!
//! `cargo run -p hypercontact-synth --release --example synth_surface_peak [-- RECIPE.yaml]`
//!
//! The tiles are hashed as the .npy bytes the stage hands over, the truth as
//! the .npy bytes of its field, the truth table as its Debug text (f64's
//! Debug form round-trips, so equal text means equal bits).

use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use hypercontact_core::{Context, Inputs, Params, Product, Stage};
use hypercontact_synth::surface::{SynthSurface, SynthSurfaceParams};

type Failure = Box<dyn std::error::Error>;

fn peak_rss() -> String {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM"))
                .map(str::to_owned)
        })
        .unwrap_or_else(|| "VmHWM: unknown".into())
}

/// The flat `key: value  # comment` lines of a sample recipe as a JSON
/// object (every value of the shipped recipes is a JSON number), so the
/// example needs no YAML reader.
fn recipe(path: &PathBuf) -> Result<SynthSurfaceParams, Failure> {
    let text = std::fs::read_to_string(path)?;
    let mut object = serde_json::Map::new();
    for line in text.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        if let Some((key, value)) = line.split_once(':') {
            let value: serde_json::Value = serde_json::from_str(value.trim())
                .map_err(|e| format!("{}: {key}: {e}", path.display()))?;
            object.insert(key.trim().to_owned(), value);
        }
    }
    Ok(serde_json::from_value(serde_json::Value::Object(object))?)
}

fn main() -> Result<(), Failure> {
    let path = std::env::args().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/samples/T1.yaml"),
        PathBuf::from,
    );
    let params = recipe(&path)?.check()?;
    let start = Instant::now();
    let outputs = SynthSurface.run(&params, &Inputs::new(), &Context::new("synth-surface"))?;
    println!(
        "{}: synth-surface in {:.2} s; {}",
        path.display(),
        start.elapsed().as_secs_f64(),
        peak_rss()
    );
    let mut hashes = BTreeMap::new();
    for (name, product) in outputs.iter() {
        let mut hasher = blake3::Hasher::new();
        match product {
            Product::Files(files) => {
                for (file, bytes) in &files.files {
                    let mut one = blake3::Hasher::new();
                    one.write_all(bytes)?;
                    hasher.write_all(file.as_bytes())?;
                    hasher.write_all(one.finalize().as_bytes())?;
                }
            }
            Product::Field(field) => field.write_npy(&mut hasher)?,
            Product::Table(table) => hasher.write_all(format!("{table:?}").as_bytes())?,
        }
        hashes.insert(name.to_owned(), hasher.finalize());
    }
    let mut all = blake3::Hasher::new();
    for (name, hash) in &hashes {
        println!("  {name}: {hash}");
        all.write_all(hash.as_bytes())?;
    }
    println!("  all products: {}", all.finalize());
    Ok(())
}
