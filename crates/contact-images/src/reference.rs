//! Is the reference frame free of contact? The calibrated method measures
//! every frame against it, so a reference in contact is dark where the
//! contact is, and every later frame looks no darker there: A/A0 = 0
//! throughout, with no error from the segmentation itself.
//!
//! Judged by intensity, not by segmentation (a reference cannot be
//! segmented against itself): contact is (almost) black, so a frame's mean
//! signal above the dark level falls by about its contact fraction, and the
//! frame before contact is the brightest of the sequence. The reference's
//! mean signal is compared with the brightest frame's.

/// Below this share of the brightest frame's mean signal the reference has
/// lost half its light: it is in contact, and the run is refused.
pub(crate) const IN_CONTACT_BELOW: f64 = 0.5;

/// Below this share (a tenth of its light gone: some 10 % of the view in
/// contact, or the lamp dimmed) the run goes on with a warning. On the
/// synthetic experiment (`synthetic_experiment.rs`) the first frame, before
/// contact, is the brightest; the default reference is it.
pub(crate) const DARKER_BELOW: f64 = 0.9;

/// A frame for messages: its number and file.
pub(crate) struct FrameName<'a> {
    pub frame: i64,
    pub file: &'a str,
}

/// `Err` (a refusal) when reference `k` holds less than
/// [`IN_CONTACT_BELOW`] of the brightest frame's mean signal, `Ok(Some)`
/// (a warning) below [`DARKER_BELOW`], `Ok(None)` otherwise, and when no
/// frame has any signal (the calibrated method refuses that itself).
pub(crate) fn judge_reference(
    k: usize,
    names: &[FrameName],
    mean_signal: &[f64],
) -> Result<Option<String>, String> {
    let Some(brightest) = (0..mean_signal.len()).reduce(|a, b| {
        if mean_signal[b] > mean_signal[a] {
            b
        } else {
            a
        }
    }) else {
        return Ok(None);
    };
    let top = mean_signal[brightest];
    if top.is_nan() || top <= 0.0 || k >= mean_signal.len() {
        return Ok(None);
    }
    let share = mean_signal[k].max(0.0) / top;
    if share >= DARKER_BELOW {
        return Ok(None);
    }
    let said = format!(
        "parameter `reference_frame` = {k} (frame {}, {}) has {:.0} % of the mean signal of \
         the brightest frame (frame {}, {})",
        names[k].frame,
        names[k].file,
        100.0 * share,
        names[brightest].frame,
        names[brightest].file
    );
    if share < IN_CONTACT_BELOW {
        return Err(format!(
            "{said}: it is in contact, and every frame's contact is measured against it \
             (A/A0 would be 0 throughout); give the index of a frame before contact, e.g. \
             {brightest}"
        ));
    }
    Ok(Some(format!(
        "warning: {said}, less than {:.0} %: is it in contact or the light dimmed? Contact \
         present in it is not counted in any frame",
        100.0 * DARKER_BELOW
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<FrameName<'static>> {
        ["a.png", "b.png", "c.png"]
            .iter()
            .enumerate()
            .map(|(k, file)| FrameName {
                frame: 10 + k as i64,
                file,
            })
            .collect()
    }

    #[test]
    fn a_dark_reference_is_refused_a_dimmer_one_warned_a_bright_one_kept() {
        let names = names();
        // The brightest frame, and one within a tenth of it: no word.
        assert_eq!(judge_reference(0, &names, &[1000.0, 700.0, 50.0]), Ok(None));
        assert_eq!(judge_reference(1, &names, &[1000.0, 950.0, 50.0]), Ok(None));
        // 70 % of the light: a warning naming both frames and the share.
        let warned = judge_reference(1, &names, &[1000.0, 700.0, 50.0])
            .unwrap()
            .unwrap();
        assert!(
            warned.starts_with(
                "warning: parameter `reference_frame` = 1 (frame 11, b.png) has 70 % of the \
                 mean signal of the brightest frame (frame 10, a.png), less than 90 %"
            ),
            "{warned}"
        );
        // A frame in full contact (5 %): refused, pointing at frame 0.
        let refused = judge_reference(2, &names, &[1000.0, 700.0, 50.0]).unwrap_err();
        assert!(
            refused.contains("= 2 (frame 12, c.png) has 5 %"),
            "{refused}"
        );
        assert!(refused.ends_with("e.g. 0"), "{refused}");
        // No signal anywhere: left to the calibrated method's own error.
        assert_eq!(judge_reference(0, &names, &[0.0, 0.0, 0.0]), Ok(None));
    }
}
