//! Shared helpers: synthetic sequences through the real stages.

#![allow(dead_code)]

use hypercontact_core::{Context, Files, Inputs, Product, Stage, Table};
use hypercontact_dic::{Dic, DicParams};
use hypercontact_synth::tensile::{SynthTensile, SynthTensileParams};

/// Runs `synth-tensile`, returning its files and truth table.
pub fn synth(params: &SynthTensileParams) -> (Files, Table) {
    use hypercontact_core::Params;
    let params = params.clone().check().unwrap();
    let out = SynthTensile
        .run(&params, &Inputs::new(), &Context::new("synth"))
        .unwrap();
    let Some(Product::Files(files)) = out.get("sequence") else {
        panic!("no sequence")
    };
    let Some(Product::Table(truth)) = out.get("truth") else {
        panic!("no truth")
    };
    (files.clone(), truth.clone())
}

/// A small sequence, quick to correlate: 3 frames of 160 × 160 px to a
/// stretch of 1.1, speckles only.
pub fn small_sequence() -> Files {
    synth(&SynthTensileParams {
        frames: 3,
        max_stretch: Some(1.1),
        width_px: 160,
        height_px: 160,
        supersample: 1,
        markers: false,
        ..Default::default()
    })
    .0
}

/// Runs `dic` on a sequence.
pub fn dic(files: &Files, params: &DicParams) -> Result<Table, hypercontact_core::StageError> {
    use hypercontact_core::Params;
    let params = params.clone().check().unwrap();
    let inputs = Inputs::new().with("sequence", Product::Files(files.clone()));
    let out = Dic.run(&params, &inputs, &Context::new("dic"))?;
    let Some(Product::Table(t)) = out.get("tensile") else {
        panic!("no tensile table")
    };
    Ok(t.clone())
}
