//! Stage `synth-surface`: interferometer tiles of a synthetic self-affine
//! sample, with the ground truth that made them.
//!
//! Output conventions (shared with real data, read by the `surface` stage):
//! `tiles` holds `tile_000.npy`, `tile_001.npy`, … (float64, metres, axis 0 =
//! x, NaN at dropouts) and `positions.csv` (`tile, file, x_m, y_m, pixel_m`:
//! the nominal position of each tile's pixel [0, 0] as the scanner records
//! it). The ground truth is in separate outputs the surface stage never reads.

pub mod scan;
pub mod self_affine;

use hypercontact_core::{
    Checked, Context, Field, Files, Inputs, OutputSpec, Outputs, ParamError, Schema, Stage,
    StageError, StageInfo, params,
};

pub use scan::{ScanPlan, ScannedTile};
pub use self_affine::SelfAffine;

/// Parameters of `synth-surface` (CI-sized defaults; the stage doc gives the
/// paper's scale).
#[params(check = consistent)]
pub struct SynthSurfaceParams {
    /// Hurst exponent H
    #[param(default = 0.8, range = 0.0..=1.0)]
    pub hurst: f64,
    /// expected rms height of the generated surface
    #[param(default = 5e-6, unit = "m", positive)]
    pub rms_m: f64,
    /// short-wavelength cut-off (no power below)
    #[param(default = 5e-6, unit = "m", positive)]
    pub lambda_min_m: f64,
    /// long-wavelength roll-off (flat PSD above)
    #[param(default = 200e-6, unit = "m", positive)]
    pub lambda_max_m: f64,
    /// tile side in pixels
    #[param(default = 256, unit = "px", range = 16..)]
    pub tile_px: usize,
    /// pixel size (the paper's field of view, 1047.9 µm, on 1024 pixels)
    #[param(default = 1047.9e-6 / 1024.0, unit = "m", positive)]
    pub pixel_m: f64,
    /// tiles along x
    #[param(default = 3, range = 1..=1000)]
    pub tiles_x: usize,
    /// tiles along y
    #[param(default = 3, range = 1..=1000)]
    pub tiles_y: usize,
    /// overlap of neighbouring tiles, fraction of the side
    #[param(default = 0.15, range = 0.0..=0.9)]
    pub overlap: f64,
    /// std of the stage-position error
    #[param(default = 3.0, unit = "px", range = 0.0..=1e3)]
    pub position_error_px: f64,
    /// std of the measurement noise
    #[param(default = 2e-9, unit = "m", range = 0.0..)]
    pub noise_m: f64,
    /// share of dropout (NaN) pixels
    #[param(default = 0.02, range = 0.0..=0.5)]
    pub dropout_fraction: f64,
    /// std of each tile's tilt
    #[param(default = 1e-3, unit = "rad", range = 0.0..=0.1)]
    pub tilt_rad: f64,
    /// std of each tile's piston offset
    #[param(default = 1e-6, unit = "m", range = 0.0..)]
    pub piston_m: f64,
    /// random seed
    #[param(default = 1)]
    pub seed: u64,
}

/// Largest generated grid side: the Fourier synthesis holds one half
/// spectrum of the grid, 8 bytes per grid point (3.2 GB at this side).
const MAX_GRID_SIDE: usize = 20_000;

/// Checks across parameters: the band is ordered and resolved, the sample
/// and the grid it is generated on fit (so `synthesise` cannot fail on size).
fn consistent(p: &SynthSurfaceParams) -> Result<(), ParamError> {
    if p.lambda_min_m >= p.lambda_max_m {
        return Err(ParamError::new(
            "lambda_min_m",
            format!(
                "must be below lambda_max_m ({} m), got {} m",
                p.lambda_max_m, p.lambda_min_m
            ),
        ));
    }
    if p.lambda_min_m < 2.0 * p.pixel_m {
        return Err(ParamError::new(
            "lambda_min_m",
            format!(
                "must be at least two pixels (2 × pixel_m = {} m), got {} m",
                2.0 * p.pixel_m,
                p.lambda_min_m
            ),
        ));
    }
    let side = p.tile_px as f64 * p.tiles_x.max(p.tiles_y) as f64;
    if side * 1.5 > MAX_GRID_SIDE as f64 {
        return Err(ParamError::new(
            "tiles_x",
            format!(
                "the sample would span about {side} px, more than this generator holds \
                 ({MAX_GRID_SIDE} px with padding)"
            ),
        ));
    }
    let [gx, gy] = grid_px(p, scan_plan(p).layout().2);
    if gx.max(gy) > MAX_GRID_SIDE {
        return Err(ParamError::new(
            "lambda_max_m",
            format!(
                "the generated grid would be {gx} × {gy} px, more than {MAX_GRID_SIDE} px a \
                 side; lower lambda_max_m or the number of tiles"
            ),
        ));
    }
    representable(p, [gx, gy])
}

