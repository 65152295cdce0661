//! The `surface` stage's analysis of a stitched map: the ISO 16610-61
//! Gaussian filter to the lateral resolution, detrending, the checks that
//! the map holds roughness, the in-fill of missing points before the FFT,
//! the PSDs along x, y and radially (SurfaceTopography's conventions), the
//! Hurst exponents fitted to them (C ∝ q^(−1−2H) along a profile,
//! q^(−2−2H) radially) and the statistics table.

use std::f64::consts::TAU;

use hypercontact_core::field::FieldError;
use hypercontact_core::{Checked, Context, Field, StageError};
use ndarray::Array2;
use rayon::prelude::*;

use crate::error::SurfaceError;
use crate::filter::{self, Grid, MapRows};
use crate::hurst::{Dimension, Flag, PowerLaw, R2_MIN, fit_power_law};
use crate::infill::{fill_harmonic, fill_zero};
use crate::line::{LineAxis, analyse_line};
use crate::plane;
use crate::psd::{Spectrum, Window, psd_radial, psd_x, psd_y};
use crate::stats::{Reference, reference_height, rms_slope, sigma};
use crate::surface_stage::{Detrend, Fill, ReferenceKind, SurfaceParams};
use crate::surface_tables::{
    AcfTable, ArealTable, DistributionsTable, MaterialRatioTable, PsdTable, ScaleDependentTable,
    StatsTable,
};

/// Everything the stage computes from a stitched map at its measured grid.
pub struct Analysis {
    pub height: Field,
    pub psd: PsdTable,
    pub stats: StatsTable,
    pub areal: ArealTable,
    pub material_ratio: MaterialRatioTable,
    pub distributions: DistributionsTable,
    pub acf: AcfTable,
    pub scale_dependent: ScaleDependentTable,
}

/// Points of the `material_ratio` output: every whole per cent.
pub const MATERIAL_RATIO_POINTS: usize = 101;

/// An rms height after detrending below this fraction of the largest
/// |height| is the detrending's rounding noise, not roughness: a flat map.
/// Real maps sit orders of magnitude above it (1 nm of roughness on a 1 m
/// offset still passes).
pub const FLAT_RELATIVE: f64 = 1e-9;

/// A measured map as the analysis takes it: held whole, or read a row at a
/// time (a stitched mosaic, or a map borrowed from an input), which the
/// filter reads a band at a time so the map is never held whole (#35).
pub enum MeasuredMap<'m> {
    Whole(Field),
    Rows {
        rows: &'m dyn MapRows,
        dx_m: f64,
        dy_m: f64,
    },
}

impl MeasuredMap<'_> {
    /// The map's grid, refused as [`Field::new`] refuses it.
    fn grid(&self) -> Result<Grid, StageError> {
        let (nx, ny, dx_m, dy_m) = match self {
            MeasuredMap::Whole(map) => (map.nx(), map.ny(), map.dx_m, map.dy_m),
            MeasuredMap::Rows { rows, dx_m, dy_m } => {
                let (nx, ny) = rows.dim();
                (nx, ny, *dx_m, *dy_m)
            }
        };
        if !(dx_m > 0.0 && dx_m.is_finite() && dy_m > 0.0 && dy_m.is_finite()) {
            return Err(StageError::other(FieldError::BadSpacing { dx_m, dy_m }));
        }
        if nx == 0 || ny == 0 {
            return Err(StageError::other(FieldError::Empty { nx, ny }));
        }
        Ok(Grid { nx, ny, dx_m, dy_m })
    }

    /// The map held whole.
    pub(crate) fn into_field(self) -> Result<Field, StageError> {
        match self {
            MeasuredMap::Whole(map) => Ok(map),
            MeasuredMap::Rows { rows, dx_m, dy_m } => {
                let (nx, ny) = rows.dim();
                let mut values = Array2::<f64>::zeros((nx, ny));
                values
                    .as_slice_mut()
                    .expect("a fresh array is contiguous")
                    .par_chunks_mut(ny.max(1))
                    .enumerate()
                    .for_each(|(x, row)| rows.write_row(x, row));
                Field::new(values, dx_m, dy_m).map_err(StageError::other)
            }
        }
    }
}

/// Filter, detrend, reference, PSDs, statistics and Hurst exponents.
pub fn analyse(
    map: Field,
    p: &Checked<SurfaceParams>,
    ctx: &Context,
) -> Result<Analysis, StageError> {
    analyse_named(map, "the height map", p, ctx)
}

