//! Subset DIC over a sequence: every POI of frame 0 is followed through all
//! frames, which accumulates its deformation across reference updates.
//!
//! Per frame: IC-GN (first-order shape function) for every POI, in parallel
//! (rayon), each starting from its own motion extrapolated from the two
//! previous frames; POIs that fail, and all of them in the first frame, are
//! reached by reliability-guided propagation (Pan, "Reliability-guided
//! digital image correlation for image deformation measurement", Appl. Opt.
//! 48, 2009): a seed's integer guess comes from FFT ZNCC, then neighbours
//! start from the best-correlated solved POI. Large deformation uses
//! incremental reference updating: when the deformation since the reference
//! frame exceeds `update_strain`, the current frame becomes the reference; a
//! POI's subset is then centred on the pixel nearest its tracked position,
//! and its position and local gradient compose as x_k = q + A (x_r − p),
//! F_k = A F_r, so the deformation relative to frame 0 accumulates.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use crate::DicError;
use crate::bspline::BSplineImage;
use crate::gray::GrayImage;
use crate::icgn::{IcgnSettings, Match, ReferenceFrame, ReferenceSubset, Warp};
use crate::poi_grid::PoiGrid;
use crate::strain::{IDENTITY, Mat2, affine_fit, mat_inv, mat_mul, principal_stretches};
use crate::zncc_fft::integer_search;

/// Controls of the subset method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubsetSettings {
    pub icgn: IcgnSettings,
    /// A POI whose final ZNCC is lower is marked invalid.
    pub min_zncc: f64,
    /// Update the reference when a principal stretch since the reference
    /// frame departs from 1 by more than this.
    pub update_strain: f64,
    /// Half-width of the FFT search window for seed points, pixels.
    pub search_px: usize,
}

/// One POI's latest state.
#[derive(Clone, Copy, Debug)]
struct PoiState {
    position: [f64; 2],
    gradient: Mat2,
    /// The state one frame earlier, for extrapolating the motion.
    previous: Option<([f64; 2], Mat2)>,
    valid: bool,
}

/// Follows the POIs of a grid through a sequence.
pub struct SubsetTracker {
    settings: SubsetSettings,
    grid: PoiGrid,
    /// The reference frame with its spline gradients, built once per
    /// reference update and shared by every POI's subset.
    reference: ReferenceFrame,
    /// Frame index of the current reference.
    pub reference_frame: usize,
    /// Position and local gradient of each POI in the reference frame.
    reference_state: Vec<Option<([f64; 2], Mat2)>>,
    state: Vec<PoiState>,
    frames_done: usize,
}

/// The result of one frame.
#[derive(Clone, Debug)]
pub struct FrameTrack {
    /// Current position of each POI, None if invalid in this frame.
    pub positions: Vec<Option<[f64; 2]>>,
    /// Final ZNCC per POI (NaN if invalid).
    pub zncc: Vec<f64>,
}

impl SubsetTracker {
    /// A tracker of the grid's active POIs (inactive ones, outside the
    /// region, are never tracked).
    pub fn new(settings: SubsetSettings, grid: PoiGrid, frame0: GrayImage) -> Self {
        let reference_state = grid
            .points
            .iter()
            .zip(&grid.active)
            .map(|(&p, &active)| active.then_some((p, IDENTITY)))
            .collect();
        let state = grid
            .points
            .iter()
            .zip(&grid.active)
            .map(|(&p, &active)| PoiState {
                position: p,
                gradient: IDENTITY,
                previous: None,
                valid: active,
            })
            .collect();
        Self {
            settings,
            grid,
            reference: ReferenceFrame::new(frame0),
            reference_frame: 0,
            reference_state,
            state,
            frames_done: 0,
        }
    }

    pub fn grid(&self) -> &PoiGrid {
        &self.grid
    }

    /// The reference subset of POI `i` and its centre pixel, if it fits.
    fn subset(&self, i: usize) -> Option<(ReferenceSubset<'_>, [f64; 2], Mat2)> {
        let (position, gradient) = self.reference_state[i]?;
        let (px, py) = (position[0].round(), position[1].round());
        if px < 0.0 || py < 0.0 {
            return None;
        }
        let half = self.settings.icgn.subset_px / 2;
        let subset = self.reference.subset(px as usize, py as usize, half)?;
        Some((subset, position, gradient))
    }

    fn accept(&self, m: &Match) -> bool {
        m.converged && m.zncc.is_finite() && m.zncc >= self.settings.min_zncc
    }

