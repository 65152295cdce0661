//! The areal material ratio (Abbott–Firestone) curve of ISO 25178-2 §3.3
//! and the functional parameters of ISO 13565-2 (adopted by ISO 25178-2
//! §4.5) read off it.
//!
//! The measured heights z = h − z̄, sorted from the highest, are the curve
//! sampled at material ratios mr_i = (i + ½)/N · 100 % (each point stands
//! for 1/N of the area); between samples the curve is linear, and it is
//! flat from mr = 0 to the first sample and from the last to 100 %.
//! Smr(c) is the material ratio at which the curve falls to height c (the
//! percentage of the area at or above c), Smc(mr) the height at ratio mr.
//!
//! Functional parameters (ISO 13565-2 §4):
//! - the equivalence line is the secant through the curve at mr and
//!   mr + 40 % with the smallest gradient (the smallest height drop; the
//!   first of equals), mr running over the samples;
//! - it meets mr = 0 at height h0 and mr = 100 % at h100: Sk = h0 − h100,
//!   Smr1 = Smr(h0), Smr2 = Smr(h100);
//! - Spk is the height of the triangle on base Smr1 whose area equals the
//!   area between the curve and h0 over 0 … Smr1 (the peaks above the
//!   core): Spk = 2·A1/Smr1; Svk likewise on base 100 % − Smr2 with the area
//!   between h100 and the curve over Smr2 … 100 % (the valleys): Svk =
//!   2·A2/(100 − Smr2). The areas are summed over the samples (each 1/N of
//!   the ratio wide); a zero base gives zero.

use ndarray::Array2;
use rayon::prelude::*;

use super::{checked_heights, measured_mean};
use crate::SurfaceError;

/// ISO 13565-2's window of the equivalence line, % of material ratio.
pub const EQUIVALENCE_WINDOW_PERCENT: f64 = 40.0;

/// The material ratio curve of a map: its measured heights about their
/// mean, sorted from the highest.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialRatio {
    heights_m: Vec<f64>,
}

/// Sk, Spk, Svk, Smr1, Smr2 of ISO 13565-2, and the equivalence line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FunctionalParameters {
    /// Core height h0 − h100, m.
    pub sk_m: f64,
    /// Reduced peak height, m.
    pub spk_m: f64,
    /// Reduced valley depth, m.
    pub svk_m: f64,
    /// Material ratio at height h0, %.
    pub smr1_percent: f64,
    /// Material ratio at height h100, %.
    pub smr2_percent: f64,
    /// The equivalence line's height at mr = 0, m.
    pub h0_m: f64,
    /// Its height at mr = 100 %, m.
    pub h100_m: f64,
    /// Where its 40 % window starts, %.
    pub window_start_percent: f64,
}

impl MaterialRatio {
    /// The curve of the measured points of the levelled map `h`, O(N log N);
    /// an error for fewer than four measured points or a ±∞ height.
    pub fn new(h: &Array2<f64>) -> Result<Self, SurfaceError> {
        let heights = checked_heights(h, "the material ratio curve")?;
        let mean = measured_mean(&heights.values);
        let mut heights_m: Vec<f64> = heights
            .values
            .iter()
            .filter(|v| !v.is_nan())
            .map(|v| v - mean)
            .collect();
        // a total order: the sorted bits do not depend on the threads
        heights_m.par_sort_unstable_by(|a, b| b.total_cmp(a));
        Ok(Self { heights_m })
    }

    /// The sorted heights, highest first, m.
    pub fn heights_m(&self) -> &[f64] {
        &self.heights_m
    }

    fn ratio_of(&self, i: usize) -> f64 {
        (i as f64 + 0.5) / self.heights_m.len() as f64 * 100.0
    }

    /// Smc(mr): the height at material ratio `mr_percent` (clamped to
    /// 0 … 100), m.
    pub fn smc_m(&self, mr_percent: f64) -> f64 {
        let z = &self.heights_m;
        let n = z.len();
        let position = mr_percent.clamp(0.0, 100.0) / 100.0 * n as f64 - 0.5;
        if position <= 0.0 {
            return z[0];
        }
        let i = position.floor() as usize;
        if i + 1 >= n {
            return z[n - 1];
        }
        let t = position - i as f64;
        z[i] + t * (z[i + 1] - z[i])
    }

