//! Do `contact-compare`'s inputs belong together? The index tables carry no
//! sample or run name (ObservedMapIndex: A/A0, frame, file, pixel_m;
//! ModelMapIndex: A/A0, load, file, spacing), so belonging is judged from
//! what they do carry: the model maps' grid against the scan's, the camera's
//! view against the scan's extent, the observed maps' frames and A/A0
//! against the contact table, and the labels against what is wired. What
//! cannot be checked before the work (a scan of another sample on the same
//! grid) shows after it, in a registration that fits badly or a load–area
//! curve far from every model: those are noted ([`quality_notes`]).

use std::collections::BTreeSet;

use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::{Field, Inputs, StageError};

use crate::maps::{ModelMaps, ObservedMap, Predictions, TRUNCATION};
use crate::stage::{AgreementTable, ContactCompareParams, TransformTable};

/// Labels the stage gives its own predictions: a model labelled so would be
/// shadowed by them.
pub const RESERVED_LABELS: [&str; 1] = [TRUNCATION];

/// Below this ZNCC the adopted registration is noted as doubtful. The
/// paper pipeline's registrations onto `bem` reach 0.78–0.81 (T1–T4), and
/// the synthetic lab's onto the truncation 0.58 (T3, the lowest measured);
/// observed maps of another run registered at 0.32.
pub const LOW_ZNCC: f64 = 0.5;

/// Above this rms log ratio for even the best model the contact table is
/// noted as doubtful: a factor e ≈ 2.7 in load on average. The paper
/// pipeline's best models score 0.08–0.10; a table of another run scored 3.6.
pub const FAR_RMS_LOG_RATIO: f64 = 1.0;

/// A registration parameter within this share of its search range from a
/// bound of the range, or beyond it (the refinement may step past the
/// coarse search's range), is noted as sitting on it.
pub const ON_BOUND_SHARE: f64 = 0.02;

/// Refuses model_maps labels that are reserved, `view_maps` keys that are
/// no `responses` label and values that are no prediction, and
/// `same_physics` names that are no `responses` label.
pub(crate) fn check_labels(
    p: &ContactCompareParams,
    inputs: &Inputs,
    predictions: &Predictions,
) -> Result<(), StageError> {
    for models in &predictions.models {
        if RESERVED_LABELS.contains(&models.label.as_str()) {
            return Err(StageError::invalid(format!(
                "input `model_maps.{0}`: the label `{0}` is reserved for the stage's own \
                 prediction (the height map cut at the observed A/A0); label the model \
                 otherwise",
                models.label
            )));
        }
    }
    let responses: BTreeSet<&str> = inputs
        .labelled("responses")
        .into_iter()
        .map(|(label, _)| label)
        .collect();
    for (key, value) in &p.view_maps {
        if !responses.contains(key.as_str()) {
            let wired: Vec<&str> = responses.iter().copied().collect();
            return Err(StageError::invalid(format!(
                "parameter `view_maps`: key `{key}` is not a label of `responses` ({})",
                if wired.is_empty() {
                    "none connected".to_owned()
                } else {
                    wired.join(", ")
                }
            )));
        }
        predictions.check_name(&format!("view_maps.{key}"), value)?;
    }
    for name in &p.same_physics {
        if !responses.contains(name.as_str()) {
            let wired: Vec<&str> = responses.iter().copied().collect();
            return Err(StageError::invalid(format!(
                "parameter `same_physics`: `{name}` is not a label of `responses` ({})",
                if wired.is_empty() {
                    "none connected".to_owned()
                } else {
                    wired.join(", ")
                }
            )));
        }
    }
    Ok(())
}

