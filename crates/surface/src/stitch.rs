//! Stitching interferometer tiles into one map.
//!
//! 1. Every pair of tiles whose nominal footprints overlap by at least
//!    `min_overlap_px` in both directions is registered by phase correlation
//!    on the overlap (`register.rs`), first at the nominal offset, then again
//!    on the overlap re-cut at the integer offset found, for the sub-pixel
//!    part.
//! 2. All pair offsets are solved together by least squares,
//!    min Σ (P_j − P_i − m_ij)², with the mean correction Σ (P_i − N_i) fixed
//!    at zero (the nominal positions are unbiased), so errors do not
//!    accumulate along a row of tiles.
//! 3. Levelling: each tile i gets a plane a_i + b_i·x + c_i·y (x, y about
//!    the tile centre) such that the differences of levelled heights in all
//!    overlaps are least squares, with the sums of a, b, c fixed at zero.
//! 4. Blending: each mosaic pixel is the weighted mean of the levelled tiles
//!    measuring it, weights falling linearly to the tile edges (feathering);
//!    NaN where no tile measured. Tiles are placed at their positions rounded
//!    to whole pixels: the map is resampled to the much coarser lateral
//!    resolution afterwards, and rounding avoids interpolating (smoothing)
//!    the measured heights. Blending is `blend.rs`'s, a row at a time.

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};
use ndarray::{Array2, ArrayView2, Slice};
use rayon::prelude::*;

use crate::blend::Placement;

use crate::error::SurfaceError;
use crate::register::{correlation, correlation_peaks, phase_correlate, refine_shift};
use crate::tiles::TileSet;

/// What stitching found for one tile.
#[derive(Clone, Debug, PartialEq)]
pub struct TileFit {
    pub nominal_px: [f64; 2],
    pub found_px: [f64; 2],
    /// Slope removed along x and y, m/m.
    pub tilt_rad: [f64; 2],
    /// Height removed at the tile centre, metres.
    pub piston_m: f64,
    /// Mean Pearson correlation of the tile's overlaps after alignment.
    pub correlation: f64,
    /// Overlaps of this tile dropped as outliers by the joint solution.
    pub pairs_rejected: usize,
}

/// The stitched map and what was found per tile.
#[derive(Clone, Debug)]
pub struct Mosaic {
    /// Heights, metres; NaN where no tile measured.
    pub heights: Array2<f64>,
    /// True where some tile's footprint covers the pixel.
    pub covered: Array2<bool>,
    pub tiles: Vec<TileFit>,
}

/// A registered pair of tiles: P_j − P_i = offset_px.
#[derive(Clone, Debug)]
struct PairFit {
    i: usize,
    j: usize,
    offset_px: [f64; 2],
    correlation: f64,
}

/// The overlap of tile i with tile j placed at offset d (integer pixels):
/// ranges in tile i's coordinates, or None if narrower than `min_px`.
fn overlap(n: (usize, usize), d: [i64; 2], min_px: usize) -> Option<[(usize, usize); 2]> {
    let size = [n.0 as i64, n.1 as i64];
    let mut out = [(0, 0); 2];
    for a in 0..2 {
        // Saturating: an offset near i64's ends (a tile placed absurdly
        // far) must mean no overlap, not wrap around into one.
        let lo = d[a].max(0);
        let hi = d[a].saturating_add(size[a]).min(size[a]);
        if hi.saturating_sub(lo) < min_px as i64 {
            return None;
        }
        out[a] = (lo as usize, hi as usize);
    }
    Some(out)
}

/// The overlap patches of tiles i and j at integer offset d, as views.
fn patches<'t>(
    a: ArrayView2<'t, f64>,
    b: ArrayView2<'t, f64>,
    d: [i64; 2],
    r: [(usize, usize); 2],
) -> (ArrayView2<'t, f64>, ArrayView2<'t, f64>) {
    let (mut pa, mut pb) = (a, b);
    pa.slice_each_axis_inplace(|axis| {
        let (lo, hi) = r[axis.axis.index()];
        Slice::from(lo..hi)
    });
    pb.slice_each_axis_inplace(|axis| {
        let k = axis.axis.index();
        let lo = (r[k].0 as i64 - d[k]) as usize;
        Slice::from(lo..lo + (r[k].1 - r[k].0))
    });
    (pa, pb)
}

/// Phase-correlation peaks tried per pair, each checked by the correlation
/// of the overlap it implies.
const PEAKS_TRIED: usize = 8;

