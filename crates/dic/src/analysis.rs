//! The `dic` stage's analysis of an opened sequence: the specimen's settings
//! (parameters over specimen.json), the points followed through every frame
//! (subsets or markers), and per frame the gauge deformation gradient F, the
//! least-squares affine map of all valid points, whose principal stretches
//! along the loading axis give `stretch` and `stretch_2`. Nominal stress is
//! the force at the frame's time over the undeformed cross-section (gauge
//! width × thickness), as the paper's section 2 tests report it.

use hypercontact_core::{Checked, Context, Field, Mode, Progress};
use ndarray::Array2;

use crate::DicError;
use crate::gray::{GrayImage, shallow_sixteen_bit};
use crate::markers::{MarkerSettings, MarkerTracker};
use crate::poi_grid::PoiGrid;
use crate::region::Region;
use crate::sequence::Sequence;
use crate::stage::{DicFieldTable, DicParams, DicTensileTable, LoadingAxis, Method};
use crate::strain::{
    IDENTITY, Mat2, affine_fit, gradient_field, green_lagrange, principal, stretches_along,
};
use crate::subset_tracking::SubsetTracker;

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
    let mut notes = Vec::new();
    let specimen = specimen(sequence, p, &mut notes)?;
    let decoded0 = sequence.decoded(0)?;
    if specimen.bit_depth.is_none()
        && let Some(max) = shallow_sixteen_bit(&decoded0)
    {
        notes.push(format!(
            "frame 0 ({}) is a 16-bit file whose largest count is {max} (below 4096): if the \
             camera has 12 bits or fewer, set `bit_depth` (counts are now fractions of 65535; \
             the subset method does not depend on it, marker thresholds do)",
            sequence.frames()[0].file
        ));
    }
    let frame0 = sequence.gray(&decoded0, 0, specimen.bit_depth)?;
    let region = region(sequence, p, frame0.width, frame0.height)?;
    let progress = ctx.progress(sequence.frames().len() as u64, "correlating frames");
    let (tracked, strain) = match p.method {
        Method::Subset => track_subsets(sequence, p, &specimen, frame0, &region, &progress)?,
        Method::Markers => track_markers(sequence, p, &specimen, &frame0, &region, &progress)?,
    };
    drop(progress);
    let axis_rad = loading_axis_rad(p.loading_axis, &tracked.gradients, &mut notes);
    let table = tensile_table(sequence, &specimen, &tracked, axis_rad)?;
    for note in &notes {
        ctx.note(note);
    }
    Ok(Analysis {
        table,
        field: tracked.field,
        strain,
        gradients: tracked.gradients,
        notes,
    })
}

/// What the parameters, or else specimen.json, settle before a frame is read.
struct Specimen {
    mode: Mode,
    pixel_m: f64,
    /// Undeformed cross-section; None without a force log.
    area_m2: Option<f64>,
    /// The camera's bits when fewer than the files'.
    bit_depth: Option<u8>,
}

/// The test's mode, pixel size, cross-section and bit depth, each from its
/// parameter or specimen.json; notes when there is no force log.
fn specimen(
    sequence: &Sequence,
    p: &DicParams,
    notes: &mut Vec<String>,
) -> Result<Specimen, DicError> {
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
    Ok(Specimen {
        mode,
        pixel_m,
        area_m2,
        bit_depth,
    })
}

/// Per frame: the gauge gradient, the share of points tracked, and the
/// rows of the `field` table.
struct Tracked {
    gradients: Vec<Mat2>,
    valid_fraction: Vec<f64>,
    field: DicFieldTable,
}

impl Tracked {
    /// Frame 0: every point where it is, F = I.
    fn starting(n_frames: usize) -> Self {
        let mut gradients = Vec::with_capacity(n_frames);
        let mut valid_fraction = Vec::with_capacity(n_frames);
        gradients.push(IDENTITY);
        valid_fraction.push(1.0);
        Self {
            gradients,
            valid_fraction,
            field: DicFieldTable::default(),
        }
    }
}

/// Subset DIC of the grid's POIs through every frame, and E_xx of the last
/// frame on the grid.
fn track_subsets(
    sequence: &Sequence,
    p: &DicParams,
    specimen: &Specimen,
    frame0: GrayImage,
    region: &AnalysedRegion,
    progress: &Progress,
) -> Result<(Tracked, Field), DicError> {
    let n_frames = sequence.frames().len();
    let frame_number = |k: usize| sequence.frames()[k].frame;
    let (grid, n_active) = active_grid(p, region, &frame0)?;
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
    let mut tracked = Tracked::starting(n_frames);
    push_field(
        &mut tracked.field,
        frame_number(0),
        &grid,
        &first,
        &ones,
        p.strain_window,
    );
    let mut tracker = SubsetTracker::new(p.subset_settings(), grid, frame0);
    progress.inc(1);
    let mut last = first;
    for k in 1..n_frames {
        let entry = &sequence.frames()[k];
        let image = sequence.image(k, specimen.bit_depth)?;
        let track = tracker.track(image, k, &entry.file)?;
        tracked.gradients.push(gauge_gradient(
            &tracker.grid().points,
            &track.positions,
            k,
            &entry.file,
        )?);
        let valid = track.positions.iter().filter(|x| x.is_some()).count();
        tracked.valid_fraction.push(valid as f64 / n_active as f64);
        push_field(
            &mut tracked.field,
            frame_number(k),
            tracker.grid(),
            &track.positions,
            &track.zncc,
            p.strain_window,
        );
        last = track.positions;
        progress.inc(1);
    }
    let strain = grid_strain(tracker.grid(), &last, p.strain_window, specimen.pixel_m)?;
    Ok((tracked, strain))
}

