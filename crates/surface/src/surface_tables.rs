//! The tables of stage `surface`, declared once: each struct is both the
//! column list the stage declares and the table it builds (the report reads
//! them from here).

use hypercontact_core::Schema;

use crate::psd::Spectrum;
use crate::stitch::TileFit;
use crate::tiles::TileSet;

/// Output `psd`: the binned PSDs along x, y and radially, one after another.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct PsdTable {
    /// x, y or radial
    pub direction: Vec<String>,
    /// wavevector, mean of the bin's members
    #[column(unit = "rad/m")]
    pub q_per_m: Vec<f64>,
    /// PSD, mean of the bin's members
    #[column(unit = "m³ (x, y) or m⁴ (radial)")]
    pub c: Vec<f64>,
}

impl PsdTable {
    /// Appends the bins of one spectrum under `direction`.
    pub fn push(&mut self, direction: &str, spectrum: &Spectrum) {
        let bins = spectrum.c.len();
        self.direction
            .extend(std::iter::repeat_n(direction.to_owned(), bins));
        self.q_per_m.extend_from_slice(&spectrum.q_per_m);
        self.c.extend_from_slice(&spectrum.c);
    }
}

/// Output `stats`: one row.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct StatsTable {
    /// areal rms height Sq after detrending
    #[column(unit = "m")]
    pub sigma_m: Vec<f64>,
    /// rms gradient √⟨|∇h|²⟩
    pub rms_slope: Vec<f64>,
    /// Hurst exponent from the PSD along x
    pub hurst_x: Vec<f64>,
    /// Hurst exponent from the PSD along y
    pub hurst_y: Vec<f64>,
    /// Hurst exponent from the radial PSD
    pub hurst_radial: Vec<f64>,
    /// R² of the Hurst fit along x (ln C on ln q)
    pub hurst_x_r2: Vec<f64>,
    /// smallest q of the PSD bins the fit along x used
    #[column(unit = "rad/m")]
    pub hurst_x_q_min_per_m: Vec<f64>,
    /// largest q of the PSD bins the fit along x used
    #[column(unit = "rad/m")]
    pub hurst_x_q_max_per_m: Vec<f64>,
    /// ok, outside 0…1, or poor power law (R² < 0.9)
    pub hurst_x_flag: Vec<String>,
    /// R² of the Hurst fit along y (ln C on ln q)
    pub hurst_y_r2: Vec<f64>,
    /// smallest q of the PSD bins the fit along y used
    #[column(unit = "rad/m")]
    pub hurst_y_q_min_per_m: Vec<f64>,
    /// largest q of the PSD bins the fit along y used
    #[column(unit = "rad/m")]
    pub hurst_y_q_max_per_m: Vec<f64>,
    /// ok, outside 0…1, or poor power law (R² < 0.9)
    pub hurst_y_flag: Vec<String>,
    /// R² of the Hurst fit along radial (ln C on ln q)
    pub hurst_radial_r2: Vec<f64>,
    /// smallest q of the PSD bins the fit along radial used
    #[column(unit = "rad/m")]
    pub hurst_radial_q_min_per_m: Vec<f64>,
    /// largest q of the PSD bins the fit along radial used
    #[column(unit = "rad/m")]
    pub hurst_radial_q_max_per_m: Vec<f64>,
    /// ok, outside 0…1, or poor power law (R² < 0.9)
    pub hurst_radial_flag: Vec<String>,
    /// points along x of the analysed (filtered) map
    pub nx: Vec<i64>,
    /// points along y of the analysed (filtered) map
    pub ny: Vec<i64>,
    /// grid spacing along x of the analysed (filtered) map
    #[column(unit = "m")]
    pub dx_m: Vec<f64>,
    /// grid spacing along y of the analysed (filtered) map
    #[column(unit = "m")]
    pub dy_m: Vec<f64>,
    /// points along x of the map before filtering (as measured or stitched)
    pub nx_measured: Vec<i64>,
    /// points along y before filtering
    pub ny_measured: Vec<i64>,
    /// grid spacing along x before filtering
    #[column(unit = "m")]
    pub dx_measured_m: Vec<f64>,
    /// grid spacing along y before filtering
    #[column(unit = "m")]
    pub dy_measured_m: Vec<f64>,
    /// share of unmeasured points in `height`
    pub nan_fraction: Vec<f64>,
    /// how missing points were filled before the PSDs: harmonic or zero
    pub fill: Vec<String>,
    /// missing points filled before the PSDs
    pub filled_points: Vec<i64>,
    /// filled_points over all points of the analysed grid
    pub filled_fraction: Vec<f64>,
}

/// Output `stitch`: one row per tile (none for a map from input `height`).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct StitchTable {
    /// the tile column of positions.csv
    pub tile: Vec<i64>,
    /// tile file
    pub file: Vec<String>,
    /// recorded position of pixel [0, 0], x
    #[column(unit = "px")]
    pub x_nominal_px: Vec<f64>,
    /// recorded position of pixel [0, 0], y
    #[column(unit = "px")]
    pub y_nominal_px: Vec<f64>,
    /// position found by stitching, x
    #[column(unit = "px")]
    pub x_found_px: Vec<f64>,
    /// position found by stitching, y
    #[column(unit = "px")]
    pub y_found_px: Vec<f64>,
    /// found minus nominal, x
    #[column(unit = "px")]
    pub x_offset_px: Vec<f64>,
    /// found minus nominal, y
    #[column(unit = "px")]
    pub y_offset_px: Vec<f64>,
    /// slope removed along x (about the tile centre)
    #[column(unit = "rad")]
    pub tilt_x_rad: Vec<f64>,
    /// slope removed along y
    #[column(unit = "rad")]
    pub tilt_y_rad: Vec<f64>,
    /// height removed at the tile centre
    #[column(unit = "m")]
    pub piston_m: Vec<f64>,
    /// mean Pearson correlation of its aligned overlaps
    pub overlap_correlation: Vec<f64>,
    /// overlaps of this tile dropped as outliers (registered offset > 0.5 px from the joint solution)
    pub pairs_rejected: Vec<i64>,
}

impl StitchTable {
    /// One row per tile of the set, from the stitching's fits (in set order).
    pub fn new(set: &TileSet, fits: &[TileFit]) -> Self {
        let column = |f: fn(&TileFit) -> f64| fits.iter().map(f).collect();
        StitchTable {
            tile: set.ids.clone(),
            file: set.names.clone(),
            x_nominal_px: column(|t| t.nominal_px[0]),
            y_nominal_px: column(|t| t.nominal_px[1]),
            x_found_px: column(|t| t.found_px[0]),
            y_found_px: column(|t| t.found_px[1]),
            x_offset_px: column(|t| t.found_px[0] - t.nominal_px[0]),
            y_offset_px: column(|t| t.found_px[1] - t.nominal_px[1]),
            tilt_x_rad: column(|t| t.tilt_rad[0]),
            tilt_y_rad: column(|t| t.tilt_rad[1]),
            piston_m: column(|t| t.piston_m),
            overlap_correlation: column(|t| t.correlation),
            pairs_rejected: fits.iter().map(|t| t.pairs_rejected as i64).collect(),
        }
    }
}