/// Registers one pair starting from its nominal offset. The integer offset
/// is the candidate (from the highest phase-correlation peaks, each also
/// taken modulo the patch size) whose overlap correlates best; the sub-pixel
/// rest comes from phase correlation on the overlap re-cut at that offset.
fn register_pair(set: &TileSet, i: usize, j: usize, min_px: usize) -> Option<PairFit> {
    let (a, b) = (set.heights[i].view(), set.heights[j].view());
    let n = a.dim();
    let nominal = [
        (set.nominal_px[j][0] - set.nominal_px[i][0]).round() as i64,
        (set.nominal_px[j][1] - set.nominal_px[i][1]).round() as i64,
    ];
    let r0 = overlap(n, nominal, min_px)?;
    let (pa, pb) = patches(a, b, nominal, r0);
    let size = [pa.dim().0 as i64, pa.dim().1 as i64];
    let mut best: Option<([i64; 2], f64)> = None;
    for (e, _) in correlation_peaks(pa, pb, PEAKS_TRIED) {
        for ex in [e[0], e[0] - size[0], e[0] + size[0]] {
            for ey in [e[1], e[1] - size[1], e[1] + size[1]] {
                let d = [nominal[0] + ex, nominal[1] + ey];
                let Some(r) = overlap(n, d, min_px) else {
                    continue;
                };
                let (qa, qb) = patches(a, b, d, r);
                let c = correlation(qa, qb);
                if best.is_none_or(|(_, b)| c > b) {
                    best = Some((d, c));
                }
            }
        }
    }
    let (mut d, _) = best?;
    // Sub-pixel rest on the overlap re-cut at d; a rest beyond half a pixel
    // moves d and is refined again.
    let mut rest = None;
    for _ in 0..3 {
        let r = overlap(n, d, min_px)?;
        let (pa, pb) = patches(a, b, d, r);
        let e = refine_shift(pa, pb, [0.0, 0.0])
            .or_else(|| phase_correlate(pa, pb).map(|f| f.shift_px))?;
        let whole = e.map(|v| v.round() as i64);
        if whole == [0, 0] {
            rest = Some((e, correlation(pa, pb)));
            break;
        }
        d = [d[0] + whole[0], d[1] + whole[1]];
    }
    let (e, correlation) = rest?;
    let offset_px = [d[0] as f64 + e[0], d[1] as f64 + e[1]];
    Some(PairFit {
        i,
        j,
        offset_px,
        correlation,
    })
}

/// A pair whose registered offset differs from the joint least-squares
/// solution by more than this (pixels, either axis) is an outlier — a
/// featureless or repetitive overlap that locked onto a wrong peak — and is
/// dropped while the tiles stay connected. Correct pairs agree to a few
/// hundredths of a pixel.
const MAX_PAIR_RESIDUAL_PX: f64 = 0.5;

/// Whether the pairs connect all n tiles.
fn connected(n: usize, pairs: &[(usize, usize)]) -> bool {
    first_unconnected(n, pairs).is_none()
}

/// The first tile not joined to tile 0 by the pairs (union–find), if any.
fn first_unconnected(n: usize, pairs: &[(usize, usize)]) -> Option<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for &(i, j) in pairs {
        let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
        parent[ri] = rj;
    }
    let r0 = root(&mut parent, 0);
    (0..n).find(|&t| root(&mut parent, t) != r0)
}

/// Checks every tile overlaps another and all are connected.
fn check_graph(set: &TileSet, pairs: &[(usize, usize)], min_px: usize) -> Result<(), SurfaceError> {
    let n = set.heights.len();
    let mut degree = vec![0; n];
    for &(i, j) in pairs {
        degree[i] += 1;
        degree[j] += 1;
    }
    if let Some(t) = (0..n).find(|&t| degree[t] == 0) {
        return Err(SurfaceError::NoOverlap {
            file: set.names[t].clone(),
            min_px,
        });
    }
    if let Some(t) = first_unconnected(n, pairs) {
        return Err(SurfaceError::Disconnected {
            file: set.names[t].clone(),
            first: set.names[0].clone(),
        });
    }
    Ok(())
}