/// The heights must stay inside f64 through the synthesis. Its prefactor
/// C0 = rms² · Lx · Ly / Σ shape(q) is at most rms² · Lx · Ly · q_r^(2+2H)
/// (the sum holds at least one point of the roll-off plateau, shape = q_r^(−2−2H)),
/// and the Fourier gain multiplies C0 · shape by Lx · Ly again, at most
/// rms² · (Lx · Ly)². Past either bound the heights came out NaN, and the
/// `surface` stage blamed its tiles.
fn representable(p: &SynthSurfaceParams, [gx, gy]: [usize; 2]) -> Result<(), ParamError> {
    let (lx, ly) = (gx as f64 * p.pixel_m, gy as f64 * p.pixel_m);
    let q_roll = std::f64::consts::TAU / p.lambda_max_m;
    let mean_square = p.rms_m * p.rms_m;
    let prefactor = mean_square * lx * ly * q_roll.powf(2.0 + 2.0 * p.hurst);
    let gain = mean_square * (lx * ly) * (lx * ly);
    let grid = format!(
        "the {gx} × {gy} px grid of pixel_m = {:e} m (Lx × Ly = {lx:e} m × {ly:e} m)",
        p.pixel_m
    );
    if !(prefactor.is_finite() && gain.is_finite()) {
        return Err(ParamError::new(
            "rms_m",
            format!(
                "{:e} m is too large for f64 on {grid}: the spectrum's prefactor \
                 rms_m² · Lx · Ly · (2π/lambda_max_m)^(2+2H) = {prefactor:e} and the Fourier \
                 gain rms_m² · (Lx · Ly)² = {gain:e} must stay finite; lower rms_m (or pixel_m, \
                 or the number of tiles)",
                p.rms_m
            ),
        ));
    }
    if mean_square < f64::MIN_POSITIVE {
        return Err(ParamError::new(
            "rms_m",
            format!(
                "{:e} m is too small for f64: rms_m² = {mean_square:e} m² underflows, the \
                 heights would all be 0",
                p.rms_m
            ),
        ));
    }
    Ok(())
}

/// The side of the periodic grid the surface is generated on, per axis,
/// for a scanned area of `size` px. Padding by at least the roll-off
/// wavelength (and a quarter of the area) decorrelates opposite edges, so
/// the crop is not periodic; sides past `MAX_GRID_SIDE` are not rounded up.
fn grid_px(p: &SynthSurfaceParams, size: [usize; 2]) -> [usize; 2] {
    let pad = ((p.lambda_max_m / p.pixel_m).ceil() as usize).max(size[0].max(size[1]) / 4);
    size.map(|n| match n.saturating_add(pad) {
        n if n > MAX_GRID_SIDE => n,
        n => hypercontact_numeric::fft2::fast_size(n),
    })
}

fn scan_plan(p: &SynthSurfaceParams) -> ScanPlan {
    ScanPlan {
        tile_px: p.tile_px,
        tiles_x: p.tiles_x,
        tiles_y: p.tiles_y,
        overlap: p.overlap,
        position_error_px: p.position_error_px,
        noise_m: p.noise_m,
        dropout_fraction: p.dropout_fraction,
        tilt_rad: p.tilt_rad,
        piston_m: p.piston_m,
        pixel_m: p.pixel_m,
        seed: p.seed,
    }
}

/// The `synth-surface` stage.
pub struct SynthSurface;

