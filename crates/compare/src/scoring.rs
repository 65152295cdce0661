//! Every labelled `responses` curve scored against the measured load–area
//! curve ([`crate::agreement`]): its A/A0 taken as the model gives it
//! (`whole`) or converted to the camera's view ([`crate::view`]) through
//! its own maps, the maps `view_maps` names, or else the truncation.

use std::collections::BTreeMap;

use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::ResponseTable;
use hypercontact_core::{Inputs, Product, Schema, StageError};
use hypercontact_interference::CameraGrid;

use crate::agreement::{Agreement, Curve, LogCurve, Range, agreement};
use crate::maps::{Predictions, TRUNCATION};
use crate::register::Registration;
use crate::stage::{AgreementTable, AreaBasis, ContactCompareParams, LoadRatioTable};
use crate::view::{on_relation, relation_of_maps, relation_of_truncation};

/// Reads a response's A/A0 on the camera's view, with one view relation
/// per maps label computed once.
struct ViewAreas<'a> {
    predictions: &'a Predictions<'a>,
    registration: &'a Registration,
    camera: CameraGrid,
    relations: BTreeMap<String, Vec<(f64, f64)>>,
}

impl ViewAreas<'_> {
    /// The A/A0 of `response` (labelled `label`) as compared, and how it
    /// was read (`view (<maps>)`).
    fn of(
        &mut self,
        p: &ContactCompareParams,
        label: &str,
        response: &ResponseTable,
    ) -> Result<(Vec<f64>, String), StageError> {
        let maps_label = p.view_maps.get(label).cloned().unwrap_or_else(|| {
            if self.predictions.model(label).is_some() {
                label.to_owned()
            } else {
                TRUNCATION.to_owned()
            }
        });
        if !self.relations.contains_key(&maps_label) {
            let param = format!("view_maps.{label}");
            self.predictions.check_name(&param, &maps_label)?;
            let relation = match self.predictions.model(&maps_label) {
                Some(m) => relation_of_maps(&m.maps, self.registration, &self.camera),
                None => relation_of_truncation(
                    &self.predictions.truncation,
                    self.registration,
                    &self.camera,
                ),
            }?;
            self.relations.insert(maps_label.clone(), relation);
        }
        let relation = &self.relations[&maps_label];
        let area_fractions = response
            .area_fraction
            .iter()
            .map(|&a| on_relation(relation, a))
            .collect();
        Ok((area_fractions, format!("view ({maps_label})")))
    }
}

/// The agreement and load-ratio tables of every labelled response, the
/// responses of `same_physics` marked by construction, `physics` (the
/// experiment's) on every row.
pub(crate) fn score_responses(
    p: &ContactCompareParams,
    inputs: &Inputs,
    contact: &ContactTable,
    predictions: &Predictions,
    registration: &Registration,
    camera: CameraGrid,
    physics: &str,
) -> Result<(AgreementTable, LoadRatioTable), StageError> {
    let experiment = Curve {
        area_fraction: &contact.area_fraction,
        load_n: &contact.force_n,
    };
    let range = Range {
        min_area_fraction: p.min_area_fraction,
        max_area_fraction: p.max_area_fraction,
    };
    let mut view = ViewAreas {
        predictions,
        registration,
        camera,
        relations: BTreeMap::new(),
    };
    let mut scores = Vec::new();
    let mut bases = Vec::new();
    let mut ratios = LoadRatioTable::default();
    for (label, product) in inputs.labelled("responses") {
        let response = read_response(label, product)?;
        let (area_fractions, basis) = match p.area_basis {
            AreaBasis::Whole => (response.area_fraction.clone(), "whole".to_owned()),
            AreaBasis::View => view.of(p, label, &response)?,
        };
        let curve = LogCurve::new(
            Curve {
                area_fraction: &area_fractions,
                load_n: &response.load_n,
            },
            &format!("`responses.{label}`"),
        )
        .map_err(|e| StageError::invalid(e.to_string()))?;
        let a = agreement(&curve, experiment, range, &p.area_fractions)
            .map_err(|e| StageError::invalid(format!("`responses.{label}`: {e}")))?;
        bases.push(basis);
        let marked = i64::from(p.same_physics.iter().any(|m| m == label));
        for (&at, &ratio) in p.area_fractions.iter().zip(&a.ratio_at) {
            ratios.model.push(label.to_owned());
            ratios.area_fraction.push(at);
            ratios.load_ratio.push(ratio);
            ratios.by_construction.push(marked);
            ratios.experiment_physics.push(physics.to_owned());
        }
        scores.push((label.to_owned(), a));
    }
    let mut table = agreement_table(&scores, &p.same_physics, physics);
    table.area = bases;
    Ok((table, ratios))
}