/// [`analyse`], with `source` (where the map came from) naming the map in
/// errors about it.
pub fn analyse_named(
    map: Field,
    source: &str,
    p: &Checked<SurfaceParams>,
    ctx: &Context,
) -> Result<Analysis, StageError> {
    analyse_measured(MeasuredMap::Whole(map), source, p, ctx)
}

/// [`analyse_named`] of a map held whole or read a row at a time.
pub fn analyse_measured(
    map: MeasuredMap,
    source: &str,
    p: &Checked<SurfaceParams>,
    ctx: &Context,
) -> Result<Analysis, StageError> {
    let measured = map.grid()?;
    if let Some(axis) = LineAxis::of(measured.nx, measured.ny) {
        return analyse_line(map.into_field()?, axis, source, p, ctx);
    }
    let progress = ctx.progress(3, "filter, PSD");
    let filtered = filtered(map, &measured, p, ctx)?;
    progress.inc(1);
    let grid = grid_of(&filtered);
    let (nan_count, nan_fraction) = missing_share(&filtered.values, p.resolution_m)?;
    let mut h = filtered.values;
    let (dx_m, dy_m) = (grid.dx_m, grid.dy_m);
    let largest_m = h
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    // A plane fitted to a periodic map removes a sawtooth that is not part
    // of it: power leaks into every q along the tilt's direction and the
    // fitted Hurst exponent falls (0.70 → 0.66 on a 1024² map). Periodic
    // maps only lose their mean.
    detrend(&mut h, if p.periodic { Detrend::Mean } else { p.detrend })?;
    let (sigma_m, slope) = roughness(&h, (dx_m, dy_m), largest_m, source)?;
    let areal = areal_tables(&h, (dx_m, dy_m), ctx);
    let distributions = distributions_table(&h, (dx_m, dy_m), p.histogram_bins, ctx);
    let scale_dependent = ScaleDependentTable::new(&h, dx_m, dy_m).unwrap_or_else(|e| {
        ctx.note(&format!(
            "warning: no scale-dependent statistics (table `scale_dependent` empty): {e}"
        ));
        ScaleDependentTable::default()
    });
    if nan_fraction > p.max_missing_fraction {
        return Err(SurfaceError::TooMuchMissing {
            map: source.to_owned(),
            fraction: nan_fraction,
            missing: nan_count,
            points: h.len(),
            max: p.max_missing_fraction,
        }
        .into());
    }
    let spectra = spectra(&h, (dx_m, dy_m), (nan_count, nan_fraction), source, p, ctx)?;
    // Inf in a spectrum would be dropped by the Hurst fit, which would
    // then blame its wavelength range.
    if spectra.iter().any(|s| s.c.iter().any(|c| !c.is_finite())) {
        return Err(overflow(source, largest_m, "its power spectrum").into());
    }
    progress.inc(1);
    let fits = hurst_fits(&spectra, &grid, p, ctx)?;

    let reference = match p.reference {
        ReferenceKind::Lowest => Reference::Lowest,
        ReferenceKind::Percentile => Reference::Percentile(p.reference_percent),
    };
    let z0 = reference_height(&h, reference);
    h.mapv_inplace(|v| v - z0);

    let mut psd = PsdTable::default();
    for (direction, spectrum) in DIRECTIONS.iter().zip(&spectra) {
        psd.push(direction.0, spectrum);
    }
    let stats = stats_table(
        (sigma_m, slope),
        &fits,
        (&grid, &measured),
        (nan_count, nan_fraction),
        p.fill,
    );
    progress.inc(1);
    Ok(Analysis {
        height: Field::new(h, dx_m, dy_m).map_err(StageError::other)?,
        psd,
        stats,
        areal: areal.areal,
        material_ratio: areal.material_ratio,
        distributions,
        acf: areal.acf,
        scale_dependent,
    })
}

/// The tables read off the areal autocorrelation and the sorted heights.
struct ArealTables {
    areal: ArealTable,
    material_ratio: MaterialRatioTable,
    acf: AcfTable,
}

