//! The per-POI loops of IC-GN (reference subset sums, B-spline values on
//! the warped subset, the target sums) compiled for the widest x86 vector
//! instruction set the running CPU has: AVX2 on x86-64-v3 machines, else the
//! SSE2 baseline the workspace is built for. `pulp::Arch` detects the CPU
//! once and calls the loop through a function built with those target
//! features, without unsafe code here (the workspace forbids it).
//!
//! The results do not depend on the choice. Rust emits each floating-point
//! addition and multiplication as its own IEEE 754 operation: LLVM neither
//! fuses a multiply and an add into an FMA nor reorders a sum unless asked
//! to (no fast-math flags, no `mul_add` in these loops), so the wider code
//! performs the same operations in the same order, only more lanes at once.
//! `tests::widest_and_baseline_give_identical_bits` checks this.

use pulp::{Arch, Simd, WithSimd};

use crate::bspline::BSplineImage;
use crate::icgn::{IcgnSettings, Match, ReferenceFrame, ReferenceSubset, Warp};

/// Which instruction set the loops run on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InstructionSet {
    /// The widest the CPU supports (what the stage uses).
    Widest,
    /// The build's baseline, for checking that both agree bit for bit.
    #[cfg_attr(not(test), allow(dead_code))]
    Baseline,
}

impl InstructionSet {
    fn arch(self) -> Arch {
        match self {
            Self::Widest => Arch::new(),
            Self::Baseline => Arch::Scalar,
        }
    }
}

/// `ReferenceSubset::new_inline` as a `pulp` operation.
struct PrepareSubset<'a> {
    frame: &'a ReferenceFrame,
    centre: (usize, usize),
    half: usize,
}

impl<'a> WithSimd for PrepareSubset<'a> {
    type Output = Option<ReferenceSubset<'a>>;

    // Inlined into pulp's target-feature function, and the loops with it,
    // so that they are compiled with its features.
    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> Self::Output {
        ReferenceSubset::new_inline(self.frame, self.centre.0, self.centre.1, self.half)
    }
}

/// `ReferenceSubset::solve_inline` as a `pulp` operation.
struct Solve<'s, 'a> {
    subset: &'s ReferenceSubset<'a>,
    target: &'s BSplineImage,
    guess: Warp,
    settings: &'s IcgnSettings,
}

impl WithSimd for Solve<'_, '_> {
    type Output = Match;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> Match {
        self.subset
            .solve_inline(self.target, self.guess, self.settings)
    }
}

/// The reference subset of side `2 half + 1` centred on `centre`.
pub(crate) fn prepare_subset(
    set: InstructionSet,
    frame: &ReferenceFrame,
    centre: (usize, usize),
    half: usize,
) -> Option<ReferenceSubset<'_>> {
    set.arch().dispatch(PrepareSubset {
        frame,
        centre,
        half,
    })
}

/// IC-GN of `subset` against `target` from `guess`.
pub(crate) fn solve(
    set: InstructionSet,
    subset: &ReferenceSubset<'_>,
    target: &BSplineImage,
    guess: Warp,
    settings: &IcgnSettings,
) -> Match {
    set.arch().dispatch(Solve {
        subset,
        target,
        guess,
        settings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gray::GrayImage;

    /// Gaussian speckles of radius ~2 px at pseudo-random places, seen
    /// through the affine map `x ↦ a x + shift` (a point x of the image
    /// shows the pattern at a⁻¹(x − shift)).
    fn speckle_image(size: usize, a: [[f64; 2]; 2], shift: [f64; 2]) -> GrayImage {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let spots: Vec<[f64; 2]> = (0..size * size / 12)
            .map(|_| [uniform() * size as f64, uniform() * size as f64])
            .collect();
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        let mut pixels = vec![0.1; size * size];
        for (i, pixel) in pixels.iter_mut().enumerate() {
            let (x, y) = ((i % size) as f64 - shift[0], (i / size) as f64 - shift[1]);
            let px = (a[1][1] * x - a[0][1] * y) / det;
            let py = (a[0][0] * y - a[1][0] * x) / det;
            for s in spots.iter().filter(|s| (s[0] - px).abs() < 6.0) {
                let r2 = (s[0] - px).powi(2) + (s[1] - py).powi(2);
                *pixel += 0.5 * (-r2 / 4.0).exp();
            }
        }
        GrayImage::new(size, size, pixels).unwrap()
    }

    #[test]
    fn widest_and_baseline_give_identical_bits() {
        let a = [[1.03, 0.01], [-0.02, 0.98]];
        let reference = ReferenceFrame::new(speckle_image(96, [[1.0, 0.0], [0.0, 1.0]], [0.0; 2]));
        let target = BSplineImage::new(&speckle_image(96, a, [0.37, -0.41]));
        let settings = IcgnSettings {
            subset_px: 21,
            max_iterations: 30,
            convergence_px: 1e-6,
        };
        let mut solved = 0;
        for (x0, y0) in [(40, 40), (48, 37), (55, 58), (36, 60)] {
            let [widest, baseline] =
                [InstructionSet::Widest, InstructionSet::Baseline].map(|set| {
                    let subset = prepare_subset(set, &reference, (x0, y0), 10).unwrap();
                    // Where the imposed map sends the centre, rounded off by a pixel.
                    let (cx, cy) = (x0 as f64, y0 as f64);
                    let u = a[0][0] * cx + a[0][1] * cy + 0.37 - cx;
                    let v = a[1][0] * cx + a[1][1] * cy - 0.41 - cy;
                    let guess = Warp::translation((u + 0.6).round(), (v - 0.7).round());
                    solve(set, &subset, &target, guess, &settings)
                });
            let bits = |m: &Match| {
                let w = m.warp;
                [w.u, w.ux, w.uy, w.v, w.vx, w.vy, m.zncc].map(f64::to_bits)
            };
            assert_eq!(bits(&widest), bits(&baseline), "POI ({x0}, {y0})");
            assert_eq!(widest.iterations, baseline.iterations);
            // The comparison is of real matches: the imposed gradient found.
            assert!(widest.converged && widest.zncc > 0.999, "{widest:?}");
            let g = widest.warp.gradient();
            assert!((g[0][0] - a[0][0]).abs() < 1e-3 && (g[1][0] - a[1][0]).abs() < 1e-3);
            solved += 1;
        }
        assert_eq!(solved, 4);
    }
}