/// Least-squares positions from pair offsets, mean correction zero.
fn solve_positions(nominal_px: &[[f64; 2]], fits: &[PairFit]) -> Option<Vec<[f64; 2]>> {
    let n = nominal_px.len();
    let mut out = vec![[0.0; 2]; n];
    for a in 0..2 {
        // Normal equations of Σ (P_j − P_i − m)² + (Σ (P_k − N_k))².
        let mut m = DMatrix::from_element(n, n, 1.0);
        let sum_nominal: f64 = nominal_px.iter().map(|p| p[a]).sum();
        let mut r = DVector::from_element(n, sum_nominal);
        for f in fits {
            m[(f.i, f.i)] += 1.0;
            m[(f.j, f.j)] += 1.0;
            m[(f.i, f.j)] -= 1.0;
            m[(f.j, f.i)] -= 1.0;
            r[f.i] -= f.offset_px[a];
            r[f.j] += f.offset_px[a];
        }
        let p = m.lu().solve(&r)?;
        for (o, v) in out.iter_mut().zip(p.iter()) {
            o[a] = *v;
        }
    }
    Some(out)
}

/// Least-squares positions with outliers removed: the pair that least
/// agrees with the joint solution goes, as long as it is off by more than
/// `MAX_PAIR_RESIDUAL_PX` and the tiles stay connected without it; then the
/// rest is solved again. Returns the positions and, per tile, how many of its
/// pairs were dropped (`fits` keeps the pairs used).
fn solve_robust(
    nominal_px: &[[f64; 2]],
    fits: &mut Vec<PairFit>,
) -> Option<(Vec<[f64; 2]>, Vec<usize>)> {
    let n = nominal_px.len();
    let mut rejected = vec![0usize; n];
    loop {
        let found = solve_positions(nominal_px, fits)?;
        let residual = |f: &PairFit| {
            (0..2)
                .map(|a| (found[f.j][a] - found[f.i][a] - f.offset_px[a]).abs())
                .fold(0.0, f64::max)
        };
        let Some((worst, r)) = fits
            .iter()
            .enumerate()
            .map(|(k, f)| (k, residual(f)))
            .max_by(|x, y| x.1.total_cmp(&y.1))
        else {
            return Some((found, rejected));
        };
        let rest: Vec<(usize, usize)> = (0..fits.len())
            .filter(|&k| k != worst)
            .map(|k| (fits[k].i, fits[k].j))
            .collect();
        if r <= MAX_PAIR_RESIDUAL_PX || !connected(n, &rest) {
            return Some((found, rejected));
        }
        let dropped = fits.remove(worst);
        rejected[dropped.i] += 1;
        rejected[dropped.j] += 1;
    }
}

/// Per-tile planes (a, b, c) in metres and metres per pixel about the centre.
fn level(set: &TileSet, fits: &[PairFit], positions: &[[i64; 2]]) -> Option<Vec<[f64; 3]>> {
    let n = set.heights.len();
    let (sx, sy) = set.heights[0].dim();
    let (cx, cy) = ((sx as f64 - 1.0) / 2.0, (sy as f64 - 1.0) / 2.0);
    let dim = 3 * n;
    // Coordinates scaled by the tile size keep the system well conditioned.
    let scale = sx.max(sy) as f64;
    let sums: Vec<(Matrix6<f64>, Vector6<f64>)> = fits
        .par_iter()
        .map(|f| {
            let mut m = Matrix6::zeros();
            let mut r = Vector6::zeros();
            let d = [
                positions[f.j][0] - positions[f.i][0],
                positions[f.j][1] - positions[f.i][1],
            ];
            let Some(range) = overlap((sx, sy), d, 1) else {
                return (m, r);
            };
            let (a, b) = (&set.heights[f.i], &set.heights[f.j]);
            let count = (range[0].1 - range[0].0) * (range[1].1 - range[1].0);
            let stride = ((count as f64 / 40_000.0).sqrt().ceil() as usize).max(1);
            for u in (range[0].0..range[0].1).step_by(stride) {
                for v in (range[1].0..range[1].1).step_by(stride) {
                    let (ub, vb) = ((u as i64 - d[0]) as usize, (v as i64 - d[1]) as usize);
                    let (ha, hb) = (a[[u, v]], b[[ub, vb]]);
                    if ha.is_nan() || hb.is_nan() {
                        continue;
                    }
                    // ha − hb = plane_i(u, v) − plane_j(ub, vb).
                    let basis = Vector6::new(
                        1.0,
                        (u as f64 - cx) / scale,
                        (v as f64 - cy) / scale,
                        -1.0,
                        -(ub as f64 - cx) / scale,
                        -(vb as f64 - cy) / scale,
                    );
                    r += basis * (ha - hb);
                    m += basis * basis.transpose();
                }
            }
            (m, r)
        })
        .collect();
    let mut m = DMatrix::zeros(dim, dim);
    let mut r = DVector::zeros(dim);
    for (f, (pm, pr)) in fits.iter().zip(&sums) {
        let index = |k: usize| if k < 3 { 3 * f.i + k } else { 3 * f.j + k - 3 };
        for p in 0..6 {
            r[index(p)] += pr[p];
            for q in 0..6 {
                m[(index(p), index(q))] += pm[(p, q)];
            }
        }
    }
    // Gauge: Σ a = Σ b = Σ c = 0, weighted like a typical overlap.
    let weight = m.trace() / dim as f64;
    for k in 0..3 {
        for i in 0..n {
            for j in 0..n {
                m[(3 * i + k, 3 * j + k)] += weight;
            }
        }
    }
    let x = m.lu().solve(&r)?;
    Some(
        (0..n)
            .map(|i| [x[3 * i], x[3 * i + 1] / scale, x[3 * i + 2] / scale])
            .collect(),
    )
}

