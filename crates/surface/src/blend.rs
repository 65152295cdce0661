//! Step 4 of stitching ([`crate::stitch`]): feathered blending. Each mosaic
//! pixel is the weighted mean of the levelled tiles measuring it, weights
//! falling linearly to the tile edges, NaN where none measured; tiles stand
//! at whole pixels.
//!
//! A mosaic row depends only on the tiles crossing it, so rows are made
//! when asked for: [`StitchedRows`] hands a region of the mosaic to the
//! filter a row at a time, and a paper-scale mosaic (8844² points, 0.6 GB)
//! is never held whole (#35). [`Placement::mosaic`] makes the whole map
//! from the same rows.

use std::ops::Range;

use ndarray::Array2;
use rayon::prelude::*;

use crate::filter::MapRows;
use crate::tiles::TileSet;

/// Where each levelled tile goes in the mosaic.
#[derive(Clone, Debug)]
pub struct Placement {
    /// Each tile's pixel [0, 0] in the mosaic (the top-left tile at 0).
    corners_px: Vec<[usize; 2]>,
    /// Each tile's plane (a, b, c): metres, metres per pixel about its centre.
    planes: Vec<[f64; 3]>,
    /// Points of a tile along x and y.
    tile_dim: (usize, usize),
    /// Points of the mosaic along x and y.
    dim: (usize, usize),
}

impl Placement {
    /// Tiles of `tile_dim` points at whole-pixel positions `rounded`
    /// (pixels, any origin; at least one tile), each less its plane.
    pub fn new(rounded: &[[i64; 2]], planes: Vec<[f64; 3]>, tile_dim: (usize, usize)) -> Self {
        let origin = [0, 1].map(|a| rounded.iter().map(|p| p[a]).min().unwrap_or(0));
        let corners_px: Vec<[usize; 2]> = rounded
            .iter()
            .map(|p| [(p[0] - origin[0]) as usize, (p[1] - origin[1]) as usize])
            .collect();
        let dim = [0, 1].map(|a| {
            corners_px
                .iter()
                .map(|c| c[a] + [tile_dim.0, tile_dim.1][a])
                .max()
                .unwrap_or(0)
        });
        Self {
            corners_px,
            planes,
            tile_dim,
            dim: (dim[0], dim[1]),
        }
    }

    /// Points of the mosaic along x and y.
    pub fn dim(&self) -> (usize, usize) {
        self.dim
    }

    /// True where some tile's footprint covers the mosaic pixel.
    pub fn covered(&self) -> Array2<bool> {
        let mut covered = Array2::from_elem(self.dim, false);
        let (sx, sy) = self.tile_dim;
        for c in &self.corners_px {
            for x in c[0]..c[0] + sx {
                covered
                    .row_mut(x)
                    .iter_mut()
                    .skip(c[1])
                    .take(sy)
                    .for_each(|v| *v = true);
            }
        }
        covered
    }

    /// Mosaic row `x` over the mosaic's `columns`, written into `row` (one
    /// value per column).
    pub fn blend_row(&self, set: &TileSet, x: usize, columns: Range<usize>, row: &mut [f64]) {
        let (sx, sy) = self.tile_dim;
        let (cx, cy) = ((sx as f64 - 1.0) / 2.0, (sy as f64 - 1.0) / 2.0);
        let feather = |u: usize, n: usize| (u.min(n - 1 - u) + 1) as f64;
        // `row` gathers Σ w·h, `weight_sum` Σ w, over the tiles in order.
        row.fill(0.0);
        let mut weight_sum = vec![0.0; row.len()];
        for (t, corner) in self.corners_px.iter().enumerate() {
            if x < corner[0] || x >= corner[0] + sx {
                continue;
            }
            let u = x - corner[0];
            let v_range = columns.start.saturating_sub(corner[1])
                ..columns.end.saturating_sub(corner[1]).min(sy);
            let [a, b, c] = self.planes[t];
            let tile_row = set.heights[t].row(u);
            for v in v_range {
                let h = tile_row[v];
                if h.is_nan() {
                    continue;
                }
                let w = feather(u, sx).min(feather(v, sy));
                let levelled = h - (a + b * (u as f64 - cx) + c * (v as f64 - cy));
                let k = corner[1] + v - columns.start;
                row[k] += w * levelled;
                weight_sum[k] += w;
            }
        }
        for (o, d) in row.iter_mut().zip(weight_sum) {
            *o = if d > 0.0 { *o / d } else { f64::NAN };
        }
    }

    /// The whole mosaic.
    pub fn mosaic(&self, set: &TileSet) -> Array2<f64> {
        let (mx, my) = self.dim;
        let mut heights = Array2::<f64>::zeros((mx, my));
        heights
            .as_slice_mut()
            .expect("a fresh array is contiguous")
            .par_chunks_mut(my)
            .enumerate()
            .for_each(|(x, row)| self.blend_row(set, x, 0..my, row));
        heights
    }
}

/// A region of a mosaic, made a row at a time: ranges along x and y.
pub struct StitchedRows<'s, 'a> {
    pub set: &'s TileSet<'a>,
    pub placement: &'s Placement,
    pub region: [(usize, usize); 2],
}

impl MapRows for StitchedRows<'_, '_> {
    fn dim(&self) -> (usize, usize) {
        let [(x0, x1), (y0, y1)] = self.region;
        (x1 - x0, y1 - y0)
    }

