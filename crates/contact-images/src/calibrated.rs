//! The lab's robust segmentation: flat-field with a no-contact reference
//! frame, a threshold calibrated between the contact and background levels,
//! hysteresis and a minimum patch size.
//!
//! Why not a global threshold: vignetting makes the background darker at the
//! frame's edges, and under white light the second dark fringe (gap ≈ 270 nm)
//! is almost as dark as contact, so a global Otsu threshold counts fringes
//! and dim corners as contact (SPEC, "Interference images").
//!
//! Steps, on each pixel's dark-corrected intensity `I − dark_level`:
//! 1. **Flat-field:** `r = (I − dark)⁺ / (I_ref − dark)` against a no-contact
//!    reference frame; a pixel whose reference is below `min_reference`
//!    (dead, unlit, outside the sample) has no ratio and is never contact.
//! 2. **Levels:** contact level `c` (a low percentile of `r`, or given) and
//!    background level `b` (the median of `r`, or given), in units of the
//!    reference (so `b ≈ 1`). Percentiles interpolate linearly between order
//!    statistics (NumPy's default). The median is the background only while
//!    contact covers less than half the usable pixels; past that, give it
//!    (1.0 when reference and frame share the illumination).
//! 3. **Hysteresis** (Canny 1986): pixels with `r <= c + seed_fraction (b − c)`
//!    seed contact; 8-connected pixels with `r <= c + fraction (b − c)` join
//!    the patch of a seed; patches without a seed are dropped. Inclusive, like
//!    every threshold of this crate.
//! 4. **Minimum patch size:** patches of fewer than `min_patch_pixels` pixels
//!    are dropped.

use crate::percentile::percentiles;
use crate::{Frame, ImageError, Labels, Mask, label};

/// How a reference-normalised level is found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Level {
    /// The `p`-th percentile (0..=100) of the usable pixels' ratios.
    Percentile(f64),
    /// A ratio given directly (for instance measured on another frame).
    Given(f64),
}

/// Parameters of the calibrated segmentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibrated {
    /// Camera dark offset subtracted from frame and reference, in counts (≥ 0).
    pub dark_level: f64,
    /// A reference pixel must exceed `dark_level` by this many counts (> 0)
    /// to be used; guards the ratio against zeros.
    pub min_reference: f64,
    /// Contact level; default the 1st percentile, which lies in contact when
    /// contact covers more than 1 % of the frame (near first contact, give it).
    pub contact_level: Level,
    /// Background level; default the median.
    pub background_level: Level,
    /// Join (high) threshold as a fraction of the way from contact to
    /// background, in (0, 1); default 0.5.
    pub fraction: f64,
    /// Seed (low) threshold, same units, in (0, `fraction`]; default 0.25.
    /// Equal to `fraction`, hysteresis is off.
    pub seed_fraction: f64,
    /// Smallest patch kept, in pixels (≥ 1); default 4 (a 2 × 2 block, 13 µm
    /// across at the rig's 6.5 µm pixels).
    pub min_patch_pixels: u64,
}

impl Default for Calibrated {
    fn default() -> Self {
        Self {
            dark_level: 0.0,
            min_reference: 1.0,
            contact_level: Level::Percentile(1.0),
            background_level: Level::Percentile(50.0),
            fraction: 0.5,
            seed_fraction: 0.25,
            min_patch_pixels: 4,
        }
    }
}

fn parameter(name: &'static str, value: impl ToString, expected: &'static str) -> ImageError {
    ImageError::Parameter {
        name,
        value: value.to_string(),
        expected,
    }
}

fn check_level(name: &'static str, level: Level) -> Result<(), ImageError> {
    match level {
        Level::Percentile(p) if !(0.0..=100.0).contains(&p) => {
            Err(parameter(name, p, "a percentile must be within 0 to 100"))
        }
        Level::Given(v) if !v.is_finite() => {
            Err(parameter(name, v, "a given level must be a finite ratio"))
        }
        _ => Ok(()),
    }
}

