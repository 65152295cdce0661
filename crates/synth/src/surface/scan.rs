//! A white-light interferometer scanning a sample tile by tile.
//!
//! Tiles lie on a grid with a given overlap; the stage misses each nominal
//! position by a random error (whole pixels of the truth grid, so a tile is
//! an exact crop of the truth and the ground truth stays exact); each tile
//! gets its own tilt and piston (the instrument re-levels at every field of
//! view), Gaussian measurement noise, and dropout pixels (NaN).

use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, StandardNormal};

/// How the instrument scans.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanPlan {
    pub tile_px: usize,
    pub tiles_x: usize,
    pub tiles_y: usize,
    /// Overlap of neighbouring tiles, as a fraction of the tile side.
    pub overlap: f64,
    /// Standard deviation of the stage-position error, pixels (rounded).
    pub position_error_px: f64,
    /// Standard deviation of the measurement noise, metres.
    pub noise_m: f64,
    /// Probability that a pixel is a dropout (NaN).
    pub dropout_fraction: f64,
    /// Standard deviation of each tile's tilt about its centre, rad (m/m).
    pub tilt_rad: f64,
    /// Standard deviation of each tile's piston offset, metres.
    pub piston_m: f64,
    pub pixel_m: f64,
    pub seed: u64,
}

/// One scanned tile and the truth about it.
#[derive(Clone, Debug, PartialEq)]
pub struct ScannedTile {
    /// Heights (axis 0 = x), metres, NaN at dropouts.
    pub heights: Array2<f64>,
    /// The position the scanner records for pixel [0, 0], pixels.
    pub nominal_px: [i64; 2],
    /// Where pixel [0, 0] really lies in the truth array, pixels.
    pub truth_px: [usize; 2],
    /// True position minus nominal position, pixels.
    pub offset_px: [i64; 2],
    /// Added slope along x and y about the tile centre, m/m.
    pub tilt_rad: [f64; 2],
    /// Added constant height, metres.
    pub piston_m: f64,
}

impl ScanPlan {
    /// Distance between neighbouring nominal positions, pixels.
    pub fn step_px(&self) -> usize {
        ((self.tile_px as f64) * (1.0 - self.overlap))
            .round()
            .max(1.0) as usize
    }

    /// Draws the true tile positions and the size of the truth area they
    /// cover: (offsets per tile in scan order, [nx, ny] of the truth).
    pub fn layout(&self) -> (Vec<[i64; 2]>, [i64; 2], [usize; 2]) {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed ^ 0x5ca1_ab1e);
        let error = Normal::new(0.0, self.position_error_px.max(0.0))
            .expect("a non-negative standard deviation");
        let offsets: Vec<[i64; 2]> = (0..self.tiles_x * self.tiles_y)
            .map(|_| {
                [
                    error.sample(&mut rng).round() as i64,
                    error.sample(&mut rng).round() as i64,
                ]
            })
            .collect();
        let mut lo = [i64::MAX; 2];
        let mut hi = [i64::MIN; 2];
        for (t, off) in offsets.iter().enumerate() {
            let nominal = self.nominal_px(t);
            for a in 0..2 {
                let p = nominal[a] + off[a];
                lo[a] = lo[a].min(p);
                hi[a] = hi[a].max(p + self.tile_px as i64);
            }
        }
        let size = [(hi[0] - lo[0]) as usize, (hi[1] - lo[1]) as usize];
        (offsets, lo, size)
    }

    /// Nominal position of tile `t` (scan order: x fastest), pixels.
    pub fn nominal_px(&self, t: usize) -> [i64; 2] {
        let step = self.step_px() as i64;
        [
            (t % self.tiles_x) as i64 * step,
            (t / self.tiles_x) as i64 * step,
        ]
    }

    /// Scans `truth`, whose pixel [0, 0] lies at nominal coordinates
    /// `origin_px`, with the position errors `offsets` from `layout`.
    pub fn scan(
        &self,
        truth: &Array2<f64>,
        offsets: &[[i64; 2]],
        origin_px: [i64; 2],
    ) -> Vec<ScannedTile> {
        let n = self.tile_px;
        let centre = (n as f64 - 1.0) / 2.0;
        offsets
            .iter()
            .enumerate()
            .map(|(t, off)| {
                let mut rng = ChaCha8Rng::seed_from_u64(self.seed.wrapping_add(1 + t as u64));
                let nominal = self.nominal_px(t);
                let tx = (nominal[0] + off[0] - origin_px[0]) as usize;
                let ty = (nominal[1] + off[1] - origin_px[1]) as usize;
                let tilt: [f64; 2] = [
                    self.tilt_rad * sample_normal(&mut rng),
                    self.tilt_rad * sample_normal(&mut rng),
                ];
                let piston_m = self.piston_m * sample_normal(&mut rng);
                let mut heights = Array2::from_shape_fn((n, n), |(i, j)| truth[[tx + i, ty + j]]);
                for ((i, j), h) in heights.indexed_iter_mut() {
                    let plane = piston_m
                        + tilt[0] * (i as f64 - centre) * self.pixel_m
                        + tilt[1] * (j as f64 - centre) * self.pixel_m;
                    let noise = sample_normal(&mut rng);
                    *h += plane + self.noise_m * noise;
                    if self.dropout_fraction > 0.0 && rng.random::<f64>() < self.dropout_fraction {
                        *h = f64::NAN;
                    }
                }
                ScannedTile {
                    heights,
                    nominal_px: nominal,
                    truth_px: [tx, ty],
                    offset_px: *off,
                    tilt_rad: tilt,
                    piston_m,
                }
            })
            .collect()
    }
}