/// Stitches a tile set. A single tile is returned as it is.
pub fn stitch(set: &TileSet, min_overlap_px: usize) -> Result<Mosaic, SurfaceError> {
    let (placement, tiles) = place(set, min_overlap_px)?;
    Ok(Mosaic {
        heights: placement.mosaic(set),
        covered: placement.covered(),
        tiles,
    })
}

/// Steps 1–3 of stitching: where each tile goes and the plane it loses
/// (blending them is [`Placement`]'s), and what was found per tile.
pub fn place(
    set: &TileSet,
    min_overlap_px: usize,
) -> Result<(Placement, Vec<TileFit>), SurfaceError> {
    let n = set.heights.len();
    let candidates = overlapping_pairs(set, min_overlap_px);
    if n > 1 {
        check_graph(set, &candidates, min_overlap_px)?;
    }
    let mut fits: Vec<PairFit> = candidates
        .par_iter()
        .filter_map(|&(i, j)| register_pair(set, i, j, min_overlap_px))
        .collect();
    let (found, rejected) = if n > 1 {
        let pairs: Vec<(usize, usize)> = fits.iter().map(|f| (f.i, f.j)).collect();
        check_graph(set, &pairs, min_overlap_px)?;
        solve_robust(&set.nominal_px, &mut fits).ok_or_else(|| {
            SurfaceError::Input("tile positions: the least-squares system is singular".into())
        })?
    } else {
        (set.nominal_px.clone(), vec![0])
    };
    let rounded: Vec<[i64; 2]> = found
        .iter()
        .map(|p| [p[0].round() as i64, p[1].round() as i64])
        .collect();
    let planes = if n > 1 {
        level(set, &fits, &rounded).ok_or_else(|| {
            SurfaceError::Input("tile levelling: the least-squares system is singular".into())
        })?
    } else {
        vec![[0.0; 3]]
    };
    let tiles = tile_fits(set, &fits, &found, &planes, &rejected);
    Ok((
        Placement::new(&rounded, planes, set.heights[0].dim()),
        tiles,
    ))
}

