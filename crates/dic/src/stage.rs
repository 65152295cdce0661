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
//! thickness), as the paper's section 2 tests report it.

use hypercontact_core::{
    Arity, Checked, Choice, Context, Field, InputPath, InputSpec, Inputs, Mode, OutputSpec,
    Outputs, Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_labfiles::FileSource;
use ndarray::Array2;

use crate::DicError;
use crate::gray::shallow_sixteen_bit;
use crate::icgn::IcgnSettings;
use crate::markers::{MarkerSettings, MarkerTracker};
use crate::poi_grid::PoiGrid;
use crate::region::Region;
use crate::sequence::Sequence;
use crate::strain::{
    IDENTITY, Mat2, affine_fit, gradient_field, green_lagrange, principal, stretches_along,
};
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

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    /// Parallel over its work (rayon): a few cores pay off on a cluster.
    fn resources(&self) -> hypercontact_core::Resources {
        hypercontact_core::Resources::PARALLEL
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

/// The stage's results.
pub struct Analysis {
    pub table: DicTensileTable,
    pub field: DicFieldTable,
    /// Green–Lagrange E_xx of the last frame.
    pub strain: Field,
    /// Gauge deformation gradient per frame.
    pub gradients: Vec<Mat2>,
    /// What the run noted (each also given to the context's notes).
    pub notes: Vec<String>,
}

/// Runs the DIC over an opened sequence.
pub fn analyse(
    sequence: &Sequence,
    p: &Checked<DicParams>,
    ctx: &Context,
) -> Result<Analysis, DicError> {
    let specimen = &sequence.specimen;
    let mut notes = Vec::new();
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
    let pixel_m = need("pixel_m", p.pixel_m.or(specimen.pixel_m))?;
    let area_m2 = if sequence.has_force() {
        let width_m = need("gauge_width_m", p.gauge_width_m.or(specimen.gauge_width_m))?;
        let thickness_m = need("thickness_m", p.thickness_m.or(specimen.thickness_m))?;
        Some(width_m * thickness_m)
    } else {
        notes.push(
            "no force.csv: stretch and strain only, force_n and nominal_stress_pa are NaN \
             (material-fit needs a force log)"
                .to_owned(),
        );
        None
    };
    let bit_depth = match (p.bit_depth, specimen.bit_depth) {
        (Some(bits), _) => Some(bits),
        (None, Some(bits)) => Some(
            u8::try_from(bits)
                .ok()
                .filter(|b| (1..=16).contains(b))
                .ok_or_else(|| {
                    DicError::file(
                        &sequence.display("specimen.json"),
                        format!("bit_depth {bits} is not 1 … 16"),
                    )
                })?,
        ),
        (None, None) => None,
    };

    let decoded0 = sequence.decoded(0)?;
    if bit_depth.is_none()
        && let Some(max) = shallow_sixteen_bit(&decoded0)
    {
        notes.push(format!(
            "frame 0 ({}) is a 16-bit file whose largest count is {max} (below 4096): if the \
             camera has 12 bits or fewer, set `bit_depth` (counts are now fractions of 65535; \
             the subset method does not depend on it, marker thresholds do)",
            sequence.frames()[0].file
        ));
    }
    let frame0 = sequence.gray(&decoded0, 0, bit_depth)?;
    let region = region(sequence, p, frame0.width, frame0.height)?;
    let n_frames = sequence.frames().len();
    let progress = ctx.progress(n_frames as u64, "correlating frames");
    let mut gradients = Vec::with_capacity(n_frames);
    let mut valid_fraction = Vec::with_capacity(n_frames);
    let mut field = DicFieldTable::default();
    let frame_number = |k: usize| sequence.frames()[k].frame;
    let strain_field;

    match p.method {
        Method::Subset => {
            let mut grid = PoiGrid::new(
                region.bounds,
                region.name,
                p.step_px,
                p.subset_px,
                frame0.width,
                frame0.height,
            )?;
            let half = p.subset_px / 2;
            let n_active = grid.restrict(|x, y| region.pixels.holds_square(x, y, half));
            if n_active == 0 {
                return Err(DicError::param(
                    region.name,
                    format!(
                        "no point of interest has its whole {} px subset inside the region \
                         (make the region larger or `subset_px` smaller)",
                        p.subset_px
                    ),
                ));
            }
            let first: Vec<Option<[f64; 2]>> = grid
                .points
                .iter()
                .zip(&grid.active)
                .map(|(&x, &a)| a.then_some(x))
                .collect();
            let ones: Vec<f64> = grid
                .active
                .iter()
                .map(|&a| if a { 1.0 } else { f64::NAN })
                .collect();
            push_field(
                &mut field,
                frame_number(0),
                &grid,
                &first,
                &ones,
                p.strain_window,
            );
            let mut tracker = SubsetTracker::new(p.subset_settings(), grid, frame0);
            gradients.push([[1.0, 0.0], [0.0, 1.0]]);
            valid_fraction.push(1.0);
            progress.inc(1);
            let mut last = first;
            for k in 1..n_frames {
                let entry = &sequence.frames()[k];
                let image = sequence.image(k, bit_depth)?;
                let track = tracker.track(image, k, &entry.file)?;
                gradients.push(gauge_gradient(
                    &tracker.grid().points,
                    &track.positions,
                    k,
                    &entry.file,
                )?);
                let valid = track.positions.iter().filter(|x| x.is_some()).count();
                valid_fraction.push(valid as f64 / n_active as f64);
                push_field(
                    &mut field,
                    frame_number(k),
                    tracker.grid(),
                    &track.positions,
                    &track.zncc,
                    p.strain_window,
                );
                last = track.positions;
                progress.inc(1);
            }
            let grid = tracker.grid();
            let gradient = gradient_field(grid.nx, grid.ny, &grid.points, &last, p.strain_window);
            let mut values = Array2::from_elem((grid.nx, grid.ny), f64::NAN);
            for (i, f) in gradient.iter().enumerate() {
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
                MarkerTracker::new(settings, &frame0, region.bounds, &sequence.frames()[0].file)?;
            let reference = tracker.reference.clone();
            let push = |field: &mut DicFieldTable, frame: i64, found: &[Option<[f64; 2]>]| {
                for (x0, x) in reference.iter().zip(found) {
                    field.frame.push(frame);
                    field.x_px.push(x0[0]);
                    field.y_px.push(x0[1]);
                    field.u_px.push(x.map_or(f64::NAN, |x| x[0] - x0[0]));
                    field.v_px.push(x.map_or(f64::NAN, |x| x[1] - x0[1]));
                    for column in [
                        &mut field.exx,
                        &mut field.eyy,
                        &mut field.exy,
                        &mut field.zncc,
                    ] {
                        column.push(f64::NAN);
                    }
                    field.valid.push(i64::from(x.is_some()));
                }
            };
            let first: Vec<Option<[f64; 2]>> = reference.iter().copied().map(Some).collect();
            push(&mut field, frame_number(0), &first);
            gradients.push([[1.0, 0.0], [0.0, 1.0]]);
            valid_fraction.push(1.0);
            progress.inc(1);
            for k in 1..n_frames {
                let entry = &sequence.frames()[k];
                let image = sequence.image(k, bit_depth)?;
                let found = tracker.track(&image, k, &entry.file)?;
                gradients.push(gauge_gradient(&tracker.reference, &found, k, &entry.file)?);
                let valid = found.iter().filter(|x| x.is_some()).count();
                valid_fraction.push(valid as f64 / found.len() as f64);
                push(&mut field, frame_number(k), &found);
                progress.inc(1);
            }
            // Markers give the gauge value only: a one-cell field over the ROI.
            let exx = gradients.last().map_or(0.0, |f| green_lagrange(f)[0]);
            let [x0, y0, x1, y1] = region.bounds;
            strain_field = Field::new(
                Array2::from_elem((1, 1), exx),
                (x1 - x0 + 1) as f64 * pixel_m,
                (y1 - y0 + 1) as f64 * pixel_m,
            )
            .map_err(|e| DicError::Invalid(e.to_string()))?;
        }
    }
    drop(progress);

    let axis_rad = match p.loading_axis {
        LoadingAxis::X => 0.0,
        LoadingAxis::Y => std::f64::consts::FRAC_PI_2,
        LoadingAxis::Principal => {
            let last = gradients.last().copied().unwrap_or(IDENTITY);
            let (_, _, theta) = principal(&last);
            // One direction, two signs: report it in (−90°, 90°].
            let theta = if theta <= -std::f64::consts::FRAC_PI_2 {
                theta + std::f64::consts::PI
            } else {
                theta
            };
            notes.push(format!(
                "loading axis: the final frame's largest principal stretch direction, {:.2}° \
                 from image x (column `loading_axis_deg`)",
                theta.to_degrees()
            ));
            theta
        }
    };
    let mut stretch = Vec::with_capacity(n_frames);
    let mut stretch_2 = Vec::with_capacity(n_frames);
    let mut force = Vec::with_capacity(n_frames);
    for (entry, f) in sequence.frames().iter().zip(&gradients) {
        let (l1, l2) = stretches_along(f, axis_rad);
        stretch.push(l1);
        stretch_2.push(l2);
        force.push(match area_m2 {
            Some(_) => sequence.force_at(entry.time_s, entry)?,
            None => f64::NAN,
        });
    }
    let table = DicTensileTable {
        mode: vec![mode.label().to_owned(); n_frames],
        frame: sequence.frames().iter().map(|f| f.frame).collect(),
        time_s: sequence.frames().iter().map(|f| f.time_s).collect(),
        strain: stretch.iter().map(|l| l - 1.0).collect(),
        stretch,
        stretch_2,
        nominal_stress_pa: force
            .iter()
            .map(|f| area_m2.map_or(f64::NAN, |a| f / a))
            .collect(),
        force_n: force,
        valid_fraction,
        loading_axis_deg: vec![axis_rad.to_degrees(); n_frames],
    };
    for note in &notes {
        ctx.note(note);
    }
    Ok(Analysis {
        table,
        field,
        strain: strain_field,
        gradients,
        notes,
    })
}

/// The analysed region and the rectangle the POI grid covers.
struct AnalysedRegion {
    pixels: Region,
    /// Bounding box of the region, [x0, y0, x1, y1].
    bounds: [usize; 4],
    /// The parameter errors about the region name.
    name: &'static str,
}

/// `roi_px` (or specimen.json's), `roi_polygon_px` and `mask`, intersected.
fn region(
    sequence: &Sequence,
    p: &DicParams,
    width: usize,
    height: usize,
) -> Result<AnalysedRegion, DicError> {
    let rect = match (p.roi_px, sequence.specimen.roi_px) {
        (Some(r), _) => Some((r, "roi_px")),
        (None, Some(r)) => Some((r, "specimen.json roi_px")),
        (None, None) => None,
    };
    let mask = match &p.mask {
        Some(name) => Some((sequence.read_image(name)?, sequence.display(name))),
        None => None,
    };
    let name = match (rect, &p.roi_polygon_px, &mask) {
        (Some((_, name)), _, _) => name,
        (None, Some(_), _) => "roi_polygon_px",
        (None, None, Some(_)) => "mask",
        (None, None, None) => {
            return Err(DicError::param(
                "roi_px",
                "is needed (no `roi_px` in specimen.json), or `roi_polygon_px` or `mask`: e.g. \
                 roi_px: [100, 50, 400, 450] (x0, y0, x1, y1 in frame-0 pixels)",
            ));
        }
    };
    let pixels = Region::new(
        width,
        height,
        rect,
        p.roi_polygon_px.as_deref(),
        mask.as_ref().map(|(m, n)| (m, n.as_str())),
    )?;
    let bounds = pixels.bounds().ok_or_else(|| {
        DicError::param(
            name,
            "the region of interest holds no pixel (roi_px, roi_polygon_px and the mask do not \
             overlap)",
        )
    })?;
    Ok(AnalysedRegion {
        pixels,
        bounds,
        name,
    })
}

/// One frame's rows of the `field` table: u, v from the positions, E from
/// the strain-window gradient, ZNCC.
fn push_field(
    field: &mut DicFieldTable,
    frame: i64,
    grid: &PoiGrid,
    positions: &[Option<[f64; 2]>],
    zncc: &[f64],
    window: usize,
) {
    let gradient = gradient_field(grid.nx, grid.ny, &grid.points, positions, window);
    for (i, x0) in grid.points.iter().enumerate() {
        let e = gradient[i].map_or([f64::NAN; 3], |f| green_lagrange(&f));
        field.frame.push(frame);
        field.x_px.push(x0[0]);
        field.y_px.push(x0[1]);
        field
            .u_px
            .push(positions[i].map_or(f64::NAN, |x| x[0] - x0[0]));
        field
            .v_px
            .push(positions[i].map_or(f64::NAN, |x| x[1] - x0[1]));
        field.exx.push(e[0]);
        field.eyy.push(e[1]);
        field.exy.push(e[2]);
        field.zncc.push(if positions[i].is_some() {
            zncc[i]
        } else {
            f64::NAN
        });
        field.valid.push(i64::from(positions[i].is_some()));
    }
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