fn read_response(label: &str, product: &Product) -> Result<ResponseTable, StageError> {
    let Product::Table(table) = product else {
        return Err(StageError::invalid(format!(
            "input `responses.{label}` is not a table"
        )));
    };
    ResponseTable::from_table(table)
        .map_err(|e| StageError::invalid(format!("input `responses.{label}`: {e}")))
}

/// Ranks by rms log ratio (1 = best; ties keep the label order) the
/// responses not in `same_physics`; those are marked by construction and
/// ranked 0 (not ranked).
pub(crate) fn agreement_table(
    scores: &[(String, Agreement)],
    same_physics: &[String],
    physics: &str,
) -> AgreementTable {
    let marked: Vec<bool> = scores
        .iter()
        .map(|(label, _)| same_physics.contains(label))
        .collect();
    let mut order: Vec<usize> = (0..scores.len()).filter(|&k| !marked[k]).collect();
    order.sort_by(|&i, &j| {
        scores[i]
            .1
            .rms_log_ratio
            .total_cmp(&scores[j].1.rms_log_ratio)
    });
    let mut rank = vec![0i64; scores.len()];
    for (r, &i) in order.iter().enumerate() {
        rank[i] = r as i64 + 1;
    }
    AgreementTable {
        model: scores.iter().map(|s| s.0.clone()).collect(),
        rms_log_ratio: scores.iter().map(|s| s.1.rms_log_ratio).collect(),
        mean_log_ratio: scores.iter().map(|s| s.1.mean_log_ratio).collect(),
        points: scores.iter().map(|s| s.1.points as i64).collect(),
        outside_model: scores.iter().map(|s| s.1.outside_model as i64).collect(),
        area: vec!["whole".to_owned(); scores.len()],
        rank,
        by_construction: marked.iter().map(|&m| i64::from(m)).collect(),
        experiment_physics: vec![physics.to_owned(); scores.len()],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scored(rms: f64) -> Agreement {
        Agreement {
            rms_log_ratio: rms,
            mean_log_ratio: rms,
            points: 10,
            outside_model: 0,
            ratio_at: Vec::new(),
        }
    }

    /// The experiment's own physics scores best but is not ranked; the
    /// others rank among themselves (#49).
    #[test]
    fn same_physics_rows_are_marked_and_left_out_of_the_ranking() {
        let scores = [
            ("icm".to_owned(), scored(0.4)),
            ("bem-linear".to_owned(), scored(0.02)),
            ("bem".to_owned(), scored(0.6)),
            ("gw".to_owned(), scored(0.3)),
        ];
        let physics = "bem, linear elastic, small-strain modulus, free boundary";
        let t = agreement_table(&scores, &["bem-linear".to_owned()], physics);
        assert_eq!(t.rank, [2, 0, 3, 1]);
        assert_eq!(t.by_construction, [0, 1, 0, 0]);
        assert_eq!(t.experiment_physics, [physics; 4]);
        // Nothing marked, no physics: the ranking of before, all judged.
        let t = agreement_table(&scores, &[], "");
        assert_eq!(t.rank, [3, 1, 4, 2]);
        assert_eq!(t.by_construction, [0; 4]);
        assert_eq!(t.experiment_physics, [""; 4]);
    }
}