/// The POI grid over the region, only POIs whose whole subset lies inside
/// active, and their number; an error when none is.
fn active_grid(
    p: &DicParams,
    region: &AnalysedRegion,
    frame0: &GrayImage,
) -> Result<(PoiGrid, usize), DicError> {
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
    Ok((grid, n_active))
}

/// Green–Lagrange E_xx on the POI grid from the strain-window gradients of
/// the final positions (NaN where invalid).
fn grid_strain(
    grid: &PoiGrid,
    positions: &[Option<[f64; 2]>],
    window: usize,
    pixel_m: f64,
) -> Result<Field, DicError> {
    let gradient = gradient_field(grid.nx, grid.ny, &grid.points, positions, window);
    let mut values = Array2::from_elem((grid.nx, grid.ny), f64::NAN);
    for (i, f) in gradient.iter().enumerate() {
        if let Some(f) = f {
            values[[i % grid.nx, i / grid.nx]] = green_lagrange(f)[0];
        }
    }
    let dx = grid.step_px as f64 * pixel_m;
    Field::new(values, dx, dx).map_err(|e| DicError::Invalid(e.to_string()))
}

/// Marker centroids through every frame; the strain field is the last
/// frame's gauge E_xx as one cell over the region.
fn track_markers(
    sequence: &Sequence,
    p: &DicParams,
    specimen: &Specimen,
    frame0: &GrayImage,
    region: &AnalysedRegion,
    progress: &Progress,
) -> Result<(Tracked, Field), DicError> {
    let n_frames = sequence.frames().len();
    let frame_number = |k: usize| sequence.frames()[k].frame;
    let settings = MarkerSettings {
        threshold: p.marker_threshold,
        min_area_px: p.marker_min_area_px,
        max_jump_px: p.marker_max_jump_px,
    };
    let mut tracker =
        MarkerTracker::new(settings, frame0, region.bounds, &sequence.frames()[0].file)?;
    let reference = tracker.reference.clone();
    let first: Vec<Option<[f64; 2]>> = reference.iter().copied().map(Some).collect();
    let mut tracked = Tracked::starting(n_frames);
    push_marker_rows(&mut tracked.field, frame_number(0), &reference, &first);
    progress.inc(1);
    for k in 1..n_frames {
        let entry = &sequence.frames()[k];
        let image = sequence.image(k, specimen.bit_depth)?;
        let found = tracker.track(&image, k, &entry.file)?;
        tracked
            .gradients
            .push(gauge_gradient(&tracker.reference, &found, k, &entry.file)?);
        let valid = found.iter().filter(|x| x.is_some()).count();
        tracked
            .valid_fraction
            .push(valid as f64 / found.len() as f64);
        push_marker_rows(&mut tracked.field, frame_number(k), &reference, &found);
        progress.inc(1);
    }
    // Markers give the gauge value only: a one-cell field over the ROI.
    let exx = tracked
        .gradients
        .last()
        .map_or(0.0, |f| green_lagrange(f)[0]);
    let [x0, y0, x1, y1] = region.bounds;
    let strain = Field::new(
        Array2::from_elem((1, 1), exx),
        (x1 - x0 + 1) as f64 * specimen.pixel_m,
        (y1 - y0 + 1) as f64 * specimen.pixel_m,
    )
    .map_err(|e| DicError::Invalid(e.to_string()))?;
    Ok((tracked, strain))
}

/// One frame's rows of the `field` table for markers: u, v only.
fn push_marker_rows(
    field: &mut DicFieldTable,
    frame: i64,
    reference: &[[f64; 2]],
    found: &[Option<[f64; 2]>],
) {
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
}

/// The loading axis as an angle from image x; `principal` takes the final
/// frame's largest principal stretch direction and says so in a note.
fn loading_axis_rad(axis: LoadingAxis, gradients: &[Mat2], notes: &mut Vec<String>) -> f64 {
    match axis {
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
    }
}

/// The `tensile` table: stretches along the axis, and with a force log the
/// force at each frame's time and the nominal stress.
fn tensile_table(
    sequence: &Sequence,
    specimen: &Specimen,
    tracked: &Tracked,
    axis_rad: f64,
) -> Result<DicTensileTable, DicError> {
    let n_frames = sequence.frames().len();
    let area_m2 = specimen.area_m2;
    let mut stretch = Vec::with_capacity(n_frames);
    let mut stretch_2 = Vec::with_capacity(n_frames);
    let mut force = Vec::with_capacity(n_frames);
    for (entry, f) in sequence.frames().iter().zip(&tracked.gradients) {
        let (l1, l2) = stretches_along(f, axis_rad);
        stretch.push(l1);
        stretch_2.push(l2);
        force.push(match area_m2 {
            Some(_) => sequence.force_at(entry.time_s, entry)?,
            None => f64::NAN,
        });
    }
    Ok(DicTensileTable {
        mode: vec![specimen.mode.label().to_owned(); n_frames],
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
        valid_fraction: tracked.valid_fraction.clone(),
        loading_axis_deg: vec![axis_rad.to_degrees(); n_frames],
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
