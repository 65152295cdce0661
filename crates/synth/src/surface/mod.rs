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
    Checked, ColumnSpec, Context, Field, Files, Inputs, OutputSpec, Outputs, ParamError,
    ProductKind, Stage, StageError, StageInfo, Table, params,
};

pub use scan::{ScanPlan, ScannedTile};
pub use self_affine::SelfAffine;

/// Parameters of `synth-surface`; defaults are CI-sized (3 × 3 tiles of
/// 256² px), the paper's scale is `tile_px: 1024, tiles_x: 10, tiles_y: 10`.
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

/// Largest generated grid side: the Fourier synthesis holds about three
/// arrays of this side squared (8 bytes each) at once.
const MAX_GRID_SIDE: usize = 20_000;

/// Checks across parameters: the band is ordered and resolved, the sample fits.
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
    Ok(())
}

/// The `synth-surface` stage.
pub struct SynthSurface;

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
        OutputSpec {
            name: "tiles",
            kind: ProductKind::Files,
            columns: &[],
            doc: "tile_NNN.npy (metres, axis 0 = x, NaN dropouts) and positions.csv",
        },
        OutputSpec {
            name: "truth",
            kind: ProductKind::Field,
            columns: &[],
            doc: "the true surface over the scanned area (pixel [0, 0] at the smallest true tile position)",
        },
        OutputSpec {
            name: "truth_offsets",
            kind: ProductKind::Table,
            columns: &[
                ColumnSpec::i64("tile", "", "tile number, scan order"),
                ColumnSpec::str("file", "tile file name"),
                ColumnSpec::f64("x_offset_px", "px", "true minus nominal position along x"),
                ColumnSpec::f64("y_offset_px", "px", "true minus nominal position along y"),
                ColumnSpec::i64("x_truth_px", "px", "the tile's pixel [0, 0] in `truth`, x"),
                ColumnSpec::i64("y_truth_px", "px", "the tile's pixel [0, 0] in `truth`, y"),
                ColumnSpec::f64(
                    "tilt_x_rad",
                    "rad",
                    "added slope along x about the tile centre",
                ),
                ColumnSpec::f64(
                    "tilt_y_rad",
                    "rad",
                    "added slope along y about the tile centre",
                ),
                ColumnSpec::f64("piston_m", "m", "added constant height"),
            ],
            doc: "the truth about each tile",
        },
    ],
};

/// The smallest n ≥ `min` of the form 2^a 3^b 5^c, a size FFTs handle fast.
fn fast_size(min: usize) -> usize {
    let mut n = min.max(1);
    loop {
        let mut m = n;
        for p in [2, 3, 5] {
            while m.is_multiple_of(p) {
                m /= p;
            }
        }
        if m == 1 {
            return n;
        }
        n += 1;
    }
}

/// The tiles, the truth and the truth table, as library calls can use them.
pub struct SynthScan {
    pub tiles: Vec<ScannedTile>,
    pub truth: Field,
}

/// Generates the sample and scans it.
pub fn synthesise(p: &Checked<SynthSurfaceParams>) -> Result<SynthScan, StageError> {
    let plan = ScanPlan {
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
    };
    let (offsets, origin, size) = plan.layout();
    // Padding by at least the roll-off wavelength (and a quarter of the
    // sample) decorrelates opposite edges: the crop is not periodic.
    let pad = ((p.lambda_max_m / p.pixel_m).ceil() as usize).max(size[0].max(size[1]) / 4);
    let (gx, gy) = (fast_size(size[0] + pad), fast_size(size[1] + pad));
    if gx.max(gy) > MAX_GRID_SIDE {
        return Err(StageError::invalid(format!(
            "parameter `lambda_max_m`: the generated grid would be {gx} × {gy} px, more than \
             {MAX_GRID_SIDE} px a side; lower lambda_max_m or the number of tiles"
        )));
    }
    let spectrum = SelfAffine {
        hurst: p.hurst,
        rms_m: p.rms_m,
        lambda_min_m: p.lambda_min_m,
        lambda_max_m: p.lambda_max_m,
    };
    let periodic = spectrum.periodic(gx, gy, p.pixel_m, p.seed);
    let truth = ndarray::Array2::from_shape_fn((size[0], size[1]), |(i, j)| periodic[[i, j]]);
    drop(periodic);
    let tiles = plan.scan(&truth, &offsets, origin);
    let truth = Field::new(truth, p.pixel_m, p.pixel_m).map_err(StageError::other)?;
    Ok(SynthScan { tiles, truth })
}

