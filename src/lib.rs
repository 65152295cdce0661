//! hypercontact: reruns a rough-surface contact study of hyperelastic rubber
//! end to end. This library part assembles the stage registry and exports a
//! run's products (`export`); the stages live in `crates/`, the runner in
//! `crates/runner`.

use hypercontact_core::{DynStage, Registry};
use serde_json::{Value, json};

pub mod export;

/// Every stage kind this build knows, by the name used after `uses:`.
pub fn registry() -> Registry {
    let mut registry = Registry::new();
    hypercontact_material::register(&mut registry);
    hypercontact_surface::register(&mut registry);
    hypercontact_truncation::register(&mut registry);
    hypercontact_icm::register(&mut registry);
    hypercontact_bem::register(&mut registry);
    hypercontact_fem::register(&mut registry);
    hypercontact_classical::register(&mut registry);
    hypercontact_synth::register(&mut registry);
    hypercontact_dic::register(&mut registry);
    hypercontact_contact_images::register(&mut registry);
    hypercontact_compare::register(&mut registry);
    hypercontact_report::register(&mut registry);
    registry
}

/// A kind as `hypercontact stages --json` prints it (and the Python module
/// reads it): parameters with defaults, units and docs, inputs, outputs.
pub fn describe_json(stage: &dyn DynStage) -> Value {
    let info = stage.info();
    json!({
        "kind": info.kind,
        "version": info.version,
        "summary": info.summary,
        "doc": info.doc,
        "params": stage.params_spec(),
        "inputs": info.inputs.iter().map(|i| json!({
            "name": i.name, "kind": i.kind, "arity": i.arity, "doc": i.doc,
            "columns": i.columns,
        })).collect::<Vec<_>>(),
        "outputs": info.outputs.iter().map(|o| json!({
            "name": o.name, "kind": o.kind, "doc": o.doc, "columns": o.columns,
        })).collect::<Vec<_>>(),
        "resources": {
            "cpus": stage.resources().cpus,
            "mem_mb": stage.resources().mem_mb,
            "time_min": stage.resources().time_min,
        },
    })
}
