//! One-shot timing of `synth-contact` at the paper's scale (too long for
//! criterion's samples): a T1-like sample (9 mm square at 20 µm: 454²,
//! H = 0.65, rms 15 µm), 30 frames to A/A0 = 0.9, each solved by boundary
//! elements and drawn onto a 2048² 16-bit camera, PNG-encoded, with the
//! force log and the truth. The target: under a minute on 2 cores.
//!
//! Run: `cargo bench -p hypercontact-synth --bench contact`
//! (`RAYON_NUM_THREADS=1` for one thread).

use std::time::Instant;

use hypercontact_core::{Context, Field, Inputs, Params, Product, Stage};
use hypercontact_synth::contact::{SynthContact, SynthContactParams};
use hypercontact_synth::surface::SelfAffine;

fn main() {
    let n = 454;
    let values = SelfAffine::T1_LIKE.non_periodic(n, n, 20e-6, 101);
    let surface = Field::new(values, 20e-6, 20e-6).unwrap();
    let material = hypercontact_material::presets::preset("paper-epdm").unwrap();
    let inputs = Inputs::new().with("surface", Product::Field(surface)).with(
        "material",
        Product::Table(hypercontact_material::table::to_table(material.as_ref())),
    );
    let p = SynthContactParams::default().check().unwrap();
    let threads = rayon::current_num_threads();
    let start = Instant::now();
    let out = SynthContact
        .run(&p, &inputs, &Context::new("synth-contact"))
        .unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let bytes: usize = match out.get("sequence") {
        Some(Product::Files(f)) => f.files.values().map(Vec::len).sum(),
        _ => 0,
    };
    println!(
        "synth-contact {n}² solve grid, 30 frames of 2048², {threads} thread(s): {seconds:.2} s \
         ({:.0} MB of frames)",
        bytes as f64 / 1e6
    );
}
