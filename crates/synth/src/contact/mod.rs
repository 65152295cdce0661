//! Stage `synth-contact`: the paper's in-situ contact experiment (Section 3,
//! Fig. 3) as a lab would record it: 16-bit interference frames of the
//! sample pressed onto quartz glass, the frame times, a 50 Hz force log on
//! the sensor's own clock; apart, the ground truth that made them.
//!
//! - [`solve`]: the contact per frame (boundary elements, the `bem` stage's
//!   physics);
//! - [`rig`]: servo ramp, camera timing, force sensor;
//! - [`view`]: the solved gap drawn onto the camera and the true contact
//!   map on its pixels;
//! - [`record`]: the frames exposed, frames.csv and the force log.
//!
//! Files of the `sequence` product (the layout `contact-images` reads, also
//! from a folder of real data): `frame_NNN.png` (16-bit grey; a camera of
//! fewer bits writes its counts unscaled in the 16-bit container),
//! `frames.csv` (`frame, time_s, file`; time_s = exposure start, camera
//! clock), `force.csv` (`time_s, force_n`, sensor clock; with `trigger`,
//! also `camera_trigger`: 1 at the samples taken while the shutter was open).

pub mod physics;
pub mod record;
pub mod rig;
pub mod solve;
pub mod view;

use hypercontact_bem::{Boundary, Influence, Problem, SolverOptions};
use hypercontact_core::contact::{ObservedMapIndex, area_fraction_label, check_map_fraction};
use hypercontact_core::{
    Arity, Checked, Context, Field, Files, InputSpec, Inputs, OutputSpec, Outputs, ParamError,
    Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_icm::{CompositeModulus, LawParams};
use hypercontact_interference::{CameraGrid, CameraParams, Placement};
use hypercontact_material::table::MaterialTable;

use crate::encode_png;
use rig::{ForceSensor, Ramp};
use solve::{ContactError, FrameContact, contact_sequence, penetration_at_m};

/// Parameters of `synth-contact`.
#[params(check = consistent)]
pub struct SynthContactParams {
    /// The experiment's contact law, as `bem`'s.
    #[param(flatten)]
    pub law: LawParams,
    /// how the sample continues beyond the map (as `bem`)
    #[param(default = Boundary::Free)]
    pub boundary: Boundary,
    /// spacing of the contact solve: the surface is low-pass filtered to it (as `surface`)
    #[param(default = 2e-5, unit = "m", positive)]
    pub resolution_m: f64,
    /// camera frames
    #[param(default = 30, range = 3..=100_000)]
    pub frames: usize,
    /// frames before first contact (the flat-field reference and the clock)
    #[param(default = 3, range = 1..=100_000)]
    pub frames_before_contact: usize,
    /// where first contact falls before the first frame in contact, in frame intervals
    #[param(default = 0.3, positive, range = ..=1.0)]
    pub contact_phase: f64,
    /// A/A0 of the solve at the last frame
    #[param(default = 0.9, positive, range = ..=0.99)]
    pub max_area_fraction: f64,
    /// servo speed (the paper's: 3 µm/s)
    #[param(default = 3e-6, unit = "m/s", positive)]
    pub speed_m_per_s: f64,
    /// exposure time (the paper's: 50 ms)
    #[param(default = 0.05, unit = "s", positive)]
    pub exposure_s: f64,
    /// sensor width (pco.panda 4.2: 2048)
    #[param(default = 2048, unit = "px", range = 8..=16384)]
    pub width_px: usize,
    /// sensor height
    #[param(default = 2048, unit = "px", range = 8..=16384)]
    pub height_px: usize,
    /// sensor pixel pitch (pco.panda 4.2: 6.5 µm)
    #[param(default = 6.5e-6, unit = "m", positive)]
    pub sensor_pixel_m: f64,
    /// optical magnification (pixel on the sample = sensor pixel / magnification)
    #[param(default = 2.0, positive)]
    pub magnification: f64,
    /// camera bit depth (counts written unscaled in 16-bit files above 8)
    #[param(default = 16, range = 8..=16)]
    pub bits: u32,
    /// signal of the brightest gap at the image centre, fraction of the full well
    #[param(default = 0.8, positive, range = ..=2.0)]
    pub exposure_fraction: f64,
    /// full-well capacity
    #[param(default = 30000.0, unit = "e", positive)]
    pub full_well_e: f64,
    /// read noise, rms
    #[param(default = 1.6, unit = "e", range = 0.0..)]
    pub read_noise_e: f64,
    /// flat-field fall-off at the image corners
    #[param(default = 0.15, range = 0.0..=0.9)]
    pub vignetting: f64,
    /// shot and read noise (false: only the optics, for tests)
    #[param(default = true)]
    pub noise: bool,
    /// turn of the camera against the scan's axes
    #[param(default = 2.5, unit = "deg", range = -180.0..=180.0)]
    pub angle_deg: f64,
    /// scan point under the image centre, from the map's centre, x
    #[param(default = 1.5e-4, unit = "m")]
    pub shift_x_m: f64,
    /// scan point under the image centre, from the map's centre, y
    #[param(default = -1e-4, unit = "m")]
    pub shift_y_m: f64,
    /// force sampling rate (the paper's: 50 Hz)
    #[param(default = 50.0, unit = "Hz", positive)]
    pub force_rate_hz: f64,
    /// force resolution (the paper's: 0.01 N)
    #[param(default = 0.01, unit = "N", positive)]
    pub force_resolution_n: f64,
    /// force noise, rms, before quantisation
    #[param(default = 0.005, unit = "N", range = 0.0..)]
    pub force_noise_n: f64,
    /// force-sensor clock minus camera clock
    #[param(default = 0.37, unit = "s", range = -3600.0..=3600.0)]
    pub clock_offset_s: f64,
    /// log the camera's exposure signal beside the force (column camera_trigger, 0/1), as a DAQ wired to the camera's trigger output does
    #[param(default = true)]
    pub trigger: bool,
    /// relative tolerance of each contact solve (as `bem`)
    #[param(default = 1e-8, positive, range = ..=0.1)]
    pub tolerance: f64,
    /// conjugate-gradient iterations per solve
    #[param(default = 2000, range = 1..=10_000_000)]
    pub max_iterations: usize,
    /// A/A0 (true, in the camera's view) of the frames whose true contact map is written
    #[param(default = vec![0.1, 0.5, 0.9], positive, range = ..=1.0)]
    pub map_fractions: Vec<f64>,
    /// random seed (camera and force noise)
    #[param(default = 1)]
    pub seed: u64,
}

fn consistent(p: &SynthContactParams) -> Result<(), ParamError> {
    if p.frames_before_contact + 1 >= p.frames {
        return Err(ParamError::new(
            "frames_before_contact",
            format!(
                "{} leaves no frame in contact of {}",
                p.frames_before_contact, p.frames
            ),
        ));
    }
    (0..p.map_fractions.len()).try_for_each(|i| check_map_fraction(&p.map_fractions, i))
}

impl SynthContactParams {
    /// The camera pixel on the sample.
    pub fn pixel_m(&self) -> f64 {
        self.sensor_pixel_m / self.magnification
    }

    pub fn placement(&self) -> Placement {
        Placement {
            angle_rad: self.angle_deg.to_radians(),
            shift_x_m: self.shift_x_m,
            shift_y_m: self.shift_y_m,
        }
    }

    pub fn grid(&self) -> CameraGrid {
        CameraGrid {
            width_px: self.width_px,
            height_px: self.height_px,
            pixel_m: self.pixel_m(),
        }
    }

    pub fn camera(&self) -> CameraParams {
        CameraParams {
            bits: self.bits,
            full_well_e: self.full_well_e,
            exposure_fraction: self.exposure_fraction,
            read_noise_e: self.read_noise_e,
            gain_e_per_dn: None,
            black_level_dn: 0.0,
            vignetting: self.vignetting,
            noise: self.noise,
        }
    }

    pub fn sensor(&self) -> ForceSensor {
        ForceSensor {
            rate_hz: self.force_rate_hz,
            resolution_n: self.force_resolution_n,
            noise_n: self.force_noise_n,
            clock_offset_s: self.clock_offset_s,
        }
    }
}

/// The `truth` table: one row per frame.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ContactTruthTable {
    /// frame index
    pub frame: Vec<i64>,
    /// exposure start, camera clock (as frames.csv)
    #[column(unit = "s")]
    pub time_s: Vec<f64>,
    /// mid-exposure, camera clock (the state drawn)
    #[column(unit = "s")]
    pub mid_time_s: Vec<f64>,
    /// rigid-plane penetration from first contact (< 0: open)
    #[column(unit = "m")]
    pub penetration_m: Vec<f64>,
    /// contact points / points of the whole solved map
    pub area_fraction: Vec<f64>,
    /// contact / seen camera pixels (nearest solve point): what the images can measure
    pub view_area_fraction: Vec<f64>,
    /// true force (noise-free, unquantised)
    #[column(unit = "N")]
    pub force_n: Vec<f64>,
    /// the physics that rendered the frames (solver, law, modulus, boundary), e.g. `bem, linear elastic, small-strain modulus, free boundary`: a model of the same physics agrees with this experiment by construction
    pub physics: Vec<String>,
}

