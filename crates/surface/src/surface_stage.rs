//! Stage `surface`: interferometer tiles → stitched, filtered height map,
//! PSDs (x, y, radial), statistics and Hurst exponents. This file declares
//! the stage and finds its map (stitched here, or given); [`crate::analysis`]
//! analyses it.

use hypercontact_core::{
    Arity, Checked, Choice, Context, InputPath, InputSpec, Inputs, OutputSpec, Outputs, ParamError,
    Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_labfiles::FileSource;

pub use crate::analysis::{
    Analysis, FLAT_RELATIVE, MeasuredMap, analyse, analyse_measured, analyse_named,
};
use crate::blend::StitchedRows;
use crate::line::LineAxis;
use crate::stitch::{covered_region, place};
use crate::tiles::read_tiles;

pub use crate::surface_tables::{
    AcfTable, ArealTable, DistributionsTable, MaterialRatioTable, PsdTable, ScaleDependentTable,
    StatsTable, StitchTable,
};

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
    /// lateral resolution and new grid spacing; 0 (the default) keeps the measured grid (the paper's pipelines set 20e-6)
    #[param(default = 0.0, unit = "m", range = 0.0..)]
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
    /// bins of each histogram of output `distributions` (height, slope, curvature)
    #[param(default = 64, range = 1..=4096)]
    pub histogram_bins: usize,
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
    version: 6,
    summary: "Stitch interferometer tiles, filter to a lateral resolution, PSD, σ and Hurst exponent, ISO 25178 parameters, ACF, distributions",
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
          weight was measured); resolution_m: 0, the default, keeps the grid: no lab map is \
          filtered unless the pipeline says so (the paper's pipelines set its 20 µm). A note gives \
          the grid before and after (also in stats: nx_measured, ny_measured, dx_measured_m, \
          dy_measured_m against nx, ny, dx_m, dy_m), and a note starting with \"warning:\" when the \
          filter keeps under 10 % of the measured points, and another when it discards more than \
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
          √⟨|∇h|²⟩ by forward differences. AREAL (ISO 25178-2, of the detrended map about its \
          mean plane, measured points only): Sa, Sq, Ssk, Sku, Sp, Sv, Sz; Sdq (as rms_slope); Sdr \
          (cells with four measured corners, the two triangulations averaged); Sal and Str from \
          the areal autocorrelation (FFT, normalised by the overlap count, mean removed) at s = \
          0.2, searched along 360 directions out to half the map (Str is an upper bound where \
          some direction never decays there); Sk, Spk, Svk, Smr1, Smr2 of ISO 13565-2 (the \
          equivalence line is the 40 % secant of least slope); the correlation length where the \
          radially averaged ACF falls to 1/e. They match SurfaceTopography 1.27 to 1e-9 where it \
          defines the same quantity (Sq, Sa, Ssk, Sku, Sp, Sv, the ACF); its Sdq differs on maps \
          with holes (it drops points next to holes). `material_ratio` is the Abbott-Firestone \
          curve at every whole per cent. Parameters are of the map analysed: after the filter, \
          if any. `acf`: the normalised ACF (as for Sal) radially averaged over the lags \
          within the search ellipse (rings one finer spacing wide, each at the mean |τ| of its \
          lags: direction radial), and along the x and y axes out to ⌊(n − 1)/2⌋ pixels \
          (directions x, y); NaN where no pair of measured points lies that far apart. \
          `distributions`: histograms (histogram_bins equal-width bins from the smallest to the \
          largest value) of the height about the mean plane (m), the slope |∇h| (1) and the \
          curvature ∇²h/2 (1/m), both by central differences at the points whose four \
          neighbours are measured (the map's edge left out); each row gives its unit, the \
          count and the density count/(points · bin width). `scale_dependent` (variable \
          bandwidth, SurfaceTopography's scale_dependent_statistical_property): at scales \
          k·Δ, k = 1, 2, 4, … ≤ ⌊(min(nx, ny) − 1)/2⌋, Δ = (dx + dy)/2, the rms slope \
          ⟨gx² + gy²⟩^½ with gx = (h[i+k, j] − h[i, j])/(k·dx), gy likewise, averaged where both exist (k = 1: SurfaceTopography's \
          rms_gradient; Sdq averages gx² and gy² apart), and \
          the rms curvature ∇²h/2 by central second differences of step k/2 (a stencil k \
          pixels long; none at k = 1), over the points whose stencil is measured; NaN for \
          fewer than 4 values. Of a self-affine map the slope goes as scale^(H−1), the \
          curvature as scale^(H−2). HURST: least squares of ln C on ln q, C ∝ q^(−1−2H) \
          (1-D) and q^(−2−2H) (radial), over wavelengths hurst_lambda_min_m … hurst_lambda_max_m \
          (default 4·dx … L/4; on a map this stage filtered, from the wavelength where the \
          Gaussian still passes 90 % of the power, 3.6 cut-offs = 7.3·resolution_m, so the filter's \
          roll-off does not steepen the slope). Each fit reports its R² (ln C on ln q) and the q \
          range of the bins it used (hurst_*_r2, hurst_*_q_min_per_m, hurst_*_q_max_per_m) and a \
          flag (hurst_*_flag): \"poor power law (R² < 0.9)\" first, else \"outside 0…1\", else \
          \"ok\"; a flagged fit also gets a note starting with \"warning:\". \
          LINE SCANS: a map one point across (n x 1: a profile along x; 1 x n: along y), e.g. \
          a stylus profile, is analysed as the profile it is (a note says so): the filter is \
          the same Gaussian along the line (ISO 16610-21's profile filter, cut-off \
          2·resolution_m; resolution_m is judged against the spacing along the line); \
          `detrend: plane` removes the least-squares line, `mean` the mean; missing points \
          are filled by linear interpolation between measured neighbours (the harmonic \
          in-fill in 1-D; ends held at the nearest measured height, a periodic profile \
          interpolated across the wrap), max_missing_fraction applies; the PSD along the \
          line is the x PSD's (same normalisation, window and bins; equal to the x PSD of a \
          map of identical copies of the line) and its Hurst exponent goes in hurst_x (or \
          hurst_y); the other direction and radial have no PSD rows, NaN exponents and the \
          flag \"not defined (line scan)\"; sigma_m is the profile's Rq and rms_slope its \
          forward-difference rms slope; the `areal` table holds the profile parameters of the \
          same definitions: Ra, Rq, Rsk, Rku, Rp, Rv, Rz (ISO 4287) in Sa … Sz, Rdq in Sdq, \
          Rk, Rpk, Rvk, Mr1, Mr2 (ISO 13565-2) in Sk … Smr2, the lag where the profile's \
          autocorrelation falls to 0.2 in Sal and to 1/e in the correlation length; Sdr and \
          Str need an area and are NaN; `distributions` holds the height histogram only, `acf` \
          the autocorrelation along the line (direction x or y), `scale_dependent` is empty \
          (slope and curvature statistics are areal). Tiles that are line scans are not stitched (one \
          line scan alone is analysed). The stages that need a 2-D map (truncation, bem, \
          fem, crop, persson, greenwood-williamson, synth-contact, contact-compare) refuse a \
          line scan, naming themselves.",
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
        OutputSpec::table::<ArealTable>("areal", "one row: ISO 25178-2 areal parameters"),
        OutputSpec::table::<MaterialRatioTable>(
            "material_ratio",
            "the Abbott-Firestone curve at every whole per cent",
        ),
        OutputSpec::table::<DistributionsTable>(
            "distributions",
            "histograms of height, slope and curvature (long format)",
        ),
        OutputSpec::table::<AcfTable>(
            "acf",
            "the autocorrelation radially averaged and along x and y, against lag",
        ),
        OutputSpec::table::<ScaleDependentTable>(
            "scale_dependent",
            "rms slope and rms curvature against scale",
        ),
    ],
};

