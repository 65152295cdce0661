//! The `contact-images` stage's analysis of an opened sequence (the paper's
//! Section 3 experiment): every frame segmented by the chosen method (with
//! the calibrated method's view of contact beside it when the clock offset
//! is estimated from first contact), the frames nearest each requested
//! A/A0 kept for the maps, the camera-to-force-log clock offset (given,
//! from the trigger, or from first contact) and the force at each frame's
//! mid-exposure.

use hypercontact_core::{Context, StageError};
use hypercontact_labfiles::sequence::{GrayFrame, Sequence};

use crate::calibrated::{Calibrated, Level, segment_calibrated};
use crate::listing::{check_given_offset, check_listing};
use crate::reference::{FrameName, judge_reference};
use crate::stage::{ContactImagesParams, ContactTable, Method, SyncTable};
use crate::sync::{contact_onset_s, force_onset_s, trigger_offset_s};
use crate::{Frame, ImageError, Mask, MultiOtsu, label, multi_otsu, otsu};

/// The stage's tables, and per requested A/A0 the nearest frame's mask.
pub(crate) struct Analysis {
    pub contact: ContactTable,
    pub sync: SyncTable,
    pub maps: Vec<Option<(usize, Mask)>>,
}

/// Segments every frame, finds the clock offset and reads the force.
pub(crate) fn analyse(
    sequence: &Sequence,
    p: &ContactImagesParams,
    ctx: &Context,
) -> Result<Analysis, StageError> {
    let n = sequence.frames.len();
    check_listing(&sequence.frames).map_err(|e| listing_error(sequence, e))?;
    // The reference frame: the calibrated method's flat field, and what
    // the first contact is found against when the clock offset is
    // estimated (a global threshold finds "contact" in every frame).
    let estimate_offset = p.clock_offset_s.is_none() && sequence.trigger.is_none();
    let reference = match (p.method, estimate_offset) {
        (Method::Calibrated, _) | (_, true) => {
            if p.reference_frame >= n {
                return Err(StageError::invalid(format!(
                    "parameter `reference_frame` = {}: the sequence has {n} frames",
                    p.reference_frame
                )));
            }
            Some(read_frame(sequence, p.reference_frame, p.bits)?)
        }
        _ => None,
    };
    let frames = segment_frames(sequence, p, reference.as_ref(), estimate_offset, ctx)?;
    if reference.is_some() {
        check_reference(sequence, p.reference_frame, &frames.rows, ctx)?;
    }
    let times_s: Vec<f64> = (0..n)
        .map(|k| sequence.frames[k].time_s + 0.5 * p.exposure_s)
        .collect();
    let sync = sync_table(sequence, p, &times_s, &frames.onset_fractions)?;
    let offset = sync.clock_offset_s[0];
    let force_n = (0..n)
        .map(|k| sequence.force_at(times_s[k] + offset, &sequence.frames[k]))
        .collect::<Result<Vec<f64>, StageError>>()?;
    let fractions: Vec<f64> = frames.rows.iter().map(|r| r.fraction).collect();
    let pixel_m2 = p.pixel_m * p.pixel_m;
    let contact = ContactTable {
        frame: sequence.frames.iter().map(|f| f.frame).collect(),
        time_s: times_s,
        force_n,
        area_fraction: fractions.clone(),
        contact_area_m2: frames
            .rows
            .iter()
            .map(|r| r.contact_pixels as f64 * pixel_m2)
            .collect(),
        patches: frames.rows.iter().map(|r| r.patches as i64).collect(),
        threshold: frames.rows.iter().map(|r| r.threshold).collect(),
        method: vec![p.method.label().to_owned(); n],
    };
    ctx.note(&format!(
        "{n} frames, A/A0 up to {:.4}, clock offset {offset:.4} s ({})",
        fractions.iter().copied().fold(0.0, f64::max),
        sync.source[0]
    ));
    Ok(Analysis {
        contact,
        sync,
        maps: frames.maps,
    })
}

/// One frame's numbers in the `contact` table.
struct Row {
    fraction: f64,
    patches: usize,
    threshold: f64,
    contact_pixels: usize,
    /// Mean count above dark_level, to judge the reference frame.
    mean_signal: f64,
}

