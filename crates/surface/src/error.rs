//! Errors of the surface stages; each names the file, tile, column or
//! parameter a user has to look at.

use hypercontact_core::StageError;

#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    #[error("{file}: {message}")]
    Tile { file: String, message: String },
    #[error("positions file {file}, line {line}: {message}")]
    Positions {
        file: String,
        line: u64,
        message: String,
    },
    #[error("positions file {file} does not match the tiles: {message}")]
    PositionsMismatch { file: String, message: String },
    #[error(
        "{file} has shape {found:?} but {first} has {expected:?}: all tiles must have one shape"
    )]
    Shape {
        file: String,
        found: (usize, usize),
        first: String,
        expected: (usize, usize),
    },
    #[error(
        "{file} has pixel_m = {found} but {first} has {expected}: all tiles must share one spacing"
    )]
    Spacing {
        file: String,
        found: f64,
        first: String,
        expected: f64,
    },
    #[error(
        "{file} overlaps no other tile by at least {min_px} px: check its position in positions.csv"
    )]
    NoOverlap { file: String, min_px: usize },
    #[error("{file} is not connected to {first} through overlapping tiles: the mosaic falls apart")]
    Disconnected { file: String, first: String },
    #[error("{0}")]
    Input(String),
    /// An areal parameter (ISO 25178) asked of a map with too few measured
    /// points for it.
    #[error(
        "{quantity} needs at least {needed} measured points, the map has {found} of {points} \
         (the rest NaN)"
    )]
    TooFewPoints {
        /// What was asked: `the height parameters`, `Sdr`.
        quantity: &'static str,
        found: usize,
        needed: usize,
        points: usize,
    },
    /// An areal parameter (ISO 25178) asked with an argument it cannot use,
    /// or of a map it cannot use (the message says which and why).
    #[error("{quantity}: {message}")]
    Areal {
        quantity: &'static str,
        message: String,
    },
    #[error(
        "{map} has heights up to {largest_m:e} m, too large for f64: {quantity} overflows \
         (is the map in metres?)"
    )]
    Overflow {
        /// Where the map came from (an input, a folder).
        map: String,
        largest_m: f64,
        /// What overflowed: `its mean square (σ²)`, `its power spectrum`.
        quantity: &'static str,
    },
    #[error(
        "{map} is flat: its rms height after detrending is {sigma_m:e} m, rounding noise \
         against heights up to {largest_m:e} m (under {:e} of them); a constant or planar map \
         has no roughness to analyse (a fill value, or a failed export?)",
        crate::analysis::FLAT_RELATIVE
    )]
    Flat {
        /// Where the map came from (an input, a folder).
        map: String,
        sigma_m: f64,
        largest_m: f64,
    },
    #[error(
        "{map} has {missing} of {points} points missing after filtering ({:.2} %), more than \
         max_missing_fraction = {max}: its PSDs would be mostly in-fill; crop it to the measured \
         region, or raise max_missing_fraction",
        100.0 * fraction
    )]
    TooMuchMissing {
        map: String,
        fraction: f64,
        missing: usize,
        points: usize,
        max: f64,
    },
    #[error("{map}: {error}")]
    Infill {
        map: String,
        error: crate::infill::InfillError,
    },
    /// Reading a file of the tile set (the error names it).
    #[error(transparent)]
    Source(#[from] StageError),
    #[error(
        "too few PSD points ({found}) between wavelengths {lambda_min_m} m and {lambda_max_m} m \
             to fit the Hurst exponent along {direction}; widen hurst_lambda_min_m / hurst_lambda_max_m"
    )]
    HurstRange {
        direction: &'static str,
        found: usize,
        lambda_min_m: f64,
        lambda_max_m: f64,
    },
}

impl From<SurfaceError> for StageError {
    fn from(e: SurfaceError) -> Self {
        StageError::other(e)
    }
}