    /// Tracks the POIs into `target` (frame `frame`, file `file` for errors).
    pub fn track(
        &mut self,
        target: GrayImage,
        frame: usize,
        file: &str,
    ) -> Result<FrameTrack, DicError> {
        let reference = self.reference.image();
        if (target.width, target.height) != (reference.width, reference.height) {
            return Err(DicError::SizeMismatch {
                frame,
                file: file.to_owned(),
                width: target.width,
                height: target.height,
                width0: reference.width,
                height0: reference.height,
            });
        }
        let spline = BSplineImage::new(&target);
        let mut results = if self.frames_done == 0 {
            vec![None; self.grid.len()]
        } else {
            self.extrapolated_matches(&spline)
        };
        let mut attempted: Vec<bool> = results.iter().map(Option::is_some).collect();
        if results.iter().any(Option::is_some) {
            self.propagate(&spline, &mut results, &mut attempted);
        }
        // The first frame, a frame where every POI was lost, and parts of
        // the region the propagation did not reach (cut off by a hole).
        self.seed_and_propagate(&target, &spline, &mut results, &mut attempted);
        if results.iter().all(Option::is_none) {
            return Err(DicError::Lost {
                frame,
                file: file.to_owned(),
                reason: format!(
                    "no subset reached ZNCC ≥ {} within {} iterations (check the frame order, \
                     `search_px`, `subset_px` or `min_zncc`)",
                    self.settings.min_zncc, self.settings.icgn.max_iterations
                ),
            });
        }
        let track = self.advance(&results);
        self.update_reference(target, &spline, &track.positions, frame);
        Ok(track)
    }

    /// Every valid POI solved in parallel from its own motion extrapolated
    /// from the two previous frames; None where rejected.
    fn extrapolated_matches(&self, spline: &BSplineImage) -> Vec<Option<Match>> {
        (0..self.grid.len())
            .into_par_iter()
            .map(|i| {
                let s = self.state[i];
                if !s.valid {
                    return None;
                }
                let (subset, ref_position, ref_gradient) = self.subset(i)?;
                let (position, gradient) = match s.previous {
                    Some((p0, g0)) => (
                        [2.0 * s.position[0] - p0[0], 2.0 * s.position[1] - p0[1]],
                        extrapolate(&s.gradient, &g0),
                    ),
                    None => (s.position, s.gradient),
                };
                let guess = guess_warp(&subset, ref_position, &ref_gradient, position, &gradient)?;
                let m = subset.solve(spline, guess, &self.settings.icgn);
                self.accept(&m).then_some(m)
            })
            .collect()
    }

    /// The POIs' new states from this frame's matches,
    /// x_k = q + A (x_r − p), F_k = A F_r; unmatched POIs become invalid.
    fn advance(&mut self, results: &[Option<Match>]) -> FrameTrack {
        let n = self.grid.len();
        let mut positions = vec![None; n];
        let mut zncc = vec![f64::NAN; n];
        for i in 0..n {
            let old = self.state[i];
            let updated = match (results[i], self.reference_state[i]) {
                (Some(m), Some((ref_position, ref_gradient))) => {
                    let centre = [ref_position[0].round(), ref_position[1].round()];
                    let a = m.warp.gradient();
                    let d = [ref_position[0] - centre[0], ref_position[1] - centre[1]];
                    let position = [
                        centre[0] + m.warp.u + a[0][0] * d[0] + a[0][1] * d[1],
                        centre[1] + m.warp.v + a[1][0] * d[0] + a[1][1] * d[1],
                    ];
                    zncc[i] = m.zncc;
                    positions[i] = Some(position);
                    PoiState {
                        position,
                        gradient: mat_mul(&a, &ref_gradient),
                        previous: old.valid.then_some((old.position, old.gradient)),
                        valid: true,
                    }
                }
                _ => PoiState {
                    valid: false,
                    previous: None,
                    ..old
                },
            };
            self.state[i] = updated;
        }
        self.frames_done += 1;
        FrameTrack { positions, zncc }
    }

    /// Incremental reference updating: `target` (frame `frame`) becomes the
    /// reference when a principal stretch of the affine fit since the
    /// reference departs from 1 by more than `update_strain`.
    fn update_reference(
        &mut self,
        target: GrayImage,
        spline: &BSplineImage,
        positions: &[Option<[f64; 2]>],
        frame: usize,
    ) {
        let (from, to): (Vec<[f64; 2]>, Vec<[f64; 2]>) = (0..self.grid.len())
            .filter_map(|i| Some((self.reference_state[i]?.0, positions[i]?)))
            .unzip();
        if let Some((_, _, f)) = affine_fit(&from, &to) {
            let (l1, l2) = principal_stretches(&f);
            if (l1 - 1.0).abs().max((l2 - 1.0).abs()) > self.settings.update_strain {
                self.reference_state = self
                    .state
                    .iter()
                    .map(|s| s.valid.then_some((s.position, s.gradient)))
                    .collect();
                self.reference = ReferenceFrame::with_spline(target, spline);
                self.reference_frame = frame;
            }
        }
    }

