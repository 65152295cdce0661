//! What the lab records of the contact experiment (the paper's Section 3,
//! Fig. 3): each frame's solved gap drawn onto the camera and exposed
//! (thin-film optics, vignetting, noise, quantisation) as a 16-bit PNG with
//! the true contact on its pixels, `frames.csv` with the exposure starts,
//! and `force.csv`, the force sensor's log on its own clock (with the
//! camera's trigger when asked).

use hypercontact_core::{Field, StageError};
use hypercontact_interference::{
    Camera, CameraGrid, GapMap, OpticsParams, Placement, expose, resample,
};
use ndarray::ArrayView2;
use rayon::prelude::*;

use super::SynthContactParams;
use super::rig::{Ramp, interpolate_force};
use super::solve::FrameContact;
use super::view;
use crate::encode_png;

/// One rendered frame: the PNG and the true contact on its pixels (None
/// where the camera sees no solved point).
pub type RenderedFrame = (Vec<u8>, Vec<Option<bool>>);

/// Every frame drawn and exposed, in parallel over frames (each frame's
/// noise from its own seed); `done` is called once per frame.
pub fn render_frames(
    contacts: &[FrameContact],
    surface: &Field,
    p: &SynthContactParams,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<RenderedFrame>, StageError> {
    let table = OpticsParams::default()
        .build()
        .map_err(|e| StageError::invalid(e.to_string()))?;
    let camera = Camera::new(p.camera(), table.max_reflectance())
        .map_err(|e| StageError::invalid(e.to_string()))?;
    let (nx, ny) = (surface.nx(), surface.ny());
    let placement = p.placement();
    let grid = p.grid();
    let measured: Vec<bool> = surface.values.iter().map(|h| !h.is_nan()).collect();
    contacts
        .par_iter()
        .enumerate()
        .map(|(k, c)| {
            let drawn = view::drawing_gap(&c.gap_m, &c.in_contact, nx, ny);
            let drawn = ArrayView2::from_shape((nx, ny), &drawn)
                .map_err(|e| StageError::invalid(e.to_string()))?;
            let gap = GapMap {
                gap_m: drawn,
                dx_m: surface.dx_m,
                dy_m: surface.dy_m,
            };
            let truth = view::true_view(
                &c.in_contact,
                &measured,
                (nx, ny),
                (surface.dx_m, surface.dy_m),
                &placement,
                &grid,
            )
            .map_err(|e| StageError::invalid(e.to_string()))?;
            let gap_m = seen_gap_m(&gap, &truth, &placement, &grid)?;
            let frame = expose(gap_m, &grid, &table, &camera, frame_seed(p.seed, k))
                .map_err(|e| StageError::invalid(e.to_string()))?;
            let png = encode_png(grid.width_px, grid.height_px, p.bits, frame.counts)?;
            done();
            Ok((png, truth))
        })
        .collect()
}

/// The gap on the camera's pixels: zero on a contact cell, never negative,
/// NaN (background) where no solved point is seen.
fn seen_gap_m(
    gap: &GapMap,
    truth: &[Option<bool>],
    placement: &Placement,
    grid: &CameraGrid,
) -> Result<Vec<f64>, StageError> {
    let mut gap_m =
        resample(gap, placement, grid).map_err(|e| StageError::invalid(e.to_string()))?;
    for (g, t) in gap_m.iter_mut().zip(truth) {
        // a pixel on a contact cell touches; NaN stays NaN (background)
        *g = if *t == Some(true) { 0.0 } else { g.max(0.0) };
    }
    Ok(gap_m)
}

/// Frame k's noise seed.
fn frame_seed(seed: u64, k: usize) -> u64 {
    seed.wrapping_mul(1_000_003).wrapping_add(k as u64)
}

/// `frames.csv`: frame, exposure start (camera clock) and file name of each
/// frame, the names numbered with at least three digits.
pub fn frames_csv(ramp: &Ramp, frames: usize) -> (String, Vec<String>) {
    let digits = (frames - 1).to_string().len().max(3);
    let mut csv = String::from("frame,time_s,file\n");
    let mut names = Vec::with_capacity(frames);
    for k in 0..frames {
        let name = format!("frame_{k:0digits$}.png");
        csv.push_str(&format!("{k},{},{name}\n", ramp.start_s(k)));
        names.push(name);
    }
    (csv, names)
}

/// `force.csv`: the sensor's log of the force interpolated between the
/// solved (penetration, force) points, on the sensor's clock; with
/// `trigger`, a column camera_trigger, 1 while the shutter was open.
pub fn force_csv(contacts: &[FrameContact], ramp: &Ramp, p: &SynthContactParams) -> String {
    let mut points = vec![(0.0, 0.0)];
    points.extend(
        contacts
            .iter()
            .filter(|c| c.penetration_m > 0.0)
            .map(|c| (c.penetration_m, c.force_n)),
    );
    let sensor = p.sensor();
    let decimals = sensor.decimals();
    let mut csv = String::from(if p.trigger {
        "time_s,force_n,camera_trigger\n"
    } else {
        "time_s,force_n\n"
    });
    for (t, f) in sensor.log(ramp, |d| interpolate_force(&points, d), p.seed) {
        csv.push_str(&format!("{t:.6},{f:.decimals$}"));
        if p.trigger {
            let open = ramp.exposing(t - sensor.clock_offset_s);
            csv.push_str(if open { ",1" } else { ",0" });
        }
        csv.push('\n');
    }
    csv
}
