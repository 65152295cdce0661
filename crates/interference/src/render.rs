//! The image-formation chain for one frame: the gap field placed on the
//! camera grid ([`crate::geometry`]), each gap's white-light reflectance
//! ([`crate::lookup`]), the sensor's counts ([`crate::camera`]).

use crate::camera::{Camera, Frame};
use crate::error::InterferenceError;
use crate::film::{Indices, Stack};
use crate::geometry::{CameraGrid, GapMap, Placement, resample};
use crate::lookup::{ReflectanceTable, TableParams};
use crate::spectrum::Spectrum;

/// Everything the reflectance table is built from (defaults: quartz, air,
/// rubber; the white LED; the default table).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OpticsParams {
    pub indices: Indices,
    pub spectrum: Spectrum,
    pub table: TableParams,
}

impl OpticsParams {
    pub fn check(&self) -> Result<(), InterferenceError> {
        self.indices.check()?;
        self.spectrum.check()?;
        self.table.check()
    }

    /// The reflectance table (built once per sequence).
    pub fn build(&self) -> Result<ReflectanceTable, InterferenceError> {
        self.check()?;
        ReflectanceTable::new(Stack::new(self.indices)?, &self.spectrum, &self.table)
    }
}

/// The frame the camera records of a gap field (NaN = not measured, seen
/// as the background), its noise drawn from `seed`.
pub fn render_frame(
    gap: &GapMap,
    placement: &Placement,
    grid: &CameraGrid,
    table: &ReflectanceTable,
    camera: &Camera,
    seed: u64,
) -> Result<Frame, InterferenceError> {
    let mut reflectance = resample(gap, placement, grid)?;
    table.apply(&mut reflectance);
    camera.capture(&reflectance, grid.width_px, grid.height_px, seed)
}