/// The ISO 25178-2 parameters about the mean plane of the detrended map
/// (before the height reference moves it), its material-ratio curve and
/// its autocorrelation. A map whose heights pass σ but whose fourth powers
/// overflow (Sku; heights beyond ~1e77 m, a map in the wrong unit) gets NaN
/// parameters, no curve, no ACF and a warning, rather than losing the PSDs
/// the stage can still give.
fn areal_tables(h: &Array2<f64>, (dx_m, dy_m): (f64, f64), ctx: &Context) -> ArealTables {
    match crate::iso25178::areal_parameters_curve_and_acf(h, dx_m, dy_m) {
        Ok((areal, ratio, acf)) => ArealTables {
            areal: ArealTable::new(&areal),
            material_ratio: MaterialRatioTable::new(&ratio, MATERIAL_RATIO_POINTS),
            acf: AcfTable::new(&acf),
        },
        Err(e) => {
            ctx.note(&format!(
                "warning: no ISO 25178 parameters (table `areal` is NaN, `material_ratio` and \
                 `acf` empty): {e}"
            ));
            ArealTables {
                areal: ArealTable::unknown(),
                material_ratio: MaterialRatioTable::default(),
                acf: AcfTable::default(),
            }
        }
    }
}

/// The height, slope and curvature histograms of the detrended map in
/// `bins` bins; a quantity that cannot be had is left out with a warning.
fn distributions_table(
    h: &Array2<f64>,
    (dx_m, dy_m): (f64, f64),
    bins: usize,
    ctx: &Context,
) -> DistributionsTable {
    let mut table = DistributionsTable::default();
    let warn = |what: &str, e: SurfaceError| {
        ctx.note(&format!("warning: no {what} in table `distributions`: {e}"));
    };
    match crate::iso25178::height_histogram(h, bins) {
        Ok(heights) => table.push("height", "m", &heights),
        Err(e) => warn("height histogram", e),
    }
    match crate::iso25178::slope_and_curvature_histograms(h, dx_m, dy_m, bins) {
        Ok((slope, curvature)) => {
            table.push("slope", "1", &slope);
            table.push("curvature", "1/m", &curvature);
        }
        Err(e) => warn("slope and curvature histograms", e),
    }
    table
}

/// The PSD directions, in the order of the tables, with the dimension of
/// their Hurst fit.
const DIRECTIONS: [(&str, Dimension); 3] = [
    ("x", Dimension::Profile),
    ("y", Dimension::Profile),
    ("radial", Dimension::Areal),
];

pub(crate) fn grid_of(map: &Field) -> Grid {
    Grid {
        nx: map.nx(),
        ny: map.ny(),
        dx_m: map.dx_m,
        dy_m: map.dy_m,
    }
}

/// The map low-pass filtered and resampled to `resolution_m` (with notes on
/// the grids), or as it is when that is not coarser than its grid.
pub(crate) fn filtered(
    map: MeasuredMap,
    measured: &Grid,
    p: &SurfaceParams,
    ctx: &Context,
) -> Result<Field, StageError> {
    let (dx_m, dy_m) = (measured.dx_m, measured.dy_m);
    if p.resolution_m > dx_m.max(dy_m) * (1.0 + 1e-9) {
        let values = match &map {
            MeasuredMap::Whole(map) => {
                filter::gaussian_resample(&map.values, dx_m, dy_m, p.resolution_m)
            }
            MeasuredMap::Rows { rows, .. } => {
                filter::gaussian_resample_rows(*rows, dx_m, dy_m, p.resolution_m)
            }
        };
        drop(map);
        let filtered =
            Field::new(values, p.resolution_m, p.resolution_m).map_err(StageError::other)?;
        for note in filter::filter_notes(measured, &grid_of(&filtered), p.resolution_m) {
            ctx.note(&note);
        }
        Ok(filtered)
    } else {
        if p.resolution_m > 0.0 {
            ctx.note(&format!(
                "resolution_m = {} m is not coarser than the grid ({} m): map kept as measured",
                p.resolution_m, dx_m
            ));
        }
        map.into_field()
    }
}

/// The number and share of missing (NaN) points of the filtered map; an
/// error when it is too small for PSDs or has no point at all.
fn missing_share(h: &Array2<f64>, resolution_m: f64) -> Result<(usize, f64), SurfaceError> {
    let (nx, ny) = h.dim();
    if nx < 8 || ny < 8 {
        return Err(SurfaceError::Input(format!(
            "the filtered map has only {nx} × {ny} points: lower resolution_m ({resolution_m} m) or measure a larger area"
        )));
    }
    let nan_count = h.iter().filter(|v| v.is_nan()).count();
    if nan_count == h.len() {
        return Err(SurfaceError::Input("every point of the map is NaN".into()));
    }
    Ok((nan_count, nan_count as f64 / h.len() as f64))
}