/// The `truth_offsets` table: one row per tile, scan order.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct TruthOffsets {
    /// tile number, scan order
    pub tile: Vec<i64>,
    /// tile file name
    pub file: Vec<String>,
    /// true minus nominal position along x
    #[column(unit = "px")]
    pub x_offset_px: Vec<f64>,
    /// true minus nominal position along y
    #[column(unit = "px")]
    pub y_offset_px: Vec<f64>,
    /// the tile's pixel [0, 0] in `truth`, x
    #[column(unit = "px")]
    pub x_truth_px: Vec<i64>,
    /// the tile's pixel [0, 0] in `truth`, y
    #[column(unit = "px")]
    pub y_truth_px: Vec<i64>,
    /// added slope along x about the tile centre
    #[column(unit = "rad")]
    pub tilt_x_rad: Vec<f64>,
    /// added slope along y about the tile centre
    #[column(unit = "rad")]
    pub tilt_y_rad: Vec<f64>,
    /// added constant height
    #[column(unit = "m")]
    pub piston_m: Vec<f64>,
}

const POSITIONS_COLUMNS: &str = "tile,file,x_m,y_m,pixel_m";

static INFO: StageInfo = StageInfo {
    kind: "synth-surface",
    version: 1,
    summary: "Synthetic interferometer tiles of a self-affine surface, with the ground truth",
    doc: "A self-affine random surface by Fourier filtering (isotropic 2-D PSD C ∝ q^(−2−2H) between \
          q_r = 2π/lambda_max_m and q_s = 2π/lambda_min_m, flat below q_r, zero above q_s; normalised \
          as in SurfaceTopography so Σ C/(Lx·Ly) = rms_m²), generated periodic on a grid larger than \
          the sample and cropped, so the sample is not periodic. It is scanned as a white-light \
          interferometer would: square tiles of tile_px × tile_px on a grid with the given overlap \
          (scan order x fastest), each displaced from its nominal position by a Gaussian error \
          (position_error_px, rounded to whole pixels), with its own tilt (about the tile centre) and \
          piston, Gaussian noise (noise_m) and dropout pixels (NaN). Output `tiles`: tile_NNN.npy \
          (float64, metres, axis 0 = x) and positions.csv (tile, file, x_m, y_m, pixel_m: the nominal \
          position of pixel [0, 0]). Ground truth: `truth` (the surface over the scanned area, no \
          noise, no tilt) and `truth_offsets`. Defaults are small; the paper's scale is tile_px: 1024, \
          tiles_x: 10, tiles_y: 10.",
    inputs: &[],
    outputs: &[
        OutputSpec::files(
            "tiles",
            "tile_NNN.npy (metres, axis 0 = x, NaN dropouts) and positions.csv",
        ),
        OutputSpec::field(
            "truth",
            "the true surface over the scanned area (pixel [0, 0] at the smallest true tile position)",
        ),
        OutputSpec::table::<TruthOffsets>("truth_offsets", "the truth about each tile"),
    ],
};

/// The tiles, the truth and the truth table, as library calls can use them.
pub struct SynthScan {
    pub tiles: Vec<ScannedTile>,
    pub truth: Field,
}

/// Generates the sample and scans it.
pub fn synthesise(p: &Checked<SynthSurfaceParams>) -> Result<SynthScan, StageError> {
    let plan = scan_plan(p);
    let (offsets, origin, size) = plan.layout();
    let [gx, gy] = grid_px(p, size);
    let spectrum = SelfAffine {
        hurst: p.hurst,
        rms_m: p.rms_m,
        lambda_min_m: p.lambda_min_m,
        lambda_max_m: p.lambda_max_m,
    };
    // Only the scanned corner of the periodic grid is ever held.
    let truth = spectrum
        .periodic_corner(gx, gy, p.pixel_m, p.seed, size)
        .map_err(StageError::other)?;
    let tiles = plan.scan(&truth, &offsets, origin);
    let truth = Field::new(truth, p.pixel_m, p.pixel_m).map_err(StageError::other)?;
    Ok(SynthScan { tiles, truth })
}

/// The file name of tile `t`.
pub fn tile_file(t: usize) -> String {
    format!("tile_{t:03}.npy")
}

