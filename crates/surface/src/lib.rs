//! Surface stages: load a height map, or stitch, filter and characterise
//! interferometer tiles (PSD, σ, Hurst exponent).

pub mod analysis;
pub mod blend;
pub mod channel_param;
pub mod crop;
pub mod error;
pub mod filter;
pub mod form;
pub mod height_map;
pub mod hurst;
pub mod infill;
pub mod iso25178;
pub mod level_rows;
pub mod line;
pub mod mask_file;
pub mod plane;
pub mod prepare;
pub mod psd;
pub mod region;
pub mod register;
pub mod spikes;
pub mod stats;
pub mod stitch;
pub mod surface_stage;
pub mod surface_tables;
pub mod tiles;
pub mod tip_cutoff;

use hypercontact_core::Registry;

pub use error::SurfaceError;

/// Registers this crate's stage kinds.
pub fn register(registry: &mut Registry) {
    registry.add(crop::Crop);
    registry.add(height_map::HeightMap);
    registry.add(surface_stage::Surface);
}
