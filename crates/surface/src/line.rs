//! Line scans (stylus profiles) through stage `surface`: a map one point
//! across, n × 1 (a profile along x) or 1 × n (along y), is analysed as the
//! 1-D profile it is, as the paper's x and y PSDs analyse the profiles of a
//! 2-D map:
//!
//! - the filter to `resolution_m` is the 2-D one's ISO 16610-61 Gaussian
//!   with the across kernel on a single point: the profile Gaussian of
//!   ISO 16610-21 with the same cut-off 2·resolution_m (weights
//!   exp(−π (x/(α λc))²), normalised over the measured points);
//! - detrending: a least-squares line a + b·i over the measured points (what
//!   `detrend: plane` is on a line) or the mean;
//! - missing points: linear interpolation between the measured neighbours
//!   ([`fill_linear`]); this is the harmonic (Laplace) in-fill of 2-D maps
//!   restricted to 1-D, h'' = 0, with a zero derivative at the ends (each end
//!   run held at the nearest measured value; a periodic profile interpolates
//!   across the wrap);
//! - the PSD along the line with the x PSD's normalisation and window
//!   ([`crate::psd::psd_x`] on the profile: C1D = |dx·FFT(w·h)|²/L, Hann
//!   scaled to mean(w²) = 1 unless periodic), its Hurst exponent
//!   (C ∝ q^(−1−2H)), σ (the profile's Rq) and the rms slope by forward
//!   differences (the 2-D x slope's convention);
//! - the `areal` table holds the profile analogues of ISO 4287 / ISO 13565-2
//!   in the columns of the same meaning: Ra, Rq, Rsk, Rku, Rp, Rv, Rz
//!   (Sa … Sz), Rdq (Sdq), Rk, Rpk, Rvk, Mr1, Mr2 (Sk … Smr2), the lag at
//!   which the profile's autocorrelation falls to 0.2 (Sal) and to 1/e
//!   (the correlation length); Sdr and Str, which need an area, are NaN.
//!
//! The y (or x) and radial PSDs and their Hurst exponents do not exist for
//! a line: the PSD table has rows for the line's direction only, their
//! stats columns are NaN and their flags say "not defined (line scan)".

use hypercontact_core::{Checked, Context, Field, StageError};
use ndarray::Array2;

use crate::analysis::{
    Analysis, MATERIAL_RATIO_POINTS, MeasuredMap, detrend, filtered, grid_of, hurst, hurst_warning,
    overflow, roughness, stats_table,
};
use crate::error::SurfaceError;
use crate::filter::Grid;
use crate::hurst::{Dimension, PowerLaw};
use crate::infill::fill_zero;
use crate::iso25178::{
    ArealParameters, ISO_DECAY_THRESHOLD, MaterialRatio, autocorrelation, height_parameters,
};
use crate::psd::{Spectrum, Window, psd_x};
use crate::stats::{Reference, reference_height, rms_slope};
use crate::surface_stage::{Detrend, Fill, ReferenceKind, SurfaceParams};
use crate::surface_tables::{
    AcfTable, ArealTable, DistributionsTable, MaterialRatioTable, PsdTable, ScaleDependentTable,
    StatsTable,
};

/// The flag of the Hurst columns a line scan has no PSD for.
pub const NOT_DEFINED: &str = "not defined (line scan)";

/// Fewest points of a (filtered) line scan with a PSD, as for each side of
/// a 2-D map.
pub const MIN_LINE_POINTS: usize = 8;

/// The axis a line scan runs along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineAxis {
    /// An n × 1 map: a profile along x (axis 0).
    X,
    /// A 1 × n map: a profile along y (axis 1).
    Y,
}

impl LineAxis {
    /// The axis of a map of nx × ny points that is a line scan (one point
    /// across, more along), None for any other map.
    pub fn of(nx: usize, ny: usize) -> Option<Self> {
        match (nx, ny) {
            (n, 1) if n > 1 => Some(LineAxis::X),
            (1, n) if n > 1 => Some(LineAxis::Y),
            _ => None,
        }
    }

