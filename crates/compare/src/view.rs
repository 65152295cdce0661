//! A model's A/A0 on the camera's view: the camera measures the contact
//! area of its view, a model gives it for the whole scan, and on a free
//! sample the two differ (its rim lifts off, so its centre carries more
//! contact). A model's maps, read inside the registered view, give pairs
//! (A/A0 of the whole scan, A/A0 in the view); between them the relation
//! is linear.

use hypercontact_core::{Field, StageError};
use hypercontact_interference::CameraGrid;

use crate::maps::{Truncation, predicted};
use crate::register::{Registration, sample_predicted};

/// The whole-scan A/A0 of profile theory's cuts the view relation is read
/// at: dense at small load, where the contact spots are few.
const TRUNCATION_LEVELS: [f64; 16] = [
    0.005, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99,
];

/// The share of the camera's pixels on the scan that `field` (1 =
/// contact) puts in contact under `registration`.
fn view_fraction(
    field: &Field,
    registration: &Registration,
    camera: &CameraGrid,
) -> Result<f64, StageError> {
    let sampled = sample_predicted(&predicted(field), registration, camera)
        .map_err(|e| StageError::invalid(format!("a model map on the camera: {e}")))?;
    let (inside, seen) = sampled
        .iter()
        .filter(|v| !v.is_nan())
        .fold((0usize, 0usize), |(i, n), v| {
            (i + usize::from(*v >= 0.5), n + 1)
        });
    if seen == 0 {
        return Err(StageError::invalid(
            "no camera pixel lands on the scan: no view area can be read",
        ));
    }
    Ok(inside as f64 / seen as f64)
}

/// (A/A0 of the whole scan, A/A0 in the view) of each of a model's maps,
/// with (0, 0) and (1, 1), sorted.
pub(crate) fn relation_of_maps(
    maps: &[(f64, Field)],
    registration: &Registration,
    camera: &CameraGrid,
) -> Result<Vec<(f64, f64)>, StageError> {
    let mut relation = vec![(0.0, 0.0), (1.0, 1.0)];
    for (whole, field) in maps {
        relation.push((*whole, view_fraction(field, registration, camera)?));
    }
    relation.sort_by(|a, b| a.0.total_cmp(&b.0));
    relation.dedup_by(|a, b| a.0 == b.0);
    Ok(relation)
}

/// Profile theory's relation: the height map cut at A/A0 = 0.005 … 0.99
/// and read in the view.
pub(crate) fn relation_of_truncation(
    truncation: &Truncation,
    registration: &Registration,
    camera: &CameraGrid,
) -> Result<Vec<(f64, f64)>, StageError> {
    let maps: Vec<(f64, Field)> = TRUNCATION_LEVELS
        .iter()
        .map(|&a| truncation.cut(a))
        .collect();
    relation_of_maps(&maps, registration, camera)
}

/// The view A/A0 at whole-scan A/A0 `a`, linear between the relation's
/// points.
pub(crate) fn on_relation(relation: &[(f64, f64)], a: f64) -> f64 {
    let i = relation.partition_point(|p| p.0 < a);
    if i == 0 {
        return relation[0].1;
    }
    if i >= relation.len() {
        return relation[relation.len() - 1].1;
    }
    let (x0, y0) = relation[i - 1];
    let (x1, y1) = relation[i];
    if x1 == x0 {
        y1
    } else {
        y0 + (y1 - y0) * (a - x0) / (x1 - x0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_relation_is_linear_between_its_points_and_flat_beyond() {
        let relation = [(0.0, 0.0), (0.5, 0.7), (1.0, 1.0)];
        assert_eq!(on_relation(&relation, 0.25), 0.35);
        assert!((on_relation(&relation, 0.75) - 0.85).abs() < 1e-15);
        assert_eq!(on_relation(&relation, 0.5), 0.7);
        assert_eq!(on_relation(&relation, -0.1), 0.0);
        assert_eq!(on_relation(&relation, 1.5), 1.0);
    }
}