/// Refuses a reference frame in contact and warns of a dim one
/// ([`judge_reference`]).
fn check_reference(
    sequence: &Sequence,
    k: usize,
    rows: &[Row],
    ctx: &Context,
) -> Result<(), StageError> {
    let names: Vec<FrameName> = sequence
        .frames
        .iter()
        .map(|f| FrameName {
            frame: f.frame,
            file: &f.file,
        })
        .collect();
    let mean_signal: Vec<f64> = rows.iter().map(|r| r.mean_signal).collect();
    match judge_reference(k, &names, &mean_signal) {
        Ok(Some(warning)) => ctx.note(&warning),
        Ok(None) => {}
        Err(refusal) => return Err(StageError::invalid(refusal)),
    }
    Ok(())
}

/// The mean count above `dark_level` (summed in integers: exact, in any order).
fn mean_signal(image: &Frame, dark_level: f64) -> f64 {
    let sum: u64 = image.data().iter().map(|&v| u64::from(v)).sum();
    sum as f64 / image.data().len() as f64 - dark_level
}

/// What the pass over the frames found.
struct Frames {
    rows: Vec<Row>,
    /// A/A0 as the calibrated method sees it, for the clock offset.
    onset_fractions: Vec<f64>,
    /// Per requested A/A0, the nearest frame so far and its mask.
    maps: Vec<Option<(usize, Mask)>>,
}

/// Segments every frame in time order.
fn segment_frames(
    sequence: &Sequence,
    p: &ContactImagesParams,
    reference: Option<&Frame>,
    estimate_offset: bool,
    ctx: &Context,
) -> Result<Frames, StageError> {
    let n = sequence.frames.len();
    let method_reference = reference.filter(|_| p.method == Method::Calibrated);
    let calibrated = Calibrated {
        dark_level: p.dark_level,
        contact_level: Level::Given(p.contact_level),
        background_level: Level::Given(p.background_level),
        fraction: p.fraction,
        seed_fraction: p.seed_fraction,
        min_patch_pixels: p.min_patch_pixels,
        ..Calibrated::default()
    };
    let progress = ctx.progress(n as u64, "frames");
    let mut frames = Frames {
        rows: Vec::with_capacity(n),
        onset_fractions: Vec::with_capacity(n),
        maps: p.map_fractions.iter().map(|_| None).collect(),
    };
    for k in 0..n {
        let image = read_frame(sequence, k, p.bits)?;
        let at = |e: ImageError| {
            StageError::file(sequence.display(&sequence.frames[k].file), e.to_string())
        };
        let s = segment(&image, method_reference, p.method, &calibrated).map_err(at)?;
        let fraction = s.mask.area_fraction();
        // Contact as the calibrated method sees it, for the clock offset.
        let onset_fraction = match (reference, p.method, estimate_offset) {
            (Some(r), method, true) if method != Method::Calibrated => {
                segment_calibrated(&image, r, &calibrated)
                    .map_err(at)?
                    .mask
                    .area_fraction()
            }
            _ => fraction,
        };
        for (slot, &want) in frames.maps.iter_mut().zip(&p.map_fractions) {
            let nearer = slot.as_ref().is_none_or(|(j, _)| {
                (fraction - want).abs() < (frames.rows[*j].fraction - want).abs()
            });
            if nearer {
                *slot = Some((k, s.mask.clone()));
            }
        }
        frames.rows.push(Row {
            fraction,
            patches: s.patches,
            threshold: s.threshold,
            contact_pixels: s.mask.count(),
            mean_signal: mean_signal(&image, p.dark_level),
        });
        frames.onset_fractions.push(onset_fraction);
        progress.inc(1);
    }
    Ok(frames)
}

/// A listing error, placed in frames.csv when the frames came from it.
fn listing_error(sequence: &Sequence, message: String) -> StageError {
    if sequence.frames.iter().any(|f| f.listed.is_some()) {
        StageError::file(sequence.display("frames.csv"), message)
    } else {
        StageError::invalid(message)
    }
}

/// Frame `k` decoded as the camera's frame (errors name its file).
fn read_frame(sequence: &Sequence, k: usize, bits: Option<u8>) -> Result<Frame, StageError> {
    let raw = sequence.frame(k)?;
    camera_frame(raw, bits)
        .map_err(|e| StageError::file(sequence.display(&sequence.frames[k].file), e.to_string()))
}

