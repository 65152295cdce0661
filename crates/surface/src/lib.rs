//! Surface stages: load a height map, or stitch, filter and characterise
//! interferometer tiles.

pub mod height_map;

use hypercontact_core::Registry;

/// Registers this crate's stage kinds.
pub fn register(registry: &mut Registry) {
    registry.add(height_map::HeightMap);
}
