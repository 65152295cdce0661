//! `height-map`'s preparation of a map as read: a mask from a file, a window, a circular
//! region, spikes set to NaN, a form subtracted and the scan lines levelled,
//! in that order, each step's effect in a note. Spikes go before the form: a
//! least-squares form is pulled by them, while the spike rule's local
//! estimates follow the form. The scan lines are levelled last, on what the
//! form leaves: a line's own median or tilt taken from a curved map would
//! take that line's share of the form (a sphere levelled line by line is
//! left a cylinder, to which no sphere fits), while line offsets pull a
//! least-squares form only through their average trend, which the form
//! absorbs and the line levelling then finds no more. The steps are
//! [`crate::region`], [`crate::spikes`], [`crate::form`] and
//! [`crate::level_rows`].

use hypercontact_core::{Choice, Context, Field, StageError};
use ndarray::Array2;

use crate::form::{CylinderAxis, remove_cylinder, remove_polynomial, remove_sphere};
use crate::height_map::HeightMapParams;
use crate::level_rows::{Axis, LevelledRows, LineModel, level_rows};
use crate::mask_file::read_mask;
use crate::region::{Keep, Shape, Window, apply_mask, crop};
use crate::spikes::{LocalRule, remove_outliers, remove_spikes};

/// The largest share of the measured points a spike rule may remove: more
/// is the map's texture or form judged as spikes (on a smooth curved map
/// the robust σ is rounding noise and every curved edge point "deviates").
pub const MAX_SPIKE_SHARE: f64 = 0.02;

/// Which points count as spikes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum SpikeRule {
    /// none are removed (the default)
    None,
    /// farther than spike_k robust σ from what the neighbours (spike_radius) predict
    Local,
    /// farther than spike_k robust σ (1.4826 MAD) from the median height of the map
    Global,
}

/// The form subtracted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum FormKind {
    /// nothing (the default; `surface` still removes a plane)
    None,
    /// a polynomial of total degree form_degree (Legendre, least squares)
    Polynomial,
    /// a sphere (dome or bowl), radius fitted
    Sphere,
    /// a cylinder with its axis along x
    CylinderX,
    /// a cylinder with its axis along y
    CylinderY,
    /// a cylinder whose in-plane axis angle is fitted
    Cylinder,
}

/// How the scan lines are levelled (the methods of Gwyddion's "Align Rows").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum LevelRows {
    /// not at all (the default)
    None,
    /// each line's median height subtracted
    Median,
    /// each line's mean height subtracted
    Mean,
    /// each line's least-squares straight line subtracted (offset and slope)
    Tilt,
    /// each line's least-squares polynomial of degree level_rows_degree subtracted
    Polynomial,
    /// each line shifted so that the median of its height differences to the line before is zero
    MedianDifferences,
}

/// The axis along which the instrument scanned each line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Choice)]
pub enum FastAxis {
    /// scan lines along x (array axis 0)
    X,
    /// scan lines along y (array axis 1)
    Y,
}

impl From<FastAxis> for Axis {
    fn from(axis: FastAxis) -> Self {
        match axis {
            FastAxis::X => Axis::X,
            FastAxis::Y => Axis::Y,
        }
    }
}

/// The fast axis a file states, and the format that states it (for the note).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatedFastAxis {
    pub axis: Axis,
    pub format: &'static str,
}

/// The map after the steps `p` asks for; each step that ran leaves a note.
/// `stated` is the fast axis the file gives, if it gives one.
pub fn prepare(
    map: Field,
    stated: Option<StatedFastAxis>,
    p: &HeightMapParams,
    ctx: &Context,
) -> Result<Field, StageError> {
    let (dx_m, dy_m) = (map.dx_m, map.dy_m);
    let mut h = map.values;
    if let Some(path) = &p.mask {
        let keep = read_mask(path.path(), p.max_points)?;
        let region =
            apply_mask(&h, dx_m, dy_m, &Shape::Points(keep), Keep::Inside).map_err(|e| {
                StageError::file(
                    path.path(),
                    format!("mask: {e} (the map as read, axis 0 = x, before any window)"),
                )
            })?;
        ctx.note(&format!(
            "{} ({})",
            region.description,
            path.path().display()
        ));
        h = region.height_m;
    }
    let window = match (p.crop_points, p.crop_m) {
        (Some([x0, y0, nx, ny]), _) => Some(Window::Points { x0, y0, nx, ny }),
        (None, Some([x0_m, y0_m, lx_m, ly_m])) => Some(Window::Metres {
            x0_m,
            y0_m,
            lx_m,
            ly_m,
        }),
        (None, None) => None,
    };
    if let Some(window) = window {
        let region = crop(&h, dx_m, dy_m, &window)?;
        ctx.note(&region.description);
        h = region.height_m;
    }
    if let Some([xc_m, yc_m, radius_m]) = p.circle_m {
        let shape = Shape::Circle {
            xc_m,
            yc_m,
            radius_m,
        };
        let region = apply_mask(&h, dx_m, dy_m, &shape, Keep::Inside)?;
        ctx.note(&region.description);
        h = region.height_m;
    }
    h = without_spikes(h, p, ctx)?;
    h = without_form(h, (dx_m, dy_m), p, ctx)?;
    h = with_lines_levelled(h, stated, p, ctx)?;
    Field::new(h, dx_m, dy_m).map_err(StageError::other)
}