/// Refuses a model map whose grid (size or spacing) differs from the scan
/// `surface`: the contact models ran on another height map.
pub(crate) fn check_model_grids(surface: &Field, models: &[ModelMaps]) -> Result<(), StageError> {
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
    for model in models {
        for (fraction, map) in &model.maps {
            if map.nx() == surface.nx()
                && map.ny() == surface.ny()
                && same(map.dx_m, surface.dx_m)
                && same(map.dy_m, surface.dy_m)
            {
                continue;
            }
            return Err(StageError::invalid(format!(
                "input `model_maps.{}`: its map at A/A0 = {fraction:.4} is {} × {} points of \
                 {} × {} µm, but `surface` is {} × {} points of {} × {} µm: the model ran on \
                 another height map",
                model.label,
                map.nx(),
                map.ny(),
                map.dx_m * 1e6,
                map.dy_m * 1e6,
                surface.nx(),
                surface.ny(),
                surface.dx_m * 1e6,
                surface.dy_m * 1e6
            )));
        }
    }
    Ok(())
}

/// Refuses observed maps of different cameras, and a camera view larger
/// than the scan along either side (sides compared shorter with shorter,
/// longer with longer, so a camera turned a quarter is not refused): the
/// scan cannot cover the view.
pub(crate) fn check_view_within_scan(
    surface: &Field,
    observed: &[ObservedMap],
) -> Result<(), StageError> {
    let first = &observed[0];
    if let Some(other) = observed
        .iter()
        .find(|m| (m.width, m.height) != (first.width, first.height) || m.pixel_m != first.pixel_m)
    {
        return Err(StageError::invalid(format!(
            "input `observed_maps`: the map of frame {} is {} × {} px of {} µm, that of frame \
             {} {} × {} px of {} µm: the maps come from different cameras or runs",
            first.frame,
            first.width,
            first.height,
            first.pixel_m * 1e6,
            other.frame,
            other.width,
            other.height,
            other.pixel_m * 1e6
        )));
    }
    let sorted = |a: f64, b: f64| if a <= b { (a, b) } else { (b, a) };
    let view = sorted(
        first.width as f64 * first.pixel_m,
        first.height as f64 * first.pixel_m,
    );
    let scan = sorted(
        surface.nx() as f64 * surface.dx_m,
        surface.ny() as f64 * surface.dy_m,
    );
    if view.0 > scan.0 || view.1 > scan.1 {
        return Err(StageError::invalid(format!(
            "the camera's view ({} × {} px of {} µm = {:.0} × {:.0} µm, input `observed_maps`) \
             is larger than the scan `surface` ({} × {} points = {:.0} × {:.0} µm): the scan \
             cannot cover it; are they of the same sample, and is contact-images' pixel_m \
             right?",
            first.width,
            first.height,
            first.pixel_m * 1e6,
            first.width as f64 * first.pixel_m * 1e6,
            first.height as f64 * first.pixel_m * 1e6,
            surface.nx(),
            surface.ny(),
            surface.nx() as f64 * surface.dx_m * 1e6,
            surface.ny() as f64 * surface.dy_m * 1e6
        )));
    }
    Ok(())
}

/// How far an observed map's A/A0 may lie from the contact table's for its
/// frame: contact-images writes the table's value itself (equal), while
/// synth-contact's true maps differ from a measurement by the method's
/// bias (the calibrated method: +2 to +23 %), so 25 % and 0.01 apart.
fn same_run(map_fraction: f64, table_fraction: f64) -> bool {
    (map_fraction - table_fraction).abs() <= 0.01 + 0.25 * table_fraction.abs()
}

/// Refuses observed maps whose frame is not in `contact`, or whose A/A0
/// is far from the table's for that frame: the two are of different runs.
pub(crate) fn check_observed_in_table(
    observed: &[ObservedMap],
    contact: &ContactTable,
) -> Result<(), StageError> {
    for map in observed {
        let Some(k) = contact.frame.iter().position(|&f| f == map.frame) else {
            return Err(StageError::invalid(format!(
                "input `observed_maps`: frame {} is not in `contact` (its {} frames): the maps \
                 and the table come from different runs",
                map.frame,
                contact.frame.len()
            )));
        };
        if !same_run(map.area_fraction, contact.area_fraction[k]) {
            return Err(StageError::invalid(format!(
                "input `observed_maps`: the map of frame {} has A/A0 = {:.4}, but `contact` \
                 gives {:.4} for that frame: the maps and the table come from different runs",
                map.frame, map.area_fraction, contact.area_fraction[k]
            )));
        }
    }
    Ok(())
}