    /// Reliability-guided propagation from the solved POIs to unsolved
    /// neighbours, best ZNCC first.
    fn propagate(
        &self,
        spline: &BSplineImage,
        results: &mut [Option<Match>],
        attempted: &mut [bool],
    ) {
        let mut queue: BinaryHeap<Ranked> = results
            .iter()
            .enumerate()
            .filter_map(|(i, m)| m.map(|m| Ranked(m.zncc, i)))
            .collect();
        while let Some(Ranked(_, i)) = queue.pop() {
            let Some(parent) = results[i] else { continue };
            let Some(parent_centre) =
                self.reference_state[i].map(|(p, _)| [p[0].round(), p[1].round()])
            else {
                continue;
            };
            let neighbours: Vec<usize> = self.grid.neighbours(i).collect();
            for j in neighbours {
                if attempted[j] {
                    continue;
                }
                attempted[j] = true;
                let Some((subset, _, _)) = self.subset(j) else {
                    continue;
                };
                let centre = [subset.x0 as f64, subset.y0 as f64];
                let (u, v) = parent
                    .warp
                    .apply(centre[0] - parent_centre[0], centre[1] - parent_centre[1]);
                let guess = Warp {
                    u: u - (centre[0] - parent_centre[0]),
                    v: v - (centre[1] - parent_centre[1]),
                    ..parent.warp
                };
                let m = subset.solve(spline, guess, &self.settings.icgn);
                if self.accept(&m) {
                    results[j] = Some(m);
                    queue.push(Ranked(m.zncc, j));
                }
            }
        }
    }

    /// Seeds the active POIs not yet attempted and propagates from them:
    /// up to `SEED_BLOCKS²` candidates spread over those POIs
    /// ([`PoiGrid::spread`]), each found by FFT ZNCC and refined by IC-GN
    /// (in parallel); every accepted seed enters the propagation queue,
    /// which takes the best ZNCC first. A region cut in parts, or a round
    /// whose candidates all fail (a hole, a glare), gets further rounds, at
    /// most `SEED_ROUNDS`.
    fn seed_and_propagate(
        &self,
        target: &GrayImage,
        spline: &BSplineImage,
        results: &mut [Option<Match>],
        attempted: &mut [bool],
    ) {
        const SEED_BLOCKS: usize = 4;
        const SEED_ROUNDS: usize = 3;
        for _ in 0..SEED_ROUNDS {
            let candidates = self.grid.spread(SEED_BLOCKS, |i| {
                !attempted[i] && self.reference_state[i].is_some()
            });
            if candidates.is_empty() {
                return;
            }
            let seeds: Vec<(usize, Option<Match>)> = candidates
                .par_iter()
                .map(|&i| (i, self.seed(i, target, spline)))
                .collect();
            for (i, m) in seeds {
                attempted[i] = true;
                results[i] = m;
            }
            self.propagate(spline, results, attempted);
        }
    }

    /// POI `seed` found by FFT ZNCC around where its own motion says it is
    /// (its frame-0 place if lost), refined by IC-GN; `None` if rejected.
    fn seed(&self, seed: usize, target: &GrayImage, spline: &BSplineImage) -> Option<Match> {
        let (subset, _, _) = self.subset(seed)?;
        let half = self.settings.icgn.subset_px / 2;
        let s = self.state[seed];
        let (cx, cy) = if s.valid {
            (s.position[0].round() as i64, s.position[1].round() as i64)
        } else {
            (subset.x0 as i64, subset.y0 as i64)
        };
        let hit = integer_search(
            self.reference.image(),
            subset.x0,
            subset.y0,
            half,
            target,
            cx,
            cy,
            self.settings.search_px,
        )?;
        let m = subset.solve(
            spline,
            Warp::translation(hit.dx as f64, hit.dy as f64),
            &self.settings.icgn,
        );
        self.accept(&m).then_some(m)
    }
}

/// The warp of reference subset `subset` (centred on pixel p) that sends
/// the tracked point from `ref_position` (local gradient `ref_gradient`)
/// to `position` (gradient `gradient`).
fn guess_warp(
    subset: &ReferenceSubset,
    ref_position: [f64; 2],
    ref_gradient: &Mat2,
    position: [f64; 2],
    gradient: &Mat2,
) -> Option<Warp> {
    let a = mat_mul(gradient, &mat_inv(ref_gradient)?);
    let p = [subset.x0 as f64, subset.y0 as f64];
    let d = [p[0] - ref_position[0], p[1] - ref_position[1]];
    let q = [
        position[0] + a[0][0] * d[0] + a[0][1] * d[1],
        position[1] + a[1][0] * d[0] + a[1][1] * d[1],
    ];
    Some(Warp::from_gradient(q[0] - p[0], q[1] - p[1], a))
}

/// 2 F_k − F_{k−1}: constant-rate extrapolation of the gradient.
fn extrapolate(current: &Mat2, previous: &Mat2) -> Mat2 {
    let mut out = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            out[i][j] = 2.0 * current[i][j] - previous[i][j];
        }
    }
    out
}

/// A POI ranked by its ZNCC for the propagation queue.
struct Ranked(f64, usize);

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Ranked {}
impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(other.1.cmp(&self.1))
    }
}
