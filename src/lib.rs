//! hypercontact: reruns a rough-surface contact study of hyperelastic rubber
//! end to end. This library part only assembles the stage registry; the
//! stages live in `crates/`, the runner in `crates/runner`.

use hypercontact_core::Registry;

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
