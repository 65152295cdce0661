//! Camera and force sensor on their own clocks: the offset between them,
//! given or estimated from first contact (the force leaving its baseline
//! against the first frame that shows contact).
//!
//! Convention: a force-log time is the camera time plus the offset,
//! `t_force = t_camera + offset_s`.

use crate::ImageError;

/// Samples at the start of the log that set its baseline and noise.
const BASELINE_SAMPLES: usize = 16;

/// How far above its baseline noise the force must rise to count as
/// contact: this many standard deviations (robust, from the median absolute
/// deviation), and at least twice the log's resolution.
const ONSET_SIGMAS: f64 = 6.0;

/// When the force log leaves its baseline: the first sample above
/// baseline + max(6 σ, 2 × resolution) (σ the robust spread of the first
/// samples; the log must start before contact) is surely in contact; the
/// onset is the sample after the last one at or below the baseline before
/// it (a force that rises as a power of time crosses the detection level
/// well after it starts; at the baseline level it is within the noise of
/// its start). `None` when the force never leaves the baseline.
pub fn force_onset_s(force: &[(f64, f64)], resolution_n: f64) -> Result<Option<f64>, ImageError> {
    if force.len() < BASELINE_SAMPLES + 1 {
        return Err(ImageError::Parameter {
            name: "force",
            value: format!("{} samples", force.len()),
            expected: "a log of more than 16 samples, starting before contact",
        });
    }
    let mut first: Vec<f64> = force[..BASELINE_SAMPLES].iter().map(|s| s.1).collect();
    let baseline = median(&mut first);
    let mut deviations: Vec<f64> = first.iter().map(|f| (f - baseline).abs()).collect();
    // 1.4826 · MAD estimates σ of Gaussian noise.
    let sigma = 1.4826 * median(&mut deviations);
    let rise = (ONSET_SIGMAS * sigma).max(2.0 * resolution_n.max(0.0));
    let Some(detected) = force.iter().position(|(_, f)| *f > baseline + rise) else {
        return Ok(None);
    };
    let start = force[..detected]
        .iter()
        .rposition(|(_, f)| *f <= baseline)
        .map_or(0, |k| k + 1);
    Ok(Some(force[start].0))
}

/// Half-way between the last frame without contact and the first with
/// (`area_fraction > 0`): the touch lies between them, and with nothing
/// known of where, the middle is off by at most half a frame interval;
/// `None` if contact never starts within the sequence.
pub fn contact_onset_s(times_s: &[f64], area_fractions: &[f64]) -> Option<f64> {
    let k = area_fractions.iter().position(|&a| a > 0.0)?;
    (k > 0).then(|| 0.5 * (times_s[k - 1] + times_s[k]))
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn onset_is_where_the_force_leaves_its_noisy_baseline() {
        // Baseline 0.2 N with ±0.01 N of noise, contact at t = 3 s, then a
        // ramp of 1 N/s sampled at 50 Hz.
        let log: Vec<(f64, f64)> = (0..400)
            .map(|i| {
                let t = i as f64 / 50.0;
                let noise = 0.01 * ((i * 7919 % 13) as f64 / 6.0 - 1.0);
                (t, 0.2 + noise + (t - 3.0).max(0.0))
            })
            .collect();
        let onset = force_onset_s(&log, 0.01).unwrap().unwrap();
        assert!((3.0..3.06).contains(&onset), "{onset}");
        // A force rising as t^1.5 (one asperity) above a flat 0.01 N
        // quantised log: detected at 0.02 N, dated back to its start.
        let log: Vec<(f64, f64)> = (0..400)
            .map(|i| {
                let t = i as f64 / 50.0;
                let f = 0.05 * (t - 2.0).max(0.0).powf(1.5);
                (t, (f / 0.01).round() * 0.01)
            })
            .collect();
        let onset = force_onset_s(&log, 0.01).unwrap().unwrap();
        assert!((2.0..2.6).contains(&onset), "{onset}");
        let flat: Vec<(f64, f64)> = (0..40).map(|i| (i as f64, 1.0)).collect();
        assert_eq!(force_onset_s(&flat, 0.01).unwrap(), None);
        assert!(force_onset_s(&flat[..5], 0.01).is_err());
    }

    #[test]
    fn contact_onset_needs_a_frame_without_contact_first() {
        let t = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(contact_onset_s(&t, &[0.0, 0.0, 0.01, 0.1]), Some(1.5));
        assert_eq!(contact_onset_s(&t, &[0.01, 0.02, 0.03, 0.1]), None);
        assert_eq!(contact_onset_s(&t, &[0.0; 4]), None);
    }
}