fn sample_normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan() -> ScanPlan {
        ScanPlan {
            tile_px: 32,
            tiles_x: 3,
            tiles_y: 2,
            overlap: 0.25,
            position_error_px: 2.0,
            noise_m: 0.0,
            dropout_fraction: 0.0,
            tilt_rad: 0.0,
            piston_m: 0.0,
            pixel_m: 1e-6,
            seed: 1,
        }
    }

    #[test]
    fn tiles_without_artefacts_are_exact_crops_of_the_truth() {
        let p = plan();
        let (offsets, origin, size) = p.layout();
        let truth = Array2::from_shape_fn((size[0], size[1]), |(i, j)| (i * 1000 + j) as f64);
        let tiles = p.scan(&truth, &offsets, origin);
        assert_eq!(tiles.len(), 6);
        for t in &tiles {
            let [x, y] = t.truth_px;
            assert_eq!(t.heights[[0, 0]], truth[[x, y]]);
            assert_eq!(t.heights[[31, 5]], truth[[x + 31, y + 5]]);
            // The nominal position plus the error is the true position.
            assert_eq!(t.nominal_px[0] + t.offset_px[0] - origin[0], x as i64);
        }
        assert_eq!(p.step_px(), 24);
        assert_eq!(tiles[4].nominal_px, [24, 24]);
    }

    #[test]
    fn artefacts_have_their_prescribed_size() {
        let mut p = plan();
        p.tile_px = 200;
        p.tiles_x = 1;
        p.tiles_y = 1;
        p.noise_m = 1e-9;
        p.dropout_fraction = 0.05;
        let (offsets, origin, size) = p.layout();
        let truth = Array2::zeros((size[0], size[1]));
        let tile = &p.scan(&truth, &offsets, origin)[0];
        let nan = tile.heights.iter().filter(|h| h.is_nan()).count() as f64 / 40_000.0;
        assert!((nan - 0.05).abs() < 0.005, "dropout share {nan}");
        let valid: Vec<f64> = tile
            .heights
            .iter()
            .copied()
            .filter(|h| !h.is_nan())
            .collect();
        let mean = valid.iter().sum::<f64>() / valid.len() as f64;
        let sd =
            (valid.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / valid.len() as f64).sqrt();
        assert!((sd / 1e-9 - 1.0).abs() < 0.02, "noise sd {sd}");
    }
}