/// σ and the rms slope of the detrended map; an error when either
/// overflows or when σ is rounding noise against the largest |height|.
pub(crate) fn roughness(
    h: &Array2<f64>,
    (dx_m, dy_m): (f64, f64),
    largest_m: f64,
    source: &str,
) -> Result<(f64, f64), SurfaceError> {
    let sigma_m = sigma(h);
    let slope = rms_slope(h, dx_m, dy_m);
    if !(largest_m.is_finite() && sigma_m.is_finite()) {
        return Err(overflow(source, largest_m, "its mean square (σ²)"));
    }
    if !slope.is_finite() {
        return Err(overflow(source, largest_m, "its mean square slope"));
    }
    if sigma_m.is_nan() || sigma_m <= FLAT_RELATIVE * largest_m {
        return Err(SurfaceError::Flat {
            map: source.to_owned(),
            sigma_m,
            largest_m,
        });
    }
    Ok((sigma_m, slope))
}

/// The map named `source`, heights up to `largest_m`, overflows f64 in
/// `quantity`.
pub(crate) fn overflow(source: &str, largest_m: f64, quantity: &'static str) -> SurfaceError {
    SurfaceError::Overflow {
        map: source.to_owned(),
        largest_m,
        quantity,
    }
}

/// Removes a least-squares plane or the mean of the measured points.
pub(crate) fn detrend(h: &mut Array2<f64>, detrend: Detrend) -> Result<(), SurfaceError> {
    match detrend {
        Detrend::Plane => {
            let fit = plane::fit_plane(h).ok_or_else(|| {
                SurfaceError::Input("too few measured points to fit a plane".into())
            })?;
            plane::subtract(h, &fit);
        }
        Detrend::Mean => {
            let valid = h.iter().filter(|v| !v.is_nan());
            let mean = valid.clone().sum::<f64>() / valid.count() as f64;
            h.mapv_inplace(|v| v - mean);
        }
    }
    Ok(())
}

/// The x, y and radial PSDs of the detrended map, its `nan_count` missing
/// points filled as `fill` says (with a note when there were any).
fn spectra(
    h: &Array2<f64>,
    (dx_m, dy_m): (f64, f64),
    (nan_count, nan_fraction): (usize, f64),
    source: &str,
    p: &SurfaceParams,
    ctx: &Context,
) -> Result<[Spectrum; 3], StageError> {
    let mut filled = h.clone();
    match p.fill {
        Fill::Harmonic => {
            fill_harmonic(&mut filled, dx_m, dy_m, p.periodic).map_err(|error| {
                SurfaceError::Infill {
                    map: source.to_owned(),
                    error,
                }
            })?;
        }
        Fill::Zero => {
            fill_zero(&mut filled);
        }
    }
    if nan_count > 0 {
        let (nx, ny) = h.dim();
        ctx.note(&format!(
            "{nan_count} missing points ({:.3} % of {nx} × {ny}) filled {} before the PSDs",
            100.0 * nan_fraction,
            match p.fill {
                Fill::Harmonic => "harmonically (Laplace)",
                Fill::Zero => "with the mean height",
            }
        ));
    }
    let window = if p.periodic {
        Window::None
    } else {
        Window::Hann
    };
    let per_decade = p.bins_per_decade;
    Ok([
        psd_x(&filled, dx_m, window, per_decade),
        psd_y(&filled, dy_m, window, per_decade),
        psd_radial(&filled, dx_m, dy_m, window, per_decade),
    ])
}

