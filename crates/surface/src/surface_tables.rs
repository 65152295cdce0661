//! The tables of stage `surface`, declared once: each struct is both the
//! column list the stage declares and the table it builds (the report reads
//! them from here).

use hypercontact_core::Schema;

use crate::iso25178::{ArealParameters, MaterialRatio};
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

/// Output `areal`: one row, the ISO 25178-2 areal parameters of the
/// analysed map about its mean plane (see [`crate::iso25178`]).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ArealTable {
    /// arithmetical mean height Sa = ⟨|z|⟩
    #[column(unit = "m")]
    pub sa_m: Vec<f64>,
    /// root mean square height Sq (= stats' sigma_m up to rounding)
    #[column(unit = "m")]
    pub sq_m: Vec<f64>,
    /// skewness Ssk = ⟨z³⟩/Sq³
    pub ssk: Vec<f64>,
    /// kurtosis Sku = ⟨z⁴⟩/Sq⁴ (3 for Gaussian heights)
    pub sku: Vec<f64>,
    /// maximum peak height Sp
    #[column(unit = "m")]
    pub sp_m: Vec<f64>,
    /// maximum pit depth Sv (positive)
    #[column(unit = "m")]
    pub sv_m: Vec<f64>,
    /// maximum height Sz = Sp + Sv
    #[column(unit = "m")]
    pub sz_m: Vec<f64>,
    /// root mean square gradient Sdq (forward differences, as stats' rms_slope)
    pub sdq: Vec<f64>,
    /// developed interfacial area ratio Sdr (cells with four measured corners, two triangulations averaged)
    #[column(unit = "%")]
    pub sdr_percent: Vec<f64>,
    /// autocorrelation length Sal: shortest lag at which the ACF falls to 0.2
    #[column(unit = "m")]
    pub sal_m: Vec<f64>,
    /// texture aspect ratio Str: shortest / longest decay length to 0.2 (an upper bound where a direction never decays within half the map)
    pub str: Vec<f64>,
    /// core height Sk (ISO 13565-2 equivalence line over 40 % of material ratio)
    #[column(unit = "m")]
    pub sk_m: Vec<f64>,
    /// reduced peak height Spk
    #[column(unit = "m")]
    pub spk_m: Vec<f64>,
    /// reduced valley depth Svk
    #[column(unit = "m")]
    pub svk_m: Vec<f64>,
    /// material ratio at the top of the core Smr1
    #[column(unit = "%")]
    pub smr1_percent: Vec<f64>,
    /// material ratio at the bottom of the core Smr2
    #[column(unit = "%")]
    pub smr2_percent: Vec<f64>,
    /// lag at which the radially averaged ACF falls to 1/e
    #[column(unit = "m")]
    pub correlation_length_m: Vec<f64>,
}

impl ArealTable {
    /// One row of NaN: parameters that could not be computed.
    pub fn unknown() -> Self {
        let nan = f64::NAN;
        Self::new(&ArealParameters {
            sa_m: nan,
            sq_m: nan,
            ssk: nan,
            sku: nan,
            sp_m: nan,
            sv_m: nan,
            sz_m: nan,
            sdq: nan,
            sdr_percent: nan,
            sal_m: nan,
            str: nan,
            sk_m: nan,
            spk_m: nan,
            svk_m: nan,
            smr1_percent: nan,
            smr2_percent: nan,
            correlation_length_m: nan,
        })
    }

    /// The one row of `a`.
    pub fn new(a: &ArealParameters) -> Self {
        Self {
            sa_m: vec![a.sa_m],
            sq_m: vec![a.sq_m],
            ssk: vec![a.ssk],
            sku: vec![a.sku],
            sp_m: vec![a.sp_m],
            sv_m: vec![a.sv_m],
            sz_m: vec![a.sz_m],
            sdq: vec![a.sdq],
            sdr_percent: vec![a.sdr_percent],
            sal_m: vec![a.sal_m],
            str: vec![a.str],
            sk_m: vec![a.sk_m],
            spk_m: vec![a.spk_m],
            svk_m: vec![a.svk_m],
            smr1_percent: vec![a.smr1_percent],
            smr2_percent: vec![a.smr2_percent],
            correlation_length_m: vec![a.correlation_length_m],
        }
    }
}

/// Output `material_ratio`: the Abbott–Firestone curve, heights about the
/// mean plane against the share of the area at or above them.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct MaterialRatioTable {
    /// material ratio Smr, 0 … 100 in even steps
    #[column(unit = "%")]
    pub material_ratio_percent: Vec<f64>,
    /// height Smc at that ratio, about the mean plane
    #[column(unit = "m")]
    pub height_m: Vec<f64>,
}

impl MaterialRatioTable {
    /// The curve of `ratio` at `points` even steps of material ratio.
    pub fn new(ratio: &MaterialRatio, points: usize) -> Self {
        let (material_ratio_percent, height_m) = ratio.curve(points);
        Self {
            material_ratio_percent,
            height_m,
        }
    }
}
