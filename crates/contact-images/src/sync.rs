//! Camera and force sensor on their own clocks: the offset between them,
//! given or estimated from first contact (the force leaving its baseline
//! against the first frame that shows contact).
//!
//! Convention: a force-log time is the camera time plus the offset,
//! `t_force = t_camera + offset_s`.

use hypercontact_core::robust::{median, median_and_sigma};

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
    let first: Vec<f64> = force[..BASELINE_SAMPLES].iter().map(|s| s.1).collect();
    // 1.4826 · MAD estimates σ of Gaussian noise.
    let (baseline, sigma) = median_and_sigma(&first);
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

/// The clock offset from the camera's exposure signal logged beside the
/// force (the rig's DAQ wired to the camera's trigger output): each run of
/// high samples is one exposure. Its start lies between the last low and
/// the first high sample, its end between the last high and the next low;
/// the middles of those two gaps bracket the exposure, whose centre on the
/// log's clock is their mean (good to about half a sample spacing). The
/// offset is the median over the exposures of that centre minus the
/// frame's mid-exposure camera time (`mid_exposure_s`, one per frame, in
/// order). Runs cut by the log's start or end are not counted; the number of
/// complete runs must equal the frames', and every exposure must agree with
/// the median within two sample spacings (a dropped frame shifts the pairing).
pub fn trigger_offset_s(
    log_times_s: &[f64],
    trigger: &[bool],
    mid_exposure_s: &[f64],
) -> Result<f64, ImageError> {
    if log_times_s.len() != trigger.len() || log_times_s.len() < 3 {
        return Err(ImageError::Parameter {
            name: "camera_trigger",
            value: format!("{} samples for {} times", trigger.len(), log_times_s.len()),
            expected: "one trigger sample per force sample, at least 3",
        });
    }
    let n = trigger.len();
    let mut centres = Vec::new();
    let mut k = 0;
    while k < n {
        if !trigger[k] {
            k += 1;
            continue;
        }
        let first = k;
        while k < n && trigger[k] {
            k += 1;
        }
        let last = k - 1;
        if first > 0 && k < n {
            let rise = 0.5 * (log_times_s[first - 1] + log_times_s[first]);
            let fall = 0.5 * (log_times_s[last] + log_times_s[last + 1]);
            centres.push(0.5 * (rise + fall));
        }
    }
    if centres.len() != mid_exposure_s.len() {
        return Err(ImageError::TriggerCount {
            exposures: centres.len(),
            frames: mid_exposure_s.len(),
        });
    }
    let offsets: Vec<f64> = centres
        .iter()
        .zip(mid_exposure_s)
        .map(|(log, camera)| log - camera)
        .collect();
    let offset_s = median(&offsets);
    let spacings: Vec<f64> = log_times_s.windows(2).map(|w| w[1] - w[0]).collect();
    let tolerance_s = 2.0 * median(&spacings);
    if let Some((index, deviation_s)) = offsets
        .iter()
        .map(|o| (o - offset_s).abs())
        .enumerate()
        .find(|(_, d)| *d > tolerance_s)
    {
        return Err(ImageError::TriggerMismatch {
            index,
            deviation_s,
            offset_s,
            tolerance_s,
        });
    }
    Ok(offset_s)
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

    /// Exposures of 50 ms every 0.7 s logged at 50 Hz on a clock 0.37 s
    /// ahead: the offset comes back within a quarter of a sample spacing;
    /// a log starting mid-exposure drops that run; a missing frame and a
    /// shuffled pairing are refused.
    #[test]
    fn the_trigger_gives_the_offset_to_a_fraction_of_a_sample() {
        let offset = 0.37;
        let starts: Vec<f64> = (0..12).map(|k| 0.3 + 0.7 * k as f64).collect();
        let mids: Vec<f64> = starts.iter().map(|s| s + 0.025).collect();
        let log: Vec<f64> = (0..500).map(|j| j as f64 / 50.0).collect();
        let trigger: Vec<bool> = log
            .iter()
            .map(|t| {
                let camera = t - offset;
                starts.iter().any(|s| (*s..s + 0.05).contains(&camera))
            })
            .collect();
        let found = trigger_offset_s(&log, &trigger, &mids).unwrap();
        assert!((found - offset).abs() < 0.005, "{found}");
        // The same log cut inside the first exposure: that run is dropped,
        // and so must the first frame be.
        let cut = log
            .iter()
            .position(|t| t - offset >= starts[0] + 0.01)
            .unwrap();
        assert!(trigger[cut]);
        let found = trigger_offset_s(&log[cut..], &trigger[cut..], &mids[1..]).unwrap();
        assert!((found - offset).abs() < 0.005, "{found}");
        let e = trigger_offset_s(&log[cut..], &trigger[cut..], &mids).unwrap_err();
        assert_eq!(
            e,
            ImageError::TriggerCount {
                exposures: 11,
                frames: 12
            }
        );
        // A frame dropped in the middle and a late one added: as many
        // exposures as frames, but the pairing is off.
        let mut shifted = mids.clone();
        shifted.remove(5);
        shifted.push(mids[11] + 0.7);
        let e = trigger_offset_s(&log, &trigger, &shifted).unwrap_err();
        assert!(matches!(e, ImageError::TriggerMismatch { .. }), "{e:?}");
        assert!(trigger_offset_s(&log[..2], &trigger[..2], &mids).is_err());
    }

    #[test]
    fn contact_onset_needs_a_frame_without_contact_first() {
        let t = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(contact_onset_s(&t, &[0.0, 0.0, 0.01, 0.1]), Some(1.5));
        assert_eq!(contact_onset_s(&t, &[0.01, 0.02, 0.03, 0.1]), None);
        assert_eq!(contact_onset_s(&t, &[0.0; 4]), None);
    }
}
