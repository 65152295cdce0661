//! `height-map`'s preparation of a map as read: a mask from a file, a window, a circular
//! region, spikes set to NaN and a form subtracted, in that order, each
//! step's effect in a note. Spikes go before the form: a least-squares form
//! is pulled by them, while the spike rule's local estimates follow the form.
//! The steps are [`crate::region`], [`crate::spikes`] and [`crate::form`].

use hypercontact_core::{Choice, Context, Field, StageError};
use ndarray::Array2;

use crate::form::{CylinderAxis, remove_cylinder, remove_polynomial, remove_sphere};
use crate::height_map::HeightMapParams;
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

/// The map after the steps `p` asks for; each step that ran leaves a note.
pub fn prepare(map: Field, p: &HeightMapParams, ctx: &Context) -> Result<Field, StageError> {
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
