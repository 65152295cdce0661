//! Stage `dic`: stretch and strain per frame of a tensile test, and force
//! and nominal stress when it has a force log, from its speckle images; and
//! the full field (u, v, Green–Lagrange E, ZNCC per POI per frame).
//!
//! The gauge-section value of a frame is the deformation gradient F of the
//! least-squares affine map from the frame-0 positions of all valid points
//! (POIs or markers) to their current ones; λ along the loading axis (x, y,
//! or the final frame's major principal direction) and λ₂ across it are F's
//! principal stretches. Nominal stress is the force, interpolated at the
//! frame's time, over the undeformed cross-section (gauge width ×
//! thickness), as the paper's section 2 tests report it. This file declares
//! the stage; [`crate::analysis`] computes it.

use hypercontact_core::{
    Arity, Checked, Choice, Context, InputPath, InputSpec, Inputs, Mode, OutputSpec, Outputs,
    Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_labfiles::FileSource;

pub use crate::analysis::{Analysis, analyse};
use crate::icgn::IcgnSettings;
use crate::sequence::Sequence;
use crate::subset_tracking::SubsetSettings;

/// How points are followed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum Method {
    /// subset DIC (IC-GN) on a POI grid
    #[default]
    Subset,
    /// centroids of painted marker dots
    Markers,
}

/// The direction `stretch` is taken along.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum LoadingAxis {
    /// image x (columns)
    #[default]
    X,
    /// image y (rows)
    Y,
    /// the final frame's largest principal stretch direction
    Principal,
}

/// Parameters of `dic`.
#[params]
pub struct DicParams {
    /// how points are followed
    #[param(default = Method::Subset)]
    pub method: Method,
    /// folder with the files (instead of the `sequence` input)
    pub dir: Option<InputPath>,
    /// the test (default: specimen.json)
    pub mode: Option<Mode>,
    /// region of interest [x0, y0, x1, y1] in frame-0 pixels (default: specimen.json)
    #[param(unit = "px")]
    pub roi_px: Option<[usize; 4]>,
    /// region of interest as a polygon [[x, y], …] in frame-0 pixels (even-odd rule)
    #[param(unit = "px")]
    pub roi_polygon_px: Option<Vec<[f64; 2]>>,
    /// image file beside the frames whose non-zero pixels are analysed (holes, notches, grips)
    pub mask: Option<String>,
    /// direction of `stretch`: x, y or principal (the final frame's largest principal stretch)
    #[param(default = LoadingAxis::X)]
    pub loading_axis: LoadingAxis,
    /// camera bits when fewer than the file's (12-bit data in 16-bit files; default: specimen.json)
    #[param(range = 1..=16)]
    pub bit_depth: Option<u8>,
    /// frame rate without frames.csv: frames in natural order of their names at times k / rate
    #[param(unit = "Hz", positive)]
    pub frame_rate_hz: Option<f64>,
    /// subset side, odd
    #[param(default = 31, unit = "px", range = 7..=501, check = odd)]
    pub subset_px: usize,
    /// POI spacing
    #[param(default = 10, unit = "px", range = 1..)]
    pub step_px: usize,
    /// strain window side in POIs
    #[param(default = 5, range = 2..)]
    pub strain_window: usize,
    /// IC-GN iteration limit
    #[param(default = 30, range = 1..)]
    pub max_iterations: usize,
    /// IC-GN stops when the update moves the subset less
    #[param(default = 1e-3, unit = "px", positive)]
    pub convergence_px: f64,
    /// POIs correlating worse are invalid
    #[param(default = 0.9, range = -1.0..=1.0)]
    pub min_zncc: f64,
    /// reference update threshold on |λ − 1|
    #[param(default = 0.1, positive)]
    pub update_strain: f64,
    /// FFT seed search radius
    #[param(default = 64, unit = "px", range = 1..)]
    pub search_px: usize,
    /// marker pixels are darker than this fraction of full scale
    #[param(default = 0.07, range = 0.0..=1.0)]
    pub marker_threshold: f64,
    /// smallest marker in frame 0
    #[param(default = 20, unit = "px")]
    pub marker_min_area_px: usize,
    /// largest distance from the predicted marker position
    #[param(default = 25.0, unit = "px", positive)]
    pub marker_max_jump_px: f64,
    /// gauge width (default: specimen.json)
    #[param(unit = "m", positive)]
    pub gauge_width_m: Option<f64>,
    /// thickness (default: specimen.json)
    #[param(unit = "m", positive)]
    pub thickness_m: Option<f64>,
    /// object-space pixel size (default: specimen.json)
    #[param(unit = "m", positive)]
    pub pixel_m: Option<f64>,
}