/// The file name of tile `t`.
pub fn tile_file(t: usize) -> String {
    format!("tile_{t:03}.npy")
}

impl SynthScan {
    /// The `tiles` product: tile_NNN.npy files and positions.csv.
    pub fn files(&self) -> Result<Files, StageError> {
        let pixel_m = self.truth.dx_m;
        let mut files = Files::new();
        let mut csv = format!("{POSITIONS_COLUMNS}\n");
        for (t, tile) in self.tiles.iter().enumerate() {
            let name = tile_file(t);
            let mut npy = Vec::new();
            Field::new(tile.heights.clone(), pixel_m, pixel_m)
                .and_then(|f| f.write_npy(&mut npy))
                .map_err(StageError::other)?;
            files.files.insert(name.clone(), npy);
            csv.push_str(&format!(
                "{t},{name},{},{},{pixel_m}\n",
                tile.nominal_px[0] as f64 * pixel_m,
                tile.nominal_px[1] as f64 * pixel_m
            ));
        }
        files
            .files
            .insert("positions.csv".to_owned(), csv.into_bytes());
        Ok(files)
    }

    /// The `truth_offsets` table.
    pub fn truth_table(&self) -> Table {
        let col_f =
            |f: &dyn Fn(&ScannedTile) -> f64| -> Vec<f64> { self.tiles.iter().map(f).collect() };
        let col_i =
            |f: &dyn Fn(&ScannedTile) -> i64| -> Vec<i64> { self.tiles.iter().map(f).collect() };
        Table::new()
            .with("tile", (0..self.tiles.len() as i64).collect::<Vec<i64>>())
            .with(
                "file",
                (0..self.tiles.len())
                    .map(tile_file)
                    .collect::<Vec<String>>(),
            )
            .with("x_offset_px", col_f(&|t| t.offset_px[0] as f64))
            .with("y_offset_px", col_f(&|t| t.offset_px[1] as f64))
            .with("x_truth_px", col_i(&|t| t.truth_px[0] as i64))
            .with("y_truth_px", col_i(&|t| t.truth_px[1] as i64))
            .with("tilt_x_rad", col_f(&|t| t.tilt_rad[0]))
            .with("tilt_y_rad", col_f(&|t| t.tilt_rad[1]))
            .with("piston_m", col_f(&|t| t.piston_m))
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
        let files = scan.files()?;
        let table = scan.truth_table();
        progress.inc(1);
        Ok(Outputs::new()
            .files("tiles", files)
            .table("truth_offsets", table)
            .field("truth", scan.truth))
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
        truth.conform(INFO.outputs[2].columns).unwrap();
        assert_eq!(truth.n_rows(), 9);
        let Some(Product::Field(surface)) = out.get("truth") else {
            panic!("no truth field")
        };
        // The truth spans the tiles: at least 2 steps plus a tile.
        assert!(surface.nx() >= 2 * 218 + 256 - 20);
        assert!(surface.values.iter().all(|h| h.is_finite()));
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
    }

    #[test]
    fn fast_sizes_have_small_factors() {
        assert_eq!(fast_size(1), 1);
        assert_eq!(fast_size(7), 8);
        assert_eq!(fast_size(1025), 1080);
    }
}