    /// `x` or `y`: the PSD direction and stats columns of the line.
    pub fn name(self) -> &'static str {
        match self {
            LineAxis::X => "x",
            LineAxis::Y => "y",
        }
    }

    /// A grid of the profile (n × 1) in the map's orientation.
    fn orient(self, g: &Grid, across_m: f64) -> Grid {
        match self {
            LineAxis::X => Grid {
                dy_m: across_m,
                ..*g
            },
            LineAxis::Y => Grid {
                nx: g.ny,
                ny: g.nx,
                dx_m: across_m,
                dy_m: g.dx_m,
            },
        }
    }
}

/// Replaces the NaN of `profile` by linear interpolation between the
/// measured points on either side; the runs before the first and after the
/// last measured point take its value, or (`periodic`) are interpolated
/// across the wrap from the last to the first. Returns the points filled;
/// a profile with no measured point is left as it is.
pub fn fill_linear(profile: &mut [f64], periodic: bool) -> usize {
    let n = profile.len();
    let measured: Vec<usize> = (0..n).filter(|&i| !profile[i].is_nan()).collect();
    let (Some(&first), Some(&last)) = (measured.first(), measured.last()) else {
        return 0;
    };
    let mut filled = 0;
    for pair in measured.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (ha, hb) = (profile[a], profile[b]);
        for (k, v) in profile.iter_mut().enumerate().take(b).skip(a + 1) {
            let t = (k - a) as f64 / (b - a) as f64;
            *v = ha + t * (hb - ha);
            filled += 1;
        }
    }
    let (h_first, h_last) = (profile[first], profile[last]);
    // Positions after `last`, wrapping past the end: last + 1 … first + n − 1.
    let span = (first + n - last) as f64;
    for (k, v) in profile.iter_mut().enumerate() {
        if k >= first && k <= last {
            continue;
        }
        *v = if periodic {
            let after = if k > last { k - last } else { k + n - last };
            h_last + after as f64 / span * (h_first - h_last)
        } else if k < first {
            h_first
        } else {
            h_last
        };
        filled += 1;
    }
    filled
}

/// Removes the least-squares line a + b·i through the measured points of
/// the profile (NaN stays NaN); an error with fewer than two of them.
pub fn remove_line(profile: &mut [f64]) -> Result<(), SurfaceError> {
    let (mut n, mut sum_i, mut sum_h) = (0.0, 0.0, 0.0);
    for (i, &h) in profile.iter().enumerate().filter(|(_, h)| !h.is_nan()) {
        n += 1.0;
        sum_i += i as f64;
        sum_h += h;
    }
    if n < 2.0 {
        return Err(SurfaceError::Input(
            "too few measured points to fit a line (two are needed)".into(),
        ));
    }
    // About the centroid: no cancellation from a large offset or index.
    let (mean_i, mean_h) = (sum_i / n, sum_h / n);
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for (i, &h) in profile.iter().enumerate().filter(|(_, h)| !h.is_nan()) {
        let di = i as f64 - mean_i;
        sxx += di * di;
        sxy += di * (h - mean_h);
    }
    let slope = sxy / sxx;
    for (i, h) in profile.iter_mut().enumerate() {
        *h -= mean_h + slope * (i as f64 - mean_i);
    }
    Ok(())
}

/// The profile parameters of a levelled profile `h` (n × 1, spacing
/// `spacing_m`) in the `areal` table's terms (see the module doc), and its
/// material-ratio curve.
pub fn profile_parameters(
    h: &Array2<f64>,
    spacing_m: f64,
) -> Result<(ArealParameters, MaterialRatio), SurfaceError> {
    let heights = height_parameters(h)?;
    let acf = autocorrelation(h, spacing_m, spacing_m)?;
    let decay = acf.decay_lengths(ISO_DECAY_THRESHOLD)?;
    let ratio = MaterialRatio::new(h)?;
    let parameters = ArealParameters::assemble(
        &heights,
        (rms_slope(h, spacing_m, spacing_m), f64::NAN),
        (decay.sal_m(), f64::NAN),
        &ratio.functional(),
        acf.correlation_length_m(),
    );
    Ok((parameters, ratio))
}