fn odd(n: &usize) -> Result<(), String> {
    if n % 2 == 1 {
        Ok(())
    } else {
        Err(format!("must be odd, got {n}"))
    }
}

impl DicParams {
    pub(crate) fn subset_settings(&self) -> SubsetSettings {
        SubsetSettings {
            icgn: IcgnSettings {
                subset_px: self.subset_px,
                max_iterations: self.max_iterations,
                convergence_px: self.convergence_px,
            },
            min_zncc: self.min_zncc,
            update_strain: self.update_strain,
            search_px: self.search_px,
        }
    }
}

/// The `dic` stage.
pub struct Dic;

/// Output `tensile`: one row per frame. `mode`, `stretch` and
/// `nominal_stress_pa` are the columns of `tensile-table`'s table, so
/// `material-fit` reads either (without a force log, force and stress are
/// NaN, which `material-fit` refuses).
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct DicTensileTable {
    /// UT, PT or BT
    pub mode: Vec<String>,
    /// frame number from frames.csv (or the image file's name)
    pub frame: Vec<i64>,
    /// frame time
    #[column(unit = "s")]
    pub time_s: Vec<f64>,
    /// loading stretch λ (the principal stretch nearest the loading axis)
    pub stretch: Vec<f64>,
    /// in-plane transverse principal stretch
    pub stretch_2: Vec<f64>,
    /// engineering strain λ − 1
    pub strain: Vec<f64>,
    /// force interpolated at the frame time (NaN without force.csv)
    #[column(unit = "N")]
    pub force_n: Vec<f64>,
    /// force / undeformed cross-section (NaN without force.csv)
    #[column(unit = "Pa")]
    pub nominal_stress_pa: Vec<f64>,
    /// share of the analysed POIs (or markers) tracked in this frame
    pub valid_fraction: Vec<f64>,
    /// loading axis, angle from image x in frame 0 (0 for x, 90 for y)
    #[column(unit = "deg")]
    pub loading_axis_deg: Vec<f64>,
}

/// Output `field`: one row per POI per frame (long format), every POI of
/// the grid (those outside the region too, never valid), so the rows of a
/// frame fill the grid row by row. Markers: one row per marker, strain NaN.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct DicFieldTable {
    /// frame number, as in `tensile`
    pub frame: Vec<i64>,
    /// frame-0 position, column
    #[column(unit = "px")]
    pub x_px: Vec<f64>,
    /// frame-0 position, row
    #[column(unit = "px")]
    pub y_px: Vec<f64>,
    /// displacement along x since frame 0 (NaN where not valid)
    #[column(unit = "px")]
    pub u_px: Vec<f64>,
    /// displacement along y since frame 0
    #[column(unit = "px")]
    pub v_px: Vec<f64>,
    /// Green–Lagrange E_xx from the strain window
    pub exx: Vec<f64>,
    /// Green–Lagrange E_yy
    pub eyy: Vec<f64>,
    /// Green–Lagrange E_xy (tensor shear, half the engineering shear)
    pub exy: Vec<f64>,
    /// ZNCC of the POI's final match (1 in frame 0)
    pub zncc: Vec<f64>,
    /// 1 if the POI was tracked in this frame, else 0
    pub valid: Vec<i64>,
}