/// The `truth_rig` table: one row.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct RigTruthTable {
    /// turn of the camera's x axis in the scan's axes
    #[column(unit = "rad")]
    pub angle_rad: Vec<f64>,
    /// scan point under the image centre, from the solved map's centre
    #[column(unit = "m")]
    pub shift_x_m: Vec<f64>,
    #[column(unit = "m")]
    pub shift_y_m: Vec<f64>,
    /// camera pixel on the sample
    #[column(unit = "m")]
    pub pixel_m: Vec<f64>,
    /// force-sensor clock minus camera clock
    #[column(unit = "s")]
    pub clock_offset_s: Vec<f64>,
    /// time between exposure starts
    #[column(unit = "s")]
    pub frame_interval_s: Vec<f64>,
    /// camera time of first contact
    #[column(unit = "s")]
    pub contact_time_s: Vec<f64>,
    /// spacing of the contact solve
    #[column(unit = "m")]
    pub solve_dx_m: Vec<f64>,
    /// solve grid along x
    pub solve_nx: Vec<i64>,
    /// solve grid along y
    pub solve_ny: Vec<i64>,
}

/// The `synth-contact` stage.
pub struct SynthContact;

static INFO: StageInfo = StageInfo {
    kind: "synth-contact",
    version: 5,
    summary: "Synthetic contact experiment: interference frames, frame times and force log \
              of a rough sample pressed onto glass, with the ground truth",
    doc: "The paper's in-situ rig (Section 3, Fig. 3). SAMPLE: the height map (use the \
          synthetic sample's ground truth, `synth-surface`'s `truth`, so experiment and model \
          see the surface through different instruments) is low-pass filtered to \
          `resolution_m` exactly as `surface` filters a stitched scan (Gaussian, cut-off twice \
          the spacing); the contact with the rigid glass is solved on that grid by the `bem` \
          solver (same boundary, tolerance and law: `hyperelastic` by default, the force by \
          the tangent-modulus integral over the solved frames, E_t*/E0* = 2 at first contact \
          with the paper's `tangent: equibiaxial` and 1 with `uniaxial`), each frame \
          warm-started from the previous one. PHYSICS: the experiment is the linear-elastic \
          boundary-element half-space of `bem` (with `boundary`), its force either E0* times \
          the linear load (`model: linear`, or a linear material) or the tangent-modulus \
          integral (`model: hyperelastic`, with `tangent`); the truth table's column `physics` \
          names which (e.g. `bem, hyperelastic, equibiaxial tangent, free boundary` or `bem, \
          linear elastic, small-strain modulus, free boundary`). A model run with the same \
          physics (`bem` with the same law and boundary) agrees with this experiment by \
          construction: its score measures only what the imaging, the image analysis and the \
          scan add, not the physics; contact-compare marks such responses with \
          `same_physics`. RAMP: the servo advances at `speed_m_per_s` (the \
          paper: 3 µm/s, \
          quasi-static); the last frame's penetration is where the solve first reaches \
          `max_area_fraction` (found by the `bem` curve search); frames are evenly spaced in \
          time, `frames_before_contact` of them with an open gap, first contact \
          `contact_phase` of an interval before the next frame's mid-exposure, so the frame interval \
          follows (an error if shorter than the exposure); each frame shows the state at \
          mid-exposure (no motion blur: 0.15 µm of travel in 50 ms). IMAGES: the gap of the \
          solve is drawn onto the camera's pixels: a pixel whose nearest solve point is in \
          contact has gap 0 (the solve's pixel-wise contact), elsewhere the gap is bilinear, \
          contact nodes at a patch edge carrying minus their open neighbours' mean gap so that \
          it rises from zero at the edge of the contact cell; seen through a known rotation `angle_deg` and shift of \
          the camera against the scan (pixel on the sample = sensor_pixel_m / magnification); \
          each gap's reflectance is the glass-air-rubber thin film (Airy; quartz 1.458, \
          rubber 1.50, the half-wave loss at the rubber) averaged over a white LED's spectrum; \
          then vignetting, shot and read noise, quantisation to `bits` (files are 16-bit PNG \
          with the counts unscaled when bits > 8). Outside the solved map the camera sees the \
          background. Contact is near black; gaps of 60 nm are half-way to the background; \
          the second dark fringe (~270 nm) of a phosphor white LED falls to ~0.3 of the \
          background, which a global Otsu threshold counts as contact at low load. FORCE: \
          the true force at the ramp's penetration (linear between the solved frames, 0 \
          before contact), Gaussian noise `force_noise_n`, quantised to `force_resolution_n`, \
          sampled at `force_rate_hz` on the sensor's clock (sensor time = camera time + \
          clock_offset_s) from 1 s (or two frame intervals) before the first frame to as long after \
          the last; with `trigger` (default) the log has a column camera_trigger, 1 at the \
          samples taken while the shutter was open (a DAQ wired to the camera's trigger \
          output), from which contact-images finds the clock offset. TRUTH (never \
          read by the analysis): `truth` per frame (penetration, A/A0 of the whole map and of \
          the camera's view, force, physics), `truth_rig` (transform, pixel size, clock offset, \
          timing, solve grid), `truth_maps` (the true contact on the camera's pixels as 8-bit \
          PNG masks, 255 = contact, at the frames nearest map_fractions of view A/A0, indexed \
          by the table truth_maps.parquet as contact-images indexes its maps, area_fraction \
          being the view's).",
    inputs: &[
        InputSpec::field(
            "surface",
            Arity::One,
            "the sample's true height map, metres (synth-surface's truth)",
        ),
        InputSpec::table::<MaterialTable>(
            "material",
            Arity::One,
            "the rubber's material (the true one: synth-tensile's material)",
        ),
    ],
    outputs: &[
        OutputSpec::files(
            "sequence",
            "frame_NNN.png (16-bit), frames.csv, force.csv: what contact-images reads",
        ),
        OutputSpec::table::<ContactTruthTable>("truth", "the true contact per frame"),
        OutputSpec::table::<RigTruthTable>("truth_rig", "the true transform, clock and timing"),
        OutputSpec::files_indexed::<ObservedMapIndex>(
            "truth_maps",
            "mask_aX.png (true contact on the camera's pixels), indexed",
        ),
    ],
};

