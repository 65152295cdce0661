//! The plan of one synthetic tensile test: specimen, stretch history, the
//! camera's view of the deformed gauge section, frame times and force log.
//!
//! Loading is along the image x axis and homogeneous about the image centre:
//! UT stretches the view by (λ, λ^−½), PT by (λ, 1), BT by (λ, λ), the
//! in-plane stretches of the paper's three tests (section 2) for an
//! incompressible solid. The stretch grows linearly in time.

use hypercontact_material::{Hyperelastic, Mode};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::render::{AxisMap, render};
use super::speckle::{CUTOFF_RADII, Marker, SpecklePattern};

/// Gauge width and gauge length of the paper's specimens (section 2: UT
/// dumbbell 6 × 115 mm, PT 40 × 10 mm, BT cross 40 × 12 mm), metres.
pub fn paper_gauge_m(mode: Mode) -> [f64; 2] {
    match mode {
        Mode::Uniaxial => [6e-3, 115e-3],
        Mode::Planar => [40e-3, 10e-3],
        Mode::Equibiaxial => [40e-3, 12e-3],
    }
}

/// The force sensors' resolutions of section 2, newtons.
pub fn paper_force_resolution_n(mode: Mode) -> f64 {
    match mode {
        Mode::Planar => 0.1,
        _ => 0.01,
    }
}

/// In-plane stretches (along x, along y) at loading stretch λ.
pub fn in_plane_stretches(mode: Mode, stretch: f64) -> [f64; 2] {
    let s = mode.stretches(stretch);
    [s[0], s[1]]
}

/// Everything needed to render the frames and write the force log.
#[derive(Clone, Debug)]
pub struct Experiment {
    pub mode: Mode,
    pub width_px: usize,
    pub height_px: usize,
    pub supersample: usize,
    pub pattern: SpecklePattern,
    pub maps: Vec<AxisMap>,
    pub times_s: Vec<f64>,
    /// Loading stretch per frame.
    pub stretches: Vec<f64>,
    /// The gauge region to analyse, frame-0 pixels `[x0, y0, x1, y1]`.
    pub roi_px: [usize; 4],
}

/// What shapes an experiment.
#[derive(Clone, Debug)]
pub struct Recipe {
    pub mode: Mode,
    pub max_stretch: f64,
    pub frames: usize,
    pub frame_interval_s: f64,
    pub width_px: usize,
    pub height_px: usize,
    pub speckle_radius_px: f64,
    pub speckle_coverage: f64,
    pub supersample: usize,
    pub markers: bool,
    pub marker_radius_px: f64,
    pub seed: u64,
}

