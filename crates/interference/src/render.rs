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
    expose(resample(gap, placement, grid)?, grid, table, camera, seed)
}

/// The frame the camera records of gaps already on its pixels (row-major
/// `[y * width + x]`, m; NaN = the background), e.g. a resampled gap field
/// a caller has edited; its noise drawn from `seed`.
pub fn expose(
    mut gap_m: Vec<f64>,
    grid: &CameraGrid,
    table: &ReflectanceTable,
    camera: &Camera,
    seed: u64,
) -> Result<Frame, InterferenceError> {
    table.apply(&mut gap_m);
    camera.capture(&gap_m, grid.width_px, grid.height_px, seed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraParams;
    use ndarray::Array2;

    /// A sphere of radius 5 mm touching the glass: contact disc, Newton's
    /// rings around it, an unmeasured strip.
    #[test]
    fn newton_rings_frame() {
        let table = OpticsParams::default().build().unwrap();
        let (n, dx_m) = (64, 5e-6);
        let radius_m: f64 = 5e-3;
        let contact_m = 40e-6;
        let field = Array2::from_shape_fn((n, n), |(i, j)| {
            if j < 4 {
                return f64::NAN;
            }
            let x = (i as f64 - 31.5) * dx_m;
            let y = (j as f64 - 31.5) * dx_m;
            let r2 = x * x + y * y - contact_m * contact_m;
            (r2 / (2.0 * radius_m)).max(0.0)
        });
        let gap = GapMap::square(field.view(), dx_m);
        let grid = CameraGrid::square(64, dx_m);
        let params = CameraParams {
            vignetting: 0.0,
            ..CameraParams::default()
        };
        let camera = Camera::new(params, table.max_reflectance()).unwrap();
        let render = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    render_frame(&gap, &Placement::default(), &grid, &table, &camera, 9).unwrap()
                })
        };
        let frame = render(1);
        assert_eq!(frame, render(2));
        let counts_per_reflectance = 0.8 * 65535.0 / table.max_reflectance();
        let at = |x: usize, y: usize| frame.counts[y * 64 + x] as f64;
        // contact (centre) is near black, the unmeasured strip at the background
        let noise = 4.0 * (counts_per_reflectance * table.background() * params.gain()).sqrt()
            / params.gain();
        assert!(at(31, 31) < 0.01 * 65535.0, "{}", at(31, 31));
        assert!((at(31, 1) - counts_per_reflectance * table.background()).abs() < noise);
        // the first bright ring where g ≈ 131 nm: r² = c² + 2 R g
        let r_bright = (contact_m * contact_m + 2.0 * radius_m * 131e-9).sqrt();
        let x_bright = (31.5 + r_bright / dx_m).round() as usize;
        assert!(
            at(x_bright, 31) > 0.9 * 0.8 * 65535.0,
            "{}",
            at(x_bright, 31)
        );
    }
}
