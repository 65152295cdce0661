//! Stage `dic`: stretch, strain, force and nominal stress per frame of a
//! tensile test, from its speckle images and force log.
//!
//! The gauge-section value of a frame is the deformation gradient F of the
//! least-squares affine map from the frame-0 positions of all valid points
//! (POIs or markers) to their current ones; λ along the loading axis x and
//! λ₂ across it are F's principal stretches. Nominal stress is the force,
//! interpolated at the frame's time, over the undeformed cross-section
//! (gauge width × thickness), as the paper's section 2 tests report it.

use hypercontact_core::{
    Arity, Checked, Choice, Context, Field, FileSource, InputPath, InputSpec, Inputs, Mode,
    OutputSpec, Outputs, Schema, Stage, StageError, StageInfo, params,
};
use ndarray::Array2;

use crate::DicError;
use crate::icgn::IcgnSettings;
use crate::markers::{MarkerSettings, MarkerTracker};
use crate::poi_grid::PoiGrid;
use crate::sequence::Sequence;
use crate::strain::{Mat2, affine_fit, gradient_field, green_lagrange, principal_stretches};
use crate::subset_tracking::{SubsetSettings, SubsetTracker};

/// How points are followed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum Method {
    /// subset DIC (IC-GN) on a POI grid
    #[default]
    Subset,
    /// centroids of painted marker dots
    Markers,
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
    fn subset_settings(&self) -> SubsetSettings {
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
/// `material-fit` reads either.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct DicTensileTable {
    /// UT, PT or BT
    pub mode: Vec<String>,
    /// frame number from frames.csv (or the image file's name)
    pub frame: Vec<i64>,
    /// frame time
    #[column(unit = "s")]
    pub time_s: Vec<f64>,
    /// loading stretch λ (principal, nearest the x axis)
    pub stretch: Vec<f64>,
    /// in-plane transverse principal stretch
    pub stretch_2: Vec<f64>,
    /// engineering strain λ − 1
    pub strain: Vec<f64>,
    /// force interpolated at the frame time
    #[column(unit = "N")]
    pub force_n: Vec<f64>,
    /// force / undeformed cross-section
    #[column(unit = "Pa")]
    pub nominal_stress_pa: Vec<f64>,
    /// share of POIs (or markers) tracked in this frame
    pub valid_fraction: Vec<f64>,
}

static INFO: StageInfo = StageInfo {
    kind: "dic",
    version: 1,
    summary: "Digital image correlation of a tensile test: stretch, strain, force, nominal stress per frame",
    doc: "Reads frames.csv, the images it lists (PNG/TIFF, 8/16 bit), force.csv and specimen.json \
          from the `sequence` input or the folder `dir`; without frames.csv, the PNG/TIFF files \
          whose names carry their time (img_0007_t1.25s.tif, as contact-images). method `subset`: POIs on a grid in the \
          ROI; FFT ZNCC integer seed, reliability-guided propagation, IC-GN with a first-order \
          shape function and bicubic B-spline interpolation (Pan et al. 2013), POIs below \
          `min_zncc` or not converged are invalid; incremental reference updating when the \
          strain since the reference exceeds `update_strain`, positions and gradients composed \
          so deformation accumulates from frame 0. method `markers`: weighted centroids of dark \
          painted dots. Gauge value per frame: least-squares affine fit of all valid points → \
          F → principal stretches (λ along x first). Field `strain`: Green–Lagrange E_xx of the \
          last frame from strain-window fits (NaN where invalid). Force linearly interpolated \
          at frame times; nominal stress = F / (gauge width × thickness).",
    inputs: &[InputSpec::files(
        "sequence",
        Arity::Optional,
        "the synth-tensile files (or use `dir`)",
    )],
    outputs: &[
        OutputSpec::table::<DicTensileTable>("tensile", "one row per frame"),
        OutputSpec::field(
            "strain",
            "Green–Lagrange E_xx of the last frame on the POI grid (markers: one gauge value)",
        ),
    ],
};

impl Stage for Dic {
    type Params = DicParams;

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
        let sequence = Sequence::open(source).map_err(StageError::other)?;
        let analysis = analyse(&sequence, p, ctx).map_err(StageError::other)?;
        Ok(Outputs::new()
            .table("tensile", analysis.table.into_table())
            .field("strain", analysis.strain))
    }
}

/// The stage's results.
pub struct Analysis {
    pub table: DicTensileTable,
    /// Green–Lagrange E_xx of the last frame.
    pub strain: Field,
    /// Gauge deformation gradient per frame.
    pub gradients: Vec<Mat2>,
}