impl Experiment {
    pub fn new(recipe: &Recipe) -> Self {
        let (w, h) = (recipe.width_px, recipe.height_px);
        let centre = [(w as f64 - 1.0) / 2.0, (h as f64 - 1.0) / 2.0];
        let frames = recipe.frames.max(1);
        let stretches: Vec<f64> = (0..frames)
            .map(|k| {
                let progress = if frames > 1 {
                    k as f64 / (frames - 1) as f64
                } else {
                    0.0
                };
                1.0 + (recipe.max_stretch - 1.0) * progress
            })
            .collect();
        let times_s = (0..frames)
            .map(|k| k as f64 * recipe.frame_interval_s)
            .collect();
        let maps: Vec<AxisMap> = stretches
            .iter()
            .map(|&l| AxisMap {
                centre,
                stretch: in_plane_stretches(recipe.mode, l),
                shift: [0.0, 0.0],
            })
            .collect();

        // The ROI stays in view with room for a 41 px subset at the largest
        // stretch: λ (h + 20) + 4 ≤ half the image.
        let largest = in_plane_stretches(recipe.mode, recipe.max_stretch.max(1.0));
        let half_x = (0.95 * ((w as f64 / 2.0 - 4.0) / largest[0].max(1.0) - 20.0)).max(1.0);
        let half_y = (0.95 * ((h as f64 / 2.0 - 4.0) / largest[1].max(1.0) - 20.0)).max(1.0);
        let roi_px = [
            (centre[0] - half_x).round().max(0.0) as usize,
            (centre[1] - half_y).round().max(0.0) as usize,
            (centre[0] + half_x).round() as usize,
            (centre[1] + half_y).round() as usize,
        ];

        let markers = if recipe.markers {
            let (mx, my) = (0.6 * half_x, 0.6 * half_y);
            [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
                .iter()
                .map(|(sx, sy)| Marker {
                    x: centre[0] + sx * mx,
                    y: centre[1] + sy * my,
                    radius: recipe.marker_radius_px,
                })
                .collect()
        } else {
            Vec::new()
        };

        // Paint every reference point any frame sees, plus the blobs' reach.
        let pad = CUTOFF_RADII * 1.4 * recipe.speckle_radius_px + 2.0;
        let mut bounds = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for map in &maps {
            for axis in 0..2 {
                let extent = if axis == 0 { w } else { h } as f64;
                let a = map.to_reference(axis, -1.0);
                let b = map.to_reference(axis, extent);
                bounds[axis] = bounds[axis].min(a.min(b) - pad);
                bounds[axis + 2] = bounds[axis + 2].max(a.max(b) + pad);
            }
        }
        let pattern = SpecklePattern::random(
            bounds,
            recipe.speckle_radius_px,
            recipe.speckle_coverage,
            markers,
            recipe.seed,
        );
        Self {
            mode: recipe.mode,
            width_px: w,
            height_px: h,
            supersample: recipe.supersample,
            pattern,
            maps,
            times_s,
            stretches,
            roi_px,
        }
    }

    /// Frame `k` without noise, 0 … 1 of full scale.
    pub fn render_frame(&self, k: usize) -> Vec<f64> {
        render(
            &self.pattern,
            &self.maps[k],
            self.width_px,
            self.height_px,
            self.supersample,
        )
    }

    /// The loading duration, seconds.
    pub fn duration_s(&self) -> f64 {
        self.times_s.last().copied().unwrap_or(0.0)
    }

    /// Loading stretch at time `t_s` (linear ramp, held after the end).
    pub fn stretch_at(&self, t_s: f64) -> f64 {
        let end = self.duration_s();
        let last = self.stretches.last().copied().unwrap_or(1.0);
        if end <= 0.0 {
            return last;
        }
        1.0 + (last - 1.0) * (t_s / end).clamp(0.0, 1.0)
    }

    /// The force log: samples at `rate_hz` from 0 to past the last frame,
    /// true force = nominal stress × `area_m2`, plus Gaussian sensor noise of
    /// half a resolution step, quantised to `resolution_n`.
    pub fn force_log(
        &self,
        material: &dyn Hyperelastic,
        area_m2: f64,
        rate_hz: f64,
        resolution_n: f64,
        seed: u64,
    ) -> Vec<(f64, f64)> {
        let samples = (self.duration_s() * rate_hz - 1e-9).ceil().max(0.0) as usize + 1;
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xf0_7ce5);
        (0..samples)
            .map(|i| {
                let t = i as f64 / rate_hz;
                let force = material.nominal_stress_pa(self.mode, self.stretch_at(t)) * area_m2;
                let noise: f64 = StandardNormal.sample(&mut rng);
                let measured = force + 0.5 * resolution_n * noise;
                (t, (measured / resolution_n).round() * resolution_n)
            })
            .collect()
    }
}

/// Adds Gaussian camera noise (std `noise` of full scale) and quantises to
/// `bit_depth` bits.
pub fn expose(pixels: &[f64], noise: f64, bit_depth: u32, seed: u64) -> Vec<u16> {
    let full = ((1u32 << bit_depth) - 1) as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    pixels
        .iter()
        .map(|&v| {
            let n: f64 = if noise > 0.0 {
                StandardNormal.sample(&mut rng)
            } else {
                0.0
            };
            ((v + noise * n).clamp(0.0, 1.0) * full).round() as u16
        })
        .collect()
}