/// The Hurst fit of each spectrum, with the notes on their ranges first
/// and the warnings on flagged fits after.
fn hurst_fits(
    spectra: &[Spectrum; 3],
    grid: &Grid,
    p: &SurfaceParams,
    ctx: &Context,
) -> Result<[PowerLaw; 3], SurfaceError> {
    let (dx_m, dy_m) = (grid.dx_m, grid.dy_m);
    let (lx, ly) = (grid.nx as f64 * dx_m, grid.ny as f64 * dy_m);
    let [sx, sy, sr] = spectra;
    let fits = [
        hurst(sx, "x", (dx_m, lx), p)?,
        hurst(sy, "y", (dy_m, ly), p)?,
        hurst(sr, "radial", (dx_m.max(dy_m), lx.min(ly)), p)?,
    ];
    for note in fits.iter().filter_map(|f| f.1.as_deref()) {
        ctx.note(note);
    }
    let fits = fits.map(|f| f.0);
    for ((direction, dimension), fit) in DIRECTIONS.iter().zip(&fits) {
        if let Some(warning) = hurst_warning(direction, fit, *dimension) {
            ctx.note(&warning);
        }
    }
    Ok(fits)
}

/// The `stats` row: σ and slope, the three Hurst fits, the filtered and
/// measured grids, and what was filled.
pub(crate) fn stats_table(
    (sigma_m, slope): (f64, f64),
    fits: &[PowerLaw; 3],
    (filtered, measured): (&Grid, &Grid),
    (nan_count, nan_fraction): (usize, f64),
    fill: Fill,
) -> StatsTable {
    let [hurst_x, hurst_y, hurst_radial] = [0, 1, 2].map(|k| fits[k].hurst(DIRECTIONS[k].1));
    let column = |f: fn(&PowerLaw) -> f64| [0, 1, 2].map(|k| vec![f(&fits[k])]);
    let [r2_x, r2_y, r2_radial] = column(|f| f.r_squared);
    let [q_min_x, q_min_y, q_min_radial] = column(|f| f.q_min_per_m);
    let [q_max_x, q_max_y, q_max_radial] = column(|f| f.q_max_per_m);
    let [flag_x, flag_y, flag_radial] =
        [0, 1, 2].map(|k| vec![fits[k].flag(DIRECTIONS[k].1).text().to_owned()]);
    StatsTable {
        sigma_m: vec![sigma_m],
        rms_slope: vec![slope],
        hurst_x: vec![hurst_x],
        hurst_y: vec![hurst_y],
        hurst_radial: vec![hurst_radial],
        hurst_x_r2: r2_x,
        hurst_x_q_min_per_m: q_min_x,
        hurst_x_q_max_per_m: q_max_x,
        hurst_x_flag: flag_x,
        hurst_y_r2: r2_y,
        hurst_y_q_min_per_m: q_min_y,
        hurst_y_q_max_per_m: q_max_y,
        hurst_y_flag: flag_y,
        hurst_radial_r2: r2_radial,
        hurst_radial_q_min_per_m: q_min_radial,
        hurst_radial_q_max_per_m: q_max_radial,
        hurst_radial_flag: flag_radial,
        nx: vec![filtered.nx as i64],
        ny: vec![filtered.ny as i64],
        dx_m: vec![filtered.dx_m],
        dy_m: vec![filtered.dy_m],
        nx_measured: vec![measured.nx as i64],
        ny_measured: vec![measured.ny as i64],
        dx_measured_m: vec![measured.dx_m],
        dy_measured_m: vec![measured.dy_m],
        nan_fraction: vec![nan_fraction],
        fill: vec![fill.to_string()],
        filled_points: vec![nan_count as i64],
        filled_fraction: vec![nan_fraction],
    }
}

/// Least PSD points a default Hurst range must hold before it gives up the
/// filter-safe short end.
const HURST_MIN_POINTS: usize = 5;

