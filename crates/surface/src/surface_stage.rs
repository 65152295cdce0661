//! Stage `surface`: interferometer tiles → stitched, filtered height map,
//! PSDs (x, y, radial), statistics and Hurst exponents.

use std::f64::consts::TAU;

use hypercontact_core::{
    Arity, Checked, Choice, Context, Field, InputPath, InputSpec, Inputs, OutputSpec, Outputs,
    ParamError, Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_labfiles::FileSource;
use ndarray::Array2;

use crate::error::SurfaceError;
use crate::filter::Grid;
use crate::hurst::{Dimension, Flag, PowerLaw, R2_MIN, fit_power_law};
use crate::infill::{fill_harmonic, fill_zero};
use crate::psd::{Spectrum, Window, psd_radial, psd_x, psd_y};
use crate::stats::{Reference, reference_height, rms_slope, sigma};
use crate::stitch::{Mosaic, covered_region, stitch};
use crate::tiles::{TileSet, read_tiles};
use crate::{filter, plane};

pub use crate::surface_tables::{PsdTable, StatsTable, StitchTable};

/// Where heights are measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum ReferenceKind {
    /// the lowest point is z = 0 (the paper's)
    Lowest,
    /// z = 0 at `reference_percent` of the heights
    Percentile,
}

/// What is removed before statistics and PSDs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum Detrend {
    /// a least-squares plane
    Plane,
    /// the mean height
    Mean,
}

/// How points still missing after filtering enter the Fourier transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum Fill {
    /// harmonic (Laplace) in-fill from the measured points (SurfaceTopography's default)
    Harmonic,
    /// the detrended mean height, 0 (stage versions ≤ 3: reproduces old runs)
    Zero,
}

/// Parameters of `surface`.
#[params(check = ordered_hurst_range)]
pub struct SurfaceParams {
    /// folder of tiles + positions.csv (instead of input `tiles`)
    pub dir: Option<InputPath>,
    /// tile files in any format read here (instead of `dir` or input `tiles`)
    #[param(default = Vec::new())]
    pub tile_files: Vec<InputPath>,
    /// positions.csv for `tile_files` (its `file` column names them by file name; default: the positions the files record)
    pub positions: Option<InputPath>,
    /// lateral resolution and new grid spacing (0 = keep the measured grid)
    #[param(default = 20e-6, unit = "m", range = 0.0..)]
    pub resolution_m: f64,
    /// height reference
    #[param(default = ReferenceKind::Lowest)]
    pub reference: ReferenceKind,
    /// percentile for `reference: percentile`
    #[param(default = 1.0, unit = "%", range = 0.0..=100.0)]
    pub reference_percent: f64,
    /// removed before stats and PSDs (periodic maps: mean only)
    #[param(default = Detrend::Plane)]
    pub detrend: Detrend,
    /// the map is periodic: no window, and only the mean is removed
    #[param(default = false)]
    pub periodic: bool,
    /// how missing points are filled before the PSDs
    #[param(default = Fill::Harmonic)]
    pub fill: Fill,
    /// refuse PSDs of maps with more missing points than this (after filtering)
    #[param(default = 0.1, range = 0.0..=1.0)]
    pub max_missing_fraction: f64,
    /// log bins per decade of q
    #[param(default = 10, range = 1..=100)]
    pub bins_per_decade: usize,
    /// shortest wavelength of the Hurst fit (default 4·dx, 7.3·resolution_m when filtered)
    #[param(unit = "m", positive)]
    pub hurst_lambda_min_m: Option<f64>,
    /// longest wavelength of the Hurst fit (default L/4)
    #[param(unit = "m", positive)]
    pub hurst_lambda_max_m: Option<f64>,
    /// least overlap (both directions) for a tile pair
    #[param(default = 16, unit = "px", range = 4..)]
    pub min_overlap_px: usize,
}

fn ordered_hurst_range(p: &SurfaceParams) -> Result<(), ParamError> {
    if let (Some(lo), Some(hi)) = (p.hurst_lambda_min_m, p.hurst_lambda_max_m)
        && lo >= hi
    {
        return Err(ParamError::new(
            "hurst_lambda_min_m",
            format!("must be below hurst_lambda_max_m ({hi} m), got {lo} m"),
        ));
    }
    Ok(())
}

/// The `surface` stage.
pub struct Surface;

