//! Overlap of a predicted and an observed binary contact map on the same
//! pixels: the confusion counts and the scores made from them (Dice =
//! F1 = 2TP / (2TP + FP + FN), IoU = TP / (TP + FP + FN), precision =
//! TP / (TP + FP), recall = TP / (TP + FN)), the usual definitions of
//! segmentation comparison.

use crate::error::CompareError;

/// Confusion counts and scores; a score whose denominator is 0 is NaN
/// (except Dice and IoU of two empty maps: they agree, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    pub true_positive: u64,
    pub false_positive: u64,
    pub false_negative: u64,
    pub true_negative: u64,
    pub dice: f64,
    pub iou: f64,
    pub precision: f64,
    pub recall: f64,
}

/// A pixel's class in an overlay: how a predicted and an observed map
/// agree there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agreement {
    /// contact in both
    TruePositive,
    /// predicted, not observed
    FalsePositive,
    /// observed, not predicted
    FalseNegative,
    /// contact in neither
    TrueNegative,
    /// no prediction there (outside the scanned map)
    Unknown,
}

/// Classifies one pixel: `predicted` None where the model has no value.
pub fn classify(predicted: Option<bool>, observed: bool) -> Agreement {
    match (predicted, observed) {
        (None, _) => Agreement::Unknown,
        (Some(true), true) => Agreement::TruePositive,
        (Some(true), false) => Agreement::FalsePositive,
        (Some(false), true) => Agreement::FalseNegative,
        (Some(false), false) => Agreement::TrueNegative,
    }
}

/// The overlap of `predicted` and `observed` (same length, one entry per
/// pixel); pixels where `predicted` is None are not counted.
pub fn overlap(predicted: &[Option<bool>], observed: &[bool]) -> Result<Overlap, CompareError> {
    if predicted.len() != observed.len() {
        return Err(CompareError::Length {
            what: "the predicted map (one entry per observed pixel)",
            expected: observed.len(),
            got: predicted.len(),
        });
    }
    let mut counts = [0u64; 4];
    for (&p, &o) in predicted.iter().zip(observed) {
        match classify(p, o) {
            Agreement::TruePositive => counts[0] += 1,
            Agreement::FalsePositive => counts[1] += 1,
            Agreement::FalseNegative => counts[2] += 1,
            Agreement::TrueNegative => counts[3] += 1,
            Agreement::Unknown => {}
        }
    }
    let [tp, fp, fn_, tn] = counts;
    if tp + fp + fn_ + tn == 0 {
        return Err(CompareError::NoOverlap {
            message: "the prediction covers none of the observed pixels".into(),
        });
    }
    let ratio = |num: u64, den: u64| {
        if den == 0 {
            f64::NAN
        } else {
            num as f64 / den as f64
        }
    };
    let either = tp + fp + fn_;
    Ok(Overlap {
        true_positive: tp,
        false_positive: fp,
        false_negative: fn_,
        true_negative: tn,
        dice: if either == 0 {
            1.0
        } else {
            ratio(2 * tp, 2 * tp + fp + fn_)
        },
        iou: if either == 0 { 1.0 } else { ratio(tp, either) },
        precision: ratio(tp, tp + fp),
        recall: ratio(tp, tp + fn_),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_maps_score_one_and_scores_follow_their_definitions() {
        let observed = [true, true, false, false, true, false];
        let same: Vec<Option<bool>> = observed.iter().map(|&o| Some(o)).collect();
        let o = overlap(&same, &observed).unwrap();
        assert_eq!((o.dice, o.iou, o.precision, o.recall), (1.0, 1.0, 1.0, 1.0));
        // Hand-counted: TP 2 (0, 4), FP 1 (3), FN 1 (1), TN 1 (2), one
        // pixel unknown (5).
        let predicted = [
            Some(true),
            Some(false),
            Some(false),
            Some(true),
            Some(true),
            None,
        ];
        let o = overlap(&predicted, &observed).unwrap();
        assert_eq!(
            (
                o.true_positive,
                o.false_positive,
                o.false_negative,
                o.true_negative
            ),
            (2, 1, 1, 1)
        );
        assert_eq!(o.dice, 4.0 / 6.0);
        assert_eq!(o.iou, 0.5);
        assert_eq!((o.precision, o.recall), (2.0 / 3.0, 2.0 / 3.0));
        // Dice = 2 IoU / (1 + IoU) always.
        assert!((o.dice - 2.0 * o.iou / (1.0 + o.iou)).abs() < 1e-15);
    }

    #[test]
    fn empty_and_mismatched_maps() {
        let none = overlap(&[Some(false), Some(false)], &[false, false]).unwrap();
        assert_eq!((none.dice, none.iou), (1.0, 1.0));
        assert!(none.precision.is_nan() && none.recall.is_nan());
        assert!(overlap(&[Some(true)], &[true, false]).is_err());
        assert!(overlap(&[None, None], &[true, false]).is_err());
    }
}