/// Fits H for one PSD over the wavelength range of the parameters, with a
/// note when the default range had to reach into the filter's roll-off.
pub(crate) fn hurst(
    spectrum: &Spectrum,
    direction: &'static str,
    (spacing_m, length_m): (f64, f64),
    p: &SurfaceParams,
) -> Result<(PowerLaw, Option<String>), SurfaceError> {
    let lambda_max_m = p.hurst_lambda_max_m.unwrap_or(length_m / 4.0);
    let count = |lambda_min_m: f64| {
        spectrum
            .q_per_m
            .iter()
            .filter(|&&q| q >= TAU / lambda_max_m && q <= TAU / lambda_min_m)
            .count()
    };
    let mut note = None;
    let lambda_min_m = p.hurst_lambda_min_m.unwrap_or_else(|| {
        let grid = 4.0 * spacing_m;
        // Where the stage filtered, stop where the Gaussian still passes
        // 90 % of the power: its roll-off would steepen the fitted slope
        // (+0.05…0.1 in H on maps of a few hundred points).
        let filtered =
            p.resolution_m > 0.0 && (spacing_m - p.resolution_m).abs() < 1e-9 * spacing_m;
        if !filtered {
            return grid;
        }
        let safe = grid.max(crate::filter::wavelength_passing_m(
            2.0 * p.resolution_m,
            0.9,
        ));
        if count(safe) >= HURST_MIN_POINTS {
            safe
        } else {
            note = Some(format!(
                "Hurst fit along {direction}: the map is too small for a fit range clear of the \
                 filter's roll-off ({safe:.3e} m … {lambda_max_m:.3e} m); fitted from 4·dx, \
                 where the filter steepens the PSD (H reads high)"
            ));
            grid
        }
    });
    let fit = fit_power_law(spectrum, TAU / lambda_max_m, TAU / lambda_min_m).ok_or_else(|| {
        SurfaceError::HurstRange {
            direction,
            found: count(lambda_min_m),
            lambda_min_m,
            lambda_max_m,
        }
    })?;
    Ok((fit, note))
}