/// tile_NNN.npy and positions.csv of the tiles (nominal position, heights)
/// in scan order, each tile's heights dropped once encoded.
fn tile_files(
    tiles: impl Iterator<Item = ([i64; 2], ndarray::Array2<f64>)>,
    pixel_m: f64,
) -> Result<Files, StageError> {
    let mut files = Files::new();
    let mut csv = format!("{POSITIONS_COLUMNS}\n");
    for (t, (nominal_px, heights)) in tiles.enumerate() {
        let name = tile_file(t);
        // A 2-D .npy header takes at most 128 bytes: one allocation a tile.
        let mut npy = Vec::with_capacity(128 + 8 * heights.len());
        Field::new(heights, pixel_m, pixel_m)
            .and_then(|f| f.write_npy(&mut npy))
            .map_err(StageError::other)?;
        files.files.insert(name.clone(), npy);
        csv.push_str(&format!(
            "{t},{name},{},{},{pixel_m}\n",
            nominal_px[0] as f64 * pixel_m,
            nominal_px[1] as f64 * pixel_m
        ));
    }
    files
        .files
        .insert("positions.csv".to_owned(), csv.into_bytes());
    Ok(files)
}

impl SynthScan {
    /// The `tiles` product: tile_NNN.npy files and positions.csv (the
    /// tiles are copied; [`Self::into_outputs`] encodes without copies).
    pub fn files(&self) -> Result<Files, StageError> {
        let tiles = self.tiles.iter().map(|t| (t.nominal_px, t.heights.clone()));
        tile_files(tiles, self.truth.dx_m)
    }

    /// The stage's three products, `tiles`, `truth_offsets` and `truth`:
    /// each tile is encoded and dropped in turn, so a tile's heights and its
    /// .npy bytes are never both alive past the one being encoded (#35).
    pub fn into_outputs(self) -> Result<Outputs, StageError> {
        let table = self.truth_table().into_table();
        let tiles = self.tiles.into_iter().map(|t| (t.nominal_px, t.heights));
        let files = tile_files(tiles, self.truth.dx_m)?;
        Ok(Outputs::new()
            .files("tiles", files)
            .table("truth_offsets", table)
            .field("truth", self.truth))
    }

    /// The `truth_offsets` table.
    pub fn truth_table(&self) -> TruthOffsets {
        let column = |f: fn(&ScannedTile) -> f64| self.tiles.iter().map(f).collect();
        let index = |f: fn(&ScannedTile) -> i64| self.tiles.iter().map(f).collect();
        TruthOffsets {
            tile: (0..self.tiles.len() as i64).collect(),
            file: (0..self.tiles.len()).map(tile_file).collect(),
            x_offset_px: column(|t| t.offset_px[0] as f64),
            y_offset_px: column(|t| t.offset_px[1] as f64),
            x_truth_px: index(|t| t.truth_px[0] as i64),
            y_truth_px: index(|t| t.truth_px[1] as i64),
            tilt_x_rad: column(|t| t.tilt_rad[0]),
            tilt_y_rad: column(|t| t.tilt_rad[1]),
            piston_m: column(|t| t.piston_m),
        }
    }
}

