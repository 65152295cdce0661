//! The two maps brought to a common pitch, and the predicted map sampled on
//! a turned, shifted camera-aligned grid.
//!
//! The camera's mask is area-averaged over square blocks of pixels into a
//! contact-fraction map on a camera-aligned grid; the predicted map is
//! box-averaged over blocks of scan points when the grid is coarser than
//! the scan. Block grids need not fill their map: the blocks start at the
//! first pixel and the leftover last row/column is dropped, so a block
//! grid's centre sits off the map's centre by half the leftover; both
//! structs keep that offset so every position stays in the coordinates of
//! `hypercontact_interference::geometry`.

use hypercontact_interference::{CameraGrid, GapMap, Placement, resample};
use ndarray::{Array2, ArrayView2};

use crate::error::CompareError;

/// The observed mask area-averaged over `block_px` × `block_px` pixels.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Blocks {
    pub block_px: usize,
    pub width: usize,
    pub height: usize,
    /// contact fraction, row-major `[y * width + x]`
    pub fraction: Vec<f64>,
    /// the block grid's centre from the frame's centre, camera pixels
    pub centre_px: [f64; 2],
}

/// Area average of a row-major mask over whole blocks (exact counts).
pub(crate) fn area_average(mask: &[bool], width: usize, height: usize, block_px: usize) -> Blocks {
    let b = block_px.max(1);
    let (bw, bh) = (width / b, height / b);
    let mut counts = vec![0u32; bw * bh];
    for y in 0..bh * b {
        let row = &mask[y * width..y * width + bw * b];
        let out = &mut counts[(y / b) * bw..(y / b + 1) * bw];
        for (x, &c) in row.iter().enumerate() {
            out[x / b] += u32::from(c);
        }
    }
    let area = (b * b) as f64;
    Blocks {
        block_px: b,
        width: bw,
        height: bh,
        fraction: counts.iter().map(|&c| c as f64 / area).collect(),
        centre_px: [
            (bw * b) as f64 / 2.0 - width as f64 / 2.0,
            (bh * b) as f64 / 2.0 - height as f64 / 2.0,
        ],
    }
}

/// The predicted map at one pitch.
#[derive(Clone, Debug)]
pub(crate) struct Level {
    /// `[[ix, iy]]`, NaN where not measured
    pub map: Array2<f64>,
    pub dx_m: f64,
    pub dy_m: f64,
    /// the grid's centre in the original map's coordinates (from its centre), m
    pub centre_m: [f64; 2],
}

impl Level {
    /// Box average over `fx` × `fy` points (each at least 1, at most the
    /// map's size), of the measured points; a block is unmeasured when
    /// fewer than half of its points are measured (the rule of the `surface`
    /// stage's NaN-aware filter).
    pub(crate) fn box_average(
        fraction: ArrayView2<f64>,
        (dx_m, dy_m): (f64, f64),
        (fx, fy): (usize, usize),
    ) -> Self {
        let (nx, ny) = fraction.dim();
        let (fx, fy) = (fx.clamp(1, nx.max(1)), fy.clamp(1, ny.max(1)));
        let (mx, my) = (nx / fx, ny / fy);
        let points = fx * fy;
        let map = Array2::from_shape_fn((mx, my), |(i, j)| {
            let (mut sum, mut measured) = (0.0, 0);
            for a in 0..fx {
                for b in 0..fy {
                    let v = fraction[[i * fx + a, j * fy + b]];
                    if !v.is_nan() {
                        sum += v;
                        measured += 1;
                    }
                }
            }
            if 2 * measured >= points && measured > 0 {
                sum / measured as f64
            } else {
                f64::NAN
            }
        });
        Self {
            map,
            dx_m: dx_m * fx as f64,
            dy_m: dy_m * fy as f64,
            centre_m: [
                ((mx * fx) as f64 - nx as f64) / 2.0 * dx_m,
                ((my * fy) as f64 - ny as f64) / 2.0 * dy_m,
            ],
        }
    }

    /// Half the size of the hull of the grid's points, m.
    pub(crate) fn half_extent_m(&self) -> [f64; 2] {
        let (mx, my) = self.map.dim();
        [
            (mx.max(1) - 1) as f64 / 2.0 * self.dx_m,
            (my.max(1) - 1) as f64 / 2.0 * self.dy_m,
        ]
    }