static INFO: StageInfo = StageInfo {
    kind: "dic",
    version: 2,
    summary: "Digital image correlation of a tensile test: stretch and strain per frame (force and nominal stress with a force log), and u, v, E, ZNCC per point per frame",
    doc: "Reads the images (PNG/TIFF: 8/16-bit grey, colour converted by Y = 0.2126 R + 0.7152 G \
          + 0.0722 B of the stored values rounded, palette, float TIFF as fractions 0 … 1), \
          frames.csv, force.csv and specimen.json from the `sequence` input or the folder `dir`. \
          Frames: frames.csv (frame, time_s, file); without it the PNG/TIFF files whose names \
          carry their time (img_0007_t1.25s.tif, as contact-images), or with `frame_rate_hz` all \
          PNG/TIFF files in natural order of their names at times k / rate. Counts are fractions \
          of 2^bit_depth − 1 (`bit_depth` or specimen.json, else the file's 8/16 bits; never \
          guessed: a note says when a 16-bit frame 0 stays below 4096). force.csv is optional: \
          without it force_n and nominal_stress_pa are NaN (strain only; material-fit then \
          refuses the table), and gauge width and thickness are not needed. Region: `roi_px`, \
          `roi_polygon_px` and the `mask` image (non-zero = analyse), intersected; a POI is \
          tracked only if its whole subset lies inside. method `subset`: POIs on a grid in the \
          region; seeds spread over the region (up to 4 × 4 candidates, FFT ZNCC integer guess \
          then IC-GN, all accepted ones queued best ZNCC first, more rounds for parts not \
          reached), reliability-guided propagation, IC-GN with a first-order shape function and \
          bicubic B-spline interpolation (Pan et al. 2013); POIs below `min_zncc` or not \
          converged are invalid; incremental reference updating when the strain since the \
          reference exceeds `update_strain`, positions and gradients composed so deformation \
          accumulates from frame 0. method `markers`: weighted centroids of dark painted dots \
          in the region's bounding box. Gauge value per frame: least-squares affine fit of all \
          valid points → F → principal stretches, `stretch` the one nearest `loading_axis` (x, \
          y, or principal: the final frame's largest principal stretch direction, reported in \
          `loading_axis_deg` and a note). Table `field`: per POI per frame u, v, Green–Lagrange \
          E_xx, E_yy, E_xy from strain-window fits, ZNCC and validity. Field `strain`: E_xx of \
          the last frame (NaN where invalid). Force linearly interpolated at frame times; \
          nominal stress = F / (gauge width × thickness).",
    inputs: &[InputSpec::files(
        "sequence",
        Arity::Optional,
        "the synth-tensile files (or use `dir`)",
    )],
    outputs: &[
        OutputSpec::table::<DicTensileTable>("tensile", "one row per frame"),
        OutputSpec::table::<DicFieldTable>(
            "field",
            "one row per point per frame: u, v, Green–Lagrange E, ZNCC",
        ),
        OutputSpec::field(
            "strain",
            "Green–Lagrange E_xx of the last frame on the POI grid (markers: one gauge value)",
        ),
    ],
};

impl Stage for Dic {
    type Params = DicParams;
    /// Parallel (rayon) over its work: a few cores pay off on a cluster.
    const RESOURCES: hypercontact_core::Resources = hypercontact_core::Resources::PARALLEL;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<DicParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let source = FileSource::input_or_dir(inputs, "sequence", "dir", p.dir.as_ref())?;
        let sequence = Sequence::open(source, p.frame_rate_hz, p.mask.as_deref())
            .map_err(StageError::other)?;
        let analysis = analyse(&sequence, p, ctx).map_err(StageError::other)?;
        Ok(Outputs::new()
            .table("tensile", analysis.table.into_table())
            .table("field", analysis.field.into_table())
            .field("strain", analysis.strain))
    }
}
