//! Runs the `surface` stage on the tiles of a sample recipe (default: the
//! paper's T1, `data/samples/T1.yaml`) exactly as pipelines/paper.yaml does
//! (`resolution_m: 20e-6`, every other parameter at its default), and prints
//! its wall time, the memory the stage adds (peak resident memory during
//! the stage minus the resident memory before it) and a BLAKE3 hash of
//! every product, so a change to the stage can be checked for memory
//! (issue #35) and for the same bits:
//!
//! `cargo run -p hypercontact-surface --release --example surface_peak [-- RECIPE.yaml [TILE_DIR]]`
//!
//! The tiles come from `synth-surface` (its `tiles` product). With TILE_DIR
//! they are written there on the first run and read back on later ones, so
//! the stage is measured in a process that never generated a surface (the
//! allocator keeps none of the generator's freed memory to hand back).
//! The peak is the kernel's VmHWM, reset just before the stage through
//! /proc/self/clear_refs. Fields are hashed by their values' bits, tables by
//! each column's name and bits (strings by their bytes and length).

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use hypercontact_core::{ColumnData, Context, Files, Inputs, Params, Product, Stage};
use hypercontact_surface::surface_stage::{Surface, SurfaceParams};
use hypercontact_synth::surface::{SynthSurface, SynthSurfaceParams};

type Failure = Box<dyn std::error::Error>;

/// A line of /proc/self/status in GiB (`VmHWM`, `VmRSS`).
fn status_gib(key: &str) -> Result<f64, Failure> {
    let status = std::fs::read_to_string("/proc/self/status")?;
    let line = status
        .lines()
        .find(|l| l.starts_with(key))
        .ok_or_else(|| format!("no {key} in /proc/self/status"))?;
    let kib: f64 = line
        .trim_start_matches(key)
        .trim_start_matches(':')
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()?;
    Ok(kib / (1024.0 * 1024.0))
}

/// The flat `key: value  # comment` lines of a sample recipe as a JSON
/// object (every value of the shipped recipes is a JSON number).
fn recipe(path: &Path) -> Result<SynthSurfaceParams, Failure> {
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

/// The recipe's `tiles` product: generated, or read from `dir` when an
/// earlier run wrote it there.
fn tiles(recipe_path: &Path, dir: Option<&Path>) -> Result<Files, Failure> {
    if let Some(dir) = dir.filter(|d| d.join("positions.csv").exists()) {
        let mut files = Files::new();
        for entry in std::fs::read_dir(dir)? {
            let path = entry?.path();
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
            files = files.with(&name.ok_or("a file without a name")?, std::fs::read(&path)?);
        }
        return Ok(files);
    }
    let params = recipe(recipe_path)?.check()?;
    let start = Instant::now();
    let mut outputs = SynthSurface
        .run(&params, &Inputs::new(), &Context::new("synth-surface"))?
        .into_inner();
    println!("synth-surface in {:.2} s", start.elapsed().as_secs_f64());
    let Some(Product::Files(files)) = outputs.remove("tiles") else {
        return Err("synth-surface gave no `tiles` files".into());
    };
    if let Some(dir) = dir {
        std::fs::create_dir_all(dir)?;
        for (name, bytes) in &files.files {
            std::fs::write(dir.join(name), bytes)?;
        }
    }
    Ok(files)
}

/// The BLAKE3 hash of a product's bits.
fn product_hash(product: &Product) -> blake3::Hash {
    let mut hasher = blake3::Hasher::new();
    match product {
        Product::Field(field) => {
            hasher.update(&(field.nx() as u64).to_le_bytes());
            hasher.update(&(field.ny() as u64).to_le_bytes());
            for v in [field.dx_m, field.dy_m].iter().chain(field.values.iter()) {
                hasher.update(&v.to_bits().to_le_bytes());
            }
        }
        Product::Table(table) => {
            for column in table.columns() {
                hasher.update(column.name.as_bytes());
                match &column.data {
                    ColumnData::F64(v) => v.iter().for_each(|x| {
                        hasher.update(&x.to_bits().to_le_bytes());
                    }),
                    ColumnData::I64(v) => v.iter().for_each(|x| {
                        hasher.update(&x.to_le_bytes());
                    }),
                    ColumnData::Str(v) => v.iter().for_each(|s| {
                        hasher.update(&(s.len() as u64).to_le_bytes());
                        hasher.update(s.as_bytes());
                    }),
                }
            }
        }
        Product::Files(files) => {
            for (name, bytes) in &files.files {
                hasher.update(name.as_bytes());
                hasher.update(blake3::hash(bytes).as_bytes());
            }
        }
    }
    hasher.finalize()
}

fn main() -> Result<(), Failure> {
    let mut args = std::env::args().skip(1);
    let recipe_path = args.next().map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/samples/T1.yaml"),
        PathBuf::from,
    );
    let tile_dir = args.next().map(PathBuf::from);
    let files = tiles(&recipe_path, tile_dir.as_deref())?;
    let inputs = Inputs::new().with("tiles", Product::Files(files));
    let params: SurfaceParams = serde_json::from_str(r#"{ "resolution_m": 20.0e-6 }"#)?;
    let params = params.check()?;

    // 5: reset the peak (VmHWM) to the present resident set.
    std::fs::write("/proc/self/clear_refs", "5")?;
    let before_gib = status_gib("VmRSS")?;
    let start = Instant::now();
    let outputs = Surface.run(&params, &inputs, &Context::new("surface"))?;
    let seconds = start.elapsed().as_secs_f64();
    let peak_gib = status_gib("VmHWM")?;
    println!(
        "{}: surface in {seconds:.2} s; RSS before {before_gib:.3} GiB, peak during \
         {peak_gib:.3} GiB: the stage adds {:.3} GiB",
        recipe_path.display(),
        peak_gib - before_gib
    );
    let hashes: BTreeMap<&str, blake3::Hash> = outputs
        .iter()
        .map(|(name, product)| (name, product_hash(product)))
        .collect();
    let mut all = blake3::Hasher::new();
    for (name, hash) in &hashes {
        println!("  {name}: {hash}");
        all.write_all(hash.as_bytes())?;
    }
    println!("  all products: {}", all.finalize());
    Ok(())
}