impl Calibrated {
    /// Refuses non-finite or out-of-range parameters.
    pub fn check(&self) -> Result<(), ImageError> {
        if !(self.dark_level.is_finite() && self.dark_level >= 0.0) {
            return Err(parameter(
                "dark_level",
                self.dark_level,
                "must be a finite count ≥ 0",
            ));
        }
        if !(self.min_reference.is_finite() && self.min_reference > 0.0) {
            return Err(parameter(
                "min_reference",
                self.min_reference,
                "must be a finite count > 0",
            ));
        }
        check_level("contact_level", self.contact_level)?;
        check_level("background_level", self.background_level)?;
        if !(self.fraction > 0.0 && self.fraction < 1.0) {
            return Err(parameter(
                "fraction",
                self.fraction,
                "must be strictly between 0 and 1",
            ));
        }
        if !(self.seed_fraction > 0.0 && self.seed_fraction <= self.fraction) {
            return Err(parameter(
                "seed_fraction",
                self.seed_fraction,
                "must be above 0 and at most `fraction`",
            ));
        }
        if self.min_patch_pixels == 0 {
            return Err(parameter("min_patch_pixels", 0, "must be at least 1 pixel"));
        }
        Ok(())
    }
}

/// A calibrated segmentation and the levels it used (reference-normalised).
#[derive(Debug, Clone, PartialEq)]
pub struct CalibratedSegmentation {
    /// Contact pixels.
    pub mask: Mask,
    /// The kept patches (8-connected, first-pixel order); their union is `mask`.
    pub patches: Labels,
    pub contact_level: f64,
    pub background_level: f64,
    /// Ratio at or below which a pixel seeds contact.
    pub seed_threshold: f64,
    /// Ratio at or below which a pixel joins a seeded patch.
    pub join_threshold: f64,
}