/// The warning for a flagged Hurst fit, None when it is fine.
pub(crate) fn hurst_warning(
    direction: &str,
    fit: &PowerLaw,
    dimension: Dimension,
) -> Option<String> {
    let h = fit.hurst(dimension);
    let over = format!(
        "R² = {:.3} over q = {:.3e} … {:.3e} rad/m, {} bins",
        fit.r_squared, fit.q_min_per_m, fit.q_max_per_m, fit.points
    );
    match fit.flag(dimension) {
        Flag::Ok => None,
        Flag::OutsideUnitRange => Some(format!(
            "warning: Hurst exponent along {direction} = {h:.3} is outside 0…1 ({over}): not \
             the exponent of a self-affine surface; check the fit range \
             (hurst_lambda_min_m, hurst_lambda_max_m) against the PSD"
        )),
        Flag::PoorPowerLaw => Some(format!(
            "warning: the PSD along {direction} is a poor power law ({over}, under {R2_MIN}): \
             its Hurst exponent {h:.3} does not describe it; look at the PSD, or narrow the fit \
             range (hurst_lambda_min_m, hurst_lambda_max_m)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // An egg-crate A sin(2πx/P) sin(2πy/P), P = 32 samples, over whole
    // periods (no plane to remove): the stage's areal table against closed
    // forms of the sampled wave (Sq = A/2; Sa = A·m², m = 2cot(π/P)/P the
    // mean |sin| over the samples; Ssk = 0; Sku = (3/8)²/(1/2)⁴ = 9/4;
    // Sp = Sv = A as the samples hit the crests), Sq against the stats
    // table's σ, the table against the module on the output map (shifted by
    // the height reference, which the mean plane takes out again), and the
    // material-ratio curve from Sp down to −Sv.
    #[test]
    fn an_egg_crate_has_its_areal_parameters_and_curve() {
        use hypercontact_core::Params;
        let (a_m, period, n) = (2e-6, 32usize, 128usize);
        let wave = |i: usize| (TAU * i as f64 / period as f64).sin();
        let h = Array2::from_shape_fn((n, n), |(i, j)| a_m * wave(i) * wave(j));
        let map = Field::new(h, 1e-6, 1e-6).unwrap();
        let p = SurfaceParams::default().check().unwrap();
        let a = analyse(map, &p, &Context::new("s")).unwrap();
        let close = |x: f64, y: f64, what: &str| {
            assert!((x - y).abs() <= 1e-9 * a_m, "{what}: {x} against {y}");
        };
        let areal = &a.areal;
        close(areal.sq_m[0], a_m / 2.0, "Sq");
        close(areal.sq_m[0], a.stats.sigma_m[0], "Sq against σ");
        let m = 2.0 / (std::f64::consts::PI / period as f64).tan() / period as f64;
        close(areal.sa_m[0], a_m * m * m, "Sa");
        assert!(areal.ssk[0].abs() < 1e-9, "Ssk {}", areal.ssk[0]);
        assert!((areal.sku[0] - 2.25).abs() < 1e-9, "Sku {}", areal.sku[0]);
        close(areal.sp_m[0], a_m, "Sp");
        close(areal.sv_m[0], a_m, "Sv");
        close(areal.sz_m[0], 2.0 * a_m, "Sz");
        let again = crate::iso25178::areal_parameters(&a.height.values, 1e-6, 1e-6).unwrap();
        let sdr = areal.sdr_percent[0];
        assert!((again.sdr_percent / sdr - 1.0).abs() < 1e-12, "Sdr {sdr}");
        close(again.sal_m, areal.sal_m[0], "Sal");
        let curve = &a.material_ratio;
        assert_eq!(curve.material_ratio_percent.len(), MATERIAL_RATIO_POINTS);
        assert_eq!(curve.material_ratio_percent[50], 50.0);
        close(curve.height_m[0], a_m, "curve at 0 %");
        close(curve.height_m[100], -a_m, "curve at 100 %");
        assert!(curve.height_m.windows(2).all(|w| w[1] <= w[0]));
        // Heights symmetric about the mean: half the area lies above it.
        assert!(
            curve.height_m[50].abs() < 1e-9 * a_m,
            "{}",
            curve.height_m[50]
        );
        // The new tables are the core's functions of the output map (the
        // height reference shifts it; differences and the ACF ignore that).
        let near = |x: &[f64], y: &[f64], what: &str| {
            assert_eq!(x.len(), y.len(), "{what}");
            // the lag of a whole period has a slope of rounding size
            let largest = x
                .iter()
                .filter(|u| u.is_finite())
                .fold(0.0, |m: f64, u| m.max(u.abs()));
            for (u, v) in x.iter().zip(y) {
                let ok = (u - v).abs() <= 1e-9 * largest || (u.is_nan() && v.is_nan());
                assert!(ok, "{what}: {u} against {v}");
            }
        };
        let acf = crate::iso25178::autocorrelation(&a.height.values, 1e-6, 1e-6).unwrap();
        let again = AcfTable::new(&acf);
        assert_eq!(a.acf.direction, again.direction);
        near(&a.acf.lag_m, &again.lag_m, "ACF lags");
        near(&a.acf.acf, &again.acf, "ACF");
        let again = ScaleDependentTable::new(&a.height.values, 1e-6, 1e-6).unwrap();
        assert_eq!(a.scale_dependent.lag_px, [1, 2, 4, 8, 16, 32]);
        near(&a.scale_dependent.rms_slope, &again.rms_slope, "slope");
        near(
            &a.scale_dependent.rms_curvature_per_m,
            &again.rms_curvature_per_m,
            "curvature",
        );
        // At one pixel the slope is Sdq up to O(1/n): Sdq averages gx² and
        // gy² over their own rows (see iso25178::hybrid).
        let sdq = areal.sdq[0];
        assert!((a.scale_dependent.rms_slope[0] / sdq - 1.0).abs() < 2.0 / n as f64);
        let d = &a.distributions;
        assert_eq!(d.count.len(), 3 * 64, "default histogram_bins");
        let points = |q: &str| -> i64 {
            (0..d.count.len())
                .filter(|&r| d.quantity[r] == q)
                .map(|r| d.count[r])
                .sum()
        };
        assert_eq!(points("height"), (n * n) as i64);
        assert_eq!(points("slope"), ((n - 2) * (n - 2)) as i64);
        assert_eq!(points("curvature"), ((n - 2) * (n - 2)) as i64);
    }

    #[test]
    fn flagged_fits_get_a_warning_naming_r2_and_range() {
        let fit = |slope: f64, r_squared: f64| PowerLaw {
            slope,
            prefactor: 1.0,
            points: 12,
            r_squared,
            q_min_per_m: 1e4,
            q_max_per_m: 1e6,
        };
        assert_eq!(
            hurst_warning("x", &fit(-2.4, 0.99), Dimension::Profile),
            None
        );
        let outside = hurst_warning("y", &fit(-3.6, 0.99), Dimension::Profile).unwrap();
        assert!(
            outside.starts_with("warning: Hurst exponent along y = 1.300 is outside 0…1")
                && outside.contains("R² = 0.990 over q = 1.000e4 … 1.000e6 rad/m, 12 bins"),
            "{outside}"
        );
        let poor = hurst_warning("radial", &fit(-3.4, 0.5), Dimension::Areal).unwrap();
        assert!(
            poor.starts_with("warning: the PSD along radial is a poor power law (R² = 0.500")
                && poor.contains("its Hurst exponent 0.700 does not describe it"),
            "{poor}"
        );
    }
}
