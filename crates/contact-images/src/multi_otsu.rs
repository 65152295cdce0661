//! Otsu's method with `k` classes (2 to 5; 3 by default): `k − 1`
//! thresholds maximising the between-class variance
//! `σ_B² = Σ_c ω_c (μ_c − μ_T)²` (Otsu 1979, the multi-level form; Liao,
//! Chen & Chung 2001 for the search). Contact is the darkest class, so the
//! contact threshold is `thresholds[0]`.
//!
//! **What is done to the bins.** An exhaustive search over 65536 levels is
//! out of reach for `k ≥ 3`, so the occupied range `[lo, hi]` of the
//! histogram is re-binned into `bins` bins (256 by default, at most 1024):
//! level `v` goes to bin `⌊(v − lo) · bins / (hi − lo)⌋`, the top level
//! joining the last bin. The binning depends only on ratios of level
//! differences, so multiplying every level by a constant (a 12-bit frame
//! stored as 16-bit values × 16) keeps every pixel in its bin; when the
//! occupied range is narrower than `bins` levels every level has its own bin
//! and the search is exact over levels. Each bin keeps its pixel count and
//! the sum of its pixels' *levels* (not its index), so class means are true
//! grey levels.
//!
//! **Search.** Classes are runs of consecutive occupied bins (empty bins
//! change no class). Maximising `σ_B²` is maximising `Σ_c S_c² / n_c` (level
//! sum `S_c`, count `n_c`), a sum over consecutive runs, solved exactly over
//! the bins by dynamic programming in O(k m²) for `m` occupied bins.
//!
//! **Thresholds** are mapped back to levels as the brightest occupied level
//! of each darker class, so `value <= thresholds[c]` is classes `0..=c`.
//! **Ties** (equal objective in floating point): at each stage the lowest
//! boundary wins, so the brightest threshold is the lowest possible, then the
//! next one below it, and so on.

use crate::ImageError;
use crate::otsu::{Totals, totals};

/// Options of the multi-level Otsu search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MultiOtsu {
    /// Number of classes `k`, 2..=5.
    pub classes: usize,
    /// Bins the occupied range is re-binned into, `classes..=1024`.
    pub bins: usize,
}

impl Default for MultiOtsu {
    fn default() -> Self {
        Self {
            classes: 3,
            bins: 256,
        }
    }
}

impl MultiOtsu {
    /// Refuses classes outside 2..=5 and bins outside `classes..=1024`.
    pub fn check(&self) -> Result<(), ImageError> {
        if !(2..=5).contains(&self.classes) {
            return Err(ImageError::Parameter {
                name: "classes",
                value: self.classes.to_string(),
                expected: "2 to 5 classes",
            });
        }
        if !(self.classes..=1024).contains(&self.bins) {
            return Err(ImageError::Parameter {
                name: "bins",
                value: self.bins.to_string(),
                expected: "at least as many bins as classes, and at most 1024",
            });
        }
        Ok(())
    }
}

/// The result of a multi-level Otsu search.
#[derive(Debug, Clone, PartialEq)]
pub struct MultiOtsuThresholds {
    /// `classes − 1` increasing inclusive thresholds; class `c` is
    /// `thresholds[c − 1] < value <= thresholds[c]`.
    pub thresholds: Vec<u16>,
    /// `σ_B²` of the partition, in (grey levels)².
    pub between_class_variance: f64,
}

impl MultiOtsuThresholds {
    /// The contact threshold: top of the darkest class.
    pub fn contact_threshold(&self) -> u16 {
        self.thresholds[0]
    }
}

/// One occupied bin: pixel count, level sum, brightest level.
#[derive(Debug, Clone, Copy)]
struct Bin {
    count: u128,
    level_sum: u128,
    top: usize,
}