static INFO: StageInfo = StageInfo {
    kind: "surface",
    version: 4,
    summary: "Stitch interferometer tiles, filter to a lateral resolution, PSD, σ and Hurst exponent",
    doc: "Source: exactly one of input `tiles` (a Files product: tile_NNN.npy + positions.csv, as \
          synth-surface writes), param `dir` (a folder of the same layout, real data) or input \
          `height` (an already stitched map, e.g. from height-map). positions.csv has columns tile, \
          file, x_m, y_m and pixel_m (nominal position of each tile's pixel [0, 0]; pixel_m may be \
          left out where the tile files state their spacing). Tiles are read by their first bytes: \
          .npy (float64/float32, metres, axis 0 = x, NaN = missing) or any instrument format \
          height-map reads (X3P, .sur, .plu, MetroPro .dat, .datx, .opd; square pixels, one \
          spacing for all); without positions.csv the tiles are the folder's tile files in natural \
          order of their names, placed by the stage positions the files record (X3P's CX/CY \
          offsets). \
          STITCHING: overlapping pairs registered by phase correlation: the eight highest peaks (of the half-whitened cross-power spectrum), each \
          also taken modulo the overlap size, are checked by the Pearson correlation of the overlap \
          they imply and the best wins, then the sub-pixel rest by Gauss–Newton on the heights of the \
          re-cut overlap (cubic-convolution interpolation, a plane absorbing tilt and piston); all \
          pair offsets solved together by least squares (mean correction zero), pairs more than \
          0.5 px from the joint solution dropped as outliers while the tiles stay connected; a \
          plane (tilt + piston) per tile from the overlaps by least squares; feathered blending \
          (weights fall linearly to tile edges), tiles placed at whole pixels; NaN where no tile \
          measured; the map is cropped to the region fully inside tile footprints. FILTER: ISO \
          16610-61 Gaussian low-pass with cut-off 2·resolution_m (50 % amplitude there), sampled \
          every resolution_m; NaN-aware (normalised convolution; NaN where under half the kernel \
          weight was measured); resolution_m: 0 keeps the grid. A note gives the grid before and \
          after (also in stats: nx_measured, ny_measured, dx_measured_m, dy_measured_m against nx, \
          ny, dx_m, dy_m), and a note starting with \"warning:\" when the filter discards more than \
          half of the PSD's range in log q: the filtered map's last q, π/resolution_m, below \
          √(q_min·q_max) of the measured map (q from 2π/longest side to π/coarser spacing). \
          DETRENDING: least-squares plane \
          (or mean) over measured points, before statistics and PSDs. HEIGHT REFERENCE: `lowest` \
          (the paper's choice: the lowest point is z = 0) or `percentile` (z = 0 at \
          reference_percent of the heights); a single pit pixel shifts every z under `lowest`, a \
          percentile is robust to it. PSD (SurfaceTopography conventions, numbers comparable one to \
          one): axis 0 = x; L = N·dx; q = 2πk/L in rad/m; 1-D: C1D = |dx·FFT_x(w·h)|²/L, k = 0…N/2−1 \
          (Nyquist dropped), averaged over all profiles; y: the same on the transposed map; radial: \
          C2D = |dx·dy·FFT2(w·h)|²/(Lx·Ly) averaged over |q| bins up to π/dx; all binned in \
          log-spaced bins (bins_per_decade, edges as SurfaceTopography's make_grid), each bin \
          reporting the mean q and mean C of its members; window: none if `periodic`, otherwise Hann \
          scaled to mean(w²) = 1 (1-D along the profile; rotationally symmetric for radial). \
          MISSING POINTS: points still NaN after filtering (their share is nan_fraction) are filled \
          before the FFT only (the `height` output keeps its NaN, σ and slope use measured points \
          only): `fill: harmonic` (default) solves the 5-point Laplace equation on them with the \
          measured heights as Dirichlet data and a zero normal derivative at the map edge (periodic \
          maps wrap), as SurfaceTopography's interpolate_undefined_data (legs weighted 1/dx², \
          1/dy²), by preconditioned conjugate gradients to a relative residual of 1e-12; \
          `fill: zero` puts them at the detrended mean (the behaviour of stage version 3). A map \
          with more than max_missing_fraction missing is refused: an in-fill carries no roughness \
          shorter than its holes, so the PSD at high q falls by about the missing share (10 % \
          scattered missing: C up to 9 % low at the short wavelengths, the Nyquist bin 28 % high, the \
          median bin within 1 %); \
          what was filled is \
          in stats (fill, filled_points, filled_fraction) and a note. STATS: sigma_m = areal rms height Sq (not profile Rq); rms_slope = \
          √⟨|∇h|²⟩ by forward differences. HURST: least squares of ln C on ln q, C ∝ q^(−1−2H) \
          (1-D) and q^(−2−2H) (radial), over wavelengths hurst_lambda_min_m … hurst_lambda_max_m \
          (default 4·dx … L/4; on a map this stage filtered, from the wavelength where the \
          Gaussian still passes 90 % of the power, 3.6 cut-offs = 7.3·resolution_m, so the filter's \
          roll-off does not steepen the slope). Each fit reports its R² (ln C on ln q) and the q \
          range of the bins it used (hurst_*_r2, hurst_*_q_min_per_m, hurst_*_q_max_per_m) and a \
          flag (hurst_*_flag): \"poor power law (R² < 0.9)\" first, else \"outside 0…1\", else \
          \"ok\"; a flagged fit also gets a note starting with \"warning:\".",
    inputs: &[
        InputSpec::files("tiles", Arity::Optional, "tile_NNN.npy + positions.csv"),
        InputSpec::field(
            "height",
            Arity::Optional,
            "an already stitched map (skips stitching)",
        ),
    ],
    outputs: &[
        OutputSpec::field(
            "height",
            "stitched, filtered, detrended map from the reference height, metres (NaN = unmeasured)",
        ),
        OutputSpec::table::<PsdTable>("psd", "binned PSDs"),
        OutputSpec::table::<StatsTable>("stats", "one row"),
        OutputSpec::table::<StitchTable>("stitch", "per tile"),
    ],
};

