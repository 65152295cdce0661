//! Synthetic registration scenes with a known truth: a self-affine surface
//! (H = 0.8) at 10 µm; the model's prediction is that surface averaged to a
//! 20 µm scan and thresholded at one area fraction, the camera's mask is the
//! 10 µm surface itself, bilinearly resampled through the known placement
//! and thresholded at another, with some pixels flipped.

#![allow(dead_code)]

use hypercontact_compare::register::{ObservedMask, PredictedMap};
use hypercontact_interference::{CameraGrid, GapMap, Placement, resample};
use hypercontact_synth::surface::SelfAffine;
use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub const SCAN_M: f64 = 20e-6;
const FINE_M: f64 = 10e-6;

/// What to build.
#[derive(Clone, Copy, Debug)]
pub struct Spec {
    /// scan points each way (at 20 µm)
    pub scan_points: usize,
    pub seed: u64,
    /// the camera with its nominal pixel
    pub camera: CameraGrid,
    pub truth: Placement,
    /// the camera's true pitch / nominal
    pub true_scale: f64,
    /// contact area fractions of the prediction and of the surface the camera sees
    pub predicted_fraction: f64,
    pub observed_fraction: f64,
    /// share of the camera's pixels flipped
    pub flipped: f64,
}

impl Spec {
    /// 450 scan points, a 512² camera at 4.33 µm turned 2.5° and shifted
    /// by (150, −100) µm; A/A0 0.30 predicted, 0.33 observed, 2 % flipped.
    pub fn quick() -> Self {
        Self {
            scan_points: 450,
            seed: 7,
            camera: CameraGrid {
                width_px: 512,
                height_px: 512,
                pixel_m: 6.5e-6 / 1.5,
            },
            truth: Placement {
                angle_rad: 2.5f64.to_radians(),
                shift_x_m: 150e-6,
                shift_y_m: -100e-6,
            },
            true_scale: 1.0,
            predicted_fraction: 0.30,
            observed_fraction: 0.33,
            flipped: 0.02,
        }
    }

    /// The paper's camera: 2048² at 3.25 µm against a 453² scan.
    pub fn paper() -> Self {
        Self {
            scan_points: 453,
            camera: CameraGrid {
                width_px: 2048,
                height_px: 2048,
                pixel_m: 3.25e-6,
            },
            ..Self::quick()
        }
    }
}

pub struct Scene {
    pub spec: Spec,
    /// 0/1 on the 20 µm scan grid, `[[ix, iy]]`
    pub predicted: Array2<f64>,
    /// row-major camera mask
    pub mask: Vec<bool>,
}

impl Scene {
    /// The prediction as the registration takes it.
    pub fn predicted_map(&self) -> PredictedMap<'_> {
        PredictedMap {
            fraction: self.predicted.view(),
            dx_m: SCAN_M,
            dy_m: SCAN_M,
        }
    }

    /// The camera's mask as the registration takes it.
    pub fn observed_mask(&self) -> ObservedMask<'_> {
        ObservedMask {
            contact: &self.mask,
            width_px: self.spec.camera.width_px,
            height_px: self.spec.camera.height_px,
            pixel_m: self.spec.camera.pixel_m,
        }
    }
}

/// The height at which `fraction` of the values lie above.
fn level_above(values: impl Iterator<Item = f64>, fraction: f64) -> f64 {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    let k = (((1.0 - fraction) * v.len() as f64) as usize).min(v.len() - 1);
    v[k]
}

pub fn build(spec: &Spec) -> Scene {
    let n = spec.scan_points;
    let fine = SelfAffine {
        hurst: 0.8,
        rms_m: 10e-6,
        lambda_min_m: 20e-6,
        lambda_max_m: 1e-3,
    }
    .non_periodic(2 * n, 2 * n, FINE_M, spec.seed);
    // 2 × 2 means: fine points 2i and 2i + 1 centre on scan point i
    let scan = Array2::from_shape_fn((n, n), |(i, j)| {
        0.25 * (fine[[2 * i, 2 * j]]
            + fine[[2 * i + 1, 2 * j]]
            + fine[[2 * i, 2 * j + 1]]
            + fine[[2 * i + 1, 2 * j + 1]])
    });
    let z_predicted = level_above(scan.iter().copied(), spec.predicted_fraction);
    let predicted = scan.mapv(|h| if h >= z_predicted { 1.0 } else { 0.0 });
    let z_observed = level_above(fine.iter().copied(), spec.observed_fraction);
    let gap = fine.mapv(|h| z_observed - h);
    let true_camera = CameraGrid {
        pixel_m: spec.camera.pixel_m * spec.true_scale,
        ..spec.camera
    };
    let gap_on_camera = resample(
        &GapMap {
            gap_m: gap.view(),
            dx_m: FINE_M,
            dy_m: FINE_M,
        },
        &spec.truth,
        &true_camera,
    )
    .unwrap();
    assert!(
        gap_on_camera.iter().all(|g| !g.is_nan()),
        "the test camera's view must lie on the surface"
    );
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed ^ 0x5eed);
    let mask = gap_on_camera
        .iter()
        .map(|&g| (g <= 0.0) ^ (rng.random::<f64>() < spec.flipped))
        .collect();
    Scene {
        spec: *spec,
        predicted,
        mask,
    }
}