/// [`profile_parameters`] as the stage's tables; a profile whose
/// parameters overflow gets a NaN row and a warning, as a 2-D map does.
fn profile_tables(
    h: &Array2<f64>,
    spacing_m: f64,
    ctx: &Context,
) -> (ArealTable, MaterialRatioTable) {
    match profile_parameters(h, spacing_m) {
        Ok((parameters, ratio)) => (
            ArealTable::new(&parameters),
            MaterialRatioTable::new(&ratio, MATERIAL_RATIO_POINTS),
        ),
        Err(e) => {
            ctx.note(&format!(
                "warning: no profile parameters (table `areal` is NaN, `material_ratio` empty): {e}"
            ));
            (ArealTable::unknown(), MaterialRatioTable::default())
        }
    }
}

/// The profile of a line-scan map as an n × 1 map along its axis, spaced
/// `along_m` both ways (a line has no spacing across; the filter then
/// judges `resolution_m` against the spacing along it).
fn as_profile(map: Field, axis: LineAxis) -> Result<(Field, f64), StageError> {
    let (along_m, across_m) = match axis {
        LineAxis::X => (map.dx_m, map.dy_m),
        LineAxis::Y => (map.dy_m, map.dx_m),
    };
    let values: Vec<f64> = map.values.iter().copied().collect();
    let n = values.len();
    let values = Array2::from_shape_vec((n, 1), values).map_err(StageError::other)?;
    let profile = Field::new(values, along_m, along_m).map_err(StageError::other)?;
    Ok((profile, across_m))
}

/// The missing points of the filtered profile and their share; an error
/// when it is too short for a PSD or nothing was measured.
fn missing_share(h: &Array2<f64>, resolution_m: f64) -> Result<(usize, f64), SurfaceError> {
    let n = h.len();
    if n < MIN_LINE_POINTS {
        return Err(SurfaceError::Input(format!(
            "the filtered line scan has only {n} points (at least {MIN_LINE_POINTS} are needed): \
             lower resolution_m ({resolution_m} m) or measure a longer profile"
        )));
    }
    let nan_count = h.iter().filter(|v| v.is_nan()).count();
    if nan_count == n {
        return Err(SurfaceError::Input(
            "every point of the line scan is NaN".into(),
        ));
    }
    Ok((nan_count, nan_count as f64 / n as f64))
}

/// [`crate::analysis::analyse_measured`] of a line scan along `axis`.
pub fn analyse_line(
    map: Field,
    axis: LineAxis,
    source: &str,
    p: &Checked<SurfaceParams>,
    ctx: &Context,
) -> Result<Analysis, StageError> {
    let progress = ctx.progress(3, "filter, PSD");
    let (profile, across_m) = as_profile(map, axis)?;
    let measured = grid_of(&profile);
    line_note(axis, &measured, ctx);
    let filtered = filtered(MeasuredMap::Whole(profile), &measured, p, ctx)?;
    progress.inc(1);
    let grid = grid_of(&filtered);
    let spacing_m = grid.dx_m;
    let (nan_count, nan_fraction) = missing_share(&filtered.values, p.resolution_m)?;
    let mut h = filtered.values;
    let largest_m = h
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    // A periodic profile only loses its mean, as a periodic map does.
    let trend = if p.periodic { Detrend::Mean } else { p.detrend };
    match trend {
        Detrend::Plane => remove_line(h.as_slice_mut().expect("a fresh profile is contiguous"))?,
        Detrend::Mean => detrend(&mut h, Detrend::Mean)?,
    }
    let (sigma_m, slope) = roughness(&h, (spacing_m, spacing_m), largest_m, source)?;
    let (areal, material_ratio) = profile_tables(&h, spacing_m, ctx);
    let (distributions, acf) = profile_distributions(&h, spacing_m, axis, p.histogram_bins, ctx);
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
    let spectrum = line_spectrum(&h, spacing_m, nan_count, p, ctx);
    if spectrum.c.iter().any(|c| !c.is_finite()) {
        return Err(overflow(source, largest_m, "its power spectrum").into());
    }
    progress.inc(1);
    let fit = line_hurst(&spectrum, axis, &grid, p, ctx)?;
    let reference = match p.reference {
        ReferenceKind::Lowest => Reference::Lowest,
        ReferenceKind::Percentile => Reference::Percentile(p.reference_percent),
    };
    let z0 = reference_height(&h, reference);
    h.mapv_inplace(|v| v - z0);
    let mut psd = PsdTable::default();
    psd.push(axis.name(), &spectrum);
    let stats = line_stats(
        (sigma_m, slope),
        &fit,
        axis,
        (&grid, &measured, across_m),
        (nan_count, nan_fraction),
        p.fill,
    );
    progress.inc(1);
    let height = oriented_height(h, axis, &grid, &measured, across_m)?;
    Ok(Analysis {
        height,
        psd,
        stats,
        areal,
        material_ratio,
        distributions,
        acf,
        // (scale-dependent slope and curvature are areal here: ⟨gx² + gy²⟩
        // and ∇²h/2 need both directions)
        scale_dependent: ScaleDependentTable::default(),
    })
}