/// The `sync` table: the clock offset as given, from the trigger column of
/// force.csv, or from first contact (force onset minus contact onset).
fn sync_table(
    sequence: &Sequence,
    p: &ContactImagesParams,
    times_s: &[f64],
    onset_fractions: &[f64],
) -> Result<SyncTable, StageError> {
    let sync =
        |offset: f64, estimated: i64, source: &str, (force, contact): (f64, f64)| SyncTable {
            clock_offset_s: vec![offset],
            estimated: vec![estimated],
            source: vec![source.into()],
            force_onset_s: vec![force],
            contact_onset_s: vec![contact],
        };
    let force_csv_error = |e: String| StageError::file(sequence.display("force.csv"), e);
    match (p.clock_offset_s, &sequence.trigger) {
        (Some(offset), _) => {
            if let (Some(first), Some(last)) = (sequence.force.first(), sequence.force.last()) {
                check_given_offset(offset, &sequence.frames, times_s, (first.0, last.0))
                    .map_err(force_csv_error)?;
            }
            Ok(sync(offset, 0, "given", (f64::NAN, f64::NAN)))
        }
        (None, Some(trigger)) => {
            let log_s: Vec<f64> = sequence.force.iter().map(|(t, _)| *t).collect();
            let offset = trigger_offset_s(&log_s, trigger, times_s)
                .map_err(|e| force_csv_error(e.to_string()))?;
            Ok(sync(offset, 1, "trigger", (f64::NAN, f64::NAN)))
        }
        (None, None) => {
            let force = force_onset_s(&sequence.force, p.force_resolution_n)
                .map_err(|e| force_csv_error(e.to_string()))?;
            let contact = contact_onset_s(times_s, onset_fractions);
            let (Some(force), Some(contact)) = (force, contact) else {
                return Err(StageError::invalid(format!(
                    "cannot estimate the clock offset: {}; give `clock_offset_s`",
                    match (force, contact) {
                        (None, _) => "the force never leaves its baseline".to_owned(),
                        _ => "no frame without contact precedes the first with contact".to_owned(),
                    }
                )));
            };
            Ok(sync(force - contact, 1, "first-contact", (force, contact)))
        }
    }
}

/// A decoded file as the camera's frame: its container depth, or `bits`.
fn camera_frame(raw: GrayFrame, bits: Option<u8>) -> Result<Frame, ImageError> {
    let bits = bits.unwrap_or(raw.bits).min(raw.bits);
    Frame::new(raw.width, raw.height, bits, raw.data)
}

/// One frame's segmentation.
struct Segmented {
    mask: Mask,
    patches: usize,
    threshold: f64,
}

fn segment(
    image: &Frame,
    reference: Option<&Frame>,
    method: Method,
    calibrated: &Calibrated,
) -> Result<Segmented, ImageError> {
    match (method, reference) {
        (Method::Calibrated, Some(reference)) => {
            let s = segment_calibrated(image, reference, calibrated)?;
            Ok(Segmented {
                patches: s.patches.count(),
                threshold: s.join_threshold,
                mask: s.mask,
            })
        }
        (Method::Otsu, _) => match otsu(&image.histogram()) {
            Ok(t) => Ok(labelled(
                image.dark_mask(t.threshold),
                f64::from(t.threshold),
            )),
            // One level everywhere: nothing to separate, no contact.
            Err(ImageError::SingleLevel { .. }) => empty(image),
            Err(e) => Err(e),
        },
        (Method::MultiOtsu, _) | (Method::Calibrated, None) => {
            match multi_otsu(&image.histogram(), &MultiOtsu::default()) {
                Ok(t) => {
                    let threshold = t.contact_threshold();
                    Ok(labelled(image.dark_mask(threshold), f64::from(threshold)))
                }
                Err(ImageError::SingleLevel { .. } | ImageError::TooFewLevels { .. }) => {
                    empty(image)
                }
                Err(e) => Err(e),
            }
        }
    }
}

fn labelled(mask: Mask, threshold: f64) -> Segmented {
    Segmented {
        patches: label(&mask).count(),
        mask,
        threshold,
    }
}

/// No contact: a frame of one level (or too few for three classes).
fn empty(image: &Frame) -> Result<Segmented, ImageError> {
    let mask = Mask::new(
        image.width(),
        image.height(),
        vec![false; image.data().len()],
    )?;
    Ok(Segmented {
        mask,
        patches: 0,
        threshold: f64::NAN,
    })
}