/// Runs the DIC over an opened sequence.
pub fn analyse(
    sequence: &Sequence,
    p: &Checked<DicParams>,
    ctx: &Context,
) -> Result<Analysis, DicError> {
    let specimen = &sequence.specimen;
    let mode = match (p.mode, &specimen.mode) {
        (Some(mode), _) => mode,
        (None, Some(label)) => Mode::from_label(label).ok_or_else(|| {
            DicError::file(
                "specimen.json",
                format!("mode `{label}` is not UT, PT or BT"),
            )
        })?,
        (None, None) => {
            return Err(DicError::param(
                "mode",
                "is needed (no `mode` in specimen.json)",
            ));
        }
    };
    let need = |param: &str, v: Option<f64>| {
        v.filter(|v| *v > 0.0 && v.is_finite()).ok_or_else(|| {
            DicError::param(
                param,
                "is needed as a positive number (parameter or specimen.json)",
            )
        })
    };
    let width_m = need("gauge_width_m", p.gauge_width_m.or(specimen.gauge_width_m))?;
    let thickness_m = need("thickness_m", p.thickness_m.or(specimen.thickness_m))?;
    let pixel_m = need("pixel_m", p.pixel_m.or(specimen.pixel_m))?;
    let area_m2 = width_m * thickness_m;
    let (roi_px, roi_name) = match (p.roi_px, specimen.roi_px) {
        (Some(r), _) => (r, "roi_px"),
        (None, Some(r)) => (r, "specimen.json roi_px"),
        (None, None) => {
            return Err(DicError::param(
                "roi_px",
                "is needed (no `roi_px` in specimen.json)",
            ));
        }
    };

    let frame0 = sequence.image(0)?;
    let n_frames = sequence.frames().len();
    let progress = ctx.progress(n_frames as u64, "correlating frames");
    let mut gradients = Vec::with_capacity(n_frames);
    let mut valid_fraction = Vec::with_capacity(n_frames);
    let strain_field;

    match p.method {
        Method::Subset => {
            let grid = PoiGrid::new(
                roi_px,
                roi_name,
                p.step_px,
                p.subset_px,
                frame0.width,
                frame0.height,
            )?;
            let mut tracker = SubsetTracker::new(p.subset_settings(), grid, frame0);
            gradients.push([[1.0, 0.0], [0.0, 1.0]]);
            valid_fraction.push(1.0);
            progress.inc(1);
            let mut last: Vec<Option<[f64; 2]>> =
                tracker.grid().points.iter().copied().map(Some).collect();
            for k in 1..n_frames {
                let entry = &sequence.frames()[k];
                let image = sequence.image(k)?;
                let track = tracker.track(image, k, &entry.file)?;
                gradients.push(gauge_gradient(
                    &tracker.grid().points,
                    &track.positions,
                    k,
                    &entry.file,
                )?);
                let valid = track.positions.iter().filter(|x| x.is_some()).count();
                valid_fraction.push(valid as f64 / track.positions.len() as f64);
                last = track.positions;
                progress.inc(1);
            }
            let grid = tracker.grid();
            let field = gradient_field(grid.nx, grid.ny, &grid.points, &last, p.strain_window);
            let mut values = Array2::from_elem((grid.nx, grid.ny), f64::NAN);
            for (i, f) in field.iter().enumerate() {
                if let Some(f) = f {
                    values[[i % grid.nx, i / grid.nx]] = green_lagrange(f)[0];
                }
            }
            let dx = grid.step_px as f64 * pixel_m;
            strain_field =
                Field::new(values, dx, dx).map_err(|e| DicError::Invalid(e.to_string()))?;
        }
        Method::Markers => {
            let settings = MarkerSettings {
                threshold: p.marker_threshold,
                min_area_px: p.marker_min_area_px,
                max_jump_px: p.marker_max_jump_px,
            };
            let mut tracker =
                MarkerTracker::new(settings, &frame0, roi_px, &sequence.frames()[0].file)?;
            gradients.push([[1.0, 0.0], [0.0, 1.0]]);
            valid_fraction.push(1.0);
            progress.inc(1);
            for k in 1..n_frames {
                let entry = &sequence.frames()[k];
                let image = sequence.image(k)?;
                let found = tracker.track(&image, k, &entry.file)?;
                gradients.push(gauge_gradient(&tracker.reference, &found, k, &entry.file)?);
                let valid = found.iter().filter(|x| x.is_some()).count();
                valid_fraction.push(valid as f64 / found.len() as f64);
                progress.inc(1);
            }
            // Markers give the gauge value only: a one-cell field over the ROI.
            let exx = gradients.last().map_or(0.0, |f| green_lagrange(f)[0]);
            let [x0, y0, x1, y1] = roi_px;
            strain_field = Field::new(
                Array2::from_elem((1, 1), exx),
                (x1 - x0 + 1) as f64 * pixel_m,
                (y1 - y0 + 1) as f64 * pixel_m,
            )
            .map_err(|e| DicError::Invalid(e.to_string()))?;
        }
    }
    drop(progress);

    let mut stretch = Vec::with_capacity(n_frames);
    let mut stretch_2 = Vec::with_capacity(n_frames);
    let mut force = Vec::with_capacity(n_frames);
    for (entry, f) in sequence.frames().iter().zip(&gradients) {
        let (l1, l2) = principal_stretches(f);
        stretch.push(l1);
        stretch_2.push(l2);
        force.push(sequence.force_at(entry.time_s, entry)?);
    }
    let table = DicTensileTable {
        mode: vec![mode.label().to_owned(); n_frames],
        frame: sequence.frames().iter().map(|f| f.frame).collect(),
        time_s: sequence.frames().iter().map(|f| f.time_s).collect(),
        strain: stretch.iter().map(|l| l - 1.0).collect(),
        stretch,
        stretch_2,
        nominal_stress_pa: force.iter().map(|f| f / area_m2).collect(),
        force_n: force,
        valid_fraction,
    };
    Ok(Analysis {
        table,
        strain: strain_field,
        gradients,
    })
}

/// The gauge deformation gradient from all valid points.
fn gauge_gradient(
    reference: &[[f64; 2]],
    current: &[Option<[f64; 2]>],
    frame: usize,
    file: &str,
) -> Result<Mat2, DicError> {
    let (from, to): (Vec<[f64; 2]>, Vec<[f64; 2]>) = reference
        .iter()
        .zip(current)
        .filter_map(|(&x0, x)| x.map(|x| (x0, x)))
        .unzip();
    affine_fit(&from, &to)
        .map(|(_, _, f)| f)
        .ok_or_else(|| DicError::Lost {
            frame,
            file: file.to_owned(),
            reason: format!(
                "only {} tracked point(s), not enough for a deformation gradient",
                from.len()
            ),
        })
}