fn without_spikes(
    h: Array2<f64>,
    p: &HeightMapParams,
    ctx: &Context,
) -> Result<Array2<f64>, StageError> {
    let spikes = match p.spikes {
        SpikeRule::None => return Ok(h),
        SpikeRule::Local => remove_spikes(
            &h,
            &LocalRule {
                k: p.spike_k,
                radius: p.spike_radius,
                ..LocalRule::default()
            },
        ),
        SpikeRule::Global => remove_outliers(&h, p.spike_k),
    }
    .map_err(|e| StageError::invalid(format!("spikes: {e}")))?;
    let measured = h.iter().filter(|v| !v.is_nan()).count();
    if spikes.points.len() as f64 > MAX_SPIKE_SHARE * measured as f64 {
        return Err(StageError::invalid(format!(
            "spikes: the {} rule marks {} of {measured} measured points ({:.1} %), more than \
             spikes can be: on a map this smooth or this curved its robust σ ({:.3e} m) is not \
             the texture's; raise spike_k, or leave spikes out",
            if p.spikes == SpikeRule::Local {
                "local"
            } else {
                "global"
            },
            spikes.points.len(),
            100.0 * spikes.points.len() as f64 / measured as f64,
            spikes.sigma_m,
        )));
    }
    ctx.note(&spikes.description);
    Ok(spikes.height_m)
}

fn without_form(
    h: Array2<f64>,
    (dx_m, dy_m): (f64, f64),
    p: &HeightMapParams,
    ctx: &Context,
) -> Result<Array2<f64>, StageError> {
    let (description, residual_m) = match p.form {
        FormKind::None => return Ok(h),
        FormKind::Polynomial => {
            let f = remove_polynomial(&h, dx_m, dy_m, p.form_degree)?;
            (f.description(), f.residual_m)
        }
        FormKind::Sphere => {
            let f = remove_sphere(&h, dx_m, dy_m)?;
            (f.description(), f.residual_m)
        }
        FormKind::CylinderX | FormKind::CylinderY | FormKind::Cylinder => {
            let axis = match p.form {
                FormKind::CylinderX => CylinderAxis::X,
                FormKind::CylinderY => CylinderAxis::Y,
                _ => CylinderAxis::Fitted,
            };
            let f = remove_cylinder(&h, dx_m, dy_m, axis)?;
            (f.description(), f.residual_m)
        }
    };
    ctx.note(&description);
    Ok(residual_m)
}

fn with_lines_levelled(
    h: Array2<f64>,
    stated: Option<StatedFastAxis>,
    p: &HeightMapParams,
    ctx: &Context,
) -> Result<Array2<f64>, StageError> {
    let model = match p.level_rows {
        LevelRows::None => return Ok(h),
        LevelRows::Median => LineModel::Median,
        LevelRows::Mean => LineModel::Mean,
        LevelRows::Tilt => LineModel::Polynomial { degree: 1 },
        LevelRows::Polynomial => LineModel::Polynomial {
            degree: p.level_rows_degree,
        },
        LevelRows::MedianDifferences => LineModel::MedianDifferences,
    };
    let (axis, whence) = fast_axis(p.fast_axis, stated);
    let rows = level_rows(&h, axis, model)
        .map_err(|e| StageError::file(&p.path, format!("level_rows: {e}")))?;
    ctx.note(&levelling_note(&rows, model, axis, &whence));
    Ok(rows.height_m)
}

/// The fast axis to level along, and where it comes from: the parameter
/// (which overrides the file, saying so where they differ), the file, or
/// the default x (as a raster scan with unrotated axes is stored).
fn fast_axis(given: Option<FastAxis>, stated: Option<StatedFastAxis>) -> (Axis, String) {
    match (given.map(Axis::from), stated) {
        (Some(axis), Some(file)) if axis != file.axis => (
            axis,
            format!(
                "given by fast_axis; the {} file states {}",
                file.format,
                file.axis.name()
            ),
        ),
        (Some(axis), _) => (axis, "given by fast_axis".into()),
        (None, Some(file)) => (file.axis, format!("as the {} file states", file.format)),
        (None, None) => (
            Axis::X,
            "the default: the file does not say; set fast_axis if the lines ran along y".into(),
        ),
    }
}

/// `level rows: each scan line's median subtracted (fast axis x, as the
/// Nanosurf .nid file states): 256 lines, 1.23 nm rms removed (at most
/// 4.10 nm from its mean; 12.0 nm rms left); 2 lines with fewer than 2
/// measured points left as is`.
fn levelling_note(rows: &LevelledRows, model: LineModel, axis: Axis, whence: &str) -> String {
    use crate::form::length;
    let what = match model {
        LineModel::MedianDifferences => {
            "each scan line shifted so that the median of its differences to the line before \
             is zero"
                .to_string()
        }
        _ => format!("each scan line's {} subtracted", model.name()),
    };
    let mut note = format!(
        "level rows: {what} (fast axis {}, {whence}): {} lines, {} rms removed (at most {} \
         from its mean; {} rms left)",
        axis.name(),
        rows.levelled,
        length(rows.removed_rms_m),
        length(rows.removed_max_m),
        length(rows.residual_rms_m),
    );
    if rows.left_as_is > 0 {
        let why = match model {
            LineModel::MedianDifferences => {
                "without a point measured both in it and in the line before".to_string()
            }
            _ => format!("with fewer than {} measured points", model.min_points()),
        };
        note.push_str(&format!("; {} lines {why} left as is", rows.left_as_is));
    }
    if rows.empty > 0 {
        note.push_str(&format!("; {} lines without a measured point", rows.empty));
    }
    note
}