impl Stage for SynthContact {
    type Params = SynthContactParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<SynthContactParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = filtered(
            inputs.areal_field("surface", "synth-contact")?,
            p.resolution_m,
        )?;
        let modulus = (p.law)
            .modulus_from_table(inputs.table("material")?, ctx)
            .map_err(|e| StageError::invalid(format!("material: {e}")))?;
        check_view_inside(&surface, &p.placement(), &p.grid())?;
        let (ramp, contacts) = solve_frames(&surface, &modulus, p, ctx)?;
        let progress = ctx.progress(p.frames as u64, "rendering frames");
        let rendered = record::render_frames(&contacts, &surface, p, &|| progress.inc(1))?;
        drop(progress);

        let (frames_csv, names) = record::frames_csv(&ramp, p.frames);
        let mut files = Files::new();
        let mut views = Vec::with_capacity(p.frames);
        for (name, (png, truth)) in names.iter().zip(rendered) {
            files = files.with(name, png);
            views.push(truth);
        }
        files = files.with("frames.csv", frames_csv.into_bytes()).with(
            "force.csv",
            record::force_csv(&contacts, &ramp, p).into_bytes(),
        );
        let view_fractions: Vec<f64> = views.iter().map(|v| view::view_fraction(v)).collect();
        let maps = truth_maps(&p.map_fractions, &view_fractions, &views, &p.grid())?;
        ctx.note(&format!(
            "{} frames every {:.3} s, penetration to {:.3} µm, A/A0 up to {:.3} ({}×{} solve grid)",
            p.frames,
            ramp.frame_interval_s,
            ramp.max_penetration_m * 1e6,
            contacts.last().map_or(0.0, |c| c.area_fraction),
            surface.nx(),
            surface.ny()
        ));
        let linear_material = modulus.tangent_mode().is_none();
        let physics = physics::label(p.law.model, p.law.tangent, p.boundary, linear_material);
        let truth = truth_table(&contacts, &ramp, view_fractions, &physics);
        let rig = rig_table(&surface, &ramp, p);
        Ok(Outputs::new()
            .files("sequence", files)
            .table("truth", truth.into_table())
            .table("truth_rig", rig.into_table())
            .files("truth_maps", maps))
    }
}