/// The pairs (i < j) whose nominal footprints overlap by `min_px` both ways.
fn overlapping_pairs(set: &TileSet, min_px: usize) -> Vec<(usize, usize)> {
    let n = set.heights.len();
    let (sx, sy) = set.heights[0].dim();
    (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
        .filter(|&(i, j)| {
            let d = [
                (set.nominal_px[j][0] - set.nominal_px[i][0]).round() as i64,
                (set.nominal_px[j][1] - set.nominal_px[i][1]).round() as i64,
            ];
            overlap((sx, sy), d, min_px).is_some()
        })
        .collect()
}

/// What was found per tile: position, plane, mean overlap correlation and
/// pairs dropped.
fn tile_fits(
    set: &TileSet,
    fits: &[PairFit],
    found: &[[f64; 2]],
    planes: &[[f64; 3]],
    rejected: &[usize],
) -> Vec<TileFit> {
    let n = set.heights.len();
    let mut correlation_sum = vec![(0.0, 0usize); n];
    for f in fits {
        for t in [f.i, f.j] {
            correlation_sum[t].0 += f.correlation;
            correlation_sum[t].1 += 1;
        }
    }
    let pixel_m = set.pixel_m;
    (0..n)
        .map(|t| TileFit {
            nominal_px: set.nominal_px[t],
            found_px: found[t],
            tilt_rad: [planes[t][1] / pixel_m, planes[t][2] / pixel_m],
            piston_m: planes[t][0],
            correlation: match correlation_sum[t] {
                (_, 0) => f64::NAN,
                (s, k) => s / k as f64,
            },
            pairs_rejected: rejected[t],
        })
        .collect()
}

/// The largest region, found by peeling border lines, every pixel of which
/// lies in some tile's footprint: ranges along x and y.
pub fn covered_region(covered: &Array2<bool>) -> [(usize, usize); 2] {
    let (nx, ny) = covered.dim();
    let (mut x0, mut x1, mut y0, mut y1) = (0, nx, 0, ny);
    while x1 > x0 + 1 && y1 > y0 + 1 {
        let holes = [
            (y0..y1).filter(|&y| !covered[[x0, y]]).count(),
            (y0..y1).filter(|&y| !covered[[x1 - 1, y]]).count(),
            (x0..x1).filter(|&x| !covered[[x, y0]]).count(),
            (x0..x1).filter(|&x| !covered[[x, y1 - 1]]).count(),
        ];
        let (worst, &count) = holes
            .iter()
            .enumerate()
            .max_by_key(|(_, c)| **c)
            .expect("four sides");
        if count == 0 {
            break;
        }
        match worst {
            0 => x0 += 1,
            1 => x1 -= 1,
            2 => y0 += 1,
            _ => y1 -= 1,
        }
    }
    [(x0, x1), (y0, y1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wrong_pair_is_dropped_and_the_rest_solved_exactly() {
        // 2 × 2 tiles, 100 px apart nominally, each missed by a known error;
        // all six pairs registered, the 0–3 diagonal locked onto a wrong
        // peak 7 px off.
        let nominal = [[0.0, 0.0], [100.0, 0.0], [0.0, 100.0], [100.0, 100.0]];
        let error = [[0.3, -1.2], [2.0, 0.5], [-1.1, 0.0], [0.4, 2.2]];
        let truth: Vec<[f64; 2]> = (0..4)
            .map(|t| [nominal[t][0] + error[t][0], nominal[t][1] + error[t][1]])
            .collect();
        let mut fits: Vec<PairFit> = [(0, 1), (0, 2), (1, 3), (2, 3), (0, 3), (1, 2)]
            .into_iter()
            .map(|(i, j)| PairFit {
                i,
                j,
                offset_px: [truth[j][0] - truth[i][0], truth[j][1] - truth[i][1]],
                correlation: 1.0,
            })
            .collect();
        fits[4].offset_px[0] += 7.0;
        let (found, rejected) = solve_robust(&nominal, &mut fits).unwrap();
        assert_eq!(rejected, [1, 0, 0, 1]);
        assert_eq!(fits.len(), 5);
        // Up to the gauge (mean correction zero), exactly the truth.
        let mean_error = [0, 1].map(|a| error.iter().map(|e| e[a]).sum::<f64>() / 4.0);
        for t in 0..4 {
            for a in 0..2 {
                let expected = truth[t][a] - mean_error[a];
                assert!((found[t][a] - expected).abs() < 1e-9, "tile {t}: {found:?}");
            }
        }
        // Without the rejection the wrong pair would pull every tile.
        let plain = solve_positions(
            &nominal,
            &[
                fits.clone(),
                vec![{
                    let mut f = fits[0].clone();
                    f.j = 3;
                    f.offset_px = [truth[3][0] - truth[0][0] + 7.0, truth[3][1] - truth[0][1]];
                    f
                }],
            ]
            .concat(),
        )
        .unwrap();
        assert!((plain[3][0] - (truth[3][0] - mean_error[0])).abs() > 1.0);
    }

    #[test]
    fn offsets_at_the_ends_of_i64_overlap_nothing() {
        for d in [i64::MAX, i64::MIN, i64::MAX - 10, i64::MIN + 10] {
            assert_eq!(overlap((40, 40), [d, 0], 16), None, "{d}");
            assert_eq!(overlap((40, 40), [0, d], 16), None, "{d}");
        }
    }

    #[test]
    fn overlap_ranges() {
        assert_eq!(overlap((10, 10), [7, 0], 2), Some([(7, 10), (0, 10)]));
        assert_eq!(overlap((10, 10), [-7, 2], 2), Some([(0, 3), (2, 10)]));
        assert_eq!(overlap((10, 10), [9, 0], 2), None);
    }

    #[test]
    fn peels_uncovered_borders() {
        let mut c = Array2::from_elem((10, 12), true);
        for y in 0..12 {
            c[[0, y]] = y > 3;
        }
        c[[9, 11]] = false;
        let r = covered_region(&c);
        assert_eq!(r[0].0, 1);
        assert!(r[0].1 == 9 || r[1].1 == 11);
    }
}
