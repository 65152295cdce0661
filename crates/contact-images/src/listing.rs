//! What the stage checks of a sequence before it reads a frame: each frame
//! number and each image file listed once (a frame listed twice, or one
//! file at two times, would be counted twice in the load–area curve), and
//! a given `clock_offset_s` that puts every frame inside the force log
//! (outside it the force is not measured, only extrapolated).

use std::collections::BTreeMap;

use hypercontact_labfiles::sequence::FrameEntry;

/// Where a frame was listed, for messages: `frames.csv line 4`, or its file
/// name when it was found by its name.
fn place(entry: &FrameEntry) -> String {
    match &entry.listed {
        Some(line) => format!("frames.csv {line}"),
        None => format!("file {}", entry.file),
    }
}

/// Refuses a frame number listed twice and a file listed twice (at two
/// times, or at one), naming both places.
pub(crate) fn check_listing(frames: &[FrameEntry]) -> Result<(), String> {
    let mut by_frame: BTreeMap<i64, &FrameEntry> = BTreeMap::new();
    let mut by_file: BTreeMap<&str, &FrameEntry> = BTreeMap::new();
    for entry in frames {
        if let Some(first) = by_frame.insert(entry.frame, entry) {
            return Err(format!(
                "frame {} is listed twice ({}: {} at {} s; {}: {} at {} s): \
                 each frame must appear once",
                entry.frame,
                place(first),
                first.file,
                first.time_s,
                place(entry),
                entry.file,
                entry.time_s
            ));
        }
        if let Some(first) = by_file.insert(&entry.file, entry) {
            return Err(format!(
                "file {} is listed for two frames ({}: frame {} at {} s; {}: frame {} at {} s): \
                 one image is one exposure, taken once",
                entry.file,
                place(first),
                first.frame,
                first.time_s,
                place(entry),
                entry.frame,
                entry.time_s
            ));
        }
    }
    Ok(())
}

/// The offsets that put every frame's mid-exposure (`mid_exposure_s`, camera
/// clock) inside the force log `log_s = (first, last)`:
/// `[first − earliest frame, last − latest frame]`; `None` for no frames.
pub(crate) fn offsets_within_log(mid_exposure_s: &[f64], log_s: (f64, f64)) -> Option<(f64, f64)> {
    let earliest = mid_exposure_s.iter().copied().reduce(f64::min)?;
    let latest = mid_exposure_s.iter().copied().reduce(f64::max)?;
    Some((log_s.0 - earliest, log_s.1 - latest))
}

/// Refuses a given clock offset that puts a frame outside the force log,
/// naming `clock_offset_s`, its value, the frame it moves out and the
/// bounds the offset must keep.
pub(crate) fn check_given_offset(
    offset_s: f64,
    frames: &[FrameEntry],
    mid_exposure_s: &[f64],
    log_s: (f64, f64),
) -> Result<(), String> {
    let Some((low_s, high_s)) = offsets_within_log(mid_exposure_s, log_s) else {
        return Ok(());
    };
    // The log reader's own slack, so an offset it accepts is accepted here.
    let slack_s = 1e-9 * (1.0 + log_s.1.abs());
    if offset_s >= low_s - slack_s && offset_s <= high_s + slack_s {
        return Ok(());
    }
    let (k, bound) = if offset_s < low_s {
        let k = argmin(mid_exposure_s);
        (k, format!("below its lower bound {low_s} s"))
    } else {
        let k = argmax(mid_exposure_s);
        (k, format!("above its upper bound {high_s} s"))
    };
    let range = if low_s <= high_s {
        format!("the offset must lie between {low_s} and {high_s} s")
    } else {
        format!(
            "no offset fits: the frames span {} s, the log only {} s",
            mid_exposure_s[argmax(mid_exposure_s)] - mid_exposure_s[argmin(mid_exposure_s)],
            log_s.1 - log_s.0
        )
    };
    Err(format!(
        "parameter `clock_offset_s` = {offset_s} s is {bound}: it puts frame {} ({}) at {} s \
         on the force log's clock, but force.csv covers {} … {} s; {range}",
        frames[k].frame,
        frames[k].file,
        mid_exposure_s[k] + offset_s,
        log_s.0,
        log_s.1
    ))
}

fn argmin(values: &[f64]) -> usize {
    (0..values.len())
        .reduce(|a, b| if values[b] < values[a] { b } else { a })
        .unwrap_or(0)
}

fn argmax(values: &[f64]) -> usize {
    (0..values.len())
        .reduce(|a, b| if values[b] > values[a] { b } else { a })
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::RowPlace;

    fn entry(frame: i64, time_s: f64, file: &str, line: u64) -> FrameEntry {
        FrameEntry {
            frame,
            time_s,
            file: file.to_owned(),
            listed: Some(RowPlace::Line(line)),
        }
    }

    #[test]
    fn a_frame_or_a_file_listed_twice_is_refused_naming_both_lines() {
        let ok = [entry(0, 0.0, "a.png", 2), entry(1, 1.0, "b.png", 3)];
        assert_eq!(check_listing(&ok), Ok(()));
        // Before #31 both were analysed as two frames.
        let twice = [
            entry(0, 0.0, "a.png", 2),
            entry(1, 1.0, "b.png", 3),
            entry(1, 2.0, "c.png", 4),
        ];
        let e = check_listing(&twice).unwrap_err();
        assert!(
            e.starts_with(
                "frame 1 is listed twice (frames.csv line 3: b.png at 1 s; frames.csv line 4"
            ),
            "{e}"
        );
        let file_twice = [entry(0, 0.0, "a.png", 2), entry(1, 1.0, "a.png", 3)];
        let e = check_listing(&file_twice).unwrap_err();
        assert!(
            e.starts_with(
                "file a.png is listed for two frames (frames.csv line 2: frame 0 at 0 s; \
                 frames.csv line 3: frame 1 at 1 s)"
            ),
            "{e}"
        );
    }

    #[test]
    fn a_given_offset_must_keep_every_frame_inside_the_log() {
        let frames = [entry(0, 0.0, "a.png", 2), entry(1, 10.0, "b.png", 3)];
        let mid = [0.5, 10.5];
        // The log covers 2 … 30 s: the offset may be 1.5 … 19.5 s.
        assert_eq!(offsets_within_log(&mid, (2.0, 30.0)), Some((1.5, 19.5)));
        for fits in [1.5, 10.0, 19.5] {
            assert_eq!(check_given_offset(fits, &frames, &mid, (2.0, 30.0)), Ok(()));
        }
        let e = check_given_offset(1e9, &frames, &mid, (2.0, 30.0)).unwrap_err();
        assert_eq!(
            e,
            "parameter `clock_offset_s` = 1000000000 s is above its upper bound 19.5 s: it puts \
             frame 1 (b.png) at 1000000010.5 s on the force log's clock, but force.csv covers \
             2 … 30 s; the offset must lie between 1.5 and 19.5 s"
        );
        let e = check_given_offset(-1.0, &frames, &mid, (2.0, 30.0)).unwrap_err();
        assert!(
            e.contains("= -1 s is below its lower bound 1.5 s: it puts frame 0 (a.png) at -0.5 s"),
            "{e}"
        );
        // A log shorter than the sequence: no offset fits, and it says why.
        let e = check_given_offset(0.0, &frames, &mid, (0.0, 5.0)).unwrap_err();
        assert!(
            e.ends_with("no offset fits: the frames span 10 s, the log only 5 s"),
            "{e}"
        );
    }
}