/// The ramp to the penetration where the solve first reaches
/// `max_area_fraction`, and the contact solved at each of its frames.
fn solve_frames(
    surface: &Field,
    modulus: &CompositeModulus,
    p: &SynthContactParams,
    ctx: &Context,
) -> Result<(Ramp, Vec<FrameContact>), StageError> {
    let solver = SolverOptions {
        tolerance: p.tolerance,
        max_iterations: p.max_iterations,
        ..SolverOptions::default()
    };
    // One operator for the search of the last penetration and the frames.
    let heights_m: Vec<f64> = surface.values.iter().copied().collect();
    let influence = Influence::new(
        surface.nx(),
        surface.ny(),
        surface.dx_m,
        surface.dy_m,
        p.boundary,
    );
    let problem = Problem::new(&influence, &heights_m)
        .map_err(|e| StageError::other(ContactError::Problem(e.to_string())))?;
    let max_m =
        penetration_at_m(&problem, solver, p.max_area_fraction).map_err(StageError::other)?;
    let ramp = Ramp::new(
        p.frames,
        p.frames_before_contact,
        p.contact_phase,
        max_m,
        p.speed_m_per_s,
        p.exposure_s,
    )
    .map_err(StageError::invalid)?;
    let progress = ctx.progress(p.frames as u64, "contact solves");
    let contacts = contact_sequence(
        &problem,
        surface.dx_m * surface.dy_m,
        modulus,
        p.law.scheme,
        solver,
        &ramp.penetrations_m(),
        &mut |_| progress.inc(1),
    )
    .map_err(StageError::other)?;
    Ok((ramp, contacts))
}