impl Stage for SynthSurface {
    type Params = SynthSurfaceParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<SynthSurfaceParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let progress = ctx.progress(2, "generate and scan");
        let scan = synthesise(p)?;
        progress.inc(1);
        let outputs = scan.into_outputs()?;
        progress.inc(1);
        Ok(outputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::Params;
    use hypercontact_core::Product;

    #[test]
    fn default_run_writes_tiles_positions_and_truth() {
        let p = SynthSurfaceParams::default().check().unwrap();
        let out = SynthSurface
            .run(&p, &Inputs::new(), &Context::new("t"))
            .unwrap();
        let Some(Product::Files(files)) = out.get("tiles") else {
            panic!("no tiles")
        };
        assert_eq!(files.files.len(), 10);
        let csv = String::from_utf8(files.files["positions.csv"].clone()).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0], POSITIONS_COLUMNS);
        assert_eq!(lines.len(), 10);
        // Tile 4 is the centre of the 3 × 3 grid: one step (218 px) along both.
        let step_m = 218.0 * p.pixel_m;
        let fields: Vec<&str> = lines[5].split(',').collect();
        assert_eq!(fields[1], "tile_004.npy");
        assert!((fields[2].parse::<f64>().unwrap() - step_m).abs() < 1e-15);
        let tile = Field::read_npy(files.files["tile_004.npy"].as_slice(), 1.0, 1.0).unwrap();
        assert_eq!(tile.values.dim(), (256, 256));
        let Some(Product::Table(truth)) = out.get("truth_offsets") else {
            panic!("no truth table")
        };
        let names: Vec<&str> = TruthOffsets::COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(truth.column_names(), names);
        assert_eq!(truth.n_rows(), 9);
        let offsets = TruthOffsets::from_table(truth).unwrap();
        assert_eq!(offsets.tile, (0..9).collect::<Vec<i64>>());
        assert_eq!(offsets.file[4], "tile_004.npy");
        let Some(Product::Field(surface)) = out.get("truth") else {
            panic!("no truth field")
        };
        // The truth spans the tiles: at least 2 steps plus a tile.
        assert!(surface.nx() >= 2 * 218 + 256 - 20);
        assert!(surface.values.iter().all(|h| h.is_finite()));
    }

    #[test]
    fn the_stage_outputs_are_the_copying_files_truth_table_and_truth() {
        // into_outputs consumes the tiles; files() and truth_table() keep
        // them: the products must not tell the two apart.
        let p = SynthSurfaceParams {
            tiles_x: 2,
            seed: 4,
            ..Default::default()
        }
        .check()
        .unwrap();
        let kept = synthesise(&p).unwrap();
        let out = synthesise(&p).unwrap().into_outputs().unwrap();
        assert_eq!(out.get_files("tiles"), Some(&kept.files().unwrap()));
        assert_eq!(
            out.get_table("truth_offsets"),
            Some(&kept.truth_table().into_table())
        );
        let Some(Product::Field(truth)) = out.get("truth") else {
            panic!("no truth field")
        };
        assert_eq!(truth, &kept.truth);
        assert_eq!(out.len(), 3);
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = |f: &dyn Fn(&mut SynthSurfaceParams)| {
            let mut p = SynthSurfaceParams::default();
            f(&mut p);
            p.check().unwrap_err().param
        };
        assert_eq!(bad(&|p| p.hurst = 1.5), "hurst");
        assert_eq!(bad(&|p| p.lambda_min_m = 1e-3), "lambda_min_m");
        assert_eq!(bad(&|p| p.lambda_min_m = 1e-7), "lambda_min_m");
        assert_eq!(bad(&|p| p.overlap = 0.95), "overlap");
        assert_eq!(bad(&|p| p.tiles_x = 0), "tiles_x");
        assert_eq!(bad(&|p| p.tile_px = 4), "tile_px");
        assert_eq!(bad(&|p| p.dropout_fraction = 0.9), "dropout_fraction");
        // A roll-off wavelength of 5 cm pads the grid past its largest side.
        assert_eq!(bad(&|p| p.lambda_max_m = 0.05), "lambda_max_m");
        assert_eq!(bad(&|p| p.tile_px = 5000), "tiles_x");
    }

    #[test]
    fn heights_beyond_f64_are_refused_naming_rms_m_and_the_grid() {
        // 1.5e150 m used to pass and give all-NaN tiles, which the surface
        // stage blamed on tile_000.npy.
        let p = SynthSurfaceParams {
            rms_m: 1.5e150,
            ..Default::default()
        };
        let e = p.check().unwrap_err();
        assert_eq!(e.param, "rms_m");
        assert!(
            e.message.contains("1.5e150 m is too large")
                && e.message.contains("pixel_m")
                && e.message.contains("px grid"),
            "{e}"
        );
        let p = SynthSurfaceParams {
            rms_m: 1e-200,
            ..Default::default()
        };
        let e = p.check().unwrap_err();
        assert!(e.param == "rms_m" && e.message.contains("too small"), "{e}");
        // Just inside the bound the heights are finite.
        let p = SynthSurfaceParams {
            rms_m: 1e148,
            ..Default::default()
        }
        .check()
        .unwrap();
        let scan = synthesise(&p).unwrap();
        assert!(scan.truth.values.iter().all(|h| h.is_finite()));
    }
}