/// The analysis of the map stitched from the tiles of `source` (named
/// `named` in errors), and the stitch table. The tiles stay views of the
/// source's bytes where they can, and the mosaic is made a band of rows at
/// a time as the filter reads it: neither is ever copied whole (#35).
fn analysed_tiles(
    source: &FileSource,
    named: &str,
    p: &Checked<SurfaceParams>,
    ctx: &Context,
) -> Result<(Analysis, StitchTable), StageError> {
    let set = read_tiles(source)?;
    if set.heights.len() > 1
        && let Some((name, heights)) = set
            .names
            .iter()
            .zip(&set.heights)
            .find(|(_, h)| LineAxis::of(h.nrows(), h.ncols()).is_some())
    {
        return Err(StageError::invalid(format!(
            "surface: tile {name} of {named} is a line scan ({} × {} points): stitching needs \
             2-D tiles; give each line scan alone (input `height`, or a one-tile set)",
            heights.nrows(),
            heights.ncols()
        )));
    }
    let progress = ctx.progress(1, "stitch tiles");
    let (placement, tiles) = place(&set, p.min_overlap_px)?;
    progress.inc(1);
    let region = covered_region(&placement.covered());
    let rows = StitchedRows {
        set: &set,
        placement: &placement,
        region,
    };
    let map = MeasuredMap::Rows {
        rows: &rows,
        dx_m: set.pixel_m,
        dy_m: set.pixel_m,
    };
    let analysis = analyse_measured(map, named, p, ctx)?;
    Ok((analysis, StitchTable::new(&set, &tiles)))
}

impl Stage for Surface {
    type Params = SurfaceParams;
    /// Parallel (rayon) over its work: a few cores pay off on a cluster.
    const RESOURCES: hypercontact_core::Resources = hypercontact_core::Resources::PARALLEL;

    fn info(&self) -> &'static StageInfo {
        &INFO
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
        let (analysis, stitch_table) = if inputs.get("height").is_some() {
            // Read a row at a time: the filter then never copies the input.
            let field = inputs.field("height")?;
            let view = field.values.view();
            let map = MeasuredMap::Rows {
                rows: &view,
                dx_m: field.dx_m,
                dy_m: field.dy_m,
            };
            let analysis = analyse_measured(map, "input `height`", p, ctx)?;
            (analysis, StitchTable::default())
        } else if !p.tile_files.is_empty() {
            let files = listed_tiles(&p.tile_files, p.positions.as_ref())?;
            let source = FileSource::Files {
                files: &files,
                input: "tile_files".into(),
            };
            analysed_tiles(&source, "the map stitched from `tile_files`", p, ctx)?
        } else {
            let source = FileSource::input_or_dir(inputs, "tiles", "dir", p.dir.as_ref())?;
            let named = match &source {
                FileSource::Files { input, .. } => format!("the map stitched from input `{input}`"),
                FileSource::Dir(dir) => format!("the map stitched from {}", dir.display()),
            };
            analysed_tiles(&source, &named, p, ctx)?
        };
        Ok(Outputs::new()
            .field("height", analysis.height)
            .table("psd", analysis.psd.into_table())
            .table("stats", analysis.stats.into_table())
            .table("stitch", stitch_table.into_table())
            .table("areal", analysis.areal.into_table())
            .table("material_ratio", analysis.material_ratio.into_table())
            .table("distributions", analysis.distributions.into_table())
            .table("acf", analysis.acf.into_table())
            .table("scale_dependent", analysis.scale_dependent.into_table()))
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