/// Warnings on a finished comparison: the adopted turn or scale on a bound
/// of its search, a ZNCC below [`LOW_ZNCC`], and even the best model's rms
/// log ratio above [`FAR_RMS_LOG_RATIO`]. This one looks at every model,
/// those by construction too: it asks whether the table belongs to the
/// run, and a model of the experiment's own physics that agrees says it
/// does; it ranks nothing.
pub(crate) fn quality_notes(
    p: &ContactCompareParams,
    transform: &TransformTable,
    agreement: &AgreementTable,
) -> Vec<String> {
    let mut notes = Vec::new();
    let frame = transform.frame[0];
    let angle_deg = transform.angle_deg[0];
    // The turn off the expected one, wrapped into (−180°, 180°].
    let off_deg = (angle_deg - p.angle_deg + 180.0).rem_euclid(360.0) - 180.0;
    if p.angle_range_deg < 180.0
        && p.angle_range_deg - off_deg.abs() <= ON_BOUND_SHARE * p.angle_range_deg
    {
        notes.push(format!(
            "warning: the turn found on frame {frame}, {angle_deg:.3}°, lies on or beyond the \
             bound of its search (angle_deg {} ± angle_range_deg {}): the fit stopped there; \
             widen the range, or check that the maps are of this sample",
            p.angle_deg, p.angle_range_deg
        ));
    }
    let scale = transform.scale[0];
    if p.refine_scale
        && p.scale_range > 0.0
        && p.scale_range - (scale - 1.0).abs() <= ON_BOUND_SHARE * p.scale_range
    {
        notes.push(format!(
            "warning: the scale found on frame {frame}, {scale:.4}, lies on or beyond the bound \
             of its search (1 ± scale_range {}): the fit stopped there; check pixel_m, or that \
             the maps are of this sample",
            p.scale_range
        ));
    }
    let zncc = transform.zncc[0];
    if zncc.is_nan() || zncc < LOW_ZNCC {
        notes.push(format!(
            "warning: the registration of frame {frame} onto `{}` reaches ZNCC {zncc:.3}, \
             below {LOW_ZNCC} (a sample's own maps reach 0.58–0.81): are the observed maps \
             and `surface` of the same sample?",
            transform.against[0]
        ));
    }
    let best = agreement
        .rms_log_ratio
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, r)| !r.is_nan())
        .min_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((k, rms)) = best
        && rms > FAR_RMS_LOG_RATIO
    {
        notes.push(format!(
            "warning: even the best model, `{}`, scores rms log ratio {rms:.3} against \
             `contact`, above {FAR_RMS_LOG_RATIO} (a factor {:.1} in load; a sample's own \
             table scores 0.08–0.10): is the contact table of this sample and run?",
            agreement.model[k],
            FAR_RMS_LOG_RATIO.exp()
        ));
    }
    notes
}

#[cfg(test)]
mod tests {
    use hypercontact_core::{Params, Product};
    use ndarray::Array2;

    use super::*;
    use crate::maps::Truncation;

    fn field(nx: usize, ny: usize, dx_m: f64) -> Field {
        Field::new(Array2::from_elem((nx, ny), 0.0), dx_m, dx_m).unwrap()
    }

    fn observed(frame: i64, area_fraction: f64, px: usize, pixel_m: f64) -> ObservedMap {
        ObservedMap {
            requested: area_fraction,
            area_fraction,
            frame,
            pixel_m,
            width: px,
            height: px,
            contact: vec![false; px * px],
        }
    }

