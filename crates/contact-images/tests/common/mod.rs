//! What the `contact-images` stage's tests share: parameters from JSON, and
//! the stage run and read back into its tables and maps.

#![allow(dead_code)]

use hypercontact_contact_images::stage::{
    ContactImages, ContactImagesParams, ContactTable, SyncTable,
};
use hypercontact_core::{Checked, Context, Files, Inputs, Params, Product, Schema, Stage};

/// The stage's parameters from JSON; they must pass their checks.
pub fn params(json: &str) -> Checked<ContactImagesParams> {
    serde_json::from_str::<ContactImagesParams>(json)
        .unwrap()
        .check()
        .unwrap()
}

/// The stage on the `sequence` input `files`.
pub fn run(
    p: &Checked<ContactImagesParams>,
    files: Files,
) -> Result<(ContactTable, SyncTable, Files), String> {
    run_on(p, Inputs::new().with("sequence", Product::Files(files)))
}

/// The stage on `inputs` (none when the parameters name a folder): the
/// `contact` and `sync` tables and the `contact_maps` files, or the error.
pub fn run_on(
    p: &Checked<ContactImagesParams>,
    inputs: Inputs,
) -> Result<(ContactTable, SyncTable, Files), String> {
    let out = ContactImages
        .run(p, &inputs, &Context::new("contact-images"))
        .map_err(|e| e.to_string())?;
    let table = |name: &str| out.get_table(name).expect(name).clone();
    let maps = out.get_files("contact_maps").expect("contact_maps").clone();
    Ok((
        ContactTable::from_table(&table("contact")).unwrap(),
        SyncTable::from_table(&table("sync")).unwrap(),
        maps,
    ))
}
