//! Global Otsu threshold on a full histogram: the paper's segmentation, one
//! threshold per frame on all `2^bits` levels (65536 bins for a 16-bit camera).
//!
//! Otsu (1979), IEEE Trans. SMC 9, 62: the threshold `t` splits the levels
//! into a dark class `C0 = {v <= t}` (contact) and a bright class
//! `C1 = {v > t}`, and maximises the between-class variance
//! `σ_B²(t) = ω0 ω1 (μ0 − μ1)²` (class weights ω, class means μ).
//!
//! With pixel counts `n0`, `n1`, level sums `S0`, `S1`, total count `N` and
//! total sum `S`, `σ_B² = D² / (N² n0 n1)` with the integer `D = N S0 − n0 S`.
//! One pass of cumulative sums gives `n0` and `S0` for every `t` (O(bins)),
//! and the candidates are ordered by comparing `D² / (n0 n1)` exactly in
//! integer arithmetic (the private `exact` module), so ties are real ties.
//!
//! **Tie rule.** `σ_B²` is constant on every run of empty levels (moving `t`
//! across an empty level changes no class), so every maximum is a plateau.
//! Of all thresholds with the maximal `σ_B²`, the *lowest* wins (as
//! scikit-image's `argmax` does); it is always an occupied level — the
//! brightest level present in the dark class — and two distinct plateaus of
//! exactly equal variance (a symmetric histogram) also resolve to the lower,
//! i.e. the smaller contact area.

use std::cmp::Ordering;

use crate::ImageError;
use crate::exact::cmp_square_ratio;

/// The largest total count a histogram may have: keeps `D` within `i128`.
const MAX_TOTAL: u128 = 1 << 48;

/// The result of a global Otsu search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Otsu {
    /// Inclusive threshold: contact is `value <= threshold`.
    pub threshold: u16,
    /// `σ_B²` at the threshold, in (grey levels)².
    pub between_class_variance: f64,
}

/// Pixel count and level sum of a histogram, after checking it.
pub(crate) struct Totals {
    pub count: u128,
    pub sum: u128,
    /// Lowest and highest occupied level.
    pub lowest: usize,
    pub highest: usize,
}

/// Checks a histogram (1 to 65536 bins, some count, total within 2^48) and
/// sums it.
pub(crate) fn totals(histogram: &[u64]) -> Result<Totals, ImageError> {
    if histogram.is_empty() || histogram.len() > 1 << 16 {
        return Err(ImageError::HistogramLength {
            len: histogram.len(),
        });
    }
    let mut count = 0_u128;
    let mut sum = 0_u128;
    let mut lowest = None;
    let mut highest = 0;
    for (level, &n) in histogram.iter().enumerate() {
        if n > 0 {
            count += u128::from(n);
            sum += u128::from(n) * level as u128;
            lowest.get_or_insert(level);
            highest = level;
        }
    }
    let Some(lowest) = lowest else {
        return Err(ImageError::EmptyHistogram);
    };
    if count > MAX_TOTAL {
        return Err(ImageError::HistogramTooLarge { total: count });
    }
    Ok(Totals {
        count,
        sum,
        lowest,
        highest,
    })
}