    fn params(json: serde_json::Value) -> ContactCompareParams {
        serde_json::from_value::<ContactCompareParams>(json)
            .unwrap()
            .check()
            .unwrap()
            .into_inner()
    }

    /// A wired response: the checks read only its label.
    fn response() -> Product {
        Product::Field(field(2, 2, 1e-5))
    }

    #[test]
    fn labels_are_refused_both_ways_and_when_reserved() {
        let surface = field(8, 8, 1e-5);
        let inputs = Inputs::new()
            .with("responses.bem", response())
            .with("responses.bem-linear", response());
        let bem = |label: &str| ModelMaps {
            label: label.to_owned(),
            maps: vec![(0.5, field(8, 8, 1e-5))],
        };
        let predictions = Predictions {
            truncation: Truncation::new(&surface),
            models: vec![bem("bem")],
        };
        let ok = params(serde_json::json!({ "view_maps": { "bem-linear": "bem" } }));
        assert!(check_labels(&ok, &inputs, &predictions).is_ok());
        // Before #31 `{ghost: bem}` was ignored; `{bem: ghost}` refused.
        let e = check_labels(
            &params(serde_json::json!({ "view_maps": { "ghost": "bem" } })),
            &inputs,
            &predictions,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "parameter `view_maps`: key `ghost` is not a label of `responses` (bem, bem-linear)"
        );
        let e = check_labels(
            &params(serde_json::json!({ "view_maps": { "bem": "ghost" } })),
            &inputs,
            &predictions,
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("parameter `view_maps.bem` = ghost"), "{e}");
        // #49: a same_physics name must be a wired response.
        let same = params(serde_json::json!({ "same_physics": ["bem-linear"] }));
        assert!(check_labels(&same, &inputs, &predictions).is_ok());
        let e = check_labels(
            &params(serde_json::json!({ "same_physics": ["bem", "fem"] })),
            &inputs,
            &predictions,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "parameter `same_physics`: `fem` is not a label of `responses` (bem, bem-linear)"
        );
        // A model labelled `truncation` was shadowed by the built-in cut.
        let shadowed = Predictions {
            truncation: Truncation::new(&surface),
            models: vec![bem("truncation")],
        };
        let e = check_labels(&ok, &inputs, &shadowed)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("input `model_maps.truncation`: the label `truncation` is reserved"),
            "{e}"
        );
    }

    #[test]
    fn model_maps_on_another_grid_and_a_view_beyond_the_scan_are_refused() {
        let surface = field(64, 64, 1e-5);
        let on = |nx, dx_m| ModelMaps {
            label: "bem".to_owned(),
            maps: vec![(0.5, field(nx, nx, dx_m))],
        };
        assert!(check_model_grids(&surface, &[on(64, 1e-5)]).is_ok());
        let e = check_model_grids(&surface, &[on(32, 2e-5)])
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "input `model_maps.bem`: its map at A/A0 = 0.5000 is 32 × 32 points of 20 × 20 µm, \
             but `surface` is 64 × 64 points of 10 × 10 µm: the model ran on another height map"
        );
        assert!(check_model_grids(&surface, &[on(64, 1.1e-5)]).is_err());
        // 640 µm of scan: a 100 px view of 4 µm fits, a 416 µm view does not
        // fit a 4 × 4 px map of 20 µm (before #31 both ran).
        assert!(check_view_within_scan(&surface, &[observed(1, 0.5, 100, 4e-6)]).is_ok());
        let e = check_view_within_scan(&field(4, 4, 2e-5), &[observed(1, 0.5, 128, 3.25e-6)])
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("the camera's view (128 × 128 px of 3.25 µm = 416 × 416 µm"),
            "{e}"
        );
        assert!(
            e.contains("is larger than the scan `surface` (4 × 4 points = 80 × 80 µm)"),
            "{e}"
        );
        let mixed = [observed(1, 0.5, 100, 4e-6), observed(2, 0.6, 100, 5e-6)];
        let e = check_view_within_scan(&surface, &mixed)
            .unwrap_err()
            .to_string();
        assert!(e.contains("different cameras or runs"), "{e}");
    }

    #[test]
    fn observed_maps_of_another_run_are_refused() {
        let contact = ContactTable {
            frame: vec![0, 1, 2],
            time_s: vec![0.0, 1.0, 2.0],
            force_n: vec![0.0, 1.0, 2.0],
            area_fraction: vec![0.0, 0.1, 0.5],
            contact_area_m2: vec![0.0; 3],
            patches: vec![0; 3],
            threshold: vec![0.0; 3],
            method: vec!["otsu".into(); 3],
        };
        assert!(check_observed_in_table(&[observed(2, 0.5, 4, 1e-6)], &contact).is_ok());
        // The true map's A/A0 may differ from the measured by the method's bias.
        assert!(check_observed_in_table(&[observed(2, 0.6, 4, 1e-6)], &contact).is_ok());
        let e = check_observed_in_table(&[observed(1, 0.5, 4, 1e-6)], &contact)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "input `observed_maps`: the map of frame 1 has A/A0 = 0.5000, but `contact` gives \
             0.1000 for that frame: the maps and the table come from different runs"
        );
        let e = check_observed_in_table(&[observed(7, 0.5, 4, 1e-6)], &contact)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("frame 7 is not in `contact` (its 3 frames)"),
            "{e}"
        );
    }

    fn transform(angle_deg: f64, scale: f64, zncc: f64) -> TransformTable {
        TransformTable {
            against: vec!["bem".into()],
            frame: vec![4],
            angle_deg: vec![angle_deg],
            scale: vec![scale],
            zncc: vec![zncc],
            ..TransformTable::default()
        }
    }

    fn agreement(rms: &[f64]) -> AgreementTable {
        AgreementTable {
            model: (0..rms.len()).map(|k| format!("m{k}")).collect(),
            rms_log_ratio: rms.to_vec(),
            by_construction: vec![0; rms.len()],
            ..AgreementTable::default()
        }
    }

    #[test]
    fn a_fit_on_its_bounds_a_low_zncc_and_far_scores_are_noted() {
        let p = params(serde_json::json!({}));
        // The paper pipeline's T1: turn 2.499°, scale 1.0000, ZNCC 0.775, best 0.083.
        assert_eq!(
            quality_notes(&p, &transform(2.499, 1.0, 0.775), &agreement(&[0.3, 0.083])),
            Vec::<String>::new()
        );
        // Maps of another run: turn and scale on their bounds, ZNCC 0.32.
        let notes = quality_notes(&p, &transform(-9.9, 0.95, 0.32), &agreement(&[3.6, 4.0]));
        assert_eq!(notes.len(), 4, "{notes:?}");
        assert!(
            notes[0].starts_with("warning: the turn found on frame 4, -9.900°"),
            "{}",
            notes[0]
        );
        assert!(
            notes[1].starts_with("warning: the scale found on frame 4, 0.9500"),
            "{}",
            notes[1]
        );
        assert!(
            notes[2].contains("reaches ZNCC 0.320, below 0.5"),
            "{}",
            notes[2]
        );
        assert!(
            notes[3].starts_with("warning: even the best model, `m0`, scores rms log ratio 3.600"),
            "{}",
            notes[3]
        );
        // A search of every turn has no bound; a turn across ±180° wraps.
        let all = params(serde_json::json!({ "angle_deg": 175.0, "angle_range_deg": 10.0 }));
        let notes = quality_notes(&all, &transform(-175.1, 1.0, 0.8), &agreement(&[0.1]));
        assert_eq!(notes.len(), 1, "{notes:?}");
        let every = params(serde_json::json!({ "angle_range_deg": 180.0 }));
        assert!(quality_notes(&every, &transform(180.0, 1.0, 0.8), &agreement(&[0.1])).is_empty());
    }
}