/// The `truth` table: per frame its times, penetration, true A/A0 of the
/// whole map and of the camera's view, true force, and the physics named.
fn truth_table(
    contacts: &[FrameContact],
    ramp: &Ramp,
    view_fractions: Vec<f64>,
    physics: &str,
) -> ContactTruthTable {
    let frames = ramp.frames;
    ContactTruthTable {
        frame: (0..frames as i64).collect(),
        time_s: (0..frames).map(|k| ramp.start_s(k)).collect(),
        mid_time_s: (0..frames).map(|k| ramp.mid_s(k)).collect(),
        penetration_m: contacts.iter().map(|c| c.penetration_m).collect(),
        area_fraction: contacts.iter().map(|c| c.area_fraction).collect(),
        view_area_fraction: view_fractions,
        force_n: contacts.iter().map(|c| c.force_n).collect(),
        physics: vec![physics.to_owned(); frames],
    }
}

/// The `truth_rig` table: the camera's placement and pixel, the clocks and
/// the solve grid.
fn rig_table(surface: &Field, ramp: &Ramp, p: &SynthContactParams) -> RigTruthTable {
    let placement = p.placement();
    RigTruthTable {
        angle_rad: vec![placement.angle_rad],
        shift_x_m: vec![placement.shift_x_m],
        shift_y_m: vec![placement.shift_y_m],
        pixel_m: vec![p.grid().pixel_m],
        clock_offset_s: vec![p.clock_offset_s],
        frame_interval_s: vec![ramp.frame_interval_s],
        contact_time_s: vec![ramp.contact_time_s],
        solve_dx_m: vec![surface.dx_m],
        solve_nx: vec![surface.nx() as i64],
        solve_ny: vec![surface.ny() as i64],
    }
}

