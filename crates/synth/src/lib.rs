//! The synthetic laboratory: stages that write the raw files a lab would
//! (interferometer tiles, ...) from a known ground truth, which they emit
//! separately so tests can score the stages that read those files.

pub mod contact;
pub mod surface;
pub mod tensile;

use hypercontact_core::Registry;

/// Registers this crate's stage kinds.
pub fn register(registry: &mut Registry) {
    registry.add(contact::SynthContact);
    registry.add(surface::SynthSurface);
    registry.add(tensile::SynthTensile);
}