/// Segments `frame` against the no-contact `reference` (same size and bit depth).
pub fn segment_calibrated(
    frame: &Frame,
    reference: &Frame,
    params: &Calibrated,
) -> Result<CalibratedSegmentation, ImageError> {
    params.check()?;
    if (frame.width(), frame.height()) != (reference.width(), reference.height()) {
        return Err(ImageError::ReferenceSize {
            frame_width: frame.width(),
            frame_height: frame.height(),
            reference_width: reference.width(),
            reference_height: reference.height(),
        });
    }
    if frame.bits() != reference.bits() {
        return Err(ImageError::ReferenceBits {
            frame_bits: frame.bits(),
            reference_bits: reference.bits(),
        });
    }

    // Flat-field; unusable pixels get +∞, above every threshold.
    let dark = params.dark_level as f32;
    let floor = params.dark_level + params.min_reference;
    let ratio: Vec<f32> = frame
        .data()
        .iter()
        .zip(reference.data())
        .map(|(&i, &i_ref)| {
            if f64::from(i_ref) < floor {
                f32::INFINITY
            } else {
                (f32::from(i) - dark).max(0.0) / (f32::from(i_ref) - dark)
            }
        })
        .collect();

    if !ratio.iter().any(|r| r.is_finite()) {
        return Err(ImageError::NoUsableReference { floor });
    }
    let wanted: Vec<f64> = [params.contact_level, params.background_level]
        .iter()
        .filter_map(|level| match level {
            Level::Percentile(p) => Some(*p),
            Level::Given(_) => None,
        })
        .collect();
    let mut found = if wanted.is_empty() {
        Vec::new()
    } else {
        percentiles(&ratio, &wanted).unwrap_or_default()
    }
    .into_iter();
    let mut level = |level: Level| match level {
        Level::Given(v) => v,
        Level::Percentile(_) => found.next().unwrap_or(f64::NAN),
    };
    let contact_level = level(params.contact_level);
    let background_level = level(params.background_level);
    // Also refuses a NaN level.
    if contact_level.partial_cmp(&background_level) != Some(std::cmp::Ordering::Less) {
        return Err(ImageError::NoContrast {
            contact: contact_level,
            background: background_level,
        });
    }
    let span = background_level - contact_level;
    let seed_threshold = contact_level + params.seed_fraction * span;
    let join_threshold = contact_level + params.fraction * span;

    let candidates = Mask::from_checked(
        frame.width(),
        frame.height(),
        ratio
            .iter()
            .map(|&r| f64::from(r) <= join_threshold)
            .collect(),
    );
    let mut patches = label(&candidates);
    let mut seeded = vec![false; patches.count()];
    for (&l, &r) in patches.labels().iter().zip(&ratio) {
        if l != 0 && f64::from(r) <= seed_threshold {
            seeded[l as usize - 1] = true;
        }
    }
    let sizes = patches.sizes().to_vec();
    patches.retain(|k| seeded[k] && sizes[k] >= params.min_patch_pixels);
    Ok(CalibratedSegmentation {
        mask: patches.mask(),
        patches,
        contact_level,
        background_level,
        seed_threshold,
        join_threshold,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    /// Frame and reference from a ratio map: `reference = 1000`, `frame =
    /// 1000 · ratio`, 8-bit-free 16-bit values.
    fn from_ratios(rows: &[&[f64]]) -> (Frame, Frame) {
        let (w, h) = (rows[0].len(), rows.len());
        let data = rows
            .iter()
            .flat_map(|row| row.iter().map(|&r| (1000.0 * r).round() as u16))
            .collect();
        (
            Frame::new(w, h, 16, data).unwrap(),
            Frame::new(w, h, 16, vec![1000; w * h]).unwrap(),
        )
    }

    /// Levels given (contact 0, background 1), thresholds 0.25 and 0.5.
    fn given(min_patch_pixels: u64) -> Calibrated {
        Calibrated {
            contact_level: Level::Given(0.0),
            background_level: Level::Given(1.0),
            min_patch_pixels,
            ..Calibrated::default()
        }
    }

    fn mask_rows(mask: &Mask) -> Vec<String> {
        mask.pixels()
            .chunks(mask.width())
            .map(|row| row.iter().map(|&p| if p { '#' } else { '.' }).collect())
            .collect()
    }

    #[test]
    fn hysteresis_keeps_weak_pixels_attached_to_a_seed() {
        const S: f64 = 0.1; // strong: seeds
        const W: f64 = 0.4; // weak: joins only
        const E: f64 = 0.5; // exactly at the join threshold: inclusive
        const B: f64 = 1.0;
        let (frame, reference) = from_ratios(&[
            &[B, B, B, B, B, B, B, B],
            &[B, S, S, B, B, B, S, B],
            &[B, S, S, B, B, B, B, B],
            &[B, B, B, W, B, B, B, B],
            &[B, B, B, B, E, B, B, B],
            &[B, B, B, B, B, B, B, B],
            &[B, W, W, B, B, B, W, B],
            &[B, W, W, B, B, B, B, B],
        ]);
        let result = segment_calibrated(&frame, &reference, &given(1)).unwrap();
        // The weak pixel diagonal to the strong block joins it (8-connected),
        // and so does the one at exactly 0.5 beyond it; the isolated weak
        // pixel and the weak block without a seed are dropped; the lone
        // strong pixel is its own patch.
        assert_eq!(
            mask_rows(&result.mask),
            [
                "........", ".##...#.", ".##.....", "...#....", "....#...", "........", "........",
                "........"
            ]
        );
        assert_eq!(result.patches.sizes(), &[6, 1]);
        assert_eq!((result.seed_threshold, result.join_threshold), (0.25, 0.5));

        // Without hysteresis (seed = join), the weak pixels all count.
        let plain = Calibrated {
            seed_fraction: 0.5,
            ..given(1)
        };
        let result = segment_calibrated(&frame, &reference, &plain).unwrap();
        assert_eq!(result.patches.sizes(), &[6, 1, 4, 1]);
    }

    #[test]
    fn minimum_patch_size_drops_small_patches() {
        const S: f64 = 0.05;
        const B: f64 = 1.0;
        // Patches of 3 and 5 pixels.
        let (frame, reference) = from_ratios(&[
            &[S, S, B, B, B, B],
            &[S, B, B, B, S, B],
            &[B, B, B, S, S, S],
            &[B, B, B, B, S, B],
        ]);
        let sizes = |min| {
            segment_calibrated(&frame, &reference, &given(min))
                .unwrap()
                .patches
                .sizes()
                .to_vec()
        };
        assert_eq!(sizes(1), [3, 5]);
        assert_eq!(sizes(3), [3, 5]);
        assert_eq!(sizes(4), [5]);
        assert_eq!(sizes(5), [5]);
        assert!(sizes(6).is_empty());
    }

    /// A synthetic contact frame: dark disks and rectangles on a vignetted
    /// background with a camera offset, Gaussian noise, and a reference frame
    /// of the same illumination with its own noise. Returns the frame, the
    /// reference and the true contact mask.
    fn synthetic(seed: u64, gain: f64) -> (Frame, Frame, Mask) {
        let (w, h) = (256_usize, 192_usize);
        let offset = 100.0; // camera dark level, counts
        let background = 30000.0;
        let contact_reflectance = 0.02; // of the background
        // Read noise and shot noise: σ² = read² + gain · signal (gain 75:
        // 5 % of the background at the centre, ~0.7 % of it in contact).
        let read_noise = 30.0;
        let disks = [(60.0, 50.0, 20.0), (180.0, 60.0, 11.0), (120.0, 140.0, 6.5)];
        let rectangles = [(20, 120, 50, 135), (200, 110, 206, 170), (150, 20, 153, 23)];
        let inside = |x: usize, y: usize| {
            let (xf, yf) = (x as f64, y as f64);
            disks
                .iter()
                .any(|&(cx, cy, r)| (xf - cx).hypot(yf - cy) <= r)
                || rectangles
                    .iter()
                    .any(|&(x0, y0, x1, y1)| (x0..x1).contains(&x) && (y0..y1).contains(&y))
        };
        let vignetting = |x: usize, y: usize| {
            let (dx, dy) = (x as f64 / w as f64 - 0.5, y as f64 / h as f64 - 0.5);
            1.0 - 1.2 * (dx * dx + dy * dy) // 0.4 of the centre at the corners
        };
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let mut frame = Vec::with_capacity(w * h);
        let mut reference = Vec::with_capacity(w * h);
        let mut truth = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let lit = background * vignetting(x, y);
                let contact = inside(x, y);
                let signal = if contact {
                    contact_reflectance * lit
                } else {
                    lit
                };
                let count = |mean: f64, noise: f64| {
                    let sigma = (read_noise * read_noise + gain * mean).sqrt();
                    (offset + mean + sigma * noise).clamp(0.0, 65535.0) as u16
                };
                frame.push(count(signal, unit.sample(&mut rng)));
                reference.push(count(lit, unit.sample(&mut rng)));
                truth.push(contact);
            }
        }
        (
            Frame::new(w, h, 16, frame).unwrap(),
            Frame::new(w, h, 16, reference).unwrap(),
            Mask::new(w, h, truth).unwrap(),
        )
    }

    /// Tolerance: at most 0.5 % of the true contact pixels may differ (noise
    /// flipping a boundary pixel), and the patch count is exact. The 3 × 3
    /// square is kept (9 ≥ 4 pixels).
    #[test]
    fn recovers_known_shapes_under_vignetting_and_noise() {
        for (seed, gain) in [(1, 75.0), (2, 75.0), (3, 300.0), (4, 300.0)] {
            let (frame, reference, truth) = synthetic(seed, gain);
            let params = Calibrated {
                dark_level: 100.0,
                ..Calibrated::default()
            };
            let result = segment_calibrated(&frame, &reference, &params).unwrap();
            let differing = result
                .mask
                .pixels()
                .iter()
                .zip(truth.pixels())
                .filter(|(a, b)| a != b)
                .count();
            assert!(
                differing as f64 <= 0.005 * truth.count() as f64,
                "seed {seed}: {differing} of {} pixels differ",
                truth.count()
            );
            assert_eq!(result.patches.count(), 6, "seed {seed}");
            assert_eq!(result.patches.count(), label(&truth).count());
            assert!((result.background_level - 1.0).abs() < 0.02);
            assert!(result.contact_level < 0.1, "{}", result.contact_level);

            // The plain threshold (no hysteresis, no patch floor) keeps noise.
            let plain = Calibrated {
                seed_fraction: params.fraction,
                min_patch_pixels: 1,
                ..params
            };
            let plain = segment_calibrated(&frame, &reference, &plain).unwrap();
            let plain_differing = plain
                .mask
                .pixels()
                .iter()
                .zip(truth.pixels())
                .filter(|(a, b)| a != b)
                .count();
            if gain > 100.0 {
                assert!(
                    plain_differing > differing,
                    "seed {seed}: {plain_differing}"
                );
            }
        }
    }

    /// The paper's global Otsu on the same frame, for contrast: vignetting
    /// darkens the corners to 40 % of the centre, near its global threshold,
    /// so noise there is counted as contact.
    #[test]
    fn calibrated_beats_global_otsu_on_a_noisy_vignetted_frame() {
        let (frame, reference, truth) = synthetic(5, 75.0);
        let params = Calibrated {
            dark_level: 100.0,
            ..Calibrated::default()
        };
        let calibrated = segment_calibrated(&frame, &reference, &params).unwrap();
        let t = crate::otsu(&frame.histogram()).unwrap().threshold;
        let global = frame.dark_mask(t);
        let errors = |mask: &Mask| {
            mask.pixels()
                .iter()
                .zip(truth.pixels())
                .filter(|(a, b)| a != b)
                .count()
        };
        assert!(errors(&calibrated.mask) < errors(&global));
    }

    #[test]
    fn zero_reference_pixels_are_never_contact() {
        // Reference: a dead column (0) and a dim one (below dark + min_reference).
        let frame = Frame::new(3, 2, 12, vec![0, 0, 10, 0, 0, 4000]).unwrap();
        let reference = Frame::new(3, 2, 12, vec![0, 100, 4000, 0, 100, 4000]).unwrap();
        let params = Calibrated {
            dark_level: 50.0,
            min_reference: 60.0,
            ..given(1)
        };
        let result = segment_calibrated(&frame, &reference, &params).unwrap();
        assert_eq!(
            result.mask.pixels(),
            &[false, false, true, false, false, false]
        );
        // No usable pixel: an error rather than NaN levels or an empty mask.
        for levels in [Calibrated::default(), given(1)] {
            let params = Calibrated {
                dark_level: 50.0,
                min_reference: 4000.0,
                ..levels
            };
            assert_eq!(
                segment_calibrated(&frame, &reference, &params),
                Err(ImageError::NoUsableReference { floor: 4050.0 })
            );
        }
    }

    #[test]
    fn bad_input_is_refused() {
        let frame = Frame::new(2, 2, 16, vec![10, 20, 30, 40]).unwrap();
        let reference = Frame::new(2, 2, 16, vec![100; 4]).unwrap();
        let bad = [
            Calibrated {
                dark_level: -1.0,
                ..Calibrated::default()
            },
            Calibrated {
                dark_level: f64::NAN,
                ..Calibrated::default()
            },
            Calibrated {
                min_reference: 0.0,
                ..Calibrated::default()
            },
            Calibrated {
                contact_level: Level::Percentile(101.0),
                ..Calibrated::default()
            },
            Calibrated {
                background_level: Level::Percentile(f64::NAN),
                ..Calibrated::default()
            },
            Calibrated {
                contact_level: Level::Given(f64::INFINITY),
                ..Calibrated::default()
            },
            Calibrated {
                fraction: 1.0,
                ..Calibrated::default()
            },
            Calibrated {
                fraction: f64::NAN,
                ..Calibrated::default()
            },
            Calibrated {
                seed_fraction: 0.6,
                ..Calibrated::default()
            },
            Calibrated {
                seed_fraction: 0.0,
                ..Calibrated::default()
            },
            Calibrated {
                min_patch_pixels: 0,
                ..Calibrated::default()
            },
        ];
        for params in bad {
            assert!(
                matches!(
                    segment_calibrated(&frame, &reference, &params),
                    Err(ImageError::Parameter { .. })
                ),
                "{params:?}"
            );
        }
        let wide = Frame::new(4, 1, 16, vec![100; 4]).unwrap();
        assert!(matches!(
            segment_calibrated(&frame, &wide, &Calibrated::default()),
            Err(ImageError::ReferenceSize { .. })
        ));
        let twelve = Frame::new(2, 2, 12, vec![100; 4]).unwrap();
        assert!(matches!(
            segment_calibrated(&frame, &twelve, &Calibrated::default()),
            Err(ImageError::ReferenceBits { .. })
        ));
        // A uniform frame has no contrast between its percentiles.
        let flat = Frame::new(2, 2, 16, vec![50; 4]).unwrap();
        assert!(matches!(
            segment_calibrated(&flat, &reference, &Calibrated::default()),
            Err(ImageError::NoContrast { .. })
        ));
        // Given levels in the wrong order.
        let inverted = Calibrated {
            contact_level: Level::Given(1.0),
            background_level: Level::Given(0.5),
            ..Calibrated::default()
        };
        assert!(matches!(
            segment_calibrated(&frame, &reference, &inverted),
            Err(ImageError::NoContrast { .. })
        ));
    }
}