/// The map filtered to the solve spacing (as `surface` filters a scan), or
/// as it is when it is already that coarse.
fn filtered(surface: &Field, resolution_m: f64) -> Result<Field, StageError> {
    if surface.dx_m >= resolution_m && surface.dy_m >= resolution_m {
        return Ok(surface.clone());
    }
    let values = hypercontact_surface::filter::gaussian_resample(
        &surface.values,
        surface.dx_m,
        surface.dy_m,
        resolution_m,
    );
    if values.nrows() < 2 || values.ncols() < 2 {
        return Err(StageError::invalid(format!(
            "the surface ({} × {} points of {:.3e} m) filtered to {resolution_m:e} m leaves {} × {} \
             points: too small a map for the resolution",
            surface.nx(),
            surface.ny(),
            surface.dx_m,
            values.nrows(),
            values.ncols()
        )));
    }
    Field::new(values, resolution_m, resolution_m).map_err(|e| StageError::invalid(e.to_string()))
}

/// Refuses a camera view that reaches beyond the solved map: the images
/// would show an edge no lab sample has in its view.
fn check_view_inside(
    surface: &Field,
    placement: &Placement,
    grid: &CameraGrid,
) -> Result<(), StageError> {
    let (nx, ny) = (surface.nx(), surface.ny());
    let similarity = hypercontact_interference::Similarity::new(
        placement,
        grid,
        (nx, ny),
        surface.dx_m,
        surface.dy_m,
    )
    .map_err(|e| StageError::invalid(e.to_string()))?;
    let (w, h) = (grid.width_px as f64 - 1.0, grid.height_px as f64 - 1.0);
    for (x, y) in [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)] {
        let (ix, iy) = similarity.apply(x, y);
        if !(ix >= 0.0 && iy >= 0.0 && ix <= (nx - 1) as f64 && iy <= (ny - 1) as f64) {
            return Err(StageError::invalid(format!(
                "the camera's view ({:.2} × {:.2} mm, turned {:.2}°, centre shifted by ({:.3}, \
                 {:.3}) mm) reaches beyond the {:.2} × {:.2} mm map: raise the magnification, \
                 use fewer pixels or a larger sample",
                grid.width_px as f64 * grid.pixel_m * 1e3,
                grid.height_px as f64 * grid.pixel_m * 1e3,
                placement.angle_rad.to_degrees(),
                placement.shift_x_m * 1e3,
                placement.shift_y_m * 1e3,
                (nx - 1) as f64 * surface.dx_m * 1e3,
                (ny - 1) as f64 * surface.dy_m * 1e3,
            )));
        }
    }
    Ok(())
}

/// The true contact masks at the frames nearest each requested view A/A0.
fn truth_maps(
    requested: &[f64],
    fractions: &[f64],
    views: &[Vec<Option<bool>>],
    grid: &CameraGrid,
) -> Result<Files, StageError> {
    let mut files = Files::new();
    let mut index = ObservedMapIndex::default();
    for &want in requested {
        let Some(k) = (0..fractions.len()).min_by(|&a, &b| {
            (fractions[a] - want)
                .abs()
                .total_cmp(&(fractions[b] - want).abs())
        }) else {
            continue;
        };
        let name = format!("mask_{}.png", area_fraction_label(want));
        let pixels = views[k]
            .iter()
            .map(|v| if *v == Some(true) { 255 } else { 0 })
            .collect();
        let png = encode_png(grid.width_px, grid.height_px, 8, pixels)?;
        files = files.with(&name, png);
        index.requested_area_fraction.push(want);
        index.area_fraction.push(fractions[k]);
        index.frame.push(k as i64);
        index.file.push(name);
        index.pixel_m.push(grid.pixel_m);
    }
    Ok(files.with_index(index))
}