/// The stitched map at the measured spacing and the stitch table.
fn stitched(
    set: &TileSet,
    p: &SurfaceParams,
    ctx: &Context,
) -> Result<(Field, StitchTable), StageError> {
    let progress = ctx.progress(1, "stitch tiles");
    let Mosaic {
        heights,
        covered,
        tiles,
    } = stitch(set, p.min_overlap_px)?;
    progress.inc(1);
    let [(x0, x1), (y0, y1)] = covered_region(&covered);
    let cropped = Array2::from_shape_fn((x1 - x0, y1 - y0), |(i, j)| heights[[x0 + i, y0 + j]]);
    drop(heights);
    let field = Field::new(cropped, set.pixel_m, set.pixel_m).map_err(StageError::other)?;
    Ok((field, StitchTable::new(set, &tiles)))
}

/// Least PSD points a default Hurst range must hold before it gives up the
/// filter-safe short end.
const HURST_MIN_POINTS: usize = 5;

/// Fits H for one PSD over the wavelength range of the parameters, with a
/// note when the default range had to reach into the filter's roll-off.
fn hurst(
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
fn hurst_warning(direction: &str, fit: &PowerLaw, dimension: Dimension) -> Option<String> {
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

/// Everything the stage computes from a stitched map at its measured grid.
pub struct Analysis {
    pub height: Field,
    pub psd: PsdTable,
    pub stats: StatsTable,
}

/// An rms height after detrending below this fraction of the largest
/// |height| is the detrending's rounding noise, not roughness: a flat map.
/// Real maps sit orders of magnitude above it (1 nm of roughness on a 1 m
/// offset still passes).
pub const FLAT_RELATIVE: f64 = 1e-9;

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
    let progress = ctx.progress(3, "filter, PSD");
    let measured = Grid {
        nx: map.nx(),
        ny: map.ny(),
        dx_m: map.dx_m,
        dy_m: map.dy_m,
    };
    let filtered = if p.resolution_m > map.dx_m.max(map.dy_m) * (1.0 + 1e-9) {
        let values = filter::gaussian_resample(&map.values, map.dx_m, map.dy_m, p.resolution_m);
        let filtered =
            Field::new(values, p.resolution_m, p.resolution_m).map_err(StageError::other)?;
        let grid = Grid {
            nx: filtered.nx(),
            ny: filtered.ny(),
            dx_m: filtered.dx_m,
            dy_m: filtered.dy_m,
        };
        for note in filter::filter_notes(&measured, &grid, p.resolution_m) {
            ctx.note(&note);
        }
        filtered
    } else {
        if p.resolution_m > 0.0 {
            ctx.note(&format!(
                "resolution_m = {} m is not coarser than the grid ({} m): map kept as measured",
                p.resolution_m, map.dx_m
            ));
        }
        map
    };
    progress.inc(1);
    let (nx, ny) = filtered.values.dim();
    if nx < 8 || ny < 8 {
        return Err(SurfaceError::Input(format!(
            "the filtered map has only {nx} × {ny} points: lower resolution_m ({} m) or measure a larger area",
            p.resolution_m
        ))
        .into());
    }
    let mut h = filtered.values;
    let (dx_m, dy_m) = (filtered.dx_m, filtered.dy_m);
    let nan_count = h.iter().filter(|v| v.is_nan()).count();
    if nan_count == h.len() {
        return Err(SurfaceError::Input("every point of the map is NaN".into()).into());
    }
    let nan_fraction = nan_count as f64 / h.len() as f64;
    let largest_m = h
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    // A plane fitted to a periodic map removes a sawtooth that is not part
    // of it: power leaks into every q along the tilt's direction and the
    // fitted Hurst exponent falls (0.70 → 0.66 on a 1024² map). Periodic
    // maps only lose their mean.
    let detrend = if p.periodic { Detrend::Mean } else { p.detrend };
    match detrend {
        Detrend::Plane => {
            let fit = plane::fit_plane(&h).ok_or_else(|| {
                SurfaceError::Input("too few measured points to fit a plane".into())
            })?;
            plane::subtract(&mut h, &fit);
        }
        Detrend::Mean => {
            let valid = h.iter().filter(|v| !v.is_nan());
            let mean = valid.clone().sum::<f64>() / valid.count() as f64;
            h.mapv_inplace(|v| v - mean);
        }
    }
    let sigma_m = sigma(&h);
    let slope = rms_slope(&h, dx_m, dy_m);
    let overflow = |quantity| SurfaceError::Overflow {
        map: source.to_owned(),
        largest_m,
        quantity,
    };
    if !(largest_m.is_finite() && sigma_m.is_finite()) {
        return Err(overflow("its mean square (σ²)").into());
    }
    if !slope.is_finite() {
        return Err(overflow("its mean square slope").into());
    }
    if sigma_m.is_nan() || sigma_m <= FLAT_RELATIVE * largest_m {
        return Err(SurfaceError::Flat {
            map: source.to_owned(),
            sigma_m,
            largest_m,
        }
        .into());
    }

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
    let sx = psd_x(&filled, dx_m, window, per_decade);
    let sy = psd_y(&filled, dy_m, window, per_decade);
    let sr = psd_radial(&filled, dx_m, dy_m, window, per_decade);
    drop(filled);
    // Inf in a spectrum would be dropped by the Hurst fit, which would
    // then blame its wavelength range.
    if [&sx, &sy, &sr]
        .iter()
        .any(|s| s.c.iter().any(|c| !c.is_finite()))
    {
        return Err(overflow("its power spectrum").into());
    }
    progress.inc(1);
    let (lx, ly) = (nx as f64 * dx_m, ny as f64 * dy_m);
    let directions = [
        ("x", Dimension::Profile),
        ("y", Dimension::Profile),
        ("radial", Dimension::Areal),
    ];
    let fits = [
        hurst(&sx, "x", (dx_m, lx), p)?,
        hurst(&sy, "y", (dy_m, ly), p)?,
        hurst(&sr, "radial", (dx_m.max(dy_m), lx.min(ly)), p)?,
    ];
    for note in fits.iter().filter_map(|f| f.1.as_deref()) {
        ctx.note(note);
    }
    let fits = fits.map(|f| f.0);
    for ((direction, dimension), fit) in directions.iter().zip(&fits) {
        if let Some(warning) = hurst_warning(direction, fit, *dimension) {
            ctx.note(&warning);
        }
    }
    let [hurst_x, hurst_y, hurst_radial] = [0, 1, 2].map(|k| fits[k].hurst(directions[k].1));
    let column = |f: fn(&PowerLaw) -> f64| [0, 1, 2].map(|k| vec![f(&fits[k])]);
    let [r2_x, r2_y, r2_radial] = column(|f| f.r_squared);
    let [q_min_x, q_min_y, q_min_radial] = column(|f| f.q_min_per_m);
    let [q_max_x, q_max_y, q_max_radial] = column(|f| f.q_max_per_m);
    let [flag_x, flag_y, flag_radial] =
        [0, 1, 2].map(|k| vec![fits[k].flag(directions[k].1).text().to_owned()]);

    let reference = match p.reference {
        ReferenceKind::Lowest => Reference::Lowest,
        ReferenceKind::Percentile => Reference::Percentile(p.reference_percent),
    };
    let z0 = reference_height(&h, reference);
    h.mapv_inplace(|v| v - z0);

    let mut psd = PsdTable::default();
    for (direction, spectrum) in [("x", &sx), ("y", &sy), ("radial", &sr)] {
        psd.push(direction, spectrum);
    }
    let stats = StatsTable {
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
        nx: vec![nx as i64],
        ny: vec![ny as i64],
        dx_m: vec![dx_m],
        dy_m: vec![dy_m],
        nx_measured: vec![measured.nx as i64],
        ny_measured: vec![measured.ny as i64],
        dx_measured_m: vec![measured.dx_m],
        dy_measured_m: vec![measured.dy_m],
        nan_fraction: vec![nan_fraction],
        fill: vec![p.fill.to_string()],
        filled_points: vec![nan_count as i64],
        filled_fraction: vec![nan_fraction],
    };
    progress.inc(1);
    Ok(Analysis {
        height: Field::new(h, dx_m, dy_m).map_err(StageError::other)?,
        psd,
        stats,
    })
}

impl Stage for Surface {
    type Params = SurfaceParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    /// Parallel over its work (rayon): a few cores pay off on a cluster.
    fn resources(&self) -> hypercontact_core::Resources {
        hypercontact_core::Resources::PARALLEL
    }

    fn run(
        &self,
        p: &Checked<SurfaceParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let given = [
            inputs.get("tiles").is_some(),
            p.dir.is_some(),
            inputs.get("height").is_some(),
            !p.tile_files.is_empty(),
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(StageError::invalid(
                "surface: give exactly one source: input `tiles`, parameter `dir`, parameter \
                 `tile_files` or input `height`",
            ));
        }
        if p.positions.is_some() && p.tile_files.is_empty() {
            return Err(StageError::invalid(
                "surface: parameter `positions` goes with `tile_files` (a folder or a `tiles` \
                 input holds its own positions.csv)",
            ));
        }
        let (map, stitch_table, source) = if inputs.get("height").is_some() {
            let map = inputs.field("height")?.clone();
            (map, StitchTable::default(), "input `height`".to_owned())
        } else if !p.tile_files.is_empty() {
            let files = listed_tiles(&p.tile_files, p.positions.as_ref())?;
            let source = FileSource::Files {
                files: &files,
                input: "tile_files".into(),
            };
            let (map, table) = stitched(&read_tiles(&source)?, p, ctx)?;
            (map, table, "the map stitched from `tile_files`".to_owned())
        } else {
            let source = FileSource::input_or_dir(inputs, "tiles", "dir", p.dir.as_ref())?;
            let (map, table) = stitched(&read_tiles(&source)?, p, ctx)?;
            let named = match &source {
                FileSource::Files { input, .. } => format!("the map stitched from input `{input}`"),
                FileSource::Dir(dir) => format!("the map stitched from {}", dir.display()),
            };
            (map, table, named)
        };
        let analysis = analyse_named(map, &source, p, ctx)?;
        Ok(Outputs::new()
            .field("height", analysis.height)
            .table("psd", analysis.psd.into_table())
            .table("stats", analysis.stats.into_table())
            .table("stitch", stitch_table.into_table()))
    }
}

/// The files of `tile_files` (and `positions`, as positions.csv) as one
/// tile set, each by its file name; two files of one name are an error.
fn listed_tiles(
    paths: &[InputPath],
    positions: Option<&InputPath>,
) -> Result<hypercontact_core::Files, StageError> {
    let mut files = hypercontact_core::Files::new();
    for path in paths {
        let name = path
            .path()
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .ok_or_else(|| StageError::file(path.path(), "names no file"))?;
        if name == crate::tiles::POSITIONS || files.files.contains_key(&name) {
            return Err(StageError::file(
                path.path(),
                format!(
                    "another file of `tile_files` is also called {name}: tiles are named by \
                     their file names"
                ),
            ));
        }
        let bytes = hypercontact_core::regular_file::read_regular_file(path.path())?;
        files = files.with(&name, bytes);
    }
    if let Some(positions) = positions {
        let bytes = hypercontact_core::regular_file::read_regular_file(positions.path())?;
        files = files.with(crate::tiles::POSITIONS, bytes);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

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
