//! Where the camera looked: every observed map with enough contact is
//! registered on its own onto the chosen prediction, the one nearest
//! `register_at` is adopted for every frame, and the spread of the others
//! is its uncertainty (1.4826 × MAD, so one map that registers badly does
//! not throw it).

use hypercontact_core::robust::median_and_sigma;
use hypercontact_core::{Context, StageError};

use crate::maps::{ObservedMap, Predictions, predicted};
use crate::register::{RegisterSettings, Registration, register};
use crate::stage::{ContactCompareParams, RegistrationsTable, TransformTable};

/// The adopted registration and its tables.
pub(crate) struct Registered {
    pub registration: Registration,
    pub transform: TransformTable,
    pub registrations: RegistrationsTable,
}

/// Registers every observed map with A/A0 >= min_register_fraction onto
/// prediction `against` and adopts the one nearest register_at.
pub(crate) fn register_observed(
    p: &ContactCompareParams,
    observed: &[ObservedMap],
    predictions: &Predictions,
    against: &str,
    ctx: &Context,
) -> Result<Registered, StageError> {
    let settings = RegisterSettings {
        angle_centre_deg: p.angle_deg,
        angle_range_deg: p.angle_range_deg,
        refine_scale: p.refine_scale,
        scale_range: p.scale_range,
        ..RegisterSettings::default()
    };
    let registered: Vec<&ObservedMap> = observed
        .iter()
        .filter(|m| m.area_fraction >= p.min_register_fraction)
        .collect();
    if registered.is_empty() {
        return Err(StageError::invalid(format!(
            "no observed map has A/A0 >= min_register_fraction ({}): the largest is {:.4}; \
             map frames with more contact (contact-images' map_fractions)",
            p.min_register_fraction,
            observed.iter().map(|m| m.area_fraction).fold(0.0, f64::max)
        )));
    }
    let progress = ctx.progress(registered.len() as u64, "registrations");
    let mut found = Vec::with_capacity(registered.len());
    for map in &registered {
        let (_, field) = predictions.map(against, map.area_fraction)?;
        let registration = register(&predicted(&field), &map.mask(), &settings).map_err(|e| {
            StageError::invalid(format!(
                "registering the observed map of frame {} (A/A0 = {:.4}) onto `{against}`: {e}",
                map.frame, map.area_fraction
            ))
        })?;
        found.push(registration);
        progress.inc(1);
    }
    drop(progress);
    let adopted = (0..registered.len())
        .min_by(|&i, &j| {
            let d = |k: usize| (registered[k].area_fraction - p.register_at).abs();
            d(i).total_cmp(&d(j))
        })
        .expect("refused above when empty");
    Ok(Registered {
        registration: found[adopted],
        transform: transform_table(against, &registered, &found, adopted),
        registrations: registrations_table(&registered, &found, adopted),
    })
}

fn registrations_table(
    registered: &[&ObservedMap],
    found: &[Registration],
    adopted: usize,
) -> RegistrationsTable {
    RegistrationsTable {
        frame: registered.iter().map(|m| m.frame).collect(),
        area_fraction: registered.iter().map(|m| m.area_fraction).collect(),
        angle_deg: found
            .iter()
            .map(|r| r.placement.angle_rad.to_degrees())
            .collect(),
        shift_x_m: found.iter().map(|r| r.placement.shift_x_m).collect(),
        shift_y_m: found.iter().map(|r| r.placement.shift_y_m).collect(),
        scale: found.iter().map(|r| r.scale).collect(),
        zncc: found.iter().map(|r| r.score).collect(),
        adopted: (0..found.len()).map(|k| i64::from(k == adopted)).collect(),
    }
}

/// A robust standard deviation: 1.4826 × the median absolute deviation
/// from the median (equal to σ for Gaussian scatter, and not thrown by one
/// map that registers badly); NaN for fewer than two values.
fn robust_sd(values: &[f64]) -> f64 {
    if values.len() < 2 {
        return f64::NAN;
    }
    median_and_sigma(values).1
}

fn transform_table(
    against: &str,
    observed: &[&ObservedMap],
    found: &[Registration],
    adopted: usize,
) -> TransformTable {
    let r = &found[adopted];
    let of = |f: fn(&Registration) -> f64| robust_sd(&found.iter().map(f).collect::<Vec<_>>());
    TransformTable {
        against: vec![against.to_owned()],
        frame: vec![observed[adopted].frame],
        area_fraction: vec![observed[adopted].area_fraction],
        angle_deg: vec![r.placement.angle_rad.to_degrees()],
        shift_x_m: vec![r.placement.shift_x_m],
        shift_y_m: vec![r.placement.shift_y_m],
        scale: vec![r.scale],
        zncc: vec![r.score],
        registrations: vec![found.len() as i64],
        angle_sd_deg: vec![of(|r| r.placement.angle_rad.to_degrees())],
        shift_x_sd_m: vec![of(|r| r.placement.shift_x_m)],
        shift_y_sd_m: vec![of(|r| r.placement.shift_y_m)],
        scale_sd: vec![of(|r| r.scale)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_is_not_thrown_by_one_bad_registration() {
        // 1.4826 × MAD: for ±1 about 0 (MAD 1) it is 1.4826; one wild
        // value among five moves it little, where the plain sd explodes.
        assert!((robust_sd(&[-1.0, 1.0, 0.0, -1.0, 1.0]) - 1.4826).abs() < 1e-12);
        assert!((robust_sd(&[-1.0, 1.0, 0.0, -1.0, 100.0]) - 1.4826).abs() < 1e-12);
        assert!(robust_sd(&[2.5]).is_nan());
    }
}
