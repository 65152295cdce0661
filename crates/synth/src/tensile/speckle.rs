//! A sprayed speckle pattern as an analytic function of reference
//! coordinates: Gaussian blobs of paint that darken a white coat, plus a few
//! painted marker dots, each on a patch the spray was kept off.
//!
//! Darkness adds as optical density, I = I_white − (I_white − I_black)(1 − e^(−S)),
//! S = Σ s_k exp(−|X − X_k|² / r_k²), so overlapping blobs saturate at the
//! black level the way paint does; markers blend to `marker_level` through a
//! logistic edge half a pixel wide. Coordinates are pixels of the undeformed
//! image (x = column, y = row).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Blobs are ignored beyond this many radii (e^(−16) ≈ 1e-7 of full scale).
pub const CUTOFF_RADII: f64 = 4.0;

/// One Gaussian blob of paint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Speckle {
    pub x: f64,
    pub y: f64,
    pub radius: f64,
    /// Optical density at the blob's centre.
    pub density: f64,
}

/// A painted marker dot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    pub x: f64,
    pub y: f64,
    pub radius: f64,
}

/// The speckle pattern on the undeformed specimen.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecklePattern {
    /// Sorted by `y`, so a band of rows finds its blobs by bisection.
    pub speckles: Vec<Speckle>,
    pub markers: Vec<Marker>,
    pub max_radius: f64,
    pub white: f64,
    pub black: f64,
    pub marker_level: f64,
}

impl SpecklePattern {
    /// Random blobs over the reference box `[x0, x1] × [y0, y1]` with mean
    /// radius `radius_px` covering about `coverage` of the area.
    pub fn random(
        bounds: [f64; 4],
        radius_px: f64,
        coverage: f64,
        markers: Vec<Marker>,
        seed: u64,
    ) -> Self {
        let [x0, y0, x1, y1] = bounds;
        let area = (x1 - x0).max(0.0) * (y1 - y0).max(0.0);
        let count =
            (coverage * area / (std::f64::consts::PI * radius_px * radius_px)).ceil() as usize;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut speckles: Vec<Speckle> = (0..count)
            .map(|_| Speckle {
                x: x0 + (x1 - x0) * rng.random::<f64>(),
                y: y0 + (y1 - y0) * rng.random::<f64>(),
                // Spray droplets vary in size and load; ±40 % and 0.8 … 2.
                radius: radius_px * (0.6 + 0.8 * rng.random::<f64>()),
                density: 0.8 + 1.2 * rng.random::<f64>(),
            })
            .collect();
        // Markers are painted on a clean patch: no blob reaches under a
        // marker's edge, so the edge's contrast, and with it the marker's
        // thresholded outline, is the same all round.
        let clear = 3.0 * 1.4 * radius_px;
        speckles.retain(|s| {
            markers
                .iter()
                .all(|m| (s.x - m.x).hypot(s.y - m.y) > m.radius + 2.0 + clear)
        });
        speckles.sort_by(|a, b| a.y.total_cmp(&b.y));
        let max_radius = speckles.iter().map(|s| s.radius).fold(0.0, f64::max);
        Self {
            speckles,
            markers,
            max_radius,
            white: 0.85,
            black: 0.12,
            marker_level: 0.02,
        }
    }

    /// The speckles whose centre lies in `[y_min, y_max]`.
    pub fn speckles_in_rows(&self, y_min: f64, y_max: f64) -> &[Speckle] {
        let start = self.speckles.partition_point(|s| s.y < y_min);
        let end = self.speckles.partition_point(|s| s.y <= y_max);
        &self.speckles[start..end.max(start)]
    }

    /// Intensity from optical density `density_sum` and marker cover at
    /// reference point (x, y).
    #[inline]
    pub fn intensity(&self, density_sum: f64, x: f64, y: f64) -> f64 {
        let coat = self.white - (self.white - self.black) * (1.0 - (-density_sum).exp());
        let cover = self.marker_cover(x, y);
        coat + cover * (self.marker_level - coat)
    }

    /// 0 … 1: how much of point (x, y) a marker's paint covers.
    #[inline]
    pub fn marker_cover(&self, x: f64, y: f64) -> f64 {
        let mut cover: f64 = 0.0;
        for m in &self.markers {
            let (dx, dy) = (x - m.x, y - m.y);
            let reach = m.radius + 8.0;
            if dx.abs() > reach || dy.abs() > reach {
                continue;
            }
            let r = (dx * dx + dy * dy).sqrt();
            // Logistic edge, 0.5 px wide.
            cover = cover.max(1.0 / (1.0 + ((r - m.radius) / 0.5).exp()));
        }
        cover
    }

    /// The pattern's intensity at reference point (x, y), evaluated directly
    /// (slow; the renderer splats instead). For tests.
    pub fn value(&self, x: f64, y: f64) -> f64 {
        let reach = CUTOFF_RADII * self.max_radius;
        let density: f64 = self
            .speckles_in_rows(y - reach, y + reach)
            .iter()
            .map(|s| {
                // The renderer's square cut-off, so both agree to rounding.
                let cut = CUTOFF_RADII * s.radius;
                let (dx, dy) = (x - s.x, y - s.y);
                if dx.abs() <= cut && dy.abs() <= cut {
                    s.density * (-(dx * dx + dy * dy) / (s.radius * s.radius)).exp()
                } else {
                    0.0
                }
            })
            .sum();
        self.intensity(density, x, y)
    }
}