/// The `distributions` and `acf` tables of a profile: the height histogram
/// (the slope and curvature ones are areal: |∇h| and ∇²h/2) and the
/// autocorrelation along the line, labelled with its axis.
fn profile_distributions(
    h: &Array2<f64>,
    spacing_m: f64,
    axis: LineAxis,
    bins: usize,
    ctx: &Context,
) -> (DistributionsTable, AcfTable) {
    let mut distributions = DistributionsTable::default();
    match crate::iso25178::height_histogram(h, bins) {
        Ok(heights) => distributions.push("height", "m", &heights),
        Err(e) => ctx.note(&format!(
            "warning: no height histogram in table `distributions`: {e}"
        )),
    }
    let mut acf = AcfTable::default();
    match crate::iso25178::autocorrelation(h, spacing_m, spacing_m) {
        Ok(correlation) => {
            // The profile is held n × 1, along x, whatever its axis.
            let (lag_m, values) = correlation.axis_profile(crate::iso25178::Axis::X);
            acf.direction
                .extend(std::iter::repeat_n(axis.name().to_owned(), lag_m.len()));
            acf.lag_m.extend(lag_m);
            acf.acf.extend(values);
        }
        Err(e) => ctx.note(&format!("warning: table `acf` empty: {e}")),
    }
    (distributions, acf)
}

/// The note that says the map is analysed as a profile, and what it lacks.
fn line_note(axis: LineAxis, measured: &Grid, ctx: &Context) {
    let (along, other) = match axis {
        LineAxis::X => ("x", "y"),
        LineAxis::Y => ("y", "x"),
    };
    ctx.note(&format!(
        "line scan: a profile of {} points along {along} at {:.4e} m, analysed as a profile: \
         PSD and Hurst exponent along {along} only (none along {other}, no radial PSD); sigma_m \
         is its Rq; the areal table holds Ra, Rq, Rsk, Rku, Rp, Rv, Rz, Rdq, Rk, Rpk, Rvk, \
         Mr1, Mr2 and the profile's autocorrelation lengths in the S columns; Sdr and Str \
         need a 2-D map and are NaN; `distributions` holds the height histogram, `acf` the \
         autocorrelation along the line, and `scale_dependent` is empty (slope and curvature \
         histograms and their scale dependence are areal)",
        measured.nx, measured.dx_m
    ));
}