    fn write_row(&self, x: usize, row: &mut [f64]) {
        let [(x0, _), (y0, y1)] = self.region;
        self.placement.blend_row(self.set, x0 + x, y0..y1, row);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::CowArray;

    /// Three 5 × 4 tiles, one with holes, overlapping unevenly.
    fn three_tiles() -> (TileSet<'static>, Placement) {
        let tile = |seed: f64| {
            Array2::from_shape_fn((5, 4), |(i, j)| {
                let v = (seed + 1.3 * i as f64 + 0.7 * j as f64).sin();
                if (i + j) % 7 == 3 { f64::NAN } else { v }
            })
        };
        let set = TileSet {
            ids: vec![0, 1, 2],
            names: vec!["a".into(), "b".into(), "c".into()],
            heights: [0.1, 2.0, 4.0]
                .map(|s| CowArray::from(tile(s)))
                .into_iter()
                .collect(),
            nominal_px: vec![[0.0; 2]; 3],
            pixel_m: 1.0,
        };
        let planes = vec![[0.1, 0.01, -0.02], [-0.05, 0.0, 0.03], [0.0, -0.01, 0.0]];
        let placement = Placement::new(&[[-2, 1], [1, 0], [2, 4]], planes, (5, 4));
        (set, placement)
    }

    #[test]
    fn a_region_made_a_row_at_a_time_has_the_bits_of_the_whole_mosaic() {
        let (set, placement) = three_tiles();
        assert_eq!(placement.dim(), (9, 8));
        let whole = placement.mosaic(&set);
        let region = [(1, 8), (2, 7)];
        let rows = StitchedRows {
            set: &set,
            placement: &placement,
            region,
        };
        assert_eq!(rows.dim(), (7, 5));
        let mut row = vec![0.0; 5];
        for x in 0..7 {
            rows.write_row(x, &mut row);
            for (y, v) in row.iter().enumerate() {
                assert_eq!(v.to_bits(), whole[[x + 1, y + 2]].to_bits(), "[{x}, {y}]");
            }
        }
    }

    /// The blend as stitch.rs did it before rows were made on demand: the
    /// whole mosaic at once, each row over its full width (#35 keeps its bits).
    fn whole_row_blend(set: &TileSet, rounded: &[[i64; 2]], planes: &[[f64; 3]]) -> Array2<f64> {
        let (sx, sy) = set.heights[0].dim();
        let origin = [0, 1].map(|a| rounded.iter().map(|p| p[a]).min().unwrap());
        let end = [0, 1].map(|a| {
            rounded
                .iter()
                .map(|p| p[a] + [sx, sy][a] as i64)
                .max()
                .unwrap()
        });
        let (mx, my) = ((end[0] - origin[0]) as usize, (end[1] - origin[1]) as usize);
        let (cx, cy) = ((sx as f64 - 1.0) / 2.0, (sy as f64 - 1.0) / 2.0);
        let feather = |u: usize, n: usize| (u.min(n - 1 - u) + 1) as f64;
        Array2::from_shape_fn((mx, my), |(x, y)| {
            let (mut num, mut den) = (0.0, 0.0);
            for (t, p) in rounded.iter().enumerate() {
                let (u, v) = (x as i64 + origin[0] - p[0], y as i64 + origin[1] - p[1]);
                if u < 0 || u >= sx as i64 || v < 0 || v >= sy as i64 {
                    continue;
                }
                let (u, v) = (u as usize, v as usize);
                let h = set.heights[t][[u, v]];
                if h.is_nan() {
                    continue;
                }
                let [a, b, c] = planes[t];
                let w = feather(u, sx).min(feather(v, sy));
                num += w * (h - (a + b * (u as f64 - cx) + c * (v as f64 - cy)));
                den += w;
            }
            if den > 0.0 { num / den } else { f64::NAN }
        })
    }

    #[test]
    fn the_mosaic_has_the_bits_of_the_whole_row_blend() {
        let (set, placement) = three_tiles();
        let reference = whole_row_blend(&set, &[[-2, 1], [1, 0], [2, 4]], &placement.planes);
        let whole = placement.mosaic(&set);
        assert_eq!(whole.dim(), reference.dim());
        for (v, r) in whole.iter().zip(&reference) {
            assert_eq!(v.to_bits(), r.to_bits());
        }
        assert!(whole.iter().any(|v| v.is_nan()) && whole.iter().any(|v| !v.is_nan()));
    }

    #[test]
    fn blends_levelled_tiles_by_their_feather_weights() {
        let (set, placement) = three_tiles();
        let whole = placement.mosaic(&set);
        // Mosaic pixel [4, 3]: tile 0 (corner [0, 1]) at [4, 2], weight
        // min(1, 2); tile 1 (corner [3, 0]) at [1, 3], weight min(2, 1);
        // tile 2 (corner [4, 4]) misses it.
        let level = |t: usize, u: usize, v: usize| {
            let [a, b, c] = placement.planes[t];
            set.heights[t][[u, v]] - (a + b * (u as f64 - 2.0) + c * (v as f64 - 1.5))
        };
        let expected = (level(0, 4, 2) + level(1, 1, 3)) / 2.0;
        assert!(
            (whole[[4, 3]] - expected).abs() < 1e-15,
            "{}",
            whole[[4, 3]]
        );
        // [3, 3] is a hole of tile 1 ([0, 3]) that tile 0 measured ([3, 2]).
        assert!(!whole[[3, 3]].is_nan());
        let covered = placement.covered();
        assert!(whole[[8, 0]].is_nan() && !covered[[8, 0]]);
        assert!(covered[[3, 3]] && covered[[8, 7]] && !covered[[0, 0]]);
    }
}