/// Otsu's threshold of a histogram (bin `v` = number of pixels of level `v`).
///
/// Errors when the histogram is empty, longer than 65536 bins, counts more
/// than 2^48 pixels, or has a single occupied level (nothing to separate).
pub fn otsu(histogram: &[u64]) -> Result<Otsu, ImageError> {
    let Totals {
        count,
        sum,
        lowest,
        highest,
    } = totals(histogram)?;
    if lowest == highest {
        return Err(ImageError::SingleLevel {
            level: lowest as u16,
        });
    }
    let count_i = count as i128;
    let sum_i = sum as i128;
    // (threshold, |D|, n0 n1) of the best candidate so far.
    let mut best: Option<(usize, u128, u128)> = None;
    let mut n0 = 0_u128;
    let mut s0 = 0_u128;
    // t = highest would leave the bright class empty.
    for (t, &n) in histogram.iter().enumerate().take(highest) {
        if n == 0 {
            // Same classes as the occupied level below: never a new maximum.
            continue;
        }
        n0 += u128::from(n);
        s0 += u128::from(n) * t as u128;
        let d = (count_i * s0 as i128 - n0 as i128 * sum_i).unsigned_abs();
        let a = n0 * (count - n0);
        let better = match best {
            None => true,
            Some((_, d_best, a_best)) => {
                cmp_square_ratio(d, a, d_best, a_best) == Ordering::Greater
            }
        };
        if better {
            best = Some((t, d, a));
        }
    }
    // lowest < highest, so the loop saw at least the lowest level.
    let (t, d, a) = best.ok_or(ImageError::SingleLevel {
        level: lowest as u16,
    })?;
    let d_over_n = d as f64 / count as f64;
    Ok(Otsu {
        threshold: t as u16,
        between_class_variance: d_over_n * d_over_n / a as f64,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::Frame;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};

    fn config(cases: u32) -> Config {
        Config {
            cases,
            rng_seed: RngSeed::Fixed(14),
            ..Config::default()
        }
    }

    /// Brute force: for every threshold `t` of the histogram (empty levels
    /// included) sum each class directly over the occupied levels, form
    /// `μ0 − μ1 = (S0 n1 − S1 n0) / (n0 n1)` and keep the first strict maximum
    /// of `(S0 n1 − S1 n0)² / (n0 n1)`, compared exactly. Also returns
    /// `σ_B² = ω0 ω1 (μ0 − μ1)²` in floating point at that threshold.
    fn brute_force(histogram: &[u64]) -> Option<(u16, f64)> {
        let occupied: Vec<(u128, u128)> = histogram
            .iter()
            .enumerate()
            .filter(|&(_, &n)| n > 0)
            .map(|(v, &n)| (v as u128, u128::from(n)))
            .collect();
        let mut best: Option<(usize, u128, u128, f64)> = None;
        for t in 0..histogram.len() {
            let (mut n0, mut s0, mut n1, mut s1) = (0_u128, 0_u128, 0_u128, 0_u128);
            for &(v, n) in &occupied {
                if v <= t as u128 {
                    n0 += n;
                    s0 += n * v;
                } else {
                    n1 += n;
                    s1 += n * v;
                }
            }
            if n0 == 0 || n1 == 0 {
                continue;
            }
            let d = (s0 as i128 * n1 as i128 - s1 as i128 * n0 as i128).unsigned_abs();
            let a = n0 * n1;
            let total = (n0 + n1) as f64;
            let (w0, w1) = (n0 as f64 / total, n1 as f64 / total);
            let (m0, m1) = (s0 as f64 / n0 as f64, s1 as f64 / n1 as f64);
            let variance = w0 * w1 * (m0 - m1) * (m0 - m1);
            if best.is_none_or(|(_, db, ab, _)| cmp_square_ratio(d, a, db, ab) == Ordering::Greater)
            {
                best = Some((t, d, a, variance));
            }
        }
        best.map(|(t, _, _, variance)| (t as u16, variance))
    }

    /// A random histogram of `2^bits` bins: a few occupied levels (clustered
    /// in two or three modes or spread), counts up to `max_count`.
    fn histogram(bits: u32, max_count: u64) -> impl Strategy<Value = Vec<u64>> {
        let levels = 1_usize << bits;
        (
            prop::collection::vec((0..levels, 1..=max_count), 2..40),
            prop::collection::vec((0..levels, 1_usize..200, 1..=max_count), 0..3),
        )
            .prop_map(move |(spikes, modes)| {
                let mut h = vec![0_u64; levels];
                for (v, n) in spikes {
                    h[v] += n;
                }
                // Blocks of equal counts: long plateaus of equal variance.
                for (start, width, n) in modes {
                    for count in h.iter_mut().skip(start).take(width) {
                        *count += n;
                    }
                }
                h
            })
    }

    fn check_against_brute_force(h: &[u64]) -> Result<(), TestCaseError> {
        match (otsu(h), brute_force(h)) {
            (Ok(fast), Some((t, variance))) => {
                prop_assert_eq!(fast.threshold, t);
                prop_assert!(
                    h[usize::from(fast.threshold)] > 0,
                    "threshold on an empty level"
                );
                let tolerance = 1e-9 * variance.max(1e-300);
                prop_assert!(
                    (fast.between_class_variance - variance).abs() <= tolerance,
                    "σ_B² {} against {}",
                    fast.between_class_variance,
                    variance
                );
            }
            (Err(ImageError::SingleLevel { .. } | ImageError::EmptyHistogram), None) => {}
            (fast, slow) => prop_assert!(false, "otsu {fast:?}, brute force {slow:?}"),
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(config(48))]

        #[test]
        fn equals_brute_force_on_16_bit_histograms(h in histogram(16, 1 << 20)) {
            check_against_brute_force(&h)?;
        }

        #[test]
        fn equals_brute_force_on_12_bit_histograms(h in histogram(12, 1 << 20)) {
            check_against_brute_force(&h)?;
        }

        /// Small counts on few levels: many exact ties between plateaus.
        #[test]
        fn equals_brute_force_on_small_tie_prone_histograms(
            h in prop::collection::vec(prop_oneof![Just(0_u64), 1_u64..4], 2..12),
        ) {
            check_against_brute_force(&h)?;
        }
    }

    #[test]
    fn tie_rule_picks_the_lowest_threshold() {
        // Three equal spikes, symmetric: t = 0 and t = 2 have equal σ_B².
        let h = [1, 0, 1, 0, 1];
        let o = otsu(&h).unwrap();
        assert_eq!(o.threshold, 0);
        // ω0 = 1/3, ω1 = 2/3, μ0 = 0, μ1 = 3: σ_B² = 2/9 · 9 = 2.
        assert!((o.between_class_variance - 2.0).abs() < 1e-12);
        // Two spikes: the plateau 10..=49 resolves to the occupied level 10.
        let mut h = vec![0_u64; 64];
        h[10] = 5;
        h[50] = 7;
        assert_eq!(otsu(&h).unwrap().threshold, 10);
    }

    #[test]
    fn bimodal_histogram_splits_between_its_modes() {
        // Two Gaussian-like modes at 1000 and 40000 in a 16-bit histogram.
        let mut h = vec![0_u64; 65536];
        for dv in -300_i64..=300 {
            let w = (1000.0 * (-(dv as f64 / 100.0).powi(2)).exp()) as u64;
            h[(1000 + dv) as usize] += w;
            h[(40000 + dv) as usize] += 3 * w;
        }
        // The modes do not overlap, so every threshold between them has the
        // same σ_B²: the tie rule gives the dark mode's brightest level.
        let dark_top = (0..20000).rev().find(|&v| h[v] > 0).unwrap();
        assert!((1200..1300).contains(&dark_top));
        assert_eq!(usize::from(otsu(&h).unwrap().threshold), dark_top);
    }

    #[test]
    fn bad_histograms_are_refused() {
        assert_eq!(otsu(&[]), Err(ImageError::HistogramLength { len: 0 }));
        assert_eq!(
            otsu(&vec![1; 65537]),
            Err(ImageError::HistogramLength { len: 65537 })
        );
        assert_eq!(otsu(&[0, 0, 0]), Err(ImageError::EmptyHistogram));
        assert_eq!(otsu(&[0, 9, 0]), Err(ImageError::SingleLevel { level: 1 }));
        assert!(matches!(
            otsu(&[u64::MAX, u64::MAX]),
            Err(ImageError::HistogramTooLarge { .. })
        ));
        // The largest allowed total works at full 16-bit range.
        let mut h = vec![0_u64; 65536];
        h[0] = 1 << 47;
        h[65535] = (1 << 47) - 1;
        assert_eq!(otsu(&h).unwrap().threshold, 0);
    }

    /// A random 12-bit frame (dark disks in a bright, noisy field).
    fn frame_12_bit() -> impl Strategy<Value = Frame> {
        (
            4_usize..40,
            4_usize..40,
            prop::collection::vec(0_u16..4096, 1600),
        )
            .prop_map(|(w, h, noise)| {
                let data = (0..w * h)
                    .map(|i| {
                        let (x, y) = ((i % w) as f64, (i / w) as f64);
                        let dark = (x - 0.3 * w as f64).hypot(y - 0.5 * h as f64) < 0.25 * w as f64;
                        let base: u16 = if dark { 200 } else { 2800 };
                        base + noise[i] / 4
                    })
                    .collect();
                Frame::new(w, h, 12, data).unwrap()
            })
    }

    /// The same frame in a 16-bit range: every value × 16, `bits = 16`.
    pub(crate) fn scaled_to_16_bits(frame: &Frame) -> Frame {
        let data = frame.data().iter().map(|&v| v * 16).collect();
        Frame::new(frame.width(), frame.height(), 16, data).unwrap()
    }

    proptest! {
        #![proptest_config(config(64))]

        /// A 12-bit frame and its copy scaled to 16 bits: same contact mask,
        /// threshold × 16, σ_B² × 256.
        #[test]
        fn twelve_bit_and_scaled_copy_give_the_same_mask(frame in frame_12_bit()) {
            let scaled = scaled_to_16_bits(&frame);
            let o12 = otsu(&frame.histogram()).unwrap();
            let o16 = otsu(&scaled.histogram()).unwrap();
            prop_assert_eq!(u32::from(o16.threshold), 16 * u32::from(o12.threshold));
            prop_assert_eq!(frame.dark_mask(o12.threshold), scaled.dark_mask(o16.threshold));
            let ratio = o16.between_class_variance / o12.between_class_variance;
            prop_assert!((ratio - 256.0).abs() < 1e-9, "ratio {ratio}");
        }
    }
}