/// The PSD along the detrended profile `h`, its `nan_count` missing points
/// filled as `p.fill` says (with a note when there were any).
fn line_spectrum(
    h: &Array2<f64>,
    spacing_m: f64,
    nan_count: usize,
    p: &SurfaceParams,
    ctx: &Context,
) -> Spectrum {
    let mut filled = h.clone();
    match p.fill {
        Fill::Harmonic => {
            let values = filled
                .as_slice_mut()
                .expect("a fresh profile is contiguous");
            fill_linear(values, p.periodic);
        }
        Fill::Zero => {
            fill_zero(&mut filled);
        }
    }
    if nan_count > 0 {
        ctx.note(&format!(
            "{nan_count} missing points ({:.3} % of {}) filled {} before the PSD",
            100.0 * nan_count as f64 / h.len() as f64,
            h.len(),
            match p.fill {
                Fill::Harmonic =>
                    "linearly between measured neighbours (the harmonic in-fill in 1-D)",
                Fill::Zero => "with the mean height",
            }
        ));
    }
    let window = if p.periodic {
        Window::None
    } else {
        Window::Hann
    };
    psd_x(&filled, spacing_m, window, p.bins_per_decade)
}

/// The Hurst fit of the profile's PSD, with its notes and warning.
fn line_hurst(
    spectrum: &Spectrum,
    axis: LineAxis,
    grid: &Grid,
    p: &SurfaceParams,
    ctx: &Context,
) -> Result<PowerLaw, SurfaceError> {
    let length_m = grid.nx as f64 * grid.dx_m;
    let (fit, note) = hurst(spectrum, axis.name(), (grid.dx_m, length_m), p)?;
    if let Some(note) = note {
        ctx.note(&note);
    }
    if let Some(warning) = hurst_warning(axis.name(), &fit, Dimension::Profile) {
        ctx.note(&warning);
    }
    Ok(fit)
}

/// The spacing across the analysed profile: as measured, or the filter's
/// `resolution_m` (both ways, as for a 2-D map) when it was resampled.
fn across_analysed_m(analysed: &Grid, measured: &Grid, across_m: f64) -> f64 {
    if analysed == measured {
        across_m
    } else {
        analysed.dx_m
    }
}

/// The `stats` row of a line scan: the line's fit in its direction's
/// columns, NaN and [`NOT_DEFINED`] in the others; grids in the map's
/// orientation.
fn line_stats(
    roughness: (f64, f64),
    fit: &PowerLaw,
    axis: LineAxis,
    (analysed, measured, across_m): (&Grid, &Grid, f64),
    missing: (usize, f64),
    fill: Fill,
) -> StatsTable {
    let none = PowerLaw {
        slope: f64::NAN,
        prefactor: f64::NAN,
        points: 0,
        r_squared: f64::NAN,
        q_min_per_m: f64::NAN,
        q_max_per_m: f64::NAN,
    };
    let fits = match axis {
        LineAxis::X => [*fit, none, none],
        LineAxis::Y => [none, *fit, none],
    };
    let across_analysed = across_analysed_m(analysed, measured, across_m);
    let mut stats = stats_table(
        roughness,
        &fits,
        (
            &axis.orient(analysed, across_analysed),
            &axis.orient(measured, across_m),
        ),
        missing,
        fill,
    );
    let other = match axis {
        LineAxis::X => &mut stats.hurst_y_flag,
        LineAxis::Y => &mut stats.hurst_x_flag,
    };
    *other = vec![NOT_DEFINED.to_owned()];
    stats.hurst_radial_flag = vec![NOT_DEFINED.to_owned()];
    stats
}

/// The analysed profile (n × 1) as the `height` output, in the map's
/// orientation.
fn oriented_height(
    h: Array2<f64>,
    axis: LineAxis,
    analysed: &Grid,
    measured: &Grid,
    across_m: f64,
) -> Result<Field, StageError> {
    let across = across_analysed_m(analysed, measured, across_m);
    let along = analysed.dx_m;
    let field = match axis {
        LineAxis::X => Field::new(h, along, across),
        LineAxis::Y => {
            let n = h.len();
            let row = h.into_shape_with_order((1, n)).map_err(StageError::other)?;
            Field::new(row, across, along)
        }
    };
    field.map_err(StageError::other)
}

#[cfg(test)]
mod tests;