/// The occupied bins of `histogram` re-binned over `[lowest, highest]`, dark first.
fn occupied_bins(histogram: &[u64], totals: &Totals, bins: usize) -> Vec<Bin> {
    let span = totals.highest - totals.lowest;
    let mut out: Vec<(usize, Bin)> = Vec::new();
    for (level, &n) in histogram
        .iter()
        .enumerate()
        .take(totals.highest + 1)
        .skip(totals.lowest)
    {
        if n == 0 {
            continue;
        }
        let index = ((level - totals.lowest) * bins / span).min(bins - 1);
        let n = u128::from(n);
        match out.last_mut() {
            Some((last, bin)) if *last == index => {
                bin.count += n;
                bin.level_sum += n * level as u128;
                bin.top = level;
            }
            _ => out.push((
                index,
                Bin {
                    count: n,
                    level_sum: n * level as u128,
                    top: level,
                },
            )),
        }
    }
    out.into_iter().map(|(_, bin)| bin).collect()
}

/// The multi-level Otsu thresholds of a histogram (bin `v` = pixels of level `v`).
///
/// Errors on invalid options, on the histograms [`crate::otsu()`] refuses, and
/// when fewer bins are occupied than there are classes.
pub fn multi_otsu(
    histogram: &[u64],
    options: &MultiOtsu,
) -> Result<MultiOtsuThresholds, ImageError> {
    options.check()?;
    let totals = totals(histogram)?;
    let k = options.classes;
    if totals.lowest == totals.highest {
        return Err(ImageError::TooFewLevels {
            occupied: 1,
            classes: k,
        });
    }
    let bins = occupied_bins(histogram, &totals, options.bins);
    let m = bins.len();
    if m < k {
        return Err(ImageError::TooFewLevels {
            occupied: m,
            classes: k,
        });
    }

    // Prefix sums over bins, exact in integers; a class of bins i..j has
    // cost S² / n, evaluated in f64.
    let mut prefix_count = vec![0_u128; m + 1];
    let mut prefix_sum = vec![0_u128; m + 1];
    for (j, bin) in bins.iter().enumerate() {
        prefix_count[j + 1] = prefix_count[j] + bin.count;
        prefix_sum[j + 1] = prefix_sum[j] + bin.level_sum;
    }
    let cost = |i: usize, j: usize| {
        let s = (prefix_sum[j] - prefix_sum[i]) as f64;
        s * s / (prefix_count[j] - prefix_count[i]) as f64
    };

    // best[c][j]: the largest Σ S²/n of c + 1 classes over bins 0..j;
    // start[c][j]: where its last class starts (the lowest on ties).
    let mut best = vec![vec![f64::NEG_INFINITY; m + 1]; k];
    let mut start = vec![vec![0_usize; m + 1]; k];
    for (j, value) in best[0].iter_mut().enumerate().skip(1) {
        *value = cost(0, j);
    }
    for c in 1..k {
        let (done, todo) = best.split_at_mut(c);
        let previous = &done[c - 1];
        // c + 1 classes need c + 1 bins; leave one bin to each later class.
        for j in (c + 1)..=(m - (k - 1 - c)) {
            let mut value = f64::NEG_INFINITY;
            let mut arg = c;
            for (i, &head) in previous.iter().enumerate().take(j).skip(c) {
                let candidate = head + cost(i, j);
                if candidate > value {
                    value = candidate;
                    arg = i;
                }
            }
            todo[0][j] = value;
            start[c][j] = arg;
        }
    }

    // Walk the class starts back from the full range.
    let mut boundaries = vec![0_usize; k + 1];
    boundaries[k] = m;
    for c in (1..k).rev() {
        boundaries[c] = start[c][boundaries[c + 1]];
    }
    let thresholds = boundaries[1..k]
        .iter()
        .map(|&b| bins[b - 1].top as u16)
        .collect();

    let total_count = totals.count as f64;
    let mean = totals.sum as f64 / total_count;
    let between_class_variance = boundaries
        .windows(2)
        .map(|w| {
            let n = (prefix_count[w[1]] - prefix_count[w[0]]) as f64;
            let class_mean = (prefix_sum[w[1]] - prefix_sum[w[0]]) as f64 / n;
            n * (class_mean - mean) * (class_mean - mean)
        })
        .sum::<f64>()
        / total_count;
    Ok(MultiOtsuThresholds {
        thresholds,
        between_class_variance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Frame, otsu};
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};

    fn config(cases: u32) -> Config {
        Config {
            cases,
            rng_seed: RngSeed::Fixed(14),
            ..Config::default()
        }
    }

    /// `σ_B² = Σ ω_c (μ_c − μ_T)²` of the classes cut at `thresholds`
    /// (inclusive), summed directly over the histogram.
    fn variance_at(histogram: &[u64], thresholds: &[usize]) -> f64 {
        let total: f64 = histogram.iter().map(|&n| n as f64).sum();
        let mean = histogram
            .iter()
            .enumerate()
            .map(|(v, &n)| v as f64 * n as f64)
            .sum::<f64>()
            / total;
        let mut edges = vec![0_usize];
        edges.extend(thresholds.iter().map(|&t| t + 1));
        edges.push(histogram.len());
        edges
            .windows(2)
            .map(|w| {
                let class = &histogram[w[0]..w[1]];
                let n: f64 = class.iter().map(|&c| c as f64).sum();
                let s: f64 = class
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| (w[0] + i) as f64 * c as f64)
                    .sum();
                (n / total) * (s / n - mean) * (s / n - mean)
            })
            .sum()
    }

    /// Brute force: every way of cutting the occupied levels into `k`
    /// non-empty runs (each threshold an occupied level, the top one
    /// excluded). Returns the best thresholds, their σ_B² and the runner-up's.
    fn brute_force(histogram: &[u64], k: usize) -> Option<(Vec<usize>, f64, f64)> {
        let occupied: Vec<usize> = (0..histogram.len()).filter(|&v| histogram[v] > 0).collect();
        if occupied.len() < k {
            return None;
        }
        let candidates = &occupied[..occupied.len() - 1];
        let mut best: Option<(Vec<usize>, f64)> = None;
        let mut second = f64::NEG_INFINITY;
        let mut chosen = vec![0_usize; k - 1];
        // Odometer over increasing index tuples into `candidates`.
        let mut idx: Vec<usize> = (0..k - 1).collect();
        loop {
            for (c, &i) in idx.iter().enumerate() {
                chosen[c] = candidates[i];
            }
            let v = variance_at(histogram, &chosen);
            match &best {
                Some((_, b)) if v <= *b => second = second.max(v),
                _ => {
                    if let Some((_, b)) = &best {
                        second = second.max(*b);
                    }
                    best = Some((chosen.clone(), v));
                }
            }
            // Advance.
            let mut c = k - 1;
            loop {
                if c == 0 {
                    let (t, v) = best.unwrap();
                    return Some((t, v, second));
                }
                c -= 1;
                if idx[c] < candidates.len() - (k - 1 - c) {
                    idx[c] += 1;
                    for d in c + 1..k - 1 {
                        idx[d] = idx[d - 1] + 1;
                    }
                    break;
                }
            }
        }
    }

    fn small_histogram() -> impl Strategy<Value = Vec<u64>> {
        prop::collection::vec(prop_oneof![1 => Just(0_u64), 3 => 1_u64..1000], 2..20)
    }

    fn check_against_brute_force(h: &[u64], k: usize) -> Result<(), TestCaseError> {
        let options = MultiOtsu {
            classes: k,
            ..MultiOtsu::default()
        };
        let fast = multi_otsu(h, &options);
        let Some((thresholds, variance, runner_up)) = brute_force(h, k) else {
            prop_assert!(
                matches!(
                    fast,
                    Err(ImageError::TooFewLevels { .. } | ImageError::EmptyHistogram)
                ),
                "{fast:?}"
            );
            return Ok(());
        };
        let fast = fast.unwrap();
        let fast_thresholds: Vec<usize> = fast.thresholds.iter().map(|&t| usize::from(t)).collect();
        let tolerance = 1e-9 * variance;
        prop_assert!(
            (variance_at(h, &fast_thresholds) - variance).abs() <= tolerance,
            "{fast_thresholds:?} against {thresholds:?}"
        );
        prop_assert!((fast.between_class_variance - variance).abs() <= tolerance);
        // Where the optimum is unique beyond rounding, the thresholds agree.
        if variance - runner_up > tolerance {
            prop_assert_eq!(fast_thresholds, thresholds);
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(config(64))]

        /// Occupied range under 256 levels: no re-binning, the search is
        /// exact over levels.
        #[test]
        fn equals_brute_force_on_small_histograms(h in small_histogram(), k in 2_usize..=5) {
            check_against_brute_force(&h, k)?;
        }

        /// Two classes over unbinned levels is global Otsu.
        #[test]
        fn two_classes_are_global_otsu(
            offset in 0_usize..60000,
            counts in prop::collection::vec(prop_oneof![Just(0_u64), 1_u64..1_000_000], 2..200),
        ) {
            let mut h = vec![0_u64; 65536];
            h[offset..offset + counts.len()].copy_from_slice(&counts);
            let options = MultiOtsu { classes: 2, bins: 256 };
            match (multi_otsu(&h, &options), otsu(&h)) {
                (Ok(multi), Ok(global)) => {
                    prop_assert_eq!(multi.thresholds, vec![global.threshold]);
                    let relative = (multi.between_class_variance / global.between_class_variance - 1.0).abs();
                    prop_assert!(relative < 1e-9);
                }
                (Err(ImageError::TooFewLevels { .. } | ImageError::EmptyHistogram),
                 Err(ImageError::SingleLevel { .. } | ImageError::EmptyHistogram)) => {}
                (multi, global) => prop_assert!(false, "{multi:?} / {global:?}"),
            }
        }

        /// Re-binned: every threshold is an occupied level that ends a bin,
        /// so no bin is split between classes.
        #[test]
        fn thresholds_fall_between_bins(
            spikes in prop::collection::vec((0_usize..65536, 1_u64..1000), 8..200),
            k in 2_usize..=5,
            bins in prop_oneof![Just(256_usize), Just(1024), 5_usize..64],
        ) {
            let mut h = vec![0_u64; 65536];
            for (v, n) in spikes {
                h[v] += n;
            }
            let totals = totals(&h).unwrap();
            let bin_of = |v: usize| {
                ((v - totals.lowest) * bins / (totals.highest - totals.lowest)).min(bins - 1)
            };
            match multi_otsu(&h, &MultiOtsu { classes: k, bins }) {
                Ok(result) => {
                    prop_assert_eq!(result.thresholds.len(), k - 1);
                    prop_assert!(result.thresholds.windows(2).all(|w| w[0] < w[1]));
                    for &t in &result.thresholds {
                        let t = usize::from(t);
                        prop_assert!(h[t] > 0);
                        let next = (t + 1..65536).find(|&v| h[v] > 0).unwrap();
                        prop_assert!(bin_of(t) < bin_of(next));
                    }
                }
                Err(ImageError::TooFewLevels { occupied, .. }) => prop_assert!(occupied < k),
                Err(e) => prop_assert!(false, "{e}"),
            }
        }
    }

    #[test]
    fn trimodal_16_bit_histogram_splits_between_modes() {
        let mut h = vec![0_u64; 65536];
        for (centre, weight) in [(1500_i64, 2_u64), (21000, 1), (52000, 5)] {
            for dv in -400_i64..=400 {
                let w = (1000.0 * (-(dv as f64 / 150.0).powi(2)).exp()) as u64;
                h[(centre + dv) as usize] += weight * w;
            }
        }
        let result = multi_otsu(&h, &MultiOtsu::default()).unwrap();
        let [t0, t1] = result.thresholds[..] else {
            panic!("{result:?}")
        };
        // Modes far apart (in bins of ~200 levels): each threshold is the
        // brightest occupied level of its mode.
        let top_below = |v: usize| (0..v).rev().find(|&l| h[l] > 0).unwrap() as u16;
        assert_eq!((t0, t1), (top_below(10000), top_below(40000)));
        assert!((1850..1950).contains(&t0) && (21350..21450).contains(&t1));
        assert_eq!(result.contact_threshold(), t0);
    }

    #[test]
    fn options_and_histograms_are_checked() {
        let h = [5_u64, 0, 3, 8, 1];
        for (classes, bins) in [(1, 256), (6, 256), (3, 2), (3, 1025)] {
            assert!(matches!(
                multi_otsu(&h, &MultiOtsu { classes, bins }),
                Err(ImageError::Parameter { .. })
            ));
        }
        assert_eq!(
            multi_otsu(
                &h,
                &MultiOtsu {
                    classes: 5,
                    bins: 256
                }
            ),
            Err(ImageError::TooFewLevels {
                occupied: 4,
                classes: 5
            })
        );
        assert_eq!(
            multi_otsu(&[0, 4, 0], &MultiOtsu::default()),
            Err(ImageError::TooFewLevels {
                occupied: 1,
                classes: 3
            })
        );
        assert_eq!(
            multi_otsu(&[], &MultiOtsu::default()),
            Err(ImageError::HistogramLength { len: 0 })
        );
        assert_eq!(
            multi_otsu(&[0; 9], &MultiOtsu::default()),
            Err(ImageError::EmptyHistogram)
        );
        // Four occupied levels, four classes: every level its own class.
        // (Levels 0..=4 need 5 bins to stay apart.)
        let r = multi_otsu(
            &h,
            &MultiOtsu {
                classes: 4,
                bins: 5,
            },
        )
        .unwrap();
        assert_eq!(r.thresholds, vec![0, 2, 3]);
    }

    /// A random 12-bit frame of three grey populations (contact, fringe,
    /// background) over a random occupied range.
    fn frame_12_bit() -> impl Strategy<Value = Frame> {
        (
            4_usize..40,
            4_usize..40,
            0_u16..3000,
            1_u16..1096,
            prop::collection::vec(0_u16..1000, 1600),
        )
            .prop_map(|(w, h, lo, span, noise)| {
                let data = (0..w * h)
                    .map(|i| {
                        let population = (i * 7 / 3 + i / w) % 3;
                        let base = lo + span * population as u16 / 3;
                        base + noise[i] % (span / 3 + 1)
                    })
                    .collect();
                Frame::new(w, h, 12, data).unwrap()
            })
    }

    proptest! {
        #![proptest_config(config(64))]

        /// The 12-bit frame and its copy × 16 at 16 bits: same contact mask,
        /// every threshold × 16, σ_B² × 256.
        #[test]
        fn twelve_bit_and_scaled_copy_give_the_same_mask(
            frame in frame_12_bit(),
            classes in 2_usize..=5,
            bins in prop_oneof![Just(256_usize), Just(1024), 5_usize..40],
        ) {
            let scaled = crate::otsu::tests::scaled_to_16_bits(&frame);
            let options = MultiOtsu { classes, bins };
            match (multi_otsu(&frame.histogram(), &options), multi_otsu(&scaled.histogram(), &options)) {
                (Ok(r12), Ok(r16)) => {
                    let times_16: Vec<u32> = r12.thresholds.iter().map(|&t| 16 * u32::from(t)).collect();
                    let r16_thresholds: Vec<u32> = r16.thresholds.iter().map(|&t| u32::from(t)).collect();
                    prop_assert_eq!(r16_thresholds, times_16);
                    prop_assert_eq!(
                        frame.dark_mask(r12.contact_threshold()),
                        scaled.dark_mask(r16.contact_threshold())
                    );
                    prop_assert_eq!(r16.between_class_variance, 256.0 * r12.between_class_variance);
                }
                (Err(e12), Err(e16)) => prop_assert_eq!(e12, e16),
                (r12, r16) => prop_assert!(false, "{r12:?} / {r16:?}"),
            }
        }
    }
}