    /// The map at the pixel centres of `grid`, turned by `angle_rad` with
    /// its centre on the field point `centre_m` (the geometry module's
    /// convention, positions in the original map's coordinates).
    pub(crate) fn sample(
        &self,
        angle_rad: f64,
        centre_m: [f64; 2],
        grid: &CameraGrid,
    ) -> Result<Vec<f64>, CompareError> {
        let gap = GapMap {
            gap_m: self.map.view(),
            dx_m: self.dx_m,
            dy_m: self.dy_m,
        };
        let placement = Placement {
            angle_rad,
            shift_x_m: centre_m[0] - self.centre_m[0],
            shift_y_m: centre_m[1] - self.centre_m[1],
        };
        Ok(resample(&gap, &placement, grid)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn block_fractions_count_the_pixels_of_each_block() {
        // 7 × 5 mask in blocks of 2: 3 × 2 blocks, the last column and row dropped
        let (w, h) = (7, 5);
        let mask: Vec<bool> = (0..w * h).map(|k| (k * 7 + k / w) % 3 == 0).collect();
        let blocks = area_average(&mask, w, h, 2);
        assert_eq!((blocks.width, blocks.height), (3, 2));
        for by in 0..2 {
            for bx in 0..3 {
                let mut n = 0;
                for y in 2 * by..2 * by + 2 {
                    for x in 2 * bx..2 * bx + 2 {
                        n += usize::from(mask[y * w + x]);
                    }
                }
                assert_eq!(blocks.fraction[by * 3 + bx], n as f64 / 4.0);
            }
        }
        // blocks cover pixels 0..6 × 0..4: centre at (2.5, 1.5) vs (3, 2)
        assert_eq!(blocks.centre_px, [-0.5, -0.5]);
        let same = area_average(&mask, w, h, 1);
        assert_eq!(same.centre_px, [0.0, 0.0]);
        assert!(
            same.fraction
                .iter()
                .zip(&mask)
                .all(|(f, &m)| *f == f64::from(u8::from(m)))
        );
    }

    #[test]
    fn blocks_average_their_measured_points() {
        // 6 × 4 in blocks of 2 × 2: one NaN of four is left out, three of
        // four leave the block unmeasured
        let mut f = Array2::from_shape_fn((6, 4), |(i, j)| 0.1 * (i + 2 * j) as f64 / 2.0);
        f[[3, 1]] = f64::NAN;
        for p in [[4, 2], [4, 3], [5, 3]] {
            f[p] = f64::NAN;
        }
        let level = Level::box_average(f.view(), (1.0, 1.0), (2, 2));
        assert_eq!(level.map.dim(), (3, 2));
        let mean =
            |points: &[[usize; 2]]| points.iter().map(|&p| f[p]).sum::<f64>() / points.len() as f64;
        assert!((level.map[[1, 0]] - mean(&[[2, 0], [3, 0], [2, 1]])).abs() < 1e-15);
        assert!((level.map[[0, 1]] - mean(&[[0, 2], [1, 2], [0, 3], [1, 3]])).abs() < 1e-15);
        assert!(level.map[[2, 1]].is_nan());
        assert_eq!(level.map.iter().filter(|v| v.is_nan()).count(), 1);
        assert_eq!(level.centre_m, [0.0, 0.0]);
        // 7 × 5 in blocks of 3 × 2: 2 × 2 blocks over points 0..6 × 0..4,
        // centred 0.5 and 0.5 points before the map's centre
        let g = Array2::from_elem((7, 5), 0.5);
        let level = Level::box_average(g.view(), (2.0, 3.0), (3, 2));
        assert_eq!(level.map.dim(), (2, 2));
        assert_eq!((level.dx_m, level.dy_m), (6.0, 6.0));
        assert_eq!(level.centre_m, [-1.0, -1.5]);
    }

    proptest! {
        #![proptest_config(hypercontact_fuzz::config(48))]

        /// A linear ramp a + bX + cY keeps its values at the same places
        /// through box averaging (with the leftover offset) and sampling on a
        /// turned grid: each camera-grid point sees the ramp at the point
        /// the geometry module's convention puts it.
        #[test]
        fn a_ramp_survives_averaging_and_turned_sampling(
            nx in 3usize..30,
            ny in 3usize..30,
            fx in 1usize..4,
            fy in 1usize..4,
            angle in -3.2f64..3.2,
            b in -1.0f64..1.0,
            c in -1.0f64..1.0,
        ) {
            let (dx, dy) = (2e-5, 3e-5);
            let ramp = |x: f64, y: f64| 0.5 + b * x / 1e-3 + c * y / 1e-3;
            let (hx, hy) = ((nx as f64 - 1.0) / 2.0, (ny as f64 - 1.0) / 2.0);
            let f = Array2::from_shape_fn((nx, ny), |(i, j)| ramp((i as f64 - hx) * dx, (j as f64 - hy) * dy));
            let level = Level::box_average(f.view(), (dx, dy), (fx, fy));
            prop_assume!(level.map.dim().0 >= 2 && level.map.dim().1 >= 2);
            // a small grid near the centre: every point lands on the map
            let grid = CameraGrid { width_px: 5, height_px: 4, pixel_m: 1e-6 };
            let centre = [level.centre_m[0] + 0.3 * dx, level.centre_m[1] - 0.2 * dy];
            let out = level.sample(angle, centre, &grid).unwrap();
            let (s, co) = angle.sin_cos();
            for y in 0..4 {
                for x in 0..5 {
                    let (px, py) = ((x as f64 - 2.0) * 1e-6, (y as f64 - 1.5) * 1e-6);
                    let (xm, ym) = (co * px - s * py + centre[0], s * px + co * py + centre[1]);
                    let v = out[y * 5 + x];
                    prop_assert!((v - ramp(xm, ym)).abs() < 1e-9, "({x}, {y}): {v} vs {}", ramp(xm, ym));
                }
            }
        }
    }
}