    /// Smr(c): the material ratio at which the curve falls to height `c_m`,
    /// % (0 above the highest point, 100 below the lowest; the largest
    /// ratio where the curve is flat at c).
    pub fn smr_percent(&self, c_m: f64) -> f64 {
        let z = &self.heights_m;
        let n = z.len();
        // samples at or above c: z[..above]
        let above = z.partition_point(|&v| v >= c_m);
        if above == 0 {
            return 0.0;
        }
        if above == n {
            return 100.0;
        }
        let (hi, lo) = (z[above - 1], z[above]);
        let t = (hi - c_m) / (hi - lo);
        self.ratio_of(above - 1) + t * (self.ratio_of(above) - self.ratio_of(above - 1))
    }

    /// The curve at `points` evenly spaced material ratios 0 … 100 % (for
    /// a plot): (material ratio %, height m).
    pub fn curve(&self, points: usize) -> (Vec<f64>, Vec<f64>) {
        let ratios: Vec<f64> = (0..points)
            .map(|k| 100.0 * k as f64 / (points.max(2) - 1) as f64)
            .collect();
        let heights = ratios.iter().map(|&mr| self.smc_m(mr)).collect();
        (ratios, heights)
    }

    /// Sk, Spk, Svk, Smr1 and Smr2 (see the module doc), O(N).
    pub fn functional(&self) -> FunctionalParameters {
        let z = &self.heights_m;
        let n = z.len();
        // the window's end lies `span` samples after its start
        let span = EQUIVALENCE_WINDOW_PERCENT / 100.0 * n as f64;
        let (whole, fraction) = (span.floor() as usize, span.fract());
        let end_height = |i: usize| {
            let j = i + whole;
            if fraction == 0.0 {
                z[j]
            } else {
                z[j] + fraction * (z[j + 1] - z[j])
            }
        };
        let starts = n - whole - usize::from(fraction > 0.0);
        let (mut best, mut best_drop) = (0, f64::INFINITY);
        for (i, &top) in z.iter().enumerate().take(starts) {
            let drop = top - end_height(i);
            if drop < best_drop {
                (best, best_drop) = (i, drop);
            }
        }
        let slope = best_drop / EQUIVALENCE_WINDOW_PERCENT;
        let start_percent = self.ratio_of(best);
        let h0_m = z[best] + slope * start_percent;
        let h100_m = z[best] - slope * (100.0 - start_percent);
        let (smr1, smr2) = (self.smr_percent(h0_m), self.smr_percent(h100_m));
        let width = 100.0 / n as f64;
        let peaks: f64 = z.iter().take_while(|&&v| v > h0_m).map(|v| v - h0_m).sum();
        let valleys: f64 = z
            .iter()
            .rev()
            .take_while(|&&v| v < h100_m)
            .map(|v| h100_m - v)
            .sum();
        let triangle = |area: f64, base: f64| if base > 0.0 { 2.0 * area / base } else { 0.0 };
        FunctionalParameters {
            sk_m: h0_m - h100_m,
            spk_m: triangle(peaks * width, smr1),
            svk_m: triangle(valleys * width, 100.0 - smr2),
            smr1_percent: smr1,
            smr2_percent: smr2,
            h0_m,
            h100_m,
            window_start_percent: start_percent,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map whose heights are the piecewise-linear curve Smc(mr) = 5 − 0.4·mr
    /// (0 … 10 %), 1 − (mr − 10)/40 (10 … 90 %), −1 − 0.4·(mr − 90)
    /// (90 … 100 %), sampled at mr_i and shuffled. The flattest 40 % secant
    /// lies in the core: h0 = 1.25, h100 = −1.25, Sk = 2.5; the line meets
    /// the peak section at Smr1 = (5 − 1.25)/0.4 = 9.375 % and the valley
    /// section at Smr2 = 90.625 %; peaks and valleys are exact triangles of
    /// height 3.75, so Spk = Svk = 3.75.
    #[test]
    fn a_three_section_curve_has_its_hand_computed_parameters() {
        let n = 100_000;
        let smc = |mr: f64| {
            if mr < 10.0 {
                5.0 - 0.4 * mr
            } else if mr < 90.0 {
                1.0 - (mr - 10.0) / 40.0
            } else {
                -1.0 - 0.4 * (mr - 90.0)
            }
        };
        // the heights in a scrambled order (7919 is prime to n)
        let h = Array2::from_shape_fn((400, 250), |(i, j)| {
            let k = ((i * 250 + j) * 7919) % n;
            smc((k as f64 + 0.5) / n as f64 * 100.0) * 1e-6
        });
        let curve = MaterialRatio::new(&h).unwrap();
        // the sampled curve's mean is 0 by symmetry, to rounding
        let p = curve.functional();
        let close = |a: f64, b: f64, tol: f64| (a - b).abs() < tol;
        assert!(close(p.sk_m, 2.5e-6, 1e-11), "{p:?}");
        assert!(close(p.h0_m, 1.25e-6, 1e-11) && close(p.h100_m, -1.25e-6, 1e-11));
        assert!(close(p.smr1_percent, 9.375, 1e-4) && close(p.smr2_percent, 90.625, 1e-4));
        assert!(
            close(p.spk_m, 3.75e-6, 1e-10) && close(p.svk_m, 3.75e-6, 1e-10),
            "{p:?}"
        );
        assert!(p.window_start_percent >= 10.0 && p.window_start_percent <= 50.0);
        // Smr and Smc are inverses on the curve
        for mr in [0.5, 9.375, 30.0, 77.7, 99.5] {
            assert!(close(curve.smr_percent(curve.smc_m(mr)), mr, 1e-9), "{mr}");
            assert!(close(curve.smc_m(mr), smc(mr) * 1e-6, 1e-11), "{mr}");
        }
        let (ratios, heights) = curve.curve(11);
        assert_eq!(ratios.len(), 11);
        assert!(close(ratios[5], 50.0, 1e-12) && close(heights[5], 0.0, 1e-11));
        assert!(close(heights[0], smc(0.0) * 1e-6, 1e-9) && heights[10] < -2.9e-6);
    }

    /// Uniform heights in [−a, a]: the curve is the straight line from a to
    /// −a, so the equivalence line is the curve itself: Sk = 2a, Smr1 = 0,
    /// Smr2 = 100 %, Spk = Svk = 0, exactly on an evenly spaced sample and
    /// within the sampling scatter on random draws.
    #[test]
    fn uniform_heights_are_all_core() {
        let (n, a) = (10_000usize, 2e-6);
        let even = Array2::from_shape_fn((100, 100), |(i, j)| {
            a * (1.0 - 2.0 * ((i * 100 + j) as f64 + 0.5) / n as f64)
        });
        let p = MaterialRatio::new(&even).unwrap().functional();
        assert!((p.sk_m / (2.0 * a) - 1.0).abs() < 1e-9, "{p:?}");
        assert!(p.spk_m.abs() < 1e-15 && p.svk_m.abs() < 1e-15, "{p:?}");
        assert!(
            p.smr1_percent < 1e-6 && p.smr2_percent > 100.0 - 1e-6,
            "{p:?}"
        );
        // a seeded draw (splitmix64 to [0, 1)): the same within ~1 %
        let random =
            crate::iso25178::tests::uniform_noise(400, 400, 9).mapv(|u| a * (2.0 * u - 1.0));
        let p = MaterialRatio::new(&random).unwrap().functional();
        assert!((p.sk_m / (2.0 * a) - 1.0).abs() < 0.02, "{p:?}");
        assert!(p.spk_m < 0.02 * a && p.svk_m < 0.02 * a, "{p:?}");
    }

    #[test]
    fn too_few_points_are_refused() {
        let mut h = Array2::from_elem((2, 2), f64::NAN);
        assert!(MaterialRatio::new(&h).is_err());
        h.fill(1.0);
        let p = MaterialRatio::new(&h).unwrap().functional();
        assert_eq!((p.sk_m, p.spk_m, p.svk_m), (0.0, 0.0, 0.0));
    }
}
